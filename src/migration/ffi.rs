//! The run-time loader of a legacy build: opens `DIR/liblegacy.so` (made by
//! `blastsph legacy build`) and calls its shims through one function-pointer type,
//!
//! ```c
//! int blastsph_shim_<name>(void **ptrs, const int64_t *sizes);
//! ```
//!
//! behind a safe API: arguments are slices by vocabulary name; their kinds and lengths are checked
//! against the build (`DIR/build.json`) before the call, pair indices against the particles.
//!
//! ```no_run
//! # use blastsph::migration::{LegacyLib, Args};
//! let lib = LegacyLib::open("runs/legacy".as_ref()).unwrap();
//! let (mut rho, mut u, mut p, mut c) = (vec![1.0], vec![2.5], vec![0.0], vec![0.0]);
//! let mut nt = [1];
//! let mut args = Args::new().int("ntotal", &mut nt).real("rho", &mut rho).real("u", &mut u)
//!     .real("p", &mut p).real("c", &mut c);
//! lib.routine("p_gas").unwrap().call(&mut args).unwrap();
//! ```
//!
//! Legacy code is not re-entrant (SAVEd locals, COMMON blocks, large local arrays that gfortran
//! makes static, the shims' own buffers): every call in the process holds one global lock.
//! A routine that executes `STOP` (or `ERROR STOP`) ends the whole process, as it ended the legacy
//! program; a handler registered with `atexit` when the first build is opened turns that end into
//! one line naming the routine (and what the caller said of the call, [`set_context`]) and exit
//! status 3, since libgfortran's `STOP 'text'` exits with status 0, which would read as success.
//!
//! This file and `host_ffi.rs` (host mode) hold the only `unsafe` code of the migration path.
#![allow(unsafe_code)]

use super::builder::{BUILD_JSON, BindingInfo, BuildInfo, RoutineInfo};
use super::shim;
use super::vocab::{self, Base, Kind, Shape};
use crate::error::{Result, input};
use libloading::os::unix::{Library, RTLD_LOCAL, RTLD_NOW, Symbol};
use std::ffi::c_void;
use std::os::raw::c_int;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The one C type of every shim.
type ShimFn = unsafe extern "C" fn(ptrs: *const *mut c_void, sizes: *const i64) -> c_int;

/// Serialises every call into legacy code in this process.
static CALL_LOCK: Mutex<()> = Mutex::new(());

/// The legacy routine being called now ("" between calls), and what the caller says of the call
/// (its step): read by the exit handler, [`legacy_exit`].
static IN_CALL: Mutex<(String, String)> = Mutex::new((String::new(), String::new()));

/// The run's summary.json, when a run (not a dual run or a bare call) is calling legacy code: the
/// exit handler marks it as ended by the legacy code ([`report_exit_to`]).
static SUMMARY: Mutex<Option<PathBuf>> = Mutex::new(None);

/// What the exit handler writes when the run has no summary.json yet (the legacy code ended it
/// in the rates at t = 0, before the run's first summary): the case, its dimension and particles.
static SKELETON: Mutex<Option<serde_json::Value>> = Mutex::new(None);

/// The run's last completed step and its time, for the summary the exit handler marks (that
/// summary is from the start or the last checkpoint).
static PROGRESS: Mutex<(u64, f64)> = Mutex::new((0, 0.0));

/// The exit status of a process that a legacy `STOP` ended (as a run that cannot go on: README,
/// "Exit statuses").
pub const STOP_STATUS: c_int = 3;

unsafe extern "C" {
    /// libgfortran's FLUSH statement: with no unit, every open unit (the legacy code's WRITEs to
    /// standard output are buffered when it is a file or a pipe).
    fn _gfortran_flush_i4(unit: *const i32);
}

#[cfg(feature = "io")]
unsafe extern "C" {
    /// HDF5's library close: flushes and closes every open file (particles.h5 created before the
    /// first frame is otherwise left truncated by `_exit`).
    fn H5close() -> i32;
}

