//! The dual run (docs/design.md, the dual run): at every step every stage runs both implementations on
//! identical inputs; every field the stage declares as written is compared; the run continues
//! with the Fortran result so differences never compound.
//!
//! Tolerance tiers (each stage declares its own, [`crate::modules::Stage::tolerance`]; also in
//! docs/howto/add-module.md):
//! - 0 ULP: the Rust twin performs the same IEEE operations (+ − × ÷ √) in the same order,
//!   including neighbour sums (gather in ascending pair order = the Fortran scatter order);
//! - also 0 ULP where a transcendental from the C library is involved (`exp` in JWL, `pow` for h
//!   in 3D): the Rust twin and gfortran call the same libm function, so the bits agree. A build
//!   that took them from elsewhere (another libm, a vectorised variant) could differ by an ULP or
//!   two; the dual run would then report it, and the tier would be raised to the measured
//!   difference, not before.
//!
//! No stage needs a relative tolerance: no summation order differs.

pub use crate::modules::ulp::ulp_diff;
use crate::modules::{Backend, Counterpart, Stage};
use crate::state::{Array, Clock, Field, Particles, Per, Snap, Work};
use serde::Serialize;
use std::collections::BTreeMap;

/// Said by a legacy routine's tolerance when the routine's acceleration includes gravity
/// (`includes_gravity`) and its Rust twin's does not: their `acc` rows differ by the gravity.
pub const GRAVITY_NOTE: &str =
    "its acc includes gravity (includes_gravity), its Rust twin's does not: acc differs by the gravity";

/// The larger of `m` and `v`, NaN when either is: a NaN on either side of a comparison (a twin
/// that broke) stays visible in the row's largest difference, where `f64::max` would drop it.
pub(crate) fn sticky_max(m: f64, v: f64) -> f64 {
    if m.is_nan() || v.is_nan() { f64::NAN } else { m.max(v) }
}

/// A ULP distance as the table prints it: "NaN" where a side was NaN, and in powers of ten above
/// 10^6 (a distance across zero or between far values: its digits say nothing more).
pub(crate) fn ulp_text(u: u64) -> String {
    match u {
        u64::MAX => "NaN".into(),
        u if u >= 1_000_000 => format!("{:.0e}", u as f64),
        u => u.to_string(),
    }
}

/// The first value out of tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct Divergence {
    pub step: u64,
    pub index: usize,
    /// "particle 17", "mirror 3", "pair 120 (4, 9)" or "length".
    pub at: String,
    pub fortran: f64,
    pub rust: f64,
}

/// Statistics of one (stage, field).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Stat {
    /// The module of the stage.
    pub module: String,
    /// The stage (`module.routine`).
    pub stage: String,
    pub field: String,
    pub tolerance_ulp: u64,
    /// Why the tolerance is what it is.
    pub tolerance_why: String,
    pub compared: u64,
    pub max_abs: f64,
    pub max_rel: f64,
    pub max_ulp: u64,
    pub out_of_tolerance: u64,
    pub first_divergence: Option<Divergence>,
    /// First difference of any size (even within tolerance).
    pub first_difference: Option<Divergence>,
    /// Where the difference in ULP is largest among the compared values (the first such value
    /// over the steps): a defect whose values already differed in the last bits shows here, not
    /// at the first divergence.
    pub largest_difference: Option<Divergence>,
    /// What the Rust side was compared with when it is not blastsph's Fortran twin: "legacy"
    /// (the user's routine, `dual --legacy`) or "none" (a compat variant, not compared).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counterpart: Option<String>,
    /// Pair lists compared as sets (see `crate::pairs`); absent when both sides
    /// returned the same list in the same order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pair_order: Option<crate::pairs::OrderStat>,
    /// The stage ran one implementation only (`tolerance_why` says why): nothing compared.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub not_compared: bool,
}

#[derive(Debug, Clone, Default)]
pub struct Comparator {
    pub stats: BTreeMap<(String, Field), Stat>,
    pub dim: usize,
    pub steps: u64,
    /// Host mode: the particles the routine was given (its `ntotal`), where its pairs reach
    /// particles past them. Their rows are its inputs: only the given particles' are compared.
    pub given: Option<usize>,
}

impl Comparator {
    pub fn new(dim: usize) -> Comparator {
        Comparator { dim, ..Default::default() }
    }

