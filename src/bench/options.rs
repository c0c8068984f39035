//! The bench's command line and options.

use crate::error::Result;

use crate::case::KernelKind;
use crate::case::NnpsKind;
use crate::error::input;
use crate::modules::Backend;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    /// Cases: names in the case folder, or paths to .toml files (comma-separated)
    #[arg(long, value_delimiter = ',', default_value = "shock_tube", value_name = "NAME,..")]
    pub cases: Vec<String>,
    /// Folder of the case files (default: cases/ of the repository around the current directory, else of the source tree)
    #[arg(long = "case-dir", value_name = "DIR")]
    pub case_dir: Option<PathBuf>,
    /// Refinement factors k: every spacing Δx becomes Δx/k (0.5 = twice as coarse)
    #[arg(long, value_delimiter = ',', default_value = "1,2,4", value_name = "K,..", allow_hyphen_values = true)]
    pub resolutions: Vec<String>,
    /// Backends: every module in Rust, or every module in Fortran
    #[arg(long, value_delimiter = ',', default_value = "rust,fortran", value_name = "rust|fortran,..")]
    pub backends: Vec<String>,
    /// Neighbour searches
    #[arg(long, value_delimiter = ',', default_value = "cell", value_name = "cell|direct,..")]
    pub nnps: Vec<String>,
    /// Kernels
    #[arg(long, value_delimiter = ',', default_value = "cubic", value_name = "cubic|gauss|quintic|wendland,..")]
    pub kernels: Vec<String>,
    /// Worker threads of the Rust modules (the Fortran core is serial); a list (`1,2`) runs every
    /// Rust configuration on each, one after the other (the thread count an axis of the matrix)
    #[arg(long, value_name = "N[,N..]", allow_hyphen_values = true)]
    pub threads: Option<String>,
    /// Run every configuration under `mpirun -np N` for each N (a list: `1,2`), with this binary;
    /// reports wall time, particle-steps/s, the ratio to one rank and the gathers' share of each
    #[arg(long, value_name = "N[,N..]", allow_hyphen_values = true)]
    pub ranks: Option<String>,
    /// Stop every run at this time (s) instead of the case's end time
    #[arg(long = "end-time", value_name = "SECONDS", allow_hyphen_values = true)]
    pub end_time: Option<String>,
    /// Where the runs, bench.csv, bench.json and the plots go
    #[arg(long, default_value = "runs/bench", value_name = "DIR")]
    pub out: PathBuf,
    /// Skip direct-search runs with more particles than this (reported as skipped)
    #[arg(long = "max-direct-particles", default_value = "20000", value_name = "N", allow_hyphen_values = true)]
    pub max_direct_particles: String,
    /// Runs of each configuration; the row reports the fastest (the physics of the repeats is
    /// bitwise the same) and lists every wall time. For timings on a machine shared with other work.
    #[arg(long, default_value = "1", value_name = "N", allow_hyphen_values = true)]
    pub repeat: String,
    /// List the matrix (with particle counts) and run nothing
    #[arg(long = "dry-run")]
    pub dry_run: bool,
    /// Override a key of every case before it is refined: --set 'analysis.window_m=[-0.35, 0.35]'
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

/// The bench's matrix and settings, checked.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Case files, in the order given.
    pub cases: Vec<PathBuf>,
    /// Refinement factors, ascending.
    pub resolutions: Vec<f64>,
    pub backends: Vec<Backend>,
    pub nnps: Vec<NnpsKind>,
    pub kernels: Vec<KernelKind>,
    /// The pool's threads: the one `--threads` value, or the largest of a list.
    pub threads: Option<usize>,
    /// `--threads` as a list of more than one value: each Rust configuration runs on each.
    pub thread_axis: Vec<usize>,
    /// `--ranks`: the rank counts each configuration runs on under mpirun (empty: in this process).
    pub ranks: Vec<usize>,
    pub end_time: Option<f64>,
    pub out: PathBuf,
    pub max_direct_particles: usize,
    /// Runs of each configuration (the fastest is reported).
    pub repeat: usize,
    pub dry_run: bool,
    pub sets: Vec<String>,
}

pub(super) fn nnps_name(n: NnpsKind) -> &'static str {
    match n {
        NnpsKind::Cell => "cell",
        NnpsKind::Direct => "direct",
    }
}

/// Parses a comma-separated flag: every item through `f`, none empty, none twice.
pub(super) fn list<T: PartialEq>(
    flag: &str,
    items: &[String],
    f: impl Fn(&str) -> Option<T>,
    what: &str,
) -> Result<Vec<T>> {
    let mut out = Vec::new();
    for s in items {
        let s = s.trim();
        let v = f(s).ok_or_else(|| input(format!("--{flag} {s}: {what}")))?;
        if out.contains(&v) {
            return Err(input(format!("--{flag}: `{s}` is given twice")));
        }
        out.push(v);
    }
    if out.is_empty() {
        return Err(input(format!("--{flag}: give at least one value")));
    }
    Ok(out)
}

