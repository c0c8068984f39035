//! `blastsph legacy compare`: a run's particles.h5 against what the user's own program wrote
//! (docs/howto/migrate.md). The manifest's output routine (`module = "output"`) is called with
//! the state of one frame, in a scratch folder, so the run's state is written in the program's
//! own layout and digits. Each file it writes is then compared with the program's file of the
//! same name, number by number. Probes name the columns: the routine is called again with one
//! argument perturbed, and the columns that change are that argument's.

use super::bind::{self, Buf, Ctx};
use super::builder::RoutineInfo;
use super::ffi::{Args, LegacyLib};
use super::vocab::{Shape, vector_component};
use crate::error::{Result, SphError, input};
use crate::state::{Particles, Work};
use serde_json::{Value, json};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

mod table;
use table::Table;

/// The state of one frame of the run: its group `Step#N`, time (s) and real particles, in the
/// order of their ids (the program's order).
pub struct Snapshot {
    pub step: usize,
    pub time: f64,
    pub p: Particles,
}

/// What `legacy compare` is given.
pub struct Opts {
    /// The run folder (particles.h5, case.toml).
    pub run: PathBuf,
    /// The `legacy build` folder.
    pub legacy: PathBuf,
    /// Where the user's program wrote its output.
    pub program_out: PathBuf,
    /// Where compare.json and the run's files in the program's format go.
    pub out: PathBuf,
}

/// The vocabulary names whose values particles.h5 (or the run's case) holds; the routine gets
/// zeros for any other.
fn in_particles_h5(name: &str) -> bool {
    let base = vector_component(name).map_or(name, |(b, _)| b);
    matches!(
        base,
        "x" | "vx"
            | "mass"
            | "rho"
            | "p"
            | "u"
            | "hsml"
            | "itype"
            | "mat"
            | "ntotal"
            | "nvirt"
            | "dt"
            | "time"
            | "itimestep"
    )
}

/// Sets the current folder for the legacy call, and back after.
struct Cwd(Option<PathBuf>);
impl Drop for Cwd {
    fn drop(&mut self) {
        if let Some(d) = &self.0 {
            let _ = std::env::set_current_dir(d);
        }
    }
}

/// The scratch folder where the routine runs: `work/` (its current folder, with the manifest's
/// `run_dirs`) and `data/` beside it (the book's `../data/`).
struct Scratch {
    root: PathBuf,
    cwd: PathBuf,
    run_dirs: Vec<String>,
}

impl Scratch {
    /// Empties the folder and makes it again.
    fn reset(&self) -> Result<()> {
        let io = |e: std::io::Error| SphError::Io(format!("{}: {e}", self.root.display()));
        if self.root.exists() {
            std::fs::remove_dir_all(&self.root).map_err(io)?;
        }
        for d in
            [self.cwd.clone(), self.root.join("data")].into_iter().chain(self.run_dirs.iter().map(|d| self.cwd.join(d)))
        {
            std::fs::create_dir_all(&d).map_err(io)?;
        }
        Ok(())
    }

    /// The files under the folder, by their path relative to `work/` (`../data/f_xv.dat` for
    /// the book's), with their tokens.
    fn files(&self) -> Result<BTreeMap<String, Table>> {
        let mut out = BTreeMap::new();
        let mut stack = vec![self.root.clone()];
        while let Some(d) = stack.pop() {
            let rd = std::fs::read_dir(&d).map_err(|e| SphError::Io(format!("{}: {e}", d.display())))?;
            for e in rd.flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_none_or(|x| x != "stdout") {
                    let rel = match p.strip_prefix(&self.cwd) {
                        Ok(r) => r.to_string_lossy().into_owned(),
                        Err(_) => format!("../{}", p.strip_prefix(&self.root).unwrap_or(&p).to_string_lossy()),
                    };
                    out.insert(rel, Table::read(&p)?);
                }
            }
        }
        Ok(out)
    }
}

/// One probe: its name (`x(2)` for a component), the vocabulary name it perturbs, and the columns
/// it changed, by file.
type Probe = (String, String, BTreeMap<String, Vec<usize>>);

/// The output routine and the buffers of its arguments, filled from the state.
struct Call<'a> {
    lib: &'a LegacyLib,
    r: &'a RoutineInfo,
    bufs: Vec<Buf>,
    scratch: &'a Scratch,
}

