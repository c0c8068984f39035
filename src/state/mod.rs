//! Simulation state: structure of arrays in the Fortran layout (`x[d + dim*i]`), so that the legacy
//! routines read and write it without copies. Particles `0..nreal` are real; `nreal..ntotal` are
//! the mirror particles of type II walls, rebuilt every step. Arrays a case does not need are left
//! empty (no stress for fluids, no burn state without a programmed burn).
//!
//! Every array a module reads or writes has a name, [`Field`]; [`Field::of`] and `Field::of_mut`
//! find it in the state. The dual run, the parity harness and `blastsph check` work through these
//! names: a module declares which fields its stages read and write, and nothing else needs to know
//! which array a field is.

use crate::param::NSTR;

pub(crate) mod pair_list;
pub use pair_list::PairList;
use serde::Serialize;

#[derive(Debug, Clone, Default)]
pub struct Particles {
    pub dim: usize,
    pub nreal: usize,
    pub ntotal: usize,
    /// Position (m), dim × ntotal.
    pub x: Vec<f64>,
    /// Velocity (m/s), dim × ntotal.
    pub v: Vec<f64>,
    /// Density (kg/m³).
    pub rho: Vec<f64>,
    /// Pressure (Pa).
    pub p: Vec<f64>,
    /// Sound speed (m/s).
    pub c: Vec<f64>,
    /// Specific internal energy (J/kg).
    pub e: Vec<f64>,
    /// Smoothing length (m).
    pub h: Vec<f64>,
    /// Mass (kg; per metre of depth in 2D, per m² in 1D).
    pub mass: Vec<f64>,
    /// Material index (0-based).
    pub mat: Vec<i32>,
    /// Particle id (real particles; stable through the run).
    pub id: Vec<i64>,
    /// Deviatoric stress (Pa), NSTR × ntotal (xx, yy, zz, xy, xz, yz); empty without strength.
    pub tau: Vec<f64>,
    /// Lighting time (s) and burn fraction of a programmed burn; empty otherwise.
    pub tlight: Vec<f64>,
    pub burn: Vec<f64>,
    /// Initial h and ρ (for h from density); empty otherwise.
    pub h0: Vec<f64>,
    pub rho0: Vec<f64>,
    /// Viscosity coefficient α of each particle (Morris–Monaghan switch), ntotal (the mirrors
    /// hold their source's); empty without the switch.
    pub alpha: Vec<f64>,
    /// Stress at t = 0, −p I + τ (Pa, tension positive), NSTR × nreal: the static reaction of
    /// absorbing walls; empty without them.
    pub sigma0: Vec<f64>,
    /// Compaction history: the largest density each real particle has reached (kg/m³), nreal;
    /// empty without a compaction EOS.
    pub rho_max: Vec<f64>,
    /// Boundary-particle kind of each real particle (`[[region]] boundary_particles`): 0 an
    /// ordinary particle, 1 integrated, 2 held ([`crate::case::BoundaryKind`]), nreal; empty
    /// without boundary particles.
    pub bnd: Vec<i32>,
}

impl Particles {
    /// Sets the number of mirror particles (resizes the per-particle arrays).
    pub(crate) fn set_ntotal(&mut self, nt: usize) {
        let d = self.dim;
        self.ntotal = nt;
        self.x.resize(d * nt, 0.0);
        self.v.resize(d * nt, 0.0);
        for a in [&mut self.rho, &mut self.p, &mut self.c, &mut self.e, &mut self.h, &mut self.mass] {
            a.resize(nt, 0.0);
        }
        self.mat.resize(nt, 0);
        if !self.tau.is_empty() {
            self.tau.resize(NSTR * nt, 0.0);
        }
        if !self.alpha.is_empty() {
            self.alpha.resize(nt, 0.0);
        }
    }
}