    /// Runs `stage` with both implementations on the same state: Rust first, its outputs kept
    /// aside, the outputs put back as they were, then Fortran; compares every output and leaves
    /// the Fortran result in the state.
    pub fn run(&mut self, stage: &dyn Stage, p: &mut Particles, w: &mut Work, k: &Clock, step: u64) {
        match stage.counterpart() {
            Counterpart::None(why) => {
                // a compat variant: no Fortran twin in blastsph's core to compare with
                stage.run(Backend::Rust, p, w, k);
                let why = format!("compat ({why}): no Fortran twin in blastsph's core; compare with --legacy");
                return self.not_compared(step, stage, &why, "none");
            }
            Counterpart::LegacyAlone(why) => {
                stage.run(Backend::Fortran, p, w, k);
                for iw in stage.take_input_writes() {
                    self.input_written(step, stage, &iw, p);
                }
                return self.not_compared(step, stage, why, "legacy");
            }
            Counterpart::Fortran | Counterpart::Legacy => {}
        }
        let outs = stage.writes();
        let before: Vec<Snap> = outs.iter().map(|f| f.snap(p, w)).collect();
        stage.run(Backend::Rust, p, w, k);
        let rust: Vec<Snap> = outs.iter().map(|f| f.snap(p, w)).collect();
        for (f, s) in outs.iter().zip(before) {
            f.restore(p, w, s);
        }
        stage.run(Backend::Fortran, p, w, k);
        self.compare(step, stage, &rust, p, w);
        for iw in stage.take_input_writes() {
            self.input_written(step, stage, &iw, p);
        }
    }

    /// A legacy routine changed an input of its stage (an argument the stage only reads, which
    /// the Rust twins leave alone): a row of its own, every changed value out of tolerance, the
    /// value before the call standing as the Rust side's.
    fn input_written(&mut self, step: u64, stage: &dyn Stage, iw: &crate::modules::InputWrite, p: &Particles) {
        let key = (format!("{} (inputs)", stage.name()), iw.field);
        let fate = if iw.kept { "the state keeps the change" } else { "the change is dropped" };
        let st = self.stats.entry(key).or_insert_with(|| Stat {
            module: stage.module_of(iw.field).name().into(),
            stage: stage.name().into(),
            field: format!("{} (input `{}` changed)", iw.field.name(), iw.arg),
            tolerance_ulp: 0,
            tolerance_why: format!(
                "the routine changed an argument its stage only reads; blastsph's twins leave it as it was ({fate})"
            ),
            counterpart: Some("legacy".into()),
            ..Default::default()
        });
        st.compared += iw.checked;
        st.out_of_tolerance += iw.count;
        st.max_abs = sticky_max(st.max_abs, iw.max_abs);
        st.max_rel = sticky_max(st.max_rel, iw.max_rel);
        st.max_ulp = st.max_ulp.max(iw.max_ulp);
        let k = iw.index / iw.width.max(1);
        let at = if iw.per_particle { who(k, p) } else { format!("pair {k}") };
        let at = if iw.width > 1 {
            format!("{at}, {} component", ["x", "y", "z"][(iw.index % iw.width).min(2)])
        } else {
            at
        };
        let d = Divergence { step, index: iw.index, at, fortran: iw.after, rust: iw.before };
        if st.first_difference.is_none() {
            st.first_difference = Some(d.clone());
        }
        if st.first_divergence.is_none() {
            st.first_divergence = Some(d);
        }
    }

    /// The rows of a stage that runs without a counterpart: compared 0 times, saying why.
    fn not_compared(&mut self, step: u64, stage: &dyn Stage, why: &str, counterpart: &str) {
        self.steps = self.steps.max(step + 1);
        let fields: Vec<Field> = if stage.writes().is_empty() { vec![Field::X] } else { stage.writes().to_vec() };
        for f in fields {
            self.stats.entry((stage.name().to_string(), f)).or_insert_with(|| Stat {
                module: stage.module().name().into(),
                stage: stage.name().into(),
                field: if stage.writes().is_empty() { "-".into() } else { f.name() },
                tolerance_why: why.to_string(),
                counterpart: Some(counterpart.into()),
                not_compared: true,
                ..Default::default()
            });
        }
    }

    /// Stages that ran without being compared (compat variants, legacy routines with no twin),
    /// each once.
    pub(crate) fn uncompared(&self) -> Vec<String> {
        let mut v: Vec<String> = self.stats.values().filter(|s| s.not_compared).map(|s| s.stage.clone()).collect();
        v.dedup();
        v
    }

