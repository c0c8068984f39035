//! What blastsph hands a legacy routine for each vocabulary name, and what it takes back: the
//! state's arrays (`Particles`, `Work`), the routine's own rate term (`dvxdt`, `dedt`: its slot of
//! the stacked terms), the book's type code `itype` from the material, and work arrays the legacy
//! code keeps from call to call (`t`, `eta`, `tdsdt`, `countiac`, ...: one array per name, shared
//! by every routine of the build, as the arrays of the book's `single_step` are).

use super::vocab::vector_component;
use crate::modules::Slots;
use crate::modules::param::NSTR;
use crate::state::{Field, Particles, Work};
use std::collections::HashMap;

/// One argument's values: reals or integers.
#[derive(Debug, Clone)]
pub enum Buf {
    R(Vec<f64>),
    I(Vec<i32>),
}

/// The blastsph field a vocabulary name is (for the plan: which stages a routine covers).
pub fn field_of(name: &str) -> Option<Field> {
    use Field::*;
    Some(match name {
        "x" => X,
        "vx" => V,
        "mass" => Mass,
        "rho" => Rho,
        "p" => P,
        "c" => C,
        "u" => E,
        "hsml" => H,
        "mat" | "itype" => Mat,
        "burn" => Burn,
        "sxx" | "syy" | "szz" | "sxy" | "sxz" | "syz" => Tau,
        "dsxx" | "dsyy" | "dszz" | "dsxy" | "dsxz" | "dsyz" => Dtau,
        "epsxx" | "epsyy" | "epszz" | "epsxy" | "epsxz" | "epsyz" => Eps,
        "rxy" | "rxz" | "ryz" => Rot,
        n if super::vocab::vector_component(n).is_some() => match super::vocab::vector_component(n)?.0 {
            "x" => X,
            "vx" => V,
            "dvxdt" => Acc,
            _ => Dwdx,
        },
        "pair_i" => PairI,
        "pair_j" => PairJ,
        "niac" => PairI,
        "w" => W,
        "dwdx" => Dwdx,
        "drhodt" => Drho,
        "dvxdt" => Acc,
        "dedt" => Dde,
        "dvx" => Dv,
        "du" => De,
        "av" => Av,
        "v_min" => VMin,
        "u_min" => EMin,
        "rho_min" => RhoMin,
        _ => return None,
    })
}

/// The component of a per-component name of the stress family (`sxx` → 0 ... `syz` → 5,
/// `rxy` → 0 ... `ryz` → 2).
fn component(name: &str) -> Option<(usize, usize)> {
    const S: [&str; 6] = ["xx", "yy", "zz", "xy", "xz", "yz"];
    const R: [&str; 3] = ["xy", "xz", "yz"];
    for pre in ["s", "ds", "eps"] {
        if let Some(k) = name.strip_prefix(pre).and_then(|c| S.iter().position(|s| *s == c)) {
            return Some((k, NSTR));
        }
    }
    name.strip_prefix('r').and_then(|c| R.iter().position(|s| *s == c)).map(|k| (k, 3))
}

/// Every name the shims take that is a work array of the legacy code, not blastsph state.
pub fn is_scratch(name: &str) -> bool {
    field_of(name).is_none()
        && !matches!(name, "itimestep" | "maxtimestep" | "ntotal" | "nvirt" | "niac" | "dt" | "time")
}

/// What a call needs besides the state.
pub struct Ctx<'a> {
    pub dim: usize,
    /// The step number (1 on the first step), the time step and the time.
    pub itimestep: i32,
    pub dt: f64,
    pub time: f64,
    /// The routine's own rate terms (`dvxdt`, `dedt`).
    pub slots: Slots,
    /// The book's type code of each material.
    pub itype: &'a [i32],
    /// Per-particle arrays are this long (ntotal, or maxn for a set-up routine).
    pub nbuf: usize,
    /// Per-pair arrays are this long (niac, or max_interaction for a search).
    pub pbuf: usize,
    /// The legacy code's work arrays, by name.
    pub scratch: &'a mut HashMap<String, Buf>,
}

fn grow(v: &mut Vec<f64>, n: usize) {
    if v.len() < n {
        v.resize(n, 0.0);
    }
}

fn padded<T: Copy + Default>(src: &[T], len: usize) -> Vec<T> {
    let mut v = vec![T::default(); len];
    let n = src.len().min(len);
    v[..n].copy_from_slice(&src[..n]);
    v
}