/// Work arrays of one step.
#[derive(Debug, Clone, Default)]
pub struct Work {
    pub pairs: PairList,
    /// W_ij per pair (m^-d).
    pub w: Vec<f64>,
    /// ∇_i W_ij per pair, dim × npair (m^-(d+1)).
    pub dwdx: Vec<f64>,
    /// W(0, h_i) (summation density).
    pub w0: Vec<f64>,
    /// Continuity rate Dρ/Dt (kg/m³/s), ntotal.
    pub drho: Vec<f64>,
    /// Acceleration terms (m/s²), stacked: term t holds (d,i) at `d + dim*i + lda*t`.
    pub acc: Vec<f64>,
    /// Energy-rate terms (J/kg/s), stacked with stride ntotal.
    pub dde: Vec<f64>,
    /// Total acceleration and energy rate of the real particles.
    pub dv: Vec<f64>,
    pub de: Vec<f64>,
    /// Strain rate (NSTR × ntotal), rotation rate (3 × ntotal), stress rate (NSTR × nreal), 1/s, Pa/s.
    pub eps: Vec<f64>,
    pub rot: Vec<f64>,
    pub dtau: Vec<f64>,
    /// XSPH velocity correction (m/s), dim × ntotal.
    pub av: Vec<f64>,
    /// dh/dt (m/s), nreal.
    pub dhdt: Vec<f64>,
    /// Half-step values of the leapfrog.
    pub rho_min: Vec<f64>,
    pub e_min: Vec<f64>,
    pub v_min: Vec<f64>,
    pub tau_min: Vec<f64>,
    /// Mirror list: source particle and wall(s) of each mirror.
    pub gsrc: Vec<i32>,
    pub gseg: Vec<i32>,
    /// The step the CFL rule proposes (s), as a one-value array (so the dual run compares it).
    pub dt_cfl: Vec<f64>,
    /// Axisymmetric geometry: 1/r* (1/m) and the planar mass m/(2πr*) (kg/m) of every particle;
    /// empty in plane geometry.
    pub rinv: Vec<f64>,
    pub pmass: Vec<f64>,
    /// Largest |μ_ij| of the viscosity per particle (m/s), for the CFL step.
    pub mumax: Vec<f64>,
    /// Energy added by the floor e ≥ 0 in the last step (J; per metre of depth in 2D), one value.
    pub efloor: Vec<f64>,
    /// The viscosity switch's workspace: ρ_i (−∇·v_i) = Σ_j m_j v_ij·∇_i W_ij (kg/m³/s), ntotal;
    /// recomputed by every switch call, not state.
    pub divv: Vec<f64>,
}

/// Where a step stands: the time a stage evaluates at and the steps around it (s).
#[derive(Debug, Clone, Copy, Default)]
pub struct Clock {
    /// Time of the state (s).
    pub t: f64,
    /// The step being taken (s); known from the step-size stage on.
    pub dt: f64,
    /// The previous step (s); 0 before the first.
    pub dt_prev: f64,
    /// True during the first step (Liu's half-step start of the leapfrog).
    pub first: bool,
}

/// How a field is indexed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Per {
    /// One row per particle (real and mirror).
    Particle,
    /// One row per pair of the neighbour list.
    Pair,
    /// Rows of stacked terms, each `dim × ntotal` (acc) or `ntotal` (dde) long.
    Term,
    /// A single value.
    One,
}

/// The named arrays of the state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Field {
    X,
    V,
    Rho,
    P,
    C,
    E,
    H,
    Mass,
    Mat,
    Tau,
    Burn,
    Tlight,
    PairI,
    PairJ,
    W,
    Dwdx,
    W0,
    Drho,
    Acc,
    Dde,
    Dv,
    De,
    Eps,
    Rot,
    Dtau,
    Av,
    Dhdt,
    RhoMin,
    EMin,
    VMin,
    TauMin,
    Gsrc,
    Gseg,
    DtCfl,
    Rinv,
    Pmass,
    Mumax,
    Efloor,
    Alpha,
    Sigma0,
    RhoMax,
    Bnd,
}

