//! Putting the mapped routines into the plan: which stages each stands for, where in the step
//! it runs, and the text and summary that `check` prints.

use super::*;
use crate::migration::builder::RoutineInfo;

/// A stage with its phase.
type Slot = (Phase, Box<dyn Stage>);

/// Stages with their phases.
type Staged = Vec<Slot>;

/// The stages module `m` contributes to this case (its compat variants where asked), the
/// once-only `Init` ones left out.
fn fresh(m: Module, ctx: &PlanCtx) -> Vec<(Phase, Box<dyn Stage>)> {
    let c = crate::migration::compat::plan(m, ctx).unwrap_or_else(|| m.plan(ctx));
    c.stages.into_iter().filter(|(ph, _)| *ph != Phase::Init).collect()
}

/// Which sound speed each side of an EOS routine that gives p only uses.
const C_SIDES: &str = "c is not among its arguments: the legacy side leaves c at 0 (your program's array that nothing writes), the Rust twin uses its own c; p compared, c not";

/// What became of one mapped routine, for `check` and summary.json.
struct Note {
    name: String,
    status: &'static str,
    why: String,
    json: serde_json::Value,
}

impl Legacy {
    /// Puts the mapped routines into the plan in place of the stages they stand for; returns the
    /// text `blastsph check` prints and the summary's `legacy` object.
    pub fn edit_plan(
        self: &Arc<Self>,
        ctx: &PlanCtx,
        entries: &mut Vec<Entry>,
        modules: &mut BTreeMap<Module, ModulePlan>,
    ) -> (String, serde_json::Value) {
        let info = self.lib.info();
        let mut notes: Vec<Note> = Vec::new();
        // the routines not run as of another formulation than the case's (below: NOT RUN where
        // no other routine stands for their module)
        let mut other_formulation: Vec<String> = Vec::new();
        let bound: Vec<Vec<String>> =
            info.routines.iter().map(|r| r.bindings.iter().map(|b| b.name.clone()).collect()).collect();
        for (ri, r) in info.routines.iter().enumerate() {
            notes.push(self.place_routine(
                ctx,
                (&mut *entries, &mut *modules),
                r,
                (ri, &bound),
                &mut other_formulation,
            ));
        }
        order_as_book(entries);
        let place = if self.scratch {
            format!(
                "a scratch folder, {}, removed when this ends: nothing is written in {}",
                self.cwd.display(),
                self.dir.join("work").display()
            )
        } else {
            self.cwd.display().to_string()
        };
        let mut text = format!(
            "legacy routines ({}, dim {}, maxn {}, max_interaction {}; they run in {place}):\n",
            self.dir.display(),
            info.dim,
            info.maxn,
            info.max_interaction,
        );
        // a routine of another formulation (the book's con_density in a summation case) is no
        // miss where another mapped routine stands for its module (sum_density); where none
        // does, nothing of the user's ran for that module and the routine counts as NOT RUN (a
        // Tait EOS mapped alone in a case whose EOS reads e: the verdict read as agreement)
        let mods_of =
            |name: &str| info.routines.iter().find(|r| r.name == name).map(|r| r.modules.clone()).unwrap_or_default();
        let ran: Vec<String> = notes.iter().filter(|n| n.status == "run").flat_map(|n| mods_of(&n.name)).collect();
        for n in notes.iter_mut() {
            if other_formulation.contains(&n.name) {
                let mods = mods_of(&n.name);
                if !mods.iter().any(|m| ran.contains(m)) {
                    n.json["replaced"] = json!(false);
                    n.why += &format!(
                        "; no mapped routine stands for {}: blastsph's own stages run in its place",
                        mods.join(",")
                    );
                }
            }
        }
        let mut routines = serde_json::Map::new();
        for n in &notes {
            text += &format!("  {:<14} {:<8} {}\n", n.name, n.status, n.why);
            let mut j = n.json.clone();
            j["status"] = json!(n.status);
            j["why"] = json!(n.why);
            routines.insert(n.name.clone(), j);
        }
        let summary = json!({ "dir": self.dir.display().to_string(), "cwd": self.cwd.display().to_string(), "routines": routines });
        (text, summary)
    }

