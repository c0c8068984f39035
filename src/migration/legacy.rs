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
//! stands for no stage but adds a rate term (`dvxdt`, `dedt`: the book's `ext_force`) or makes a
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

mod differences;
pub mod host;
mod plan;
mod virt;

use differences::state_differences;

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
    /// What the set-up's `virt_part` made: its boundary particles and their kind.
    virt_made: Option<(usize, String)>,
}

/// An opened legacy build, bound to a case.
pub struct Legacy {
    lib: LegacyLib,
    dir: PathBuf,
    cwd: PathBuf,
    /// The code's type code of each material.
    itype: Vec<i32>,
    setup_only: bool,
    /// `cwd` is `work` in a scratch folder of its own (`check`), removed when the build is closed.
    scratch: bool,
    /// The warnings said so far, shared by every opening of one bridge (the ledger opens the
    /// build once per row): each is said once.
    said: Arc<Mutex<std::collections::BTreeSet<String>>>,
    /// The case's fixed step (s), what the routines get as `dt`.
    dt: Option<f64>,
    flags: Flags,
    shared: Mutex<Shared>,
    /// Host mode ([`super::host`]): the user's program makes the calls.
    pub(crate) host: bool,
    /// Host mode: what the stage's "Fortran" side does at its next run (puts the outputs the
    /// user's routine gave into the state).
    pub(crate) host_fill: Mutex<Option<HostFill>>,
    /// Host mode: each legacy stage's rate-term slots, by stage name, as the plan assigned them.
    pub(crate) host_slots: Mutex<BTreeMap<String, Slots>>,
}

/// Puts a host call's legacy outputs into the state.
pub(crate) type HostFill = Box<dyn FnOnce(&mut Particles, &mut Work) + Send>;

