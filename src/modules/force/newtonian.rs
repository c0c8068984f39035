//! The Rust twin of the physical viscosity (`sph_force_newtonian`). Pass 1 forms each pair's
//! strain-rate terms with the Fortran's expressions (dv = v_j − v_i, the diagonal scaled by 2/3);
//! pass 2 gathers, per particle over its pairs in ascending pair order (the Fortran's scatter
//! order), `(m_other h)/ρ_other`, and from the sums forms the heating ((½η)/ρ) ε:ε and the
//! quotients η ε/ρ² the Fortran forms per pair (the same operations, so the same values); pass 3
//! forms each pair's force term Σ_β (q_i + q_j) ∂W/∂x_β, added by the signed gather (+ m_j f at
//! i, − m_i f at j). 0 ULP, independent of the thread count.

use super::Newtonian;
use crate::modules::nnps::PairList;
use crate::modules::param::NSTR;
use crate::modules::{by_dim, gather_signed, grow, par_rows, par_rows2};

pub(crate) const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

/// The strain-rate components a dimension has, as indices of the xx, yy, zz, xy, xz, yz order.
const fn comps(dim: usize) -> &'static [usize] {
    match dim {
        1 => &[0],
        2 => &[0, 3, 1],
        _ => &[0, 3, 4, 1, 5, 2],
    }
}

/// The strain-rate sums of the physical viscosity, shared with the book-order force of the
/// `liu-book` compat profile.
pub(crate) struct Strain<'a> {
    pub pl: &'a PairList,
    pub dwdx: &'a [f64],
    pub mass: &'a [f64],
    pub rho: &'a [f64],
    pub v: &'a [f64],
    pub eta: &'a [f64],
    /// The 2/3 of the trace term (the book's literal is single precision).
    pub c23: f64,
    /// q = η ε/ρ² (the book's `pa_sph = 2`), else η ε (`pa_sph = 1`).
    pub per_rho2: bool,
}

impl Strain<'_> {
    /// Per particle the quotients q (NSTR values, xx yy zz xy xz yz) and the heating
    /// ((½η)/ρ) ε:ε (J/kg/s); `hsb` is a scratch buffer of the pair terms.
    pub(crate) fn rates<const D: usize>(&self, hsb: &mut Vec<f64>, q: &mut [f64], tds: &mut [f64]) {
        let Strain { pl, dwdx, mass, rho, v, eta, c23, per_rho2 } = *self;
        let np = pl.len();
        let cs = comps(D);
        let (pi, pj) = (&pl.i, &pl.j);
        grow(hsb, NSTR * np);
        par_rows(&mut hsb[..NSTR * np], NSTR, |k, hs| {
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            let g = &dwdx[D * k..D * k + D];
            let mut dv = [0.0f64; 3];
            for d in 0..D {
                dv[d] = v[d + D * j] - v[d + D * i];
            }
            hs.fill(0.0);
            if D == 1 {
                hs[0] = 2.0 * dv[0] * g[0];
            } else if D == 2 {
                hs[0] = 2.0 * dv[0] * g[0] - dv[1] * g[1];
                hs[3] = dv[0] * g[1] + dv[1] * g[0];
                hs[1] = 2.0 * dv[1] * g[1] - dv[0] * g[0];
            } else {
                hs[0] = 2.0 * dv[0] * g[0] - dv[1] * g[1] - dv[2] * g[2];
                hs[3] = dv[0] * g[1] + dv[1] * g[0];
                hs[4] = dv[0] * g[2] + dv[2] * g[0];
                hs[1] = 2.0 * dv[1] * g[1] - dv[0] * g[0] - dv[2] * g[2];
                hs[5] = dv[1] * g[2] + dv[2] * g[1];
                hs[2] = 2.0 * dv[2] * g[2] - dv[0] * g[0] - dv[1] * g[1];
            }
            for h in hs.iter_mut().take(D) {
                *h *= c23;
            }
        });
        let hsb: &[f64] = hsb;
        let nt = mass.len();
        par_rows2(&mut q[..NSTR * nt], NSTR, &mut tds[..nt], 1, |ia, qa, ea| {
            let mut t = [0.0f64; NSTR];
            for r in pl.incident(ia) {
                let (k, o) = (r.pair(), r.other());
                let hs = &hsb[NSTR * k..NSTR * k + NSTR];
                for &c in cs {
                    t[c] += mass[o] * hs[c] / rho[o];
                }
            }
            let s = if D == 1 {
                t[0] * t[0]
            } else if D == 2 {
                t[0] * t[0] + 2.0 * t[3] * t[3] + t[1] * t[1]
            } else {
                t[0] * t[0] + 2.0 * t[3] * t[3] + 2.0 * t[4] * t[4] + t[1] * t[1] + 2.0 * t[5] * t[5] + t[2] * t[2]
            };
            ea[0] = 0.5 * eta[ia] / rho[ia] * s;
            let ri2 = rho[ia] * rho[ia];
            for c in 0..NSTR {
                qa[c] = if per_rho2 { eta[ia] * t[c] / ri2 } else { eta[ia] * t[c] };
            }
        });
    }
}

pub(super) fn newtonian(a: &mut Newtonian) {
    by_dim!(a.dim, 0, run(a))
}

fn run<const D: usize, const W: usize>(a: &mut Newtonian) {
    let Newtonian { pairs: pl, dwdx, mass, rho, v, eta, dvdt, dedt, .. } = a;
    let (pl, dwdx, mass, rho, v, eta) = (*pl, *dwdx, *mass, *rho, *v, *eta);
    let (np, nt) = (pl.len(), mass.len());
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    let (pi, pj) = (&pl.i, &pl.j);
    grow(&mut buf.part, NSTR * nt);
    let s = Strain { pl, dwdx, mass, rho, v, eta, c23: 2.0 / 3.0, per_rho2: true };
    s.rates::<D>(&mut buf.pair, &mut buf.part[..NSTR * nt], &mut dedt[..nt]);
    let qb: &[f64] = &buf.part;
    par_rows(&mut buf.pair[..D * np], D, |k, f| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let (qi, qj) = (&qb[NSTR * i..NSTR * i + NSTR], &qb[NSTR * j..NSTR * j + NSTR]);
        for al in 0..D {
            let mut s = 0.0;
            for be in 0..D {
                let q = IV[al][be];
                s += (qi[q] + qj[q]) * g[be];
            }
            f[al] = s;
        }
    });
    gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, &mut []);
}