impl Call<'_> {
    /// Calls the routine on `bufs` in the scratch folder (what it prints kept out of the
    /// report) and reads the files it wrote.
    fn run(&self, bufs: &mut [Buf]) -> Result<BTreeMap<String, Table>> {
        self.scratch.reset()?;
        let routine = self.lib.routine(&self.r.name)?;
        let mut args = Args::new();
        for (b, buf) in self.r.bindings.iter().zip(bufs.iter_mut()) {
            args = match buf {
                Buf::R(v) => args.real(&b.name, v),
                Buf::I(v) => args.int(&b.name, v),
            };
        }
        let log = self.scratch.root.join("output.stdout");
        let (r, _) = super::ffi::quiet_stdout(&log, || {
            let back = std::env::current_dir().ok();
            std::env::set_current_dir(&self.scratch.cwd)
                .map_err(|e| SphError::Io(format!("{}: {e}", self.scratch.cwd.display())))?;
            let _cwd = Cwd(back);
            let r = routine.call(&mut args);
            super::ffi::flush_fortran();
            r
        });
        r?;
        self.scratch.files()
    }

    /// The columns each probe changes: for every per-particle argument (each component of a
    /// vector) and real scalar, the routine called with it perturbed (v → 1.25 v + 0.5; an
    /// integer + 1). Returns (probe name, vocabulary name) → changed columns by file.
    fn probe(&self, base: &BTreeMap<String, Table>, dim: usize, n: usize) -> Result<Vec<Probe>> {
        let mut out = Vec::new();
        for (k, b) in self.r.bindings.iter().enumerate() {
            let stride = b.shape.stride(dim);
            let per_particle = b.shape.per_particle();
            let scalar_real = b.shape == Shape::Scalar && matches!(self.bufs[k], Buf::R(_));
            if !(per_particle || scalar_real) {
                continue;
            }
            for comp in 0..stride {
                let mut bufs = self.bufs.clone();
                let rows = if per_particle { n } else { 1 };
                match &mut bufs[k] {
                    Buf::R(v) => (0..rows).for_each(|i| {
                        let j = comp + stride * i;
                        if j < v.len() {
                            v[j] = 1.25 * v[j] + 0.5;
                        }
                    }),
                    Buf::I(v) => (0..rows).for_each(|i| {
                        if let Some(x) = v.get_mut(comp + stride * i) {
                            *x += 1;
                        }
                    }),
                }
                let files = self.run(&mut bufs)?;
                let changed = base
                    .iter()
                    .filter_map(|(f, t)| files.get(f).map(|u| (f.clone(), t.changed_columns(u))))
                    .filter(|(_, c)| !c.is_empty())
                    .collect();
                let label = if stride > 1 { format!("{}({})", b.name, comp + 1) } else { b.name.clone() };
                out.push((label, b.name.clone(), changed));
            }
        }
        Ok(out)
    }
}

/// The buffers of the routine's arguments for the state `p` at time `time`.
fn buffers(r: &RoutineInfo, p: &Particles, itype: &[i32], (dt, time): (f64, f64)) -> Vec<Buf> {
    let work = Work::default();
    let mut scratch = HashMap::new();
    let step = if dt > 0.0 { (time / dt).round() as i32 } else { 0 };
    let mut ctx = Ctx {
        dim: p.dim,
        itimestep: step,
        dt,
        time,
        slots: Default::default(),
        itype,
        nbuf: p.ntotal,
        pbuf: 0,
        scratch: &mut scratch,
    };
    let split = virtual_split(p);
    r.bindings
        .iter()
        .map(|b| match (b.name.as_str(), split) {
            ("ntotal", Some((n, _))) => Buf::I(vec![n as i32]),
            ("nvirt", Some((_, nv))) => Buf::I(vec![nv as i32]),
            _ => bind::gather(&b.name, b.shape == Shape::ParticleVec, b.shape.per_pair(), &mut ctx, p, &work),
        })
        .collect()
}

