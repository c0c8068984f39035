//! The solver: owns the state and the time loop, and calls each module through its dispatch
//! function with the implementation the plan chose. In a dual run ([`crate::dual`]) every module
//! call runs both implementations on identical inputs, compares their outputs, and continues with
//! the Fortran result.

use crate::case::{Case, DensityKind, NnpsKind, SmoothingKind, StepRule, WallKind};
use crate::dual::Comparator;
use crate::error::{Result, SphError, input};
use crate::legacy::{MatTable, MirrorArrays, NSTR, Segments};
use crate::modules::{self as md, Backend, Choice, Module};
use crate::setup;
use crate::state::{Particles, Work};

/// What runs: one flag and one implementation per module, and why.
#[derive(Debug, Clone)]
pub struct Plan {
    pub active: [bool; 13],
    pub why: [String; 13],
    pub choice: Choice,
}

impl Plan {
    pub fn is_active(&self, m: Module) -> bool {
        self.active[idx(m)]
    }
    pub fn backend(&self, m: Module) -> Backend {
        self.choice.get(m)
    }
    /// "fortran", "rust" or "mixed" over the active modules.
    pub fn label(&self) -> &'static str {
        let mut f = false;
        let mut r = false;
        for m in Module::ALL {
            if self.is_active(m) {
                match self.backend(m) {
                    Backend::Fortran => f = true,
                    Backend::Rust => r = true,
                }
            }
        }
        match (f, r) {
            (true, false) => "fortran",
            (false, true) => "rust",
            _ => "mixed",
        }
    }
}

fn idx(m: Module) -> usize {
    Module::ALL.iter().position(|x| *x == m).unwrap_or(0)
}

/// The leapfrog's staggered variables, their rates, the XSPH correction (empty when off) and the
/// positions of the first `n` particles, borrowed from the state.
fn leapfrog_parts<'a>(
    p: &'a mut Particles,
    w: &'a mut Work,
    dim: usize,
    n: usize,
    ntau: usize,
) -> (crate::legacy::Leapfrog<'a>, crate::legacy::Rates<'a>, &'a [f64], &'a mut [f64]) {
    let Work { rho_min, e_min, v_min, tau_min, drho, de, dv, dtau, av, .. } = w;
    let s = crate::legacy::Leapfrog {
        rho: &mut p.rho[..n],
        e: &mut p.e[..n],
        v: &mut p.v[..dim * n],
        tau: &mut p.tau[..ntau],
        rho_min,
        e_min,
        v_min,
        tau_min,
    };
    let r = crate::legacy::Rates { drho: &drho[..n], de, dv, dtau: &dtau[..ntau] };
    let av: &[f64] = if av.is_empty() { &[] } else { &av[..dim * n] };
    (s, r, av, &mut p.x[..dim * n])
}

/// Particles per chunk of the solver's own parallel passes (fixed, so that their sums do not
/// depend on the thread count).
const CHUNK: usize = 1024;

/// Terms of the acceleration sum, in the order they are added.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccTerm {
    Force,
    Viscosity,
    Penalty,
    Wall,
}

/// Terms of the energy-rate sum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeTerm {
    Force,
    Viscosity,
    Strength,
}

/// Everything the step needs from the case, resolved once.
#[derive(Debug, Clone)]
pub struct Config {
    pub dim: usize,
    pub kernel: crate::case::KernelKind,
    pub kappa: f64,
    pub cell: bool,
    pub summation: bool,
    pub smoothing: SmoothingKind,
    pub theta: f64,
    pub xsph_eps: f64,
    pub visc: (f64, f64, f64),
    pub penalty: (f64, i32, i32),
    pub mt: MatTable,
    pub mirror_segs: Segments,
    pub wall_segs: Segments,
    pub all_segs: Segments,
    /// Unit tangent, length and normal of each of `all_segs` (for the penetration checks).
    pub all_frames: Vec<([f64; 3], f64, [f64; 3])>,
    pub wall: (f64, f64, f64, i32, i32),
    pub noslip: bool,
    pub grav: Vec<f64>,
    pub step: StepRule,
    pub dt_fixed: f64,
    pub cfl: f64,
    pub dt_max: f64,
    pub end: f64,
    pub out_interval: f64,
    pub det_point: Vec<f64>,
    pub det_width: f64,
    pub acc_terms: Vec<AccTerm>,
    pub de_terms: Vec<DeTerm>,
    pub dx_min: f64,
    pub need_drho: bool,
    pub max_steps: u64,
}

impl Config {
    pub fn acc_slot(&self, t: AccTerm) -> usize {
        self.acc_terms.iter().position(|x| *x == t).unwrap_or(usize::MAX)
    }
    pub fn de_slot(&self, t: DeTerm) -> usize {
        self.de_terms.iter().position(|x| *x == t).unwrap_or(usize::MAX)
    }
}

/// Energy book-keeping (J; per metre of depth in 2D).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Book {
    /// Work done on the particles by the type I wall force.
    pub work_wall: f64,
    /// Work done by the penalty force.
    pub work_penalty: f64,
    /// Work done by gravity.
    pub work_gravity: f64,
}

/// Health of the run, reported in summary.json.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Stability {
    /// Deepest position of a real particle behind a wall line (m; 0 = none crossed).
    pub max_wall_penetration_m: f64,
    /// Particles counted outside [domain] (if the case has one).
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
    /// Wall time spent in each module (s), in Module::ALL order, plus the solver's own work.
    pub timers: [f64; 14],
    need_incidence: bool,
}

/// Backend choices from the CLI, applied over the case's [backend] table.
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    pub backend: Option<Backend>,
    pub rust: Vec<String>,
    pub fortran: Vec<String>,
    pub nnps: Option<String>,
    pub end_time: Option<f64>,
}

