//! Leapfrog (thesis (2-17)…(2-27); Liu's time_integration) with a variable step, the rate sums
//! and the CFL step.
//!
//! Staggered variables u ∈ {ρ (continuity), e, v, τ}:
//! predict (after the first step): u_min = u; u(t_n) = u_min + Δt_{n−1}/2 · du(t_{n−1});
//! advance, first step: u(t_{1/2}) = u(t_0) + Δt_0/2 · du(t_0);
//! later: u(t_{n+1/2}) = u_min + (Δt_{n−1} + Δt_n)/2 · du(t_n); then x += Δt (v + av).
//! With a fixed step this is Liu's scheme exactly. CFL (s):
//! Δt = C min_i min(h_i/(c_i + |v_i|), √(h_i/|a_i|)). Rust twin: elementwise, same order, 0 ULP;
//! one parallel pass over blocks of particles updates every staggered variable (the CFL minimum is
//! taken per task in index order, then over the tasks in order, so it does not depend on the
//! thread count).

use super::{Backend, CHUNK, par_rows, serial};
use crate::legacy::{self, Leapfrog, NSTR, Rates};
use rayon::prelude::*;

/// One staggered variable for [`zip_vars`]: u, u_min, du, values per particle.
type Var<'a> = (&'a mut [f64], &'a mut [f64], &'a [f64], usize);

/// A block's share of one variable: u, u_min, du.
type Part<'a> = (&'a mut [f64], &'a mut [f64], &'a [f64]);

/// `f(u, umin, du)` over every variable, in one parallel pass over blocks of particles (each
/// block handles the block's values of every variable, in the order given).
fn zip_vars<F>(n: usize, vars: Vec<Var<'_>>, f: F)
where
    F: Fn(&mut [f64], &mut [f64], &[f64]) + Sync + Send,
{
    // particles per block
    let rows = 4 * CHUNK;
    let nb = n.div_ceil(rows);
    let mut blocks: Vec<Vec<Part<'_>>> = (0..nb).map(|_| Vec::with_capacity(vars.len())).collect();
    for (u, um, du, w) in vars {
        let parts =
            u[..w * n].chunks_mut(w * rows).zip(um[..w * n].chunks_mut(w * rows)).zip(du[..w * n].chunks(w * rows));
        for (blk, ((a, b), c)) in blocks.iter_mut().zip(parts) {
            blk.push((a, b, c));
        }
    }
    let run = |blk: Vec<Part<'_>>| {
        for (a, b, c) in blk {
            f(a, b, c);
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

/// `out(d,i) = Σ_t acc_t(d,i) + grav(d)` for i < n; `acc` stacks `nterm` arrays of `lda` values.
#[allow(clippy::too_many_arguments)]
pub fn sum_rates(
    b: Backend,
    dim: usize,
    n: usize,
    lda: usize,
    nterm: usize,
    acc: &[f64],
    grav: &[f64],
    out: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::sum_rates(dim, n, lda, nterm, acc, grav, out),
        Backend::Rust => par_rows(&mut out[..dim * n], dim, |i, o| {
            for d in 0..dim {
                let l = d + dim * i;
                let mut s = 0.0;
                if nterm > 0 {
                    s = acc[l];
                }
                for t in 1..nterm {
                    s += acc[l + lda * t];
                }
                o[d] = s + grav[d];
            }
        }),
    }
}

pub fn predict(b: Backend, dim: usize, n: usize, dt_prev: f64, cont: bool, s: Leapfrog, r: Rates) {
    match b {
        Backend::Fortran => legacy::integrator_predict(dim, n, dt_prev, cont, s, r),
        Backend::Rust => {
            let half = 0.5 * dt_prev;
            let step = |u: &mut [f64], umin: &mut [f64], du: &[f64]| {
                for ((u, m), d) in u.iter_mut().zip(umin.iter_mut()).zip(du) {
                    *m = *u;
                    *u += half * d;
                }
            };
            let mut s = s;
            zip_vars(n, vars(dim, n, cont, &mut s, &r), step);
        }
    }
}

#[allow(clippy::too_many_arguments)]
pub fn advance(
    b: Backend,
    dim: usize,
    n: usize,
    first: bool,
    dt_prev: f64,
    dt: f64,
    cont: bool,
    s: Leapfrog,
    r: Rates,
    av: &[f64],
    x: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::integrator_advance(dim, n, first, dt_prev, dt, cont, s, r, av, x),
        Backend::Rust => {
            let sc = if first { 0.5 * dt } else { 0.5 * (dt_prev + dt) };
            // (u_min is read, not written: it comes mutably only to share the helper)
            let upd = |u: &mut [f64], umin: &mut [f64], du: &[f64]| {
                if first {
                    for l in 0..u.len() {
                        u[l] += sc * du[l];
                    }
                } else {
                    for l in 0..u.len() {
                        u[l] = umin[l] + sc * du[l];
                    }
                }
            };
            let mut s = s;
            zip_vars(n, vars(dim, n, cont, &mut s, &r), upd);
            let v: &[f64] = s.v;
            if av.is_empty() {
                par_rows(&mut x[..dim * n], dim, |i, xi| {
                    for d in 0..dim {
                        xi[d] += dt * v[d + dim * i];
                    }
                });
            } else {
                par_rows(&mut x[..dim * n], dim, |i, xi| {
                    for d in 0..dim {
                        xi[d] += dt * (v[d + dim * i] + av[d + dim * i]);
                    }
                });
            }
        }
    }
}

pub fn cfl(b: Backend, dim: usize, cfl: f64, h: &[f64], c: &[f64], v: &[f64], dv: &[f64]) -> f64 {
    match b {
        Backend::Fortran => legacy::integrator_cfl(dim, cfl, h, c, v, dv),
        Backend::Rust => {
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
                    let mut t = h[i] / (c[i] + vv.sqrt());
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
            cfl * m
        }
    }
}
