//! `blastsph run` on a rank other than 0 under mpirun: the same solver, stepped in the same
//! order, with no files and no printing. Rank 0 runs [`super::Loop`] and writes every output;
//! the others take part in the split row loops of its stages ([`crate::modules::ranks`]) and
//! stop where it stops.

use super::{RunOptions, RunResult, stop_flag};
use crate::case::{self, StepRule};
use crate::error::{Result, SphError, input};
use crate::modules::ranks;
use crate::sim::Sim;
use std::sync::atomic::Ordering;

/// `r`, once every rank has said whether its own part of the start succeeded: an error where
/// another rank failed (the one that failed says why; this one stays silent).
pub(super) fn agreed<T>(r: Result<T>) -> Result<T> {
    let failed = ranks::any(r.is_err());
    match r {
        Ok(_) if failed => Err(input("another rank could not start the run")),
        r => r,
    }
}

/// A rank other than 0: the case, the solver, and the steps rank 0 takes.
pub(super) fn run(case_path: &std::path::Path, opts: &RunOptions) -> Result<RunResult> {
    let parsed = (|| {
        let text = case::read_text(case_path)?;
        let origin = case_path.display().to_string();
        case::parse(&text, &origin, &opts.sets, case_path.file_stem().and_then(|s| s.to_str()))
    })();
    let case = agreed(parsed)?;
    let dir = opts.out.clone().unwrap_or_else(|| crate::rundir::default_dir(case.name()));
    let built = Sim::new(case, &opts.ov).and_then(|sim| {
        crate::case::slips::check(&sim.case, &sim.p, sim.cfg.dx_min)?;
        Ok(sim)
    });
    let mut sim = agreed(built)?;
    // rank 0's Loop::fresh evaluates the rates at t = 0 for its first output
    sim.rates();
    let fixed_steps = match sim.cfg.step {
        StepRule::Fixed => Some((sim.cfg.end / sim.cfg.dt_fixed).round().max(1.0) as u64),
        StepRule::Cfl => None,
    };
    let stop = stop_flag();
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
