//! Run-directory output (docs/reference/output.md): `particles.h5` in the H5Part layout that ParaView
//! opens directly (groups `Step#N` of equal-length 1D datasets and a float64 `TimeValue`
//! attribute), and its XDMF sidecar `particles.xmf` (`File > Open particles.xmf` in ParaView, or
//! `OpenDataFile` in pvpython).
//!
//! Storage (docs/reference/output.md has the measurements):
//! - every dataset is chunked (at most 65 536 values a chunk) and compressed (byte shuffle, then
//!   deflate level 1): the 1 ms surface blast shrinks from 67.6 MB to 36.6 MB (level 4 gives
//!   36.4 MB for 42 % more instructions in the writer);
//! - a component that is zero by construction (z in 1D and 2D, y in 1D, and the matching
//!   velocity and shear-stress components) is declared with fill value 0 and never written:
//!   HDF5 allocates no chunk for it, so it costs a few hundred bytes of header and no data, and
//!   reads back as zeros. They stay because ParaView's H5PartReader takes its points from its
//!   coordinate arrays `x`, `y`, `z`, and the output contract (docs/reference/output.md) names `z` (0 in 2D) and `vz`;
//! - `/xdmf/Step#N/{xyz, vxyz, stress}` are (N, 3) and (N, 9) HDF5 virtual datasets over the 1D
//!   columns (no data of their own): ParaView's Xdmf3 reader builds points and vectors only from
//!   such arrays.
//!
//! `particles.xmf` is rewritten (to a temporary name, then renamed) after an output step when
//! the time since its last rewrite is at least ten times what that rewrite took, and always at a
//! checkpoint and at the end: a run that is killed leaves an XDMF that names the steps of the
//! HDF5 file up to a recent one (every one, while the XDMF is small), and a run of many frames
//! does not spend its time rewriting it (the text grows with the frames: rewritten after every
//! one, 10 000 frames of the shock tube took 394 s; now 21 s, docs/reference/output.md).

use crate::error::{IoAt, Result, SphError};
use crate::modules::param::NSTR;
use crate::sim::Sim;
use crate::sim::checkpoint::{self, Blob};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Opens or creates an HDF5 file without HDF5's own file lock. HDF5 locks a file it opens with
/// `flock` on a descriptor it opens without close-on-exec, so a child process started while the
/// file is open (a test harness starting `blastsph`, a user's script) inherits the lock and holds
/// it after blastsph has closed the file: the next open of the file failed with "unable to lock
/// file, errno = 11" (seen intermittently in the parallel tests). A run directory's `run.lock` is
/// the lock that keeps two runs apart: only the process that holds it writes particles.h5 or
/// revolved.h5 (the latter under a temporary name, then renamed).
pub(crate) fn h5_file(path: &Path, mode: hdf5::file::OpenMode) -> hdf5::Result<hdf5::File> {
    hdf5::File::with_options().with_fapl(|p| p.file_locking(false)).open_as(path, mode)
}

fn h5err(e: hdf5::Error) -> SphError {
    SphError::Io(format!("particles.h5: {e}"))
}

/// Values per chunk (at most): 512 KiB of float64.
const CHUNK: usize = 65_536;
/// Deflate level: 4 is within a few per cent of 9 in size on these arrays, at a third of the time.
const DEFLATE: u8 = 1;

/// Running maxima per particle id, updated every step (not only at outputs): the peak particle
/// velocity |v| (m/s) and the peak pressure (Pa) each particle has had so far.
#[derive(Debug, Clone, Default)]
pub struct Peaks {
    /// Peak particle velocity (m/s) per id.
    pub ppv: Vec<f64>,
    /// Peak pressure (Pa) per id.
    pub p_peak: Vec<f64>,
}

impl Peaks {
    pub fn new(sim: &Sim) -> Peaks {
        let n = sim.p.nreal;
        let mut pk = Peaks { ppv: vec![0.0; n], p_peak: vec![f64::NEG_INFINITY; n] };
        pk.update(sim);
        pk
    }

