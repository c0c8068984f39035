//! Running the user's legacy routines inside blastsph (`run --legacy DIR`, `dual --legacy DIR`,
//! `check --legacy DIR`): each mapped routine becomes a stage of the plan in place of the stages
//! of its modules that it computes.
//!
//! **Which stages a routine stands for.** Among the stages the case's plan has for the routine's
//! modules (with the `--compat` variants where the case asks for them), those whose every output
//! is one of the routine's arguments, and whose every input is an argument or is made inside the
//! routine from its arguments (the book's `sum_density` computes W(0, h) itself: blastsph's
//! `kernel.self` then joins the chain as a helper). So `direct_find` (nnps, kernel) stands for
//! `nnps.search` and `kernel.pairs`; `int_force` (eos, force) for `eos.eval` and `force.internal`;
//! `con_density` in a summation-density case stands for nothing and is not run. A routine that
//! stands for no stage but adds a rate term (`dvxdt`, `dedt`: the book's `art_heat`) or makes a
//! work array another mapped routine takes (`viscosity`'s `eta`) runs on its own, uncompared.
//!
//! **When.** At the phase of the first stage it stands for; routines of the book's `single_step`
//! keep that routine's order among themselves. Each is called once per step — a second evaluation
//! at the same time (the run evaluates the rates once before the first step, for the output at
//! t = 0) replays the first call's outputs — so SAVEd locals and COMMON blocks see the calls the
//! legacy program makes.
//!
//! **Where.** The routines run with the current folder `DIR/work` (made here, with `DIR/data`
//! beside it: the book's `input` and `output` open `../data/...`).

use super::bind::{self, Buf, Ctx};
use super::compat::{Flags, Item};
use super::ffi::{Args, LegacyLib};
use super::vocab::Shape;
use crate::case::{Case, StepRule};
use crate::error::{Result, SphError, input};
use crate::modules::{Backend, Counterpart, InputWrite, Module, Phase, PlanCtx, Slots, Stage, Terms, Tolerance};
use crate::setup::Initial;
use crate::sim::plan::{Entry, ModulePlan};
use crate::state::{Clock, Field, Particles, Snap, Work};
use serde_json::json;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// The order of the book's `single_step` calls (routines of these names keep it).
const BOOK_ORDER: &[&str] = &[
    "virt_part",
    "direct_find",
    "link_list",
    "tree_search",
    "sum_density",
    "con_density",
    "viscosity",
    "int_force",
    "art_visc",
    "ext_force",
    "h_upgrade",
    "art_heat",
    "av_vel",
];

/// Inputs a routine need not take: the material (the routine knows its own), and the burn
/// fraction and stress of cases that have none.
const IMPLIED: &[Field] = &[Field::Mat, Field::Burn, Field::Tau];

/// The state legacy calls share: the legacy code's work arrays, the step counter, call counts.
#[derive(Default)]
struct Shared {
    scratch: HashMap<String, Buf>,
    step: i32,
    last_t: Option<u64>,
    calls: BTreeMap<String, u64>,
    /// (routine, argument) pairs already warned of a changed input.
    warned: std::collections::HashSet<(String, String)>,
}

/// An opened legacy build, bound to a case.
pub struct Legacy {
    lib: LegacyLib,
    dir: PathBuf,
    cwd: PathBuf,
    /// The code's type code of each material.
    itype: Vec<i32>,
    setup_only: bool,
    /// `cwd` is a scratch folder of its own (`check`), removed when the build is closed.
    scratch: bool,
    /// The warnings said so far, shared by every opening of one bridge (the ledger opens the
    /// build once per row): each is said once.
    said: Arc<Mutex<std::collections::BTreeSet<String>>>,
    /// The case's fixed step (s), what the routines get as `dt`.
    dt: Option<f64>,
    flags: Flags,
    shared: Mutex<Shared>,
}

/// The book's type code of an EOS kind.
fn book_code(kind: &str) -> Option<i32> {
    match kind {
        "ideal_gas" => Some(1),
        "water" => Some(2),
        _ => None,
    }
}

/// Ends the process with one line: a legacy call cannot go on (the legacy program would have
/// stopped too; a `STOP` in the legacy code ends the process the same way).
fn die(msg: String) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(2)
}

/// A new, empty folder under the system's temporary folder.
fn scratch_folder() -> Result<PathBuf> {
    let base = std::env::temp_dir();
    for k in 0..1000u32 {
        let d = base.join(format!("blastsph-check-{}-{k}", std::process::id()));
        match std::fs::create_dir(&d) {
            Ok(()) => return Ok(d),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(SphError::Io(format!("{}: {e}", d.display()))),
        }
    }
    Err(SphError::Io(format!("{}: no free scratch folder name", base.display())))
}

impl Drop for Legacy {
    fn drop(&mut self) {
        if self.scratch {
            let _ = std::fs::remove_dir_all(&self.cwd);
        }
    }
}

/// Runs the legacy code with the current folder set to its work folder.
struct Cwd(Option<PathBuf>);
impl Cwd {
    fn enter(dir: &Path) -> Cwd {
        let back = std::env::current_dir().ok();
        if std::env::set_current_dir(dir).is_err() {
            return Cwd(None);
        }
        Cwd(back)
    }
}
impl Drop for Cwd {
    fn drop(&mut self) {
        if let Some(d) = &self.0 {
            let _ = std::env::set_current_dir(d);
        }
    }
}

