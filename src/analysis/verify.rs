//! Measurements of the verification problems (`cases/verify/`, `[analysis] kind = "sedov" |
//! "noh" | "reflection" | "detonation"`) against their exact solutions, for `summary.json` (at the
//! end of a run) and `blastsph report` (with profile plots). Every definition is stated here and in
//! docs/validation.md ("Verification problems").
//!
//! Common measures (SI units):
//! - **radial profile**: the particles binned by distance r from the centre in bins one initial
//!   spacing Δx wide; a bin's density is the mean of its particles' ρ;
//! - **shock radius, peak measure** R_peak: the position of the largest binned density, refined by
//!   the vertex of the parabola through that bin and its two neighbours;
//! - **shock radius, threshold measure** R_half: outward from that bin, where the binned density
//!   falls through the middle between its peak and the density ahead of the shock (linear
//!   interpolation between bins) — the mid-rise of the front;
//! - **window peak**: the largest mean density of the particles whose r lies in a window
//!   (s − Δx, s], over window ends s every Δx/50 — the binned peak without the bins' alignment —
//!   and the same for the exact solution (a particle mean samples the profile with the weight
//!   ρ(r) r^(dim−1) of particles on a lattice of dimension dim), so that the measured peak is set
//!   against what the exact profile itself reaches when averaged over Δx: behind a Sedov shock the
//!   density falls so steeply that at 10⁴ particles in 2D the exact profile's Δx mean peaks at
//!   0.80 of the jump (γ = 1.4), not 1;
//! - **L1(ρ)** = Σ m_i |ρ_i − ρ_exact(r_i)| / Σ m_i over the particles within 1.5 exact shock
//!   radii (kg/m³): mass-weighted (the mean over the particles when their masses are equal), so
//!   that a few rarefied particles near a blast's centre, whose volume m/ρ is huge, do not dominate
//!   it; also given divided by the exact density jump's density;
//! - **clumping**: the largest particle density over the exact peak density;
//! - **ahead** (Sedov): the particles beyond 1.2 exact shock radii moving outward at more than a
//!   tenth of the exact post-shock velocity — rows of particles running ahead of the front as
//!   jets — their count and the largest r over the exact radius (0 when there are none);
//! - e < 0: the count of particles with negative specific internal energy, and the smallest e.

use crate::analysis::noh::{Noh, reflect};
use crate::analysis::sedov::Sedov;
use crate::analysis::sedov_edge::{Setup, edge_warning, nearest_edge, setup_of};
use crate::case::{AnalysisKind, Case, EosCfg};
use crate::error::{Result, input};
use crate::modules::detonation::cj::{Jwl, TaylorWave};
use crate::output::Frame;
use serde_json::{Value, json};

/// A frame of the current state of a simulation (real particles), for the end-of-run summary.
pub(crate) fn frame_of(sim: &crate::sim::Sim) -> Frame {
    let p = &sim.p;
    let (d, n) = (sim.cfg.dim, p.nreal);
    let comp = |a: &[f64], k: usize| -> Vec<f64> { (0..n).map(|i| if k < d { a[k + d * i] } else { 0.0 }).collect() };
    Frame {
        time: sim.t,
        x: comp(&p.x, 0),
        y: comp(&p.x, 1),
        z: comp(&p.x, 2),
        vx: comp(&p.v, 0),
        vy: comp(&p.v, 1),
        vz: comp(&p.v, 2),
        rho: p.rho[..n].to_vec(),
        p: p.p[..n].to_vec(),
        e: p.e[..n].to_vec(),
        h: p.h[..n].to_vec(),
        mass: p.mass[..n].to_vec(),
        mat: p.mat[..n].to_vec(),
        id: p.id[..n].to_vec(),
        ppv: Vec::new(),
        p_peak: Vec::new(),
        bnd: p.bnd.clone(),
    }
}

/// The part of a frame a detonation's history reads (time, positions, pressure, material),
/// kept at every output of a run so that its summary has the history `blastsph report` gives.
pub(crate) fn slim(f: Frame) -> Frame {
    Frame {
        time: f.time,
        x: f.x,
        y: Vec::new(),
        z: Vec::new(),
        vx: Vec::new(),
        vy: Vec::new(),
        vz: Vec::new(),
        rho: Vec::new(),
        p: f.p,
        e: Vec::new(),
        h: Vec::new(),
        mass: Vec::new(),
        mat: f.mat,
        id: Vec::new(),
        ppv: Vec::new(),
        p_peak: Vec::new(),
        bnd: Vec::new(),
    }
}