    /// Folds the current state into the maxima (every step).
    pub(crate) fn update(&mut self, sim: &Sim) {
        let p = &sim.p;
        let d = p.dim;
        for i in 0..p.nreal {
            let id = p.id[i] as usize;
            let v2: f64 = (0..d).map(|a| p.v[a + d * i] * p.v[a + d * i]).sum();
            let v = v2.sqrt();
            if v > self.ppv[id] {
                self.ppv[id] = v;
            }
            if p.p[i] > self.p_peak[id] {
                self.p_peak[id] = p.p[i];
            }
        }
    }
}

/// One dataset of a step as the XDMF names it.
#[derive(Debug, Clone)]
struct Item {
    name: &'static str,
    /// "Float" or "Int".
    number: &'static str,
    precision: u8,
}

/// What one written step holds (for the XDMF).
#[derive(Debug, Clone)]
struct StepInfo {
    time: f64,
    n: usize,
    stress: bool,
    burn: bool,
    peaks: bool,
    /// The boundary-particle kinds (`bnd`: 0 ordinary, 1 integrated, 2 held).
    bnd: bool,
}

/// H5Part writer: one `Step#N` group per output, flushed after each (so a crash keeps what was
/// written), and the XDMF sidecar rewritten after each.
pub struct H5Part {
    file: hdf5::File,
    h5_name: String,
    xmf: Option<PathBuf>,
    dim: usize,
    written: Vec<StepInfo>,
    pub steps: usize,
    /// Steps written since the XDMF was last rewritten.
    xmf_dirty: bool,
    /// When the XDMF was last rewritten, and what that took (s).
    xmf_at: Option<std::time::Instant>,
    xmf_cost: f64,
}

impl H5Part {
    /// Creates `path` (refused when it exists: never written through a link); the XDMF sidecar
    /// goes beside it as `<stem>.xmf`.
    pub fn create(path: &Path) -> Result<H5Part> {
        let file = h5_file(path, hdf5::file::OpenMode::CreateExcl).map_err(h5err)?;
        let h5_name = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        Ok(H5Part {
            file,
            h5_name,
            xmf: Some(path.with_extension("xmf")),
            dim: 0,
            written: Vec::new(),
            steps: 0,
            xmf_dirty: false,
            xmf_at: None,
            xmf_cost: 0.0,
        })
    }

    /// Writes the real particles of `sim` as group `Step#<steps>` (with the running peaks, when
    /// given), then rewrites the XDMF.
    pub fn write(&mut self, sim: &Sim, peaks: Option<&Peaks>) -> Result<()> {
        let p = &sim.p;
        let n = p.nreal;
        let dim = p.dim;
        self.dim = dim;
        let g = self.file.create_group(&format!("Step#{}", self.steps)).map_err(h5err)?;
        let chunk = n.clamp(1, CHUNK);
        let put = |name: &str, data: &[f64]| put_data(&g, name, data, chunk);
        // a component that is zero by construction: declared, never written (no storage)
        let zero = |name: &str| put_zero(&g, name, n, chunk);
        let comp = |a: usize, src: &[f64]| -> Vec<f64> { (0..n).map(|i| src[a + dim * i]).collect() };
        for (a, name) in ["x", "y", "z"].iter().enumerate() {
            if a < dim { put(name, &comp(a, &p.x))? } else { zero(name)? }
        }
        for (a, name) in ["vx", "vy", "vz"].iter().enumerate() {
            if a < dim { put(name, &comp(a, &p.v))? } else { zero(name)? }
        }
        put("rho", &p.rho[..n])?;
        put("p", &p.p[..n])?;
        put("e", &p.e[..n])?;
        put("h", &p.h[..n])?;
        put("c", &p.c[..n])?;
        put("mass", &p.mass[..n])?;
        put_data(&g, "mat", &p.mat[..n], chunk)?;
        put_data(&g, "id", &p.id[..n], chunk)?;
        let stress = !p.tau.is_empty();
        if stress {
            // total stress sigma = -p I + tau (Pa), components xx yy zz xy xz yz
            let names = ["sxx", "syy", "szz", "sxy", "sxz", "syz"];
            for (q, name) in names.iter().enumerate() {
                // xz and yz vanish below 3D (plane strain: no shear out of the plane)
                if q >= 4 && dim < 3 {
                    zero(name)?;
                    continue;
                }
                let v: Vec<f64> = (0..n).map(|i| p.tau[q + NSTR * i] - if q < 3 { p.p[i] } else { 0.0 }).collect();
                put(name, &v)?;
            }
            // mean, von Mises and principal stresses (src/stress_invariants.rs)
            let inv = crate::stress_invariants::fields(&p.tau, &p.p, n, dim);
            for (name, v) in crate::stress_invariants::NAMES.iter().zip(&inv) {
                put(name, v)?;
            }
        }
        let burn = !p.burn.is_empty();
        if burn {
            put("burn", &p.burn[..n])?;
        }
        let bnd = !p.bnd.is_empty();
        if bnd {
            put_data(&g, "bnd", &p.bnd[..n], chunk)?;
        }
        if let Some(pk) = peaks {
            let by_index = |src: &[f64]| -> Vec<f64> { (0..n).map(|i| src[p.id[i] as usize]).collect() };
            put("ppv", &by_index(&pk.ppv))?;
            put("p_peak", &by_index(&pk.p_peak))?;
        }
        write_views(&self.file, self.steps, n, dim, stress)?;
        put_time(&g, sim.t)?;
        self.file.flush().map_err(h5err)?;
        self.steps += 1;
        self.written.push(StepInfo { time: sim.t, n, stress, burn, peaks: peaks.is_some(), bnd });
        self.xmf_dirty = true;
        let due = self.xmf_at.is_none_or(|t| t.elapsed().as_secs_f64() >= 10.0 * self.xmf_cost);
        if due { self.sync_xdmf() } else { Ok(()) }
    }