impl Legacy {
    /// Opens the build in `dir` for `case`: the dimensions must agree and every material needs
    /// a type code if a routine takes `itype`. With `scratch`, the routines run in a new folder
    /// under the system's temporary folder, removed when the build is closed, not in `dir/work`
    /// (`check` writes nothing of the user's code's files).
    pub fn open(dir: &Path, case: &Case, how: &super::attach::LegacyBridge) -> Result<Arc<Legacy>> {
        let (setup_only, scratch) = (how.setup_only, how.scratch);
        let said = how.said.clone();
        let warn = |msg: String| {
            if said.lock().unwrap_or_else(|e| e.into_inner()).insert(msg.clone()) {
                eprintln!("warning: {msg}");
            }
        };
        let lib = LegacyLib::open(dir)?;
        let info = lib.info();
        let shown = dir.display();
        if info.dim != case.dim {
            return Err(input(format!(
                "--legacy {shown}: the build has dim = {} (its {}), the case dim = {}",
                info.dim,
                info.include_name(),
                case.dim
            )));
        }
        if case.sph.lattice_gradient
            && let Some(r) =
                info.routines.iter().find(|r| r.modules.iter().any(|m| m.split(',').any(|m| m.trim() == "kernel")))
        {
            return Err(input(format!(
                "--legacy {shown}: routine {} stands for the kernel, which has no lattice normalisation: sph.lattice_gradient = true needs blastsph's kernel (drop one of them)",
                r.name
            )));
        }
        let needs_itype = info.routines.iter().any(|r| r.bindings.iter().any(|b| b.name == "itype"));
        let mut itype = Vec::new();
        for m in &case.materials {
            let kind = m.eos.kind();
            let code = info.itype.get(&m.name).or_else(|| info.itype.get(kind)).copied().or_else(|| book_code(kind));
            match code {
                Some(c) => itype.push(c),
                None if needs_itype => {
                    return Err(input(format!(
                        "--legacy {shown}: material `{}` ({kind}) has no itype code: add `[itype]` `{} = N` to the manifest and rebuild",
                        m.name, m.name
                    )));
                }
                None => itype.push(0),
            }
        }
        // a manifest code that names no material of the case and no EOS kind: a typo reads as
        // "this material has no code of its own" (its kind's, or the book's, is taken instead)
        if needs_itype {
            use crate::case::EosCfg;
            for key in info.itype.keys() {
                if !EosCfg::KINDS.contains(&key.as_str()) && !case.materials.iter().any(|m| &m.name == key) {
                    let names: Vec<String> = case
                        .materials
                        .iter()
                        .zip(&itype)
                        .map(|(m, c)| format!("{} ({}) = {c}", m.name, m.eos.kind()))
                        .collect();
                    warn(format!(
                        "--legacy {shown}: the manifest's [itype] `{key}` names no material of this case and no EOS kind ({}): a misspelt name? the codes the routines get: {}",
                        EosCfg::KINDS.join(", "),
                        names.join(", ")
                    ));
                }
            }
        }
        let abs = std::path::absolute(dir).map_err(|e| SphError::Io(format!("{shown}: {e}")))?;
        let cwd = if scratch { scratch_folder()? } else { abs.join("work") };
        let run_dirs = info.run_dirs.iter().map(|d| cwd.join(d));
        let data = (!scratch).then(|| abs.join("data"));
        for d in [cwd.clone()].into_iter().chain(data).chain(run_dirs) {
            std::fs::create_dir_all(&d).map_err(|e| SphError::Io(format!("{}: {e}", d.display())))?;
        }
        let dt = (case.time.step == StepRule::Fixed).then_some(case.time.dt_s).flatten();
        let flags = super::compat::flags(&case.compat)?;
        let l = Arc::new(Legacy {
            lib,
            dir: abs,
            cwd,
            itype,
            setup_only,
            scratch,
            said: how.said.clone(),
            dt,
            flags,
            shared: Mutex::new(Shared::default()),
        });
        l.init(case.dim)?;
        Ok(l)
    }

    /// Calls the manifest's init routines (module `init`: the code's own initialiser, which fills
    /// its COMMON blocks), once each, in the manifest's order, before the set-up routine and the
    /// first step. Their arguments are given as at the set-up (no particles yet); what they
    /// return is not read.
    fn init(&self, dim: usize) -> Result<()> {
        let info = self.lib.info();
        for r in info.routines.iter().filter(|r| r.modules.iter().any(|m| m == "init")) {
            let mut bufs = self.start_bufs(r, dim);
            self.call_raw(&r.name, &r.bindings, &mut bufs)?;
            *self.shared().calls.entry(r.name.clone()).or_default() += 1;
        }
        Ok(())
    }

    /// The buffers of routine `r`'s arguments before the first step: no particles, arrays of the
    /// build's `maxn` (zeros), the case's fixed step if it has one.
    fn start_bufs(&self, r: &super::builder::RoutineInfo, dim: usize) -> Vec<Buf> {
        let maxn = self.lib.info().maxn;
        let empty = Particles { dim, ..Default::default() };
        let work = Work::default();
        let mut sh = self.shared();
        let mut ctx = Ctx {
            dim,
            itimestep: 0,
            dt: self.dt.unwrap_or(0.0),
            time: 0.0,
            slots: Slots::default(),
            itype: &self.itype,
            nbuf: maxn,
            pbuf: 0,
            scratch: &mut sh.scratch,
        };
        r.bindings
            .iter()
            .map(|b| bind::gather(&b.name, is_vec(b.shape), b.shape.per_pair(), &mut ctx, &empty, &work))
            .collect()
    }

