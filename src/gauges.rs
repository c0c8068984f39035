//! Gauges (`[[gauge]]`, docs/reference/cases.md): pressure, velocity and stress at a point of the ground,
//! every step, into `gauges.csv`; peak, arrival, impulse and peak particle velocity into
//! summary.json.
//!
//! Two kinds:
//! - `particle` (Lagrangian, the default): the real particle nearest `point_m` at t = 0, followed
//!   as it moves. The point often lies half-way between lattice sites (four particles at one
//!   distance): distances within 1e-6 of the finest spacing count as equal, and among equals the
//!   particle generated first wins (lowest id: regions in file order, then lattice order, lowest
//!   z, then y, then x). The choice is then the same after an exact rescaling of the case.
//! - `point` (Eulerian): the fixed point, values by the Shepard-normalised SPH interpolation
//!   f(x) = Σ_j V_j f_j W(|x − x_j|, h_j) / Σ_j V_j W(|x − x_j|, h_j), V_j = m_j/ρ_j (axisymmetric:
//!   the area m_j/(2π r_j ρ_j) in the r-z plane), over the real particles of every material (thesis (2-7), normalised so a point near a free surface or an
//!   interface is not under-read). A point with no particle within reach (in a void) records
//!   nothing for that step (an empty field in gauges.csv).
//!
//! Quantities: p (Pa), velocity components (m/s), total stress σ = −p I + τ (Pa; only in cases
//! with strength): 1D xx; 2D xx, yy, zz, xy; 3D all six. In 2D and 3D with strength, also the
//! stress invariants of [`crate::stress_invariants`] (mean stress, von Mises, σ1 ≥ σ2 ≥ σ3; Pa),
//! computed from the recorded components when a line is written (outside the twins).

use crate::case::{GaugeCfg, GaugeKind, KernelKind};
use crate::error::{IoAt, Result, SphError};
use crate::modules::param::NSTR;
use crate::sim::Sim;
use crate::sim::checkpoint::{Blob, Item};
// the invariant columns after a gauge's stress components (2D and 3D with strength) carry the
// names of the per-particle fields
use crate::stress_invariants::NAMES as INVARIANTS;
use serde_json::{Value, json};
use std::io::Write;
use std::path::Path;

/// W(r, h) of the case's kernel (m^-d). The one place the gauges reach into the solver's
/// modules: `blastsph::modules::kernel::w_dw` (the gradient it also returns is not used).
fn kernel_w(dim: usize, kind: KernelKind, r: f64, dx: &[f64], h: f64) -> f64 {
    let mut g = [0.0; 3];
    crate::modules::kernel::w_dw(dim, kind, r, dx, h, &mut g[..dim])
}

/// Stress components recorded for a dimension (indices into the NSTR layout xx yy zz xy xz yz).
fn stress_components(dim: usize) -> &'static [(usize, &'static str)] {
    match dim {
        1 => &[(0, "sxx")],
        2 => &[(0, "sxx"), (1, "syy"), (2, "szz"), (3, "sxy")],
        _ => &[(0, "sxx"), (1, "syy"), (2, "szz"), (3, "sxy"), (4, "sxz"), (5, "syz")],
    }
}

const VNAMES: [&str; 3] = ["vx", "vy", "vz"];

/// The invariants of the stress components `s` recorded in `dim` (2D: xx, yy, zz, xy, the
/// out-of-plane shears zero; 3D: all six; Pa): None in 1D, where only xx is recorded.
pub fn invariants_of(dim: usize, s: &[f64]) -> Option<crate::stress_invariants::Invariants> {
    match (dim, s) {
        (2, &[xx, yy, zz, xy, ..]) => Some(crate::stress_invariants::of([xx, yy, zz, xy, 0.0, 0.0])),
        (3, &[xx, yy, zz, xy, xz, yz, ..]) => Some(crate::stress_invariants::of([xx, yy, zz, xy, xz, yz])),
        _ => None,
    }
}

/// One gauge's reading at one step: p, velocity (dim), stress (as recorded); None in a void.
type Reading = Option<Vec<f64>>;

/// The gauges of a run.
pub struct Gauges {
    pub names: Vec<String>,
    pub cfg: Vec<GaugeCfg>,
    /// For particle gauges: the followed particle's id; for point gauges: None.
    pub particle: Vec<Option<usize>>,
    /// For particle gauges: how many particles were at the nearest distance (1 = no tie).
    pub tied: Vec<usize>,
    /// Initial position of the followed particle (particle gauges).
    pub start_m: Vec<Vec<f64>>,
    dim: usize,
    stress: bool,
    file: Option<std::io::BufWriter<std::fs::File>>,
    /// (time s, reading) of every step, per gauge.
    pub record: Vec<Vec<(f64, Reading)>>,
}