/// The values blastsph passes for `name` (`vec` true: `dim` values per particle or pair).
pub fn gather(name: &str, vec: bool, per_pair: bool, c: &mut Ctx, p: &Particles, w: &Work) -> Buf {
    let (dim, nt) = (c.dim, p.ntotal);
    let width = if vec { dim } else { 1 };
    let len = width * if per_pair { c.pbuf } else { c.nbuf };
    let strided = |src: &[f64], (k, stride): (usize, usize)| -> Vec<f64> {
        // (the stress rate is kept for the real particles only: the mirrors' rows read 0)
        let mut v = vec![0.0; len];
        for i in 0..nt.min(len).min(src.len() / stride) {
            v[i] = src[k + stride * i];
        }
        v
    };
    let r = |src: &[f64]| Buf::R(padded(src, len));
    match name {
        "itimestep" => Buf::I(vec![c.itimestep]),
        "maxtimestep" => Buf::I(vec![1]),
        "ntotal" => Buf::I(vec![nt as i32]),
        "nvirt" => Buf::I(vec![(nt - p.nreal) as i32]),
        "niac" => Buf::I(vec![w.pairs.len() as i32]),
        "dt" => Buf::R(vec![c.dt]),
        "time" => Buf::R(vec![c.time]),
        "x" => r(&p.x[..dim * nt]),
        "vx" => r(&p.v[..dim * nt]),
        "mass" => r(&p.mass[..nt]),
        "rho" => r(&p.rho[..nt]),
        "p" => r(&p.p[..nt]),
        "c" => r(&p.c[..nt]),
        "u" => r(&p.e[..nt]),
        "hsml" => r(&p.h[..nt]),
        "burn" => r(&p.burn),
        "itype" => Buf::I(padded(
            &(0..nt)
                .map(|i| {
                    let code = c.itype.get(p.mat[i] as usize).copied().unwrap_or(0);
                    // the book's virtual particles: ghosts and boundary particles, itype < 0
                    if i < p.nreal && p.bnd.get(i).is_none_or(|&b| b == 0) { code } else { -code }
                })
                .collect::<Vec<_>>(),
            len,
        )),
        "mat" => Buf::I(padded(&p.mat[..nt], len)),
        "pair_i" => Buf::I(padded(&w.pairs.i, len)),
        "pair_j" => Buf::I(padded(&w.pairs.j, len)),
        "w" => r(&w.w),
        "dwdx" => r(&w.dwdx),
        "drhodt" => r(&w.drho),
        "dvxdt" => r(w.acc.get(c.slots.acc_range(dim * nt)).unwrap_or(&[])),
        "dedt" => r(w.dde.get(c.slots.de_range(nt)).unwrap_or(&[])),
        "dvx" => r(&w.dv),
        "du" => r(&w.de),
        "av" => r(&w.av),
        "v_min" => r(&w.v_min),
        "u_min" => r(&w.e_min),
        "rho_min" => r(&w.rho_min),
        n if vector_component(n).is_some() => {
            // one component of a vector: every dim-th value from the component's, as many rows
            // as the vector holds (particles, or pairs for dwdx)
            let (base, k) = vector_component(n).expect("a component");
            let src: &[f64] = match base {
                "x" => &p.x[..dim * nt],
                "vx" => &p.v[..dim * nt],
                "dvxdt" => w.acc.get(c.slots.acc_range(dim * nt)).unwrap_or(&[]),
                _ => &w.dwdx,
            };
            let mut v = vec![0.0; len];
            if k < dim {
                for (r, slot) in v.iter_mut().enumerate().take(src.len() / dim) {
                    *slot = src[k + dim * r];
                }
            }
            Buf::R(v)
        }
        n if n.starts_with("ds") && component(n).is_some() => Buf::R(strided(&w.dtau, component(n).unwrap())),
        n if n.starts_with("eps") && component(n).is_some() => Buf::R(strided(&w.eps, component(n).unwrap())),
        n if n.starts_with('s') && component(n).is_some() => Buf::R(strided(&p.tau, component(n).unwrap())),
        n if n.starts_with('r') && component(n).is_some() => Buf::R(strided(&w.rot, component(n).unwrap())),
        n => {
            // a work array of the legacy code: kept from call to call, zeros at first
            let int = matches!(n, "countiac");
            let b = c.scratch.entry(n.to_string()).or_insert_with(|| if int { Buf::I(vec![]) } else { Buf::R(vec![]) });
            match b {
                Buf::R(v) => Buf::R(padded(v, len)),
                Buf::I(v) => Buf::I(padded(v, len)),
            }
        }
    }
}

