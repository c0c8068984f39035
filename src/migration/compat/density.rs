//! Summation density as Liu & Liu's book code computes it with `nor_density = .true.`
//! (`--compat liu-book,nor_density`; docs/compat-liu-book.md §4), item `nor_density`: the
//! book's `sum_density` divides the sum by the kernel's integral (Shepard/CSPM normalisation)
//! Σ_j (m_j/ρ_j) W_ij, taken with the densities the particles had *before* the summation:
//!
//! ```text
//! wi(i)  = selfdens*mass(i)/rho(i)              (old rho)
//! wi(i) += mass(j)/rho(j)*w(k), wi(j) += mass(i)/rho(i)*w(k)   (pair order)
//! rho(i) = selfdens*mass(i);  rho(i) += mass(j)*w(k) ...       (blastsph's sum)
//! rho(i) = rho(i)/wi(i)
//! ```
//!
//! ρ_i = (m_i W_ii + Σ_j m_j W_ij) / (m_i W_ii/ρ_i + Σ_j m_j W_ij/ρ_j) (kg/m³). Planar cases
//! only (an axisymmetric case keeps blastsph's twin). No Fortran twin in blastsph's core.

use super::{Flags, Item};
use crate::modules::{Backend, Contribution, Counterpart, Module, PlanCtx, Stage, par_rows};
use crate::state::{Clock, Field, Particles, Work};

/// `sum_density` with `nor_density`: the sum over the old densities' kernel integral.
pub struct NorSumStage {
    why: &'static str,
}

impl Stage for NorSumStage {
    fn module(&self) -> Module {
        Module::Density
    }
    fn name(&self) -> &'static str {
        "density.summation"
    }
    fn reads(&self) -> &[Field] {
        &[Field::PairI, Field::PairJ, Field::W, Field::W0, Field::Mass, Field::Rho]
    }
    fn writes(&self) -> &[Field] {
        &[Field::Rho]
    }
    fn run(&self, _b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let nt = p.ntotal;
        let (pl, wk, w0, mass) = (&w.pairs, &w.w, &w.w0, &p.mass[..nt]);
        // the old densities, read by every particle's integral before any is overwritten
        let old: Vec<f64> = p.rho[..nt].to_vec();
        par_rows(&mut p.rho[..nt], 1, |i, r| {
            // wi(i) = selfdens*mass(i)/rho(i), then + mass(j)/rho(j)*w(k) in pair order
            let mut wi = w0[i] * mass[i] / old[i];
            // rho(i) = selfdens*mass(i), then + mass(j)*w(k) in pair order
            let mut s = mass[i] * w0[i];
            for e in pl.incident(i) {
                let j = e.other();
                wi += mass[j] / old[j] * wk[e.pair()];
                s += mass[j] * wk[e.pair()];
            }
            r[0] = s / wi;
        });
    }
    fn counterpart(&self) -> Counterpart {
        Counterpart::None(self.why)
    }
}

/// Summation density with the book's normalisation, when `nor_density` is on (planar cases
/// with summation density); the continuity rate stage, if the case has one, is blastsph's.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    if !f.has(Item::NorDensity) || ctx.case.axisymmetric() {
        return None;
    }
    let mut normal = crate::modules::density::plan(ctx);
    let why: &'static str = Box::leak(format!("density: {}", f.label()).into_boxed_str());
    let mut found = false;
    for (_, st) in normal.stages.iter_mut() {
        if st.name() == "density.summation" {
            *st = Box::new(NorSumStage { why });
            found = true;
        }
    }
    found.then(|| Contribution::run(format!("{}, normalised [compat {}]", normal.why, f.label()), normal.stages))
}