    fn locate(&self, f: Field, l: usize, p: &Particles, w: &Work) -> String {
        let (per, width) = f.layout(self.dim);
        // the component of a vector or tensor value (x, y, z where there are dim of them)
        // (a stress, strain or stress rate: xx, yy, zz, xy, xz, yz, the vocabulary's sxx…; a
        // rotation rate: xy, xz, yz, its rxy…)
        let comp = |c: usize| -> String {
            if width <= 1 {
                String::new()
            } else if f == Field::Rot {
                format!(", {} component", ["xy", "xz", "yz"][c.min(2)])
            } else if width == crate::modules::param::NSTR {
                format!(", {} component", ["xx", "yy", "zz", "xy", "xz", "yz"][c.min(5)])
            } else if width == self.dim {
                format!(", {} component", ["x", "y", "z"][c.min(2)])
            } else {
                format!(", component {c}")
            }
        };
        match per {
            Per::Term => {
                let nt = p.ntotal.max(1);
                let term = l / (width * nt);
                let r = l % (width * nt);
                format!("term {term}, {}{}", who(r / width, p), comp(r % width))
            }
            Per::One => "the step".into(),
            Per::Pair => {
                let k = l / width;
                let (i, j) = (w.pairs.i.get(k).copied().unwrap_or(-1), w.pairs.j.get(k).copied().unwrap_or(-1));
                format!("pair {k} ({i}, {j}){}", comp(l % width))
            }
            Per::Particle => format!("{}{}", who(l / width, p), comp(l % width)),
        }
    }

    /// Compares the Fortran result (now in p, w) with the Rust copies of the stage's outputs.
    fn compare(&mut self, step: u64, stage: &dyn Stage, rust: &[Snap], p: &Particles, w: &Work) {
        let tol = stage.tolerance();
        self.steps = self.steps.max(step + 1);
        let legacy = stage.counterpart() == Counterpart::Legacy;
        // pair lists in another order (or with other pairs): compared as sets
        let aligned = crate::pairs::align(stage.writes(), rust, p, w, self.dim);
        let rust: &[Snap] = aligned.as_ref().map_or(rust, |a| &a.snaps);
        for (&f, r) in stage.writes().iter().zip(rust) {
            let key = (stage.name().to_string(), f);
            let mut st = self.stats.remove(&key).unwrap_or_else(|| Stat {
                module: stage.module_of(f).name().into(),
                stage: stage.name().into(),
                field: f.name(),
                tolerance_ulp: tol.ulp,
                tolerance_why: tol.why.into(),
                counterpart: legacy.then(|| "legacy".to_string()),
                ..Default::default()
            });
            if let Some(a) = &aligned
                && f == Field::PairI
            {
                let o = st.pair_order.get_or_insert_with(Default::default);
                o.add(&a.stat);
                st.out_of_tolerance += a.stat.only_rust;
                if a.stat.only_rust > 0 && st.first_divergence.is_none() {
                    st.first_divergence = Some(Divergence {
                        step,
                        index: 0,
                        at: format!("{} pairs only in the Rust list", a.stat.only_rust),
                        fortran: f64::NAN,
                        rust: a.stat.only_rust as f64,
                    });
                }
            }
            let pairs: Vec<(f64, f64)> = match (f.of(p, w), r) {
                (Array::F(a), Snap::F(b)) => {
                    if a.len() != b.len() {
                        note_len(&mut st, step, a.len(), b.len());
                    }
                    a.iter().zip(b.iter()).map(|(x, y)| (*x, *y)).collect()
                }
                (Array::I(a), Snap::I(b)) => {
                    if a.len() != b.len() {
                        note_len(&mut st, step, a.len(), b.len());
                    }
                    a.iter().zip(b.iter()).map(|(x, y)| (*x as f64, *y as f64)).collect()
                }
                _ => Vec::new(),
            };
            // an output the twin writes for the real particles only: the mirrors' rows are a later
            // stage's (a legacy routine may fill them too)
            let rows = if stage.real_rows().contains(&f) && p.ntotal > 0 && pairs.len().is_multiple_of(p.ntotal) {
                pairs.len() / p.ntotal * p.nreal
            } else {
                pairs.len()
            };
            let (per, width) = f.layout(self.dim);
            let (width, nt, given) = (width.max(1), p.ntotal.max(1), self.given.unwrap_or(usize::MAX));
            let keep = |l: usize| match per {
                Per::Particle => l / width < given,
                Per::Term => l % (width * nt) / width < given,
                Per::Pair | Per::One => true,
            };
            st.compared += (0..rows).filter(|&l| keep(l)).count() as u64;
            for (l, (a, b)) in pairs.into_iter().take(rows).enumerate().filter(|(l, _)| keep(*l)) {
                if a.to_bits() == b.to_bits() || (a == b) {
                    continue;
                }
                let u = ulp_diff(a, b);
                let abs = (a - b).abs();
                let rel = abs / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
                st.max_abs = sticky_max(st.max_abs, abs);
                st.max_rel = sticky_max(st.max_rel, rel);
                // against the largest value's own difference (a legacy routine's writes to its
                // inputs raise max_ulp through their own path, without a value here)
                if st.largest_difference.as_ref().is_none_or(|l| u > ulp_diff(l.fortran, l.rust)) {
                    st.largest_difference =
                        Some(Divergence { step, index: l, at: self.locate(f, l, p, w), fortran: a, rust: b });
                }
                st.max_ulp = st.max_ulp.max(u);
                if st.first_difference.is_none() {
                    st.first_difference =
                        Some(Divergence { step, index: l, at: self.locate(f, l, p, w), fortran: a, rust: b });
                }
                if u > tol.ulp {
                    st.out_of_tolerance += 1;
                    if st.first_divergence.is_none() {
                        st.first_divergence =
                            Some(Divergence { step, index: l, at: self.locate(f, l, p, w), fortran: a, rust: b });
                    }
                }
            }
            self.stats.insert(key, st);
        }
    }

