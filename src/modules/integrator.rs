//! Leapfrog (thesis (2-17)…(2-27); Liu's time_integration) with a variable step, the rate sums
//! and the CFL step.
//!
//! Staggered variables u ∈ {ρ (continuity), e, v, τ}:
//! predict (after the first step): u_min = u; u(t_n) = u_min + Δt_{n−1}/2 · du(t_{n−1});
//! advance, first step: u(t_{1/2}) = u(t_0) + Δt_0/2 · du(t_0);
//! later: u(t_{n+1/2}) = u_min + (Δt_{n−1} + Δt_n)/2 · du(t_n); then x += Δt (v + av).
//! With a fixed step this is Liu's scheme exactly. CFL (s):
//! Δt = C min_i min(h_i/(c_i + |v_i|), √(h_i/|a_i|)). Rust twin: elementwise, same order, 0 ULP;
//! one fused pass per staggered variable, in tasks of a few thousand values (the CFL minimum is
//! taken per task in index order, then over the tasks in order, so it does not depend on the
//! thread count).

use super::{Backend, CHUNK, par_rows, serial};
use crate::legacy::{self, Leapfrog, NSTR, Rates};
use rayon::prelude::*;

/// Values per task of the elementwise updates.
const EW: usize = 8 * CHUNK;

/// `f(u, umin, du)` over matching blocks of three arrays.
fn zip3<F>(u: &mut [f64], umin: &mut [f64], du: &[f64], f: F)
where
    F: Fn(&mut [f64], &mut [f64], &[f64]) + Sync + Send,
{
    let n = u.len();
    let (umin, du) = (&mut umin[..n], &du[..n]);
    if serial() {
        u.chunks_mut(EW).zip(umin.chunks_mut(EW)).zip(du.chunks(EW)).for_each(|((a, b), c)| f(a, b, c));
    } else {
        u.par_chunks_mut(EW).zip(umin.par_chunks_mut(EW)).zip(du.par_chunks(EW)).for_each(|((a, b), c)| f(a, b, c));
    }
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
            zip3(&mut s.e[..n], &mut s.e_min[..n], &r.de[..n], step);
            if cont {
                zip3(&mut s.rho[..n], &mut s.rho_min[..n], &r.drho[..n], step);
            }
            zip3(&mut s.v[..dim * n], &mut s.v_min[..dim * n], &r.dv[..dim * n], step);
            if !s.tau.is_empty() {
                zip3(&mut s.tau[..NSTR * n], &mut s.tau_min[..NSTR * n], &r.dtau[..NSTR * n], step);
            }
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
            // (u_min is read, not written: zip3 hands it over mutably only to share the helper)
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
            zip3(&mut s.e[..n], &mut s.e_min[..n], &r.de[..n], upd);
            if cont {
                zip3(&mut s.rho[..n], &mut s.rho_min[..n], &r.drho[..n], upd);
            }
            zip3(&mut s.v[..dim * n], &mut s.v_min[..dim * n], &r.dv[..dim * n], upd);
            if !s.tau.is_empty() {
                zip3(&mut s.tau[..NSTR * n], &mut s.tau_min[..NSTR * n], &r.dtau[..NSTR * n], upd);
            }
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
