//! The one place where a layer outside the core attaches to a run. The core defines these two
//! traits and calls them at fixed points of [`super::Sim::new`] and [`super::Plan::build_with`];
//! it knows nothing of what implements them. The legacy-code bridge (`blastsph legacy`, the
//! case's `[compat]` table) is such a layer.
//!
//! A caller hands a [`Bridge`] in [`super::Overrides::bridge`]. Without one, the core runs the
//! case as written and refuses a `[compat]` table, which only a bridge can give a meaning.

use crate::case::Case;
use crate::error::Result;
use crate::modules::{Contribution, Module, PlanCtx};
use crate::setup::Initial;
use crate::sim::plan::{Entry, ModulePlan};
use std::collections::BTreeMap;
use std::sync::Arc;

/// What a caller hands to [`super::Sim::new`]: it sees the case first and returns the run's hook.
pub trait Bridge: Send + Sync + std::fmt::Debug {
    /// Checks and edits the case before anything is built from it (rounding its numbers as a
    /// legacy code writes them, say); returns the hook the run consults afterwards.
    fn attach(&self, case: &mut Case) -> Result<Arc<dyn Hook>>;
}

/// The run's hook: consulted while the run is built, never inside a step (stages it adds run
/// like any other stage).
pub trait Hook: Send + Sync {
    /// Replaces or edits the initial particles the case's regions made.
    fn setup(&self, _case: &Case, init: Initial) -> Result<Initial> {
        Ok(init)
    }

    /// The stages module `m` contributes in place of its own plan, or `None` for its own.
    fn contribution(&self, _m: Module, _ctx: &PlanCtx) -> Option<Contribution> {
        None
    }

    /// Edits the ordered stages and the module lines once every module has contributed. Returns
    /// the notes `blastsph check` prints and the record summary.json keeps (null for none).
    fn edit_plan(
        &self,
        _ctx: &PlanCtx,
        _entries: &mut Vec<Entry>,
        _modules: &mut BTreeMap<Module, ModulePlan>,
    ) -> (String, serde_json::Value) {
        (String::new(), serde_json::Value::Null)
    }
}