    pub fn ok(&self) -> bool {
        self.stats.values().all(|s| s.out_of_tolerance == 0)
    }

    pub fn rows(&self) -> Vec<Stat> {
        self.stats.values().cloned().collect()
    }

    /// The printed table. A row out of tolerance for a known reason (its tolerance's
    /// [`GRAVITY_NOTE`]) says the reason after its first divergence.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:<24} {:<7} {:>10} {:>10} {:>10} {:>6} {:>4} {:>6}  first divergence\n",
            "stage", "field", "compared", "max abs", "max rel", "maxULP", "tol", "out"
        );
        for st in self.stats.values() {
            let other = st.counterpart.as_deref().unwrap_or("fortran");
            // a pair list's entries are particle numbers (−1: no pair there), not reals
            let pair = st.field.starts_with("pair_");
            let num = |v: f64| {
                if !pair {
                    format!("{v:e}")
                } else if v < 0.0 {
                    "no pair".to_string()
                } else {
                    format!("particle {}", v as i64)
                }
            };
            let mut fd = match &st.first_divergence {
                // pairs missing from the other list: a count, said in `at`
                Some(d) if pair && d.fortran.is_nan() => format!("step {}, {}", d.step, d.at),
                Some(d) => format!("step {}, {}: {other} {}, rust {}", d.step, d.at, num(d.fortran), num(d.rust)),
                None if st.not_compared && other == "none" => "compat: no Fortran twin, compare with --legacy".into(),
                None if st.not_compared => "no Rust twin here: not compared".into(),
                None => "-".into(),
            };
            // where the difference is largest, when that is elsewhere than the first divergence
            if let (Some(d), Some(l)) = (&st.first_divergence, &st.largest_difference)
                && !pair
                && (d.step, d.index) != (l.step, l.index)
            {
                let u = ulp_text(ulp_diff(l.fortran, l.rust));
                fd += &format!(
                    "; largest ({u} ULP) step {}, {}: {other} {}, rust {}",
                    l.step,
                    l.at,
                    num(l.fortran),
                    num(l.rust)
                );
            }
            if st.out_of_tolerance > 0
                && let Some(k) = st.tolerance_why.find(GRAVITY_NOTE)
            {
                fd += &format!("; {}", &st.tolerance_why[k..]);
            }
            if let Some(o) = &st.pair_order {
                fd += &format!("  [pairs as sets: {}]", o.text(other));
            }
            s += &format!(
                "{:<24} {:<7} {:>10} {:>10.3e} {:>10.3e} {:>6} {:>4} {:>6}  {}\n",
                st.stage,
                st.field,
                st.compared,
                st.max_abs,
                st.max_rel,
                ulp_text(st.max_ulp),
                st.tolerance_ulp,
                st.out_of_tolerance,
                fd
            );
        }
        s
    }
}

fn who(k: usize, p: &Particles) -> String {
    if k < p.nreal {
        format!("particle {}", p.id.get(k).copied().unwrap_or(k as i64))
    } else {
        format!("mirror {}", k - p.nreal)
    }
}