    /// Rewrites the XDMF sidecar when steps were written since its last rewrite (at a
    /// checkpoint and at the end of a run: the module doc).
    pub(crate) fn sync_xdmf(&mut self) -> Result<()> {
        if !self.xmf_dirty {
            return Ok(());
        }
        let t0 = std::time::Instant::now();
        self.write_xdmf()?;
        self.xmf_cost = t0.elapsed().as_secs_f64();
        self.xmf_at = Some(std::time::Instant::now());
        self.xmf_dirty = false;
        Ok(())
    }

    /// Rewrites the XDMF sidecar: a temporal collection of one polyvertex grid per step (through
    /// a temporary file renamed over it: never written through a link).
    fn write_xdmf(&self) -> Result<()> {
        let Some(path) = &self.xmf else { return Ok(()) };
        let text = xdmf_text(&self.h5_name, self.dim, &self.written);
        crate::rundir::write_atomic(path, text.as_bytes())
    }

    /// What a checkpoint keeps of the writer: the steps written (time, particles, which
    /// optional datasets).
    pub(crate) fn save(&self, b: &mut Blob) {
        b.put_f64("h5.time", &self.written.iter().map(|s| s.time).collect::<Vec<_>>());
        b.put("h5.n", checkpoint::Item::U64(self.written.iter().map(|s| s.n as u64).collect()));
        let flags = |s: &StepInfo| {
            u32::from(s.stress) | u32::from(s.burn) << 1 | u32::from(s.peaks) << 2 | u32::from(s.bnd) << 3
        };
        b.put("h5.flags", checkpoint::Item::U32(self.written.iter().map(flags).collect()));
        b.put("h5.dim", checkpoint::Item::U64(vec![self.dim as u64]));
    }

