//! The command line (docs/design.md): `run`, `dual`, `check`, `report`.
// The doc comments below are clap's help texts, which name placeholders as <case name>.
#![allow(rustdoc::invalid_html_tags)]

use crate::case;
use crate::error::{IoAt, Result, SphError, input};
use crate::modules::Backend;
use crate::runner::{self, RunOptions};
use crate::sim::{Overrides, Sim};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

mod folders;
mod legacy_cmd;
mod legacy_compare;
mod ranks;
mod runs;
mod validate_cmd;
use folders::*;
use legacy_cmd::LegacyCmd;
pub(crate) use runs::check_text;
pub use runs::{dual_run, free_run};
use validate_cmd::validate;

#[derive(Parser, Debug)]
#[command(
    name = "blastsph",
    version,
    about = "SPH hydrocode for explosions in soil and water (Fortran legacy core + Rust twin)"
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
}

#[derive(clap::Args, Debug, Clone, Default)]
pub struct CaseArgs {
    /// Override a case key: --set sph.nnps=cell, --set material.loose_sand.pmin_pa=0
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Implementation of every module
    #[arg(long, value_name = "fortran|rust")]
    pub backend: Option<String>,
    /// Modules to run in Rust (comma-separated)
    #[arg(long, value_delimiter = ',', value_name = "M,..")]
    pub rust: Vec<String>,
    /// Modules to run in Fortran (comma-separated)
    #[arg(long, value_delimiter = ',', value_name = "M,..")]
    pub fortran: Vec<String>,
    /// Neighbour search
    #[arg(long, value_name = "direct|cell")]
    pub nnps: Option<String>,
    /// Stop at this time (s) instead of the case's end time
    #[arg(long = "end-time", value_name = "SECONDS")]
    pub end_time: Option<f64>,
    /// Refuse a case with more particles than this (default: what fits in 80 % of the
    /// machine's memory, estimated before anything is generated)
    #[arg(long = "max-particles", value_name = "N")]
    pub max_particles: Option<u64>,
    #[command(flatten)]
    pub legacy: LegacyArgs,
}

/// Your legacy code and the compatibility items (docs/howto/migrate.md).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LegacyArgs {
    /// A `legacy build` folder: your routines in place of the modules they stand for
    #[arg(long, value_name = "DIR")]
    pub legacy: Option<PathBuf>,
    /// Compatibility items of the Rust twins: a profile (liu-book), items to switch on
    /// (sound_speed), off (-sound_speed); comma-separated (as --set compat.ITEM=true|false)
    #[arg(long, value_name = "PROFILE,ITEM,-ITEM", allow_hyphen_values = true)]
    pub compat: Option<String>,
}

impl LegacyArgs {
    /// The `--set` overrides of the legacy build's manifest (its `density_clamp`, a routine that
    /// `includes_gravity`), then `sets`, then those of `--compat`.
    pub fn sets(&self, sets: &[String]) -> Result<Vec<String>> {
        let mut out = Vec::new();
        if let Some(dir) = &self.legacy {
            let info = crate::migration::builder::BuildInfo::read(dir)?;
            if let Some([lo, hi]) = info.density_clamp {
                out.push(format!("sph.density_clamp=[{lo:?},{hi:?}]"));
            }
            if info.gravity_in.is_some() {
                out.push("physics.gravity_in_forces=true".into());
            }
        }
        out.extend_from_slice(sets);
        if let Some(c) = &self.compat {
            out.extend(crate::migration::compat::sets_of(c)?);
        }
        Ok(out)
    }
}

/// When a run writes its checkpoint (checkpoint.bin: the full state, for `blastsph resume`).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CheckpointArgs {
    /// Write a checkpoint every N steps (besides every --checkpoint-wall seconds, at the end, and
    /// at a clean stop on SIGINT or SIGTERM)
    #[arg(long = "checkpoint-every", value_name = "N")]
    pub every: Option<u64>,
    /// Write a checkpoint every this many seconds of wall time (default 900)
    #[arg(long = "checkpoint-wall", value_name = "SECONDS")]
    pub wall: Option<f64>,
}