impl Gauges {
    pub fn new(sim: &Sim, path: Option<&Path>) -> Result<Gauges> {
        let dim = sim.cfg.dim;
        let n = sim.p.nreal;
        let tol = 1e-6 * sim.cfg.dx_min;
        let mut g = Gauges {
            names: Vec::new(),
            cfg: sim.case.gauges.clone(),
            particle: Vec::new(),
            tied: Vec::new(),
            start_m: Vec::new(),
            dim,
            stress: !sim.p.tau.is_empty(),
            file: None,
            record: vec![Vec::new(); sim.case.gauges.len()],
        };
        for gc in &sim.case.gauges {
            g.names.push(gc.name.clone());
            match gc.kind {
                GaugeKind::Particle => {
                    let dist = |i: usize| -> f64 {
                        (0..dim).map(|d| (sim.p.x[d + dim * i] - gc.point_m[d]).powi(2)).sum::<f64>().sqrt()
                    };
                    let best = (0..n).map(dist).fold(f64::INFINITY, f64::min);
                    // among the particles at the nearest distance, the lowest id
                    let ties: Vec<usize> = (0..n).filter(|&i| dist(i) <= best + tol).collect();
                    let pick = ties.iter().copied().min_by_key(|&i| sim.p.id[i]).unwrap_or(0);
                    g.particle.push(Some(sim.p.id[pick] as usize));
                    g.tied.push(ties.len());
                    g.start_m.push((0..dim).map(|d| sim.p.x[d + dim * pick]).collect());
                }
                GaugeKind::Point => {
                    g.particle.push(None);
                    g.tied.push(0);
                    g.start_m.push(gc.point_m.clone());
                }
            }
        }
        if let Some(p) = path
            && !g.names.is_empty()
        {
            let mut f = std::io::BufWriter::new(crate::rundir::create_new(p)?);
            writeln!(f, "{}", g.columns().join(",")).map_err(|e| SphError::Io(e.to_string()))?;
            g.file = Some(f);
        }
        Ok(g)
    }

    /// What a checkpoint keeps of the gauges: the particles they follow and every reading so far
    /// (summary.json's measures are taken over the whole record).
    pub fn save(&self, b: &mut Blob) {
        b.put("gauges.particle", Item::I64(self.particle.iter().map(|p| p.map_or(-1, |i| i as i64)).collect()));
        b.put("gauges.tied", Item::U64(self.tied.iter().map(|&t| t as u64).collect()));
        b.put_f64("gauges.start_m", &self.start_m.concat());
        for (k, rec) in self.record.iter().enumerate() {
            b.put_f64(&format!("gauges.{k}.t"), &rec.iter().map(|r| r.0).collect::<Vec<_>>());
            b.put(&format!("gauges.{k}.some"), Item::U32(rec.iter().map(|r| u32::from(r.1.is_some())).collect()));
            b.put_f64(&format!("gauges.{k}.q"), &rec.iter().filter_map(|r| r.1.clone()).collect::<Vec<_>>().concat());
        }
    }

