//! The Rust twin of the strength module: m/ρ of every particle first (the value the Fortran
//! computes per pair), then each particle gathers L over its pairs in ascending pair order (the
//! Fortran's scatter order), with v_j − v_i taken in pair order; then ε̇, R and the Jaumann rate.
//! 0 ULP, independent of the thread count.

use crate::modules::grow;
use super::{Rates, Yield};
use crate::modules::nnps::PairList;
use crate::modules::param::{NPAR, NSTR, SPH_MP_ALPHA_PHI, SPH_MP_COHESION, SPH_MP_SHEAR};
use crate::modules::{by_dim, par_rows, par_rows2};

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

pub(super) fn rates(a: &mut Rates) {
    let Rates { dim, nreal, pairs: pl, dwdx, mass, rho, v, mat, mt, tau, rinv, eps, rot, dtau, dedt } = a;
    let (dim, nreal) = (*dim, *nreal);
    let nt = mass.len();
    let shear = (SPH_MP_SHEAR - 1) as usize;
    let mut buf = pl.scratch.lock();
    grow(&mut buf.part, nt);
    par_rows(&mut buf.part[..nt], 1, |a, r| r[0] = mass[a] / rho[a]);
    let vol: &[f64] = &buf.part;
    by_dim!(dim, 0, velocity_gradient(pl, dwdx, vol, v, rinv, &mut eps[..NSTR * nt], &mut rot[..3 * nt]));
    let eps: &[f64] = eps;
    let rot: &[f64] = rot;
    par_rows2(&mut dtau[..NSTR * nreal], NSTR, &mut dedt[..nreal], 1, |i, dt, de| {
        let m = mat[i] as usize;
        let g = mt.mpar[shear + NPAR * m];
        if let Ok(dt) = <&mut [f64; NSTR]>::try_from(&mut *dt) {
            *dt = [0.0; NSTR];
        }
        de[0] = 0.0;
        if g <= 0.0 {
            return;
        }
        let e = &eps[NSTR * i..NSTR * i + NSTR];
        let r = &rot[3 * i..3 * i + 3];
        let e3 = [[e[0], e[3], e[4]], [e[3], e[1], e[5]], [e[4], e[5], e[2]]];
        let r3 = [[0.0, r[0], r[1]], [-r[0], 0.0, r[2]], [-r[1], -r[2], 0.0]];
        let mut t3 = [[0.0f64; 3]; 3];
        for al in 0..3 {
            for be in 0..3 {
                t3[al][be] = tau[IV[al][be] + NSTR * i];
            }
        }
        let tr = e3[0][0] + e3[1][1] + e3[2][2];
        for al in 0..3 {
            for be in al..3 {
                let mut s = 2.0 * g * e3[al][be];
                if al == be {
                    s -= 2.0 * g * tr / 3.0;
                }
                for q in 0..3 {
                    s += t3[al][q] * r3[be][q];
                    s += r3[al][q] * t3[q][be];
                }
                dt[IV[al][be]] = s;
            }
        }
        let mut s = 0.0;
        for al in 0..3 {
            for be in 0..3 {
                s += t3[al][be] * e3[al][be];
            }
        }
        de[0] = s / rho[i];
    });
}

/// ε̇ and R of every particle from L = Σ_j (m_j/ρ_j)(v_j − v_i) ⊗ ∇_i W_ij, gathered in pair order;
/// with `rinv` (axisymmetric), ε̇_θθ = v_r/r.
fn velocity_gradient<const D: usize, const W: usize>(
    pl: &PairList,
    dwdx: &[f64],
    vol: &[f64],
    v: &[f64],
    rinv: &[f64],
    eps: &mut [f64],
    rot: &mut [f64],
) {
    par_rows2(eps, NSTR, rot, 3, |a, eps, rot| {
        let mut gl = [[0.0f64; 3]; 3];
        let va = &v[D * a..D * a + D];
        for e in pl.incident(a) {
            let (k, o) = (e.pair(), e.other());
            let f = vol[o];
            let vo = &v[D * o..D * o + D];
            let g = &dwdx[D * k..D * k + D];
            for al in 0..D {
                // v_j − v_i in pair order
                let dva = if e.is_i() { vo[al] - va[al] } else { va[al] - vo[al] };
                for be in 0..D {
                    gl[al][be] += f * dva * g[be];
                }
            }
        }
        let mut e3 = [[0.0f64; 3]; 3];
        let mut r3 = [[0.0f64; 3]; 3];
        for al in 0..D {
            for be in 0..D {
                e3[al][be] = 0.5 * (gl[al][be] + gl[be][al]);
                r3[al][be] = 0.5 * (gl[al][be] - gl[be][al]);
            }
        }
        if let Some(ri) = rinv.get(a) {
            // axisymmetric: the hoop strain rate v_r/r
            e3[2][2] = va[0] * ri;
        }
        eps.copy_from_slice(&[e3[0][0], e3[1][1], e3[2][2], e3[0][1], e3[0][2], e3[1][2]]);
        rot.copy_from_slice(&[r3[0][1], r3[0][2], r3[1][2]]);
    });
}

/// Drucker–Prager radial return of τ for the first `mat.len()` particles.
pub(super) fn yield_return(a: &mut Yield) {
    let Yield { mat, mt, p, tau } = a;
    let n = mat.len();
    let shear = (SPH_MP_SHEAR - 1) as usize;
    let aphi = (SPH_MP_ALPHA_PHI - 1) as usize;
    let coh = (SPH_MP_COHESION - 1) as usize;
    par_rows(&mut tau[..NSTR * n], NSTR, |i, t| {
        let m = mat[i] as usize;
        let par = &mt.mpar[NPAR * m..NPAR * (m + 1)];
        if par[shear] <= 0.0 {
            return;
        }
        let j2 = 0.5 * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) + t[3] * t[3] + t[4] * t[4] + t[5] * t[5];
        let y = 3.0 * par[aphi] * p[i] + par[coh];
        if y <= 0.0 {
            t.iter_mut().for_each(|x| *x = 0.0);
        } else {
            let sj = j2.sqrt();
            if sj > y {
                let f = y / sj;
                t.iter_mut().for_each(|x| *x *= f);
            }
        }
    });
}
