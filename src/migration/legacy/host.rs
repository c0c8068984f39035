//! Host mode (`blastsph legacy host CASE --legacy DIR`): the user's own program runs as
//! written, its main and step loop, from `DIR/libhost.so` ([`crate::migration::builder`]). At
//! each call of a mapped routine its wrapper hands the argument addresses here twice: before
//! the call (the inputs are copied) and after it (the outputs are read). The Rust twins the
//! routine stands for in the case's plan (the same legacy stage as in `dual --legacy`) then run
//! on the copied inputs, and the dual run's comparator compares every output. By default the
//! program goes on with its routine's outputs; with `rust_outputs`, with the twins'.
//!
//! The state the twins see is made from the routine's arguments only: `ntotal` particles
//! (`each_particle`: one; `each_pair`: two, x_i = dx, x_j = 0, both of the pair's h) and the
//! `niac` pairs. The values go through the same names as the guest shims' ([`bind`]).

use super::*;
use crate::dual::Comparator;
use crate::migration::builder::{ArgInfo, BuildInfo, RoutineInfo};
use crate::migration::host_ffi as hffi;
use crate::migration::host_ffi::ArgPtr;
use crate::migration::vocab::{self, Base, CallMode, Kind};
use crate::sim::{Overrides, Sim};
use std::fmt::Write as _;
use std::os::raw::c_int;

/// Options of a host run.
#[derive(Debug, Clone, Default)]
pub struct HostOpts {
    /// Go on with the Rust twins' outputs in place of the routines'.
    pub rust_outputs: bool,
    /// The program's command-line arguments.
    pub args: Vec<String>,
}

/// One mapped routine in a host run.
struct Mapped {
    info: RoutineInfo,
    /// Its compared stage in the plan (an index of the entries), if it stands for one.
    entry: Option<usize>,
    /// What the plan made of it (status and why).
    status: String,
    why: String,
    calls: u64,
    compared: u64,
}

/// A call in progress: its inputs, with its particle and pair counts and the particles it was
/// given (its `ntotal`: fewer than `nt` where its pairs reach past them).
struct Pending {
    inputs: Vec<Option<Buf>>,
    nt: usize,
    np: usize,
    given: usize,
}

struct Run {
    sim: Sim,
    lg: Arc<Legacy>,
    mapped: Vec<Mapped>,
    cmp: Comparator,
    rust: bool,
    stack: Vec<Option<Pending>>,
    maxn: usize,
    maxia: usize,
    report: PathBuf,
    /// A call that could not be compared or given back, said once at the end.
    failed: Vec<String>,
    /// The exit status, once the report is written.
    done: Option<i32>,
}

/// The host run in progress (the wrappers' hook reaches it; the program is single-threaded).
static RUN: Mutex<Option<Run>> = Mutex::new(None);

fn run_lock() -> std::sync::MutexGuard<'static, Option<Run>> {
    RUN.lock().unwrap_or_else(|e| e.into_inner())
}