    /// The gauges of a run resumed from checkpoint `b`, appending to `path` (gauges.csv, already
    /// cut back to its length at the checkpoint).
    pub fn resume(sim: &Sim, path: Option<&Path>, b: &Blob) -> Result<Gauges> {
        let bad = |w: &str| crate::error::input(format!("checkpoint: gauges: {w}"));
        let ng = sim.case.gauges.len();
        let dim = sim.cfg.dim;
        let stress = !sim.p.tau.is_empty();
        let particle = b.i64("gauges.particle")?;
        let tied = b.u64("gauges.tied")?;
        let start = b.f64("gauges.start_m")?;
        if particle.len() != ng || tied.len() != ng || start.len() != ng * dim {
            return Err(bad(&format!("{} gauges in the checkpoint, {ng} in the case", particle.len())));
        }
        let width = 1 + dim + if stress { stress_components(dim).len() } else { 0 };
        let mut record = Vec::with_capacity(ng);
        for k in 0..ng {
            let t = b.f64(&format!("gauges.{k}.t"))?;
            let some = b.u32(&format!("gauges.{k}.some"))?;
            let q = b.f64(&format!("gauges.{k}.q"))?;
            let nsome = some.iter().filter(|&&s| s != 0).count();
            if some.len() != t.len() || q.len() != nsome * width {
                return Err(bad(&format!("the record of gauge {k} is inconsistent")));
            }
            let mut vals = q.chunks_exact(width);
            record.push(
                t.iter()
                    .zip(&some)
                    .map(|(&t, &s)| (t, if s != 0 { vals.next().map(|v| v.to_vec()) } else { None }))
                    .collect(),
            );
        }
        let n = sim.p.nreal;
        let mut particles = Vec::with_capacity(ng);
        for &p in &particle {
            particles.push(match p {
                -1 => None,
                p if p >= 0 && (p as usize) < n => Some(p as usize),
                _ => return Err(bad("a followed particle out of range")),
            });
        }
        let file = match path {
            Some(p) if ng > 0 => Some(std::io::BufWriter::new(crate::rundir::open_append(p)?)),
            _ => None,
        };
        Ok(Gauges {
            names: sim.case.gauges.iter().map(|g| g.name.clone()).collect(),
            cfg: sim.case.gauges.clone(),
            particle: particles,
            tied: tied.iter().map(|&t| t as usize).collect(),
            start_m: start.chunks_exact(dim.max(1)).map(|c| c.to_vec()).collect(),
            dim,
            stress,
            file,
            record,
        })
    }