/// Runs at `exit`: when a legacy call is in progress the legacy code executed `STOP` (libgfortran
/// calls `exit`, with status 0 for `STOP 'text'`): says so in one line and ends with
/// [`STOP_STATUS`] instead, after flushing the Fortran units and closing HDF5's files (particles.h5
/// stays readable; gauges.csv keeps the lines up to the last frame written, when it is flushed:
/// later ones are in a buffer the exit loses).
extern "C" fn legacy_exit() {
    let (name, ctx) = match IN_CALL.try_lock() {
        Ok(g) => g.clone(),
        Err(_) => return,
    };
    if name.is_empty() {
        return;
    }
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let at = if ctx.is_empty() { String::new() } else { format!(" {ctx}") };
    let what = format!(
        "legacy routine {name} ended the process{at} (a STOP, a CALL EXIT, or a Fortran runtime error such as -fcheck=bounds finds: libgfortran's own line, if any, is above)"
    );
    // (writeln, not eprintln: a closed stderr must not panic inside an extern "C" handler)
    let _ = writeln!(
        std::io::stderr(),
        "error: {what}: your program would have ended here, and so does blastsph (exit status {STOP_STATUS}; the output written so far is kept)"
    );
    if let Ok(g) = SUMMARY.try_lock()
        && let Some(p) = g.as_ref()
    {
        mark_summary(p, &what);
    }
    flush_fortran_at_exit();
    // SAFETY: H5close closes the HDF5 library's open files (no HDF5 call is in progress: the
    // legacy call is, and they are serialised on this thread); `_exit` ends the process at once
    // without running the remaining exit handlers (this one would otherwise return into
    // libgfortran's exit with status 0).
    unsafe {
        #[cfg(feature = "io")]
        H5close();
        libc::_exit(STOP_STATUS);
    }
}

/// Rewrites the summary.json at `path` (the run's last, from its start or its last checkpoint;
/// the [`SKELETON`] when the first rates ended the run before its first summary) as the end of a
/// run that the legacy code ended: `"status": "unstable"` (exit status 3, as for a run that
/// cannot go on), `"partial": true` (its energies are the checkpoint's, not the last step's), the
/// last completed step and its time ([`PROGRESS`]) and the line printed as its `"diagnostic"`. Through a temporary file; any
/// failure leaves the file as it was (the handler must not fail).
fn mark_summary(path: &Path, what: &str) {
    let read = std::fs::read_to_string(path).ok().and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let skeleton = || SKELETON.try_lock().ok().and_then(|g| g.clone());
    let Some(mut v) = read.or_else(skeleton) else { return };
    let Some(obj) = v.as_object_mut() else { return };
    obj.insert("status".into(), "unstable".into());
    obj.insert("partial".into(), true.into());
    obj.insert("diagnostic".into(), what.into());
    if let Ok(g) = PROGRESS.try_lock() {
        obj.insert("steps".into(), g.0.into());
        obj.insert("time".into(), g.1.into());
    }
    let Ok(out) = serde_json::to_string_pretty(&v) else { return };
    let _ = crate::files::write_atomic(path, out.as_bytes());
}

/// Flushes every Fortran unit (a legacy routine's WRITEs to standard output, which libgfortran
/// buffers when it is a file or a pipe), so that they come out in order with blastsph's own lines.
pub fn flush_fortran() {
    // SAFETY: FLUSH with no unit (NULL) takes no pointer of ours and flushes every open unit; it
    // is called between legacy calls (on the thread that makes them), or at exit (on a thread
    // of its own, while the legacy call that ended the process waits in `exit`).
    unsafe { _gfortran_flush_i4(std::ptr::null()) }
}

/// How long an exit handler waits for libgfortran's flush of every unit (s).
const EXIT_FLUSH_WAIT_S: u64 = 2;

/// [`flush_fortran`] from an exit handler, on a thread of its own, waited for at most
/// `EXIT_FLUSH_WAIT_S` (2 s). A Fortran runtime error inside an I/O statement (an OPEN of a missing
/// file) exits with that statement's unit still locked; libgfortran's flush would then wait for
/// it for ever. The process then ends without the unflushed output.
pub fn flush_fortran_at_exit() {
    let (tx, rx) = std::sync::mpsc::channel();
    let spawned = std::thread::Builder::new().spawn(move || {
        flush_fortran();
        let _ = tx.send(());
    });
    if spawned.is_ok() {
        let _ = rx.recv_timeout(std::time::Duration::from_secs(EXIT_FLUSH_WAIT_S));
    }
}

/// Runs `f` with the process's standard output (file descriptor 1) sent to `file`: what a
/// legacy routine prints there (a set-up routine's banner) stays out of blastsph's own output.
/// Returns `f`'s result and the number of lines it printed (0 when the file cannot be made:
/// then the output is not redirected).
pub fn quiet_stdout<R>(file: &Path, f: impl FnOnce() -> R) -> (R, usize) {
    use std::io::Write;
    use std::os::fd::AsRawFd;
    let _ = std::io::stdout().flush();
    flush_fortran();
    let Ok(out) = std::fs::File::create(file) else { return (f(), 0) };
    // SAFETY: `dup` of descriptor 1 gives a new descriptor that this function owns and closes
    // below; `out` is open for the whole redirection.
    let saved = unsafe { libc::dup(1) };
    // SAFETY: `dup2` onto descriptor 1 replaces the process's standard output with `out`.
    if saved < 0 || unsafe { libc::dup2(out.as_raw_fd(), 1) } < 0 {
        return (f(), 0);
    }
    let r = f();
    let _ = std::io::stdout().flush();
    flush_fortran();
    // SAFETY: puts the saved standard output back on descriptor 1 and closes the copy, which
    // this function made.
    unsafe {
        libc::dup2(saved, 1);
        libc::close(saved);
    }
    let lines = std::fs::read_to_string(file).map_or(0, |t| t.lines().count());
    (r, lines)
}