    /// Reopens the particles.h5 of a run at its checkpoint `b`: the steps written after the
    /// checkpoint (by a run killed later) are removed, and the XDMF rewritten to match, so the
    /// run continues the file as if it had never stopped.
    pub fn resume(path: &Path, b: &Blob) -> Result<H5Part> {
        let time = b.f64("h5.time")?;
        let n = b.u64("h5.n")?;
        let flags = b.u32("h5.flags")?;
        if n.len() != time.len() || flags.len() != time.len() {
            return Err(crate::error::input("checkpoint: the list of written steps is inconsistent"));
        }
        let written: Vec<StepInfo> = time
            .iter()
            .zip(&n)
            .zip(&flags)
            .map(|((&time, &n), &f)| StepInfo {
                time,
                n: n as usize,
                stress: f & 1 != 0,
                burn: f & 2 != 0,
                peaks: f & 4 != 0,
                bnd: f & 8 != 0,
            })
            .collect();
        let steps = written.len();
        let dim = usize::try_from(b.count("h5.dim")?).unwrap_or(0);
        let file = match cut_back(path, steps) {
            Ok(f) => f,
            Err(Cut::Missing(e)) => return Err(e),
            Err(Cut::Failed(e)) => {
                // a step written after the checkpoint was left half-written by a kill: copy the
                // steps the checkpoint needs into a new file
                rebuild(path, &written, dim).map_err(|e2| {
                    crate::error::input(format!(
                        "{e}; rebuilding it from its first {steps} steps failed too ({})",
                        e2.to_string().replace(&format!("{}: ", path.display()), "")
                    ))
                })?;
                eprintln!(
                    "warning: {} could not be cut back in place ({}); rebuilt from its first {steps} steps, the ones the checkpoint needs",
                    path.display(),
                    e.to_string().replace(&format!("{}: ", path.display()), "")
                );
                h5_file(path, hdf5::file::OpenMode::ReadWrite).map_err(h5err)?
            }
        };
        let h5_name = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let h = H5Part {
            file,
            h5_name,
            xmf: Some(path.with_extension("xmf")),
            dim,
            written,
            steps,
            xmf_dirty: false,
            xmf_at: None,
            xmf_cost: 0.0,
        };
        h.write_xdmf()?;
        Ok(h)
    }
}

/// Why a particles.h5 could not be cut back in place.
enum Cut {
    /// A step the checkpoint needs is missing: nothing to rebuild it from.
    Missing(SphError),
    /// HDF5 refused (a damaged later step): the file may be rebuilt.
    Failed(SphError),
}

/// Opens `path` for writing and removes the steps past the first `steps` (in /Step#k and
/// /xdmf/Step#k), checking that those `steps` are there.
fn cut_back(path: &Path, steps: usize) -> std::result::Result<hdf5::File, Cut> {
    let damaged =
        |e: hdf5::Error| Cut::Failed(crate::error::input(format!("{}: damaged or not HDF5 ({e})", path.display())));
    let file = h5_file(path, hdf5::file::OpenMode::ReadWrite).map_err(damaged)?;
    for k in 0..steps {
        if !file.link_exists(&format!("Step#{k}")) {
            return Err(Cut::Missing(crate::error::input(format!(
                "{}: Step#{k} is missing, the checkpoint needs {steps} steps written",
                path.display()
            ))));
        }
    }
    let later = |g: &hdf5::Group| -> std::result::Result<Vec<String>, Cut> {
        Ok(g.member_names()
            .map_err(damaged)?
            .into_iter()
            .filter(|m| m.strip_prefix("Step#").and_then(|k| k.parse::<usize>().ok()).is_some_and(|k| k >= steps))
            .collect())
    };
    for m in later(&file)? {
        file.unlink(&m).map_err(damaged)?;
    }
    if let Ok(x) = file.group("xdmf") {
        for m in later(&x)? {
            x.unlink(&m).map_err(damaged)?;
        }
    }
    file.flush().map_err(damaged)?;
    Ok(file)
}

/// A chunked, compressed 1D dataset `name` of `data` in `g` (the storage of the module doc).
fn put_data<T: hdf5::H5Type>(g: &hdf5::Group, name: &str, data: &[T], chunk: usize) -> Result<()> {
    g.new_dataset_builder()
        .chunk(chunk)
        .shuffle()
        .deflate(DEFLATE)
        .with_data(data)
        .create(name)
        .map(|_| ())
        .map_err(h5err)
}

/// A float64 dataset of `n` zeros by construction: declared with fill value 0, never written.
fn put_zero(g: &hdf5::Group, name: &str, n: usize, chunk: usize) -> Result<()> {
    g.new_dataset_builder()
        .empty::<f64>()
        .shape(n)
        .chunk(chunk)
        .fill_value(0.0f64)
        .create(name)
        .map(|_| ())
        .map_err(h5err)
}

