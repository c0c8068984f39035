//! `blastsph run` and `resume` on a rank other than 0 under mpirun: the same solver, stepped in
//! the same order, with no files and no printing. Rank 0 runs [`super::Loop`] and writes every
//! output; the others take part in the split row loops of its stages
//! ([`crate::modules::ranks`]) and stop where it stops.
//!
//! The start: rank 0 checks the case and the run directory and builds its run alone, then says
//! how that went (one byte to every rank). The others then build their solvers from the same
//! case and say whether they could. Until the time loop no row loop is split, so a rank that
//! stops before it leaves no other waiting.

use super::{RunOptions, RunResult, stop_flag};
use crate::case::{self, StepRule};
use crate::error::{Result, SphError, input};
use crate::modules::ranks;
use crate::sim::Sim;
use std::path::Path;
use std::sync::atomic::Ordering;

/// What rank 0 says of its start.
const FAILED: u8 = 0;
const FRESH: u8 = 1;
const RESUME: u8 = 2;

/// Rank 0's word on its start (sent by rank 0, received by the others).
fn word(tag: u8) -> u8 {
    let mut b = vec![tag];
    ranks::broadcast(&mut b);
    b.first().copied().unwrap_or(FAILED)
}

/// Rank 0's side of the start of `run`: `r` is its own start (a new run ready to step, or the
/// continuation of a stopped one, which [`super::restart::resume`] starts). An error where
/// another rank could not build its solver.
pub(super) fn settle_run<F, R>(r: Result<std::result::Result<F, R>>) -> Result<std::result::Result<F, R>> {
    if ranks::size() < 2 {
        return r;
    }
    let tag = match &r {
        Err(_) => FAILED,
        Ok(Ok(_)) => FRESH,
        Ok(Err(_)) => RESUME,
    };
    word(tag);
    if tag == FRESH && ranks::any(false) {
        return Err(input("another rank could not build the run"));
    }
    r
}

/// Rank 0's side of the start of `resume`: `text` is the case as resumed (with its new end
/// time), from which the other ranks build their solvers with the checkpoint of `dir`.
pub(super) fn settle_resume<T>(r: Result<T>, dir: &Path, text: &str, max_particles: Option<u64>) -> Result<T> {
    if ranks::size() < 2 {
        return r;
    }
    if r.is_err() {
        word(FAILED);
        return r;
    }
    word(RESUME);
    let mut b = serde_json::to_vec(&serde_json::json!([dir, text, max_particles])).unwrap_or_default();
    ranks::broadcast(&mut b);
    if ranks::any(false) {
        return Err(input("another rank could not build the resumed run"));
    }
    r
}

/// The quiet end of a rank other than 0 when rank 0 refused (rank 0 says why).
fn refused() -> SphError {
    input("rank 0 refused the run")
}

/// A rank other than 0 in `run`: rank 0's word, then the case, the solver, and the steps.
pub(super) fn run(case_path: &Path, opts: &RunOptions) -> Result<RunResult> {
    match word(FAILED) {
        FRESH => {}
        RESUME => return resume(opts),
        _ => return Err(refused()),
    }
    let built = (|| {
        let text = case::read_text(case_path)?;
        let origin = case_path.display().to_string();
        let case = case::parse(&text, &origin, &opts.sets, case_path.file_stem().and_then(|s| s.to_str()))?;
        let mut sim = Sim::new(case, &opts.ov)?;
        crate::case::slips::check(&sim.case, &sim.p, sim.cfg.dx_min)?;
        // rank 0's Loop::fresh evaluates the rates at t = 0 for its first output
        sim.rates();
        Ok(sim)
    })();
    let failed = ranks::any(built.is_err());
    let sim = built?;
    if failed {
        return Err(refused());
    }
    steps(sim, opts)
}

/// A rank other than 0 in `resume` (or in a `run` that continues its stopped run): rank 0's
/// word, its run directory and the case as resumed, then the checkpoint, the solver, the steps.
pub(super) fn resume(opts: &RunOptions) -> Result<RunResult> {
    if word(FAILED) != RESUME {
        return Err(refused());
    }
    let mut b = Vec::new();
    ranks::broadcast(&mut b);
    let built = (|| {
        let said: (std::path::PathBuf, String, Option<u64>) =
            serde_json::from_slice(&b).map_err(|e| input(format!("rank 0's resumed run: {e}")))?;
        super::restart::solver_of(&said.0, &said.1, said.2)
    })();
    let failed = ranks::any(built.is_err());
    let sim = built?;
    if failed {
        return Err(refused());
    }
    steps(sim, opts)
}

/// The steps rank 0 takes, to the end or to the step after which every rank stops.
fn steps(mut sim: Sim, opts: &RunOptions) -> Result<RunResult> {
    let dir = opts.out.clone().unwrap_or_default();
    let fixed_steps = match sim.cfg.step {
        StepRule::Fixed => Some((sim.cfg.end / sim.cfg.dt_fixed).round().max(1.0) as u64),
        StepRule::Cfl => None,
    };
    let stop = stop_flag();
    ranks::arm();
    loop {
        let done = match fixed_steps {
            Some(ns) => sim.nstep >= ns,
            None => sim.t >= sim.cfg.end * (1.0 - 1e-12),
        };
        if done {
            break;
        }
        // an unstable step is the same step on every rank: each ends with rank 0's status
        sim.step()?;
        if ranks::any(stop.load(Ordering::Relaxed) || opts.stop_after_step.is_some_and(|s| sim.nstep >= s)) {
            return Err(SphError::Stopped(format!("at step {}", sim.nstep)));
        }
    }
    Ok(RunResult { dir, summary: serde_json::Value::Null, sim })
}