pub fn plan(case: &Case, ov: &Overrides) -> Result<Plan> {
    // the Rust twins by default: bitwise equal to the legacy core and several times faster
    let mut choice = Choice::all(Backend::Rust);
    if let Some(d) = &case.backend.default {
        choice = Choice::all(Backend::parse(d).unwrap_or(Backend::Fortran));
    }
    for m in &case.backend.rust {
        choice
            .set(Module::parse(m).ok_or_else(|| input(format!("backend.rust: unknown module `{m}`")))?, Backend::Rust);
    }
    for m in &case.backend.fortran {
        choice.set(
            Module::parse(m).ok_or_else(|| input(format!("backend.fortran: unknown module `{m}`")))?,
            Backend::Fortran,
        );
    }
    if let Some(b) = ov.backend {
        choice = Choice::all(b);
    }
    for (list, b, flag) in [(&ov.rust, Backend::Rust, "--rust"), (&ov.fortran, Backend::Fortran, "--fortran")] {
        for m in list {
            let m = m.trim();
            let mm = Module::parse(m)
                .ok_or_else(|| input(format!("{flag}: unknown module `{m}` (modules: {})", Module::names())))?;
            choice.set(mm, b);
        }
    }
    let mut active = [true; 13];
    let mut why: [String; 13] = Default::default();
    let set = |active: &mut [bool; 13], why: &mut [String; 13], m: Module, on: bool, w: String| {
        active[idx(m)] = on;
        why[idx(m)] = w;
    };
    let mirrors = case.walls.iter().any(|w| w.kind != WallKind::Repulsive);
    let rep = case.walls.iter().any(|w| w.kind != WallKind::Mirror);
    set(
        &mut active,
        &mut why,
        Module::Boundary,
        !case.walls.is_empty(),
        match (mirrors, rep) {
            (true, true) => "walls: type I force and type II mirrors".into(),
            (true, false) => "walls: type II mirrors".into(),
            (false, true) => "walls: type I force".into(),
            _ => "no walls".into(),
        },
    );
    set(&mut active, &mut why, Module::Nnps, true, format!("{:?} search", case.sph.nnps).to_lowercase());
    set(
        &mut active,
        &mut why,
        Module::Kernel,
        true,
        format!("{} kernel, support {}h", case.sph.kernel.name(), case.sph.kernel.support()),
    );
    let dens = match case.sph.density {
        DensityKind::Summation => "summation".to_string(),
        DensityKind::Continuity => format!("continuity, {:?} form", case.sph.continuity_form).to_lowercase(),
    };
    set(&mut active, &mut why, Module::Density, true, dens);
    let prog = setup::programmed(case);
    set(
        &mut active,
        &mut why,
        Module::Detonation,
        prog,
        if prog {
            "programmed burn".into()
        } else if case.detonation.is_some() {
            "instantaneous burn: nothing to run".into()
        } else {
            "no charge lit".into()
        },
    );
    let kinds: Vec<&str> = case.materials.iter().map(|m| m.eos.kind()).collect();
    set(&mut active, &mut why, Module::Eos, true, kinds.join(", "));
    let st = setup::has_strength(case);
    set(
        &mut active,
        &mut why,
        Module::Strength,
        st,
        if st { "materials with strength present".into() } else { "fluids only: no stress arrays".into() },
    );
    set(
        &mut active,
        &mut why,
        Module::Force,
        true,
        if st { "sigma = -p I + tau".into() } else { "pressure only".into() },
    );
    let visc = case.viscosity.alpha > 0.0 || case.viscosity.beta > 0.0;
    set(
        &mut active,
        &mut why,
        Module::Viscosity,
        visc,
        format!("alpha = {}, beta = {}", case.viscosity.alpha, case.viscosity.beta),
    );
    let mt = setup::material_table(case);
    let used: std::collections::BTreeSet<i32> =
        case.regions.iter().filter_map(|r| case.material_index(&r.material)).map(|m| mt.group[m]).collect();
    let pen = case.penalty.is_some() && used.len() > 1;
    set(
        &mut active,
        &mut why,
        Module::Penalty,
        pen,
        if pen {
            format!("{} penalty groups", used.len())
        } else if case.penalty.is_some() {
            "one material group: nothing to push apart".into()
        } else {
            "no [penalty]".into()
        },
    );
    let xs = case.sph.xsph_eps > 0.0;
    set(&mut active, &mut why, Module::Xsph, xs, format!("eps = {}", case.sph.xsph_eps));
    let sm = case.sph.smoothing != SmoothingKind::Constant;
    set(&mut active, &mut why, Module::Smoothing, sm, format!("{:?}", case.sph.smoothing).to_lowercase());
    set(&mut active, &mut why, Module::Integrator, true, format!("leapfrog, {:?} step", case.time.step).to_lowercase());
    Ok(Plan { active, why, choice })
}

