//! Averaged velocity (XSPH; Liu's av_vel): av_i = ε Σ_j (m_j/ρ̄_ij)(v_j − v_i) W_ij (m/s).
//! The integrator moves particles with v + av. Rust twin: gather, 0 ULP.

use super::{Backend, nnps::PairList, par_rows};
use crate::legacy;

#[allow(clippy::too_many_arguments)]
pub fn average(
    b: Backend,
    dim: usize,
    pl: &PairList,
    w: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    eps: f64,
    av: &mut [f64],
) {
    match b {
        Backend::Fortran => legacy::xsph_average(dim, &pl.i, &pl.j, w, mass, rho, v, eps, av),
        Backend::Rust => {
            let nt = mass.len();
            par_rows(&mut av[..dim * nt], dim, |a, acc| {
                acc.iter_mut().for_each(|x| *x = 0.0);
                for &k in pl.incident(a) {
                    let k = k as usize;
                    let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                    let mrho = 0.5 * (rho[i] + rho[j]);
                    for d in 0..dim {
                        let f = (v[d + dim * i] - v[d + dim * j]) / mrho * w[k];
                        if a == i {
                            acc[d] -= mass[j] * f;
                        } else {
                            acc[d] += mass[i] * f;
                        }
                    }
                }
                acc.iter_mut().for_each(|x| *x *= eps);
            });
        }
    }
}