/// Runs the user's program of build `dir` in `out/work` with every mapped routine compared
/// against its Rust twins in `case`; the report goes to `out/host_report.json` and its table to
/// stdout. The exit status: 0 every compared value at 0 ULP, 4 otherwise.
pub fn run(case: Case, dir: &Path, out: &Path, opts: HostOpts) -> Result<i32> {
    let info = BuildInfo::read(dir)?;
    let Some(lib) = &info.host else {
        return Err(input(format!(
            "legacy host: {} has no host program: {} (run blastsph legacy build again)",
            dir.display(),
            info.host_note.as_deref().unwrap_or("it was built without one")
        )));
    };
    if let Some(r) = info.host_refused.first() {
        return Err(input(format!("legacy host: cannot interpose {r}")));
    }
    let bridge = super::super::attach::LegacyBridge { dir: Some(dir.to_path_buf()), host: true, ..Default::default() };
    let opened = bridge.opened.clone();
    let sim = Sim::new(case, &Overrides { bridge: Some(Arc::new(bridge)), ..Default::default() })?;
    let lg = opened.0.lock().unwrap_or_else(|e| e.into_inner()).clone();
    let lg = lg.ok_or_else(|| input("legacy host: the build was not opened"))?;
    let mapped = mapped(&sim, &info)?;
    let out = std::path::absolute(out).map_err(|e| SphError::Io(format!("{}: {e}", out.display())))?;
    let work = out.join("work");
    for d in [work.clone(), out.join("data")].into_iter().chain(info.run_dirs.iter().map(|d| work.join(d))) {
        std::fs::create_dir_all(&d).map_err(|e| SphError::Io(format!("{}: {e}", d.display())))?;
    }
    let dim = sim.case.dim;
    *run_lock() = Some(Run {
        sim,
        lg,
        mapped,
        cmp: Comparator::new(dim),
        rust: opts.rust_outputs,
        stack: Vec::new(),
        maxn: info.maxn,
        maxia: info.max_interaction,
        report: out.join("host_report.json"),
        failed: Vec::new(),
        done: None,
    });
    hffi::at_exit(host_exit);
    let lib = std::path::absolute(dir).map_err(|e| SphError::Io(format!("{}: {e}", dir.display())))?.join(lib);
    let mut argv = vec![lib.display().to_string()];
    argv.extend(opts.args);
    std::env::set_current_dir(&work).map_err(|e| SphError::Io(format!("{}: {e}", work.display())))?;
    let rc = hffi::run_main(&lib, &argv, hook)?;
    let code = finish();
    Ok(if code != 0 { code } else { rc })
}

/// Every mapped routine with its compared stage, or the line that refuses a routine host mode
/// cannot give its twins.
fn mapped(sim: &Sim, info: &BuildInfo) -> Result<Vec<Mapped>> {
    let notes = &sim.plan.legacy["routines"];
    let mut out = Vec::new();
    for r in &info.routines {
        let name = format!("legacy.{}", r.name);
        let entry = sim
            .plan
            .entries
            .iter()
            .position(|e| e.stage.name() == name && e.stage.counterpart() == Counterpart::Legacy);
        if entry.is_some() {
            let has = |n: &str| r.args.iter().any(|a| a.name == n);
            let why = if !r.globals.is_empty() {
                Some(
                    "its values are in COMMON blocks or modules (`globals`), and host mode reads a routine's arguments only",
                )
            } else if r.call == CallMode::Whole && r.args.iter().any(|a| a.shape.per_particle()) && !has("ntotal") {
                Some(
                    "it takes per-particle arrays but not `ntotal`, so host mode cannot tell how many values they hold",
                )
            } else if r.call == CallMode::Whole && r.args.iter().any(|a| a.shape.per_pair()) && !has("niac") {
                Some("it takes per-pair arrays but not `niac`, so host mode cannot tell how many values they hold")
            } else {
                None
            };
            if let Some(why) = why {
                return Err(input(format!("legacy host: cannot compare routine {}: {why}", r.name)));
            }
        }
        let n = &notes[&r.name];
        out.push(Mapped {
            info: r.clone(),
            entry,
            status: n["status"].as_str().unwrap_or("-").to_string(),
            why: n["why"].as_str().unwrap_or("").to_string(),
            calls: 0,
            compared: 0,
        });
    }
    Ok(out)
}

/// The wrappers' hook: phase 0 before the routine's call, 1 after it.
extern "C" fn hook(routine: c_int, phase: c_int, args: hffi::RawArgs) {
    let mut g = run_lock();
    let Some(run) = g.as_mut() else { return };
    let k = routine as usize;
    let Some(m) = run.mapped.get(k) else { return };
    let ptrs = hffi::arg_ptrs(args, m.info.args.len());
    if phase == 0 {
        let p = run.before(k, &ptrs);
        run.stack.push(p);
    } else {
        let p = run.stack.pop().flatten();
        run.mapped[k].calls += 1;
        if let Some(p) = p {
            run.after(k, &ptrs, p);
        }
    }
}