impl CheckpointArgs {
    fn policy(&self) -> Result<runner::Checkpoints> {
        let mut c = runner::Checkpoints::CLI;
        if let Some(n) = self.every {
            if n == 0 {
                return Err(input("--checkpoint-every 0: need at least 1 step"));
            }
            c.every_steps = Some(n);
        }
        if let Some(w) = self.wall {
            if !(w.is_finite() && w > 0.0) {
                return Err(input(format!("--checkpoint-wall {w}: must be a positive number of seconds")));
            }
            c.every_wall_s = Some(w);
        }
        Ok(c)
    }
}

#[derive(Subcommand, Debug)]
pub enum Cmd {
    /// Run a case into a run directory (particles.h5, particles.xmf, summary.json, gauges.csv,
    /// case.toml)
    Run {
        /// The case: a .toml file, or the name of one in the case folder (see --case-dir)
        case: PathBuf,
        /// Run directory (default: runs/<case name>)
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        #[command(flatten)]
        args: CaseArgs,
        /// Worker threads of the Rust modules (default: one per core)
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// No progress bar and no progress lines
        #[arg(long)]
        quiet: bool,
        /// Seconds between progress lines on stderr when it is not a terminal (a log file, a
        /// batch queue); on a terminal a bar is shown instead
        #[arg(long = "progress-every", value_name = "SECONDS", default_value = "5")]
        progress_every: f64,
        /// Folder to look a case name up in (default: cases/ of the repository around the
        /// current directory, else of the source tree this binary was built from)
        #[arg(long = "case-dir", value_name = "DIR")]
        case_dir: Option<PathBuf>,
        /// Replace a run directory that is not empty (its blastsph files are removed first;
        /// a folder holding other files is refused even then)
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        checkpoints: CheckpointArgs,
    },
    /// Continue a run from its last checkpoint (after a kill, a clean stop, or past its end with
    /// --end-time), appending to its particles.h5, gauges.csv and summary.json
    Resume {
        /// The run directory (holds checkpoint.bin, case.toml, particles.h5)
        dir: PathBuf,
        /// Run to this time (s) instead of the case's end time (case.toml is changed to it)
        #[arg(long = "end-time", value_name = "SECONDS")]
        end_time: Option<f64>,
        /// Continue although case.toml or the blastsph binary changed since the checkpoint
        #[arg(long = "allow-changed")]
        allow_changed: bool,
        /// Worker threads of the Rust modules (default: one per core; the results do not
        /// depend on it)
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// No progress bar and no progress lines
        #[arg(long)]
        quiet: bool,
        /// Seconds between progress lines on stderr when it is not a terminal
        #[arg(long = "progress-every", value_name = "SECONDS", default_value = "5")]
        progress_every: f64,
        /// Refuse a case with more particles than this (default: from the machine's memory)
        #[arg(long = "max-particles", value_name = "N")]
        max_particles: Option<u64>,
        #[command(flatten)]
        checkpoints: CheckpointArgs,
    },
    /// Run both implementations of every module at every step and compare them
    Dual {
        /// The case: a .toml file, or the name of one in the case folder (see --case-dir)
        case: PathBuf,
        /// Steps to run (default 100)
        #[arg(long, value_name = "N")]
        steps: Option<u64>,
        /// Where dual_report.json goes (default: runs/<case name>_dual); an earlier dual's
        /// report there is replaced, a folder with a run's files is refused
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Free-running mode: an all-Fortran and an all-Rust run from the same start
        #[arg(long)]
        free: bool,
        /// Override a case key: --set sph.nnps=cell, --set material.loose_sand.pmin_pa=0
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Neighbour search
        #[arg(long, value_name = "direct|cell")]
        nnps: Option<String>,
        /// Worker threads of the Rust modules (default: one per core)
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// Folder to look a case name up in (default as for `run`)
        #[arg(long = "case-dir", value_name = "DIR")]
        case_dir: Option<PathBuf>,
        /// Refuse a case with more particles than this (default: from the machine's memory)
        #[arg(long = "max-particles", value_name = "N")]
        max_particles: Option<u64>,
        #[command(flatten)]
        legacy: LegacyArgs,
    },
    /// Validate a case, print the module plan and the particle count
    Check {
        /// The case: a .toml file, or the name of one in the case folder (see --case-dir)
        case: PathBuf,
        #[command(flatten)]
        args: CaseArgs,
        /// Folder to look a case name up in (default as for `run`)
        #[arg(long = "case-dir", value_name = "DIR")]
        case_dir: Option<PathBuf>,
        /// Worker threads of the set-up (default: one per core): taken so that a `run` command
        /// line checks as it is; the plan and the estimates do not depend on it
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Measurements and plots of a finished run directory
    Report {
        /// The run directory (holds summary.json, case.toml, particles.h5)
        dir: PathBuf,
        /// Times of the particle snapshots (s, comma-separated; the nearest output of each);
        /// default: the start, the quarters and the end
        #[arg(long, value_delimiter = ',', value_name = "SECONDS,..")]
        times: Vec<f64>,
        /// Also write an animation of the run (animation.gif: the pressure map at every
        /// output step)
        #[arg(long)]
        animate: bool,
        /// The window of the particle maps (m, X_LO,X_HI,Y_LO,Y_HI; r and z in RZ), in place of
        /// the case's analysis.view_m
        #[arg(long, value_delimiter = ',', value_name = "X_LO,X_HI,Y_LO,Y_HI", allow_hyphen_values = true)]
        window: Vec<f64>,
    },
    /// The revolved 3D points of an axisymmetric run, for ParaView (revolved.h5, revolved.xmf
    /// in the run directory)
    Revolve {
        /// The run directory of an axisymmetric run
        dir: PathBuf,
        /// Sectors (points per ring), 1 to 720
        #[arg(long, default_value_t = 36)]
        sectors: usize,
        /// Angle revolved (degrees, (0, 360]; 270 shows the inside)
        #[arg(long, default_value_t = 360.0)]
        angle: f64,
    },
    /// Run every thesis scene, compare with the thesis and check its trends (validation.md)
    Validate {
        /// Where the runs and validation.md go
        #[arg(long, default_value = "runs/validation", value_name = "DIR")]
        out: PathBuf,
        /// Folder of the case files (default as for `run`)
        #[arg(long, alias = "case-dir", value_name = "DIR")]
        cases: Option<PathBuf>,
        /// Only these scenes (comma-separated)
        #[arg(long, value_delimiter = ',', value_name = "SCENE,..")]
        only: Vec<String>,
        #[command(flatten)]
        args: CaseArgs,
        /// Worker threads of the Rust modules (default: one per core)
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// No progress lines of the runs
        #[arg(long)]
        quiet: bool,
    },
    /// Bring your own legacy code: build it with shims into a library (docs/howto/migrate.md)
    Legacy {
        #[command(subcommand)]
        cmd: LegacyCmd,
    },
    /// Speed against error: a matrix of cases × resolutions × backends × searches × kernels
    /// (bench.csv, bench.json, error_vs_time.png; docs/performance.md)
    Bench {
        #[command(flatten)]
        args: crate::bench::BenchArgs,
    },
    /// Error bars: the case at spacings Δx, Δx/2, Δx/4; each headline figure's observed order,
    /// extrapolated value and grid convergence index (DIR/converge.json, a plot per figure; docs/howto/converge.md)
    Converge {
        #[command(flatten)]
        args: crate::converge::ConvergeArgs,
    },
}

fn overrides(a: &CaseArgs) -> Result<Overrides> {
    let backend = match &a.backend {
        Some(b) => Some(Backend::parse(b).ok_or_else(|| input(format!("--backend {b}: must be fortran or rust")))?),
        None => None,
    };
    Ok(Overrides {
        backend,
        rust: a.rust.clone(),
        fortran: a.fortran.clone(),
        nnps: a.nnps.clone(),
        end_time: a.end_time,
        max_particles: a.max_particles,
        bridge: Some(crate::migration::bridge(a.legacy.legacy.clone(), false)),
    })
}

/// Builds the global pool of the Rust modules: `n` threads, or rayon's default.
fn threads(n: Option<usize>) -> Result<()> {
    if let Some(k) = n
        && !(1..=MAX_THREADS).contains(&k)
    {
        return Err(input(format!("--threads {k}: need 1 to {MAX_THREADS} threads")));
    }
    // the whole run executes on a worker (see `on_pool`): give it the main thread's stack room
    let per_rank = n.or_else(ranks::default_threads);
    let built =
        rayon::ThreadPoolBuilder::new().num_threads(per_rank.unwrap_or(0)).stack_size(STACK_BYTES).build_global();
    match (built, n) {
        (Err(e), Some(_)) => Err(input(format!("--threads: {e}"))),
        _ => Ok(()),
    }
}

const STACK_BYTES: usize = 16 << 20;
/// The most worker threads a run may ask for.
const MAX_THREADS: usize = 1024;

/// Runs `f` on a worker thread of the global pool. The Rust modules make a few dozen parallel
/// calls per step; started from a worker, each runs inline with one thread, and with more it
/// wakes the others instead of handing the whole call over from an outside thread and blocking.
fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| f())
}