    /// The note of a routine that runs outside the step (a set-up, `virt_part`, an initialiser),
    /// or not at all (an output routine; every routine of a set-up-only run); `None` for the rest.
    fn outside_the_step(&self, r: &RoutineInfo) -> Option<Note> {
        let note = |status: &'static str, why: String, json: serde_json::Value| Note {
            name: r.name.clone(),
            status,
            why,
            json,
        };
        if r.modules.iter().any(|m| m == "setup") {
            return Some(note(
                "setup",
                "makes the initial particles (called once, before the first step)".into(),
                json!({}),
            ));
        }
        if let Some(k) = &r.virtual_kind {
            // (not yet called, as in host mode, where the program calls it: no count to give)
            let Some((n, k)) = self.shared().virt_made.clone() else {
                let why = format!("makes the boundary particles, {k} (with --legacy, called once after the set-up)");
                return Some(note("setup", why, json!({ "virtual": k })));
            };
            let why = format!("made {n} boundary particles, {k} (called once after the set-up, with itimestep = 1)");
            return Some(note("setup", why, json!({ "virtual": k, "made": n })));
        }
        if r.modules.iter().any(|m| m == "init") {
            return Some(note(
                "init",
                "fills its COMMON blocks (called once, before the set-up and the first step)".into(),
                json!({}),
            ));
        }
        if r.modules.iter().any(|m| m == "output") {
            return Some(note("not run", "an output routine: blastsph writes particles.h5".into(), json!({})));
        }
        if self.setup_only {
            return Some(note("not run", "set-up only (the ledger's Rust runs)".into(), json!({})));
        }
        None
    }

    /// Puts mapped routine `r` (the `ri`-th of `bound`) into the plan in place of the stages it
    /// stands for, if it stands for any; what became of it.
    fn place_routine(
        self: &Arc<Self>,
        ctx: &PlanCtx,
        (entries, modules): (&mut Vec<Entry>, &mut BTreeMap<Module, ModulePlan>),
        r: &RoutineInfo,
        (ri, bound): (usize, &[Vec<String>]),
        other_formulation: &mut Vec<String>,
    ) -> Note {
        let note = |status: &'static str, why: String, json: serde_json::Value| Note {
            name: r.name.clone(),
            status,
            why,
            json,
        };
        if let Some(n) = self.outside_the_step(r) {
            return n;
        }
        let mut mods: Vec<Module> = r.modules.iter().filter_map(|m| Module::parse(m)).collect();
        if mods.contains(&Module::Integrator) || mods.len() > 3 {
            return note(
                "not run",
                format!(
                    "a driver spanning {}: --legacy runs the routines it calls (map those); compare its program with `run --legacy`",
                    r.modules.join(",")
                ),
                json!({}),
            );
        }
        let (argf, covered, helpers) = cover_routine(ctx, &mut mods, &bound[ri]);
        let mut writes: Vec<Field> = Vec::new();
        let alone = covered.is_empty();
        if alone {
            match alone_writes(ctx, (entries, modules), (r, ri, bound), (&mods, &argf), other_formulation) {
                Ok(w) => writes = w,
                Err(n) => return n,
            }
        }
        let reads = merge_fields(&covered, &helpers, alone, &argf, &mut writes);
        // an EOS that gives p only: c is not its output (the state's c is set to the program's
        // array that nothing writes, 0, at each call)
        let zero_c = covered.iter().any(|(_, s)| lacks_c_only(s.as_ref(), &argf));
        if zero_c {
            writes.retain(|f| *f != Field::C);
        }
        // where the stages it stands for are in the step
        let pos = places(entries, &covered);
        let (maker, clash) = order_in_step(entries, &pos, &reads, &writes);
        // what the maker makes of the routine's inputs
        let made: Vec<String> = maker.map_or(Vec::new(), |m| {
            entries[m].stage.writes().iter().filter(|f| reads.contains(f)).map(|f| f.name()).collect()
        });
        if let (Some((name, f)), Some(m)) = (clash, maker) {
            let why = format!(
                "it stands for {} of different places in the step: {name} between them reads its {}, and {} after it makes its {}; called at either place it would read or give a stale value, so blastsph's own {} runs in its place (map it as separate routines)",
                covered.iter().map(|(_, s)| s.name()).collect::<Vec<_>>().join(" + "),
                f.name(),
                entries[m].stage.name(),
                made.join(", "),
                r.modules.join(",")
            );
            return note("not run", why, json!({ "replaced": false }));
        }
        let after: String = maker.map_or(String::new(), |m| {
            format!(", after {} (which makes its {})", entries[m].stage.name(), made.join(", "))
        });
        // the phase: the maker's, or the first of the stages it stands for
        let phase = maker
            .map(|m| entries[m].phase)
            .or_else(|| covered.iter().map(|(ph, _)| *ph).min())
            .or_else(|| mods.iter().flat_map(|&m| fresh(m, ctx)).map(|(ph, _)| ph).min())
            .unwrap_or(Phase::Rates);
        let at = remove_covered(entries, &pos, maker);
        let module = covered.first().map_or(mods[0], |(_, s)| s.module());
        let terms = covered.iter().map(|(_, s)| s.terms()).find(|t| *t != Terms::default()).unwrap_or_else(|| {
            let k = ri as u8;
            Terms {
                acc: writes.contains(&Field::Acc).then_some(10 + k),
                de: writes.contains(&Field::Dde).then_some(10 + k),
            }
        });
        let twins: Vec<String> = helpers.iter().chain(&covered).map(|(_, s)| s.name().to_string()).collect();
        let mut tol = self.tolerance_of(r, &mods, (&helpers, &covered), alone, &twins);
        if zero_c {
            tol.why = Box::leak(format!("{}; {C_SIDES}", tol.why).into_boxed_str());
        }
        let why_alone: Option<&'static str> = alone.then(|| {
            &*Box::leak(
                format!("legacy {}: no Rust twin in this case; runs alone, not compared", r.name).into_boxed_str(),
            )
        });
        let chain: Vec<Box<dyn Stage>> = helpers.into_iter().chain(covered).map(|(_, s)| s).collect();
        let real_rows = real_rows_of(&writes, &chain);
        let stage = LegacyStage {
            lg: Arc::clone(self),
            routine: ri,
            name: Box::leak(format!("legacy.{}", r.name).into_boxed_str()),
            module,
            chain,
            reads,
            writes: writes.clone(),
            real_rows,
            terms,
            slots: Slots::default(),
            tol,
            alone: why_alone,
            replay: Mutex::new(None),
            input_writes: Mutex::new(Vec::new()),
            zero_c,
        };
        let entry = Entry { phase, stage: Box::new(stage), backend: Backend::Fortran, seconds: 0.0 };
        match at {
            Some(k) => entries.insert(k, entry),
            None => entries.push(entry),
        }
        for m in &mods {
            if let Some(mp) = modules.get_mut(m)
                && !alone
            {
                mp.why = format!("legacy {} [{}]; {}", r.name, self.dir.display(), mp.why);
            }
        }
        let ph = format!("{phase:?}").to_lowercase();
        let what = if alone {
            "no Rust twin yet: runs alone in its place, not compared".to_string()
        } else if zero_c {
            format!("stands for {} for p only; {C_SIDES}", twins.join(" + "))
        } else {
            format!("stands for {}", twins.join(" + "))
        };
        let mut j =
            json!({ "stands_for": twins, "phase": ph, "writes": writes.iter().map(|f| f.name()).collect::<Vec<_>>() });
        if zero_c {
            j["c"] = json!("legacy: 0, an array no routine writes; Rust twin: its own");
        }
        note(if alone { "alone" } else { "run" }, format!("{what}; phase {ph}{after}"), j)
    }

    /// The tolerance of routine `r` against the stages it stands for: the twins compared, the
    /// compat items of their modules that are off.
    fn tolerance_of(
        &self,
        r: &RoutineInfo,
        mods: &[Module],
        (helpers, covered): (&[Slot], &[Slot]),
        alone: bool,
        twins: &[String],
    ) -> Tolerance {
        let label =
            if self.flags.is_empty() { "no --compat".to_string() } else { format!("compat {}", self.flags.label()) };
        // the items of the routine's modules and of the twins it is compared with (the
        // book's sum_density computes W(0) with the kernel: kernel items)
        let mut twin_mods: Vec<Module> = mods.to_vec();
        twin_mods.extend(helpers.iter().chain(covered).map(|(_, s)| s.module()));
        let off: Vec<&str> = Item::all()
            .filter(|&i| !self.flags.has(i) && twin_mods.iter().any(|m| i.modules().split(',').any(|x| x == m.name())))
            .map(Item::name)
            .collect();
        let mut hint =
            if off.is_empty() { String::new() } else { format!("; compat items off here: {}", off.join(", ")) };
        // the repulsion adds the gravity itself under physics.gravity_in_forces
        let with_gravity = twins.iter().any(|t| t == "boundary.repulsion");
        if !alone && !with_gravity && self.lib.info().gravity_in.as_deref() == Some(r.name.as_str()) {
            hint += &format!("; {}", crate::dual::GRAVITY_NOTE);
        }
        Tolerance {
            ulp: 0,
            why: Box::leak(
                format!(
                    "legacy {} against {} ({label}){hint}",
                    r.name,
                    if alone { "nothing".into() } else { twins.join(" + ") }
                )
                .into_boxed_str(),
            ),
        }
    }
}

