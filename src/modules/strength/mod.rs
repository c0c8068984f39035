//! Soil strength (thesis (4-29)…(4-32), docs/theory.md §7).
//! L_i^{αβ} = Σ_j (m_j/ρ_j)(v_j^α − v_i^α) ∂W_ij/∂x_i^β (1/s); ε̇ = (L + Lᵀ)/2, R = (L − Lᵀ)/2;
//! Jaumann dτ/dt = 2G(ε̇ − ⅓ tr ε̇ I) + τ Rᵀ + R τ (Pa/s); deviatoric work τ:ε̇/ρ (J/kg/s).
//! Drucker–Prager return: Y = 3 α_φ p + k; Y ≤ 0 → τ = 0 (tension cut-off); √J2 > Y → τ ← τ Y/√J2.
//! Plane strain: out-of-plane rates zero, τ_zz kept. Axisymmetric (RZ, x = r, y = z): zz is the
//! hoop direction θ, ε̇_θθ = v_r/r (`rinv` = 1/r* of the geometry module) enters the Jaumann rate,
//! the trace and the work, and the pair sums take the planar mass m/(2πr). Stress order xx, yy,
//! zz, xy, xz, yz. Fortran twin: `sph_strength.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::param::{MatTable, NSTR};
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// `sph_strength_rates`: strain and rotation rates of every particle of the pair list
/// (ntotal = `mass.len()`), stress rate and deviatoric work of the first `nreal`.
pub struct Rates<'a> {
    pub dim: usize,
    pub nreal: usize,
    pub pairs: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    /// Deviatoric stress (Pa), NSTR × ntotal.
    pub tau: &'a [f64],
    /// Axisymmetric geometry: 1/r* (1/m) of every particle, ntotal; empty in plane geometry.
    pub rinv: &'a [f64],
    /// ε̇ (1/s), NSTR × ntotal.
    pub eps: &'a mut [f64],
    /// R (xy, xz, yz; 1/s), 3 × ntotal.
    pub rot: &'a mut [f64],
    /// dτ/dt (Pa/s), NSTR × nreal.
    pub dtau: &'a mut [f64],
    /// τ:ε̇/ρ (J/kg/s), nreal.
    pub dedt: &'a mut [f64],
}

/// `sph_strength_yield`: the Drucker–Prager return of the first `mat.len()` particles.
pub struct Yield<'a> {
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    pub p: &'a [f64],
    pub tau: &'a mut [f64],
}

impl Twin for Rates<'_> {
    fn rust(&mut self) {
        rust::rates(self)
    }
    fn fortran(&mut self) {
        ffi::rates(self)
    }
}

impl Twin for Yield<'_> {
    fn rust(&mut self) {
        rust::yield_return(self)
    }
    fn fortran(&mut self) {
        ffi::yield_return(self)
    }
}

/// The strain, rotation and stress rates, and the deviatoric work as a term of the energy rate.
pub struct RatesStage {
    mt: MatTable,
    slots: Slots,
    /// Axisymmetric: the planar mass and 1/r of the geometry module.
    rz: bool,
}

impl Stage for RatesStage {
    fn module(&self) -> Module {
        Module::Strength
    }
    fn name(&self) -> &'static str {
        "strength.rates"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Pmass, Field::Rho, Field::V, Field::Mat, Field::Tau, Field::Rinv]
        } else {
            &[Field::PairI, Field::PairJ, Field::Dwdx, Field::Mass, Field::Rho, Field::V, Field::Mat, Field::Tau]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Eps, Field::Rot, Field::Dtau, Field::Dde]
    }
    fn register(&self, p: &mut Particles) {
        p.tau = vec![0.0; NSTR * p.ntotal];
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        let (nt, n) = (p.ntotal, p.nreal);
        self.slots.size(w, p.dim, nt);
        w.eps.resize(NSTR * nt, 0.0);
        w.rot.resize(3 * nt, 0.0);
        w.dtau.resize(NSTR * n, 0.0);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, n, nt) = (p.dim, p.nreal, p.ntotal);
        let de = self.slots.de_range(nt);
        let (mass, rinv): (&[f64], &[f64]) =
            if self.rz { (&w.pmass[..nt], &w.rinv[..nt]) } else { (&p.mass[..nt], &[]) };
        Rates {
            dim,
            nreal: n,
            pairs: &w.pairs,
            dwdx: &w.dwdx,
            mass,
            rho: &p.rho[..nt],
            v: &p.v[..dim * nt],
            mat: &p.mat[..nt],
            mt: &self.mt,
            tau: &p.tau,
            rinv,
            eps: &mut w.eps,
            rot: &mut w.rot,
            dtau: &mut w.dtau,
            dedt: &mut w.dde[de.start..de.start + n],
        }
        .run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: None, de: Some(2) }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// The return to the yield surface after the advance.
pub struct YieldStage {
    mt: MatTable,
}

impl Stage for YieldStage {
    fn module(&self) -> Module {
        Module::Strength
    }
    fn name(&self) -> &'static str {
        "strength.yield"
    }
    fn reads(&self) -> &[Field] {
        &[Field::Mat, Field::P, Field::Tau]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Tau]
    }
    fn real_rows(&self) -> &[Field] {
        &[Field::Tau]
    }
    fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
        let n = p.nreal;
        Yield { mat: &p.mat[..n], mt: &self.mt, p: &p.p[..n], tau: &mut p.tau[..NSTR * n] }.run(b);
    }
}

/// Runs when some material has strength.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    if !crate::case::has_strength(ctx.case) {
        return Contribution::skip("fluids only: no stress arrays");
    }
    let mt = ctx.mt.clone();
    let rz = ctx.case.axisymmetric();
    Contribution::run(
        if rz { "materials with strength present; hoop strain rate v_r/r" } else { "materials with strength present" },
        vec![
            (Phase::Rates, Box::new(RatesStage { mt: mt.clone(), slots: Slots::default(), rz })),
            (Phase::Correct, Box::new(YieldStage { mt })),
        ],
    )
}
