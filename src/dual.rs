//! The dual run (DESIGN.md "Dual run"): at every step every module call runs both implementations
//! on identical inputs; every output field is compared; the run continues with the Fortran result
//! so differences never compound.
//!
//! Tolerance tiers (also in docs/migration.md):
//! - 0 ULP: the Rust twin performs the same IEEE operations (+ − × ÷ √) in the same order,
//!   including neighbour sums (gather in ascending pair order = the Fortran scatter order);
//! - also 0 ULP where a transcendental from the C library is involved (`exp` in JWL, `pow` for h
//!   in 3D): the Rust twin and gfortran call the same libm function, so the bits agree. A build
//!   that took them from elsewhere (another libm, a vectorised variant) could differ by an ULP or
//!   two; the dual run would then report it, and the tier would be raised to the measured
//!   difference, not before.
//!
//! No module needs a relative tolerance: no summation order differs.

use crate::legacy::NSTR;
use crate::modules::Module;
use crate::state::{Particles, Work};
use serde::Serialize;
use std::collections::BTreeMap;

/// A named output array of a module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub enum Field {
    X,
    V,
    Rho,
    P,
    C,
    E,
    H,
    Mass,
    Mat,
    Tau,
    Burn,
    Tlight,
    PairI,
    PairJ,
    W,
    Dwdx,
    W0,
    Drho,
    Acc,
    Dde,
    Dv,
    De,
    Eps,
    Rot,
    Dtau,
    Av,
    Dhdt,
    RhoMin,
    EMin,
    VMin,
    TauMin,
    Gsrc,
    Gseg,
    DtCfl,
}

impl Field {
    pub fn name(self) -> String {
        format!("{self:?}").to_lowercase()
    }
    /// Values per particle (or per pair) and whether the field is indexed by pair.
    fn stride(self, dim: usize) -> (usize, bool) {
        match self {
            Field::X | Field::V | Field::Dv | Field::Av | Field::VMin | Field::Acc => (dim, false),
            Field::Tau | Field::Eps | Field::Dtau | Field::TauMin => (NSTR, false),
            Field::Rot => (3, false),
            Field::Dwdx => (dim, true),
            Field::W | Field::PairI | Field::PairJ => (1, true),
            Field::Gseg => (2, false),
            _ => (1, false),
        }
    }
}

/// A copy of one field.
#[derive(Debug, Clone)]
pub enum Snap {
    F(Vec<f64>),
    I(Vec<i32>),
}

fn fvec<'a>(p: &'a Particles, w: &'a Work, f: Field) -> Option<&'a Vec<f64>> {
    Some(match f {
        Field::X => &p.x,
        Field::V => &p.v,
        Field::Rho => &p.rho,
        Field::P => &p.p,
        Field::C => &p.c,
        Field::E => &p.e,
        Field::H => &p.h,
        Field::Mass => &p.mass,
        Field::Tau => &p.tau,
        Field::Burn => &p.burn,
        Field::Tlight => &p.tlight,
        Field::W => &w.w,
        Field::Dwdx => &w.dwdx,
        Field::W0 => &w.w0,
        Field::Drho => &w.drho,
        Field::Acc => &w.acc,
        Field::Dde => &w.dde,
        Field::Dv => &w.dv,
        Field::De => &w.de,
        Field::Eps => &w.eps,
        Field::Rot => &w.rot,
        Field::Dtau => &w.dtau,
        Field::Av => &w.av,
        Field::Dhdt => &w.dhdt,
        Field::RhoMin => &w.rho_min,
        Field::EMin => &w.e_min,
        Field::VMin => &w.v_min,
        Field::TauMin => &w.tau_min,
        Field::DtCfl => &w.dt_cfl,
        Field::Mat | Field::PairI | Field::PairJ | Field::Gsrc | Field::Gseg => return None,
    })
}