/// At `exit` (a `STOP` in the program): the report, and the status 4 if a value diverged.
extern "C" fn host_exit() {
    let code = finish();
    if code != 0 {
        hffi::exit_now(code);
    }
}

/// Writes the report once; the exit status.
fn finish() -> i32 {
    let mut g = run_lock();
    let Some(run) = g.as_mut() else { return 0 };
    if let Some(c) = run.done {
        return c;
    }
    super::super::ffi::flush_fortran_at_exit();
    let (text, json, ok) = run.report();
    let _ = std::fs::write(&run.report, serde_json::to_string_pretty(&json).unwrap_or_default());
    use std::io::Write;
    let mut so = std::io::stdout();
    let _ = write!(so, "{text}");
    let _ = so.flush();
    let code = if ok { 0 } else { 4 };
    run.done = Some(code);
    code
}

impl Run {
    /// The counts a call's arrays hold: (particles given, particles, pairs), from its `ntotal`
    /// and `niac`. The particles are at least those its pairs name: the book calls `av_vel` with
    /// the real particles' `ntotal` and pairs that reach the virtual ones after them.
    fn counts(&self, r: &RoutineInfo, ptrs: &[ArgPtr]) -> (usize, usize, usize) {
        let at = |n: &str| r.args.iter().zip(ptrs).find(|(a, _)| a.name == n);
        let scalar = |n: &str, max: usize| -> usize {
            at(n).map_or(0, |(a, p)| match read_arg(a, *p, 1) {
                Some(Buf::I(v)) => (v[0].max(0) as usize).min(max),
                _ => 0,
            })
        };
        match r.call {
            CallMode::Whole => {
                let (nt, np) = (scalar("ntotal", self.maxn), scalar("niac", self.maxia));
                let named = |n: &str| -> usize {
                    at(n).map_or(0, |(a, p)| match read_arg(a, *p, np) {
                        Some(Buf::I(v)) => v.iter().map(|&k| k.max(0) as usize).max().unwrap_or(0),
                        _ => 0,
                    })
                };
                (nt, nt.max(named("pair_i")).max(named("pair_j")).min(self.maxn), np)
            }
            CallMode::EachParticle => (1, 1, 0),
            CallMode::EachPair => (2, 2, 1),
        }
    }

    /// The values of every argument of `r` at `ptrs`, `nt` particles and `np` pairs (indices
    /// made 0-based, as blastsph holds them).
    fn read(&self, r: &RoutineInfo, ptrs: &[ArgPtr], (nt, np): (usize, usize)) -> Vec<Option<Buf>> {
        let dim = self.sim.case.dim;
        r.args
            .iter()
            .zip(ptrs)
            .map(|(a, p)| {
                if a.value.is_some() {
                    // a dummy bound to a value of the manifest: the program's own, not compared
                    return None;
                }
                let n = match (r.call, a.shape) {
                    (CallMode::Whole, Shape::Scalar) => 1,
                    (CallMode::Whole, s) => a.lead.unwrap_or(s.stride(dim)) * if s.per_pair() { np } else { nt },
                    (_, s) => s.stride(dim),
                };
                let one = vocab::lookup(&a.name).is_some_and(|t| t.base == Base::One);
                read_arg(a, *p, n).map(|b| match b {
                    Buf::I(v) if one => Buf::I(v.into_iter().map(|i| i - 1).collect()),
                    Buf::R(v) if a.lead.is_some() => Buf::R(packed(&v, dim, a.lead.unwrap_or(dim))),
                    b => b,
                })
            })
            .collect()
    }