/// A clap error as one line: its first line and the usage of the command, exit status 2.
fn clap_line(e: &clap::Error) -> String {
    let text = e.to_string();
    let mut lines = text.lines().skip_while(|l| l.trim().is_empty());
    let mut first = lines.next().unwrap_or("error: bad arguments").trim().to_string();
    // a first line that ends in a colon lists what it names on the lines under it (the missing
    // arguments): they join it
    if first.ends_with(':') {
        let named: Vec<&str> = lines.map(str::trim).take_while(|l| !l.is_empty() && !l.starts_with("Usage:")).collect();
        if !named.is_empty() {
            first = format!("{first} {}", named.join(", "));
        }
    }
    if !first.starts_with("error:") {
        first = format!("error: {first}");
    }
    let usage = text.lines().find_map(|l| l.trim().strip_prefix("Usage:")).map(|u| u.trim().to_string());
    match usage {
        Some(u) => {
            let cmd: Vec<&str> = u.split_whitespace().take_while(|w| !w.starts_with(['[', '<', '-'])).collect();
            format!("{first} (usage: {u}; `{} --help` explains every argument)", cmd.join(" "))
        }
        None => {
            // a bad value: no usage in clap's text; the subcommand's help when one was named
            use clap::CommandFactory;
            let named = std::env::args().nth(1).filter(|a| Cli::command().get_subcommands().any(|c| c.get_name() == a));
            match named {
                Some(c) if c != "help" => format!("{first} (`blastsph {c} --help` explains every argument)"),
                _ => format!("{first} (`blastsph --help` lists the commands)"),
            }
        }
    }
}