    /// The header of gauges.csv: time_s, every gauge's pressure (as before this file recorded
    /// more), then per gauge its velocity components and stress components.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec!["time_s".to_string()];
        for n in &self.names {
            c.push(format!("{n}_p_pa"));
        }
        for n in &self.names {
            for v in &VNAMES[..self.dim] {
                c.push(format!("{n}_{v}_ms"));
            }
            if self.stress {
                for (_, s) in stress_components(self.dim) {
                    c.push(format!("{n}_{s}_pa"));
                }
                if self.dim > 1 {
                    c.extend(INVARIANTS.iter().map(|s| format!("{n}_{s}_pa")));
                }
            }
        }
        c
    }

    fn read(&self, sim: &Sim, k: usize) -> Reading {
        let p = &sim.p;
        let dim = self.dim;
        let comps = stress_components(dim);
        let quantity = |i: usize| -> Vec<f64> {
            let mut q = Vec::with_capacity(1 + dim + comps.len());
            q.push(p.p[i]);
            q.extend((0..dim).map(|a| p.v[a + dim * i]));
            if self.stress {
                for &(c, _) in comps {
                    q.push(p.tau[c + NSTR * i] - if c < 3 { p.p[i] } else { 0.0 });
                }
            }
            q
        };
        match self.particle[k] {
            Some(id) => Some(quantity(sim.index_of_id[id] as usize)),
            None => {
                let x0 = &self.cfg[k].point_m;
                let kind = sim.cfg.kernel;
                let reach = kind.support();
                let rz = sim.case.axisymmetric();
                let mut sum: Vec<f64> = Vec::new();
                let mut wsum = 0.0;
                let mut dx = [0.0; 3];
                for j in 0..p.nreal {
                    let h = p.h[j];
                    let mut r2 = 0.0;
                    for a in 0..dim {
                        dx[a] = x0[a] - p.x[a + dim * j];
                        r2 += dx[a] * dx[a];
                    }
                    if r2 >= (reach * h) * (reach * h) {
                        continue;
                    }
                    // the particle's volume; axisymmetric: its area in the r-z plane, m/(2π r ρ)
                    let vol = if rz {
                        p.mass[j] / (2.0 * std::f64::consts::PI * p.x[dim * j].abs().max(0.25 * h) * p.rho[j])
                    } else {
                        p.mass[j] / p.rho[j]
                    };
                    let w = vol * kernel_w(dim, kind, r2.sqrt(), &dx[..dim], h);
                    if w <= 0.0 {
                        continue;
                    }
                    let q = quantity(j);
                    if sum.is_empty() {
                        sum = vec![0.0; q.len()];
                    }
                    for (s, v) in sum.iter_mut().zip(&q) {
                        *s += w * v;
                    }
                    wsum += w;
                }
                if wsum > 0.0 { Some(sum.into_iter().map(|s| s / wsum).collect()) } else { None }
            }
        }
    }

    /// Records every gauge at the current step (and writes a line of gauges.csv).
    pub fn sample(&mut self, sim: &Sim) -> Result<()> {
        if self.names.is_empty() {
            return Ok(());
        }
        let readings: Vec<Reading> = (0..self.names.len()).map(|k| self.read(sim, k)).collect();
        if let Some(f) = self.file.as_mut() {
            let mut line = format!("{:.9e}", sim.t);
            for r in &readings {
                match r {
                    Some(q) => line += &format!(",{:.6e}", q[0]),
                    None => line += ",",
                }
            }
            let width = self.dim + if self.stress { stress_components(self.dim).len() } else { 0 };
            let extra = if self.stress && self.dim > 1 { INVARIANTS.len() } else { 0 };
            for r in &readings {
                for c in 0..width {
                    match r {
                        Some(q) => line += &format!(",{:.6e}", q[1 + c]),
                        None => line += ",",
                    }
                }
                let inv = r.as_ref().and_then(|q| invariants_of(self.dim, &q[1 + self.dim..]));
                match inv {
                    Some(i) => i.values().iter().take(extra).for_each(|v| line += &format!(",{v:.6e}")),
                    None => line += &",".repeat(extra),
                }
            }
            writeln!(f, "{line}").map_err(|e| SphError::Io(e.to_string()))?;
        }
        for (k, r) in readings.into_iter().enumerate() {
            self.record[k].push((sim.t, r));
        }
        Ok(())
    }

    pub fn flush(&mut self) {
        if let Some(f) = self.file.as_mut() {
            let _ = f.flush();
        }
    }

    /// Flushes gauges.csv to the disk (before a checkpoint records its length).
    pub fn sync(&mut self) -> Result<()> {
        if let Some(f) = self.file.as_mut() {
            f.flush().io_at("gauges.csv")?;
            f.get_ref().sync_all().io_at("gauges.csv")?;
        }
        Ok(())
    }

    /// The measures of gauge `k` (see [`GaugeStats`]).
    pub fn stats(&self, k: usize) -> GaugeStats {
        let d = self.dim;
        let mut series: Vec<(f64, f64, f64)> = Vec::new();
        // (a reading after steps in a void: the impulse is not carried across the gap)
        let mut after_gap: Vec<bool> = Vec::new();
        let mut gap = false;
        for (t, r) in &self.record[k] {
            match r {
                Some(q) => {
                    series.push((*t, q[0], q[1..1 + d].iter().map(|v| v * v).sum::<f64>().sqrt()));
                    after_gap.push(gap);
                    gap = false;
                }
                None => gap = true,
            }
        }
        GaugeStats::of(&series, &after_gap)
    }

    /// Gauge `k`'s highest von Mises stress and its most compressive (lowest) mean stress over
    /// the record (Pa); None without strength, in 1D or without a reading.
    fn stress_extremes(&self, k: usize) -> Option<(f64, f64)> {
        if !self.stress {
            return None;
        }
        let d = self.dim;
        let all: Vec<_> =
            self.record[k].iter().filter_map(|(_, r)| r.as_ref().and_then(|q| invariants_of(d, &q[1 + d..]))).collect();
        let vm = all.iter().map(|i| i.von_mises).fold(f64::NEG_INFINITY, f64::max);
        let mean = all.iter().map(|i| i.mean).fold(f64::INFINITY, f64::min);
        (!all.is_empty()).then_some((vm, mean))
    }

    /// summary.json `gauges`: what each gauge is and its measures. A gauge whose pressure rose
    /// above its first reading by less than [`REACHED`] of the largest rise of the run's gauges
    /// has not been reached by the wave: `reached` false, no arrival (its peak is its noise).
    pub fn summary(&self) -> Vec<Value> {
        let stats: Vec<GaugeStats> = (0..self.names.len()).map(|k| self.stats(k)).collect();
        let top = stats.iter().map(|s| s.rise_pa).fold(0.0, f64::max);
        (0..self.names.len())
            .map(|k| {
                let mut s = stats[k].clone();
                let reached = s.arrival_s.is_some() && s.rise_pa >= REACHED * top;
                if !reached {
                    s.arrival_s = None;
                }
                let stress = self.stress_extremes(k);
                json!({
                    "name": self.names[k],
                    "kind": match self.cfg[k].kind { GaugeKind::Particle => "particle", GaugeKind::Point => "point" },
                    "point_m": self.cfg[k].point_m,
                    "particle": self.particle[k],
                    "particle_start_m": if self.particle[k].is_some() { json!(self.start_m[k]) } else { Value::Null },
                    "tied_particles": if self.particle[k].is_some() { json!(self.tied[k]) } else { Value::Null },
                    "peak_pa": s.peak_pa,
                    "peak_time_s": s.peak_time_s,
                    "arrival_s": s.arrival_s,
                    "reached": reached,
                    "impulse_pa_s": s.impulse_pa_s,
                    "ppv_ms": s.ppv_ms,
                    "ppv_time_s": s.ppv_time_s,
                    "samples": s.samples,
                    "void_samples": self.record[k].len() - s.samples,
                    "peak_von_mises_pa": stress.map(|m| m.0),
                    "min_mean_stress_pa": stress.map(|m| m.1),
                })
            })
            .collect()
    }
}