fn radius(s: &Setup, f: &Frame, i: usize) -> f64 {
    let dx = f.x[i] - s.centre[0];
    if s.dim == 1 {
        return dx.abs();
    }
    let dy = f.y[i] - s.centre[1];
    let dz = if s.dim == 3 { f.z[i] - s.centre[2] } else { 0.0 };
    (dx * dx + dy * dy + dz * dz).sqrt()
}

/// Binned mean density against distance: (bin centre, mean ρ, count).
fn profile(r: &[f64], rho: &[f64], dr: f64) -> Vec<(f64, f64, usize)> {
    let rmax = r.iter().cloned().fold(0.0, f64::max);
    let nb = ((rmax / dr) as usize + 1).min(1_000_000);
    let mut sum = vec![0.0; nb];
    let mut cnt = vec![0usize; nb];
    for (k, &ri) in r.iter().enumerate() {
        let b = ((ri / dr) as usize).min(nb - 1);
        sum[b] += rho[k];
        cnt[b] += 1;
    }
    (0..nb).filter(|&b| cnt[b] > 0).map(|b| ((b as f64 + 0.5) * dr, sum[b] / cnt[b] as f64, cnt[b])).collect()
}

/// R_peak, R_half and the peak binned density of a profile; `ahead(r)` is the density ahead of
/// the shock at r.
fn shock_measures(prof: &[(f64, f64, usize)], ahead: &dyn Fn(f64) -> f64) -> (f64, f64, f64) {
    if prof.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let kmax = (0..prof.len()).max_by(|&a, &b| prof[a].1.total_cmp(&prof[b].1)).unwrap_or(0);
    let (mut rp, peak) = (prof[kmax].0, prof[kmax].1);
    if kmax > 0 && kmax + 1 < prof.len() {
        let (ya, yb, yc) = (prof[kmax - 1].1, prof[kmax].1, prof[kmax + 1].1);
        let den = ya - 2.0 * yb + yc;
        let dr = 0.5 * (prof[kmax + 1].0 - prof[kmax - 1].0);
        if den < 0.0 {
            rp += dr * 0.5 * (ya - yc) / den;
        }
    }
    let mut rhalf = f64::NAN;
    for k in kmax..prof.len().saturating_sub(1) {
        let (ra, da) = (prof[k].0, prof[k].1);
        let (rb, db) = (prof[k + 1].0, prof[k + 1].1);
        let (la, lb) = (0.5 * (peak + ahead(ra)), 0.5 * (peak + ahead(rb)));
        if da >= la && db < lb {
            let s = (da - la) / ((da - la) - (db - lb));
            rhalf = ra + s * (rb - ra);
            break;
        }
    }
    (rp, rhalf, peak)
}

/// The window peak of particles at distances `r` with densities `rho` (see the module's notes):
/// the largest mean of the ρ whose r lies in (s − `dx`, s], over window ends s every dx/50.
fn window_peak(r: &[f64], rho: &[f64], dx: f64) -> f64 {
    let mut o: Vec<usize> = (0..r.len()).collect();
    o.sort_by(|&a, &b| r[a].total_cmp(&r[b]));
    let rs: Vec<f64> = o.iter().map(|&k| r[k]).collect();
    let mut cum = vec![0.0; o.len() + 1];
    for (k, &i) in o.iter().enumerate() {
        cum[k + 1] = cum[k] + rho[i];
    }
    let (Some(&r0), Some(&r1)) = (rs.first(), rs.last()) else { return f64::NAN };
    let step = dx / 50.0;
    let nstep = (((r1 - r0) / step) as usize + 1).min(10_000_000);
    let mut best = f64::NAN;
    for k in 0..=nstep {
        let s = r0 + k as f64 * step;
        let a = rs.partition_point(|&x| x <= s - dx);
        let b = rs.partition_point(|&x| x <= s);
        if b > a {
            let m = (cum[b] - cum[a]) / (b - a) as f64;
            if best.is_nan() || m > best {
                best = m;
            }
        }
    }
    best
}