/// One line on stderr: a message never spans lines, whatever it quotes.
fn one_line(s: &str) -> String {
    let line: String = s.chars().map(|c| if c == '\n' || c == '\r' { ' ' } else { c }).collect();
    // a value the message quotes whole (a 100 kB number given to --set) is cut to its start
    line.split(' ')
        .map(|w| {
            let n = w.chars().count();
            if n > 120 {
                format!("{}… ({n} characters)", w.chars().take(60).collect::<String>())
            } else {
                w.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The command line, parsed: a negative number after a flag is its value (`--end-time -1` is
/// refused by the flag's own range check, naming it, not taken for an unknown flag `-1`).
fn parse_args() -> std::result::Result<Cli, clap::Error> {
    use clap::{CommandFactory, FromArgMatches};
    fn negatives(c: clap::Command) -> clap::Command {
        c.allow_negative_numbers(true).mut_subcommands(negatives)
    }
    let m = negatives(Cli::command()).try_get_matches()?;
    Cli::from_arg_matches(&m)
}

/// Entry point; returns the exit status: 0 done, 1 an I/O failure during a run, 2 refused input,
/// 3 unstable, 4 a dual run out of tolerance, 5 stopped cleanly by a signal (README).
pub fn main() -> i32 {
    // output into a pipe that closes (`blastsph dual … | head -1`) ends the process quietly, as
    // it ends other command-line tools (Rust ignores SIGPIPE, and the failed write would panic)
    crate::os_ffi::default_sigpipe();
    // MPI first under mpirun (it is finalised when this returns)
    let _mpi = ranks::start();
    // a panic is a bug: one line saying so (never a backtrace on a user's terminal)
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_default();
        let at = info.location().map(|l| format!(" at {}:{}", l.file(), l.line())).unwrap_or_default();
        eprintln!("{}", one_line(&format!("internal error (a bug in blastsph, please report it): {msg}{at}")));
        ranks::on_panic();
    }));
    let cli = match parse_args() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind;
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    let _ = e.print();
                    0
                }
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    eprintln!("error: a command is needed (usage: blastsph <COMMAND>; `blastsph --help` lists them)");
                    2
                }
                _ => {
                    if ranks::speaks() {
                        eprintln!("{}", one_line(&clap_line(&e)));
                    }
                    2
                }
            };
        }
    };
    let done = ranks::supported(&cli.cmd).and_then(|_| dispatch(cli));
    if let Err(e) = &done {
        if ranks::speaks() {
            match e {
                SphError::Stopped(m) => eprintln!("{}", one_line(&format!("stopped {m}"))),
                e => eprintln!("{}", one_line(&format!("error: {e}"))),
            }
        }
        ranks::end(e);
    }
    match done {
        Ok(code) => code,
        Err(e) => e.exit_code(),
    }
}