fn fvec_mut<'a>(p: &'a mut Particles, w: &'a mut Work, f: Field) -> Option<&'a mut Vec<f64>> {
    Some(match f {
        Field::X => &mut p.x,
        Field::V => &mut p.v,
        Field::Rho => &mut p.rho,
        Field::P => &mut p.p,
        Field::C => &mut p.c,
        Field::E => &mut p.e,
        Field::H => &mut p.h,
        Field::Mass => &mut p.mass,
        Field::Tau => &mut p.tau,
        Field::Burn => &mut p.burn,
        Field::Tlight => &mut p.tlight,
        Field::W => &mut w.w,
        Field::Dwdx => &mut w.dwdx,
        Field::W0 => &mut w.w0,
        Field::Drho => &mut w.drho,
        Field::Acc => &mut w.acc,
        Field::Dde => &mut w.dde,
        Field::Dv => &mut w.dv,
        Field::De => &mut w.de,
        Field::Eps => &mut w.eps,
        Field::Rot => &mut w.rot,
        Field::Dtau => &mut w.dtau,
        Field::Av => &mut w.av,
        Field::Dhdt => &mut w.dhdt,
        Field::RhoMin => &mut w.rho_min,
        Field::EMin => &mut w.e_min,
        Field::VMin => &mut w.v_min,
        Field::TauMin => &mut w.tau_min,
        Field::DtCfl => &mut w.dt_cfl,
        Field::Mat | Field::PairI | Field::PairJ | Field::Gsrc | Field::Gseg => return None,
    })
}

fn ivec<'a>(p: &'a Particles, w: &'a Work, f: Field) -> &'a Vec<i32> {
    match f {
        Field::Mat => &p.mat,
        Field::PairI => &w.pairs.i,
        Field::PairJ => &w.pairs.j,
        Field::Gsrc => &w.gsrc,
        _ => &w.gseg,
    }
}

fn ivec_mut<'a>(p: &'a mut Particles, w: &'a mut Work, f: Field) -> &'a mut Vec<i32> {
    match f {
        Field::Mat => &mut p.mat,
        Field::PairI => &mut w.pairs.i,
        Field::PairJ => &mut w.pairs.j,
        Field::Gsrc => &mut w.gsrc,
        _ => &mut w.gseg,
    }
}

pub fn snapshot(p: &Particles, w: &Work, outs: &[Field]) -> Vec<Snap> {
    outs.iter()
        .map(|&f| match fvec(p, w, f) {
            Some(v) => Snap::F(v.clone()),
            None => Snap::I(ivec(p, w, f).clone()),
        })
        .collect()
}

pub fn restore(p: &mut Particles, w: &mut Work, outs: &[Field], snaps: Vec<Snap>) {
    for (&f, s) in outs.iter().zip(snaps) {
        match s {
            Snap::F(v) => {
                if let Some(t) = fvec_mut(p, w, f) {
                    *t = v;
                }
            }
            Snap::I(v) => *ivec_mut(p, w, f) = v,
        }
    }
}

/// Distance in units in the last place between two doubles (0 for +0 and −0).
pub fn ulp_diff(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    if a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    let key = |x: f64| -> i64 {
        let bits = x.to_bits() as i64;
        if bits < 0 { i64::MIN.wrapping_sub(bits) } else { bits }
    };
    (key(a) as i128 - key(b) as i128).unsigned_abs().min(u64::MAX as u128) as u64
}