impl BenchOptions {
    /// Checks the flags; every error is one line naming the flag.
    pub fn from_args(a: &BenchArgs) -> Result<BenchOptions> {
        let resolutions = {
            let mut r = list(
                "resolutions",
                &a.resolutions,
                |s| s.parse::<f64>().ok().filter(|k| k.is_finite() && *k > 0.0),
                "a refinement factor must be a positive number (1 = the case as written, 2 = half the spacing)",
            )?;
            r.sort_by(|x, y| x.total_cmp(y));
            r
        };
        let backends = list("backends", &a.backends, Backend::parse, "must be rust or fortran")?;
        let nnps = list(
            "nnps",
            &a.nnps,
            |s| match s {
                "cell" => Some(NnpsKind::Cell),
                "direct" => Some(NnpsKind::Direct),
                _ => None,
            },
            "must be cell or direct",
        )?;
        let kernels = list(
            "kernels",
            &a.kernels,
            |s| match s {
                "cubic" => Some(KernelKind::Cubic),
                "gauss" => Some(KernelKind::Gauss),
                "quintic" => Some(KernelKind::Quintic),
                "wendland" => Some(KernelKind::Wendland),
                _ => None,
            },
            "must be cubic, gauss, quintic or wendland",
        )?;
        let thread_list = match &a.threads {
            None => Vec::new(),
            Some(s) => s
                .split(',')
                .map(|t| t.trim().parse::<usize>().ok().filter(|n| *n > 0))
                .collect::<Option<Vec<usize>>>()
                .filter(|l| !l.is_empty())
                .ok_or_else(|| {
                    input(format!("--threads {s}: need whole numbers of threads, at least 1 (e.g. 2, or 1,2)"))
                })?,
        };
        if let Some(t) = thread_list.iter().enumerate().find_map(|(i, t)| thread_list[..i].contains(t).then_some(t)) {
            return Err(input(format!("--threads {}: {t} threads twice", a.threads.as_deref().unwrap_or(""))));
        }
        let threads = thread_list.iter().copied().max();
        let mut thread_axis = thread_list;
        if thread_axis.len() < 2 {
            thread_axis.clear();
        }
        let mut ranks = match &a.ranks {
            None => Vec::new(),
            Some(s) => {
                let items: Vec<String> = s.split(',').map(String::from).collect();
                list(
                    "ranks",
                    &items,
                    |t| t.parse::<usize>().ok().filter(|n| (1..=4096).contains(n)),
                    "need whole numbers of ranks from 1 to 4096 (e.g. 1,2)",
                )?
            }
        };
        // in ascending order, once each: the ratio to one rank needs the one-rank run first
        ranks.sort_unstable();
        ranks.dedup();
        if !ranks.is_empty() && !thread_axis.is_empty() {
            return Err(input("--ranks: give --threads one value (the threads of each rank), not a list"));
        }
        let end_time = match &a.end_time {
            None => None,
            Some(s) => Some(
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|t| t.is_finite() && *t > 0.0)
                    .ok_or_else(|| input(format!("--end-time {s}: must be a positive time in seconds")))?,
            ),
        };
        let max_direct_particles = a.max_direct_particles.trim().parse::<usize>().map_err(|_| {
            input(format!("--max-direct-particles {}: need a whole number of particles", a.max_direct_particles))
        })?;
        let repeat = a
            .repeat
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&r| (1..=100).contains(&r))
            .ok_or_else(|| input(format!("--repeat {}: need a whole number of runs from 1 to 100", a.repeat)))?;
        let mut cases = Vec::new();
        for c in &a.cases {
            let c = c.trim();
            if c.is_empty() {
                return Err(input("--cases: an empty case name"));
            }
            let path = if c.ends_with(".toml") || c.contains('/') {
                PathBuf::from(c)
            } else {
                crate::casedir::folder(a.case_dir.as_deref())?.join(format!("{c}.toml"))
            };
            if !path.is_file() {
                return Err(input(format!("--cases {c}: no case file {}", path.display())));
            }
            if cases.contains(&path) {
                return Err(input(format!("--cases: `{c}` is given twice")));
            }
            cases.push(path);
        }
        if cases.is_empty() {
            return Err(input("--cases: give at least one case"));
        }
        Ok(BenchOptions {
            cases,
            resolutions,
            backends,
            nnps,
            kernels,
            threads,
            thread_axis,
            ranks,
            end_time,
            out: a.out.clone(),
            max_direct_particles,
            repeat,
            dry_run: a.dry_run,
            sets: a.sets.clone(),
        })
    }
}