/// SIGINT and SIGTERM set the run's stop flag: it finishes its step, writes a checkpoint and
/// stops with status 5. A second signal of the same kind ends the program at once (status 130
/// for SIGINT, 143 for SIGTERM) when it comes more than [`SECOND_SIGNAL_S`] after the first: a
/// batch system or `timeout` that signals the process and then its process group sends two at
/// once, and both mean one clean stop.
fn stop_on_signals() -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    let flag = runner::stop_flag();
    // armed a moment after the first signal set the flag
    let armed = Arc::new(AtomicBool::new(false));
    for (sig, code) in [(SIGINT, 130), (SIGTERM, 143)] {
        signal_hook::flag::register_conditional_shutdown(sig, code, armed.clone())
            .and_then(|_| signal_hook::flag::register(sig, flag.clone()))
            .io_at("cannot install the signal handlers")?;
    }
    let (f, a) = (flag.clone(), armed);
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            while !f.load(Ordering::SeqCst) {
                std::thread::sleep(std::time::Duration::from_millis(50));
            }
            std::thread::sleep(std::time::Duration::from_secs_f64(SECOND_SIGNAL_S));
            a.store(true, Ordering::SeqCst);
        })
        .io_at("cannot start the signal watcher")?;
    Ok(())
}

/// Seconds after a first SIGINT or SIGTERM during which a second one is the same request.
const SECOND_SIGNAL_S: f64 = 1.0;