    fn before(&self, k: usize, ptrs: &[ArgPtr]) -> Option<Pending> {
        let m = &self.mapped[k];
        m.entry?;
        let (given, nt, np) = self.counts(&m.info, ptrs);
        Some(Pending { inputs: self.read(&m.info, ptrs, (nt, np)), nt, np, given })
    }

    fn after(&mut self, k: usize, ptrs: &[ArgPtr], pend: Pending) {
        let Some(e) = self.mapped[k].entry else { return };
        let r = self.mapped[k].info.clone();
        let call = self.mapped[k].calls;
        let counts = self.counts(&r, ptrs);
        let np_out = if r.call == CallMode::Whole { counts.2 } else { 1 };
        let outputs = self.read(&r, ptrs, (pend.nt, np_out));
        // an array the routine adds into (`adds`): what it added is compared with the twin's term
        let names: Vec<&str> = r.args.iter().map(|a| a.name.as_str()).collect();
        let outputs = crate::migration::adds::added(&r.adds, &names, outputs, &pend.inputs);
        let stage = &self.sim.plan.entries[e].stage;
        let slots = self.lg.host_slots.lock().unwrap_or_else(|e| e.into_inner()).get(stage.name()).copied();
        let slots = slots.unwrap_or_default();
        let (mut p, mut w, clock) = self.state(&r, stage.as_ref(), slots, &pend);
        // the routine's outputs, put into the state when the comparator runs its "Fortran" side
        let writes: Vec<Field> = stage.writes().to_vec();
        let named: Vec<(String, Buf)> =
            r.args.iter().zip(outputs).filter_map(|(a, b)| Some((a.name.clone(), b?))).collect();
        let (dim, itype) = (p.dim, self.lg.itype.clone());
        *self.lg.host_fill.lock().unwrap_or_else(|e| e.into_inner()) = Some(Box::new(move |p, w| {
            let mut scratch = HashMap::new();
            let mut ctx = ctx_of(dim, slots, &itype, (p.ntotal, np_out), &mut scratch);
            for (n, b) in named {
                if bind::field_of(&n).is_some_and(|f| writes.contains(&f)) {
                    bind::scatter(&n, b, &writes, &mut ctx, p, w, np_out);
                }
            }
        }));
        let kept = self.rust.then(|| (p.clone(), w.clone()));
        // the rows past the particles it was given are its inputs: not compared
        self.cmp.given = (pend.given < pend.nt).then_some(pend.given);
        self.cmp.run(stage.as_ref(), &mut p, &mut w, &clock, call);
        self.mapped[k].compared += 1;
        if let Some((mut p, mut w)) = kept {
            stage.run(Backend::Rust, &mut p, &mut w, &clock);
            if let Err(msg) = self.give_back(&r, (ptrs, &pend.inputs), slots, &p, &w)
                && self.failed.len() < 10
            {
                self.failed.push(format!("routine {} call {call}: {msg}", r.name));
            }
        }
    }

