//! The Rust twin of the leapfrog: elementwise, same order, 0 ULP; one parallel pass over blocks of
//! particles updates every staggered variable (the CFL minimum is taken per task in index order,
//! then over the tasks in order, so it does not depend on the thread count).

use super::{Advance, Cfl, Clamp, Efloor, Leapfrog, Predict, Rates, SumRates};
use crate::modules::param::NSTR;
use crate::modules::{CHUNK, par_rows, serial};
use rayon::prelude::*;

/// One staggered variable for [`zip_vars`]: u, u_min, du, values per particle.
type Var<'a> = (&'a mut [f64], &'a mut [f64], &'a [f64], usize);

/// A block's share of one variable: u, u_min, du, values per particle.
type Part<'a> = (&'a mut [f64], &'a mut [f64], &'a [f64], usize);

/// True where row `r` of a block's boundary-particle kinds (empty: none) is a held particle.
fn held(bnd: &[i32], r: usize) -> bool {
    bnd.get(r) == Some(&2)
}

/// `f(u, umin, du, w, bnd)` over every variable, in one parallel pass over blocks of particles
/// (each block handles the block's values of every variable, in the order given; `w` values per
/// particle, `bnd` the block's boundary-particle kinds or empty).
fn zip_vars<F>(n: usize, vars: Vec<Var<'_>>, bnd: &[i32], f: F)
where
    F: Fn(&mut [f64], &mut [f64], &[f64], usize, &[i32]) + Sync + Send,
{
    // particles per block
    let rows = 4 * CHUNK;
    let nb = n.div_ceil(rows);
    let mut blocks: Vec<(Vec<Part<'_>>, &[i32])> = (0..nb)
        .map(|k| {
            let kb: &[i32] = if bnd.is_empty() { &[] } else { &bnd[k * rows..((k + 1) * rows).min(n)] };
            (Vec::with_capacity(vars.len()), kb)
        })
        .collect();
    for (u, um, du, w) in vars {
        let parts =
            u[..w * n].chunks_mut(w * rows).zip(um[..w * n].chunks_mut(w * rows)).zip(du[..w * n].chunks(w * rows));
        for (blk, ((a, b), c)) in blocks.iter_mut().zip(parts) {
            blk.0.push((a, b, c, w));
        }
    }
    let run = |(blk, kb): (Vec<Part<'_>>, &[i32])| {
        for (a, b, c, w) in blk {
            f(a, b, c, w, kb);
        }
    };
    if serial() {
        blocks.into_iter().for_each(run);
    } else {
        blocks.into_par_iter().for_each(run);
    }
}

/// The staggered variables of the leapfrog that are present: e, ρ (continuity), v, τ (strength).
fn vars<'b>(dim: usize, n: usize, cont: bool, s: &'b mut Leapfrog<'_>, r: &'b Rates<'_>) -> Vec<Var<'b>> {
    let mut out: Vec<Var<'b>> = vec![(&mut s.e[..n], &mut s.e_min[..n], &r.de[..n], 1)];
    if cont {
        out.push((&mut s.rho[..n], &mut s.rho_min[..n], &r.drho[..n], 1));
    }
    out.push((&mut s.v[..dim * n], &mut s.v_min[..dim * n], &r.dv[..dim * n], dim));
    if !s.tau.is_empty() {
        out.push((&mut s.tau[..NSTR * n], &mut s.tau_min[..NSTR * n], &r.dtau[..NSTR * n], NSTR));
    }
    out
}

/// `out(d,i) = Σ_t acc_t(d,i) + grav(d)` for i < n (no gravity for a boundary particle); `acc`
/// stacks `nterm` arrays of `lda` values.
pub(super) fn sum_rates(a: &mut SumRates) {
    let SumRates { dim, n, lda, nterm, acc, grav, out, bnd } = a;
    let (dim, n, lda, nterm) = (*dim, *n, *lda, *nterm);
    let bnd: &[i32] = bnd;
    par_rows(&mut out[..dim * n], dim, |i, o| {
            let fixed = !bnd.is_empty() && bnd[i] != 0;
            for d in 0..dim {
                let l = d + dim * i;
                let mut s = 0.0;
                if nterm > 0 {
                    s = acc[l];
                }
                for t in 1..nterm {
                    s += acc[l + lda * t];
                }
                o[d] = if fixed { s } else { s + grav[d] };
            }
        });
}

pub(super) fn predict(a: &mut Predict) {
    let Predict { dim, n, dt_prev, cont, lf, rates, bnd } = a;
    let (dim, n, dt_prev, cont) = (*dim, *n, *dt_prev, *cont);
    let half = 0.5 * dt_prev;
    let step = |u: &mut [f64], umin: &mut [f64], du: &[f64], w: usize, kb: &[i32]| {
        if kb.is_empty() {
            // no boundary particles: the plain loop, without a kind lookup per value
            for ((u, m), d) in u.iter_mut().zip(umin.iter_mut()).zip(du) {
                *m = *u;
                *u += half * d;
            }
            return;
        }
        for l in 0..u.len() {
            umin[l] = u[l];
            if !held(kb, l / w) {
                u[l] += half * du[l];
            }
        }
    };
    zip_vars(n, vars(dim, n, cont, lf, rates), bnd, step);
}

pub(super) fn advance(a: &mut Advance) {
    let Advance { dim, n, first, dt_prev, dt, cont, lf, rates, av, x, bnd } = a;
    let bnd: &[i32] = bnd;
    let (dim, n, first, dt_prev, dt, cont) = (*dim, *n, *first, *dt_prev, *dt, *cont);
    let sc = if first { 0.5 * dt } else { 0.5 * (dt_prev + dt) };
    // (u_min is read, not written: it comes mutably only to share the helper)
    let upd = |u: &mut [f64], umin: &mut [f64], du: &[f64], w: usize, kb: &[i32]| {
        for l in 0..u.len() {
            if !kb.is_empty() && held(kb, l / w) {
                continue;
            }
            if first {
                u[l] += sc * du[l];
            } else {
                u[l] = umin[l] + sc * du[l];
            }
        }
    };
    zip_vars(n, vars(dim, n, cont, lf, rates), bnd, upd);
    let v: &[f64] = &*lf.v;
    // boundary particles of either kind stay where they are
    let fixed = |i: usize| !bnd.is_empty() && bnd[i] != 0;
    if av.is_empty() {
        par_rows(&mut x[..dim * n], dim, |i, xi| {
            if fixed(i) {
                return;
            }
            for d in 0..dim {
                xi[d] += dt * v[d + dim * i];
            }
        });
    } else {
        par_rows(&mut x[..dim * n], dim, |i, xi| {
            if fixed(i) {
                return;
            }
            for d in 0..dim {
                xi[d] += dt * (v[d + dim * i] + av[d + dim * i]);
            }
        });
    }
}

pub(super) fn cfl(a: &Cfl) -> f64 {
    let Cfl { dim, cfl, h, c, v, dv, kv, mumax, eta, mat, rho, .. } = a;
    let (dim, cfl, kv) = (*dim, *cfl, *kv);
    let with_mu = !mumax.is_empty();
    let n = h.len();
    let part = |b: usize| -> f64 {
        let mut m = f64::MAX;
        for i in b * CHUNK..(b * CHUNK + CHUNK).min(n) {
            let mut vv = 0.0;
            let mut aa = 0.0;
            for d in 0..dim {
                vv += v[d + dim * i] * v[d + dim * i];
                aa += dv[d + dim * i] * dv[d + dim * i];
            }
            let mut t = if with_mu { h[i] / (c[i] + vv.sqrt() + kv * mumax[i]) } else { h[i] / (c[i] + vv.sqrt()) };
            if aa > 0.0 {
                let tf = (h[i] / aa.sqrt()).sqrt();
                if tf < t {
                    t = tf;
                }
            }
            if t < m {
                m = t;
            }
        }
        m
    };
    let nb = n.div_ceil(CHUNK);
    let mins: Vec<f64> =
        if serial() { (0..nb).map(part).collect() } else { (0..nb).into_par_iter().map(part).collect() };
    let m = mins.into_iter().fold(f64::MAX, |a, b| if b < a { b } else { a });
    let mut dt = cfl * m;
    if !eta.is_empty() {
        // the diffusion limit 0.125 h²/ν, ν = η/ρ, in index order as the Fortran takes it
        for i in 0..n {
            let e = eta[mat[i] as usize];
            if e > 0.0 {
                let tv = 0.125 * rho[i] * h[i] * h[i] / e;
                if tv < dt {
                    dt = tv;
                }
            }
        }
    }
    dt
}

/// e_i = max(e_i, 0), in index order; the energy added Σ_i m_i max(0, −e_i), term by term as the
/// Fortran sums it.
pub(super) fn efloor(a: &mut Efloor) {
    let mut added = 0.0;
    for (ei, &m) in a.e.iter_mut().zip(a.mass) {
        if *ei < 0.0 {
            added -= m * *ei;
            *ei = 0.0;
        }
    }
    *a.added = added;
}

/// Fortran's `sph_integrator_clamp`: below lo becomes lo, above hi becomes hi, a NaN stays.
pub(super) fn clamp(a: &mut Clamp) {
    let (lo, hi) = (a.lo, a.hi);
    for r in a.rho.iter_mut() {
        if *r < lo {
            *r = lo;
        } else if *r > hi {
            *r = hi;
        }
    }
}
