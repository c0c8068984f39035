//! Health checks: a run that goes unstable stops with a diagnostic naming the step, the particle
//! and the quantity. Each check is one parallel pass over fixed chunks of particles that records,
//! per chunk, the first particle in trouble and the statistics; the chunks are combined in order,
//! so the particle named is the lowest-numbered one whatever the thread count.

use super::{CHUNK, Sim};
use crate::case::{DT_MIN_FRACTION, StepRule};
use crate::error::{Result, SphError};
use crate::modules::boundary::walls::behind_wall;

/// Steps of a window of the progress check.
pub const PACE_WINDOW: u64 = 1000;
/// How far beyond `time.max_steps` a projection may reach before the run is stopped.
pub const PACE_FACTOR: f64 = 10.0;
use crate::modules::param::NSTR;
use crate::state::{Field, Particles};

/// What is wrong with a particle's state.
#[derive(Debug, Clone, Copy)]
enum Bad {
    X(usize),
    V(usize),
    Rho,
    E,
    P,
    Tau(usize),
    /// h/h0 collapsed (or not finite).
    H(f64),
}

/// One chunk's findings.
#[derive(Debug, Clone, Copy)]
struct Part {
    /// The first particle with a bad value.
    bad: Option<usize>,
    /// The first particle deeper than the limit behind a wall: (particle, wall, depth).
    crossed: Option<(usize, usize, f64)>,
    /// The first particle outside the domain.
    outside: Option<usize>,
    energy: f64,
    ke_max: (f64, usize),
    hr: (f64, f64),
    pen: f64,
    out: usize,
}

impl Part {
    fn new() -> Part {
        Part {
            bad: None,
            crossed: None,
            outside: None,
            energy: 0.0,
            ke_max: (0.0, 0),
            hr: (f64::INFINITY, 0.0),
            pen: 0.0,
            out: 0,
        }
    }

    /// Adds the chunk `q` that follows this one.
    fn then(mut self, q: &Part) -> Part {
        self.bad = self.bad.or(q.bad);
        self.crossed = self.crossed.or(q.crossed);
        self.outside = self.outside.or(q.outside);
        self.energy += q.energy;
        if q.ke_max.0 > self.ke_max.0 {
            self.ke_max = q.ke_max;
        }
        self.hr = (self.hr.0.min(q.hr.0), self.hr.1.max(q.hr.1));
        self.pen = self.pen.max(q.pen);
        self.out += q.out;
        self
    }
}

/// The smoothing length's collapse that stops a run: h below this share of its initial value. A
/// shock compresses a gas at most (γ+1)/(γ−1) times (21 at γ = 1.1), h ∝ ρ^(−1/d), so no physical
/// flow of the scenes comes near; particles that pass through each other do (an inviscid strong
/// shock tube at a fixed step, 1D: h/h0 = 0.0016, ρ 154 against the exact 6, "ok" at 1e-3).
const H_COLLAPSE: f64 = 1e-2;

/// What is wrong with particle `i`: the first bad quantity in the order x, v (by component), ρ,
/// e, p, τ, h.
fn what_is_bad(p: &Particles, dim: usize, i: usize, h0: f64) -> Bad {
    for d in 0..dim {
        if !p.x[d + dim * i].is_finite() {
            return Bad::X(d);
        }
        if !p.v[d + dim * i].is_finite() {
            return Bad::V(d);
        }
    }
    let r = p.h[i] / h0;
    if !p.rho[i].is_finite() || p.rho[i] <= 0.0 {
        Bad::Rho
    } else if !p.e[i].is_finite() {
        Bad::E
    } else if !p.p[i].is_finite() {
        Bad::P
    } else if let Some(k) = (!p.tau.is_empty()).then(|| (0..NSTR).find(|&k| !p.tau[k + NSTR * i].is_finite())).flatten()
    {
        Bad::Tau(k)
    } else {
        Bad::H(r)
    }
}

impl Sim {
    fn material(&self, i: usize) -> &str {
        &self.case.materials[self.p.mat[i] as usize].name
    }