/// The window peak of an exact profile `rho(r)` out to `rmax`, as particles on a lattice of
/// dimension `dim` would sample it (weight ρ r^(dim−1)), with windows Δx = `dx` wide.
fn window_peak_exact(rho: &dyn Fn(f64) -> f64, rmax: f64, dim: usize, dx: f64) -> f64 {
    // cells dx/50 wide (midpoint rule), the window 50 cells
    let (nc, per) = (((rmax / dx) * 50.0).ceil().min(10_000_000.0) as usize, 50);
    let c = dx / 50.0;
    let (mut cw, mut cwr) = (vec![0.0; nc + 1], vec![0.0; nc + 1]);
    for k in 0..nc {
        let x = (k as f64 + 0.5) * c;
        let q = rho(x);
        let w = q * x.powi(dim as i32 - 1);
        cw[k + 1] = cw[k] + w;
        cwr[k + 1] = cwr[k] + w * q;
    }
    (per..=nc)
        .filter(|&b| cw[b] - cw[b - per] > 0.0)
        .map(|b| (cwr[b] - cwr[b - per]) / (cw[b] - cw[b - per]))
        .fold(f64::NAN, f64::max)
}

fn l1(vol: &[f64], err: &[f64]) -> f64 {
    let v: f64 = vol.iter().sum();
    vol.iter().zip(err).map(|(a, b)| a * b.abs()).sum::<f64>() / v.max(1e-300)
}

fn neg_e(f: &Frame) -> (usize, f64) {
    (f.e.iter().filter(|&&e| e < 0.0).count(), f.e.iter().cloned().fold(f64::INFINITY, f64::min))
}

/// Profiles of one frame for the plots: (r, ρ, radial v, p) per particle and the exact curves.
pub struct Profiles {
    pub particles: Vec<[f64; 4]>,
    pub exact: Vec<[f64; 4]>,
    pub xlabel: &'static str,
}

fn radial_v(s: &Setup, f: &Frame, i: usize, r: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let mut u = f.vx[i] * (f.x[i] - s.centre[0]);
    if s.dim > 1 {
        u += f.vy[i] * (f.y[i] - s.centre[1]);
    }
    if s.dim == 3 {
        u += f.vz[i] * (f.z[i] - s.centre[2]);
    }
    u / r
}

/// The measures of the last frame (and, for a detonation, of every frame), as JSON, with the
/// profiles for the plots. `x0`: the particles' initial positions (`dim` values each), which a
/// point blast's gas edge is measured on.
pub fn measure(case: &Case, frames: &[Frame], x0: &[f64]) -> Result<(Value, Option<Profiles>)> {
    let last = frames.last().ok_or_else(|| input("no output step to measure"))?;
    match case.analysis.kind {
        AnalysisKind::Sedov => sedov(case, last, x0),
        AnalysisKind::Noh => noh(case, last),
        AnalysisKind::Reflection => reflection(case, last),
        AnalysisKind::Detonation => detonation(case, frames),
        _ => Ok((json!({}), None)),
    }
}

