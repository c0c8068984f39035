//! The plan of a case: the ordered list of stages its step runs, which implementation runs each
//! module, and why each module runs or is skipped. Every decision about what a case models is
//! made here, once; the step only runs the list.

use crate::case::Case;
use crate::error::{Result, input};
use crate::modules::{Backend, Module, Phase, PlanCtx, Slots, Stage};
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
    /// Build the incidence lists after the search (some Rust twin gathers over them).
    pub incidence: bool,
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
        let mut entries = Vec::new();
        let mut modules = BTreeMap::new();
        for &m in Module::ALL {
            let c = m.plan(ctx);
            let backend = choice.get(&m).copied().unwrap_or(Backend::Rust);
            modules.insert(m, ModulePlan { active: !c.stages.is_empty(), backend, why: c.why });
            for (phase, stage) in c.stages {
                entries.push(Entry { phase, stage, backend, seconds: 0.0 });
            }
        }
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
        Plan { entries, modules, acc_terms, de_terms, incidence }
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
    pub fn text(&self) -> String {
        let mut s = String::from("module plan:\n");
        for (m, p) in &self.modules {
            if p.active {
                s += &format!("  {:<11} {:<8} {}  [{}]\n", m.name(), p.backend.name(), p.why, m.what());
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
                e.backend.name(),
                names(e.stage.reads()),
                names(e.stage.writes())
            );
            if e.phase == Phase::Search && self.incidence {
                s += "      search        (solver) incidence lists for the Rust gathers\n";
            }
        }
        if !self.acc_terms.is_empty() {
            s += &format!("acceleration = {} (+ gravity)\n", self.acc_terms.join(" + "));
        }
        if !self.de_terms.is_empty() {
            s += &format!("energy rate = {}\n", self.de_terms.join(" + "));
        }
        s
    }
}