/// The book's type code of an EOS kind.
pub(crate) fn book_code(kind: &str) -> Option<i32> {
    match kind {
        "ideal_gas" => Some(1),
        // the book's water: its Mie–Grüneisen kind and the Tait form of its p_art_water
        "water" | "tait" | "morris" => Some(2),
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
        if self.scratch
            && let Some(root) = self.cwd.parent()
        {
            let _ = std::fs::remove_dir_all(root);
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
        // a scratch folder has the build's layout: `work` where the routines run, `data` beside it
        let root = if scratch { scratch_folder()? } else { abs.clone() };
        let cwd = root.join("work");
        let run_dirs = info.run_dirs.iter().map(|d| cwd.join(d));
        for d in [cwd.clone(), root.join("data")].into_iter().chain(run_dirs) {
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
            host: how.host,
            host_fill: Mutex::new(None),
            host_slots: Mutex::new(BTreeMap::new()),
        });
        if !how.host {
            l.init(case.dim)?;
        }
        Ok(l)
    }

    /// Calls the manifest's init routines (module `init`: the code's own initialiser of its COMMON
    /// blocks), once each, in order, before the set-up routine and the first step. Their arguments
    /// are given as at the set-up (no particles yet); what they return is not read.
    fn init(&self, dim: usize) -> Result<()> {
        let info = self.lib.info();
        for r in info.routines.iter().filter(|r| r.modules.iter().any(|m| m == "init")) {
            let mut bufs = self.set_up_bufs(r, &Particles { dim, ..Default::default() }, 0);
            self.call_quiet(&r.name, &r.bindings, &mut bufs)?;
            *self.shared().calls.entry(r.name.clone()).or_default() += 1;
        }
        Ok(())
    }

    /// The buffers of routine `r`'s arguments before the run's first step, gathered from `p` (no
    /// particles: zeros) at step `itimestep`: arrays of `maxn`, no work arrays, t = 0, the fixed step.
    fn set_up_bufs(&self, r: &super::builder::RoutineInfo, p: &Particles, itimestep: i32) -> Vec<Buf> {
        let maxn = self.lib.info().maxn;
        let work = Work::default();
        let mut sh = self.shared();
        let mut ctx = Ctx {
            dim: p.dim,
            itimestep,
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
            .map(|b| bind::gather(&b.name, is_vec(b.shape), b.shape.per_pair(), &mut ctx, p, &work))
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
        let Some(r) = self.setup_routine() else { return self.virt_part(case, base) };
        let info = self.lib.info();
        let (dim, maxn) = (case.dim, info.maxn);
        let mut bufs = self.set_up_bufs(r, &Particles { dim, ..Default::default() }, 0);
        self.call_quiet(&r.name, &r.bindings, &mut bufs)?;
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
        // differs is said once (the case's gauges, charge and walls were written for its own)
        let described = base.x.len() / dim.max(1);
        if described != n {
            self.warn(format!(
                "legacy {} made {n} particles, the case describes {described}: the run takes the routine's (check that the case's regions, gauges and charge are the ones your program sets up)",
                r.name
            ));
        }
        let made = Initial { x, v, rho, e, h, mass, mat, region, counts, dx_min: base.dx_min, bnd: Vec::new() };
        if let Some(diff) = state_differences(case, &base, &made) {
            self.warn(format!(
                "legacy {}'s particles are not the state the case describes: {diff}; the run takes the routine's, while the case's exact solution, gauges and charge are the case's",
                r.name
            ));
        }
        self.virt_part(case, made)
    }

    /// [`Self::call_raw`] for an init or set-up routine. In a scratch folder (`check`) what it
    /// prints on standard output is kept out of `check`'s text and said once as a count.
    fn call_quiet(&self, name: &str, bindings: &[super::builder::BindingInfo], bufs: &mut [Buf]) -> Result<()> {
        if !self.scratch {
            return self.call_raw(name, bindings, bufs);
        }
        let file = self.cwd.join(format!("{name}.stdout"));
        let (r, lines) = super::ffi::quiet_stdout(&file, || self.call_raw(name, bindings, bufs));
        if lines > 0 && self.said.lock().unwrap_or_else(|e| e.into_inner()).insert(format!("quiet {name}")) {
            let n = if lines == 1 { "1 line".to_string() } else { format!("{lines} lines") };
            eprintln!(
                "note: legacy {name} printed {n} on standard output, not shown here (check runs it in a scratch folder); run and dual show them"
            );
        }
        r
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
    /// An EOS routine that gives p only: each call sets the state's c to the legacy code's c,
    /// a work array that nothing writes (0).
    zero_c: bool,
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
        if self.lg.host {
            // host mode: the user's program called the routine; its outputs go into the state
            if let Some(fill) = self.lg.host_fill.lock().unwrap_or_else(|e| e.into_inner()).take() {
                fill(p, w);
            }
            return;
        }
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
                self.unwritten_c(p);
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
        // a search makes its pairs from none: niac = 0 in (some count on from the caller's 0)
        let mut bufs: Vec<Buf> = r
            .bindings
            .iter()
            .map(|b| match b.name.as_str() {
                "niac" if search => Buf::I(vec![0]),
                _ => bind::gather(&b.name, is_vec(b.shape), b.shape.per_pair(), &mut ctx, p, w),
            })
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
        drop(sh);
        self.unwritten_c(p);
        let snaps = self.writes.iter().map(|f| f.snap(p, w)).collect();
        *self.replay.lock().unwrap_or_else(|e| e.into_inner()) = Some((key, snaps));
        *self.input_writes.lock().unwrap_or_else(|e| e.into_inner()) = changed;
    }
}

impl LegacyStage {
    /// For an EOS routine that gives p only: the state's c becomes the legacy code's c, an array
    /// that no routine writes, kept from call to call (0 for every particle).
    fn unwritten_c(&self, p: &mut Particles) {
        if !self.zero_c {
            return;
        }
        let nt = p.ntotal;
        let mut sh = self.lg.shared();
        let Buf::R(c) = sh.scratch.entry(UNWRITTEN_C.to_string()).or_insert_with(|| Buf::R(Vec::new())) else {
            return;
        };
        if c.len() < nt {
            c.resize(nt, 0.0);
        }
        if p.c.len() < nt {
            p.c.resize(nt, 0.0);
        }
        p.c[..nt].copy_from_slice(&c[..nt]);
    }
}

/// The key of the legacy code's unwritten sound speed among its work arrays (no argument name).
const UNWRITTEN_C: &str = "c (written by no routine)";

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
        if self.lg.host {
            self.lg.host_slots.lock().unwrap_or_else(|e| e.into_inner()).insert(self.name.to_string(), slots);
        }
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
