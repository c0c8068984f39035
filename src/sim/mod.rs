//! The solver: owns the state and the time loop. The case's plan ([`plan`]) is the ordered list of
//! stages a step runs; the step (`step`) runs it, each stage with the implementation the plan
//! chose; the health checks (`health`) stop a run that went unstable. In a dual run
//! ([`crate::dual`]) every stage runs both implementations on identical inputs, their outputs are
//! compared, and the run continues with the Fortran result.

pub mod checkpoint;
mod config;
pub mod geostatic;
mod health;
pub mod hook;
pub mod plan;
mod step;

pub use crate::modules::boundary::walls::behind_wall;
pub use checkpoint::Blob;
pub use config::{Config, Frame};
pub use hook::{Bridge, Hook};
pub use plan::{Overrides, Plan};

use crate::case::{Case, NnpsKind};
use crate::dual::Comparator;
use crate::error::{Result, input};
use crate::modules::param::{NSTR, SPH_MP_SHEAR};
use crate::modules::{Phase, PlanCtx};
use crate::setup;
use crate::state::{Particles, Work};
use std::collections::BTreeMap;

/// Particles per chunk of the solver's own parallel passes (fixed, so that their sums do not
/// depend on the thread count).
const CHUNK: usize = 1024;

/// Energy book-keeping (J; per metre of depth in 2D).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Book {
    /// Work done on the particles by the walls: the type I force, and the dampers and static
    /// reaction of absorbing walls.
    pub work_wall: f64,
    /// Work done by the penalty force.
    pub work_penalty: f64,
    /// Work done by gravity.
    pub work_gravity: f64,
    /// Energy added by the floor e ≥ 0 (`sph.e_floor`; theory.md §14).
    pub work_floor: f64,
    /// Energy the held boundary particles hand to the others (theory.md, "Boundary
    /// particles"): −Σ m (v·a + ė) Δt over the held particles, with a and ė the rates their
    /// pair sums give them, which the leapfrog computes and does not apply.
    pub work_boundary: f64,
}

impl Book {
    /// The external forces' work and the floor's energy together (J): what the total energy
    /// changes by, E − E0.
    pub fn work(&self) -> f64 {
        self.work_wall + self.work_penalty + self.work_gravity + self.work_floor + self.work_boundary
    }

    /// The energy a run has had to work with (J): |E0| plus each work in magnitude (a body at
    /// rest at e = 0 under gravity starts from 0 J); the scale of the energy balance's residual.
    pub fn scale(&self, e0: f64) -> f64 {
        e0.abs()
            + self.work_wall.abs()
            + self.work_penalty.abs()
            + self.work_gravity.abs()
            + self.work_floor.abs()
            + self.work_boundary.abs()
    }
}

/// Health of the run, reported in summary.json.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Stability {
    /// Deepest position of a real particle behind a wall line (m; 0 = none crossed).
    pub max_wall_penetration_m: f64,
    /// Particles counted outside `[domain]` (if the case has one).
    pub left_domain: usize,
    /// Smallest and largest h/h_initial seen.
    pub h_ratio_min: f64,
    pub h_ratio_max: f64,
    /// Closest approach of particles of different penalty groups, in units of the finest initial
    /// spacing (checked at every output).
    pub min_interface_gap_dx: Option<f64>,
    /// Most neighbours of one particle at the last output, and the mean.
    pub max_neighbours: usize,
    pub mean_neighbours: f64,
    pub nan: bool,
}

pub struct Sim {
    pub case: Case,
    pub cfg: Config,
    pub plan: Plan,
    pub p: Particles,
    pub w: Work,
    pub t: f64,
    pub nstep: u64,
    pub dt_prev: f64,
    pub book: Book,
    pub stab: Stability,
    /// Initial smoothing length of each real particle.
    pub h_init: Vec<f64>,
    /// Region of each real particle.
    pub region: Vec<u32>,
    /// Initial positions of the real particles (m).
    pub x_init: Vec<f64>,
    /// Kinetic + internal energy at t = 0 (J; per metre of depth in 2D).
    pub e_initial: f64,
    /// Current index of the real particle of each id (particles move in memory when reordered).
    pub index_of_id: Vec<u32>,
    /// Set in a dual run.
    pub cmp: Option<Comparator>,
    /// Wall time of the solver's own work outside the stages (s), by name ("incidence", "reorder").
    pub timers: BTreeMap<&'static str, f64>,
    /// The first step the CFL rule proposed (s; 0 before it): the default floor of the step is a
    /// fraction of it ([`crate::case::DT_MIN_FRACTION`]).
    pub dt_first: f64,
    /// Where the current window of the progress check began: (step, time s).
    pub pace: (u64, f64),
}

