//! Leapfrog (thesis (2-17)…(2-27); Liu's time_integration) with a variable step, the rate sums
//! and the CFL step.
//!
//! Staggered variables u ∈ {ρ (continuity), e, v, τ}:
//! predict (after the first step): u_min = u; u(t_n) = u_min + Δt_{n−1}/2 · du(t_{n−1});
//! advance, first step: u(t_{1/2}) = u(t_0) + Δt_0/2 · du(t_0);
//! later: u(t_{n+1/2}) = u_min + (Δt_{n−1} + Δt_n)/2 · du(t_n); then x += Δt (v + av).
//! With a fixed step this is Liu's scheme exactly. CFL (s):
//! Δt = C min_i min(h_i/(c_i + |v_i|), √(h_i/|a_i|)). Rust twin: elementwise, same order, 0 ULP.

use super::Backend;
use crate::legacy::{self, Leapfrog, NSTR, Rates};
use rayon::prelude::*;

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
        Backend::Rust => out[..dim * n].par_iter_mut().enumerate().for_each(|(l, o)| {
            let d = l % dim;
            let mut s = 0.0;
            if nterm > 0 {
                s = acc[l];
            }
            for t in 1..nterm {
                s += acc[l + lda * t];
            }
            *o = s + grav[d];
        }),
    }
}

pub fn predict(b: Backend, dim: usize, n: usize, dt_prev: f64, cont: bool, s: Leapfrog, r: Rates) {
    match b {
        Backend::Fortran => legacy::integrator_predict(dim, n, dt_prev, cont, s, r),
        Backend::Rust => {
            let half = 0.5 * dt_prev;
            s.e_min[..n].copy_from_slice(&s.e[..n]);
            s.e[..n].par_iter_mut().zip(r.de[..n].par_iter()).for_each(|(e, de)| *e += half * de);
            if cont {
                s.rho_min[..n].copy_from_slice(&s.rho[..n]);
                s.rho[..n].par_iter_mut().zip(r.drho[..n].par_iter()).for_each(|(u, du)| *u += half * du);
            }
            s.v_min[..dim * n].copy_from_slice(&s.v[..dim * n]);
            s.v[..dim * n].par_iter_mut().zip(r.dv[..dim * n].par_iter()).for_each(|(u, du)| *u += half * du);
            if !s.tau.is_empty() {
                s.tau_min[..NSTR * n].copy_from_slice(&s.tau[..NSTR * n]);
                s.tau[..NSTR * n].par_iter_mut().zip(r.dtau[..NSTR * n].par_iter()).for_each(|(u, du)| *u += half * du);
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
            fn upd(u: &mut [f64], umin: &[f64], du: &[f64], first: bool, sc: f64) {
                if first {
                    u.par_iter_mut().zip(du.par_iter()).for_each(|(u, du)| *u += sc * du);
                } else {
                    u.par_iter_mut().zip(umin.par_iter().zip(du.par_iter())).for_each(|(u, (m, du))| *u = m + sc * du);
                }
            }
            let sc = if first { 0.5 * dt } else { 0.5 * (dt_prev + dt) };
            upd(&mut s.e[..n], &s.e_min[..n], &r.de[..n], first, sc);
            if cont {
                upd(&mut s.rho[..n], &s.rho_min[..n], &r.drho[..n], first, sc);
            }
            upd(&mut s.v[..dim * n], &s.v_min[..dim * n], &r.dv[..dim * n], first, sc);
            if !s.tau.is_empty() {
                upd(&mut s.tau[..NSTR * n], &s.tau_min[..NSTR * n], &r.dtau[..NSTR * n], first, sc);
            }
            let v: &[f64] = s.v;
            if av.is_empty() {
                x[..dim * n].par_iter_mut().zip(v[..dim * n].par_iter()).for_each(|(x, v)| *x += dt * v);
            } else {
                x[..dim * n]
                    .par_iter_mut()
                    .zip(v[..dim * n].par_iter().zip(av[..dim * n].par_iter()))
                    .for_each(|(x, (v, a))| *x += dt * (v + a));
            }
        }
    }
}

pub fn cfl(b: Backend, dim: usize, cfl: f64, h: &[f64], c: &[f64], v: &[f64], dv: &[f64]) -> f64 {
    match b {
        Backend::Fortran => legacy::integrator_cfl(dim, cfl, h, c, v, dv),
        Backend::Rust => {
            let m = (0..h.len())
                .into_par_iter()
                .map(|i| {
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
                    t
                })
                .reduce(|| f64::MAX, |a, b| if b < a { b } else { a });
            cfl * m
        }
    }
}