fn sedov(case: &Case, f: &Frame, x0: &[f64]) -> Result<(Value, Option<Profiles>)> {
    let s = setup_of(case)?;
    let d = case.dim.max(1);
    let pos0 = |i: usize| -> [f64; 3] { std::array::from_fn(|k| if k < d { x0[d * i + k] } else { 0.0 }) };
    let edge = nearest_edge(&s, x0.len() / d, &pos0);
    let sol = Sedov::new(s.j, s.gamma).ok_or_else(|| input("sedov: no similarity solution"))?;
    let t = f.time;
    let rex = sol.radius(s.energy, s.rho0, t);
    let edge_warning = edge_warning(case, &s, t, rex, edge.as_ref());
    let jump = sol.jump();
    let n = f.x.len();
    let r: Vec<f64> = (0..n).map(|i| radius(&s, f, i)).collect();
    let prof = profile(&r, &f.rho, s.dx);
    let (rp, rh, peak) = shock_measures(&prof, &|_| s.rho0);
    let pw = window_peak(&r, &f.rho, s.dx);
    let pwe = window_peak_exact(&|x| sol.sample(x, s.energy, s.rho0, t).rho, 1.2 * rex, s.dim, s.dx);
    let (mut vol, mut err) = (Vec::new(), Vec::new());
    for i in 0..n {
        if r[i] <= 1.5 * rex {
            vol.push(f.mass[i]);
            err.push(f.rho[i] - sol.sample(r[i], s.energy, s.rho0, t).rho);
        }
    }
    let l1r = l1(&vol, &err);
    let rho_max = f.rho.iter().cloned().fold(0.0, f64::max);
    let (nneg, emin) = neg_e(f);
    let peak_r = |rr: &[f64], rh: &[f64]| shock_measures(&profile(rr, rh, s.dx), &|_| s.rho0).0;
    let axis = case.axisymmetric().then(|| super::axis::measures(f, &r, [s.centre[0], s.centre[1]], s.dx, &peak_r));
    let parts: Vec<[f64; 4]> = (0..n).map(|i| [r[i], f.rho[i], radial_v(&s, f, i, r[i]), f.p[i]]).collect();
    // particles running ahead of the front (jets): beyond 1.2 R (a smeared front's toe reaches
    // 3-4 spacings, 0.2 R at 15-20 spacings from the centre) at more than a tenth of the exact
    // post-shock velocity
    let u2 = sol.sample(rex * (1.0 - 1e-9), s.energy, s.rho0, t).u;
    let ahead: Vec<f64> = parts.iter().filter(|q| q[0] > 1.2 * rex && q[2] > 0.1 * u2).map(|q| q[0]).collect();
    let ahead_max = ahead.iter().cloned().fold(0.0, f64::max);
    let rmax = r.iter().cloned().fold(0.0, f64::max).min(1.5 * rex).max(rex * 1.05);
    let exact: Vec<[f64; 4]> = (0..=1000)
        .map(|k| {
            let x = rmax * k as f64 / 1000.0;
            let q = sol.sample(x, s.energy, s.rho0, t);
            [x, q.rho, q.u, q.p]
        })
        .collect();
    let mut v = json!({
        "kind": "sedov",
        "geometry_j": s.j,
        "gamma": s.gamma,
        "xi0": sol.xi0,
        "energy": s.energy,
        "rho0": s.rho0,
        "time": t,
        "shock_radius_exact_m": rex,
        "shock_radius_peak_m": rp,
        "shock_radius_half_m": rh,
        "shock_radius_peak_ratio": rp / rex,
        "shock_radius_half_ratio": rh / rex,
        "density_jump_exact": jump,
        "peak_density_binned": peak,
        "peak_density_fraction_of_jump": (peak / s.rho0 - 1.0) / (jump - 1.0),
        "peak_density_ratio": peak / (s.rho0 * jump),
        "peak_density_window": pw,
        "peak_density_window_exact": pwe,
        "peak_density_window_fraction_of_exact": (pw - s.rho0) / (pwe - s.rho0),
        "max_particle_density": rho_max,
        "clumping": rho_max / (s.rho0 * jump),
        "ahead_count": ahead.len(),
        "ahead_max_radius_ratio": ahead_max / rex,
        "l1_rho": l1r,
        "l1_rho_relative": l1r / (s.rho0 * jump),
        "l1_window_m": 1.5 * rex,
        "negative_e_count": nneg,
        "min_e": emin,
        "dx_m": s.dx,
        "edge_m": edge.as_ref().map(|e| e.0),
        "warning": edge_warning,
    });
    if let (Some(a), Some(o)) = (axis, v.as_object_mut()) {
        o.insert("axis_shock_radius_peak_ratio".into(), json!(a[0] / rex));
        o.insert("equator_shock_radius_peak_ratio".into(), json!(a[1] / rex));
        o.insert("axis_max_density".into(), json!(a[2]));
        o.insert("axis_max_density_ratio".into(), json!(a[2] / (s.rho0 * jump)));
    }
    Ok((v, Some(Profiles { particles: parts, exact, xlabel: "r (m)" })))
}

