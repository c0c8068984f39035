//! The time step: the plan's stages, phase by phase (Liu's single_step and time_integration loop
//! body), with the solver's own work between them: the incidence lists after the search, the
//! check of the rates, the step size, the energy book-keeping, the health check.

use super::{CHUNK, Sim};
use crate::case::StepRule;
use crate::error::Result;
use crate::modules::Phase;
use crate::modules::param::NSTR;
use crate::state::Clock;

impl Sim {
    fn clock(&self, dt: f64) -> Clock {
        Clock { t: self.t, dt, dt_prev: self.dt_prev, first: self.nstep == 0 }
    }

    /// Runs every stage of phase `ph` (in a dual run, both implementations, compared).
    /// Across processes each rank computes a block of every split row loop
    /// ([`crate::modules::ranks`]); every rank runs every phase.
    pub(super) fn run_phase(&mut self, ph: Phase, dt: f64) {
        crate::modules::ranks::split(|| self.run_phase_here(ph, dt));
    }

    fn run_phase_here(&mut self, ph: Phase, dt: f64) {
        let k = self.clock(dt);
        for e in self.plan.entries.iter_mut().filter(|e| e.phase == ph) {
            e.stage.prepare(&mut self.p, &mut self.w);
            match self.cmp.as_mut() {
                None => {
                    let t0 = std::time::Instant::now();
                    e.stage.run(e.backend, &mut self.p, &mut self.w, &k);
                    e.seconds += t0.elapsed().as_secs_f64();
                }
                Some(cmp) => cmp.run(e.stage.as_ref(), &mut self.p, &mut self.w, &k, self.nstep),
            }
        }
        if ph == Phase::Search && self.plan.incidence {
            let t0 = std::time::Instant::now();
            self.w.pairs.build_incidence(self.p.ntotal);
            *self.timers.entry("incidence").or_default() += t0.elapsed().as_secs_f64();
        }
    }

    /// Evaluates every rate at the current time: the phases from the mirrors to the rate sums.
    pub fn rates(&mut self) {
        for ph in Phase::STEP.into_iter().filter(|p| (Phase::Mirrors..=Phase::Sum).contains(p)) {
            self.run_phase(ph, 0.0);
        }
    }