    /// Says `msg` on stderr as a warning, once per bridge.
    fn warn(&self, msg: String) {
        if self.said.lock().unwrap_or_else(|e| e.into_inner()).insert(msg.clone()) {
            eprintln!("warning: {msg}");
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Refuses a case with more particles than the build's `maxn`.
    pub fn check_capacity(&self, particles: usize) -> Result<()> {
        self.lib.info().check_capacity(particles, None)
    }

    fn shared(&self) -> std::sync::MutexGuard<'_, Shared> {
        self.shared.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Calls of each routine so far.
    pub fn calls(&self) -> BTreeMap<String, u64> {
        self.shared().calls.clone()
    }

    /// The set-up routine (module `setup`), if the manifest maps one.
    fn setup_routine(&self) -> Option<&super::builder::RoutineInfo> {
        self.lib.info().routines.iter().find(|r| r.modules.iter().any(|m| m == "setup"))
    }

    pub fn has_setup(&self) -> bool {
        self.setup_routine().is_some()
    }

    /// The initial particles from the user's set-up routine (the book's `input`); `base` (the
    /// case's own particles) gives the finest spacing and the regions.
    pub fn setup(&self, case: &Case, base: Initial) -> Result<Initial> {
        let Some(r) = self.setup_routine() else { return Ok(base) };
        let info = self.lib.info();
        let (dim, maxn) = (case.dim, info.maxn);
        let mut bufs = self.start_bufs(r, dim);
        self.call_raw(&r.name, &r.bindings, &mut bufs)?;
        let get = |n: &str| r.bindings.iter().position(|b| b.name == n).map(|k| &bufs[k]);
        let n = match get("ntotal") {
            Some(Buf::I(v)) => v[0],
            _ => return Err(input(format!("legacy {}: a set-up routine must return ntotal", r.name))),
        };
        if n < 1 || n as usize > maxn {
            return Err(input(format!("legacy {}: returned ntotal = {n} (maxn = {maxn})", r.name)));
        }
        let n = n as usize;
        let real = |name: &str, w: usize| -> Result<Vec<f64>> {
            match get(name) {
                Some(Buf::R(v)) => Ok(v[..w * n].to_vec()),
                _ => Err(input(format!("legacy {}: a set-up routine must give {name}", r.name))),
            }
        };
        let (x, rho, e, h, mass) =
            (real("x", dim)?, real("rho", 1)?, real("u", 1)?, real("hsml", 1)?, real("mass", 1)?);
        let v = real("vx", dim).unwrap_or_else(|_| vec![0.0; dim * n]);
        let mat: Vec<i32> = match get("itype").or_else(|| get("mat")) {
            Some(Buf::I(codes)) if get("itype").is_some() => codes[..n]
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    self.itype.iter().position(|&k| k == c.abs()).map(|m| m as i32).ok_or_else(|| {
                        input(format!(
                            "legacy {}: particle {} has itype {c}, which no material of the case has (codes: {:?})",
                            r.name,
                            i + 1,
                            self.itype
                        ))
                    })
                })
                .collect::<Result<_>>()?,
            Some(Buf::I(m)) => m[..n].to_vec(),
            _ if case.materials.len() == 1 => vec![0; n],
            _ => return Err(input(format!("legacy {}: give itype (the case has several materials)", r.name))),
        };
        let region_of = |m: i32| -> u32 {
            let name = &case.materials[m as usize].name;
            case.regions.iter().position(|rg| &rg.material == name).unwrap_or(0) as u32
        };
        let region: Vec<u32> = mat.iter().map(|&m| region_of(m)).collect();
        let mut counts = vec![0usize; case.regions.len().max(1)];
        region.iter().for_each(|&r| counts[r as usize] += 1);
        // the case must still describe these particles (docs/howto/migrate.md): a count that
        // differs is said once (the run takes the routine's particles, while the case's gauges,
        // charge and walls were written for its own)
        let described = base.x.len() / dim.max(1);
        if described != n {
            self.warn(format!(
                "legacy {} made {n} particles, the case describes {described}: the run takes the routine's (check that the case's regions, gauges and charge are the ones your program sets up)",
                r.name
            ));
        }
        let made = Initial { x, v, rho, e, h, mass, mat, region, counts, dx_min: base.dx_min };
        if let Some(diff) = state_differences(case, &base, &made) {
            self.warn(format!(
                "legacy {}'s particles are not the state the case describes: {diff}; the run takes the routine's, while the case's exact solution, gauges and charge are the case's",
                r.name
            ));
        }
        Ok(made)
    }

    /// Calls routine `name` on `bufs` (one per binding), in the work folder.
    fn call_raw(&self, name: &str, bindings: &[super::builder::BindingInfo], bufs: &mut [Buf]) -> Result<()> {
        let routine = self.lib.routine(name)?;
        let mut args = Args::new();
        for (b, buf) in bindings.iter().zip(bufs.iter_mut()) {
            args = match buf {
                Buf::R(v) => args.real(&b.name, v),
                Buf::I(v) => args.int(&b.name, v),
            };
        }
        let _cwd = Cwd::enter(&self.cwd);
        // blastsph's lines so far before the routine's, and the routine's before what follows
        {
            use std::io::Write;
            let _ = std::io::stdout().flush();
        }
        let r = routine.call(&mut args);
        super::ffi::flush_fortran();
        r
    }
}

fn is_vec(s: Shape) -> bool {
    matches!(s, Shape::ParticleVec | Shape::PairVec)
}

/// A mapped routine as a stage of the plan.
pub struct LegacyStage {
    lg: Arc<Legacy>,
    /// Index of the routine in the build.
    routine: usize,
    name: &'static str,
    module: Module,
    /// The Rust twins it stands for (helpers first), in plan order: the dual run's Rust side.
    chain: Vec<Box<dyn Stage>>,
    /// The outputs its twins write for the real particles only ([`Stage::real_rows`]).
    real_rows: Vec<Field>,
    reads: Vec<Field>,
    writes: Vec<Field>,
    terms: Terms,
    slots: Slots,
    tol: Tolerance,
    /// Set for a routine with no twin: why it runs alone.
    alone: Option<&'static str>,
    /// The last call's outputs, with what it was called on ([`ReplayKey`]).
    replay: Mutex<Option<(ReplayKey, Vec<Snap>)>>,
    /// The inputs the last call changed, until the dual run takes them.
    input_writes: Mutex<Vec<InputWrite>>,
}

/// Per-particle state a routine may change although its stage only reads it: the state takes
/// the change, as the legacy program's arrays keep it (the material codes, the pair list, the
/// kernel values and the rate arrays are not: a change to them is reported and dropped).
const KEEPS: &[Field] =
    &[Field::X, Field::V, Field::Mass, Field::Rho, Field::P, Field::C, Field::E, Field::H, Field::Burn, Field::Tau];

/// What a call did to an input argument (`before`, `after`: its buffer around the call), over
/// its first `n` particles or pairs of `width` values; None when it left them as they were.
fn input_change(
    field: Field,
    arg: &str,
    shape: Shape,
    width: usize,
    n: usize,
    before: &Buf,
    after: &Buf,
) -> Option<InputWrite> {
    let pairs: Vec<(f64, f64)> = match (before, after) {
        (Buf::R(a), Buf::R(b)) => a.iter().zip(b).take(width * n).map(|(x, y)| (*x, *y)).collect(),
        (Buf::I(a), Buf::I(b)) => a.iter().zip(b).take(width * n).map(|(x, y)| (*x as f64, *y as f64)).collect(),
        _ => return None,
    };
    let mut iw: Option<InputWrite> = None;
    for (l, (a, b)) in pairs.into_iter().enumerate() {
        if a.to_bits() == b.to_bits() {
            continue;
        }
        let abs = (a - b).abs();
        let rel = abs / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
        let w = iw.get_or_insert_with(|| InputWrite {
            field,
            arg: arg.to_string(),
            per_particle: !shape.per_pair(),
            width,
            index: l,
            before: a,
            after: b,
            checked: (width * n) as u64,
            count: 0,
            max_abs: 0.0,
            max_rel: 0.0,
            max_ulp: 0,
            kept: KEEPS.contains(&field),
        });
        w.count += 1;
        w.max_abs = crate::dual::sticky_max(w.max_abs, abs);
        w.max_rel = crate::dual::sticky_max(w.max_rel, rel);
        w.max_ulp = w.max_ulp.max(crate::dual::ulp_diff(a, b));
    }
    iw
}