impl Sim {
    pub fn new(case: Case, ov: &Overrides) -> Result<Sim> {
        let mut case = case;
        if let Some(t) = ov.end_time {
            let max = crate::case::validate::T_MAX;
            if !(t.is_finite() && t > 0.0 && t <= max) {
                return Err(input(format!("--end-time {t}: must be a positive time in seconds, at most {max:e}")));
            }
            case.time.end_s = t;
            // what depends on the end (fixed steps against max_steps, the number of outputs)
            case.validate().map_err(|e| input(format!("--end-time {t}: {e}")))?;
        }
        if let Some(n) = &ov.nnps {
            case.sph.nnps = match n.as_str() {
                "direct" => NnpsKind::Direct,
                "cell" => NnpsKind::Cell,
                _ => return Err(input(format!("--nnps {n}: must be direct or cell"))),
            };
        }
        let choice = plan::choices(&case, ov)?;
        // the layer the caller attaches sees the case first (it may edit its numbers)
        let hook = match &ov.bridge {
            Some(b) => Some(b.attach(&mut case)?),
            None if !case.compat.is_empty() => {
                return Err(input(
                    "[compat]: this build of blastsph has no legacy bridge to read it (cargo feature `legacy`)",
                ));
            }
            None => None,
        };
        let mut init = setup::particles_limited(&case, ov.max_particles)?;
        if let Some(h) = &hook {
            init = h.setup(&case, init)?;
        }
        let dim = case.dim;
        let n = init.mass.len();
        let mt = setup::material_table(&case);
        let tau0 = geostatic::apply(&case, &mt, &mut init);
        let kappa = case.sph.kernel.support();
        let ctx = PlanCtx { case: &case, dim, mt: &mt, kappa, dx_min: init.dx_min, x0: &init.x, h0: &init.h };
        let plan = Plan::build_with(&ctx, &choice, hook.as_deref());
        if case.physics.gravity_in_forces && plan.legacy.is_null() {
            return Err(input(
                "physics.gravity_in_forces = true: only a --legacy build whose manifest marks a routine includes_gravity may set it; without one the run would have no gravity",
            ));
        }
        let cfg = Config::new(&case, mt, &init.x, init.dx_min);
        let bnd = std::mem::take(&mut init.bnd);
        let mut p = Particles {
            dim,
            nreal: n,
            ntotal: n,
            x: init.x,
            v: init.v,
            rho: init.rho,
            p: vec![0.0; n],
            c: vec![0.0; n],
            e: init.e,
            h: init.h,
            mass: init.mass,
            mat: init.mat,
            id: (0..n as i64).collect(),
            ..Default::default()
        };
        if !bnd.is_empty() {
            p.bnd = bnd;
        } else if case.regions.iter().any(|r| r.boundary_particles.is_some()) {
            p.bnd = crate::setup::boundary_kinds(&case, &init.region);
        }
        // boundary particles come from the case's regions or from a legacy set-up (virt_part);
        // under a legacy build the stage may stand for an ext_force with gravity alone
        if case.boundary.repulsion.is_some() && plan.legacy.is_null() && !p.bnd.iter().any(|&k| k != 0) {
            return Err(input(
                "boundary.repulsion: the case has no boundary particles to push off (give a region boundary_particles = \"held\" or \"integrated\", or map a legacy virt_part)",
            ));
        }
        for e in &plan.entries {
            e.stage.register(&mut p);
        }
        if let Some(t) = tau0
            && p.tau.len() >= t.len()
        {
            p.tau[..t.len()].copy_from_slice(&t);
        }
        let h_init = p.h.clone();
        let x_init = p.x.clone();
        let mut sim = Sim {
            case,
            cfg,
            plan,
            p,
            w: Work::default(),
            t: 0.0,
            nstep: 0,
            dt_prev: 0.0,
            book: Book::default(),
            stab: Stability { h_ratio_min: 1.0, h_ratio_max: 1.0, ..Default::default() },
            h_init,
            x_init,
            e_initial: 0.0,
            index_of_id: (0..n as u32).collect(),
            region: init.region,
            cmp: None,
            timers: BTreeMap::new(),
            dt_first: 0.0,
            pace: (0, 0.0),
        };
        sim.run_phase(Phase::Init, 0.0);
        let (ke, ie, _) = sim.energies();
        sim.e_initial = ke + ie;
        Ok(sim)
    }