fn note_len(st: &mut Stat, step: u64, a: usize, b: usize) {
    st.out_of_tolerance += 1;
    if st.first_divergence.is_none() {
        st.first_divergence =
            Some(Divergence { step, index: 0, at: "length".into(), fortran: a as f64, rust: b as f64 });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_first_divergence_names_the_component_of_a_vector() {
        let cmp = Comparator::new(2);
        let p = Particles { dim: 2, nreal: 3, ntotal: 4, id: vec![0, 1, 2], ..Default::default() };
        let w = Work::default();
        assert_eq!(cmp.locate(Field::V, 3, &p, &w), "particle 1, y component");
        assert_eq!(cmp.locate(Field::V, 6, &p, &w), "mirror 0, x component");
        assert_eq!(cmp.locate(Field::Rho, 2, &p, &w), "particle 2");
        assert_eq!(cmp.locate(Field::Tau, 6 + 3, &p, &w), "particle 1, xy component");
        assert_eq!(cmp.locate(Field::Rot, 3 + 2, &p, &w), "particle 1, yz component");
    }

    /// A stage that writes p with `fill` (given the backend), its real rows only when `.0`.
    struct PStage(bool, fn(Backend, &mut Particles));
    impl Stage for PStage {
        fn module(&self) -> crate::modules::Module {
            crate::modules::Module::Eos
        }
        fn name(&self) -> &'static str {
            "eos.eval"
        }
        fn reads(&self) -> &[Field] {
            &[]
        }
        fn writes(&self) -> &[Field] {
            &[Field::P]
        }
        fn real_rows(&self) -> &[Field] {
            if self.0 { &[Field::P] } else { &[] }
        }
        fn run(&self, b: Backend, p: &mut Particles, _w: &mut Work, _k: &Clock) {
            (self.1)(b, p)
        }
    }

    /// p for the real particles with either backend, and for the mirrors too with the
    /// "Fortran" one (as a legacy EOS over all `ntotal` particles does).
    fn eos_all_rows(b: Backend, p: &mut Particles) {
        let n = if b == Backend::Fortran { p.ntotal } else { p.nreal };
        for (i, v) in p.p[..n].iter_mut().enumerate() {
            *v = 10.0 + i as f64;
        }
    }

    #[test]
    fn the_mirrors_rows_of_a_real_only_output_are_not_compared() {
        let k = Clock { t: 0.0, dt: 0.0, dt_prev: 0.0, first: true };
        for real_only in [true, false] {
            let mut cmp = Comparator::new(1);
            let mut p =
                Particles { dim: 1, nreal: 3, ntotal: 5, id: vec![0, 1, 2], p: vec![0.0; 5], ..Default::default() };
            let mut w = Work::default();
            cmp.run(&PStage(real_only, eos_all_rows), &mut p, &mut w, &k, 0);
            let st = &cmp.rows()[0];
            if real_only {
                assert_eq!((st.compared, st.out_of_tolerance), (3, 0), "{st:?}");
                assert!(cmp.ok());
            } else {
                assert_eq!((st.compared, st.out_of_tolerance), (5, 2), "{st:?}");
                assert_eq!(st.first_divergence.as_ref().unwrap().at, "mirror 0");
            }
        }
    }

    /// p whose "Fortran" value differs from the Rust one by 1 ULP at particle 0 and by much
    /// more at particle 2.
    fn skewed(b: Backend, p: &mut Particles) {
        p.p[..3].copy_from_slice(&[1.0, 2.0, 3.0]);
        if b == Backend::Fortran {
            p.p[0] = f64::from_bits(1.0f64.to_bits() + 1);
            p.p[2] = 3.5;
        }
    }

    #[test]
    fn the_largest_difference_is_located_beside_the_first() {
        let k = Clock { t: 0.0, dt: 0.0, dt_prev: 0.0, first: true };
        let mut cmp = Comparator::new(1);
        let mut p = Particles { dim: 1, nreal: 3, ntotal: 3, id: vec![0, 1, 2], p: vec![0.0; 3], ..Default::default() };
        let mut w = Work::default();
        cmp.run(&PStage(false, skewed), &mut p, &mut w, &k, 0);
        let st = &cmp.rows()[0];
        assert_eq!(st.first_divergence.as_ref().unwrap().at, "particle 0", "{st:?}");
        let l = st.largest_difference.as_ref().unwrap();
        assert_eq!((l.at.as_str(), l.fortran, l.rust), ("particle 2", 3.5, 3.0), "{st:?}");
        let t = cmp.table();
        assert!(t.contains("; largest (") && t.contains("step 0, particle 2: fortran 3.5e0, rust 3e0"), "{t}");
    }

    #[test]
    fn a_nan_difference_stays_in_the_rows_largest_difference() {
        assert_eq!(sticky_max(0.0, 2.0), 2.0);
        assert!(sticky_max(0.0, f64::NAN).is_nan());
        assert!(sticky_max(f64::NAN, 2.0).is_nan());
        assert_eq!(ulp_diff(1.0, f64::NAN), u64::MAX);
        assert_eq!(
            (ulp_text(u64::MAX), ulp_text(4116290059416633344), ulp_text(999_999)),
            ("NaN".into(), "4e18".into(), "999999".into())
        );
    }
}
