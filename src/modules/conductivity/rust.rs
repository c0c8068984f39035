//! The Rust twin of the conductivity: one parallel pass over the pairs computes
//! q = α v_sig (e_i − e_j)/ρ̄ (x̂·∇W), the Fortran's expression (0 for coincident particles), into a
//! reused buffer; the gather adds m_j q at the i end and −m_i q at the j end over each particle's
//! pairs in ascending pair order (the Fortran's scatter order). A coincident pair adds ±0, which
//! leaves a sum that starts at +0 unchanged. 0 ULP, independent of the thread count.
//!
//! The artificial heat (`noh`) in three passes: the pair terms (v_j − v_i)·∇W, gathered per
//! particle into the divergence, with (m_other × term)/ρ_other at both ends in ascending pair order
//! (the Fortran's scatter); q_i per particle from it; then each pair's f = q̄/(ρ̄ (r² + φ² h̄²)) (x·∇W)
//! and e_i − e_j, gathered as + (m_j f)(e_i − e_j) at the i end and − (m_i f)(e_i − e_j) at the j
//! end (written + ((−m_i) f)(e_i − e_j), the same IEEE operations), doubled at the end.

use crate::modules::grow;
use super::{Noh, Price};
use crate::modules::{by_dim, gather_signed, par_rows};

pub(super) fn price(a: &mut Price) {
    by_dim!(a.dim, 0, run(a))
}

fn run<const D: usize, const W: usize>(a: &mut Price) {
    let Price { pairs: pl, dwdx, x, v, rho, p, e, mass, alpha, signal, rinv, dedt, .. } = a;
    let (pl, dwdx, x, v, rho, p, e, mass, alpha, signal) = (*pl, *dwdx, *x, *v, *rho, *p, *e, *mass, *alpha, *signal);
    let rinv: &[f64] = rinv;
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    // RZ: three terms a pair (0, the i end's q r̄/r_i, the j end's −q r̄/r_j), gathered as the
    // energy column of a 1-component sum (+ m_j at the i end, + m_i at the j end)
    let wd = if rinv.is_empty() { 1 } else { 3 };
    grow(&mut buf.pair, wd * np);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..wd * np], wd, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let (mut r2, mut xw, mut vr) = (0.0, 0.0, 0.0);
        for d in 0..D {
            let dx = x[d + D * i] - x[d + D * j];
            r2 += dx * dx;
            xw += dx * dwdx[d + D * k];
            vr += (v[d + D * i] - v[d + D * j]) * dx;
        }
        let q = if r2 > 0.0 {
            let r = r2.sqrt();
            let mrho = 0.5 * (rho[i] + rho[j]);
            let vs = if signal == 0 { ((p[i] - p[j]).abs() / mrho).sqrt() } else { vr.abs() / r };
            alpha * vs * (e[i] - e[j]) / mrho * (xw / r)
        } else {
            0.0
        };
        if t.len() == 1 {
            t[0] = q;
        } else {
            // |1/r*|: an axis image carries a signed 1/r*, its ring the source's |r|
            let fi = 0.5 * (1.0 + rinv[i].abs() / rinv[j].abs());
            let fj = 0.5 * (1.0 + rinv[j].abs() / rinv[i].abs());
            t[0] = 0.0;
            t[1] = q * fi;
            t[2] = -(q * fj);
        }
    });
    if rinv.is_empty() {
        // rows of one value: + m_j q at the i end, − m_i q at the j end
        gather_signed::<1, 1>(pl, &buf.pair, mass, None, dedt, &mut []);
    } else {
        // + m_j (q r̄/r_i) at the i end, + m_i (−q r̄/r_j) at the j end (the Fortran's − m_i (q r̄/r_j))
        let nt = mass.len();
        grow(&mut buf.part, nt);
        gather_signed::<1, 3>(pl, &buf.pair, mass, None, &mut buf.part[..nt], dedt);
    }
}

pub(super) fn noh(a: &mut Noh) {
    by_dim!(a.dim, 0, run_noh(a))
}

fn run_noh<const D: usize, const W: usize>(a: &mut Noh) {
    let Noh { pairs: pl, dwdx, x, v, h, rho, c, e, mass, coef, dedt, .. } = a;
    let (pl, dwdx, x, v, h, rho, c, e, mass) = (*pl, *dwdx, *x, *v, *h, *rho, *c, *e, *mass);
    let super::HeatCoef { g1, g2, phi2 } = *coef;
    let (np, nt) = (pl.len(), mass.len());
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    grow(&mut buf.pair, 2 * np);
    grow(&mut buf.part, nt);
    let (pi, pj) = (&pl.i, &pl.j);
    // the divergence's pair terms (v_j − v_i)·∇_i W_ij
    par_rows(&mut buf.pair[..np], 1, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let mut hv = 0.0;
        for d in 0..D {
            hv += (v[d + D * j] - v[d + D * i]) * dwdx[d + D * k];
        }
        t[0] = hv;
    });
    // div_a, then q_a = g1 h c + g2 h² (|div| − div) in its place
    let terms: &[f64] = &buf.pair[..np];
    par_rows(&mut buf.part[..nt], 1, |p, q| {
        let mut s = 0.0;
        for inc in pl.incident(p) {
            let o = inc.other();
            s += mass[o] * terms[inc.pair()] / rho[o];
        }
        q[0] = g1 * h[p] * c[p] + g2 * (h[p] * h[p]) * (s.abs() - s);
    });
    // each pair's f and e_i − e_j
    let qs: &[f64] = &buf.part[..nt];
    par_rows(&mut buf.pair[..2 * np], 2, |k, t| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let (mut r2, mut xw) = (0.0, 0.0);
        for d in 0..D {
            let dx = x[d + D * i] - x[d + D * j];
            r2 += dx * dx;
            xw += dx * dwdx[d + D * k];
        }
        let hb = 0.5 * (h[i] + h[j]);
        let mrho = 0.5 * (rho[i] + rho[j]);
        let qb = 0.5 * (qs[i] + qs[j]);
        t[0] = qb / (mrho * (r2 + phi2 * (hb * hb))) * xw;
        t[1] = e[i] - e[j];
    });
    let terms: &[f64] = &buf.pair[..2 * np];
    par_rows(&mut dedt[..nt], 1, |p, out| {
        let mut s = 0.0;
        for inc in pl.incident(p) {
            let m = mass[inc.other()];
            let ms = if inc.is_i() { m } else { -m };
            let t = &terms[2 * inc.pair()..2 * inc.pair() + 2];
            s += ms * t[0] * t[1];
        }
        out[0] = 2.0 * s;
    });
}