    /// Turns on the dual run: every stage runs both implementations (the set-up stages again, so
    /// that they are compared too).
    pub fn enable_dual(&mut self, cmp: Comparator) {
        self.cmp = Some(cmp);
        self.plan.incidence = true;
        self.run_phase(Phase::Init, 0.0);
    }

    /// Closest approach of particles of different penalty groups (in units of the finest spacing),
    /// and neighbour counts, from the current pair list.
    pub fn interface_stats(&mut self) {
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let pl = &self.w.pairs;
        let mut cnt = vec![0usize; self.p.ntotal.max(n)];
        let mut gap = f64::INFINITY;
        let multi = self.cfg.mt.group.iter().collect::<std::collections::BTreeSet<_>>().len() > 1;
        for k in 0..pl.len() {
            let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
            if i < cnt.len() {
                cnt[i] += 1;
            }
            if j < cnt.len() {
                cnt[j] += 1;
            }
            let (gi, gj) = (self.cfg.mt.group[self.p.mat[i] as usize], self.cfg.mt.group[self.p.mat[j] as usize]);
            if multi && j < n && gi != gj && gi >= 0 && gj >= 0 {
                let mut r2 = 0.0;
                for d in 0..dim {
                    let dx = self.p.x[d + dim * i] - self.p.x[d + dim * j];
                    r2 += dx * dx;
                }
                gap = gap.min(r2.sqrt());
            }
        }
        self.stab.max_neighbours = cnt[..n].iter().copied().max().unwrap_or(0);
        self.stab.mean_neighbours = cnt[..n].iter().sum::<usize>() as f64 / n.max(1) as f64;
        if gap.is_finite() {
            let g = gap / self.cfg.dx_min;
            self.stab.min_interface_gap_dx = Some(self.stab.min_interface_gap_dx.map_or(g, |x: f64| x.min(g)));
        }
    }

    /// Kinetic, internal and elastic energy of the real particles (J; per metre of depth in 2D).
    pub fn energies(&self) -> (f64, f64, f64) {
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let mut ke = 0.0;
        let mut ie = 0.0;
        let mut el = 0.0;
        let shear = SPH_MP_SHEAR as usize - 1;
        for i in 0..n {
            let m = self.p.mass[i];
            let v2: f64 = (0..dim).map(|d| self.p.v[d + dim * i] * self.p.v[d + dim * i]).sum();
            ke += 0.5 * m * v2;
            ie += m * self.p.e[i];
            if !self.p.tau.is_empty() {
                let g = self.cfg.mt.column(self.p.mat[i] as usize)[shear];
                if g > 0.0 {
                    let t = &self.p.tau[NSTR * i..NSTR * i + NSTR];
                    let tt = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + 2.0 * (t[3] * t[3] + t[4] * t[4] + t[5] * t[5]);
                    el += m / self.p.rho[i] * tt / (4.0 * g);
                }
            }
        }
        (ke, ie, el)
    }

    pub fn total_mass(&self) -> f64 {
        self.p.mass[..self.p.nreal].iter().sum()
    }

    /// Seconds per module and per piece of the solver's own work (summary.json `module_seconds`).
    pub fn seconds(&self) -> BTreeMap<String, f64> {
        let mut s: BTreeMap<String, f64> =
            self.plan.module_seconds().into_iter().map(|(m, t)| (m.name().to_string(), t)).collect();
        for (k, t) in &self.timers {
            s.insert(k.to_string(), *t);
        }
        s
    }
}