/// Names the summary.json that the exit handler marks when a legacy routine ends the process
/// during a run (`None`: none, e.g. between runs or in a dual run, which keeps no summary).
pub fn report_exit_to(path: Option<PathBuf>) {
    // absolute: the handler runs inside a legacy call, whose current folder is `DIR/work`, so a
    // relative run folder (`--out r`) would name another place there
    let path = path.map(|p| std::path::absolute(&p).unwrap_or(p));
    *SUMMARY.lock().unwrap_or_else(|e| e.into_inner()) = path;
}

/// As [`report_exit_to`], before the run has a summary.json: the exit handler writes `skeleton`
/// (marked) when it finds none.
pub fn report_exit_with(path: PathBuf, skeleton: serde_json::Value) {
    *SKELETON.lock().unwrap_or_else(|e| e.into_inner()) = Some(skeleton);
    *PROGRESS.lock().unwrap_or_else(|e| e.into_inner()) = (0, 0.0);
    report_exit_to(Some(path));
}

/// The run's last completed step and time, for the summary the exit handler marks.
pub fn report_progress(step: u64, t: f64) {
    *PROGRESS.lock().unwrap_or_else(|e| e.into_inner()) = (step, t);
}

/// Says what the next legacy calls are (e.g. "at step 3"), for the line a `STOP` prints.
pub fn set_context(ctx: String) {
    IN_CALL.lock().unwrap_or_else(|e| e.into_inner()).1 = ctx;
}

/// Registers [`legacy_exit`] once per process.
fn watch_exit() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // SAFETY: `legacy_exit` is an `extern "C" fn()` that lives as long as the program.
        unsafe {
            libc::atexit(legacy_exit);
        }
    });
}

/// An opened legacy build.
pub struct LegacyLib {
    dir: PathBuf,
    info: BuildInfo,
    lib: Library,
}

impl std::fmt::Debug for LegacyLib {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LegacyLib").field("dir", &self.dir).field("routines", &self.info.routines.len()).finish()
    }
}

impl LegacyLib {
    /// Opens the build in `dir` (its `build.json` and library).
    pub fn open(dir: &Path) -> Result<LegacyLib> {
        let info = BuildInfo::read(dir)?;
        watch_exit();
        let path = dir.join(&info.library);
        if !path.is_file() {
            return Err(input(format!("{}: no library (see {})", path.display(), dir.join(BUILD_JSON).display())));
        }
        let _guard = CALL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
        // SAFETY: loading runs the library's initialisers: those of libgfortran (already loaded
        // by blastsph's own core) and of the user's code compiled by `legacy build`, which has none
        // of its own (Fortran has no static constructors); RTLD_NOW resolves every symbol now,
        // so a missing one fails here and not in the middle of a call.
        let lib = unsafe { Library::open(Some(&path), RTLD_NOW | RTLD_LOCAL) }
            .map_err(|e| input(format!("{}: cannot load: {e}", path.display())))?;
        Ok(LegacyLib { dir: dir.to_path_buf(), info, lib })
    }

    pub fn info(&self) -> &BuildInfo {
        &self.info
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// A mapped routine by name (any case).
    pub fn routine(&self, name: &str) -> Result<Routine<'_>> {
        let spec = self.info.routine(name).ok_or_else(|| {
            let known: Vec<&str> = self.info.routines.iter().map(|r| r.name.as_str()).collect();
            input(format!("legacy build {}: no routine {name} (mapped: {})", self.dir.display(), known.join(", ")))
        })?;
        let sym = format!("{}\0", spec.shim);
        // SAFETY: every shim of a legacy build is generated by `shim::source` with exactly the
        // signature of `ShimFn` (bind(C), arguments `type(c_ptr) :: ptrs(*)`,
        // `integer(c_int64_t) :: sizes(*)`, result `integer(c_int)`).
        let f: Symbol<ShimFn> = unsafe { self.lib.get(sym.as_bytes()) }
            .map_err(|e| input(format!("{}: no symbol {}: {e}", self.dir.display(), spec.shim)))?;
        Ok(Routine { lib: self, spec, f: *f })
    }
}