/// The H5Part `TimeValue` attribute (s) of a step group.
fn put_time(g: &hdf5::Group, t: f64) -> Result<()> {
    let attr = g.new_attr::<f64>().create("TimeValue").map_err(h5err)?;
    attr.write_scalar(&t).map_err(h5err)
}

/// The interleaved views of step `step` (n particles) for the XDMF readers, in /xdmf/Step#N
/// (outside the H5Part groups, whose reader expects 1D datasets only): ParaView's Xdmf3 reader
/// (the one its OpenDataFile picks for .xmf) builds points and vectors only from (N, 3) arrays.
/// They are HDF5 virtual datasets: each column maps a 1D dataset of /Step#N, a column that is
/// zero by construction maps nothing (the fill value 0), so they store no data.
fn write_views(file: &hdf5::File, step: usize, n: usize, dim: usize, stress: bool) -> Result<()> {
    let top = match file.group("xdmf") {
        Ok(t) => t,
        Err(_) => file.create_group("xdmf").map_err(h5err)?,
    };
    let gx = top.create_group(&format!("Step#{step}")).map_err(h5err)?;
    let view = |name: &str, cols: &[Option<&str>]| -> Result<()> {
        let mut b = gx.new_dataset_builder().empty::<f64>().shape((n, cols.len())).fill_value(0.0f64);
        for (c, src) in cols.iter().enumerate() {
            if let Some(src) = src {
                b = b.virtual_map(".", format!("/Step#{step}/{src}"), n, .., (n, cols.len()), (.., c));
            }
        }
        b.create(name).map(|_| ()).map_err(h5err)
    };
    let live = |a: usize, name: &'static str| if a < dim { Some(name) } else { None };
    view("xyz", &[live(0, "x"), live(1, "y"), live(2, "z")])?;
    view("vxyz", &[live(0, "vx"), live(1, "vy"), live(2, "vz")])?;
    if stress {
        // 3 x 3, row by row: xx xy xz / xy yy yz / xz yz zz
        let xz = live(2, "sxz");
        let yz = live(2, "syz");
        view("stress", &[Some("sxx"), Some("sxy"), xz, Some("sxy"), Some("syy"), yz, xz, yz, Some("szz")])?;
    }
    Ok(())
}

/// Copies the first `written.len()` steps of the particles.h5 at `path` into a new file renamed
/// over it: for a file that cannot be cut back in place. A run killed while it wrote a step can
/// leave that step's object header unwritten while the root group already links it, and HDF5
/// then refuses to unlink it ("bad object header version number"); the steps before it are
/// intact. Values are copied exactly (a column zero by construction stays declared, unwritten).
fn rebuild(path: &Path, written: &[StepInfo], dim: usize) -> Result<()> {
    use hdf5::types::{FloatSize, IntSize, TypeDescriptor};
    let bad = |what: String| crate::error::input(format!("{}: {what}", path.display()));
    let src = h5_file(path, hdf5::file::OpenMode::Read).map_err(|e| bad(format!("damaged or not HDF5 ({e})")))?;
    let tmp = path.with_extension("h5.rebuild");
    crate::rundir::remove_stale(&tmp)?;
    {
        let dst = h5_file(&tmp, hdf5::file::OpenMode::CreateExcl).map_err(h5err)?;
        for (k, st) in written.iter().enumerate() {
            let name = format!("Step#{k}");
            let unreadable = |e: hdf5::Error| bad(format!("{name} cannot be read ({e})"));
            let g = src.group(&name).map_err(unreadable)?;
            let o = dst.create_group(&name).map_err(h5err)?;
            let chunk = st.n.clamp(1, CHUNK);
            for m in g.member_names().map_err(unreadable)? {
                let ds = g.dataset(&m).map_err(unreadable)?;
                if ds.size() != st.n {
                    return Err(bad(format!("{name}/{m} holds {} values, the checkpoint says {}", ds.size(), st.n)));
                }
                match ds.dtype().and_then(|t| t.to_descriptor()).map_err(unreadable)? {
                    TypeDescriptor::Float(FloatSize::U8) if ds.storage_size() == 0 => put_zero(&o, &m, st.n, chunk)?,
                    TypeDescriptor::Float(FloatSize::U8) => {
                        put_data(&o, &m, &ds.read_raw::<f64>().map_err(unreadable)?, chunk)?
                    }
                    TypeDescriptor::Integer(IntSize::U4) => {
                        put_data(&o, &m, &ds.read_raw::<i32>().map_err(unreadable)?, chunk)?
                    }
                    TypeDescriptor::Integer(IntSize::U8) => {
                        put_data(&o, &m, &ds.read_raw::<i64>().map_err(unreadable)?, chunk)?
                    }
                    t => return Err(bad(format!("{name}/{m}: a dataset of type {t:?}, not one blastsph writes"))),
                }
            }
            let t: f64 = g.attr("TimeValue").and_then(|a| a.read_scalar()).map_err(unreadable)?;
            put_time(&o, t)?;
            write_views(&dst, k, st.n, dim, st.stress)?;
        }
        dst.flush().map_err(h5err)?;
    }
    drop(src);
    std::fs::rename(&tmp, path).io_at(path.display())
}

