//! The revolved 3D points of an axisymmetric (RZ) run, for ParaView: `blastsph revolve DIR`.
//!
//! An RZ particle is a ring of radius r at height z (x = r, y = z in the run). Revolved over an
//! angle Θ (360° the whole body; 270° a cut-away that shows the inside) in N sectors, each ring
//! becomes N points (r cos θ_k, r sin θ_k, z), θ_k = (k + ½) Θ/N (m), z up; the velocity
//! (v_r, v_z) becomes (v_r cos θ_k, v_r sin θ_k, v_z) (m/s); ρ, p, e, h and the material are the
//! ring's, the mass is the ring's share m Θ/(2π N) (kg), and the point's id is id N + k. The
//! file pair `revolved.h5` (one group `Step#n` per output step of particles.h5, with the arrays
//! ParaView's XDMF readers take: `xyz` and `vxyz` (M, 3), the scalars (M)) and `revolved.xmf`
//! (a temporal collection of polyvertex grids) goes beside the run's own files.

use crate::error::{IoAt, Result, SphError, input};
use crate::output::{Frame, read_group};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn h5err(e: hdf5::Error) -> SphError {
    SphError::Io(format!("revolved.h5: {e}"))
}

/// Writes `revolved.h5` and `revolved.xmf` in the run directory `dir`; returns the .xmf's path.
/// Refused (one line, exit 2) for a run that is not axisymmetric, a sector count outside
/// 1..=720 or an angle outside (0, 360] degrees, and when the files exist.
pub fn revolve(dir: &Path, sectors: usize, angle_deg: f64) -> Result<PathBuf> {
    if !(1..=720).contains(&sectors) {
        return Err(input(format!("--sectors {sectors}: from 1 to 720")));
    }
    if !(angle_deg.is_finite() && angle_deg > 0.0 && angle_deg <= 360.0) {
        return Err(input(format!("--angle {angle_deg}: degrees, in (0, 360]")));
    }
    let _lock = crate::rundir::lock_read(dir, "revolve")?;
    let (case, _) = crate::report::load_case(dir)?;
    if !case.axisymmetric() {
        return Err(input(format!(
            "{}: not an axisymmetric run (geometry = \"axisymmetric\"): nothing to revolve",
            dir.display()
        )));
    }
    let path = dir.join("particles.h5");
    let damaged = |e: hdf5::Error| input(format!("{}: damaged or not an H5Part file ({e})", path.display()));
    let (src, names) = crate::output::open_steps(&path)?;
    if names.is_empty() {
        return Err(input(format!("{}: particles.h5 holds no output step", dir.display())));
    }
    // the memory one revolved step takes while it is written, before anything is: the rings of
    // the largest step times the sectors (a million rings at 720 sectors asked for 17 GB at once)
    let rings = names
        .iter()
        .map(|(_, n)| src.group(n).and_then(|g| g.dataset("x")).map(|d| d.size()))
        .collect::<std::result::Result<Vec<usize>, _>>()
        .map_err(damaged)?;
    let most = rings.iter().copied().max().unwrap_or(0);
    let need = (most * sectors) as f64 * POINT_BYTES + most as f64 * RING_BYTES;
    let (limit, from) = crate::case::size::memory_limit();
    if need > limit {
        let fit = ((limit - most as f64 * RING_BYTES) / (most as f64 * POINT_BYTES)).floor().max(0.0);
        return Err(input(format!(
            "--sectors {sectors}: {most} rings make {} points a step, about {} of memory while a step is written, more than {} ({from}): at most {fit} sectors here",
            most * sectors,
            crate::case::size::bytes_text(need),
            crate::case::size::bytes_text(limit)
        )));
    }
    let h5 = dir.join("revolved.h5");
    let xmf = dir.join("revolved.xmf");
    for p in [&h5, &xmf] {
        if p.exists() {
            return Err(input(format!("{}: exists (remove it to revolve again)", p.display())));
        }
    }
    // written under a temporary name, renamed when complete (a revolve that was killed left a
    // revolved.h5 that refused the next one)
    let tmp = dir.join("revolved.h5.part");
    crate::rundir::remove_stale(&tmp)?;
    let file = crate::output::h5_file(&tmp, hdf5::file::OpenMode::CreateExcl).map_err(h5err)?;
    let theta = angle_deg.to_radians();
    let mut steps = Vec::new();
    // one output step at a time
    for (k, (_, name)) in names.iter().enumerate() {
        let f = read_group(&src, name).map_err(|e| input(format!("{}: {name}: {e}", path.display())))?;
        let m = write_step(&file, k, &f, sectors, theta)?;
        steps.push((f.time, m));
    }
    file.flush().map_err(h5err)?;
    drop(file);
    std::fs::rename(&tmp, &h5).io_at(h5.display())?;
    crate::rundir::write_atomic(&xmf, xdmf("revolved.h5", &steps).as_bytes())?;
    Ok(xmf)
}

/// Bytes a revolved point takes while its step is written (the arrays of `write_step`: xyz and
/// vxyz 48, the five scalars 40, mat, id and cell 20, with a margin for HDF5's chunk buffers).
const POINT_BYTES: f64 = 128.0;
/// Bytes a ring of the run takes in the step read from particles.h5 (its 16 arrays).
const RING_BYTES: f64 = 128.0;