fn noh(case: &Case, f: &Frame) -> Result<(Value, Option<Profiles>)> {
    let s = setup_of(case)?;
    let sol = Noh { j: s.j, gamma: s.gamma, rho0: s.rho0, u0: s.u0 };
    let t = f.time;
    let sh = sol.shocked();
    let rex = sol.radius(t);
    let n = f.x.len();
    let r: Vec<f64> = (0..n).map(|i| radius(&s, f, i)).collect();
    let prof = profile(&r, &f.rho, s.dx);
    // the threshold measure: where ρ falls through the middle of ρ₂ and the inflow density
    let ahead = |x: f64| sol.sample(x.max(rex * 1.000001), t).rho;
    let mut rh = f64::NAN;
    for k in 0..prof.len().saturating_sub(1) {
        let (ra, da, rb, db) = (prof[k].0, prof[k].1, prof[k + 1].0, prof[k + 1].1);
        let (la, lb) = (0.5 * (sh.rho + ahead(ra)), 0.5 * (sh.rho + ahead(rb)));
        if ra > 0.3 * rex && da >= la && db < lb {
            rh = ra + (da - la) / ((da - la) - (db - lb)) * (rb - ra);
            break;
        }
    }
    // the shocked plateau away from the centre (0.4 R … 0.8 R) and the centre (r < 2 Δx)
    let mean = |lo: f64, hi: f64, q: &dyn Fn(usize) -> f64| {
        let v: Vec<f64> = (0..n).filter(|&i| r[i] >= lo && r[i] < hi).map(q).collect();
        if v.is_empty() { f64::NAN } else { v.iter().sum::<f64>() / v.len() as f64 }
    };
    let rho_plateau = mean(0.4 * rex, 0.8 * rex, &|i| f.rho[i]);
    let e_plateau = mean(0.4 * rex, 0.8 * rex, &|i| f.e[i]);
    let rho_centre = mean(0.0, 2.0 * s.dx, &|i| f.rho[i]);
    let e_centre = mean(0.0, 2.0 * s.dx, &|i| f.e[i]);
    let window = 1.5 * rex;
    let (mut vol, mut err) = (Vec::new(), Vec::new());
    for i in 0..n {
        if r[i] <= window {
            vol.push(f.mass[i]);
            err.push(f.rho[i] - sol.sample(r[i], t).rho);
        }
    }
    let l1r = l1(&vol, &err);
    let (nneg, emin) = neg_e(f);
    let rho_max = f.rho.iter().cloned().fold(0.0, f64::max);
    let parts: Vec<[f64; 4]> =
        (0..n).filter(|&i| r[i] <= 3.0 * rex).map(|i| [r[i], f.rho[i], radial_v(&s, f, i, r[i]), f.p[i]]).collect();
    let exact: Vec<[f64; 4]> = (1..=1000)
        .map(|k| {
            let x = 3.0 * rex * k as f64 / 1000.0;
            let q = sol.sample(x, t);
            [x, q.rho, q.u, q.p]
        })
        .collect();
    let v = json!({
        "kind": "noh",
        "geometry_j": s.j,
        "gamma": s.gamma,
        "rho0": s.rho0,
        "u0": s.u0,
        "time": t,
        "shock_radius_exact_m": rex,
        "shock_radius_half_m": rh,
        "shock_radius_half_ratio": rh / rex,
        "post_shock_density_exact": sh.rho,
        "post_shock_density": rho_plateau,
        "post_shock_density_ratio": rho_plateau / sh.rho,
        "post_shock_e_exact": sh.e,
        "post_shock_e": e_plateau,
        "centre_density_ratio": rho_centre / sh.rho,
        "centre_e_ratio": e_centre / sh.e,
        "wall_heating_e_excess": e_centre / sh.e - 1.0,
        "max_particle_density": rho_max,
        "clumping": rho_max / sh.rho,
        "l1_rho": l1r,
        "l1_rho_relative": l1r / sh.rho,
        "l1_window_m": window,
        "negative_e_count": nneg,
        "min_e": emin,
        "dx_m": s.dx,
    });
    Ok((v, Some(Profiles { particles: parts, exact, xlabel: "r (m)" })))
}