/// What a second call at the same time must find unchanged to replay the first call's outputs:
/// the time (its bits), the particle count, the smoothing lengths (a fingerprint of their bits:
/// `smoothing = "density"` sets them anew at every evaluation, and the mirrors and pairs follow)
/// and, for a routine that does not make the pair list, the pair count.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct ReplayKey {
    t: u64,
    ntotal: usize,
    h: u64,
    pairs: usize,
}

impl ReplayKey {
    fn of(k: &Clock, p: &Particles, w: &Work, search: bool) -> ReplayKey {
        // FNV-1a over the bits of h
        let h = p.h[..p.ntotal.min(p.h.len())]
            .iter()
            .fold(0xcbf2_9ce4_8422_2325u64, |a, v| (a ^ v.to_bits()).wrapping_mul(0x0000_0100_0000_01b3));
        ReplayKey { t: k.t.to_bits(), ntotal: p.ntotal, h, pairs: if search { 0 } else { w.pairs.len() } }
    }
}

impl LegacyStage {
    fn call(&self, p: &mut Particles, w: &mut Work, k: &Clock) {
        let key = ReplayKey::of(k, p, w, self.writes.contains(&Field::PairI));
        {
            // a second evaluation at the same time over the same particles and pairs replays the
            // first; one over other mirrors or pairs (the smoothing lengths changed between the
            // two: `smoothing = "density"`) calls the routine again, since the first's outputs
            // do not fit the state
            let rp = self.replay.lock().unwrap_or_else(|e| e.into_inner());
            if let Some((t, snaps)) = &*rp
                && *t == key
            {
                for (f, s) in self.writes.iter().zip(snaps.clone()) {
                    f.restore(p, w, s);
                }
                return;
            }
        }
        let lg = &self.lg;
        let info = lg.lib.info();
        let r = &info.routines[self.routine];
        let (nt, np) = (p.ntotal, w.pairs.len());
        let search = self.writes.contains(&Field::PairI);
        if nt > info.maxn || (!search && np > info.max_interaction) {
            die(format!(
                "legacy {}: {nt} particles and {np} pairs, more than the build's maxn = {} or max_interaction = {} (its {}): raise them and rebuild",
                r.name,
                info.maxn,
                info.max_interaction,
                info.include_name()
            ));
        }
        let mut sh = lg.shared();
        if sh.last_t != Some(key.t) {
            sh.step += 1;
            sh.last_t = Some(key.t);
        }
        *sh.calls.entry(r.name.clone()).or_default() += 1;
        let itimestep = sh.step;
        let mut ctx = Ctx {
            dim: p.dim,
            itimestep,
            dt: lg.dt.unwrap_or(k.dt_prev),
            time: k.t,
            slots: self.slots,
            itype: &lg.itype,
            nbuf: nt,
            pbuf: if search { info.max_interaction } else { np },
            scratch: &mut sh.scratch,
        };
        let mut bufs: Vec<Buf> = r
            .bindings
            .iter()
            .map(|b| bind::gather(&b.name, is_vec(b.shape), b.shape.per_pair(), &mut ctx, p, w))
            .collect();
        // the state the stage only reads, as it was: a routine that changes it is reported
        let watched: Vec<(usize, Field, Buf)> = r
            .bindings
            .iter()
            .enumerate()
            .filter_map(|(k, b)| {
                let f = bind::field_of(&b.name)?;
                // (an each_particle routine's arguments are scalars per call: the buffer is the
                // whole per-particle array all the same)
                (!self.writes.contains(&f)).then(|| (k, f, bufs[k].clone()))
            })
            .collect();
        super::ffi::set_context(format!("at step {itimestep} (its itimestep, from 1)"));
        if let Err(e) = lg.call_raw(&r.name, &r.bindings, &mut bufs) {
            die(e.to_string());
        }
        let mut changed = Vec::new();
        for (k, f, before) in &watched {
            let b = &r.bindings[*k];
            let width = if is_vec(b.shape) { p.dim } else { 1 };
            let n = if b.shape.per_pair() { np } else { nt };
            if let Some(iw) = input_change(*f, &b.name, b.shape, width, n, before, &bufs[*k]) {
                changed.push(iw);
            }
        }
        // a field the case does not carry (no burn fraction without a programmed burn, no stress
        // without strength) cannot take a change
        for iw in changed.iter_mut() {
            if (iw.field == Field::Burn && p.burn.is_empty()) || (iw.field == Field::Tau && p.tau.is_empty()) {
                iw.kept = false;
            }
        }
        let mut writes = self.writes.clone();
        for iw in &changed {
            if iw.kept && !writes.contains(&iw.field) {
                writes.push(iw.field);
            }
            if sh.warned.insert((r.name.clone(), iw.arg.clone())) {
                let what = if iw.per_particle { "particle" } else { "pair" };
                let fate = if iw.kept {
                    "the state keeps it, as your program's arrays do"
                } else {
                    "dropped: blastsph does not take it from a routine that does not compute it, so from here on `run --legacy` differs from your program, whose later routines see the change"
                };
                let at = iw.index / iw.width;
                eprintln!(
                    "warning: legacy routine {} changed its input `{}` at step {itimestep} (its itimestep, from 1; {} values; first at {what} {at} counted from 0, your index {}: {:e} -> {:e}), which blastsph's twin of it leaves alone: {fate} (`dual --legacy` reports it as a divergence)",
                    r.name,
                    iw.arg,
                    iw.count,
                    at + 1,
                    iw.before,
                    iw.after
                );
            }
        }
        let np_after = match r.bindings.iter().position(|b| b.name == "niac").map(|k| &bufs[k]) {
            Some(Buf::I(v)) if search => v[0].max(0) as usize,
            _ => np,
        };
        let mut ctx = Ctx {
            dim: p.dim,
            itimestep,
            dt: 0.0,
            time: k.t,
            slots: self.slots,
            itype: &lg.itype,
            nbuf: nt,
            pbuf: np_after,
            scratch: &mut sh.scratch,
        };
        for (b, buf) in r.bindings.iter().zip(bufs) {
            bind::scatter(&b.name, buf, &writes, &mut ctx, p, w, np_after);
        }
        let snaps = self.writes.iter().map(|f| f.snap(p, w)).collect();
        *self.replay.lock().unwrap_or_else(|e| e.into_inner()) = Some((key, snaps));
        *self.input_writes.lock().unwrap_or_else(|e| e.into_inner()) = changed;
    }
}