    /// Stops on a non-finite rate, naming the particle and the term (force, viscosity, ...).
    pub(super) fn check_rates(&mut self) -> Result<()> {
        use rayon::prelude::*;
        let (dim, n, nt) = (self.cfg.dim, self.p.nreal, self.p.ntotal);
        let (dv, de) = (&self.w.dv, &self.w.de);
        let first = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                (c * CHUNK..((c + 1) * CHUNK).min(n))
                    .find(|&i| !(0..dim).all(|d| dv[d + dim * i].is_finite()) || !de[i].is_finite())
            })
            .collect::<Vec<_>>()
            .into_iter()
            .flatten()
            .next();
        let Some(i) = first else { return Ok(()) };
        self.stab.nan = true;
        let lda = dim * nt;
        let mut terms = Vec::new();
        for (k, t) in self.plan.acc_terms.iter().enumerate() {
            if !(0..dim).all(|d| self.w.acc[k * lda + d + dim * i].is_finite()) {
                terms.push(format!("acceleration of {t}"));
            }
        }
        for (k, t) in self.plan.de_terms.iter().enumerate() {
            if !self.w.dde[k * nt + i].is_finite() {
                terms.push(format!("energy rate of {t}"));
            }
        }
        let pos: Vec<String> = (0..dim).map(|d| format!("{:.5}", self.p.x[d + dim * i])).collect();
        let pl = &self.w.pairs;
        let others: Vec<usize> = (0..pl.len())
            .filter_map(|k| {
                let (a, b) = (pl.i[k] as usize, pl.j[k] as usize);
                if a == i {
                    Some(b)
                } else if b == i {
                    Some(a)
                } else {
                    None
                }
            })
            .collect();
        let neighbours = others.len();
        // where the non-finite value came from: a state value the rates read (this particle's or
        // a neighbour's), made by the stages that write it (a legacy routine's NaN sound speed
        // shows first in the viscosity of its neighbours)
        let fields: [(Field, &[f64]); 5] = [
            (Field::Rho, &self.p.rho),
            (Field::P, &self.p.p),
            (Field::C, &self.p.c),
            (Field::E, &self.p.e),
            (Field::H, &self.p.h),
        ];
        let source = std::iter::once(i).chain(others.iter().copied()).find_map(|j| {
            fields.iter().find(|(_, a)| a.get(j).is_some_and(|v| !v.is_finite())).map(|(f, a)| (j, *f, a[j]))
        });
        let source = source.map_or(String::new(), |(j, f, v)| {
            // the stages of the step (the once-only set-up ones only when no other writes it)
            let writers = |init: bool| -> Vec<&str> {
                self.plan
                    .entries
                    .iter()
                    .filter(|e| (e.phase == crate::modules::Phase::Init) == init && e.stage.writes().contains(&f))
                    .map(|e| e.stage.name())
                    .collect()
            };
            let by = Some(writers(false)).filter(|b| !b.is_empty()).unwrap_or_else(|| writers(true));
            let who = match (j == i, self.p.id.get(j).filter(|_| j < self.p.nreal)) {
                (true, _) => "its".to_string(),
                (false, Some(id)) => format!("its neighbour {id}'s"),
                // a wall's or symmetry plane's image, which has no id of its own
                (false, None) => format!("its neighbour {j}'s (a virtual particle, a wall's image)"),
            };
            // a pressure or sound speed made from a density at or below zero (a JWL's exp(−R/η))
            let rho = self.p.rho.get(j).copied().unwrap_or(f64::NAN);
            let from = if matches!(f, Field::P | Field::C) && (rho.is_nan() || rho <= 0.0) {
                format!(", from its density {rho:e} kg/m3 (not above zero)")
            } else {
                String::new()
            };
            format!(
                "; {who} {} is {v} already (written by {}){from}",
                f.name(),
                if by.is_empty() { "the set-up".to_string() } else { by.join(", ") }
            )
        });
        Err(SphError::Unstable(format!(
            "step {} (t = {:.6e} s): particle {} (material {}) at [{}] m has a non-finite rate: {}{source} (rho = {:e} kg/m3, p = {:e} Pa, h = {:e} m, {neighbours} neighbours)",
            self.nstep,
            self.t,
            self.p.id[i],
            self.material(i),
            pos.join(", "),
            if terms.is_empty() { "gravity".to_string() } else { terms.join(", ") },
            self.p.rho[i],
            self.p.p[i],
            self.p.h[i],
        )))
    }

    /// The diagnostic of a step the CFL rule could not take: the particle that limits it.
    pub(super) fn bad_step(&self, dt: f64) -> SphError {
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let norm =
            |a: &[f64], i: usize| -> f64 { (0..dim).map(|d| a[d + dim * i] * a[d + dim * i]).sum::<f64>().sqrt() };
        let mut worst = (f64::INFINITY, 0usize);
        for i in 0..n {
            let tc = self.p.h[i] / (self.p.c[i] + norm(&self.p.v, i));
            let tf = (self.p.h[i] / norm(&self.w.dv, i)).sqrt();
            let t = if tc.is_nan() || tf.is_nan() { -1.0 } else { tc.min(tf) };
            if t < worst.0 {
                worst = (t, i);
            }
        }
        let i = worst.1;
        SphError::Unstable(format!(
            "step {} (t = {:.6e} s): time step dt = {dt:e} s; limited by particle {} (material {}): h = {:e} m, c = {:e} m/s, |v| = {:e} m/s, |a| = {:e} m/s2, rho = {:e} kg/m3, e = {:e} J/kg",
            self.nstep,
            self.t,
            self.p.id[i],
            self.material(i),
            self.p.h[i],
            self.p.c[i],
            norm(&self.p.v, i),
            norm(&self.w.dv, i),
            self.p.rho[i],
            self.p.e[i]
        ))
    }

    /// The floor of the CFL step (s): `time.dt_min_s`, else [`DT_MIN_FRACTION`] × the first step.
    pub fn dt_floor(&self) -> f64 {
        self.case.time.dt_min_s.unwrap_or(DT_MIN_FRACTION * self.dt_first)
    }

    /// The diagnostic of a step that fell below the floor: the particle that limits it.
    pub(super) fn collapsed(&self, dt: f64) -> SphError {
        let why = match self.case.time.dt_min_s {
            Some(m) => format!("time.dt_min_s = {m:e} s"),
            None => format!("time.dt_min_s, by default {DT_MIN_FRACTION:e} × the first step {:e} s", self.dt_first),
        };
        let detail = self.bad_step(dt).to_string();
        let detail = detail.split_once("; ").map_or(detail.as_str(), |(_, d)| d).to_string();
        SphError::Unstable(format!(
            "step {} (t = {:.6e} s): the time step collapsed: dt = {dt:e} s is below the floor {:e} s ({why}); {detail}",
            self.nstep,
            self.t,
            self.dt_floor()
        ))
    }

    /// Stops a CFL run whose pace makes its end unreachable: every [`PACE_WINDOW`] steps, the
    /// steps still needed at the mean step of the window are projected; beyond [`PACE_FACTOR`] ×
    /// `time.max_steps` in all, the run stops with a diagnostic (it would end at `max_steps`
    /// anyway, after hours).
    pub(super) fn check_pace(&mut self) -> Result<()> {
        if self.cfg.step != StepRule::Cfl {
            return Ok(());
        }
        let (n0, t0) = self.pace;
        let steps = self.nstep.saturating_sub(n0);
        if steps < PACE_WINDOW {
            return Ok(());
        }
        self.pace = (self.nstep, self.t);
        let mean = (self.t - t0) / steps as f64;
        let left = self.cfg.end - self.t;
        if left <= 0.0 {
            return Ok(());
        }
        let need = if mean > 0.0 { left / mean } else { f64::INFINITY };
        let limit = PACE_FACTOR * self.cfg.max_steps as f64;
        if self.nstep as f64 + need > limit {
            return Err(SphError::Unstable(format!(
                "step {} (t = {:.6e} s): at the pace of the last {steps} steps (mean dt = {mean:e} s) the run needs about {need:.3e} more steps to reach {:e} s, more than {PACE_FACTOR} × time.max_steps = {:e} in all: the end is out of reach",
                self.nstep, self.t, self.cfg.end, limit
            )));
        }
        Ok(())
    }

    /// The health of the state after a step, in one pass: stops a run that went unstable, naming
    /// the step, the particle and the quantity; else updates the statistics.
    pub(super) fn check(&mut self) -> Result<()> {
        use rayon::prelude::*;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let p = &self.p;
        let h_init = &self.h_init;
        let segs = &self.cfg.all_segs;
        let frames = &self.cfg.all_frames;
        let limit = 0.5 * self.cfg.dx_min;
        let domain = self.case.domain.as_ref();
        let chunk = |c: usize| {
            let mut q = Part::new();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                // branch-free: whether anything is wrong (which, is found below for one particle)
                let mut v2 = 0.0;
                let mut bad = false;
                for d in 0..dim {
                    bad |= !p.x[d + dim * i].is_finite() || !p.v[d + dim * i].is_finite();
                    v2 += p.v[d + dim * i] * p.v[d + dim * i];
                }
                bad |= !p.rho[i].is_finite() || p.rho[i] <= 0.0 || !p.e[i].is_finite() || !p.p[i].is_finite();
                if !p.tau.is_empty() {
                    bad |= !p.tau[NSTR * i..NSTR * i + NSTR].iter().all(|t| t.is_finite());
                }
                let r = p.h[i] / h_init[i];
                bad |= !r.is_finite() || r < H_COLLAPSE;
                if bad && q.bad.is_none() {
                    q.bad = Some(i);
                }
                q.hr = (q.hr.0.min(r), q.hr.1.max(r));
                let ke = 0.5 * p.mass[i] * v2;
                q.energy += ke + p.mass[i] * p.e[i];
                if ke > q.ke_max.0 {
                    q.ke_max = (ke, i);
                }
                let xi = &p.x[dim * i..dim * i + dim];
                for (s, fr) in frames.iter().enumerate() {
                    if let Some(depth) = behind_wall(dim, xi, segs.get(dim, s), fr) {
                        q.pen = q.pen.max(depth);
                        if depth > limit && q.crossed.is_none() {
                            q.crossed = Some((i, s, depth));
                        }
                    }
                }
                if let Some(dm) = domain
                    && (0..dim).any(|d| xi[d] < dm.lo_m[d] || xi[d] > dm.hi_m[d])
                {
                    q.out += 1;
                    q.outside = q.outside.or(Some(i));
                }
            }
            q
        };
        let parts: Vec<Part> = (0..n.div_ceil(CHUNK)).into_par_iter().map(chunk).collect();
        let all = parts.iter().fold(Part::new(), |a, q| a.then(q));
        let step = self.nstep;
        let at = format!("step {step} (t = {:.6e} s)", self.t);
        if let Some(i) = all.bad {
            let b = what_is_bad(p, dim, i, h_init[i]);
            self.stab.nan |= !matches!(b, Bad::Rho | Bad::H(_)) || !p.rho[i].is_finite();
            let (what, v) = match b {
                Bad::X(d) => (format!("x[{d}]"), p.x[d + dim * i]),
                Bad::V(d) => (format!("v[{d}]"), p.v[d + dim * i]),
                Bad::Rho => ("density".into(), p.rho[i]),
                Bad::E => ("internal energy".into(), p.e[i]),
                Bad::P => ("pressure".into(), p.p[i]),
                Bad::Tau(k) => (format!("deviatoric stress component {k}"), p.tau[k + NSTR * i]),
                Bad::H(r) => ("h/h0 (smoothing length collapsed)".into(), r),
            };
            return Err(SphError::Unstable(format!(
                "{at}: particle {} (material {}) has {what} = {v:e}",
                p.id[i],
                self.material(i)
            )));
        }
        let st = &mut self.stab;
        st.h_ratio_min = st.h_ratio_min.min(all.hr.0);
        st.h_ratio_max = st.h_ratio_max.max(all.hr.1);
        st.max_wall_penetration_m = st.max_wall_penetration_m.max(all.pen);
        st.left_domain = st.left_domain.max(all.out);
        // energy blow-up: the balance residual (energy created beyond the work of the wall,
        // penalty and gravity forces) above the energy the run has had to work with — the
        // initial energy and the external forces' work, each in magnitude (a body at rest at
        // e = 0 falling under gravity starts from 0 J: its kinetic energy is gravity's work,
        // booked half a step behind, so twice the last step's gravity work in magnitude is
        // allowed on top); healthy runs stay under 1 %
        let bk = &self.book;
        let budget = self.e_initial + bk.work();
        let scale = bk.scale(self.e_initial);
        // the last step's gravity work in magnitude at the step's end, Σ m |g·v| Δt: taken only
        // where the residual is above the rest of the scale (one pass over the particles)
        let gravity_step = || {
            let (g, v, m) = (&self.cfg.grav, &self.p.v, &self.p.mass);
            self.dt_prev
                * (0..self.p.nreal)
                    .map(|i| m[i] * (0..dim).map(|d| g[d] * v[d + dim * i]).sum::<f64>().abs())
                    .sum::<f64>()
        };
        let residual = all.energy - budget;
        if residual > scale.max(f64::MIN_POSITIVE) && residual > scale + 2.0 * gravity_step() {
            let (ke, i) = all.ke_max;
            return Err(SphError::Unstable(format!(
                "{at}: total energy {:e} J exceeds the initial {:e} J plus the work of external forces by more than the initial energy and that work together; fastest particle {} (material {}), |v| = {:e} m/s",
                all.energy,
                self.e_initial,
                self.p.id[i],
                self.material(i),
                (2.0 * ke / self.p.mass[i]).sqrt()
            )));
        }
        if let Some((i, s, depth)) = all.crossed {
            let pos: Vec<String> = (0..dim).map(|d| format!("{:.5}", self.p.x[d + dim * i])).collect();
            // in RZ the segment after the case's walls is the axis (a mirror of its own)
            let what = if self.case.axisymmetric() && s >= self.case.walls.len() {
                "the axis r = 0 (a mirror)".to_string()
            } else {
                format!("wall {s}")
            };
            return Err(SphError::Unstable(format!(
                "{at}: particle {} crossed {what} by {depth:.3e} m (x = [{}] m)",
                self.p.id[i],
                pos.join(", ")
            )));
        }
        if let (Some(i), true) = (all.outside, domain.is_some_and(|d| d.stop_on_exit)) {
            return Err(SphError::Unstable(format!(
                "{at}: particle {} (material {}) has a position outside [domain]; x[0] = {:e}",
                self.p.id[i],
                self.material(i),
                self.p.x[dim * i]
            )));
        }
        if self.nstep >= self.cfg.max_steps && self.t < self.cfg.end {
            return Err(SphError::Unstable(format!(
                "step {step}: time.max_steps reached at t = {:.6e} s before the end time",
                self.t
            )));
        }
        Ok(())
    }
}
