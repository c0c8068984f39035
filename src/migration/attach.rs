//! The bridge as the core sees it ([`crate::sim::Bridge`], [`crate::sim::Hook`]): the case's
//! `[compat]` table (its numbers as a legacy code writes them, the compat variants of the
//! modules' stages) and, with `--legacy DIR`, the user's routines in the plan.

use super::compat;
use super::legacy::Legacy;
use crate::case::Case;
use crate::error::Result;
use crate::modules::{Contribution, Module, PlanCtx};
use crate::setup::Initial;
use crate::sim::plan::{Entry, ModulePlan};
use crate::sim::{Bridge, Hook};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// What a command attaches to its runs: the `[compat]` table always, a legacy build if given.
#[derive(Debug, Clone, Default)]
pub struct LegacyBridge {
    /// The legacy build (`--legacy DIR`).
    pub dir: Option<PathBuf>,
    /// Only its set-up routine (the initial particles), no routine in the step.
    pub setup_only: bool,
    /// The routines run in a scratch folder, removed afterwards (`check`).
    pub scratch: bool,
    /// The warnings said so far: a run opened again through the same bridge says each once.
    pub said: Arc<Mutex<BTreeSet<String>>>,
    /// Host mode (`blastsph legacy host`): the user's own program calls the routines; the plan
    /// only gives each its Rust twins. No init or set-up routine is called.
    pub host: bool,
    /// The build as opened (host mode hands each call's values to its stages through it).
    pub opened: Opened,
}

/// The legacy build a bridge opened, for the caller that made the bridge.
#[derive(Clone, Default)]
pub struct Opened(pub Arc<Mutex<Option<Arc<Legacy>>>>);

impl std::fmt::Debug for Opened {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Opened")
    }
}

/// The bridge for a run: `dir` the legacy build, if any.
pub fn bridge(dir: Option<PathBuf>, setup_only: bool) -> Arc<dyn Bridge> {
    Arc::new(LegacyBridge { dir, setup_only, ..Default::default() })
}

/// The bridge for `check`: the legacy build's init and set-up routines run in a scratch folder,
/// so that `check` writes nothing in the user's folders.
pub fn check_bridge(dir: Option<PathBuf>) -> Arc<dyn Bridge> {
    Arc::new(LegacyBridge { dir, scratch: true, ..Default::default() })
}

struct Attached {
    legacy: Option<Arc<Legacy>>,
}

impl Bridge for LegacyBridge {
    fn attach(&self, case: &mut Case) -> Result<Arc<dyn Hook>> {
        // the case's own numbers as a legacy code writes them (nothing without `literals`)
        compat::apply_case(case)?;
        let legacy = match &self.dir {
            Some(d) => Some(Legacy::open(d, case, self)?),
            None => None,
        };
        if self.host {
            *self.opened.0.lock().unwrap_or_else(|e| e.into_inner()) = legacy.clone();
        }
        Ok(Arc::new(Attached { legacy }))
    }
}

impl Hook for Attached {
    fn setup(&self, case: &Case, init: Initial) -> Result<Initial> {
        let Some(l) = &self.legacy else { return Ok(init) };
        if l.host {
            // the user's program makes its own particles
            return Ok(init);
        }
        // before the set-up routine fills maxn-long arrays with the case's particles
        l.check_capacity(init.mass.len())?;
        let init = l.setup(case, init)?;
        l.check_capacity(init.mass.len())?;
        Ok(init)
    }

    fn contribution(&self, m: Module, ctx: &PlanCtx) -> Option<Contribution> {
        compat::plan(m, ctx)
    }

    fn edit_plan(
        &self,
        ctx: &PlanCtx,
        entries: &mut Vec<Entry>,
        modules: &mut BTreeMap<Module, ModulePlan>,
    ) -> (String, serde_json::Value) {
        match &self.legacy {
            Some(l) => l.edit_plan(ctx, entries, modules),
            None => (String::new(), serde_json::Value::Null),
        }
    }
}