/// One output step, revolved: returns the number of points written.
fn write_step(file: &hdf5::File, k: usize, f: &Frame, sectors: usize, theta: f64) -> Result<usize> {
    let n = f.x.len();
    let m = n * sectors;
    let (mut xyz, mut vxyz) = (Vec::with_capacity(3 * m), Vec::with_capacity(3 * m));
    let mut id = Vec::with_capacity(m);
    let rep = |a: &[f64]| -> Vec<f64> { a.iter().flat_map(|&v| std::iter::repeat_n(v, sectors)).collect() };
    let (cs, sn): (Vec<f64>, Vec<f64>) = (0..sectors)
        .map(|s| {
            let t = (s as f64 + 0.5) * theta / sectors as f64;
            (t.cos(), t.sin())
        })
        .unzip();
    for i in 0..n {
        for s in 0..sectors {
            xyz.extend_from_slice(&[f.x[i] * cs[s], f.x[i] * sn[s], f.y[i]]);
            vxyz.extend_from_slice(&[f.vx[i] * cs[s], f.vx[i] * sn[s], f.vy[i]]);
            id.push(f.id[i] * sectors as i64 + s as i64);
        }
    }
    let share = theta / (2.0 * std::f64::consts::PI * sectors as f64);
    let mass: Vec<f64> = rep(&f.mass).into_iter().map(|v| v * share).collect();
    let mat: Vec<i32> = f.mat.iter().flat_map(|&v| std::iter::repeat_n(v, sectors)).collect();
    let cell: Vec<i64> = (0..m as i64).collect();
    let g = file.create_group(&format!("Step#{k}")).map_err(h5err)?;
    // (m, 3), row by row; everything chunked and compressed (a ring's values repeat N times)
    let chunk = m.clamp(1, 65_536);
    let put2 = |name: &str, a: &[f64]| -> Result<()> {
        let ds =
            g.new_dataset::<f64>().shape((m, 3)).chunk((chunk, 3)).shuffle().deflate(1).create(name).map_err(h5err)?;
        ds.write_raw(a).map_err(h5err)
    };
    put2("xyz", &xyz)?;
    put2("vxyz", &vxyz)?;
    let put = |name: &str, a: &[f64]| -> Result<()> {
        g.new_dataset_builder().chunk(chunk).shuffle().deflate(1).with_data(a).create(name).map(|_| ()).map_err(h5err)
    };
    put("rho", &rep(&f.rho))?;
    put("p", &rep(&f.p))?;
    put("e", &rep(&f.e))?;
    put("h", &rep(&f.h))?;
    put("mass", &mass)?;
    g.new_dataset_builder().chunk(chunk).shuffle().deflate(1).with_data(&mat).create("mat").map_err(h5err)?;
    g.new_dataset_builder().chunk(chunk).shuffle().deflate(1).with_data(&id).create("id").map_err(h5err)?;
    g.new_dataset_builder().chunk(chunk).shuffle().deflate(1).with_data(&cell).create("cell").map_err(h5err)?;
    let attr = g.new_attr::<f64>().create("TimeValue").map_err(h5err)?;
    attr.write_scalar(&f.time).map_err(h5err)?;
    Ok(m)
}

/// The XDMF text of the revolved steps (time, points).
fn xdmf(h5: &str, steps: &[(f64, usize)]) -> String {
    let mut s = String::new();
    s += "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n";
    s += "<!-- written by `blastsph revolve`: the rings of an axisymmetric run revolved about the axis (z up);\n";
    s += "     SI units; mass is each point's share of its ring. Open this file in ParaView. -->\n";
    s += "<Xdmf Version=\"2.0\">\n  <Domain>\n";
    s += "    <Grid Name=\"revolved\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    let item = |s: &mut String, k: usize, dims: &str, name: &str, num: &str, prec: u8| {
        let _ = writeln!(
            s,
            "        <DataItem Dimensions=\"{dims}\" NumberType=\"{num}\" Precision=\"{prec}\" Format=\"HDF\">{h5}:/Step#{k}/{name}</DataItem>"
        );
    };
    for (k, &(t, m)) in steps.iter().enumerate() {
        let _ = writeln!(s, "    <Grid Name=\"Step#{k}\" GridType=\"Uniform\">");
        let _ = writeln!(s, "      <Time Value=\"{t:?}\"/>");
        let _ =
            writeln!(s, "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{m}\" NodesPerElement=\"1\">");
        item(&mut s, k, &m.to_string(), "cell", "Int", 8);
        s += "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n";
        item(&mut s, k, &format!("{m} 3"), "xyz", "Float", 8);
        s += "      </Geometry>\n";
        let _ = writeln!(s, "      <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">");
        item(&mut s, k, &format!("{m} 3"), "vxyz", "Float", 8);
        s += "      </Attribute>\n";
        for (name, num, prec) in [
            ("rho", "Float", 8),
            ("p", "Float", 8),
            ("e", "Float", 8),
            ("h", "Float", 8),
            ("mass", "Float", 8),
            ("mat", "Int", 4),
            ("id", "Int", 8),
        ] {
            let _ = writeln!(s, "      <Attribute Name=\"{name}\" AttributeType=\"Scalar\" Center=\"Node\">");
            item(&mut s, k, &m.to_string(), name, num, prec);
            s += "      </Attribute>\n";
        }
        s += "    </Grid>\n";
    }
    s += "    </Grid>\n  </Domain>\n</Xdmf>\n";
    s
}