/// The fields of a routine's arguments `names`, the stages it stands for and their helpers
/// ([`cover`]). A routine mapped to `force` alone that stands for no force stage (the book's
/// `ext_force`) stands for the repulsion of boundary particles where the case has it: `mods`
/// then gains the boundary.
fn cover_routine(ctx: &PlanCtx, mods: &mut Vec<Module>, names: &[String]) -> (Vec<Field>, Staged, Staged) {
    let mut argf: Vec<Field> = names.iter().filter_map(|n| bind::field_of(n)).collect();
    // the book's itype is negative on a boundary particle: it gives the boundary kinds too
    if names.iter().any(|n| n == "itype") {
        argf.push(Field::Bnd);
    }
    let (mut covered, mut helpers) = cover(ctx, mods, &argf);
    if covered.is_empty() && *mods == [Module::Force] && ctx.case.boundary.repulsion.is_some() {
        (covered, helpers) = cover(ctx, &[Module::Boundary], &argf);
        covered.retain(|(_, s)| s.name() == "boundary.repulsion");
        if !covered.is_empty() {
            mods.push(Module::Boundary);
        }
    }
    (argf, covered, helpers)
}

/// The stages of modules `mods` that a routine with the arguments `argf` stands for, and the
/// helper stages that make inside it the inputs not among its arguments.
fn cover(ctx: &PlanCtx, mods: &[Module], argf: &[Field]) -> (Staged, Staged) {
    let satisfied = |s: &dyn Stage| s.reads().iter().all(|f| argf.contains(f) || IMPLIED.contains(f));
    let mut covered: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
    let mut helpers: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
    for &m in mods {
        for (ph, s) in fresh(m, ctx) {
            if !s.writes().iter().all(|f| argf.contains(f) || lacks_c_only(s.as_ref(), argf)) {
                continue;
            }
            // inputs not among the arguments: made inside the routine by a helper stage
            let mut need: Vec<(Phase, Box<dyn Stage>)> = Vec::new();
            let mut ok = true;
            for f in s.reads().iter().filter(|f| !argf.contains(f) && !IMPLIED.contains(f)) {
                let h = Module::ALL
                    .iter()
                    .flat_map(|&hm| fresh(hm, ctx))
                    .find(|(_, h)| h.writes() == [*f] && satisfied(h.as_ref()));
                match h {
                    Some(h) => need.push(h),
                    None => ok = false,
                }
            }
            if ok {
                for h in need {
                    if !helpers.iter().any(|x| x.1.name() == h.1.name()) {
                        helpers.push(h);
                    }
                }
                covered.push((ph, s));
            }
        }
    }
    (covered, helpers)
}