/// The book's count of real and virtual particles, `(ntotal, nvirt)`, where the run's boundary
/// particles all come after its ordinary ones (in the order of the ids, as a `virt_part` appends
/// them): an output routine then writes each kind where the program does. None otherwise: every
/// particle is then counted in `ntotal`.
fn virtual_split(p: &Particles) -> Option<(usize, usize)> {
    let nb = p.bnd.iter().filter(|&&b| b != 0).count();
    let n0 = p.nreal - nb;
    (nb > 0 && p.ntotal == p.nreal && p.bnd[..n0].iter().all(|&b| b == 0)).then_some((n0, nb))
}

/// The type code of each material of the run's case (as `run --legacy` gives them).
fn itype_codes(lib: &LegacyLib, case: &crate::case::Case) -> Vec<i32> {
    let info = lib.info();
    case.materials
        .iter()
        .map(|m| {
            let kind = m.eos.kind();
            info.itype
                .get(&m.name)
                .or_else(|| info.itype.get(kind))
                .copied()
                .or_else(|| super::legacy::book_code(kind))
                .unwrap_or(0)
        })
        .collect()
}

/// `blastsph legacy compare`: the report's text and compare.json's value.
pub fn compare(o: &Opts, case: &crate::case::Case, snap: &Snapshot) -> Result<(String, Value)> {
    let lib = LegacyLib::open(&o.legacy)?;
    let info = lib.info();
    let r = info.routines.iter().find(|r| r.modules.iter().any(|m| m == "output")).ok_or_else(|| {
        input(format!(
            "--legacy {}: no output routine mapped: map the routine that writes your program's output with module = \"output\" in legacy.toml and rebuild",
            o.legacy.display()
        ))
    })?;
    if !o.program_out.is_dir() {
        return Err(input(format!("--program-out {}: no such folder", o.program_out.display())));
    }
    if case.dim != info.dim {
        return Err(input(format!(
            "--legacy {}: the build has dim = {}, the run dim = {}",
            o.legacy.display(),
            info.dim,
            case.dim
        )));
    }
    let (p, n) = (&snap.p, snap.p.ntotal);
    info.check_capacity(n, None)?;
    let dt = case.time.dt_s.unwrap_or(0.0);
    let itype = itype_codes(&lib, case);
    let scratch =
        Scratch { root: o.out.join("written"), cwd: o.out.join("written/work"), run_dirs: info.run_dirs.clone() };
    let call = Call { lib: &lib, r, bufs: buffers(r, p, &itype, (dt, snap.time)), scratch: &scratch };
    let base = call.run(&mut call.bufs.clone())?;
    let probes = call.probe(&base, case.dim, n)?;
    // the run's files in the program's format stay in OUT/written for a look
    call.run(&mut call.bufs.clone())?;
    report(o, r, (snap.step, snap.time, n), &base, &probes)
}

