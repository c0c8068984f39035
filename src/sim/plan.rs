//! The plan of a case: the ordered list of stages its step runs, which implementation runs each
//! module, and why each module runs or is skipped. Every decision about what a case models is
//! made here, once; the step only runs the list.

use crate::case::Case;
use crate::error::{Result, input};
use crate::modules::{Backend, Counterpart, Module, Phase, PlanCtx, Slots, Stage};
use crate::state::Field;
use std::collections::BTreeMap;

/// Backend choices from the CLI, applied over the case's `[backend]` table.
#[derive(Debug, Clone, Default)]
pub struct Overrides {
    pub backend: Option<Backend>,
    pub rust: Vec<String>,
    pub fortran: Vec<String>,
    pub nnps: Option<String>,
    pub end_time: Option<f64>,
    /// The layer attached to the run ([`super::hook`]): it may edit the case, the initial
    /// particles and the plan.
    pub bridge: Option<std::sync::Arc<dyn super::Bridge>>,
    /// The largest particle count allowed (`--max-particles`); default: what fits in 80 % of
    /// the machine's memory ([`crate::case::size`]).
    pub max_particles: Option<u64>,
}

/// One stage of the step, with the implementation that runs it and the time it took.
pub struct Entry {
    pub phase: Phase,
    pub stage: Box<dyn Stage>,
    pub backend: Backend,
    /// Wall time spent in the stage (s).
    pub seconds: f64,
}

/// What the plan says of one module.
#[derive(Debug, Clone)]
pub struct ModulePlan {
    /// Its stages run.
    pub active: bool,
    pub backend: Backend,
    /// Why it runs, or why it is skipped.
    pub why: String,
}

pub struct Plan {
    /// The stages, in the order the step runs them (by phase, then module registry order).
    pub entries: Vec<Entry>,
    pub modules: BTreeMap<Module, ModulePlan>,
    /// The stage that owns each slot of the stacked acceleration and energy-rate terms.
    pub acc_terms: Vec<&'static str>,
    pub de_terms: Vec<&'static str>,
    /// How gravity enters the acceleration, as `check` prints it after the terms: empty without
    /// gravity, "(+ gravity)" when the integrator adds it, "(gravity inside the force stages)"
    /// under `physics.gravity_in_forces`.
    pub gravity: &'static str,
    /// Build the incidence lists after the search (some Rust twin gathers over them).
    pub incidence: bool,
    /// What the legacy routines replace and what is not run, for `blastsph check` (empty without
    /// `--legacy`).
    pub notes: String,
    /// The same for summary.json (`legacy`), null without `--legacy`.
    pub legacy: serde_json::Value,
}

/// A stage's implementation as printed: its backend, or "legacy" / "compat".
fn impl_of(e: &Entry) -> &'static str {
    match e.stage.counterpart() {
        Counterpart::Legacy | Counterpart::LegacyAlone(_) => "legacy",
        Counterpart::None(_) => "compat",
        Counterpart::Fortran => e.backend.name(),
    }
}

/// The implementation of every module: Rust by default (bitwise equal to the legacy core and
/// several times faster), then the case's `[backend]` table, then the command line.
pub fn choices(case: &Case, ov: &Overrides) -> Result<BTreeMap<Module, Backend>> {
    let all = |b: Backend| Module::ALL.iter().map(|&m| (m, b)).collect::<BTreeMap<_, _>>();
    let mut choice = all(Backend::Rust);
    if let Some(d) = &case.backend.default {
        choice = all(Backend::parse(d).unwrap_or(Backend::Fortran));
    }
    let unknown = |key: &str, m: &str| input(format!("{key}: unknown module `{m}` (modules: {})", Module::names()));
    // a module in both lists of one place is a contradiction, not a choice
    let both = |r: &[String], f: &[String], what: &str| -> Result<()> {
        match r.iter().find(|m| f.iter().any(|x| x.trim().eq_ignore_ascii_case(m.trim()))) {
            Some(m) => Err(input(format!("{what}: module `{}` is asked for in Rust and in Fortran", m.trim()))),
            None => Ok(()),
        }
    };
    both(&case.backend.rust, &case.backend.fortran, "backend.rust and backend.fortran")?;
    both(&ov.rust, &ov.fortran, "--rust and --fortran")?;
    for (list, b, key) in [
        (&case.backend.rust, Backend::Rust, "backend.rust"),
        (&case.backend.fortran, Backend::Fortran, "backend.fortran"),
    ] {
        for m in list {
            choice.insert(Module::parse(m).ok_or_else(|| unknown(key, m))?, b);
        }
    }
    if let Some(b) = ov.backend {
        choice = all(b);
    }
    for (list, b, flag) in [(&ov.rust, Backend::Rust, "--rust"), (&ov.fortran, Backend::Fortran, "--fortran")] {
        for m in list {
            let m = m.trim();
            choice.insert(Module::parse(m).ok_or_else(|| unknown(flag, m))?, b);
        }
    }
    Ok(choice)
}

