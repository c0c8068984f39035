//! Run-directory output (DESIGN.md contracts): `particles.h5` in the H5Part layout that ParaView
//! opens directly (groups `Step#N` of equal-length 1D datasets and a float64 `TimeValue`
//! attribute), `gauges.csv`, and `summary.json`.

use crate::error::{Result, SphError};
use crate::modules::param::NSTR;
use crate::sim::Sim;
use std::io::Write;
use std::path::Path;

fn h5err(e: hdf5::Error) -> SphError {
    SphError::Io(format!("particles.h5: {e}"))
}

/// H5Part writer: one `Step#N` group per output, flushed after each so a crash keeps what was
/// written.
pub struct H5Part {
    file: hdf5::File,
    pub steps: usize,
}

impl H5Part {
    pub fn create(path: &Path) -> Result<H5Part> {
        let file = hdf5::File::create(path).map_err(h5err)?;
        Ok(H5Part { file, steps: 0 })
    }

    /// Writes the real particles of `sim` as group `Step#<steps>`.
    pub fn write(&mut self, sim: &Sim) -> Result<()> {
        let p = &sim.p;
        let n = p.nreal;
        let dim = p.dim;
        let g = self.file.create_group(&format!("Step#{}", self.steps)).map_err(h5err)?;
        let comp = |a: usize, src: &[f64]| -> Vec<f64> {
            if a < dim { (0..n).map(|i| src[a + dim * i]).collect() } else { vec![0.0; n] }
        };
        let put = |name: &str, data: &[f64]| -> Result<()> {
            g.new_dataset_builder().with_data(data).create(name).map(|_| ()).map_err(h5err)
        };
        for (a, name) in ["x", "y", "z"].iter().enumerate() {
            put(name, &comp(a, &p.x))?;
        }
        for (a, name) in ["vx", "vy", "vz"].iter().enumerate() {
            put(name, &comp(a, &p.v))?;
        }
        put("rho", &p.rho[..n])?;
        put("p", &p.p[..n])?;
        put("e", &p.e[..n])?;
        put("h", &p.h[..n])?;
        put("c", &p.c[..n])?;
        put("mass", &p.mass[..n])?;
        g.new_dataset_builder().with_data(&p.mat[..n]).create("mat").map_err(h5err)?;
        g.new_dataset_builder().with_data(&p.id[..n]).create("id").map_err(h5err)?;
        if !p.tau.is_empty() {
            // total stress sigma = -p I + tau (Pa)
            let names = ["sxx", "syy", "szz", "sxy", "sxz", "syz"];
            for (q, name) in names.iter().enumerate() {
                let v: Vec<f64> = (0..n).map(|i| p.tau[q + NSTR * i] - if q < 3 { p.p[i] } else { 0.0 }).collect();
                put(name, &v)?;
            }
        }
        if !p.burn.is_empty() {
            put("burn", &p.burn[..n])?;
        }
        let attr = g.new_attr::<f64>().create("TimeValue").map_err(h5err)?;
        attr.write_scalar(&sim.t).map_err(h5err)?;
        self.file.flush().map_err(h5err)?;
        self.steps += 1;
        Ok(())
    }
}

/// One step of one H5Part group, read back (for reports and tests).
#[derive(Debug, Clone, Default)]
pub struct Frame {
    pub time: f64,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    pub rho: Vec<f64>,
    pub p: Vec<f64>,
    pub e: Vec<f64>,
    pub h: Vec<f64>,
    pub mass: Vec<f64>,
    pub mat: Vec<i32>,
    pub id: Vec<i64>,
}

/// Reads the groups of a particles.h5, in step order.
pub fn read_frames(path: &Path) -> Result<Vec<Frame>> {
    let f = hdf5::File::open(path).map_err(|e| SphError::Io(format!("{}: {e}", path.display())))?;
    let mut names: Vec<(usize, String)> = f
        .member_names()
        .map_err(h5err)?
        .into_iter()
        .filter_map(|n| n.strip_prefix("Step#").and_then(|k| k.parse().ok()).map(|k| (k, n.clone())))
        .collect();
    names.sort();
    let mut out = Vec::new();
    for (_, name) in names {
        out.push(read_group(&f, &name)?);
    }
    Ok(out)
}