    /// The state the twins of `stage` see: the routine's inputs as particles and pairs.
    fn state(&self, r: &RoutineInfo, stage: &dyn Stage, slots: Slots, pend: &Pending) -> (Particles, Work, Clock) {
        let dim = self.sim.case.dim;
        let n = pend.nt;
        let mut p = Particles {
            dim,
            nreal: n,
            ntotal: n,
            x: vec![0.0; dim * n],
            v: vec![0.0; dim * n],
            rho: vec![0.0; n],
            p: vec![0.0; n],
            c: vec![0.0; n],
            e: vec![0.0; n],
            h: vec![0.0; n],
            mass: vec![0.0; n],
            mat: vec![0; n],
            id: (0..n as i64).collect(),
            ..Default::default()
        };
        stage.register(&mut p);
        let mut w = Work::default();
        let arg =
            |name: &str| r.args.iter().zip(&pend.inputs).find(|(a, _)| a.name == name).and_then(|(_, b)| b.clone());
        let real = |name: &str| match arg(name) {
            Some(Buf::R(v)) => v.first().copied(),
            _ => None,
        };
        let int = |name: &str| match arg(name) {
            Some(Buf::I(v)) => v.first().copied(),
            _ => None,
        };
        let dt = real("dt").or(self.lg.dt).unwrap_or(0.0);
        let clock = Clock { t: real("time").unwrap_or(0.0), dt, dt_prev: dt, first: false };
        if let Some(Buf::I(codes)) = arg("itype") {
            for (i, c) in codes.iter().take(n).enumerate() {
                p.mat[i] = self.lg.itype.iter().position(|k| *k == c.abs()).unwrap_or(0) as i32;
            }
            // a negative itype is a boundary particle, of the kind of the mapped virt_part
            if codes.iter().take(n).any(|&c| c < 0) {
                let kind = self.lg.lib.info().routines.iter().find_map(|r| r.virtual_kind.as_deref());
                let code = if kind == Some("integrated") { 1 } else { 2 };
                p.bnd = (0..n).map(|i| if codes.get(i).is_some_and(|&c| c < 0) { code } else { 0 }).collect();
            }
        }
        if let Some(Buf::I(m)) = arg("mat") {
            p.mat[..n.min(m.len())].copy_from_slice(&m[..n.min(m.len())]);
        }
        if let Some(nv) = int("nvirt") {
            p.nreal = n.saturating_sub(nv.max(0) as usize);
        }
        let mut scratch = HashMap::new();
        let mut ctx = ctx_of(dim, slots, &self.lg.itype, (n, pend.np), &mut scratch);
        ctx.itimestep = int("itimestep").unwrap_or(0);
        ctx.dt = dt;
        if r.call == CallMode::EachPair {
            // the pair (0, 1): x_0 - x_1 = dx exactly, and (h + h)/2 = h
            if let Some(Buf::R(d)) = arg("dx") {
                p.x[..dim.min(d.len())].copy_from_slice(&d[..dim.min(d.len())]);
            }
            let h = real("hsml").unwrap_or(0.0);
            p.h = vec![h, h];
            w.pairs.i = vec![0];
            w.pairs.j = vec![1];
            w.pairs.build_incidence(n);
            stage.prepare(&mut p, &mut w);
            return (p, w, clock);
        }
        let fields: Vec<Field> = r.args.iter().filter_map(|a| bind::field_of(&a.name)).collect();
        let named = || r.args.iter().zip(&pend.inputs).filter_map(|(a, b)| Some((a.name.as_str(), b.clone()?)));
        for (name, b) in named().filter(|(n, _)| matches!(*n, "pair_i" | "pair_j")) {
            bind::scatter(name, b, &fields, &mut ctx, &mut p, &mut w, pend.np);
        }
        // the Rust gathers go through the incidence lists, as after the search of a step
        w.pairs.build_incidence(n);
        stage.prepare(&mut p, &mut w);
        for (name, b) in named().filter(|(n, _)| !matches!(*n, "pair_i" | "pair_j" | "itype" | "mat")) {
            bind::scatter(name, b, &fields, &mut ctx, &mut p, &mut w, pend.np);
        }
        (p, w, clock)
    }