    /// Sorts the real particles by the cell of a grid of edge κ·min(h) (row-major cell order),
    /// carrying every per-particle array, including the half-step values and rates the next
    /// step reads. Deterministic (a stable sort).
    pub fn reorder(&mut self) {
        let t0 = std::time::Instant::now();
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        if n == 0 {
            return;
        }
        let hmin = self.p.h[..n].iter().cloned().fold(f64::INFINITY, f64::min);
        let cs = self.cfg.kappa * hmin;
        let mut lo = [0.0f64; 3];
        let mut nc = [1usize; 3];
        for d in 0..dim {
            let (a, b) = (0..n).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), i| {
                (a.min(self.p.x[d + dim * i]), b.max(self.p.x[d + dim * i]))
            });
            lo[d] = a;
            nc[d] = (((b - a) / cs) as usize + 1).min(1 << 20);
        }
        let key = |i: usize| -> usize {
            let mut k = 0usize;
            for d in (0..dim).rev() {
                let c = (((self.p.x[d + dim * i] - lo[d]) / cs) as usize).min(nc[d] - 1);
                k = k * nc[d] + c;
            }
            k
        };
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by_key(|&i| key(i as usize));
        fn perm<T: Copy>(v: &mut [T], order: &[u32], width: usize) {
            if v.len() < width * order.len() {
                return;
            }
            let old: Vec<T> = v[..width * order.len()].to_vec();
            for (new, &o) in order.iter().enumerate() {
                let o = o as usize;
                v[width * new..width * new + width].copy_from_slice(&old[width * o..width * o + width]);
            }
        }
        let p = &mut self.p;
        for a in [&mut p.x, &mut p.v] {
            perm(a, &order, dim);
        }
        for a in [&mut p.rho, &mut p.p, &mut p.c, &mut p.e, &mut p.h, &mut p.mass] {
            perm(a, &order, 1);
        }
        perm(&mut p.mat, &order, 1);
        perm(&mut p.bnd, &order, 1);
        perm(&mut p.id, &order, 1);
        perm(&mut p.tau, &order, NSTR);
        perm(&mut p.sigma0, &order, NSTR);
        for a in [&mut p.tlight, &mut p.burn, &mut p.h0, &mut p.rho0, &mut p.rho_max] {
            perm(a, &order, 1);
        }
        perm(&mut self.h_init, &order, 1);
        perm(&mut self.x_init, &order, dim);
        perm(&mut self.region, &order, 1);
        let w = &mut self.w;
        for a in [&mut w.v_min, &mut w.dv] {
            perm(a, &order, dim);
        }
        for a in [&mut w.rho_min, &mut w.e_min, &mut w.de, &mut w.drho, &mut w.dhdt] {
            perm(a, &order, 1);
        }
        for a in [&mut w.tau_min, &mut w.dtau] {
            perm(a, &order, NSTR);
        }
        for (k, &id) in self.p.id[..n].iter().enumerate() {
            self.index_of_id[id as usize] = k as u32;
        }
        self.w.pairs.invalidate();
        *self.timers.entry("reorder").or_default() += t0.elapsed().as_secs_f64();
    }

    /// One leapfrog step. Returns the step taken (s).
    pub fn step(&mut self) -> Result<f64> {
        let every = self.case.sph.reorder_every;
        if every > 0 && self.nstep > 0 && self.nstep.is_multiple_of(every) {
            self.reorder();
        }
        if self.nstep > 0 {
            self.run_phase(Phase::Predict, 0.0);
        }
        self.rates();
        // the step the rule proposes, before it is cut to the end of the run
        let mut proposed = f64::INFINITY;
        let dt = match self.cfg.step {
            StepRule::Fixed => self.cfg.dt_fixed,
            StepRule::Cfl => {
                self.run_phase(Phase::StepSize, 0.0);
                // (a NaN stays NaN, for the diagnostic below)
                let dt = self.w.dt_cfl[0];
                let dt = if dt > self.cfg.dt_max { self.cfg.dt_max } else { dt };
                proposed = dt;
                if self.nstep == 0 {
                    self.dt_first = dt;
                }
                // shortened to land on the next output time or the end (a step within 1e-6 of
                // its own length short of it is stretched onto it: no sliver step follows)
                let left = self.next_landing() - self.t;
                if dt >= left * (1.0 - 1e-6) { left } else { dt }
            }
        };
        self.check_rates()?;
        if dt.is_nan() || dt <= 0.0 || !dt.is_finite() {
            return Err(self.bad_step(dt));
        }
        if proposed < self.dt_floor() {
            return Err(self.collapsed(proposed));
        }
        self.account(dt);
        self.run_phase(Phase::Advance, dt);
        self.run_phase(Phase::Correct, dt);
        if self.plan.has("integrator.efloor") {
            // the energy the floor e ≥ 0 added (theory.md §14)
            self.book.work_floor += self.w.efloor[0];
        }
        // a step that lands on an output time or the end sets the clock to it exactly
        let target = self.next_landing();
        self.t = if self.cfg.step == StepRule::Cfl && dt == target - self.t { target } else { self.t + dt };
        self.dt_prev = dt;
        self.nstep += 1;
        self.check()?;
        self.check_pace()?;
        Ok(dt)
    }

    /// The time the next step must not pass (s): the first output time k·Δt_out after the clock
    /// (k a whole number, Δt_out = `time.output_interval_s`), or the end, whichever is sooner. A
    /// clock within 1e-9 Δt_out of an output time counts as on it.
    pub fn next_landing(&self) -> f64 {
        let (end, every) = (self.cfg.end, self.cfg.out_interval);
        if !(every > 0.0 && every.is_finite()) {
            return end;
        }
        let k = (self.t / every + 1e-9).floor() + 1.0;
        (k * every).min(end)
    }

    /// Work of the wall (type I and absorbing), penalty and gravity forces over the step (v at
    /// t), and the energy the held boundary particles hand to the others. One parallel pass;
    /// the sums are taken per fixed chunk of particles, then over the chunks in order, so they
    /// do not depend on the thread count.
    ///
    /// A held particle's forces are not applied, so it does no external work; no boundary
    /// particle takes gravity. The pair sums conserve Σ m (v·a + ė) over all particles, so the
    /// others gain what the held ones are given and do not keep: −Σ_held m (v·a_pair + ė) Δt,
    /// with a_pair the summed acceleration less the wall and penalty terms (J).
    fn account(&mut self, dt: f64) {
        use rayon::prelude::*;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let lda = dim * self.p.ntotal;
        let (acc, v, m, g) = (&self.w.acc, &self.p.v, &self.p.mass, &self.cfg.grav);
        let bnd = &self.p.bnd;
        let kind = |i: usize| bnd.get(i).copied().unwrap_or(0);
        let held = crate::case::BoundaryKind::Held as i32;
        let slot = |name: &str| self.plan.acc_slot(name).map(|s| &acc[s * lda..s * lda + dim * n]);
        let (fw, fp, fa, fr) =
            (slot("boundary.wall_force"), slot("penalty.force"), slot("absorb.dashpot"), slot("boundary.repulsion"));
        let ext = [fw, fa, fp, fr];
        // under `physics.gravity_in_forces` the repulsion stage adds the gravity itself, to
        // every particle (an integrated boundary particle too): its work is gravity's
        let in_forces = self.case.physics.gravity_in_forces;
        // v_i · f_i from +0 over the components
        let dot = |f: &[f64], i: usize| -> f64 {
            let mut s = 0.0;
            for d in 0..dim {
                s += f[d + dim * i] * v[d + dim * i];
            }
            s
        };
        // without gravity every term of its sum is +0 (the check stops a run with a non-finite v)
        let gravity = g[..dim].iter().any(|&x| x != 0.0);
        let (dv, de) = (&self.w.dv, &self.w.de);
        let parts: Vec<[f64; 4]> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut t = [0.0; 4];
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let k = kind(i);
                    if k == held {
                        // the pair part of its rates, v·(a − wall − penalty − repulsion) + ė
                        let mut a = dot(dv, i);
                        for f in ext.iter().flatten() {
                            a -= dot(f, i);
                        }
                        t[3] -= m[i] * (a + de[i]);
                        continue;
                    }
                    let mut gv = 0.0;
                    for d in 0..dim {
                        gv += g[d] * v[d + dim * i];
                    }
                    // the absorbing walls' dampers and static reaction, and the boundary
                    // particles' repulsion (less the gravity it carries): wall work too
                    if let Some(f) = fw {
                        t[0] += m[i] * dot(f, i);
                    }
                    if let Some(f) = fa {
                        t[0] += m[i] * dot(f, i);
                    }
                    if let Some(f) = fr {
                        t[0] += m[i] * if in_forces { dot(f, i) - gv } else { dot(f, i) };
                    }
                    if let Some(f) = fp {
                        t[1] += m[i] * dot(f, i);
                    }
                    if gravity && (k == 0 || in_forces) {
                        t[2] += m[i] * gv;
                    }
                }
                t
            })
            .collect();
        let tot = parts.iter().fold([0.0; 4], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2], a[3] + p[3]]);
        self.book.work_wall += dt * tot[0];
        self.book.work_penalty += dt * tot[1];
        self.book.work_gravity += dt * tot[2];
        self.book.work_boundary += dt * tot[3];
    }
}