fn reflection(case: &Case, f: &Frame) -> Result<(Value, Option<Profiles>)> {
    let mut s = setup_of(case)?;
    let xw = case.walls[0].from_m[0];
    s.centre = [xw, 0.0, 0.0];
    let p1 = (s.gamma - 1.0) * s.rho0 * s.e_amb;
    let st = reflect(s.gamma, s.rho0, p1, s.u0)
        .ok_or_else(|| input("reflection: the gas does not move towards the wall"))?;
    let t = f.time;
    let xs = st.speed * t;
    let n = f.x.len();
    let r: Vec<f64> = (0..n).map(|i| radius(&s, f, i)).collect();
    let prof = profile(&r, &f.rho, s.dx);
    let mut rh = f64::NAN;
    let mid = 0.5 * (st.rho + s.rho0);
    for k in 0..prof.len().saturating_sub(1) {
        if prof[k].0 > 0.3 * xs && prof[k].1 >= mid && prof[k + 1].1 < mid {
            rh = prof[k].0 + (prof[k].1 - mid) / (prof[k].1 - prof[k + 1].1) * (prof[k + 1].0 - prof[k].0);
            break;
        }
    }
    let mean = |lo: f64, hi: f64, q: &dyn Fn(usize) -> f64| {
        let v: Vec<f64> = (0..n).filter(|&i| r[i] >= lo && r[i] < hi).map(q).collect();
        if v.is_empty() { f64::NAN } else { v.iter().sum::<f64>() / v.len() as f64 }
    };
    let rho_plateau = mean(0.4 * xs, 0.8 * xs, &|i| f.rho[i]);
    let e_plateau = mean(0.4 * xs, 0.8 * xs, &|i| f.e[i]);
    let iw = (0..n).min_by(|&a, &b| r[a].total_cmp(&r[b])).unwrap_or(0);
    let exact_at = |x: f64| if x < xs { (st.rho, 0.0, st.p) } else { (s.rho0, -s.u0, p1) };
    let (mut vol, mut err) = (Vec::new(), Vec::new());
    for i in 0..n {
        if r[i] <= 1.5 * xs {
            vol.push(f.mass[i]);
            err.push(f.rho[i] - exact_at(r[i]).0);
        }
    }
    let l1r = l1(&vol, &err);
    let (nneg, emin) = neg_e(f);
    let sign = if f.x.iter().sum::<f64>() / n as f64 >= xw { 1.0 } else { -1.0 };
    let parts: Vec<[f64; 4]> =
        (0..n).filter(|&i| r[i] <= 3.0 * xs).map(|i| [r[i], f.rho[i], sign * f.vx[i], f.p[i]]).collect();
    let exact: Vec<[f64; 4]> = (0..=1000)
        .map(|k| {
            let x = 3.0 * xs * k as f64 / 1000.0;
            let q = exact_at(x);
            [x, q.0, q.1, q.2]
        })
        .collect();
    let v = json!({
        "kind": "reflection",
        "gamma": s.gamma,
        "rho1": s.rho0,
        "p1": p1,
        "u1": s.u0,
        "time": t,
        "reflected_density_exact": st.rho,
        "reflected_e_exact": st.e,
        "reflected_p_exact": st.p,
        "shock_distance_exact_m": xs,
        "shock_distance_half_m": rh,
        "shock_distance_ratio": rh / xs,
        "plateau_density_ratio": rho_plateau / st.rho,
        "plateau_e_ratio": e_plateau / st.e,
        "wall_density_ratio": f.rho[iw] / st.rho,
        "wall_e_ratio": f.e[iw] / st.e,
        "wall_heating_e_excess": f.e[iw] / st.e - 1.0,
        "l1_rho": l1r,
        "l1_rho_relative": l1r / st.rho,
        "negative_e_count": nneg,
        "min_e": emin,
        "dx_m": s.dx,
    });
    Ok((v, Some(Profiles { particles: parts, exact, xlabel: "distance from the wall (m)" })))
}

/// The JWL explosive of a case, its material index, and e0.
fn explosive(case: &Case) -> Result<(usize, Jwl)> {
    for (m, mc) in case.materials.iter().enumerate() {
        if let EosCfg::Jwl { rho0_kgm3, a_pa, b_pa, r1, r2, omega, .. } = mc.eos {
            let e0 =
                case.regions.iter().find(|r| r.material == mc.name).and_then(|r| r.e_jkg).or(mc.e0_jkg).unwrap_or(0.0);
            return Ok((m, Jwl { rho0: rho0_kgm3, a: a_pa, b: b_pa, r1, r2, omega, e0 }));
        }
    }
    Err(input("detonation: no JWL material"))
}