fn dispatch(cli: Cli) -> Result<i32> {
    match cli.cmd {
        Cmd::Run { case, out, args, threads: th, quiet, progress_every: pe, case_dir, force, checkpoints } => {
            progress_every(pe)?;
            let case = crate::casedir::resolve(&case, case_dir.as_deref())?;
            threads(th)?;
            let opts = RunOptions {
                out,
                sets: args.legacy.sets(&args.sets)?,
                ov: overrides(&args)?,
                quiet,
                threads: th,
                force,
                checkpoints: checkpoints.policy()?,
                stop_after_step: None,
            };
            stop_on_signals()?;
            let r = on_pool(|| runner::run(&case, &opts))?;
            if ranks::speaks() {
                finished(&r, "wall");
            }
            Ok(0)
        }
        Cmd::Resume {
            dir,
            end_time,
            allow_changed,
            threads: th,
            quiet,
            progress_every: pe,
            max_particles,
            checkpoints,
        } => {
            progress_every(pe)?;
            threads(th)?;
            let o = crate::runner::restart::ResumeOptions {
                end_time,
                allow_changed,
                quiet,
                checkpoints: checkpoints.policy()?,
                max_particles,
                stop_after_step: None,
            };
            stop_on_signals()?;
            let r = on_pool(|| crate::runner::restart::resume(&dir, &o))?;
            if ranks::speaks() {
                finished(&r, "wall in all");
            }
            Ok(0)
        }
        Cmd::Check { case, args, case_dir, threads: n } => check(case, args, case_dir, n),
        Cmd::Validate { out, cases, only, args, threads: th, quiet } => validate(out, cases, only, args, th, quiet),
        Cmd::Bench { args } => {
            let o = crate::bench::BenchOptions::from_args(&args)?;
            if !o.dry_run {
                own_folder(&o.out, "bench.json", "bench")?;
                threads(o.threads)?;
            }
            // on a pool worker, as `run` is: the runs' parallel calls then start from a worker
            let b = on_pool(|| crate::bench::bench(&o))?;
            print!("{}", b.text);
            for f in &b.files {
                println!("written: {}", f.display());
            }
            Ok(0)
        }
        Cmd::Converge { args } => {
            let (case, o) = args.options()?;
            own_folder(&o.out, crate::converge::JSON, "converge")?;
            threads(args.threads)?;
            let (table, files) = on_pool(|| crate::converge::converge(&case, &o))?;
            print!("{table}");
            for f in &files {
                println!("written: {}", f.display());
            }
            Ok(0)
        }
        Cmd::Legacy { cmd } => legacy_cmd::legacy(cmd),
        Cmd::Revolve { dir, sectors, angle } => {
            crate::rundir::check_existing(&dir, "revolve")?;
            let xmf = crate::revolve::revolve(&dir, sectors, angle)?;
            println!("revolved: {} (open it in ParaView)", xmf.display());
            Ok(0)
        }
        Cmd::Report { dir, times, animate, window } => {
            if let Some(t) = times.iter().find(|t| !t.is_finite() || **t < 0.0 || **t > 1e6) {
                return Err(input(format!("--times {t}: times must be finite, from 0 to 1e6 s")));
            }
            if times.len() > 1000 {
                return Err(input(format!("--times: {} times (at most 1000 snapshots)", times.len())));
            }
            crate::rundir::check_existing(&dir, "report")?;
            let window = match window[..] {
                [] => None,
                [x0, x1, y0, y1] if [x0, x1, y0, y1].iter().all(|v| v.is_finite()) && x1 > x0 && y1 > y0 => {
                    Some([x0, x1, y0, y1])
                }
                _ => {
                    return Err(input(format!(
                        "--window {window:?}: need four finite numbers X_LO,X_HI,Y_LO,Y_HI (m) with X_HI > X_LO and Y_HI > Y_LO"
                    )));
                }
            };
            crate::report::report_in(&dir, &times, animate, window)?;
            Ok(0)
        }
        Cmd::Dual { case, steps, out, free, sets, nnps, threads: th, case_dir, max_particles, legacy } => {
            if steps == Some(0) {
                return Err(input("--steps 0: a dual run compares at least one step"));
            }
            let case = crate::casedir::resolve(&case, case_dir.as_deref())?;
            threads(th)?;
            let c = case::load(&case, &legacy.sets(&sets)?)?;
            if free && legacy.legacy.is_some() {
                return Err(input("dual --free --legacy: the free mode compares blastsph's two backends; drop --free"));
            }
            let ov = Overrides {
                nnps,
                max_particles,
                bridge: Some(crate::migration::bridge(legacy.legacy.clone(), false)),
                ..Default::default()
            };
            let dir = out
                .unwrap_or_else(|| PathBuf::from("runs").join(format!("{}_dual", crate::rundir::sanitize(c.name()))));
            report_folder(&dir, &["dual_report.json", "dual_free.json"], "dual run")?;
            crate::rundir::prepare(&dir, false)?;
            if free {
                let rep = on_pool(|| free_run(c, &ov, steps.unwrap_or(100), &dir))?;
                println!("{rep}");
                Ok(0)
            } else {
                // a signal stops it after the step, with the steps so far reported (status 5)
                stop_on_signals()?;
                on_pool(|| dual_run(c, &ov, steps.unwrap_or(100), &dir))
            }
        }
    }
}