/// Compares the files and writes the report.
fn report(
    o: &Opts,
    r: &RoutineInfo,
    (step, time, n): (usize, f64, usize),
    base: &BTreeMap<String, Table>,
    probes: &[Probe],
) -> Result<(String, Value)> {
    if base.is_empty() {
        return Err(input(format!("legacy {}: the output routine wrote no file", r.name)));
    }
    let mut text = format!(
        "{} (Step#{step}, t = {time} s, {n} particles) written by your {} and compared with {}\n",
        o.run.join("particles.h5").display(),
        r.name,
        o.program_out.display()
    );
    text.push_str(&format!(
        "{:<22} {:>4} {:<16} {:>8} {:>11} {:>11} {:>9} {:>9}\n",
        "file", "col", "field", "compared", "max abs", "max rel", "differing", "first"
    ));
    let mut files = Vec::new();
    let mut first: Option<(usize, usize, String)> = None;
    let mut digits: Option<usize> = None;
    let mut compared_any = false;
    for (rel, run_t) in base {
        let name = Path::new(rel).file_name().map_or(rel.clone(), |f| f.to_string_lossy().into_owned());
        // its path from the program's working folder (unless it leaves that folder), its name
        // in --program-out, then the path that leaves it: a program writing both beside itself
        // and in ../data is compared with --program-out its working folder
        let (direct, by_name) = (o.program_out.join(rel), o.program_out.join(&name));
        let up = rel.starts_with("..");
        let found = [(!up).then(|| direct.clone()), Some(by_name.clone()), up.then_some(direct)];
        let path = found.into_iter().flatten().find(|p| p.is_file()).unwrap_or(by_name);
        if !path.is_file() {
            return Err(input(format!(
                "--program-out {}: no {name} (your {} writes {rel})",
                o.program_out.display(),
                r.name
            )));
        }
        let prog = Table::read(&path)?;
        let names = |c: usize| -> Vec<(&str, &str)> {
            probes
                .iter()
                .filter(|(_, _, ch)| ch.get(rel).is_some_and(|v| v.contains(&c)))
                .map(|(l, v, _)| (l.as_str(), v.as_str()))
                .collect()
        };
        let width = run_t.lines.iter().map(|(_, t)| t.len()).max().unwrap_or(0);
        let missing: Vec<usize> = (0..width).filter(|&c| names(c).iter().any(|(_, v)| !in_particles_h5(v))).collect();
        let cols = table::compare(&name, run_t, &prog, n, &missing)?;
        if cols.is_empty() {
            // nothing read as numbers in rows: an unformatted (binary) file
            text.push_str(&format!("{name:<22} not compared: no text columns (an unformatted file?)\n"));
            let status = "not compared: no text columns";
            files.push(
                json!({ "file": rel, "program_file": path.display().to_string(), "columns": [], "status": status }),
            );
            continue;
        }
        compared_any = true;
        let mut jcols = Vec::new();
        for (c, col) in cols.iter().enumerate() {
            let field = names(c).iter().map(|(l, _)| *l).collect::<Vec<_>>().join("+");
            let shown = if field.is_empty() { "-".to_string() } else { field.clone() };
            if missing.contains(&c) {
                text.push_str(&format!("{name:<22} {:>4} {shown:<16} not in particles.h5 (zero in the call)\n", c + 1));
                jcols.push(json!({ "col": c + 1, "field": field, "status": "not in particles.h5" }));
                continue;
            }
            let at = col.first.map_or("-".to_string(), |(l, p, _, _)| p.map_or(format!("line {l}"), |p| p.to_string()));
            text.push_str(&format!(
                "{name:<22} {:>4} {shown:<16} {:>8} {:>11.3e} {:>11.3e} {:>9} {at:>9}\n",
                c + 1,
                col.compared,
                col.max_abs,
                col.max_rel,
                col.differing
            ));
            if let Some(d) = col.digits {
                digits = Some(digits.map_or(d, |k| k.min(d)));
            }
            if let Some((l, p, a, b)) = col.first {
                let what = format!(
                    "{name} col {} ({shown}), {}: run {a:e}, program {b:e}",
                    c + 1,
                    p.map_or(format!("line {l}"), |p| format!("particle {p}"))
                );
                let key = p.unwrap_or(0);
                if first.as_ref().is_none_or(|(k, _, _)| key < *k) {
                    first = Some((key, c, what));
                }
            }
            let mut j = col.json();
            j["col"] = json!(c + 1);
            j["field"] = json!(field);
            j["status"] = json!("compared");
            jcols.push(j);
        }
        files.push(json!({ "file": rel, "program_file": path.display().to_string(), "lines": run_t.lines.len(), "columns": jcols }));
    }
    let equal = first.is_none() && compared_any;
    let verdict = match (&first, digits) {
        (Some((_, _, w)), _) => format!("they part: first at {w}"),
        (None, Some(d)) if d >= 17 => "equal at the 17 digits written: bit for bit".to_string(),
        (None, Some(d)) => format!("equal at the {d} digits written"),
        (None, None) if !compared_any => "nothing compared: no file has text columns".to_string(),
        (None, None) => "equal (every value written is an integer or zero)".to_string(),
    };
    text.push_str(&verdict);
    text.push('\n');
    let v = json!({
        "run": o.run.display().to_string(),
        "step": step,
        "time": time,
        "particles": n,
        "routine": r.name,
        "program_out": o.program_out.display().to_string(),
        "files": files,
        "digits": digits,
        "equal": equal,
        "verdict": verdict,
    });
    let out = serde_json::to_string_pretty(&v).map_err(|e| SphError::Io(e.to_string()))?;
    crate::files::write_atomic(&o.out.join("compare.json"), out.as_bytes())?;
    Ok((text, v))
}