/// Marks a legacy call in progress (for [`legacy_exit`]) until dropped.
struct InCall;
impl InCall {
    fn enter(name: &str) -> InCall {
        IN_CALL.lock().unwrap_or_else(|e| e.into_inner()).0 = name.to_string();
        InCall
    }
}
impl Drop for InCall {
    fn drop(&mut self) {
        IN_CALL.lock().unwrap_or_else(|e| e.into_inner()).0.clear();
    }
}

/// One argument slice.
#[derive(Debug)]
pub enum Slot<'a> {
    Real(&'a mut [f64]),
    Int(&'a mut [i32]),
}

impl Slot<'_> {
    fn len(&self) -> usize {
        match self {
            Slot::Real(s) => s.len(),
            Slot::Int(s) => s.len(),
        }
    }
    fn kind(&self) -> Kind {
        match self {
            Slot::Real(_) => Kind::Real,
            Slot::Int(_) => Kind::Int,
        }
    }
    fn ptr(&mut self) -> *mut c_void {
        match self {
            Slot::Real(s) => s.as_mut_ptr().cast(),
            Slot::Int(s) => s.as_mut_ptr().cast(),
        }
    }
}

/// The arguments of a call, by vocabulary name (aliases allowed). Scalars are one-value slices.
/// Every slice may be written: the shim copies each buffer back after the call.
#[derive(Debug, Default)]
pub struct Args<'a> {
    items: Vec<(String, Slot<'a>)>,
}

impl<'a> Args<'a> {
    pub fn new() -> Self {
        Args { items: Vec::new() }
    }
    fn canonical(name: &str) -> String {
        vocab::lookup(name).map(|t| t.name.to_string()).unwrap_or_else(|| name.to_ascii_lowercase())
    }
    /// A `double precision` argument.
    pub fn real(mut self, name: &str, s: &'a mut [f64]) -> Self {
        self.items.push((Self::canonical(name), Slot::Real(s)));
        self
    }
    /// A default-`integer` argument (0-based indices for `pair_i`, `pair_j`, `mat`).
    pub fn int(mut self, name: &str, s: &'a mut [i32]) -> Self {
        self.items.push((Self::canonical(name), Slot::Int(s)));
        self
    }
    fn get(&self, name: &str) -> Option<&Slot<'a>> {
        self.items.iter().find(|(n, _)| n == name).map(|(_, s)| s)
    }
    fn int_value(&self, name: &str) -> Option<i32> {
        match self.get(name) {
            Some(Slot::Int(s)) if s.len() == 1 => Some(s[0]),
            _ => None,
        }
    }
}

/// A routine of an opened build.
pub struct Routine<'l> {
    lib: &'l LegacyLib,
    spec: &'l RoutineInfo,
    f: ShimFn,
}

impl std::fmt::Debug for Routine<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Routine").field("name", &self.spec.name).field("shim", &self.spec.shim).finish()
    }
}