/// The outputs of routine `r` (the `ri`-th of `bound`) when it stands for no stage: the rate
/// terms it adds; or, where it is not run, what became of it.
fn alone_writes(
    ctx: &PlanCtx,
    (entries, modules): (&[Entry], &BTreeMap<Module, ModulePlan>),
    (r, ri, bound): (&RoutineInfo, usize, &[Vec<String>]),
    (mods, argf): (&[Module], &[Field]),
    other_formulation: &mut Vec<String>,
) -> std::result::Result<Vec<Field>, Note> {
    let note =
        |status: &'static str, why: String, json: serde_json::Value| Note { name: r.name.clone(), status, why, json };
    let active = mods.iter().any(|m| modules.get(m).is_some_and(|p| p.active));
    let mut writes: Vec<Field> = Vec::new();
    let shared_scratch = bound[ri]
        .iter()
        .any(|n| bind::is_scratch(n) && bound.iter().enumerate().any(|(o, names)| o != ri && names.contains(n)));
    let term = bound[ri].iter().any(|n| n == "dvxdt" || n == "dedt");
    if !active {
        return Err(note("not run", format!("the case does not run {}", r.modules.join(",")), json!({})));
    }
    // for each stage it might stand for, what it writes and what it reads that are
    // not among the routine's arguments
    let missing: Vec<(&'static str, Vec<String>, Vec<String>)> = mods
        .iter()
        .flat_map(|&m| fresh(m, ctx))
        .map(|(_, s)| {
            let names = |fs: &[Field], implied: bool| -> Vec<String> {
                fs.iter()
                    .filter(|f| !(argf.contains(f) || (implied && IMPLIED.contains(f))))
                    .map(|f| f.name().to_string())
                    .collect()
            };
            (s.name(), names(s.writes(), false), names(s.reads(), true))
        })
        .collect();
    // a near miss: a stage whose inputs are all among the arguments but not all its
    // outputs (the same physics, one output short; a routine of another formulation,
    // the book's con_density in a summation case, is no miss)
    let near = missing.iter().any(|(_, out, inp)| inp.is_empty() && !out.is_empty());
    let lacks: Vec<String> = missing
        .iter()
        .map(|(name, out, inp)| {
            if out.is_empty() {
                format!("{name} reads {}", inp.join(", "))
            } else {
                format!("{name} also writes {}", out.join(", "))
            }
        })
        .collect();
    let hint = if ctx.case.time.viscous_step && mods.contains(&Module::Viscosity) && !argf.contains(&Field::Mumax) {
        " (mumax, the largest mu_ij, is asked for by the viscous time-step limit: --set time.viscous_step=false drops it)"
    } else {
        ""
    };
    // the stages of the case's other modules that its arguments would compute
    // whole (a routine mapped under the wrong `module`: an EOS given as density)
    let fits: Vec<String> = if near {
        Vec::new()
    } else {
        Module::ALL
            .iter()
            .filter(|m| !mods.contains(m) && modules.get(m).is_some_and(|p| p.active))
            .flat_map(|&m| fresh(m, ctx))
            .filter(|(_, s)| {
                // a stage that only corrects what it reads (the density clamp) fits any
                // routine that holds the field: no sign of a misplaced module
                s.writes().iter().any(|f| !s.reads().contains(f))
                    && s.writes().iter().all(|f| argf.contains(f))
                    && s.reads().iter().all(|f| argf.contains(f) || IMPLIED.contains(f))
            })
            .map(|(_, s)| s.name().to_string())
            .collect()
    };
    if !(term || shared_scratch || fits.is_empty()) {
        let other: Vec<&str> = fits.iter().filter_map(|f| f.split('.').next()).collect();
        let why = format!(
            "it computes none of the {} stages from its arguments ({}, not among them), but its arguments fit {} of another module: is its manifest's module = \"{}\"? blastsph's own {} runs in its place",
            r.modules.join(","),
            lacks.join("; "),
            fits.join(", "),
            other.first().copied().unwrap_or(""),
            other.join(",")
        );
        return Err(note("not run", why, json!({ "replaced": false })));
    }
    if !(term || shared_scratch) {
        let why = if near {
            format!(
                "it computes none of the case's {} stages from its arguments: {}, not among them{hint}; blastsph's own {} runs in its place",
                r.modules.join(","),
                lacks.join("; "),
                r.modules.join(",")
            )
        } else {
            format!(
                "it computes none of the case's {} stages from its arguments ({}, not among them: the case uses another formulation)",
                r.modules.join(","),
                lacks.join("; ")
            )
        };
        let n = note("not run", why, if near { json!({ "replaced": false }) } else { json!({}) });
        if !near {
            other_formulation.push(r.name.clone());
        }
        return Err(n);
    }
    // a routine that adds rate terms beside a Rust stage of its own module that it
    // cannot stand for (that stage writes something the routine does not give) would
    // count the same physics twice: the Rust stage runs, the routine does not
    let left: Vec<&str> = entries
        .iter()
        .filter(|e| e.phase != Phase::Init && mods.contains(&e.stage.module()))
        .map(|e| e.stage.name())
        .collect();
    if term && !left.is_empty() {
        let why = format!(
            "it adds rate terms of {} but cannot stand for {} ({}, not among its arguments{hint}); running both would count that physics twice, so blastsph's own {} runs in its place",
            r.modules.join(","),
            left.join(", "),
            lacks.join("; "),
            r.modules.join(",")
        );
        return Err(note("not run", why, json!({ "replaced": false })));
    }
    if bound[ri].iter().any(|n| n == "dvxdt") {
        writes.push(Field::Acc);
    }
    if bound[ri].iter().any(|n| n == "dedt") {
        writes.push(Field::Dde);
    }
    Ok(writes)
}

/// True for an EOS stage whose only output missing from the arguments `argf` is the sound speed,
/// p being among them: a routine that gives p only stands for it, and c is then the program's
/// array that nothing writes (0).
fn lacks_c_only(s: &dyn Stage, argf: &[Field]) -> bool {
    s.module() == Module::Eos
        && argf.contains(&Field::P)
        && !argf.contains(&Field::C)
        && s.writes().iter().all(|f| argf.contains(f) || *f == Field::C)
}

/// Where in the step a routine standing for the stages at `pos` runs: the last stage between
/// them that makes one of its `reads` (the maker), and a stage between the first place and the
/// maker that reads one of its `writes` (the clash).
fn order_in_step(
    entries: &[Entry],
    pos: &[usize],
    reads: &[Field],
    writes: &[Field],
) -> (Option<usize>, Option<(&'static str, Field)>) {
    // A routine standing for stages of several phases runs at the first of them, unless
    // a stage of its own step between them makes one of its inputs (a "density,force"
    // routine reads the p the EOS writes after the density rate): then it runs after the
    // last such maker, so that it reads what its twins read where they stood. A stage
    // between the first place and that maker that reads one of its outputs would then
    // read a stale value: such a routine cannot stand for these stages, and is not run.
    // (The entries are in the modules' order here; the step is their stable sort by
    // phase, so a stage's place in the step is (phase, index).)
    let key = |k: usize| (entries[k].phase, k);
    let (first, last) = (pos.iter().map(|&k| key(k)).min(), pos.iter().map(|&k| key(k)).max());
    let between = |k: usize, a: (Phase, usize), b: (Phase, usize)| {
        !pos.contains(&k) && entries[k].phase != Phase::Init && key(k) > a && key(k) < b
    };
    let mut maker: Option<usize> = None;
    if let (Some(a), Some(b)) = (first, last) {
        for k in 0..entries.len() {
            if between(k, a, b)
                && entries[k].stage.writes().iter().any(|f| reads.contains(f))
                && maker.is_none_or(|m| key(k) > key(m))
            {
                maker = Some(k);
            }
        }
    }
    let mut clash = None;
    if let (Some(a), Some(m)) = (first, maker) {
        clash = (0..entries.len()).filter(|&k| between(k, a, key(m))).find_map(|k| {
            let e = &entries[k];
            e.stage.reads().iter().find(|f| writes.contains(f)).map(|f| (e.stage.name(), *f))
        });
    }
    (maker, clash)
}

/// Legacy stages of the book's `single_step` keep its order: one that comes earlier in the book
/// but sits in a later phase moves just before the other (the physical `viscosity`, whose `eta`
/// `int_force` reads).
fn order_as_book(entries: &mut Vec<Entry>) {
    let seq = |e: &Entry| -> Option<usize> {
        (e.stage.counterpart() != Counterpart::Fortran)
            .then(|| e.stage.name().strip_prefix("legacy."))
            .flatten()
            .and_then(|n| BOOK_ORDER.iter().position(|b| *b == n))
    };
    loop {
        let mut moved = false;
        'outer: for a in 0..entries.len() {
            let Some(sa) = seq(&entries[a]) else { continue };
            for b in 0..entries.len() {
                let Some(sb) = seq(&entries[b]) else { continue };
                if sa < sb && entries[a].phase > entries[b].phase {
                    let target = entries[b].phase;
                    let mut e = entries.remove(a);
                    e.phase = target;
                    entries.insert(if b < a { b } else { b - 1 }, e);
                    moved = true;
                    break 'outer;
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// Adds to `writes` what the covered stages write; what the routine reads: the covered stages'
/// and helpers' inputs it does not write, or, standing for no stage, its other arguments.
fn merge_fields(
    covered: &[Slot],
    helpers: &[Slot],
    alone: bool,
    argf: &[Field],
    writes: &mut Vec<Field>,
) -> Vec<Field> {
    for (_, s) in covered {
        for &f in s.writes() {
            if !writes.contains(&f) {
                writes.push(f);
            }
        }
    }
    let mut reads: Vec<Field> = Vec::new();
    for (_, s) in covered.iter().chain(helpers) {
        for &f in s.reads() {
            if !reads.contains(&f) && !writes.contains(&f) {
                reads.push(f);
            }
        }
    }
    if alone {
        reads = argf.iter().copied().filter(|f| !writes.contains(f)).collect();
    }
    reads
}

/// The places in the step of the covered stages.
fn places(entries: &[Entry], covered: &[Slot]) -> Vec<usize> {
    covered
        .iter()
        .filter_map(|(_, s)| {
            entries
                .iter()
                .position(|e| e.phase != Phase::Init && e.stage.module() == s.module() && e.stage.name() == s.name())
        })
        .collect()
}

/// Removes the stages at `pos` from the step; the index the routine's stage goes to.
fn remove_covered(entries: &mut Vec<Entry>, pos: &[usize], maker: Option<usize>) -> Option<usize> {
    // the stages it stands for leave the step (from the last, so the others keep their
    // indices); it goes where the first of them was, or just after the maker (its index
    // less the removed stages before it)
    let mut gone = pos.to_vec();
    gone.sort_unstable();
    for &k in gone.iter().rev() {
        entries.remove(k);
    }
    match maker {
        Some(m) => Some(m + 1 - gone.iter().filter(|&&k| k < m).count()),
        None => gone.first().copied(),
    }
}

/// The outputs that the stages of `chain` write for the real particles only.
fn real_rows_of(writes: &[Field], chain: &[Box<dyn Stage>]) -> Vec<Field> {
    // the outputs its twins write for the real particles only (the last twin to write
    // each field says)
    writes
        .iter()
        .copied()
        .filter(|f| chain.iter().rev().find(|s| s.writes().contains(f)).is_some_and(|s| s.real_rows().contains(f)))
        .collect()
}
