//! The Rust twin of the conductivity: one parallel pass over the pairs computes
//! q = α v_sig (e_i − e_j)/ρ̄ (x̂·∇W), the Fortran's expression (0 for coincident particles), into a
//! reused buffer; the gather adds m_j q at the i end and −m_i q at the j end over each particle's
//! pairs in ascending pair order (the Fortran's scatter order). A coincident pair adds ±0, which
//! leaves a sum that starts at +0 unchanged. 0 ULP, independent of the thread count.

use super::Price;
use crate::modules::{by_dim, gather_signed, par_rows};

pub(super) fn price(a: &mut Price) {
    by_dim!(a.dim, 0, run(a))
}

fn run<const D: usize, const W: usize>(a: &mut Price) {
    let Price { pairs: pl, dwdx, x, v, rho, p, e, mass, alpha, signal, dedt, .. } = a;
    let (pl, dwdx, x, v, rho, p, e, mass, alpha, signal) = (*pl, *dwdx, *x, *v, *rho, *p, *e, *mass, *alpha, *signal);
    let np = pl.len();
    let mut guard = pl.scratch.lock();
    let buf = &mut *guard;
    buf.pair.resize(np, 0.0);
    let (pi, pj) = (&pl.i, &pl.j);
    par_rows(&mut buf.pair[..np], 1, |k, q| {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let (mut r2, mut xw, mut vr) = (0.0, 0.0, 0.0);
        for d in 0..D {
            let dx = x[d + D * i] - x[d + D * j];
            r2 += dx * dx;
            xw += dx * dwdx[d + D * k];
            vr += (v[d + D * i] - v[d + D * j]) * dx;
        }
        q[0] = if r2 > 0.0 {
            let r = r2.sqrt();
            let mrho = 0.5 * (rho[i] + rho[j]);
            let vs = if signal == 0 { ((p[i] - p[j]).abs() / mrho).sqrt() } else { vr.abs() / r };
            alpha * vs * (e[i] - e[j]) / mrho * (xw / r)
        } else {
            0.0
        };
    });
    // rows of one value: + m_j q at the i end, − m_i q at the j end
    gather_signed::<1, 1>(pl, &buf.pair, mass, None, dedt, &mut []);
}