impl Routine<'_> {
    pub fn info(&self) -> &RoutineInfo {
        self.spec
    }
    /// What [`Routine::call`] needs, in the shim's order.
    pub fn bindings(&self) -> &[BindingInfo] {
        &self.spec.bindings
    }

    /// Calls the routine through its shim. Every binding must be in `args` with its kind;
    /// per-particle arrays hold at most `maxn` particles and at least `ntotal` (when given),
    /// per-pair arrays at most `max_interaction` pairs and at least `niac` (when given); pair
    /// indices lie within the particles. After the call the slices hold what the routine left.
    pub fn call(&self, args: &mut Args<'_>) -> Result<()> {
        let info = &self.lib.info;
        let (dim, name) = (info.dim, &self.spec.name);
        let err = |m: String| input(format!("legacy call {name}: {m}"));
        for (k, (n, _)) in args.items.iter().enumerate() {
            if args.items[..k].iter().any(|(o, _)| o == n) {
                return Err(err(format!("\"{n}\" given twice")));
            }
            if !self.spec.bindings.iter().any(|b| &b.name == n) {
                let need: Vec<&str> = self.spec.bindings.iter().map(|b| b.name.as_str()).collect();
                return Err(err(format!("\"{n}\" is not an argument of this routine (it takes {})", need.join(", "))));
            }
        }
        let ntotal = args.int_value("ntotal");
        let niac = args.int_value("niac");
        let mut min_particles = usize::MAX;
        for b in &self.spec.bindings {
            let s = args.get(&b.name).ok_or_else(|| err(format!("argument \"{}\" missing", b.name)))?;
            if s.kind() != b.kind {
                return Err(err(format!("\"{}\" must be {:?}, got {:?}", b.name, b.kind, s.kind())));
            }
            let stride = b.shape.stride(dim);
            let len = s.len();
            let (cap, what) = match b.shape {
                Shape::Scalar => (1, "value"),
                Shape::Particle | Shape::ParticleVec => (info.maxn, "particles (maxn)"),
                Shape::Pair | Shape::PairVec => (info.max_interaction, "pairs (max_interaction)"),
            };
            if b.shape == Shape::Scalar {
                if len != 1 {
                    return Err(err(format!("\"{}\" is a scalar: give one value, not {len}", b.name)));
                }
                continue;
            }
            if len % stride != 0 {
                return Err(err(format!("\"{}\" has {len} values, not a multiple of dim = {dim}", b.name)));
            }
            let count = len / stride;
            if count > cap {
                return Err(err(format!("\"{}\" holds {count} {what}, more than the build's {cap}", b.name)));
            }
            let need = if b.shape.per_particle() { ntotal } else { niac };
            if let Some(n) = need
                && n > 0
                && count < n as usize
            {
                let of = if b.shape.per_particle() { "ntotal" } else { "niac" };
                return Err(err(format!("\"{}\" holds {count} values per component, {of} is {n}", b.name)));
            }
            if let Some(n) = need
                && n < 0
            {
                return Err(err(format!("negative count {n}")));
            }
            if b.shape.per_particle() {
                min_particles = min_particles.min(count);
            }
        }
        // pair indices (0-based here) must name particles the arrays hold
        let bound = match ntotal {
            Some(n) if n > 0 => (n as usize).min(min_particles),
            _ => min_particles.min(info.maxn),
        };
        if let Some(n) = niac
            && n > 0
        {
            for pname in ["pair_i", "pair_j"] {
                if let Some(Slot::Int(s)) = args.get(pname) {
                    let n = (n as usize).min(s.len());
                    if let Some(k) = s[..n].iter().position(|&v| v < 0 || v as usize >= bound) {
                        return Err(err(format!("{pname}[{k}] = {} is not a particle index in 0..{bound}", s[k])));
                    }
                }
            }
        }
        if let Some(b) = self.spec.bindings.iter().find(|b| b.base == Base::One && b.shape.per_particle())
            && let Some(Slot::Int(s)) = args.get(&b.name)
            && let Some(k) = s.iter().position(|&v| v < 0)
        {
            return Err(err(format!("{}[{k}] = {} is negative (0-based numbers)", b.name, s[k])));
        }

        let mut ptrs: Vec<*mut c_void> = Vec::with_capacity(self.spec.bindings.len());
        let mut sizes: Vec<i64> = Vec::with_capacity(self.spec.bindings.len());
        for b in &self.spec.bindings {
            let pos = args.items.iter().position(|(n, _)| n == &b.name).expect("checked above");
            let slot = &mut args.items[pos].1;
            sizes.push(slot.len() as i64);
            ptrs.push(slot.ptr());
        }
        let status = {
            let _guard = CALL_LOCK.lock().unwrap_or_else(|e| e.into_inner());
            let _in = InCall::enter(name);
            // SAFETY: `ptrs[k]` points to `sizes[k]` values of the binding's type (f64 for
            // real, i32 for integer: checked above), each from a distinct `&mut` slice borrowed
            // for the whole call; the shim reads and writes at most `sizes[k]` values through
            // `ptrs[k]` and copies the data into its own buffers before the user's routine sees
            // it, so the routine never holds a pointer into Rust memory after the call; the global
            // lock keeps the shims' buffers and the legacy code's static data to one caller.
            unsafe { (self.f)(ptrs.as_ptr(), sizes.as_ptr()) }
        };
        match status {
            shim::OK => Ok(()),
            shim::TOO_LARGE => Err(err("an array is larger than its legacy buffer".into())),
            shim::BAD_COUNT => Err(err("ntotal or niac lies outside the legacy buffers".into())),
            shim::TRUNCATED => {
                let got = args.int_value("niac").unwrap_or(-1);
                Err(err(format!(
                    "the routine found {got} pairs, more than the pair arrays hold: grow them and call again"
                )))
            }
            shim::BAD_PAIR => Err(err("a pair index lies outside the particles".into())),
            shim::NOT_ALLOCATED => Err(err(
                "an allocatable module variable among its globals is not allocated (allocate it in a routine mapped as module = \"init\")".into(),
            )),
            s => Err(err(format!("the shim returned status {s}"))),
        }
    }
}