impl Sim {
    pub fn new(case: Case, ov: &Overrides) -> Result<Sim> {
        let mut case = case;
        if let Some(t) = ov.end_time {
            if t.is_nan() || t <= 0.0 {
                return Err(input(format!("--end-time {t}: must be positive")));
            }
            case.time.end_s = t;
        }
        if let Some(n) = &ov.nnps {
            case.sph.nnps = match n.as_str() {
                "direct" => NnpsKind::Direct,
                "cell" => NnpsKind::Cell,
                _ => return Err(input(format!("--nnps {n}: must be direct or cell"))),
            };
        }
        let plan = plan(&case, ov)?;
        let init = setup::particles(&case)?;
        let dim = case.dim;
        let n = init.mass.len();
        let mt = setup::material_table(&case);
        let mirror_segs = setup::segments(&case, &init.x, |k| k != WallKind::Repulsive);
        let wall_segs = setup::segments(&case, &init.x, |k| k != WallKind::Mirror);
        let all_segs = setup::segments(&case, &init.x, |_| true);
        let strength = plan.is_active(Module::Strength);
        let mut acc_terms = vec![AccTerm::Force];
        let mut de_terms = vec![DeTerm::Force];
        if plan.is_active(Module::Viscosity) {
            acc_terms.push(AccTerm::Viscosity);
            de_terms.push(DeTerm::Viscosity);
        }
        if strength {
            de_terms.push(DeTerm::Strength);
        }
        if plan.is_active(Module::Penalty) {
            acc_terms.push(AccTerm::Penalty);
        }
        if !wall_segs.is_empty() {
            acc_terms.push(AccTerm::Wall);
        }
        let b = &case.boundary;
        let pen = case.penalty.as_ref().map(|p| (p.pbar, p.n1, p.n2)).unwrap_or((0.0, 12, 6));
        let cfg = Config {
            dim,
            kernel: case.sph.kernel,
            kappa: case.sph.kernel.support(),
            cell: case.sph.nnps == NnpsKind::Cell,
            summation: case.sph.density == DensityKind::Summation,
            smoothing: case.sph.smoothing,
            theta: case.sph.theta,
            xsph_eps: case.sph.xsph_eps,
            visc: (case.viscosity.alpha, case.viscosity.beta, case.viscosity.phi_over_h),
            penalty: pen,
            mt,
            mirror_segs,
            wall_segs,
            all_frames: (0..all_segs.len())
                .map(|s| md::boundary::frame(dim, &all_segs.seg[3 * dim * s..3 * dim * (s + 1)]))
                .collect(),
            all_segs,
            wall: (
                b.wall_spacing_m.unwrap_or(0.25 * init.dx_min),
                b.r0_m.unwrap_or(0.5 * init.dx_min),
                b.d_m2s2,
                b.n1,
                b.n2,
            ),
            noslip: b.noslip,
            grav: case.physics.gravity_ms2.clone().unwrap_or_else(|| vec![0.0; dim]),
            step: case.time.step,
            dt_fixed: case.time.dt_s.unwrap_or(0.0),
            cfl: case.time.cfl,
            dt_max: case.time.dt_max_s.unwrap_or(f64::INFINITY),
            end: case.time.end_s,
            out_interval: case.time.output_interval_s,
            det_point: case.detonation.as_ref().and_then(|d| d.point_m.clone()).unwrap_or_default(),
            det_width: case.detonation.as_ref().map(|d| d.width_h).unwrap_or(0.0),
            acc_terms,
            de_terms,
            dx_min: init.dx_min,
            need_drho: case.sph.density == DensityKind::Continuity || case.sph.smoothing == SmoothingKind::Rate,
            max_steps: case.time.max_steps,
        };
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
        if strength {
            p.tau = vec![0.0; NSTR * n];
        }
        if cfg.smoothing == SmoothingKind::Density {
            p.h0 = p.h.clone();
            p.rho0 = p.rho.clone();
        }
        let need_incidence = Module::ALL.iter().any(|m| plan.is_active(*m) && plan.backend(*m) == Backend::Rust);
        let h_init = p.h.clone();
        let p_x_init = p.x.clone();
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
            x_init: p_x_init,
            e_initial: 0.0,
            index_of_id: (0..n as u32).collect(),
            region: init.region,
            cmp: None,
            timers: [0.0; 14],
            need_incidence,
        };
        if sim.plan.is_active(Module::Detonation) {
            sim.p.tlight = vec![0.0; n];
            sim.p.burn = vec![0.0; n];
            let b = sim.plan.backend(Module::Detonation);
            let dim = sim.cfg.dim;
            md::detonation::light(b, dim, &sim.p.x, &sim.p.mat, &sim.cfg.mt, &sim.cfg.det_point, &mut sim.p.tlight);
            md::detonation::burn(
                b,
                0.0,
                &sim.p.mat,
                &sim.cfg.mt,
                &sim.p.tlight,
                &sim.p.h,
                sim.cfg.det_width,
                &mut sim.p.burn,
            );
        }
        let b = sim.plan.backend(Module::Eos);
        md::eos::eval(b, &sim.cfg.mt, &sim.p.mat, &sim.p.burn, &sim.p.rho, &sim.p.e, &mut sim.p.p, &mut sim.p.c);
        let (ke, ie, _) = sim.energies();
        sim.e_initial = ke + ie;
        Ok(sim)
    }

    /// Turns on the dual run: every module call runs both implementations.
    pub fn enable_dual(&mut self, cmp: Comparator) {
        use crate::dual::Field as F;
        self.cmp = Some(cmp);
        self.need_incidence = true;
        // the set-up calls of Sim::new, run again so that they are compared too
        let (dim, n) = (self.cfg.dim, self.p.nreal);
        if self.plan.is_active(Module::Detonation) {
            self.exec(Module::Detonation, &[F::Tlight, F::Burn], |b, p, _, c| {
                md::detonation::light(b, dim, &p.x[..dim * n], &p.mat[..n], &c.mt, &c.det_point, &mut p.tlight);
                md::detonation::burn(b, 0.0, &p.mat[..n], &c.mt, &p.tlight, &p.h[..n], c.det_width, &mut p.burn);
            });
        }
        self.exec(Module::Eos, &[F::P, F::C], |b, p, _, c| {
            let (pp, cc) = (&mut p.p, &mut p.c);
            md::eos::eval(b, &c.mt, &p.mat[..n], &p.burn, &p.rho[..n], &p.e[..n], &mut pp[..n], &mut cc[..n]);
        });
    }

    /// Runs module `m` through `f`. In a dual run, `f` runs twice (Rust, then Fortran on the same
    /// inputs) and the fields `outs` are compared; the Fortran result is kept.
    fn exec<F>(&mut self, m: Module, outs: &[crate::dual::Field], f: F)
    where
        F: Fn(Backend, &mut Particles, &mut Work, &Config),
    {
        match self.cmp.as_mut() {
            None => {
                let t0 = std::time::Instant::now();
                f(self.plan.choice.get(m), &mut self.p, &mut self.w, &self.cfg);
                self.timers[idx(m)] += t0.elapsed().as_secs_f64();
            }
            Some(cmp) => {
                let before = crate::dual::snapshot(&self.p, &self.w, outs);
                f(Backend::Rust, &mut self.p, &mut self.w, &self.cfg);
                let rust = crate::dual::snapshot(&self.p, &self.w, outs);
                crate::dual::restore(&mut self.p, &mut self.w, outs, before);
                f(Backend::Fortran, &mut self.p, &mut self.w, &self.cfg);
                cmp.compare(self.nstep, m, outs, &rust, &self.p, &self.w);
            }
        }
    }

    /// Evaluates every rate at the current time (Liu's single_step).
    pub fn rates(&mut self) {
        use crate::dual::Field as F;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        // 1. mirrors
        if self.plan.is_active(Module::Boundary) && !self.cfg.mirror_segs.is_empty() {
            self.exec(Module::Boundary, &[F::Gsrc, F::Gseg], |b, p, w, c| {
                md::boundary::mirror_make(
                    b,
                    dim,
                    &p.x[..dim * n],
                    &p.h[..n],
                    c.kappa,
                    &c.mirror_segs,
                    &mut w.gsrc,
                    &mut w.gseg,
                );
            });
            let nt = n + self.w.gsrc.len();
            self.p.set_ntotal(nt);
            self.exec(
                Module::Boundary,
                &[F::X, F::V, F::Rho, F::P, F::C, F::E, F::H, F::Mass, F::Mat, F::Tau],
                |b, p, w, c| {
                    let a = MirrorArrays {
                        x: &mut p.x,
                        v: &mut p.v,
                        rho: &mut p.rho,
                        p: &mut p.p,
                        c: &mut p.c,
                        e: &mut p.e,
                        h: &mut p.h,
                        mass: &mut p.mass,
                        mat: &mut p.mat,
                        tau: &mut p.tau,
                    };
                    md::boundary::mirror_fill(b, dim, n, &w.gsrc, &w.gseg, &c.mirror_segs, c.noslip, a);
                },
            );
        }
        let nt = self.p.ntotal;
        // 2. neighbours
        self.exec(Module::Nnps, &[F::PairI, F::PairJ], |b, p, w, c| {
            md::nnps::search(b, c.cell, dim, n, &p.x[..dim * nt], &p.h[..nt], c.kappa, &mut w.pairs);
        });
        let np = self.w.pairs.len();
        if self.need_incidence {
            let t0 = std::time::Instant::now();
            self.w.pairs.build_incidence(nt);
            self.timers[13] += t0.elapsed().as_secs_f64();
        }
        self.w.w.resize(np, 0.0);
        self.w.dwdx.resize(dim * np, 0.0);
        // 3. kernel
        self.exec(Module::Kernel, &[F::W, F::Dwdx], |b, p, w, c| {
            md::kernel::pairs(b, dim, c.kernel, &w.pairs, &p.x[..dim * nt], &p.h[..nt], &mut w.w, &mut w.dwdx);
        });
        // 4. density
        if self.cfg.summation {
            self.w.w0.resize(nt, 0.0);
            self.exec(Module::Kernel, &[F::W0], |b, p, w, c| {
                md::kernel::self_w(b, dim, c.kernel, &p.h[..nt], &mut w.w0)
            });
            self.exec(Module::Density, &[F::Rho], |b, p, w, _| {
                md::density::summation(b, &w.pairs, &w.w, &w.w0, &p.mass[..nt], &mut p.rho[..nt]);
            });
            if nt > n {
                self.exec(Module::Boundary, &[F::Rho], |b, p, w, _| {
                    md::boundary::mirror_copy(b, n, &w.gsrc, &mut p.rho)
                });
            }
        }
        if self.cfg.need_drho {
            self.w.drho.resize(nt, 0.0);
            let vol = self.case.sph.continuity_form == crate::case::ContinuityForm::Volume;
            self.exec(Module::Density, &[F::Drho], |b, p, w, _| {
                let (pl, g, m, v) = (&w.pairs, &w.dwdx, &p.mass[..nt], &p.v[..dim * nt]);
                if vol {
                    md::density::rate_vol(b, dim, pl, g, m, &p.rho[..nt], v, &mut w.drho);
                } else {
                    md::density::rate(b, dim, pl, g, m, v, &mut w.drho);
                }
            });
        }
        if self.cfg.smoothing == SmoothingKind::Density && self.plan.is_active(Module::Smoothing) {
            self.exec(Module::Smoothing, &[F::H], |b, p, _, _| {
                md::smoothing::from_density(b, dim, &p.rho[..n], &p.h0, &p.rho0, &mut p.h[..n]);
            });
        }
        // 5. detonation
        if self.plan.is_active(Module::Detonation) {
            let t = self.t;
            self.exec(Module::Detonation, &[F::Burn], |b, p, _, c| {
                md::detonation::burn(b, t, &p.mat[..n], &c.mt, &p.tlight, &p.h[..n], c.det_width, &mut p.burn);
            });
        }
        // 6. equation of state
        self.exec(Module::Eos, &[F::P, F::C], |b, p, _, c| {
            let (pp, cc) = (&mut p.p, &mut p.c);
            md::eos::eval(b, &c.mt, &p.mat[..n], &p.burn, &p.rho[..n], &p.e[..n], &mut pp[..n], &mut cc[..n]);
        });
        if nt > n {
            self.exec(Module::Boundary, &[F::P, F::C], |b, p, w, _| {
                md::boundary::mirror_copy(b, n, &w.gsrc, &mut p.p);
                md::boundary::mirror_copy(b, n, &w.gsrc, &mut p.c);
            });
        }
        // 7..11: the rate terms
        let lda = dim * nt;
        let nacc = self.cfg.acc_terms.len();
        let nde = self.cfg.de_terms.len();
        self.w.acc.resize(nacc * lda, 0.0);
        self.w.dde.resize(nde * nt, 0.0);
        if self.plan.is_active(Module::Strength) {
            self.w.eps.resize(NSTR * nt, 0.0);
            self.w.rot.resize(3 * nt, 0.0);
            self.w.dtau.resize(NSTR * n, 0.0);
            let s = self.cfg.de_slot(DeTerm::Strength);
            self.exec(Module::Strength, &[F::Eps, F::Rot, F::Dtau, F::Dde], |b, p, w, c| {
                let out = md::strength::StrengthOut {
                    eps: &mut w.eps,
                    rot: &mut w.rot,
                    dtau: &mut w.dtau,
                    dedt: &mut w.dde[s * nt..s * nt + n],
                };
                md::strength::rates(
                    b,
                    dim,
                    n,
                    &w.pairs,
                    &w.dwdx,
                    &p.mass[..nt],
                    &p.rho[..nt],
                    &p.v[..dim * nt],
                    &p.mat[..nt],
                    &c.mt,
                    &p.tau,
                    out,
                );
            });
        }
        let (sa, sd) = (self.cfg.acc_slot(AccTerm::Force), self.cfg.de_slot(DeTerm::Force));
        self.exec(Module::Force, &[F::Acc, F::Dde], |b, p, w, _| {
            let (acc, dde) = (&mut w.acc[sa * lda..(sa + 1) * lda], &mut w.dde[sd * nt..(sd + 1) * nt]);
            md::force::internal(
                b,
                dim,
                &w.pairs,
                &w.dwdx,
                &p.mass[..nt],
                &p.rho[..nt],
                &p.p[..nt],
                &p.v[..dim * nt],
                &p.tau,
                acc,
                dde,
            );
        });
        if self.plan.is_active(Module::Viscosity) {
            let (sa, sd) = (self.cfg.acc_slot(AccTerm::Viscosity), self.cfg.de_slot(DeTerm::Viscosity));
            self.exec(Module::Viscosity, &[F::Acc, F::Dde], |b, p, w, c| {
                let (acc, dde) = (&mut w.acc[sa * lda..(sa + 1) * lda], &mut w.dde[sd * nt..(sd + 1) * nt]);
                md::viscosity::monaghan(
                    b,
                    dim,
                    &w.pairs,
                    &w.dwdx,
                    &p.x[..dim * nt],
                    &p.v[..dim * nt],
                    &p.h[..nt],
                    &p.rho[..nt],
                    &p.c[..nt],
                    &p.mass[..nt],
                    c.visc,
                    acc,
                    dde,
                );
            });
        }
        if self.plan.is_active(Module::Penalty) {
            let sa = self.cfg.acc_slot(AccTerm::Penalty);
            self.exec(Module::Penalty, &[F::Acc], |b, p, w, c| {
                let acc = &mut w.acc[sa * lda..(sa + 1) * lda];
                let (pb, n1, n2) = c.penalty;
                md::penalty::force(
                    b,
                    dim,
                    &w.pairs,
                    &p.x[..dim * nt],
                    &p.h[..nt],
                    &p.mass[..nt],
                    &p.mat[..nt],
                    &c.mt,
                    pb,
                    n1,
                    n2,
                    acc,
                );
            });
        }
        if !self.cfg.wall_segs.is_empty() {
            let sa = self.cfg.acc_slot(AccTerm::Wall);
            self.exec(Module::Boundary, &[F::Acc], |b, p, w, c| {
                let acc = &mut w.acc[sa * lda..sa * lda + dim * n];
                let (sp, r0, dc, n1, n2) = c.wall;
                md::boundary::wall_force(b, dim, &p.x[..dim * n], &c.wall_segs, sp, r0, dc, n1, n2, acc);
            });
        }
        if self.plan.is_active(Module::Xsph) {
            self.w.av.resize(dim * nt, 0.0);
            self.exec(Module::Xsph, &[F::Av], |b, p, w, c| {
                md::xsph::average(
                    b,
                    dim,
                    &w.pairs,
                    &w.w,
                    &p.mass[..nt],
                    &p.rho[..nt],
                    &p.v[..dim * nt],
                    c.xsph_eps,
                    &mut w.av,
                );
            });
        }
        if self.cfg.smoothing == SmoothingKind::Rate && self.plan.is_active(Module::Smoothing) {
            self.w.dhdt.resize(n, 0.0);
            self.exec(Module::Smoothing, &[F::Dhdt], |b, p, w, _| {
                md::smoothing::rate(b, dim, &p.rho[..n], &p.h[..n], &w.drho[..n], &mut w.dhdt);
            });
        }
        // 12. sums
        self.w.dv.resize(dim * n, 0.0);
        self.w.de.resize(n, 0.0);
        self.exec(Module::Integrator, &[F::Dv, F::De], |b, _, w, c| {
            md::integrator::sum_rates(b, dim, n, lda, nacc, &w.acc, &c.grav, &mut w.dv);
            md::integrator::sum_rates(b, 1, n, nt, nde, &w.dde, &[0.0], &mut w.de);
        });
    }

    /// Sorts the real particles by the cell of a grid of edge κ·min(h) (row-major cell order),
    /// carrying every per-particle array, including the half-step values and rates the next
    /// step reads. Deterministic (a stable counting sort).
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
        perm(&mut p.id, &order, 1);
        perm(&mut p.tau, &order, NSTR);
        for a in [&mut p.tlight, &mut p.burn, &mut p.h0, &mut p.rho0] {
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
        self.timers[13] += t0.elapsed().as_secs_f64();
    }

    /// One leapfrog step (Liu's time_integration loop body).
    pub fn step(&mut self) -> Result<f64> {
        use crate::dual::Field as F;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let first = self.nstep == 0;
        let every = self.case.sph.reorder_every;
        if every > 0 && self.nstep > 0 && self.nstep % every == 0 {
            self.reorder();
        }
        let cont = !self.cfg.summation;
        let ntau = if self.p.tau.is_empty() { 0 } else { NSTR * n };
        if first {
            self.w.rho_min.resize(n, 0.0);
            self.w.e_min.resize(n, 0.0);
            self.w.v_min.resize(dim * n, 0.0);
            self.w.tau_min.resize(ntau, 0.0);
            self.w.drho.resize(self.p.ntotal.max(n), 0.0);
        } else {
            let dtp = self.dt_prev;
            self.exec(
                Module::Integrator,
                &[F::Rho, F::E, F::V, F::Tau, F::RhoMin, F::EMin, F::VMin, F::TauMin],
                |b, p, w, _| {
                    let (s, r, _, _) = leapfrog_parts(p, w, dim, n, ntau);
                    md::integrator::predict(b, dim, n, dtp, cont, s, r);
                },
            );
        }
        self.rates();
        let dt = match self.cfg.step {
            StepRule::Fixed => self.cfg.dt_fixed,
            StepRule::Cfl => {
                self.w.dt_cfl.resize(1, 0.0);
                self.exec(Module::Integrator, &[F::DtCfl], |b, p, w, c| {
                    w.dt_cfl[0] = md::integrator::cfl(b, dim, c.cfl, &p.h[..n], &p.c[..n], &p.v[..dim * n], &w.dv);
                });
                let mut dt = self.w.dt_cfl[0].min(self.cfg.dt_max);
                let left = self.cfg.end - self.t;
                if dt > left {
                    dt = left;
                }
                dt
            }
        };
        self.check_rates()?;
        if dt.is_nan() || dt <= 0.0 || !dt.is_finite() {
            return Err(self.bad_step(dt));
        }
        self.account(dt);
        let dtp = self.dt_prev;
        self.exec(Module::Integrator, &[F::Rho, F::E, F::V, F::Tau, F::X], |b, p, w, _| {
            let (s, r, av, x) = leapfrog_parts(p, w, dim, n, ntau);
            md::integrator::advance(b, dim, n, first, dtp, dt, cont, s, r, av, x);
        });
        if self.plan.is_active(Module::Strength) {
            self.exec(Module::Strength, &[F::Tau], |b, p, _, c| {
                md::strength::yield_return(b, &p.mat[..n], &c.mt, &p.p[..n], &mut p.tau[..ntau]);
            });
        }
        if self.cfg.smoothing == SmoothingKind::Rate && self.plan.is_active(Module::Smoothing) {
            self.exec(Module::Smoothing, &[F::H], |b, p, w, c| {
                md::smoothing::advance(b, dt, c.theta, &w.dhdt, &mut p.h[..n])
            });
        }
        self.t += dt;
        self.dt_prev = dt;
        self.nstep += 1;
        self.check()?;
        Ok(dt)
    }

    /// Stops on a non-finite rate, naming the particle and the term (force, viscosity, ...).
    fn check_rates(&mut self) -> Result<()> {
        use rayon::prelude::*;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let lda = dim * self.p.ntotal;
        let nt = self.p.ntotal;
        let ok = self.w.dv[..dim * n].par_chunks(CHUNK).all(|c| c.iter().all(|v| v.is_finite()))
            && self.w.de[..n].par_chunks(CHUNK).all(|c| c.iter().all(|v| v.is_finite()));
        if ok {
            return Ok(());
        }
        for i in 0..n {
            let dv_ok = (0..dim).all(|d| self.w.dv[d + dim * i].is_finite());
            if dv_ok && self.w.de[i].is_finite() {
                continue;
            }
            self.stab.nan = true;
            let mut terms = Vec::new();
            for (k, t) in self.cfg.acc_terms.iter().enumerate() {
                if !(0..dim).all(|d| self.w.acc[k * lda + d + dim * i].is_finite()) {
                    terms.push(format!("{t:?} acceleration").to_lowercase());
                }
            }
            for (k, t) in self.cfg.de_terms.iter().enumerate() {
                if !self.w.dde[k * nt + i].is_finite() {
                    terms.push(format!("{t:?} energy rate").to_lowercase());
                }
            }
            let pos: Vec<String> = (0..dim).map(|d| format!("{:.5}", self.p.x[d + dim * i])).collect();
            return Err(SphError::Unstable(format!(
                "step {} (t = {:.6e} s): particle {} (material {}) at [{}] m has a non-finite rate: {} (rho = {:e} kg/m3, p = {:e} Pa, h = {:e} m, {} neighbours)",
                self.nstep,
                self.t,
                self.p.id[i],
                self.case.materials[self.p.mat[i] as usize].name,
                pos.join(", "),
                if terms.is_empty() { "gravity".to_string() } else { terms.join(", ") },
                self.p.rho[i],
                self.p.p[i],
                self.p.h[i],
                (0..self.w.pairs.len())
                    .filter(|&k| self.w.pairs.i[k] as usize == i || self.w.pairs.j[k] as usize == i)
                    .count()
            )));
        }
        Ok(())
    }

    /// The diagnostic of a step the CFL rule could not take: the particle that limits it.
    fn bad_step(&self, dt: f64) -> SphError {
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
            self.case.materials[self.p.mat[i] as usize].name,
            self.p.h[i],
            self.p.c[i],
            norm(&self.p.v, i),
            norm(&self.w.dv, i),
            self.p.rho[i],
            self.p.e[i]
        ))
    }

    /// Work of the wall, penalty and gravity forces over the step (v at t). One parallel pass;
    /// the sums are taken per fixed chunk of particles, then over the chunks in order, so they do
    /// not depend on the thread count.
    fn account(&mut self, dt: f64) {
        use rayon::prelude::*;
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let lda = dim * self.p.ntotal;
        let (sw, sp) = (self.cfg.acc_slot(AccTerm::Wall), self.cfg.acc_slot(AccTerm::Penalty));
        let (acc, v, m, g) = (&self.w.acc, &self.p.v, &self.p.mass, &self.cfg.grav);
        // Σ_i m_i (f_i·v_i) over the particles of chunk c, for the force array `f` (the
        // particles in order, each dot product from +0 over the components)
        let power = |f: &[f64], c: usize| -> f64 {
            let (a0, a1) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
            let mut t = 0.0;
            for (k, (fi, vi)) in
                f[dim * a0..dim * a1].chunks_exact(dim).zip(v[dim * a0..dim * a1].chunks_exact(dim)).enumerate()
            {
                let mut s = 0.0;
                for d in 0..dim {
                    s += fi[d] * vi[d];
                }
                t += m[a0 + k] * s;
            }
            t
        };
        let slot = |s: usize| if s == usize::MAX { None } else { Some(&acc[s * lda..s * lda + dim * n]) };
        let (fw, fp) = (slot(sw), slot(sp));
        // without gravity every term of its sum is +0 (the check stops a run with a non-finite v)
        let gravity = g[..dim].iter().any(|&x| x != 0.0);
        let parts: Vec<[f64; 3]> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut t = [0.0; 3];
                if let Some(f) = fw {
                    t[0] = power(f, c);
                }
                if let Some(f) = fp {
                    t[1] = power(f, c);
                }
                if gravity {
                    for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                        let mut s = 0.0;
                        for d in 0..dim {
                            s += g[d] * v[d + dim * i];
                        }
                        t[2] += m[i] * s;
                    }
                }
                t
            })
            .collect();
        let tot = parts.iter().fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
        self.book.work_wall += dt * tot[0];
        self.book.work_penalty += dt * tot[1];
        self.book.work_gravity += dt * tot[2];
    }

    /// Stops a run that went unstable, naming the step, the particle and the quantity.
    fn check(&mut self) -> Result<()> {
        if let Some(ok) = self.scan() {
            return ok;
        }
        self.check_slow()
    }

    /// The health of the state in one parallel pass (fixed chunks, combined in order). Returns
    /// None when something is wrong, so that `check_slow` names the first culprit; else updates
    /// the statistics and applies the energy and step checks.
    fn scan(&mut self) -> Option<Result<()>> {
        use rayon::prelude::*;
        #[derive(Clone, Copy)]
        struct Part {
            bad: bool,
            energy: f64,
            ke_max: (f64, usize),
            hr: (f64, f64),
            pen: f64,
            out: usize,
        }
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let p = &self.p;
        let h_init = &self.h_init;
        let segs = &self.cfg.all_segs;
        let frames = &self.cfg.all_frames;
        let limit = 0.5 * self.cfg.dx_min;
        let domain = self.case.domain.as_ref();
        let parts: Vec<Part> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut q =
                    Part { bad: false, energy: 0.0, ke_max: (0.0, 0), hr: (f64::INFINITY, 0.0), pen: 0.0, out: 0 };
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let mut v2 = 0.0;
                    for d in 0..dim {
                        q.bad |= !p.x[d + dim * i].is_finite() || !p.v[d + dim * i].is_finite();
                        v2 += p.v[d + dim * i] * p.v[d + dim * i];
                    }
                    q.bad |= !p.rho[i].is_finite() || p.rho[i] <= 0.0 || !p.e[i].is_finite() || !p.p[i].is_finite();
                    if !p.tau.is_empty() {
                        q.bad |= !p.tau[NSTR * i..NSTR * i + NSTR].iter().all(|t| t.is_finite());
                    }
                    let r = p.h[i] / h_init[i];
                    q.bad |= !r.is_finite() || r < 1e-3;
                    q.hr = (q.hr.0.min(r), q.hr.1.max(r));
                    let ke = 0.5 * p.mass[i] * v2;
                    q.energy += ke + p.mass[i] * p.e[i];
                    if ke > q.ke_max.0 {
                        q.ke_max = (ke, i);
                    }
                    for (s, fr) in frames.iter().enumerate() {
                        if let Some(depth) =
                            behind_wall(dim, &p.x[dim * i..dim * i + dim], &segs.seg[3 * dim * s..], fr)
                        {
                            q.pen = q.pen.max(depth);
                        }
                    }
                    if let Some(dm) = domain
                        && (0..dim).any(|d| p.x[d + dim * i] < dm.lo_m[d] || p.x[d + dim * i] > dm.hi_m[d])
                    {
                        q.out += 1;
                    }
                }
                q
            })
            .collect();
        let mut all = Part { bad: false, energy: 0.0, ke_max: (0.0, 0), hr: (f64::INFINITY, 0.0), pen: 0.0, out: 0 };
        for q in &parts {
            all.bad |= q.bad;
            all.energy += q.energy;
            if q.ke_max.0 > all.ke_max.0 {
                all.ke_max = q.ke_max;
            }
            all.hr = (all.hr.0.min(q.hr.0), all.hr.1.max(q.hr.1));
            all.pen = all.pen.max(q.pen);
            all.out += q.out;
        }
        let stop_on_exit = domain.is_some_and(|d| d.stop_on_exit) && all.out > 0;
        if all.bad || all.pen > limit || stop_on_exit {
            return None;
        }
        let st = &mut self.stab;
        st.h_ratio_min = st.h_ratio_min.min(all.hr.0);
        st.h_ratio_max = st.h_ratio_max.max(all.hr.1);
        st.max_wall_penetration_m = st.max_wall_penetration_m.max(all.pen);
        st.left_domain = st.left_domain.max(all.out);
        let step = self.nstep;
        let budget = self.e_initial + self.book.work_wall + self.book.work_penalty + self.book.work_gravity;
        if all.energy - budget > self.e_initial.abs().max(f64::MIN_POSITIVE) {
            let (ke, i) = all.ke_max;
            return Some(Err(SphError::Unstable(format!(
                "step {step} (t = {:.6e} s): total energy {:e} J exceeds the initial {:e} J plus the work of external forces by more than the initial energy; fastest particle {} (material {}), |v| = {:e} m/s",
                self.t,
                all.energy,
                self.e_initial,
                self.p.id[i],
                self.case.materials[self.p.mat[i] as usize].name,
                (2.0 * ke / self.p.mass[i]).sqrt()
            ))));
        }
        if self.nstep >= self.cfg.max_steps && self.t < self.cfg.end {
            return Some(Err(SphError::Unstable(format!(
                "step {step}: time.max_steps reached at t = {:.6e} s before the end time",
                self.t
            ))));
        }
        Some(Ok(()))
    }

    /// The sequential check: finds and names the first particle in trouble.
    fn check_slow(&mut self) -> Result<()> {
        let dim = self.cfg.dim;
        let n = self.p.nreal;
        let step = self.nstep;
        let p = &self.p;
        let bad = |what: &str, i: usize, v: f64| -> SphError {
            SphError::Unstable(format!(
                "step {step} (t = {:.6e} s): particle {} (material {}) has {what} = {v:e}",
                self.t, p.id[i], self.case.materials[p.mat[i] as usize].name
            ))
        };
        let mut energy = 0.0;
        let mut ke_max = (0.0f64, 0usize);
        for i in 0..n {
            for d in 0..dim {
                if !p.x[d + dim * i].is_finite() {
                    self.stab.nan = true;
                    return Err(bad(&format!("x[{d}]"), i, p.x[d + dim * i]));
                }
                if !p.v[d + dim * i].is_finite() {
                    self.stab.nan = true;
                    return Err(bad(&format!("v[{d}]"), i, p.v[d + dim * i]));
                }
            }
            if !p.rho[i].is_finite() || p.rho[i] <= 0.0 {
                self.stab.nan |= !p.rho[i].is_finite();
                return Err(bad("density", i, p.rho[i]));
            }
            if !p.e[i].is_finite() {
                self.stab.nan = true;
                return Err(bad("internal energy", i, p.e[i]));
            }
            if !p.p[i].is_finite() {
                self.stab.nan = true;
                return Err(bad("pressure", i, p.p[i]));
            }
            if !p.tau.is_empty() {
                for q in 0..NSTR {
                    if !p.tau[q + NSTR * i].is_finite() {
                        self.stab.nan = true;
                        return Err(bad(&format!("deviatoric stress component {q}"), i, p.tau[q + NSTR * i]));
                    }
                }
            }
            let r = p.h[i] / self.h_init[i];
            if !r.is_finite() || r < 1e-3 {
                return Err(bad("h/h0 (smoothing length collapsed)", i, r));
            }
            if r < self.stab.h_ratio_min {
                self.stab.h_ratio_min = r;
            }
            if r > self.stab.h_ratio_max {
                self.stab.h_ratio_max = r;
            }
            let v2: f64 = (0..dim).map(|d| p.v[d + dim * i] * p.v[d + dim * i]).sum();
            let ke = 0.5 * p.mass[i] * v2;
            energy += ke + p.mass[i] * p.e[i];
            if ke > ke_max.0 {
                ke_max = (ke, i);
            }
        }
        // energy blow-up: the balance residual (energy created beyond the work of the wall,
        // penalty and gravity forces) above the initial energy; healthy runs stay under 1 %
        let budget = self.e_initial + self.book.work_wall + self.book.work_penalty + self.book.work_gravity;
        if energy - budget > self.e_initial.abs().max(f64::MIN_POSITIVE) {
            let i = ke_max.1;
            return Err(SphError::Unstable(format!(
                "step {step} (t = {:.6e} s): total energy {energy:e} J exceeds the initial {:e} J plus the work of external forces by more than the initial energy; fastest particle {} (material {}), |v| = {:e} m/s",
                self.t,
                self.e_initial,
                p.id[i],
                self.case.materials[p.mat[i] as usize].name,
                (2.0 * ke_max.0 / p.mass[i]).sqrt()
            )));
        }
        // wall crossing: a particle behind a wall line, within the wall's extent
        let segs = &self.cfg.all_segs;
        for (s, fr) in self.cfg.all_frames.iter().enumerate() {
            for i in 0..n {
                if let Some(depth) = behind_wall(dim, &p.x[dim * i..dim * i + dim], &segs.seg[3 * dim * s..], fr) {
                    if depth > self.stab.max_wall_penetration_m {
                        self.stab.max_wall_penetration_m = depth;
                    }
                    if depth > 0.5 * self.cfg.dx_min {
                        let pos: Vec<String> = (0..dim).map(|d| format!("{:.5}", p.x[d + dim * i])).collect();
                        return Err(SphError::Unstable(format!(
                            "step {step} (t = {:.6e} s): particle {} crossed wall {s} by {depth:.3e} m (x = [{}] m)",
                            self.t,
                            p.id[i],
                            pos.join(", ")
                        )));
                    }
                }
            }
        }
        if let Some(dm) = &self.case.domain {
            let out = (0..n)
                .filter(|&i| (0..dim).any(|d| p.x[d + dim * i] < dm.lo_m[d] || p.x[d + dim * i] > dm.hi_m[d]))
                .count();
            if out > 0 && dm.stop_on_exit {
                let i = (0..n)
                    .find(|&i| (0..dim).any(|d| p.x[d + dim * i] < dm.lo_m[d] || p.x[d + dim * i] > dm.hi_m[d]))
                    .unwrap_or(0);
                return Err(bad("a position outside [domain]; x[0]", i, p.x[dim * i]));
            }
            self.stab.left_domain = self.stab.left_domain.max(out);
        }
        if self.nstep >= self.cfg.max_steps && self.t < self.cfg.end {
            return Err(SphError::Unstable(format!(
                "step {step}: time.max_steps reached at t = {:.6e} s before the end time",
                self.t
            )));
        }
        Ok(())
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
            if multi && j < n && self.cfg.mt.group[self.p.mat[i] as usize] != self.cfg.mt.group[self.p.mat[j] as usize]
            {
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
        let shear = crate::legacy::SPH_MP_SHEAR as usize - 1;
        for i in 0..n {
            let m = self.p.mass[i];
            let v2: f64 = (0..dim).map(|d| self.p.v[d + dim * i] * self.p.v[d + dim * i]).sum();
            ke += 0.5 * m * v2;
            ie += m * self.p.e[i];
            if !self.p.tau.is_empty() {
                let g = self.cfg.mt.mpar[shear + crate::legacy::NPAR * self.p.mat[i] as usize];
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
}

/// How far (m) the point `x` lies behind the line of the wall segment `sg` (from, then the
/// normal at `2 dim`) whose frame is `fr` (boundary::frame), if it is behind it and within the
/// segment's extent along it.
#[inline]
fn behind_wall(dim: usize, x: &[f64], sg: &[f64], fr: &([f64; 3], f64, [f64; 3])) -> Option<f64> {
    let (ut, el, nrm) = fr;
    let (mut dn, mut tp) = (0.0, 0.0);
    for d in 0..dim {
        let r = x[d] - sg[d];
        dn += r * nrm[d];
        tp += r * ut[d];
    }
    (tp >= 0.0 && tp <= *el && dn < 0.0).then_some(-dn)
}