/// A float64 dataset item.
const F8: fn(&'static str) -> Item = |name| Item { name, number: "Float", precision: 8 };

fn data_item(out: &mut String, indent: &str, h5: &str, step: usize, dims: &str, it: &Item) {
    // the interleaved arrays live in /xdmf/Step#N, the H5Part columns in /Step#N
    let group = if matches!(it.name, "xyz" | "vxyz" | "stress") { "xdmf/" } else { "" };
    let _ = writeln!(
        out,
        "{indent}<DataItem Dimensions=\"{dims}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{h5}:/{group}Step#{step}/{}</DataItem>",
        it.number, it.precision, it.name
    );
}

fn attribute(out: &mut String, h5: &str, step: usize, dims: &str, kind: &str, label: &str, it: &Item) {
    let _ = writeln!(out, "      <Attribute Name=\"{label}\" AttributeType=\"{kind}\" Center=\"Node\">");
    data_item(out, "        ", h5, step, dims, it);
    let _ = writeln!(out, "      </Attribute>");
}

/// The XDMF text for the steps written so far. It reads with both of ParaView's XDMF readers
/// (Xdmf3, which `OpenDataFile` picks for .xmf, and the older XDMF reader): the geometry is the
/// interleaved (N, 3) `xyz`, the velocity the (N, 3) `vxyz`, the stress the (N, 9) `stress`
/// (Xdmf3 reads neither the X_Y_Z geometry nor the JOIN function of the old format), and the
/// polyvertex cells list the particles by their `id` (a permutation of 0..N), so that every
/// particle is a vertex cell that ParaView draws.
fn xdmf_text(h5: &str, _dim: usize, steps: &[StepInfo]) -> String {
    let mut s = String::new();
    s += "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
    s += "<!-- written by blastsph beside particles.h5 after every output step: open this file in ParaView.\n";
    s += "     SI units: velocity (m/s) a 3-component vector, stress (Pa, total: -p I + deviator) a 3x3 tensor,\n";
    s += "     sigma_mean, von_mises, sigma_1 >= sigma_2 >= sigma_3 (Pa) the mean, von Mises and principal stresses,\n";
    s += "     ppv (m/s) and p_peak (Pa) the peak particle velocity and peak pressure of each particle so far. -->\n";
    s += "<Xdmf Version=\"2.0\">\n  <Domain>\n";
    s += "    <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (k, st) in steps.iter().enumerate() {
        let n = st.n;
        let n1 = format!("{n}");
        let _ = writeln!(s, "    <Grid Name=\"Step#{k}\" GridType=\"Uniform\">");
        let _ = writeln!(s, "      <Time Value=\"{:?}\"/>", st.time);
        let _ =
            writeln!(s, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{n}\" NodesPerElement=\"1\">");
        data_item(&mut s, "        ", h5, k, &n1, &Item { name: "id", number: "Int", precision: 8 });
        let _ = writeln!(s, "      </Topology>");
        let _ = writeln!(s, "      <Geometry GeometryType=\"XYZ\">");
        data_item(&mut s, "        ", h5, k, &format!("{n} 3"), &F8("xyz"));
        let _ = writeln!(s, "      </Geometry>");
        attribute(&mut s, h5, k, &format!("{n} 3"), "Vector", "velocity", &F8("vxyz"));
        if st.stress {
            attribute(&mut s, h5, k, &format!("{n} 9"), "Tensor", "stress", &F8("stress"));
            for name in crate::stress_invariants::NAMES {
                attribute(&mut s, h5, k, &n1, "Scalar", name, &F8(name));
            }
        }
        for name in ["rho", "p", "e", "h", "c", "mass"] {
            attribute(&mut s, h5, k, &n1, "Scalar", name, &F8(name));
        }
        attribute(&mut s, h5, k, &n1, "Scalar", "mat", &Item { name: "mat", number: "Int", precision: 4 });
        attribute(&mut s, h5, k, &n1, "Scalar", "id", &Item { name: "id", number: "Int", precision: 8 });
        if st.burn {
            attribute(&mut s, h5, k, &n1, "Scalar", "burn", &F8("burn"));
        }
        if st.bnd {
            attribute(&mut s, h5, k, &n1, "Scalar", "bnd", &Item { name: "bnd", number: "Int", precision: 4 });
        }
        if st.peaks {
            attribute(&mut s, h5, k, &n1, "Scalar", "ppv", &F8("ppv"));
            attribute(&mut s, h5, k, &n1, "Scalar", "p_peak", &F8("p_peak"));
        }
        let _ = writeln!(s, "    </Grid>");
    }
    s += "    </Grid>\n  </Domain>\n</Xdmf>\n";
    s
}

