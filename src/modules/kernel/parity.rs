//! Parity of the kernel: every kernel over jittered clouds, 1D to 3D, reaching every branch; the
//! self-contribution; single points at the branch edges q = 0, 1, 2, 3 and either side of them.

use super::{Pairs, Point, SelfW};
use crate::modules::testkit::*;

#[test]
fn kernel_pairs_all_kernels_all_dims() {
    for (dim, seed) in clouds(11) {
        let cl = cloud(dim, side(dim), seed);
        for kind in KERNELS {
            let pl = pairs(&cl, kind.support());
            let np = pl.len();
            // the pairs reach every branch of the kernel: q < 1, 1 ≤ q < 2, (and 2 ≤ q < 3)
            let mut branch = [0usize; 3];
            for k in 0..np {
                let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                let r = (0..dim).map(|d| (cl.x[d + dim * i] - cl.x[d + dim * j]).powi(2)).sum::<f64>().sqrt();
                let q = r / (0.5 * (cl.h[i] + cl.h[j]));
                branch[(q as usize).min(2)] += 1;
            }
            assert!(branch[0] > 0 && branch[1] > 0, "{branch:?}");
            if kind.support() > 2.0 {
                assert!(branch[2] > 0, "{branch:?}");
            }
            // without and with the lattice normalisation of ∇W (sph.lattice_gradient)
            for gscale in [1.0, 1.0 / super::lattice_moment(dim, kind, 1.0)] {
                let tag = format!("kernel::pairs {} {dim}D seed {seed} gscale {gscale}", kind.name());
                let [_, g] = parity(&tag, 0, ["w", "dwdx"], [sentinel(np), sentinel(dim * np)], |b, [w, dwdx]| {
                    run(Pairs { dim, kind, pairs: &pl, x: &cl.x, h: &cl.h, w, dwdx, gscale }, b)
                });
                nonzero(&tag, &g);
            }
        }
    }
}

#[test]
fn kernel_self_all_kernels_all_dims() {
    let mut g = Rng::new(21);
    let h = g.vec(500, 0.002, 0.05);
    for dim in 1..=3 {
        for kind in KERNELS {
            let tag = format!("kernel::self {} {dim}D", kind.name());
            let [w0] = parity(&tag, 0, ["w0"], [sentinel(h.len())], |b, [w0]| {
                run(SelfW { dim, kind, h: &h, w0 }, b)
            });
            nonzero(&tag, &w0);
        }
    }
}

/// The point evaluation of both twins at the branch edges q = 0, 1, 2, 3 (and either side of
/// them), along an axis and along a diagonal.
#[test]
fn kernel_point_at_branch_edges() {
    let h = 0.013;
    let mut qs = vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5];
    for edge in [1.0f64, 2.0, 3.0] {
        qs.push(f64::from_bits(edge.to_bits() - 1));
        qs.push(f64::from_bits(edge.to_bits() + 1));
    }
    for dim in 1..=3 {
        for kind in KERNELS {
            let mut seps = Vec::new();
            for &q in &qs {
                for diagonal in [false, true] {
                    let mut dx = vec![0.0; dim];
                    if diagonal {
                        let s = q * h / (dim as f64).sqrt();
                        dx.iter_mut().enumerate().for_each(|(d, v)| *v = if d % 2 == 0 { s } else { -s });
                    } else {
                        dx[0] = q * h;
                    }
                    seps.push(dx);
                }
            }
            let n = seps.len();
            let tag = format!("kernel::point edges {} {dim}D", kind.name());
            parity(&tag, 0, ["w", "dwdx"], [sentinel(n), sentinel(dim * n)], |b, [w, g]| {
                for (k, dx) in seps.iter().enumerate() {
                    run(Point { dim, kind, dx, h, w: &mut w[k], dwdx: &mut g[dim * k..dim * k + dim] }, b);
                }
            });
        }
    }
}

/// The lattice moment against sums made apart (numpy over a lattice of unit spacing): the cubic
/// spline at h = Δx in 2D and 3D, and at 1.2 Δx in 3D; and a gradient of a linear field on a
/// lattice comes out exact once ∇W is divided by it.
#[test]
fn the_lattice_moment_is_the_cubic_splines_first_moment_and_mends_a_linear_gradient() {
    use crate::case::KernelKind;
    let s = |d, h| super::lattice_moment(d, KernelKind::Cubic, h);
    assert!((s(2, 1.0) - 1.0131).abs() < 5e-5, "{}", s(2, 1.0));
    assert!((s(3, 1.0) - 1.0200).abs() < 5e-5, "{}", s(3, 1.0));
    assert!((s(3, 1.2) - 0.9817).abs() < 5e-5, "{}", s(3, 1.2));
    // f = 3 x + 2 y on a 2D lattice (Δx = 0.01, h = Δx): Σ_j V_j (f_j − f_i) ∇_i W_ij / S = ∇f
    // at the centre particle, with ∇W from the twin's w_dw
    let (dx, n) = (0.01, 9usize);
    let mut x = Vec::new();
    for j in 0..n {
        for i in 0..n {
            x.extend_from_slice(&[i as f64 * dx, j as f64 * dx]);
        }
    }
    let c = (n / 2) * n + n / 2;
    let f = |k: usize| 3.0 * x[2 * k] + 2.0 * x[2 * k + 1];
    let gs = 1.0 / s(2, 1.0);
    let mut grad = [0.0; 2];
    for k in 0..n * n {
        if k == c {
            continue;
        }
        let d = [x[2 * c] - x[2 * k], x[2 * c + 1] - x[2 * k + 1]];
        let mut g = [0.0; 2];
        let r = (d[0] * d[0] + d[1] * d[1]).sqrt();
        super::w_dw(2, KernelKind::Cubic, r, &d, dx, &mut g);
        for a in 0..2 {
            grad[a] += dx * dx * (f(k) - f(c)) * g[a] * gs;
        }
    }
    assert!((grad[0] - 3.0).abs() < 1e-9 && (grad[1] - 2.0).abs() < 1e-9, "{grad:?}");
}