    /// Writes the twins' outputs (in `p`, `w`) into the routine's arguments at `ptrs`.
    fn give_back(
        &self,
        r: &RoutineInfo,
        (ptrs, before): (&[ArgPtr], &[Option<Buf>]),
        slots: Slots,
        p: &Particles,
        w: &Work,
    ) -> std::result::Result<(), String> {
        let Some(e) = self.mapped.iter().find(|m| m.info.name == r.name).and_then(|m| m.entry) else { return Ok(()) };
        let writes = self.sim.plan.entries[e].stage.writes();
        let whole = r.call == CallMode::Whole;
        let np = w.pairs.len();
        if whole && writes.contains(&Field::PairI) && np > self.maxia {
            return Err(format!("the twins found {np} pairs, more than max_interaction = {}", self.maxia));
        }
        let (nbuf, pbuf) = if whole { (p.ntotal, np) } else { (1, 1) };
        let mut scratch = HashMap::new();
        let mut ctx = ctx_of(p.dim, slots, &self.lg.itype, (nbuf, pbuf), &mut scratch);
        for ((a, ptr), old) in r.args.iter().zip(ptrs).zip(before) {
            let out = match bind::field_of(&a.name) {
                Some(Field::PairI) if a.name == "niac" => writes.contains(&Field::PairI),
                Some(f) => writes.contains(&f),
                None => false,
            };
            if !out {
                continue;
            }
            let vec = a.shape.stride(p.dim) > 1;
            let mut b = bind::gather(&a.name, vec, a.shape.per_pair() && whole, &mut ctx, p, w);
            if r.adds.contains(&a.name) {
                b = crate::migration::adds::onto(old.as_ref(), b);
            }
            let one = vocab::lookup(&a.name).is_some_and(|t| t.base == Base::One);
            let b = match b {
                Buf::I(v) if one => Buf::I(v.into_iter().map(|i| i + 1).collect()),
                Buf::R(v) if let Some(l) = a.lead => {
                    // dim values of each particle or pair into the program's `l` per one; the
                    // components past dim keep what the program holds there
                    let mut laid = match hffi::read(*ptr, Kind::Real, v.len() / p.dim * l) {
                        Some(Buf::R(old)) => old,
                        _ => return Err(format!("argument {} has no address", a.dummy)),
                    };
                    for (k, c) in v.chunks(p.dim).enumerate() {
                        laid[k * l..k * l + p.dim].copy_from_slice(c);
                    }
                    Buf::R(laid)
                }
                b => b,
            };
            write_arg(a, *ptr, &b);
        }
        Ok(())
    }

    /// `names`, each routine with `adds` marked: its rows are not bit for bit where its arrays
    /// held values before the call.
    fn named(&self, names: &[String]) -> String {
        let adds = |n: &String| self.mapped.iter().any(|m| &m.info.name == n && !m.info.adds.is_empty());
        let one = |n: &String| if adds(n) { format!("{n} (adds: after less before)") } else { n.clone() };
        names.iter().map(one).collect::<Vec<_>>().join(", ")
    }