/// One step of one H5Part group, read back (for reports and tests).
#[derive(Debug, Clone, Default)]
pub struct Frame {
    pub time: f64,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Zeros below 3D.
    pub z: Vec<f64>,
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    /// Zeros below 3D.
    pub vz: Vec<f64>,
    pub rho: Vec<f64>,
    pub p: Vec<f64>,
    pub e: Vec<f64>,
    pub h: Vec<f64>,
    pub mass: Vec<f64>,
    pub mat: Vec<i32>,
    pub id: Vec<i64>,
    /// Peak particle velocity so far (m/s); empty in files written before it was recorded.
    pub ppv: Vec<f64>,
    /// Peak pressure so far (Pa); empty in files written before it was recorded.
    pub p_peak: Vec<f64>,
    /// Boundary-particle kind (0 ordinary, 1 integrated, 2 held); empty without boundary particles.
    pub bnd: Vec<i32>,
}

/// Opens a particles.h5 for reading and lists its `Step#N` groups by N (a file that cannot be
/// read is the input's fault, a damaged run directory: exit status 2).
pub(crate) fn open_steps(path: &Path) -> Result<(hdf5::File, Vec<(usize, String)>)> {
    let damaged =
        |e: hdf5::Error| crate::error::input(format!("{}: damaged or not an H5Part file ({e})", path.display()));
    let f = h5_file(path, hdf5::file::OpenMode::Read).map_err(damaged)?;
    let mut names: Vec<(usize, String)> = f
        .member_names()
        .map_err(damaged)?
        .into_iter()
        .filter_map(|n| n.strip_prefix("Step#").and_then(|k| k.parse().ok()).map(|k| (k, n.clone())))
        .collect();
    names.sort();
    Ok((f, names))
}