impl Stage for LegacyStage {
    fn module(&self) -> Module {
        self.module
    }
    fn name(&self) -> &'static str {
        self.name
    }
    fn reads(&self) -> &[Field] {
        &self.reads
    }
    fn writes(&self) -> &[Field] {
        &self.writes
    }
    fn real_rows(&self) -> &[Field] {
        &self.real_rows
    }
    /// The state the stages it stands for keep (the deviatoric stress of a strength routine's
    /// `strength.rates`): allocated whoever computes it.
    fn register(&self, p: &mut Particles) {
        for s in &self.chain {
            s.register(p);
        }
    }
    /// The work arrays the stages it stands for fill (the strain and rotation rates, the stress
    /// rate), sized as they size them: the routine's outputs are scattered into them.
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        for s in &self.chain {
            s.prepare(p, w);
        }
        if self.terms != Terms::default() {
            self.slots.size(w, p.dim, p.ntotal);
        }
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, k: &Clock) {
        if b == Backend::Rust && self.alone.is_none() {
            // each twin sized again right before it runs: a later twin's outputs follow an
            // earlier one's (the kernel's per-pair arrays follow the search's pair count)
            for s in &self.chain {
                s.prepare(p, w);
                s.run(Backend::Rust, p, w, k);
            }
        } else {
            self.call(p, w, k);
        }
    }
    fn tolerance(&self) -> Tolerance {
        self.tol
    }
    fn terms(&self) -> Terms {
        self.terms
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
        for s in &mut self.chain {
            s.assign(slots);
        }
    }
    fn module_of(&self, f: Field) -> Module {
        self.chain.iter().rev().find(|s| s.writes().contains(&f)).map_or(self.module, |s| s.module())
    }
    fn take_input_writes(&self) -> Vec<InputWrite> {
        std::mem::take(&mut *self.input_writes.lock().unwrap_or_else(|e| e.into_inner()))
    }
    fn counterpart(&self) -> Counterpart {
        match self.alone {
            Some(why) => Counterpart::LegacyAlone(why),
            None => Counterpart::Legacy,
        }
    }
}

/// The stages module `m` contributes to this case (its compat variants where asked), the
/// once-only `Init` ones left out.
fn fresh(m: Module, ctx: &PlanCtx) -> Vec<(Phase, Box<dyn Stage>)> {
    let c = super::compat::plan(m, ctx).unwrap_or_else(|| m.plan(ctx));
    c.stages.into_iter().filter(|(ph, _)| *ph != Phase::Init).collect()
}

/// What became of one mapped routine, for `check` and summary.json.
struct Note {
    name: String,
    status: &'static str,
    why: String,
    json: serde_json::Value,
}

