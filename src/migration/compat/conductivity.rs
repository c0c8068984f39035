//! The artificial heat as Liu & Liu's book code writes its constants (`--compat`, item
//! `literals`; docs/compat-liu-book.md §13): φ²/h̄² is the default-real literal `0.01`, rounded to
//! single precision, and the case's g1, g2 are rounded by `migration::compat::apply_case`. The
//! book's operation order is the twin's own, so the stage is blastsph's, with its Fortran twin.

use super::{Flags, Item, single};
use crate::case::ConductivityKind;
use crate::modules::conductivity::{HeatCoef, HeatStage};
use crate::modules::{Contribution, Phase, PlanCtx, Slots};

/// The book's art_heat constants, when `literals` is on and the case has the artificial heat.
pub fn plan(ctx: &PlanCtx, f: Flags) -> Option<Contribution> {
    let c = &ctx.case.conductivity;
    if !f.has(Item::Literals) || c.kind != ConductivityKind::Noh || !c.on() {
        return None;
    }
    let normal = crate::modules::conductivity::plan(ctx);
    let coef = HeatCoef { g1: c.g1(), g2: c.g2(), phi2: single(HeatCoef::PHI2) };
    let st = HeatStage { coef, slots: Slots::default() };
    Some(Contribution::run(
        format!("{}, phi2 = {} [compat {}]", normal.why, coef.phi2, f.label()),
        vec![(Phase::Rates, Box::new(st))],
    ))
}