/// Reads the groups of a particles.h5, in step order.
pub fn read_frames(path: &Path) -> Result<Vec<Frame>> {
    let (f, names) = open_steps(path)?;
    let mut out = Vec::new();
    for (_, name) in names {
        let fr = read_group(&f, &name).map_err(|e| crate::error::input(format!("{}: {name}: {e}", path.display())))?;
        let n = fr.x.len();
        let lens = [
            fr.y.len(),
            fr.vx.len(),
            fr.vy.len(),
            fr.rho.len(),
            fr.p.len(),
            fr.e.len(),
            fr.h.len(),
            fr.mass.len(),
            fr.mat.len(),
            fr.id.len(),
        ];
        if lens.iter().any(|&l| l != n)
            || [fr.ppv.len(), fr.p_peak.len(), fr.bnd.len()].iter().any(|&l| l != 0 && l != n)
        {
            return Err(crate::error::input(format!(
                "{}: {name}: datasets of different lengths (damaged)",
                path.display()
            )));
        }
        out.push(fr);
    }
    Ok(out)
}

/// Reads the groups of a particles.h5 up to the last complete one: a last group that cannot be
/// read (a run killed while writing it) is left out and named in the second value.
pub(crate) fn read_complete_frames(path: &Path) -> Result<(Vec<Frame>, Option<String>)> {
    match read_frames(path) {
        Ok(f) => Ok((f, None)),
        Err(e) => {
            let (f, names) = open_steps(path)?;
            let mut out = Vec::new();
            for (k, (_, name)) in names.iter().enumerate() {
                match read_group(&f, name) {
                    Ok(fr) if fr.x.len() == fr.id.len() => out.push(fr),
                    _ if k + 1 == names.len() && k > 0 => {
                        return Ok((out, Some(format!("{name}, incomplete, left out"))));
                    }
                    _ => return Err(e),
                }
            }
            Err(e)
        }
    }
}

/// One `Step#N` group of an open particles.h5, read whole.
pub(crate) fn read_group(f: &hdf5::File, name: &str) -> Result<Frame> {
    let g = f.group(name).map_err(h5err)?;
    let rd = |n: &str| -> Result<Vec<f64>> { g.dataset(n).and_then(|d| d.read_raw::<f64>()).map_err(h5err) };
    let opt = |n: &str| -> Result<Vec<f64>> { if g.link_exists(n) { rd(n) } else { Ok(Vec::new()) } };
    Ok(Frame {
        time: g.attr("TimeValue").and_then(|a| a.read_scalar::<f64>()).map_err(h5err)?,
        x: rd("x")?,
        y: rd("y")?,
        z: rd("z")?,
        vx: rd("vx")?,
        vy: rd("vy")?,
        vz: rd("vz")?,
        rho: rd("rho")?,
        p: rd("p")?,
        e: rd("e")?,
        h: rd("h")?,
        mass: rd("mass")?,
        mat: g.dataset("mat").and_then(|d| d.read_raw::<i32>()).map_err(h5err)?,
        id: g.dataset("id").and_then(|d| d.read_raw::<i64>()).map_err(h5err)?,
        ppv: opt("ppv")?,
        p_peak: opt("p_peak")?,
        bnd: if g.link_exists("bnd") {
            g.dataset("bnd").and_then(|d| d.read_raw::<i32>()).map_err(h5err)?
        } else {
            Vec::new()
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A child process started while blastsph has an HDF5 file open inherits HDF5's descriptor;
    /// with HDF5's own lock that child held the file locked after blastsph closed it, and the next
    /// open failed ("unable to lock file, errno = 11": the parallel tests' intermittent failure).
    /// Without the lock the file opens again, for reading and for writing, while the child lives.
    #[test]
    fn a_child_started_while_a_file_is_open_does_not_lock_it() {
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("p.h5");
        let f = h5_file(&path, hdf5::file::OpenMode::CreateExcl).unwrap();
        f.new_dataset::<f64>().shape(3).create("x").unwrap().write_raw(&[1.0, 2.0, 3.0]).unwrap();
        let mut child = std::process::Command::new("sleep").arg("3").spawn().expect("sleep");
        drop(f);
        let r = h5_file(&path, hdf5::file::OpenMode::Read).expect("read while the child lives");
        let x: Vec<f64> = r.dataset("x").unwrap().read_raw().unwrap();
        assert_eq!(x, [1.0, 2.0, 3.0]);
        drop(r);
        h5_file(&path, hdf5::file::OpenMode::ReadWrite).expect("write while the child lives");
        let _ = child.kill();
        let _ = child.wait();
    }
}