/// A field's array, borrowed.
pub enum Array<'a> {
    F(&'a [f64]),
    I(&'a [i32]),
}

/// A field's array, to write.
pub enum ArrayMut<'a> {
    F(&'a mut Vec<f64>),
    I(&'a mut Vec<i32>),
}

/// A copy of one field.
#[derive(Debug, Clone)]
pub enum Snap {
    F(Vec<f64>),
    I(Vec<i32>),
}

impl Field {
    /// Snake-case name, as in reports (`rho_min`, `pair_i`).
    pub fn name(self) -> String {
        let mut s = String::new();
        for (k, ch) in format!("{self:?}").chars().enumerate() {
            if ch.is_ascii_uppercase() && k > 0 {
                s.push('_');
            }
            s.push(ch.to_ascii_lowercase());
        }
        s
    }

    /// How the field is indexed and how many values a row holds (`dim` in the space dimension).
    pub fn layout(self, dim: usize) -> (Per, usize) {
        use Field::*;
        match self {
            X | V | Av | VMin | Dv => (Per::Particle, dim),
            Tau | Eps | Dtau | TauMin | Sigma0 => (Per::Particle, NSTR),
            Rot => (Per::Particle, 3),
            // the walls of each mirror: images of up to two walls (three in 3D)
            Gseg => (Per::Particle, if dim == 3 { 3 } else { 2 }),
            Dwdx => (Per::Pair, dim),
            W | PairI | PairJ => (Per::Pair, 1),
            Acc => (Per::Term, dim),
            Dde => (Per::Term, 1),
            DtCfl | Efloor => (Per::One, 1),
            _ => (Per::Particle, 1),
        }
    }

    /// The field's array in the state.
    pub fn of<'a>(self, p: &'a Particles, w: &'a Work) -> Array<'a> {
        use Field::*;
        Array::F(match self {
            Mat => return Array::I(&p.mat),
            Bnd => return Array::I(&p.bnd),
            PairI => return Array::I(&w.pairs.i),
            PairJ => return Array::I(&w.pairs.j),
            Gsrc => return Array::I(&w.gsrc),
            Gseg => return Array::I(&w.gseg),
            X => &p.x,
            V => &p.v,
            Rho => &p.rho,
            P => &p.p,
            C => &p.c,
            E => &p.e,
            H => &p.h,
            Mass => &p.mass,
            Tau => &p.tau,
            Burn => &p.burn,
            Tlight => &p.tlight,
            W => &w.w,
            Dwdx => &w.dwdx,
            W0 => &w.w0,
            Drho => &w.drho,
            Acc => &w.acc,
            Dde => &w.dde,
            Dv => &w.dv,
            De => &w.de,
            Eps => &w.eps,
            Rot => &w.rot,
            Dtau => &w.dtau,
            Av => &w.av,
            Dhdt => &w.dhdt,
            RhoMin => &w.rho_min,
            EMin => &w.e_min,
            VMin => &w.v_min,
            TauMin => &w.tau_min,
            DtCfl => &w.dt_cfl,
            Rinv => &w.rinv,
            Pmass => &w.pmass,
            Mumax => &w.mumax,
            Efloor => &w.efloor,
            Alpha => &p.alpha,
            Sigma0 => &p.sigma0,
            RhoMax => &p.rho_max,
        })
    }

    /// A copy of the field.
    pub(crate) fn snap(self, p: &Particles, w: &Work) -> Snap {
        match self.of(p, w) {
            Array::F(a) => Snap::F(a.to_vec()),
            Array::I(a) => Snap::I(a.to_vec()),
        }
    }

    /// The field's array in the state, to write.
    pub(crate) fn of_mut<'a>(self, p: &'a mut Particles, w: &'a mut Work) -> ArrayMut<'a> {
        use Field::*;
        ArrayMut::F(match self {
            Mat => return ArrayMut::I(&mut p.mat),
            Bnd => return ArrayMut::I(&mut p.bnd),
            PairI => return ArrayMut::I(&mut w.pairs.i),
            PairJ => return ArrayMut::I(&mut w.pairs.j),
            Gsrc => return ArrayMut::I(&mut w.gsrc),
            Gseg => return ArrayMut::I(&mut w.gseg),
            X => &mut p.x,
            V => &mut p.v,
            Rho => &mut p.rho,
            P => &mut p.p,
            C => &mut p.c,
            E => &mut p.e,
            H => &mut p.h,
            Mass => &mut p.mass,
            Tau => &mut p.tau,
            Burn => &mut p.burn,
            Tlight => &mut p.tlight,
            W => &mut w.w,
            Dwdx => &mut w.dwdx,
            W0 => &mut w.w0,
            Drho => &mut w.drho,
            Acc => &mut w.acc,
            Dde => &mut w.dde,
            Dv => &mut w.dv,
            De => &mut w.de,
            Eps => &mut w.eps,
            Rot => &mut w.rot,
            Dtau => &mut w.dtau,
            Av => &mut w.av,
            Dhdt => &mut w.dhdt,
            RhoMin => &mut w.rho_min,
            EMin => &mut w.e_min,
            VMin => &mut w.v_min,
            TauMin => &mut w.tau_min,
            DtCfl => &mut w.dt_cfl,
            Rinv => &mut w.rinv,
            Pmass => &mut w.pmass,
            Mumax => &mut w.mumax,
            Efloor => &mut w.efloor,
            Alpha => &mut p.alpha,
            Sigma0 => &mut p.sigma0,
            RhoMax => &mut p.rho_max,
        })
    }

    /// Puts a copy back (the array takes the copy's length).
    pub(crate) fn restore(self, p: &mut Particles, w: &mut Work, s: Snap) {
        match (self.of_mut(p, w), s) {
            (ArrayMut::F(a), Snap::F(v)) => *a = v,
            (ArrayMut::I(a), Snap::I(v)) => *a = v,
            _ => {}
        }
    }
}
