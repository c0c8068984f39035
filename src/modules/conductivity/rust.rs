//! The Rust twin of the conductivity: one parallel pass over the pairs computes
//! q = α v_sig (e_i − e_j)/ρ̄ (x̂·∇W), the Fortran's expression (0 for coincident particles), into a
//! reused buffer; the gather adds m_j q at the i end and −m_i q at the j end over each particle's
//! pairs in ascending pair order (the Fortran's scatter order). A coincident pair adds ±0, which
//! leaves a sum that starts at +0 unchanged. 0 ULP, independent of the thread count.

use crate::modules::grow;
use super::Price;
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