impl Plan {
    /// Asks every module for its stages, orders them, and gives the rate terms their slots.
    pub fn build(ctx: &PlanCtx, choice: &BTreeMap<Module, Backend>) -> Plan {
        Self::build_with(ctx, choice, None)
    }

    /// As [`Plan::build`], with the run's hook ([`super::Hook`]): a module may contribute the
    /// hook's stages in place of its own (a stage without a Fortran twin runs in Rust), and the
    /// hook edits the plan last.
    pub fn build_with(ctx: &PlanCtx, choice: &BTreeMap<Module, Backend>, hook: Option<&dyn super::Hook>) -> Plan {
        let mut entries = Vec::new();
        let mut modules = BTreeMap::new();
        for &m in Module::ALL {
            let c = hook.and_then(|h| h.contribution(m, ctx)).unwrap_or_else(|| m.plan(ctx));
            let backend = choice.get(&m).copied().unwrap_or(Backend::Rust);
            modules.insert(m, ModulePlan { active: !c.stages.is_empty(), backend, why: c.why });
            for (phase, stage) in c.stages {
                let backend = match stage.counterpart() {
                    Counterpart::None(_) => Backend::Rust,
                    _ => backend,
                };
                entries.push(Entry { phase, stage, backend, seconds: 0.0 });
            }
        }
        let (notes, legacy) = match hook {
            Some(h) => h.edit_plan(ctx, &mut entries, &mut modules),
            None => (String::new(), serde_json::Value::Null),
        };
        // by phase; within a phase the registry order (the sort is stable)
        entries.sort_by_key(|e| e.phase);
        // the rate terms in rank order: their slots, and the order of the sums
        let ranked = |f: &dyn Fn(&Entry) -> Option<u8>| -> Vec<(u8, usize)> {
            let mut v: Vec<(u8, usize)> =
                entries.iter().enumerate().filter_map(|(k, e)| f(e).map(|r| (r, k))).collect();
            v.sort();
            v
        };
        let acc = ranked(&|e| e.stage.terms().acc);
        let de = ranked(&|e| e.stage.terms().de);
        let (nacc, nde) = (acc.len(), de.len());
        for k in 0..entries.len() {
            let slots = Slots {
                acc: acc.iter().position(|t| t.1 == k).unwrap_or(0),
                de: de.iter().position(|t| t.1 == k).unwrap_or(0),
                nacc,
                nde,
            };
            entries[k].stage.assign(slots);
        }
        let acc_terms = acc.iter().map(|t| entries[t.1].stage.name()).collect();
        let de_terms = de.iter().map(|t| entries[t.1].stage.name()).collect();
        let incidence = entries.iter().any(|e| e.backend == Backend::Rust);
        let gravity = match (ctx.case.gravity_on(), ctx.case.physics.gravity_in_forces) {
            (false, _) => "",
            (true, false) => " (+ gravity)",
            (true, true) => " (gravity inside the force stages)",
        };
        Plan { entries, modules, acc_terms, de_terms, gravity, incidence, notes, legacy }
    }

    pub fn is_active(&self, m: Module) -> bool {
        self.modules.get(&m).is_some_and(|p| p.active)
    }

    pub fn backend(&self, m: Module) -> Backend {
        self.modules.get(&m).map_or(Backend::Rust, |p| p.backend)
    }

    pub fn why(&self, m: Module) -> &str {
        self.modules.get(&m).map_or("", |p| p.why.as_str())
    }

    /// True when some stage writes `f` (the case models it).
    pub fn writes(&self, f: Field) -> bool {
        self.entries.iter().any(|e| e.stage.writes().contains(&f))
    }

    /// True when the plan has the stage `name` (e.g. `penalty.force`).
    pub fn has(&self, name: &str) -> bool {
        self.entries.iter().any(|e| e.stage.name() == name)
    }