    /// The table, the report and whether every compared value is at 0 ULP.
    fn report(&self) -> (String, serde_json::Value, bool) {
        let rows = self.cmp.rows();
        let mut text = format!(
            "{:<14} {:>9} {:>9}  {:<8} {:>10} {:>10} {:>10} {:>6} {:>6}  first divergence\n",
            "routine", "calls", "compared", "field", "values", "max abs", "max rel", "maxULP", "out"
        );
        let mut routines = serde_json::Map::new();
        let (mut zero, mut diverged, mut uncompared) = (Vec::new(), Vec::new(), Vec::new());
        for m in &self.mapped {
            let name = format!("legacy.{}", m.info.name);
            let mine: Vec<&crate::dual::Stat> = rows.iter().filter(|s| s.stage == name).collect();
            if m.entry.is_none() {
                text +=
                    &format!("{:<14} {:>9} {:>9}  not compared: {} ({})\n", m.info.name, m.calls, 0, m.status, m.why);
                uncompared.push(m.info.name.clone());
            } else if mine.is_empty() {
                text += &format!("{:<14} {:>9} {:>9}  not called\n", m.info.name, m.calls, m.compared);
            }
            for (j, s) in mine.iter().enumerate() {
                let (calls, compared) =
                    if j == 0 { (m.calls.to_string(), m.compared.to_string()) } else { (String::new(), String::new()) };
                let fd = match &s.first_divergence {
                    Some(d) => format!("call {}, {}: legacy {:e}, rust {:e}", d.step, d.at, d.fortran, d.rust),
                    None => "-".into(),
                };
                text += &format!(
                    "{:<14} {:>9} {:>9}  {:<8} {:>10} {:>10.3e} {:>10.3e} {:>6} {:>6}  {fd}\n",
                    if j == 0 { m.info.name.as_str() } else { "" },
                    calls,
                    compared,
                    s.field,
                    s.compared,
                    s.max_abs,
                    s.max_rel,
                    crate::dual::ulp_text(s.max_ulp),
                    s.out_of_tolerance
                );
            }
            if !m.info.adds.is_empty() && !mine.is_empty() {
                let _ = writeln!(
                    text,
                    "{:<14} {}",
                    "",
                    crate::migration::adds::HOST_NOTE.replace("{}", &m.info.adds.join(", "))
                );
            }
            if m.entry.is_some() && !mine.is_empty() {
                if mine.iter().all(|s| s.out_of_tolerance == 0) {
                    zero.push(m.info.name.clone());
                } else {
                    diverged.push(m.info.name.clone());
                }
            }
            routines.insert(
                m.info.name.clone(),
                json!({ "calls": m.calls, "compared_calls": m.compared, "status": m.status, "why": m.why,
                        "rows": mine }),
            );
        }
        let ok = diverged.is_empty() && self.failed.is_empty();
        let _ = writeln!(
            text,
            "host mode ({} outputs): {} routines at 0 ULP at every compared call{}{}{}; report {}",
            if self.rust { "the Rust twins'" } else { "the program's own" },
            zero.len(),
            if diverged.is_empty() { String::new() } else { format!("; DIVERGING: {}", self.named(&diverged)) },
            if uncompared.is_empty() {
                String::new()
            } else {
                format!("; not compared (no twin in this case): {}", uncompared.join(", "))
            },
            if self.failed.is_empty() { String::new() } else { format!("; FAILED: {}", self.failed.join("; ")) },
            self.report.display()
        );
        let json = json!({
            "outputs": if self.rust { "rust" } else { "legacy" },
            "ok": ok,
            "zero_ulp": zero,
            "diverging": diverged,
            "not_compared": uncompared,
            "failed": self.failed,
            "routines": routines,
        });
        (text, json, ok)
    }
}

/// The context [`bind`] needs: `nbuf` particles and `pbuf` pairs.
/// The `dim` values of each particle or pair from an array laid out `lead` values apart
/// (`x(maxdim,maxn)`), one after the other as blastsph holds them.
fn packed(v: &[f64], dim: usize, lead: usize) -> Vec<f64> {
    v.chunks(lead).flat_map(|c| c[..dim.min(c.len())].iter().copied()).collect()
}

fn ctx_of<'a>(
    dim: usize,
    slots: Slots,
    itype: &'a [i32],
    (nbuf, pbuf): (usize, usize),
    scratch: &'a mut HashMap<String, Buf>,
) -> Ctx<'a> {
    Ctx { dim, itimestep: 0, dt: 0.0, time: 0.0, slots, itype, nbuf, pbuf, scratch }
}

/// The `n` values of argument `a` at `p`: an integer the routine declares double precision is
/// read as doubles and rounded (the whole numbers it holds, exactly).
fn read_arg(a: &ArgInfo, p: ArgPtr, n: usize) -> Option<Buf> {
    if a.real {
        return match hffi::read(p, Kind::Real, n)? {
            Buf::R(v) => Some(Buf::I(v.into_iter().map(|x| x.round() as i32).collect())),
            b => Some(b),
        };
    }
    hffi::read(p, a.kind, n)
}

/// Writes `b` into argument `a` at `p`, as doubles where the routine declares the integer so.
fn write_arg(a: &ArgInfo, p: ArgPtr, b: &Buf) {
    match b {
        Buf::I(v) if a.real => hffi::write(p, &Buf::R(v.iter().map(|&i| f64::from(i)).collect())),
        b => hffi::write(p, b),
    }
}
