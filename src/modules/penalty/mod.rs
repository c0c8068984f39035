//! Penalty force between materials (thesis (4-53), (4-54); docs/theory.md §10): for a pair in different
//! penalty groups, neither exempt (group < 0, `penalty_group = "none"`), pe = (h_i + h_j)/(2 r_ij); while pe > 1,
//! PB_ij = P̄ (pe^{n1} − pe^{n2}) x_ij / r_ij², a_i += PB_ij/m_i, a_j −= PB_ij/m_j (m/s²).
//! Integer powers as products. Fortran twin: `sph_penalty.f90`.

mod ffi;
#[cfg(test)]
mod parity;
mod rust;

use super::nnps::PairList;
use super::param::MatTable;
use super::{Backend, Contribution, Module, Phase, PlanCtx, Slots, Stage, Terms, Twin};
use crate::state::{Clock, Field, Particles, Work};

/// The constants of (4-53): P̄ (N·m per metre of depth in 2D) and the exponents n1 > n2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coef {
    pub pbar: f64,
    pub n1: i32,
    pub n2: i32,
}

/// `sph_penalty_force` over the pair list (ntotal = `mass.len()`).
pub struct Force<'a> {
    pub dim: usize,
    pub pairs: &'a PairList,
    pub x: &'a [f64],
    pub h: &'a [f64],
    pub mass: &'a [f64],
    pub mat: &'a [i32],
    pub mt: &'a MatTable,
    pub coef: Coef,
    /// Acceleration (m/s²), dim × ntotal.
    pub dvdt: &'a mut [f64],
}

impl Twin for Force<'_> {
    fn rust(&mut self) {
        rust::force(self)
    }
    fn fortran(&mut self) {
        ffi::force(self)
    }
}

/// The penalty term of the acceleration.
pub struct PenaltyStage {
    mt: MatTable,
    coef: Coef,
    slots: Slots,
    /// Axisymmetric: the force per unit length of a ring, divided by the planar mass.
    rz: bool,
}

impl Stage for PenaltyStage {
    fn module(&self) -> Module {
        Module::Penalty
    }
    fn name(&self) -> &'static str {
        "penalty.force"
    }
    fn reads(&self) -> &[Field] {
        if self.rz {
            &[Field::PairI, Field::PairJ, Field::X, Field::H, Field::Pmass, Field::Mat]
        } else {
            &[Field::PairI, Field::PairJ, Field::X, Field::H, Field::Mass, Field::Mat]
        }
    }
    fn writes(&self) -> &[Field] {
        &[Field::Acc]
    }
    fn prepare(&self, p: &mut Particles, w: &mut Work) {
        self.slots.size(w, p.dim, p.ntotal);
    }
    fn run(&self, b: Backend, p: &mut Particles, w: &mut Work, _k: &Clock) {
        let (dim, nt) = (p.dim, p.ntotal);
        let mass = if self.rz { &w.pmass[..nt] } else { &p.mass[..nt] };
        let (x, h, mat) = (&p.x[..dim * nt], &p.h[..nt], &p.mat[..nt]);
        let dvdt = &mut w.acc[self.slots.acc_range(dim * nt)];
        Force { dim, pairs: &w.pairs, x, h, mass, mat, mt: &self.mt, coef: self.coef, dvdt }.run(b);
    }
    fn terms(&self) -> Terms {
        Terms { acc: Some(2), de: None }
    }
    fn assign(&mut self, slots: Slots) {
        self.slots = slots;
    }
}

/// Runs when the case has a `[penalty]` and its regions use more than one penalty group that is
/// not exempt.
pub fn plan(ctx: &PlanCtx) -> Contribution {
    let case = ctx.case;
    // the groups in use, and the exempt materials (group < 0) by name, each once
    let mats: std::collections::BTreeSet<usize> =
        case.regions.iter().filter_map(|r| case.material_index(&r.material)).collect();
    let used: std::collections::BTreeSet<i32> = mats.iter().map(|&m| ctx.mt.group[m]).filter(|&g| g >= 0).collect();
    let exempt: Vec<&str> =
        mats.iter().filter(|&&m| ctx.mt.group[m] < 0).map(|&m| case.materials[m].name.as_str()).collect();
    let none = if exempt.is_empty() { String::new() } else { format!("; none on {}", exempt.join(", ")) };
    match &case.penalty {
        Some(p) if used.len() > 1 => Contribution::run(
            format!("{} penalty groups{none}", used.len()),
            vec![(
                Phase::Rates,
                Box::new(PenaltyStage {
                    mt: ctx.mt.clone(),
                    coef: Coef { pbar: p.pbar, n1: p.n1, n2: p.n2 },
                    slots: Slots::default(),
                    rz: case.axisymmetric(),
                }),
            )],
        ),
        Some(_) => Contribution::skip("one material group (besides those exempt): nothing to push apart"),
        None => Contribution::skip("no [penalty]"),
    }
}