/// Takes back what the routine left in `b` for `name`, into the state when `f` (the field the
/// name is) is among `writes`, and into the work arrays for a work-array name. `np` is the pair
/// count after the call.
pub fn scatter(name: &str, b: Buf, writes: &[Field], c: &mut Ctx, p: &mut Particles, w: &mut Work, np: usize) {
    let (dim, nt) = (c.dim, p.ntotal);
    if is_scratch(name) {
        c.scratch.insert(name.to_string(), b);
        return;
    }
    let Some(f) = field_of(name) else { return };
    if !writes.contains(&f) || name == "niac" {
        return;
    }
    let put = |dst: &mut Vec<f64>, v: &[f64], n: usize| {
        if dst.len() < n {
            dst.resize(n, 0.0);
        }
        dst[..n].copy_from_slice(&v[..n.min(v.len())]);
    };
    match (name, b) {
        ("pair_i", Buf::I(v)) => w.pairs.i = v[..np.min(v.len())].to_vec(),
        ("pair_j", Buf::I(v)) => w.pairs.j = v[..np.min(v.len())].to_vec(),
        ("w", Buf::R(v)) => w.w = v[..np.min(v.len())].to_vec(),
        ("dwdx", Buf::R(v)) => w.dwdx = v[..(dim * np).min(v.len())].to_vec(),
        ("dvxdt", Buf::R(v)) => {
            let r = c.slots.acc_range(dim * nt);
            w.acc[r].copy_from_slice(&v[..dim * nt]);
        }
        ("dedt", Buf::R(v)) => {
            let r = c.slots.de_range(nt);
            w.dde[r].copy_from_slice(&v[..nt]);
        }
        ("x", Buf::R(v)) => put(&mut p.x, &v, dim * nt),
        ("vx", Buf::R(v)) => put(&mut p.v, &v, dim * nt),
        ("mass", Buf::R(v)) => put(&mut p.mass, &v, nt),
        ("rho", Buf::R(v)) => put(&mut p.rho, &v, nt),
        ("p", Buf::R(v)) => put(&mut p.p, &v, nt),
        ("c", Buf::R(v)) => put(&mut p.c, &v, nt),
        ("u", Buf::R(v)) => put(&mut p.e, &v, nt),
        ("hsml", Buf::R(v)) => put(&mut p.h, &v, nt),
        ("burn", Buf::R(v)) => put(&mut p.burn, &v, nt),
        ("drhodt", Buf::R(v)) => put(&mut w.drho, &v, nt),
        ("dvx", Buf::R(v)) => put(&mut w.dv, &v, dim * p.nreal),
        ("du", Buf::R(v)) => put(&mut w.de, &v, p.nreal),
        ("av", Buf::R(v)) => put(&mut w.av, &v, dim * nt),
        ("v_min", Buf::R(v)) => put(&mut w.v_min, &v, dim * p.nreal),
        ("u_min", Buf::R(v)) => put(&mut w.e_min, &v, p.nreal),
        ("rho_min", Buf::R(v)) => put(&mut w.rho_min, &v, p.nreal),
        (n, Buf::R(v)) if vector_component(n).is_some() => {
            let (base, k) = vector_component(n).expect("a component");
            if k >= dim {
                return;
            }
            let rows = if base == "dwdx" { np } else { nt };
            let dst: &mut [f64] = match base {
                "x" => {
                    grow(&mut p.x, dim * nt);
                    &mut p.x[..dim * nt]
                }
                "vx" => {
                    grow(&mut p.v, dim * nt);
                    &mut p.v[..dim * nt]
                }
                "dvxdt" => {
                    let r = c.slots.acc_range(dim * nt);
                    &mut w.acc[r]
                }
                _ => {
                    // the pairs a search leaves: the other components follow in their own scatter
                    w.dwdx.resize(dim * np, 0.0);
                    &mut w.dwdx[..]
                }
            };
            for r in 0..rows.min(v.len()) {
                dst[k + dim * r] = v[r];
            }
        }
        (n, Buf::R(v)) => {
            if let Some((k, stride)) = component(n) {
                let dst = match f {
                    Field::Tau => &mut p.tau,
                    Field::Dtau => &mut w.dtau,
                    Field::Eps => &mut w.eps,
                    _ => &mut w.rot,
                };
                // (the stress rate is kept for the real particles only: its rows end there)
                for i in 0..nt.min(dst.len() / stride).min(v.len()) {
                    dst[k + stride * i] = v[i];
                }
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_map_to_fields_and_components() {
        assert_eq!(field_of("u"), Some(Field::E));
        assert_eq!(field_of("dvxdt"), Some(Field::Acc));
        assert_eq!(field_of("tdsdt"), None);
        assert!(is_scratch("tdsdt") && is_scratch("countiac") && !is_scratch("dt") && !is_scratch("rho"));
        assert_eq!(component("syz"), Some((5, NSTR)));
        assert_eq!(component("dsxy"), Some((3, NSTR)));
        assert_eq!(component("epsxx"), Some((0, NSTR)));
        assert_eq!(component("ryz"), Some((2, 3)));
        assert_eq!(component("rho"), None);
    }
}