impl Legacy {
    /// Puts the mapped routines into the plan in place of the stages they stand for; returns the
    /// text `blastsph check` prints and the summary's `legacy` object.
    pub fn edit_plan(
        self: &Arc<Self>,
        ctx: &PlanCtx,
        entries: &mut Vec<Entry>,
        modules: &mut BTreeMap<Module, ModulePlan>,
    ) -> (String, serde_json::Value) {
        let info = self.lib.info();
        let mut notes: Vec<Note> = Vec::new();
        // the routines not run as of another formulation than the case's (below: NOT RUN where
        // no other routine stands for their module)
        let mut other_formulation: Vec<String> = Vec::new();
        let bound: Vec<Vec<String>> =
            info.routines.iter().map(|r| r.bindings.iter().map(|b| b.name.clone()).collect()).collect();
        for (ri, r) in info.routines.iter().enumerate() {
            let mut note = |status: &'static str, why: String, json: serde_json::Value| {
                notes.push(Note { name: r.name.clone(), status, why, json })
            };
            if r.modules.iter().any(|m| m == "setup") {
                note("setup", "makes the initial particles (called once, before the first step)".into(), json!({}));
                continue;
            }
            if r.modules.iter().any(|m| m == "init") {
                note(
                    "init",
                    "fills its COMMON blocks (called once, before the set-up and the first step)".into(),
                    json!({}),
                );
                continue;
            }
            if r.modules.iter().any(|m| m == "output") {
                note("not run", "an output routine: blastsph writes particles.h5".into(), json!({}));
                continue;
            }
            if self.setup_only {
                note("not run", "set-up only (the ledger's Rust runs)".into(), json!({}));
                continue;
            }
            let mods: Vec<Module> = r.modules.iter().filter_map(|m| Module::parse(m)).collect();
            if mods.contains(&Module::Integrator) || mods.len() > 3 {
                note(
                    "not run",
                    format!(
                        "a driver spanning {}: --legacy runs the routines it calls (map those); compare its program with `run --legacy`",
                        r.modules.join(",")
                    ),
                    json!({}),
                );
                continue;
            }
            let argf: Vec<Field> = bound[ri].iter().filter_map(|n| bind::field_of(n)).collect();
            let satisfied = |s: &dyn Stage| s.reads().iter().all(|f| argf.contains(f) || IMPLIED.contains(f));
            let mut covered: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
            let mut helpers: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
            for &m in &mods {
                for (ph, s) in fresh(m, ctx) {
                    if !s.writes().iter().all(|f| argf.contains(f)) {
                        continue;
                    }
                    // inputs not among the arguments: made inside the routine by a helper stage
                    let mut need: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
                    let mut ok = true;
                    for f in s.reads().iter().filter(|f| !argf.contains(f) && !IMPLIED.contains(f)) {
                        let h = Module::ALL
                            .iter()
                            .flat_map(|&hm| fresh(hm, ctx))
                            .find(|(_, h)| h.writes() == [*f] && satisfied(h.as_ref()));
                        match h {
                            Some(h) => need.push(h),
                            None => ok = false,
                        }
                    }
                    if ok {
                        for h in need {
                            if !helpers.iter().any(|x| x.1.name() == h.1.name()) {
                                helpers.push(h);
                            }
                        }
                        covered.push((ph, s));
                    }
                }
            }
            let active = mods.iter().any(|m| modules.get(m).is_some_and(|p| p.active));
            let mut writes: Vec<Field> = Vec::new();
            let alone = covered.is_empty();
            if alone {
                let shared_scratch = bound[ri].iter().any(|n| {
                    bind::is_scratch(n) && bound.iter().enumerate().any(|(o, names)| o != ri && names.contains(n))
                });
                let term = bound[ri].iter().any(|n| n == "dvxdt" || n == "dedt");
                if !active {
                    note("not run", format!("the case does not run {}", r.modules.join(",")), json!({}));
                    continue;
                }
                // for each stage it might stand for, what it writes and what it reads that are
                // not among the routine's arguments
                let missing: Vec<(&'static str, Vec<String>, Vec<String>)> = mods
                    .iter()
                    .flat_map(|&m| fresh(m, ctx))
                    .map(|(_, s)| {
                        let names = |fs: &[Field], implied: bool| -> Vec<String> {
                            fs.iter()
                                .filter(|f| !(argf.contains(f) || (implied && IMPLIED.contains(f))))
                                .map(|f| f.name().to_string())
                                .collect()
                        };
                        (s.name(), names(s.writes(), false), names(s.reads(), true))
                    })
                    .collect();
                // a near miss: a stage whose inputs are all among the arguments but not all its
                // outputs (the same physics, one output short; a routine of another formulation,
                // the book's con_density in a summation case, is no miss)
                let near = missing.iter().any(|(_, out, inp)| inp.is_empty() && !out.is_empty());
                let lacks: Vec<String> = missing
                    .iter()
                    .map(|(name, out, inp)| {
                        if out.is_empty() {
                            format!("{name} reads {}", inp.join(", "))
                        } else {
                            format!("{name} also writes {}", out.join(", "))
                        }
                    })
                    .collect();
                let hint = if ctx.case.time.viscous_step
                    && mods.contains(&Module::Viscosity)
                    && !argf.contains(&Field::Mumax)
                {
                    " (mumax, the largest mu_ij, is asked for by the viscous time-step limit: --set time.viscous_step=false drops it)"
                } else {
                    ""
                };
                // the stages of the case's other modules that its arguments would compute
                // whole (a routine mapped under the wrong `module`: an EOS given as density)
                let fits: Vec<String> = if near {
                    Vec::new()
                } else {
                    Module::ALL
                        .iter()
                        .filter(|m| !mods.contains(m) && modules.get(m).is_some_and(|p| p.active))
                        .flat_map(|&m| fresh(m, ctx))
                        .filter(|(_, s)| {
                            !s.writes().is_empty()
                                && s.writes().iter().all(|f| argf.contains(f))
                                && s.reads().iter().all(|f| argf.contains(f) || IMPLIED.contains(f))
                        })
                        .map(|(_, s)| s.name().to_string())
                        .collect()
                };
                if !(term || shared_scratch || fits.is_empty()) {
                    let other: Vec<&str> = fits.iter().filter_map(|f| f.split('.').next()).collect();
                    let why = format!(
                        "it computes none of the {} stages from its arguments ({}, not among them), but its arguments fit {} of another module: is its manifest's module = \"{}\"? blastsph's own {} runs in its place",
                        r.modules.join(","),
                        lacks.join("; "),
                        fits.join(", "),
                        other.first().copied().unwrap_or(""),
                        other.join(",")
                    );
                    note("not run", why, json!({ "replaced": false }));
                    continue;
                }
                if !(term || shared_scratch) {
                    let why = if near {
                        format!(
                            "it computes none of the case's {} stages from its arguments: {}, not among them{hint}; blastsph's own {} runs in its place",
                            r.modules.join(","),
                            lacks.join("; "),
                            r.modules.join(",")
                        )
                    } else {
                        format!(
                            "it computes none of the case's {} stages from its arguments ({}, not among them: the case uses another formulation)",
                            r.modules.join(","),
                            lacks.join("; ")
                        )
                    };
                    note("not run", why, if near { json!({ "replaced": false }) } else { json!({}) });
                    if !near {
                        other_formulation.push(r.name.clone());
                    }
                    continue;
                }
                // a routine that adds rate terms beside a Rust stage of its own module that it
                // cannot stand for (that stage writes something the routine does not give) would
                // count the same physics twice: the Rust stage runs, the routine does not
                let left: Vec<&str> = entries
                    .iter()
                    .filter(|e| e.phase != Phase::Init && mods.contains(&e.stage.module()))
                    .map(|e| e.stage.name())
                    .collect();
                if term && !left.is_empty() {
                    let why = format!(
                        "it adds rate terms of {} but cannot stand for {} ({}, not among its arguments{hint}); running both would count that physics twice, so blastsph's own {} runs in its place",
                        r.modules.join(","),
                        left.join(", "),
                        lacks.join("; "),
                        r.modules.join(",")
                    );
                    note("not run", why, json!({ "replaced": false }));
                    continue;
                }
                if bound[ri].iter().any(|n| n == "dvxdt") {
                    writes.push(Field::Acc);
                }
                if bound[ri].iter().any(|n| n == "dedt") {
                    writes.push(Field::Dde);
                }
            }
            for (_, s) in &covered {
                for &f in s.writes() {
                    if !writes.contains(&f) {
                        writes.push(f);
                    }
                }
            }
            let mut reads: Vec<Field> = Vec::new();
            for (_, s) in covered.iter().chain(&helpers) {
                for &f in s.reads() {
                    if !reads.contains(&f) && !writes.contains(&f) {
                        reads.push(f);
                    }
                }
            }
            if alone {
                reads = argf.iter().copied().filter(|f| !writes.contains(f)).collect();
            }
            // where the stages it stands for are in the step
            let pos: Vec<usize> = covered
                .iter()
                .filter_map(|(_, s)| {
                    entries.iter().position(|e| {
                        e.phase != Phase::Init && e.stage.module() == s.module() && e.stage.name() == s.name()
                    })
                })
                .collect();
            // A routine standing for stages of several phases runs at the first of them, unless
            // a stage of its own step between them makes one of its inputs (a "density,force"
            // routine reads the p the EOS writes after the density rate): then it runs after the
            // last such maker, so that it reads what its twins read where they stood. A stage
            // between the first place and that maker that reads one of its outputs would then
            // read a stale value: such a routine cannot stand for these stages, and is not run.
            // (The entries are in the modules' order here; the step is their stable sort by
            // phase, so a stage's place in the step is (phase, index).)
            let key = |k: usize| (entries[k].phase, k);
            let (first, last) = (pos.iter().map(|&k| key(k)).min(), pos.iter().map(|&k| key(k)).max());
            let between = |k: usize, a: (Phase, usize), b: (Phase, usize)| {
                !pos.contains(&k) && entries[k].phase != Phase::Init && key(k) > a && key(k) < b
            };
            let mut maker: Option<usize> = None;
            if let (Some(a), Some(b)) = (first, last) {
                for k in 0..entries.len() {
                    if between(k, a, b)
                        && entries[k].stage.writes().iter().any(|f| reads.contains(f))
                        && maker.is_none_or(|m| key(k) > key(m))
                    {
                        maker = Some(k);
                    }
                }
            }
            // what the maker makes of the routine's inputs
            let made: Vec<String> = maker.map_or(Vec::new(), |m| {
                entries[m].stage.writes().iter().filter(|f| reads.contains(f)).map(|f| f.name()).collect()
            });
            if let (Some(a), Some(m)) = (first, maker) {
                let clash = (0..entries.len()).filter(|&k| between(k, a, key(m))).find_map(|k| {
                    let e = &entries[k];
                    e.stage.reads().iter().find(|f| writes.contains(f)).map(|f| (e.stage.name(), *f))
                });
                if let Some((name, f)) = clash {
                    let why = format!(
                        "it stands for {} of different places in the step: {name} between them reads its {}, and {} after it makes its {}; called at either place it would read or give a stale value, so blastsph's own {} runs in its place (map it as separate routines)",
                        covered.iter().map(|(_, s)| s.name()).collect::<Vec<_>>().join(" + "),
                        f.name(),
                        entries[m].stage.name(),
                        made.join(", "),
                        r.modules.join(",")
                    );
                    note("not run", why, json!({ "replaced": false }));
                    continue;
                }
            }
            let after: String = maker.map_or(String::new(), |m| {
                format!(", after {} (which makes its {})", entries[m].stage.name(), made.join(", "))
            });
            // the phase: the maker's, or the first of the stages it stands for
            let phase = maker
                .map(|m| entries[m].phase)
                .or_else(|| covered.iter().map(|(ph, _)| *ph).min())
                .or_else(|| mods.iter().flat_map(|&m| fresh(m, ctx)).map(|(ph, _)| ph).min())
                .unwrap_or(Phase::Rates);
            // the stages it stands for leave the step (from the last, so the others keep their
            // indices); it goes where the first of them was, or just after the maker (its index
            // less the removed stages before it)
            let mut gone = pos.clone();
            gone.sort_unstable();
            for &k in gone.iter().rev() {
                entries.remove(k);
            }
            let at = match maker {
                Some(m) => Some(m + 1 - gone.iter().filter(|&&k| k < m).count()),
                None => gone.first().copied(),
            };
            let module = covered.first().map_or(mods[0], |(_, s)| s.module());
            let terms = covered.iter().map(|(_, s)| s.terms()).find(|t| *t != Terms::default()).unwrap_or_else(|| {
                let k = ri as u8;
                Terms {
                    acc: writes.contains(&Field::Acc).then_some(10 + k),
                    de: writes.contains(&Field::Dde).then_some(10 + k),
                }
            });
            let twins: Vec<String> = helpers.iter().chain(&covered).map(|(_, s)| s.name().to_string()).collect();
            let label = if self.flags.is_empty() {
                "no --compat".to_string()
            } else {
                format!("compat {}", self.flags.label())
            };
            // the items of the routine's modules and of the twins it is compared with (the
            // book's sum_density computes W(0) with the kernel: kernel items)
            let mut twin_mods: Vec<Module> = mods.clone();
            twin_mods.extend(helpers.iter().chain(&covered).map(|(_, s)| s.module()));
            let off: Vec<&str> = Item::all()
                .filter(|&i| {
                    !self.flags.has(i) && twin_mods.iter().any(|m| i.modules().split(',').any(|x| x == m.name()))
                })
                .map(Item::name)
                .collect();
            let hint =
                if off.is_empty() { String::new() } else { format!("; compat items off here: {}", off.join(", ")) };
            let tol = Tolerance {
                ulp: 0,
                why: Box::leak(
                    format!(
                        "legacy {} against {} ({label}){hint}",
                        r.name,
                        if alone { "nothing".into() } else { twins.join(" + ") }
                    )
                    .into_boxed_str(),
                ),
            };
            let why_alone: Option<&'static str> = alone.then(|| {
                &*Box::leak(
                    format!("legacy {}: no Rust twin in this case; runs alone, not compared", r.name).into_boxed_str(),
                )
            });
            let chain: Vec<Box<dyn Stage>> = helpers.into_iter().chain(covered).map(|(_, s)| s).collect();
            // the outputs its twins write for the real particles only (the last twin to write
            // each field says)
            let real_rows: Vec<Field> = writes
                .iter()
                .copied()
                .filter(|f| {
                    chain.iter().rev().find(|s| s.writes().contains(f)).is_some_and(|s| s.real_rows().contains(f))
                })
                .collect();
            let stage = LegacyStage {
                lg: Arc::clone(self),
                routine: ri,
                name: Box::leak(format!("legacy.{}", r.name).into_boxed_str()),
                module,
                chain,
                reads,
                writes: writes.clone(),
                real_rows,
                terms,
                slots: Slots::default(),
                tol,
                alone: why_alone,
                replay: Mutex::new(None),
                input_writes: Mutex::new(Vec::new()),
            };
            let entry = Entry { phase, stage: Box::new(stage), backend: Backend::Fortran, seconds: 0.0 };
            match at {
                Some(k) => entries.insert(k, entry),
                None => entries.push(entry),
            }
            for m in &mods {
                if let Some(mp) = modules.get_mut(m)
                    && !alone
                {
                    mp.why = format!("legacy {} [{}]; {}", r.name, self.dir.display(), mp.why);
                }
            }
            let ph = format!("{phase:?}").to_lowercase();
            let what = if alone {
                "no Rust twin yet: runs alone in its place, not compared".to_string()
            } else {
                format!("stands for {}", twins.join(" + "))
            };
            note(
                if alone { "alone" } else { "run" },
                format!("{what}; phase {ph}{after}"),
                json!({ "stands_for": twins, "phase": ph, "writes": writes.iter().map(|f| f.name()).collect::<Vec<_>>() }),
            );
        }
        order_as_book(entries);
        let place = if self.scratch {
            format!(
                "a scratch folder, {}, removed when this ends: nothing is written in {}",
                self.cwd.display(),
                self.dir.join("work").display()
            )
        } else {
            self.cwd.display().to_string()
        };
        let mut text = format!(
            "legacy routines ({}, dim {}, maxn {}, max_interaction {}; they run in {place}):\n",
            self.dir.display(),
            info.dim,
            info.maxn,
            info.max_interaction,
        );
        // a routine of another formulation (the book's con_density in a summation case) is no
        // miss where another mapped routine stands for its module (sum_density); where none
        // does, nothing of the user's ran for that module and the routine counts as NOT RUN (a
        // Tait EOS mapped alone in a case whose EOS reads e: the verdict read as agreement)
        let mods_of =
            |name: &str| info.routines.iter().find(|r| r.name == name).map(|r| r.modules.clone()).unwrap_or_default();
        let ran: Vec<String> = notes.iter().filter(|n| n.status == "run").flat_map(|n| mods_of(&n.name)).collect();
        for n in notes.iter_mut() {
            if other_formulation.contains(&n.name) {
                let mods = mods_of(&n.name);
                if !mods.iter().any(|m| ran.contains(m)) {
                    n.json["replaced"] = json!(false);
                    n.why += &format!(
                        "; no mapped routine stands for {}: blastsph's own stages run in its place",
                        mods.join(",")
                    );
                }
            }
        }
        let mut routines = serde_json::Map::new();
        for n in &notes {
            text += &format!("  {:<14} {:<8} {}\n", n.name, n.status, n.why);
            let mut j = n.json.clone();
            j["status"] = json!(n.status);
            j["why"] = json!(n.why);
            routines.insert(n.name.clone(), j);
        }
        let summary = json!({ "dir": self.dir.display().to_string(), "cwd": self.cwd.display().to_string(), "routines": routines });
        (text, summary)
    }
}