fn detonation(case: &Case, frames: &[Frame]) -> Result<(Value, Option<Profiles>)> {
    let (mj, jwl) = explosive(case)?;
    let wave = TaylorWave::new(&jwl).ok_or_else(|| input("detonation: no CJ state for this JWL"))?;
    let cj = wave.cj;
    let init = crate::setup::particles(case)?;
    let dx = init.dx_min;
    let xd = case.detonation.as_ref().and_then(|d| d.point_m.clone()).unwrap_or_default();
    let x0 = xd.first().copied().unwrap_or(0.0);
    // a wall through the lighting point makes the Taylor wave's plateau
    let wall = case.walls.iter().any(|w| (w.from_m[0] - x0).abs() < 0.5 * dx && (w.to_m[0] - x0).abs() < 0.5 * dx);
    let dist = |f: &Frame, i: usize| (f.x[i] - x0).abs();
    // every frame: the peak pressure of the explosive and the front (the farthest particle above
    // half p_CJ), from the frames after 10 spacings of travel
    let mut hist = Vec::new();
    for f in frames {
        if f.time <= 0.0 || cj.d * f.time < 10.0 * dx {
            continue;
        }
        let (mut pk, mut front) = (0.0f64, 0.0f64);
        for i in 0..f.x.len() {
            if f.mat[i] as usize != mj {
                continue;
            }
            pk = pk.max(f.p[i]);
            if f.p[i] > 0.5 * cj.p {
                front = front.max(dist(f, i));
            }
        }
        hist.push(json!({"time": f.time, "travel_dx": cj.d * f.time / dx, "peak_p_ratio": pk / cj.p, "front_m": front, "front_exact_m": cj.d * f.time}));
    }
    let f = frames.last().ok_or_else(|| input("no output step"))?;
    let t = f.time;
    let n = f.x.len();
    let ex: Vec<usize> = (0..n).filter(|&i| f.mat[i] as usize == mj).collect();
    let pk = ex.iter().map(|&i| f.p[i]).fold(0.0, f64::max);
    let xf = cj.d * t;
    let hmax = ex.iter().map(|&i| f.h[i]).fold(0.0, f64::max);
    let ahead: Vec<usize> = ex.iter().copied().filter(|&i| dist(f, i) > xf + 2.0 * hmax).collect();
    let rho_ahead = ahead.iter().map(|&i| f.rho[i]).fold(0.0, f64::max);
    let rho_max = ex.iter().map(|&i| f.rho[i]).fold(0.0, f64::max);
    let plateau = if wall {
        let v: Vec<f64> = ex.iter().filter(|&&i| dist(f, i) < 0.5 * wave.c_plateau * t).map(|&i| f.p[i]).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    } else {
        None
    };
    let (mut vol, mut err) = (Vec::new(), Vec::new());
    if wall {
        for &i in &ex {
            if dist(f, i) <= xf {
                vol.push(f.mass[i]);
                err.push(f.p[i] - wave.sample(dist(f, i), t).p);
            }
        }
    }
    let l1p = if wall { Some(l1(&vol, &err)) } else { None };
    let (nneg, emin) = neg_e(f);
    let sign = |i: usize| if f.x[i] >= x0 { 1.0 } else { -1.0 };
    let parts: Vec<[f64; 4]> = ex.iter().map(|&i| [dist(f, i), f.rho[i], sign(i) * f.vx[i], f.p[i]]).collect();
    let dmax = ex.iter().map(|&i| dist(f, i)).fold(0.0, f64::max);
    let exact: Vec<[f64; 4]> = (0..=2000)
        .map(|k| {
            let x = dmax * k as f64 / 2000.0;
            let q = wave.sample(x, t);
            [x, q.rho, q.u, q.p]
        })
        .collect();
    let ratios: Vec<f64> = hist.iter().filter_map(|h| h["peak_p_ratio"].as_f64()).collect();
    let v = json!({
        "kind": "detonation",
        "p_cj": cj.p,
        "rho_cj": cj.rho,
        "d_cj": cj.d,
        "u_cj": cj.u,
        "plateau_p_exact": wave.plateau.p,
        "time": t,
        "travel_dx": xf / dx,
        "dx_m": dx,
        "front_p_ratio": pk / cj.p,
        "front_p_ratio_min_over_run": ratios.iter().cloned().fold(f64::INFINITY, f64::min),
        "front_p_ratio_max_over_run": ratios.iter().cloned().fold(0.0, f64::max),
        "plateau_p": plateau,
        "plateau_ratio": plateau.map(|p| p / wave.plateau.p),
        "l1_p_taylor_relative": l1p.map(|x| x / cj.p),
        "max_density_ahead_of_front": rho_ahead,
        "max_density_ratio_to_cj": rho_max / cj.rho,
        "negative_e_count": nneg,
        "min_e": emin,
        "history": hist,
    });
    Ok((v, Some(Profiles { particles: parts, exact, xlabel: "distance from the lighting point (m)" })))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal-mass particles on a line whose spacing follows a profile ρ(x) (the k-th at
    /// ∫₀ˣ ρ = (k + ½) m), each carrying ρ at its place: their window peak is the exact one with
    /// the weight ρ (dim = 1), not the plain spatial mean of the profile.
    #[test]
    fn window_peak_of_particles_on_a_profile_is_the_exact_window_peak() {
        let sol = Sedov::new(1, 1.4).unwrap();
        let (e, rho0, t) = (1.0, 1.0, 0.5);
        let rex = sol.radius(e, rho0, t);
        let prof = |x: f64| sol.sample(x, e, rho0, t).rho;
        let m = rex / 4000.0;
        let (mut r, mut rho) = (Vec::new(), Vec::new());
        let (mut x, mut acc, mut k) = (0.0, 0.0, 0usize);
        let c = m / 200.0;
        while x < 1.2 * rex {
            let q = prof(x + 0.5 * c);
            acc += q * c;
            x += c;
            if acc >= (k as f64 + 0.5) * m {
                r.push(x);
                rho.push(q);
                k += 1;
            }
        }
        let dx = rex / 12.0;
        let pw = window_peak(&r, &rho, dx);
        let pwe = window_peak_exact(&prof, 1.2 * rex, 1, dx);
        // the spatial mean over the same windows (weight 1), which a particle mean is not: it
        // must differ by more than the tolerance, or this test could not tell the two apart (a
        // window of R/12, where the steep profile makes them 3.6 % apart)
        let c = dx / 50.0;
        let cells: Vec<f64> = (0..(1.2 * rex / c) as usize).map(|k| prof((k as f64 + 0.5) * c)).collect();
        let flat = cells.windows(50).map(|w| w.iter().sum::<f64>() / 50.0).fold(0.0, f64::max);
        let rel = (pw - pwe).abs() / (pwe - rho0);
        assert!(rel < 0.01, "particles' window peak {pw} against the exact {pwe}");
        assert!((flat - pwe).abs() / (pwe - rho0) > 0.03, "spatial mean {flat} against {pwe}");
        assert!(pwe < sol.jump() * rho0 && pwe > 0.5 * (1.0 + sol.jump()) * rho0, "1D window peak {pwe}");
    }

    /// A step profile's window peak is its top in every dimension; the Sedov profile's
    /// approaches the jump as the window narrows, from below (behind the shock ρ falls steeply).
    #[test]
    fn window_peak_exact_of_a_step_and_of_sedov() {
        for dim in 1..=3 {
            let p = window_peak_exact(&|x| if x < 0.3 { 4.0 } else { 1.0 }, 0.5, dim, 0.01);
            assert!((p - 4.0).abs() < 1e-12, "step, dim {dim}: {p}");
        }
        let sol = Sedov::new(2, 1.4).unwrap();
        let rex = sol.radius(1.0, 1.0, 0.1);
        let prof = |x: f64| sol.sample(x, 1.0, 1.0, 0.1).rho;
        let frac: Vec<f64> = [1.0 / 104.0, 1.0 / 208.0, 1.0 / 416.0, 1.0 / 832.0]
            .iter()
            .map(|&dx| (window_peak_exact(&prof, 1.2 * rex, 2, dx) - 1.0) / (sol.jump() - 1.0))
            .collect();
        assert!(frac.windows(2).all(|w| w[1] > w[0]), "{frac:?}");
        assert!(frac[0] > 0.75 && frac[0] < 0.85, "{frac:?}");
        assert!(frac[3] > 0.9 && frac[3] < 1.0, "{frac:?}");
    }
}
