//! Progress of a run, on stderr: a bar on a terminal; otherwise (a batch job, a queue, output
//! redirected to a file) one line every few seconds:
//!
//! ```text
//! progress: step 1200  t = 3.312e-4 s (33.1 %)  dt = 2.71e-7 s  3.05e6 particle-steps/s  elapsed 4 s  ETA 8 s
//! ```
//!
//! `--quiet` silences both. The ETA extrapolates the simulated time per wall second so far.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Seconds between progress lines (when stderr is not a terminal), as bits of an f64.
static EVERY_BITS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0x4014_0000_0000_0000); // 5.0

/// Sets the seconds between progress lines (`blastsph run --progress-every`; default 5).
pub fn set_every(seconds: f64) {
    EVERY_BITS.store(seconds.to_bits(), std::sync::atomic::Ordering::Relaxed);
}

/// Seconds between progress lines.
pub fn every() -> f64 {
    f64::from_bits(EVERY_BITS.load(std::sync::atomic::Ordering::Relaxed))
}

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    Quiet,
    Bar,
    /// A line every this many seconds.
    Lines(f64),
}

impl Mode {
    /// Quiet, or a bar when stderr is a terminal, or lines every `every_s` seconds.
    pub fn choose(quiet: bool, every_s: f64) -> Mode {
        if quiet {
            Mode::Quiet
        } else if std::io::stderr().is_terminal() {
            Mode::Bar
        } else {
            Mode::Lines(every_s)
        }
    }
}

/// The progress of one run.
pub struct Progress {
    mode: Mode,
    bar: indicatif::ProgressBar,
    start: Instant,
    last_line: Instant,
    end: f64,
    particles: usize,
    label: String,
    /// Time (s) and step the run (or its resume) started from.
    t0: f64,
    step0: u64,
}

fn hms(s: f64) -> String {
    if !s.is_finite() {
        return "?".into();
    }
    let s = s.round() as u64;
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, (s % 3600) / 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{s} s")
    }
}

impl Progress {
    /// A run to simulated time `end` (s) of `particles` particles; `label` names it in lines.
    pub fn new(mode: Mode, end: f64, particles: usize, label: &str) -> Progress {
        let bar = if mode == Mode::Bar {
            let pb = indicatif::ProgressBar::new(1000);
            pb.set_style(
                indicatif::ProgressStyle::with_template("{bar:30} {percent:>3}% {msg} [{elapsed} < {eta}]")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            pb
        } else {
            indicatif::ProgressBar::hidden()
        };
        let now = Instant::now();
        Progress { mode, bar, start: now, last_line: now, end, particles, label: label.to_string(), t0: 0.0, step0: 0 }
    }

    /// A run resumed at time `t0` (s) and step `step0`: rates and the ETA count from there.
    pub fn starting_at(mut self, t0: f64, step0: u64) -> Progress {
        self.t0 = t0;
        self.step0 = step0;
        self
    }

    /// Reports step `nstep` at time `t` (s) after a step `dt` (s); cheap when nothing is due.
    pub fn update(&mut self, nstep: u64, t: f64, dt: f64) {
        match self.mode {
            Mode::Quiet => {}
            Mode::Bar => {
                if nstep.is_multiple_of(10) {
                    let el = self.start.elapsed().as_secs_f64().max(1e-9);
                    self.bar.set_position(((t / self.end) * 1000.0).clamp(0.0, 1000.0) as u64);
                    self.bar.set_message(format!(
                        "step {nstep} t = {t:.3e} s dt = {dt:.2e} s {:.2e} particle-steps/s",
                        (self.particles as f64 * nstep.saturating_sub(self.step0) as f64) / el
                    ));
                }
            }
            Mode::Lines(every) => {
                if self.last_line.elapsed() >= Duration::try_from_secs_f64(every).unwrap_or(Duration::MAX) {
                    self.last_line = Instant::now();
                    let el = self.start.elapsed().as_secs_f64().max(1e-9);
                    let frac = (t / self.end).clamp(0.0, 1.0);
                    // the pace of this process: the part of the run it has done
                    let done = ((t - self.t0) / (self.end - self.t0)).clamp(0.0, 1.0);
                    let eta = if done > 0.0 { el * (1.0 - done) / done } else { f64::INFINITY };
                    let mut e = std::io::stderr().lock();
                    let _ = writeln!(
                        e,
                        "progress: {}step {nstep}  t = {t:.4e} s ({:.1} %)  dt = {dt:.3e} s  {:.3e} particle-steps/s  elapsed {}  ETA {}",
                        self.label,
                        100.0 * frac,
                        (self.particles as f64 * nstep.saturating_sub(self.step0) as f64) / el,
                        hms(el),
                        hms(eta)
                    );
                    let _ = e.flush();
                }
            }
        }
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