/// The least rise above its first reading, as a share of the largest rise among a run's
/// gauges, that counts as the wave's arrival at a gauge: below it the record is the ambient
/// state's noise (a gauge 30 cm out in saturated sand before the wave: 16 Pa over 46 Pa against
/// 300 MPa near the charge). A real pulse this much weaker than the strongest gauge's is
/// hundreds of times farther from the charge, farther than a scene's gauges lie.
pub const REACHED: f64 = 1e-4;

/// What an engineer reads off a gauge record (docs/reference/cases.md `[[gauge]]`).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct GaugeStats {
    /// Peak pressure (Pa) and its time (s); None without a reading.
    pub peak_pa: Option<f64>,
    pub peak_time_s: Option<f64>,
    /// Arrival: the first time the pressure's rise above its first reading reaches half the
    /// peak's (s); None when the peak is not above the first reading (or, in a run's summary,
    /// when the wave has not reached the gauge: [`REACHED`]).
    pub arrival_s: Option<f64>,
    /// The peak's rise above the first reading (Pa).
    #[serde(skip)]
    pub rise_pa: f64,
    /// Positive impulse ∫ max(p − p_first, 0) dt over the record (Pa·s; per the trapezoid rule
    /// over the steps, not across steps without a reading).
    pub impulse_pa_s: Option<f64>,
    /// Peak particle velocity max |v| (m/s) and its time (s).
    pub ppv_ms: Option<f64>,
    pub ppv_time_s: Option<f64>,
    /// Steps with a reading.
    pub samples: usize,
}

impl GaugeStats {
    /// From (time s, pressure Pa, speed m/s) samples in time order; `after_gap[i]` (or none:
    /// empty) when steps without a reading (a point gauge in a void) came before sample i: the
    /// impulse's trapezoid does not bridge them.
    pub fn of(series: &[(f64, f64, f64)], after_gap: &[bool]) -> GaugeStats {
        let Some(&(_, p0, _)) = series.first() else { return GaugeStats::default() };
        let mut peak = (f64::NEG_INFINITY, 0.0);
        let mut ppv = (f64::NEG_INFINITY, 0.0);
        for &(t, p, v) in series {
            if p > peak.0 {
                peak = (p, t);
            }
            if v > ppv.0 {
                ppv = (v, t);
            }
        }
        let rise = peak.0 - p0;
        let arrival = if rise > 0.0 { series.iter().find(|s| s.1 - p0 >= 0.5 * rise).map(|s| s.0) } else { None };
        let mut imp = 0.0;
        for (i, w) in series.windows(2).enumerate() {
            if after_gap.get(i + 1).copied().unwrap_or(false) {
                continue;
            }
            let (a, b) = ((w[0].1 - p0).max(0.0), (w[1].1 - p0).max(0.0));
            imp += 0.5 * (a + b) * (w[1].0 - w[0].0);
        }
        GaugeStats {
            peak_pa: Some(peak.0),
            peak_time_s: Some(peak.1),
            arrival_s: arrival,
            rise_pa: if rise.is_finite() { rise } else { 0.0 },
            impulse_pa_s: Some(imp),
            ppv_ms: Some(ppv.0),
            ppv_time_s: Some(ppv.1),
            samples: series.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::GaugeStats;

    /// The impulse's trapezoid does not bridge steps without a reading (a point gauge in a void):
    /// 0 before a gap, 10 Pa after it, 1 s apart, added 5 Pa·s of no data before.
    #[test]
    fn the_impulse_does_not_bridge_a_gap() {
        let s = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 10.0, 0.0), (3.0, 10.0, 0.0)];
        let whole = GaugeStats::of(&s, &[]);
        assert_eq!(whole.impulse_pa_s, Some(15.0));
        let gap = GaugeStats::of(&s, &[false, false, true, false]);
        assert_eq!(gap.impulse_pa_s, Some(10.0));
        assert_eq!(gap.peak_pa, Some(10.0));
    }
}