fn read_group(f: &hdf5::File, name: &str) -> Result<Frame> {
    let g = f.group(name).map_err(h5err)?;
    let rd = |n: &str| -> Result<Vec<f64>> { g.dataset(n).and_then(|d| d.read_raw::<f64>()).map_err(h5err) };
    Ok(Frame {
        time: g.attr("TimeValue").and_then(|a| a.read_scalar::<f64>()).map_err(h5err)?,
        x: rd("x")?,
        y: rd("y")?,
        vx: rd("vx")?,
        vy: rd("vy")?,
        rho: rd("rho")?,
        p: rd("p")?,
        e: rd("e")?,
        h: rd("h")?,
        mass: rd("mass")?,
        mat: g.dataset("mat").and_then(|d| d.read_raw::<i32>()).map_err(h5err)?,
        id: g.dataset("id").and_then(|d| d.read_raw::<i64>()).map_err(h5err)?,
    })
}

/// Gauges: the real particle nearest each gauge point at t = 0, recorded every step.
pub struct Gauges {
    pub names: Vec<String>,
    pub points: Vec<Vec<f64>>,
    pub particle: Vec<usize>,
    file: Option<std::io::BufWriter<std::fs::File>>,
    /// Peak pressure (Pa) and its time (s) per gauge.
    pub peak: Vec<(f64, f64)>,
    /// (time s, pressure Pa) of every step, per gauge.
    pub record: Vec<Vec<(f64, f64)>>,
}

impl Gauges {
    pub fn new(sim: &Sim, path: Option<&Path>) -> Result<Gauges> {
        let dim = sim.cfg.dim;
        let n = sim.p.nreal;
        let mut particle = Vec::new();
        let mut names = Vec::new();
        let mut points = Vec::new();
        for g in &sim.case.gauges {
            let mut best = (f64::INFINITY, 0usize);
            for i in 0..n {
                let r2: f64 = (0..dim).map(|d| (sim.p.x[d + dim * i] - g.point_m[d]).powi(2)).sum();
                if r2 < best.0 {
                    best = (r2, i);
                }
            }
            particle.push(best.1);
            names.push(g.name.clone());
            points.push(g.point_m.clone());
        }
        let file = match path {
            Some(p) if !names.is_empty() => {
                let mut f = std::io::BufWriter::new(
                    std::fs::File::create(p).map_err(|e| SphError::Io(format!("{}: {e}", p.display())))?,
                );
                let mut head = String::from("time_s");
                for nme in &names {
                    head += &format!(",{nme}_p_pa");
                }
                writeln!(f, "{head}").map_err(|e| SphError::Io(e.to_string()))?;
                let mut l2 = String::from("# particle");
                for (k, &i) in particle.iter().enumerate() {
                    let pos: Vec<String> = (0..dim).map(|d| format!("{:.4}", sim.p.x[d + dim * i])).collect();
                    l2 += &format!(
                        ",{} id {} at [{}] m (gauge point {:?})",
                        names[k],
                        sim.p.id[i],
                        pos.join(" "),
                        points[k]
                    );
                }
                writeln!(f, "{l2}").map_err(|e| SphError::Io(e.to_string()))?;
                Some(f)
            }
            _ => None,
        };
        let ng = names.len();
        Ok(Gauges {
            names,
            points,
            particle,
            file,
            peak: vec![(f64::NEG_INFINITY, 0.0); ng],
            record: vec![Vec::new(); ng],
        })
    }

    pub fn sample(&mut self, sim: &Sim) -> Result<()> {
        if self.names.is_empty() {
            return Ok(());
        }
        let mut line = format!("{:.9e}", sim.t);
        for (k, &i0) in self.particle.iter().enumerate() {
            // particle i0 at t = 0 is id i0; it may have moved in memory
            let i = sim.index_of_id[i0] as usize;
            let p = sim.p.p[i];
            line += &format!(",{p:.6e}");
            if p > self.peak[k].0 {
                self.peak[k] = (p, sim.t);
            }
            self.record[k].push((sim.t, p));
        }
        if let Some(f) = self.file.as_mut() {
            writeln!(f, "{line}").map_err(|e| SphError::Io(e.to_string()))?;
        }
        Ok(())
    }

    pub fn flush(&mut self) {
        if let Some(f) = self.file.as_mut() {
            let _ = f.flush();
        }
    }

    /// Arrival time: the first time the pressure exceeds half the gauge's peak (s).
    pub fn arrival(&self, k: usize) -> f64 {
        let half = 0.5 * self.peak[k].0;
        self.record[k].iter().find(|(_, p)| *p >= half && half > 0.0).map(|(t, _)| *t).unwrap_or(f64::NAN)
    }
}
