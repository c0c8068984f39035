//! The Rust twin of the internal force: the per-particle quotients of the Fortran's pair
//! expression (p_i/ρ_i², and (τ_i − p_i δ)/ρ_i² with strength; the same operations, so the same
//! values) are computed once per particle; one parallel pass over the pairs then forms each pair's
//! force term f (their sums in the Fortran's order, i and j in pair order) and energy term
//! ½ p̄ v_ij·∇W (in the plane asymmetric form v_ij·∇W alone: the gather multiplies it by the
//! receiving end's own p/ρ², the product the Fortran forms per pair) into a reused buffer; one
//! parallel pass over the particles then adds, over each
//! particle's pairs in ascending pair order (the Fortran's scatter order), ∓ m_other f and
//! m_other × the energy term, writing both outputs. Where the Fortran subtracts m f, the buffer
//! holds −f and the gather adds (x − m f and x + m (−f) are the same IEEE operation). 0 ULP,
//! independent of the thread count.
//! The interface form keeps p and τ − p δ undivided per particle and divides each pair's sum by
//! ρ_i ρ_j, as the Fortran does; its energy terms go to two columns, one per end.

use crate::modules::grow;
use super::Internal;
use crate::modules::param::NSTR;
use crate::modules::{by_dim, gather_signed, gather_signed_own, par_rows};

const IV: [[usize; 3]; 3] = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];

pub(super) fn internal(a: &mut Internal) {
    // two energy columns (one per end) in RZ; in plane geometry one: ½ p̄ v_ij·∇W, or in the
    // asymmetric form v_ij·∇W, which the gather multiplies by the receiving end's own p/ρ²
    if !a.rinv.is_empty() || a.iface { by_dim!(a.dim, 2, run(a)) } else { by_dim!(a.dim, 1, run(a)) }
}

fn run<const D: usize, const W: usize>(a: &mut Internal) {
    let Internal { pairs: pl, dwdx, mass, rho, p, v, tau, asym, iface, rinv, dvdt, dedt, .. } = a;
    let (pl, dwdx, mass, rho, p, v, tau, asym, rinv) = (*pl, *dwdx, *mass, *rho, *p, *v, *tau, *asym, *rinv);
    let iface = *iface;
    let rz = !rinv.is_empty();
    let np = pl.len();
    let nt = mass.len();
    let strength = !tau.is_empty();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    // per particle, the values the Fortran computes per pair: p/ρ², then (τ − p δ)/ρ² (D × D)
    let wp = if strength { 1 + D * D } else { 1 };
    grow(&mut buf.part, wp * nt);
    par_rows(&mut buf.part[..wp * nt], wp, |i, sg| {
        if iface {
            // the interface form: p and τ − p δ, divided per pair by ρ_i ρ_j
            sg[0] = p[i];
            if strength {
                for al in 0..D {
                    for be in 0..D {
                        let q = IV[al][be];
                        sg[1 + D * al + be] = if al == be { tau[q + NSTR * i] - p[i] } else { tau[q + NSTR * i] };
                    }
                }
            }
            return;
        }
        let ri2 = rho[i] * rho[i];
        sg[0] = p[i] / ri2;
        if strength {
            for al in 0..D {
                for be in 0..D {
                    let q = IV[al][be];
                    sg[1 + D * al + be] =
                        if al == be { (tau[q + NSTR * i] - p[i]) / ri2 } else { tau[q + NSTR * i] / ri2 };
                }
            }
        }
    });
    grow(&mut buf.pair, W * np);
    let sig: &[f64] = &buf.part;
    let (pi, pj) = (&pl.i, &pl.j);
    // pair terms: t (D values; the i end gets + m_j t, the j end − m_i t), then de
    par_rows(&mut buf.pair[..W * np], W, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let g = &dwdx[D * k..D * k + D];
        let (si, sj) = (&sig[wp * i..wp * i + wp], &sig[wp * j..wp * j + wp]);
        let rr = rho[i] * rho[j];
        let pr = if iface { (si[0] + sj[0]) / rr } else { si[0] + sj[0] };
        // each end's own p/ρ² (interface: p/(ρ_i ρ_j)) of the asymmetric energy form
        let (qi, qj) = if iface { (si[0] / rr, sj[0] / rr) } else { (si[0], sj[0]) };
        // v_ij·∇W of the plane energy terms (RZ forms its own two below)
        let mut vd = 0.0;
        if !rz {
            for d in 0..D {
                vd += (v[d + D * i] - v[d + D * j]) * g[d];
            }
        }
        if !strength {
            for d in 0..D {
                t[d] = -(pr * g[d]);
            }
        } else {
            for al in 0..D {
                let mut f = 0.0;
                for be in 0..D {
                    let s = si[1 + D * al + be] + sj[1 + D * al + be];
                    let s = if iface { s / rr } else { s };
                    f += s * g[be];
                }
                t[al] = f;
            }
        }
        if rz {
            // the axisymmetric energy terms: v_i − (r_j/r_i) v_j and (r_i/r_j) v_i − v_j
            let (sji, sij) = (rinv[i] / rinv[j], rinv[j] / rinv[i]);
            let (mut vdi, mut vdj, mut vwi, mut vwj) = (0.0, 0.0, 0.0, 0.0);
            for d in 0..D {
                vdi += (v[d + D * i] - sji * v[d + D * j]) * g[d];
                vdj += (sij * v[d + D * i] - v[d + D * j]) * g[d];
                vwi += v[d + D * i] * g[d];
                vwj += v[d + D * j] * g[d];
            }
            // the coefficients of the two ends: p_i/ρ_i², p_j/ρ_j² (asymmetric) or ½ p̄ each
            let (ci, cj) = if asym { (qi, qj) } else { (0.5 * pr, 0.5 * pr) };
            // a pair across the axis (the other end an image, 1/r* < 0): the real ring's
            // internal energy takes the work of the image's force on it, p̄ v·∇W per μ
            t[D] = if rinv[j] < 0.0 { pr * vwi } else { ci * vdi };
            t[D + 1] = if rinv[i] < 0.0 { -(pr * vwj) } else { cj * vdj };
        } else if iface {
            // the plane interface form: one energy column per end
            if asym {
                t[D] = qi * vd;
                t[D + 1] = qj * vd;
            } else {
                t[D] = 0.5 * pr * vd;
                t[D + 1] = 0.5 * pr * vd;
            }
        } else if asym {
            // the asymmetric form: each end its own p/ρ² times v_ij·∇W (the gather's factor)
            t[D] = vd;
        } else {
            t[D] = 0.5 * pr * vd;
        }
    });
    if asym && !rz && !iface {
        gather_signed_own::<D, W>(pl, &buf.pair, mass, sig, wp, dvdt, dedt);
    } else {
        gather_signed::<D, W>(pl, &buf.pair, mass, None, dvdt, dedt);
    }
}