/// `blastsph check CASE`: the plan, the warnings and the size estimate of a case.
fn check(case: PathBuf, args: CaseArgs, case_dir: Option<PathBuf>, n: Option<usize>) -> Result<i32> {
    threads(n)?;
    let case = crate::casedir::resolve(&case, case_dir.as_deref())?;
    let c = case::load(&case, &args.legacy.sets(&args.sets)?)?;
    let est = case::size::check(&c, args.max_particles)?;
    let mut ov = overrides(&args)?;
    // a legacy set-up routine runs in a scratch folder: check writes nothing of the user's
    ov.bridge = Some(crate::migration::attach::check_bridge(args.legacy.legacy.clone()));
    let sim = Sim::new(c, &ov)?;
    case::slips::check(&sim.case, &sim.p, sim.cfg.dx_min)?;
    // under mpirun every rank checks the same case; rank 0 alone prints
    if !ranks::speaks() {
        return Ok(0);
    }
    print!("{}", check_text(&sim));
    // a legacy build's pair arrays against the estimate (its STOP, or a refusal, would
    // come at the first step)
    if let Some(info) = args.legacy.legacy.as_deref().and_then(|d| crate::migration::BuildInfo::read(d).ok())
        && est.pairs > info.max_interaction as f64
        && sim.plan.legacy["routines"]
            .as_object()
            .is_some_and(|r| r.values().any(|v| v["status"] == "run" || v["status"] == "alone"))
    {
        println!(
            "warning: about {:.3e} neighbour pairs (the estimate below) against the legacy build's max_interaction = {} (its {}): a routine that takes the pairs is refused, or your search stops, at the first step; raise max_interaction and rebuild",
            est.pairs,
            info.max_interaction,
            info.include_name()
        );
    }
    let (limit, from) = case::size::memory_limit();
    println!(
        "size (estimated before generating): at most {:.0} particles, {:.3e} neighbour pairs, {} of memory ({})",
        est.particles,
        est.pairs,
        case::size::bytes_text(est.bytes),
        match args.max_particles {
            Some(m) => format!("limit: --max-particles {m}"),
            None => format!("limit: {} of memory, {from}", case::size::bytes_text(limit)),
        }
    );
    Ok(0)
}

/// What a finished `run` or `resume` prints: its line, and a warning when its energy balance is
/// off (src/report/mod.rs `energy_warning`).
fn finished(r: &runner::RunResult, wall: &str) {
    println!("{}", finished_line(&r.summary, wall, &r.dir));
    if let Some(w) = crate::report::energy_warning(&r.summary) {
        eprintln!("warning: {w}");
    }
}

/// The one line a finished `run` or `resume` prints: case, particles, steps, time, wall time
/// (`wall` names what it counts), backend, run directory.
fn finished_line(s: &serde_json::Value, wall: &str, dir: &std::path::Path) -> String {
    // a user's legacy routines (`--legacy`) named beside the backend of the rest
    let legacy: Vec<&str> =
        s["legacy"].as_array().map_or(Vec::new(), |a| a.iter().filter_map(|v| v.as_str()).collect());
    let legacy = if legacy.is_empty() { String::new() } else { format!("; legacy routines in {}", legacy.join(", ")) };
    format!(
        "{}: {} particles, {} steps, t = {:.4e} s, {:.2} s {wall} ({} backend{legacy}), output in {}",
        s["case"].as_str().unwrap_or("?"),
        s["particles"],
        s["steps"],
        s["time"].as_f64().unwrap_or(0.0),
        s["wall_seconds"].as_f64().unwrap_or(0.0),
        s["backend"].as_str().unwrap_or("?"),
        dir.display()
    )
}
