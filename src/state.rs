//! Simulation state: structure of arrays in the Fortran layout (`x[d + dim*i]`), so that the legacy
//! routines read and write it without copies. Particles `0..nreal` are real; `nreal..ntotal` are
//! the mirror particles of type II walls, rebuilt every step. Arrays a case does not need are left
//! empty (no stress for fluids, no burn state without a programmed burn).

use crate::legacy::NSTR;
use crate::modules::nnps::PairList;

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
}

impl Particles {
    /// Sets the number of mirror particles (resizes the per-particle arrays).
    pub fn set_ntotal(&mut self, nt: usize) {
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
}