/// Legacy stages of the book's `single_step` keep its order: one that comes earlier in the book
/// but sits in a later phase moves just before the other (the physical `viscosity`, whose `eta`
/// `int_force` reads).
fn order_as_book(entries: &mut Vec<Entry>) {
    let seq = |e: &Entry| -> Option<usize> {
        (e.stage.counterpart() != Counterpart::Fortran)
            .then(|| e.stage.name().strip_prefix("legacy."))
            .flatten()
            .and_then(|n| BOOK_ORDER.iter().position(|b| *b == n))
    };
    loop {
        let mut moved = false;
        'outer: for a in 0..entries.len() {
            let Some(sa) = seq(&entries[a]) else { continue };
            for b in 0..entries.len() {
                let Some(sb) = seq(&entries[b]) else { continue };
                if sa < sb && entries[a].phase > entries[b].phase {
                    let target = entries[b].phase;
                    let mut e = entries.remove(a);
                    e.phase = target;
                    entries.insert(if b < a { b } else { b - 1 }, e);
                    moved = true;
                    break 'outer;
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// What differs, material by material, between the case's own particles `base` and those a
/// legacy set-up routine made: the particle count (when the totals agree: another total is
/// warned of on its own), and the integrals Σ m (mass: kg in 3D and RZ,
/// kg/m in 2D plane, kg/m² in 1D), Σ m/ρ (volume, m^dim), Σ m e (internal energy, J in 3D),
/// Σ m v (momentum) and the centre of mass
/// Σ m x / Σ m. Sums agree to a relative 10⁻⁵ (a routine's single-precision literals move them
/// by about 10⁻⁷) and the centres to a twentieth of the finest spacing. None when nothing
/// differs; else the first differences, named.
pub(crate) fn state_differences(case: &Case, base: &Initial, made: &Initial) -> Option<String> {
    let dim = case.dim.max(1);
    #[derive(Default)]
    struct Sums {
        n: usize,
        m: f64,
        vol: f64,
        me: f64,
        mv: [f64; 3],
        mvabs: f64,
        mx: [f64; 3],
    }
    let sums = |p: &Initial, mat: usize| {
        let mut s = Sums::default();
        for (k, _) in p.mat.iter().enumerate().filter(|(_, m)| **m as usize == mat) {
            let m = p.mass[k];
            s.n += 1;
            s.m += m;
            s.vol += m / p.rho[k];
            s.me += m * p.e[k];
            for d in 0..dim {
                s.mv[d] += m * p.v[dim * k + d];
                s.mvabs += (m * p.v[dim * k + d]).abs();
                s.mx[d] += m * p.x[dim * k + d];
            }
        }
        s
    };
    let off =
        |a: f64, b: f64, scale: f64| (a - b).abs() > 1e-5 * scale.max(f64::MIN_POSITIVE) || a.is_nan() != b.is_nan();
    let mut out: Vec<String> = Vec::new();
    for (mi, mc) in case.materials.iter().enumerate() {
        let (c, g) = (sums(base, mi), sums(made, mi));
        if c.n == 0 && g.n == 0 {
            continue;
        }
        let name = &mc.name;
        // (another total count is said by its own warning)
        if c.n != g.n && base.mat.len() == made.mat.len() {
            out.push(format!("{name}: {} particles against the case's {}", g.n, c.n));
        }
        if off(g.m, c.m, c.m.abs().max(g.m.abs())) {
            out.push(format!("{name}: mass {:.6e} against the case's {:.6e}", g.m, c.m));
        }
        if off(g.vol, c.vol, c.vol.abs().max(g.vol.abs())) {
            out.push(format!("{name}: volume Σm/ρ {:.6e} against the case's {:.6e}", g.vol, c.vol));
        }
        if off(g.me, c.me, c.me.abs().max(g.me.abs())) {
            out.push(format!("{name}: internal energy Σme {:.6e} against the case's {:.6e}", g.me, c.me));
        }
        if (0..dim).any(|d| off(g.mv[d], c.mv[d], c.mvabs.max(g.mvabs))) {
            out.push(format!(
                "{name}: momentum Σmv ({}) against the case's ({})",
                fmt_vec(&g.mv[..dim]),
                fmt_vec(&c.mv[..dim])
            ));
        }
        if c.m > 0.0 && g.m > 0.0 {
            let cc: Vec<f64> = (0..dim).map(|d| c.mx[d] / c.m).collect();
            let gc: Vec<f64> = (0..dim).map(|d| g.mx[d] / g.m).collect();
            if (0..dim).any(|d| (cc[d] - gc[d]).abs() > 0.05 * base.dx_min || cc[d].is_nan() != gc[d].is_nan()) {
                out.push(format!(
                    "{name}: centre of mass ({}) m against the case's ({}) m",
                    fmt_vec(&gc),
                    fmt_vec(&cc)
                ));
            }
        }
    }
    if out.is_empty() {
        return None;
    }
    let more = out.len().saturating_sub(3);
    out.truncate(3);
    let mut t = out.join("; ");
    if more > 0 {
        t.push_str(&format!(" (and {more} more)"));
    }
    Some(t)
}

/// A short vector of values for a message, `a, b, c` with 6 significant digits.
fn fmt_vec(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:.6e}")).collect::<Vec<_>>().join(", ")
}