/// The tolerance of a module (in ULP) and why, for a case of dimension `dim` that does or does
/// not use a JWL material.
pub fn tolerance(m: Module, dim: usize, jwl: bool) -> (u64, &'static str) {
    match m {
        Module::Eos if jwl => (0, "JWL calls exp: both sides take it from the same C library"),
        Module::Smoothing if dim == 3 => {
            (0, "h from density in 3D calls pow: both sides take it from the same C library")
        }
        _ => (0, "same IEEE operations in the same order"),
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

/// Statistics of one (module, field).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Stat {
    pub module: String,
    pub field: String,
    pub tolerance_ulp: u64,
    pub compared: u64,
    pub max_abs: f64,
    pub max_rel: f64,
    pub max_ulp: u64,
    pub out_of_tolerance: u64,
    pub first_divergence: Option<Divergence>,
    /// First difference of any size (even within tolerance).
    pub first_difference: Option<Divergence>,
}

#[derive(Debug, Clone, Default)]
pub struct Comparator {
    pub stats: BTreeMap<(Module, Field), Stat>,
    pub dim: usize,
    /// Whether the case uses a JWL material (sets the EOS tier).
    pub jwl: bool,
    pub steps: u64,
}

impl Comparator {
    pub fn new(dim: usize, jwl: bool) -> Comparator {
        Comparator { dim, jwl, ..Default::default() }
    }

    fn locate(&self, f: Field, l: usize, p: &Particles, w: &Work) -> String {
        let (stride, pair) = f.stride(self.dim);
        match f {
            Field::Acc | Field::Dde => {
                let nt = p.ntotal.max(1);
                let per = if f == Field::Acc { self.dim * nt } else { nt };
                let term = l / per;
                let within = l % per;
                let s = if f == Field::Acc { self.dim } else { 1 };
                return format!("term {term}, {}", who(within / s, p));
            }
            Field::DtCfl => return "the step".into(),
            _ => {}
        }
        let k = l / stride;
        if pair {
            let (i, j) = (w.pairs.i.get(k).copied().unwrap_or(-1), w.pairs.j.get(k).copied().unwrap_or(-1));
            format!("pair {k} ({i}, {j})")
        } else {
            who(k, p)
        }
    }

    /// Compares the Fortran result (now in p, w) with the Rust snapshot.
    pub fn compare(&mut self, step: u64, m: Module, outs: &[Field], rust: &[Snap], p: &Particles, w: &Work) {
        let (tol, _) = tolerance(m, self.dim, self.jwl);
        self.steps = self.steps.max(step + 1);
        for (&f, r) in outs.iter().zip(rust) {
            let mut st = self.stats.remove(&(m, f)).unwrap_or_else(|| Stat {
                module: m.name().into(),
                field: f.name(),
                tolerance_ulp: tol,
                ..Default::default()
            });
            let pairs: Vec<(f64, f64)> = match (fvec(p, w, f), r) {
                (Some(a), Snap::F(b)) => {
                    if a.len() != b.len() {
                        note_len(&mut st, step, a.len(), b.len());
                    }
                    a.iter().zip(b.iter()).map(|(x, y)| (*x, *y)).collect()
                }
                (None, Snap::I(b)) => {
                    let a = ivec(p, w, f);
                    if a.len() != b.len() {
                        note_len(&mut st, step, a.len(), b.len());
                    }
                    a.iter().zip(b.iter()).map(|(x, y)| (*x as f64, *y as f64)).collect()
                }
                _ => Vec::new(),
            };
            st.compared += pairs.len() as u64;
            for (l, (a, b)) in pairs.into_iter().enumerate() {
                if a.to_bits() == b.to_bits() || (a == b) {
                    continue;
                }
                let u = ulp_diff(a, b);
                let abs = (a - b).abs();
                let rel = abs / a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
                st.max_abs = st.max_abs.max(abs);
                st.max_rel = st.max_rel.max(rel);
                st.max_ulp = st.max_ulp.max(u);
                if st.first_difference.is_none() {
                    st.first_difference =
                        Some(Divergence { step, index: l, at: self.locate(f, l, p, w), fortran: a, rust: b });
                }
                if u > tol {
                    st.out_of_tolerance += 1;
                    if st.first_divergence.is_none() {
                        st.first_divergence =
                            Some(Divergence { step, index: l, at: self.locate(f, l, p, w), fortran: a, rust: b });
                    }
                }
            }
            self.stats.insert((m, f), st);
        }
    }

    pub fn ok(&self) -> bool {
        self.stats.values().all(|s| s.out_of_tolerance == 0)
    }

    pub fn rows(&self) -> Vec<Stat> {
        self.stats.values().cloned().collect()
    }

    /// The printed table.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:<11} {:<7} {:>10} {:>10} {:>10} {:>6} {:>4} {:>6}  first divergence\n",
            "module", "field", "compared", "max abs", "max rel", "maxULP", "tol", "out"
        );
        for st in self.stats.values() {
            let fd = match &st.first_divergence {
                Some(d) => format!("step {}, {}: fortran {:e}, rust {:e}", d.step, d.at, d.fortran, d.rust),
                None => "-".into(),
            };
            s += &format!(
                "{:<11} {:<7} {:>10} {:>10.3e} {:>10.3e} {:>6} {:>4} {:>6}  {}\n",
                st.module,
                st.field,
                st.compared,
                st.max_abs,
                st.max_rel,
                st.max_ulp,
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