    /// The acceleration slot of the stage `name`, if it has one.
    pub fn acc_slot(&self, name: &str) -> Option<usize> {
        self.acc_terms.iter().position(|t| *t == name)
    }

    /// "fortran", "rust" or "mixed" over the active modules.
    pub fn label(&self) -> &'static str {
        let active = self.modules.values().filter(|p| p.active);
        let f = active.clone().any(|p| p.backend == Backend::Fortran);
        let r = active.clone().any(|p| p.backend == Backend::Rust);
        match (f, r) {
            (true, false) => "fortran",
            (false, true) => "rust",
            _ => "mixed",
        }
    }

    /// The modules some of whose stages run a user's legacy routine (`--legacy`), in plan order.
    pub fn legacy_modules(&self) -> Vec<&'static str> {
        let mut v: Vec<&'static str> = Vec::new();
        for e in &self.entries {
            if matches!(e.stage.counterpart(), Counterpart::Legacy | Counterpart::LegacyAlone(_)) {
                let name = e.stage.module().name();
                if !v.contains(&name) {
                    v.push(name);
                }
            }
        }
        v
    }

    /// Seconds spent in each active module's stages.
    pub fn module_seconds(&self) -> BTreeMap<Module, f64> {
        let mut s: BTreeMap<Module, f64> =
            self.modules.iter().filter(|(_, p)| p.active).map(|(m, _)| (*m, 0.0)).collect();
        for e in &self.entries {
            *s.entry(e.stage.module()).or_default() += e.seconds;
        }
        s
    }

    /// The plan as `blastsph check` prints it: the modules (what each computes, which
    /// implementation, why), then the stages of a step in order with what they read and write.
    /// One line per mapped legacy routine that does not run although the case runs its
    /// modules (it computes none of their stages from its arguments): blastsph's own stages run
    /// in its place, which a dual run would otherwise report as agreement.
    pub fn legacy_warnings(&self) -> Vec<String> {
        let Some(routines) = self.legacy["routines"].as_object() else { return Vec::new() };
        routines
            .iter()
            .filter(|(_, r)| r["replaced"] == serde_json::json!(false))
            .map(|(name, r)| format!("legacy {name} is not run: {}", r["why"].as_str().unwrap_or("")))
            .collect()
    }

    /// What runs module `m`, as `check` and summary.json name it: "legacy" where a user's
    /// routine stands for its stages, "compat" for a compat variant, else its backend.
    pub fn implementation(&self, m: Module) -> &'static str {
        let Some(p) = self.modules.get(&m) else { return Backend::Rust.name() };
        if p.why.starts_with("legacy ") {
            return "legacy";
        }
        let mine = self.entries.iter().filter(|e| e.stage.module() == m && e.phase != Phase::Init);
        mine.map(impl_of).find(|l| *l != "fortran" && *l != "rust").unwrap_or(p.backend.name())
    }

    pub fn text(&self) -> String {
        let mut s = String::from("module plan:\n");
        for (m, p) in &self.modules {
            if p.active {
                let label = self.implementation(*m);
                s += &format!("  {:<11} {:<8} {}  [{}]\n", m.name(), label, p.why, m.what());
            } else {
                s += &format!("  {:<11} {:<8} {}\n", m.name(), "skipped", p.why);
            }
        }
        let names = |fs: &[Field]| fs.iter().map(|f| f.name()).collect::<Vec<_>>().join(" ");
        s += "step (stages in order; init runs once before the first step, predict from the second):\n";
        for (k, e) in self.entries.iter().enumerate() {
            let ph = format!("{:?}", e.phase).to_lowercase();
            s += &format!(
                "  {:>2}. {:<13} {:<24} {:<8} reads {} -> writes {}\n",
                k + 1,
                ph,
                e.stage.name(),
                impl_of(e),
                names(e.stage.reads()),
                names(e.stage.writes())
            );
            if e.phase == Phase::Search && self.incidence {
                s += "      search        (solver) incidence lists for the Rust gathers\n";
            }
        }
        if !self.acc_terms.is_empty() {
            s += &format!("acceleration = {}{}\n", self.acc_terms.join(" + "), self.gravity);
        }
        if !self.de_terms.is_empty() {
            s += &format!("energy rate = {}\n", self.de_terms.join(" + "));
        }
        s + &self.notes
    }
}
