//! Parity of the boundaries: the wall force, and the mirrors (list, fill in free and no slip,
//! with and without τ, copy), for a 1D column, 2D boxes and 3D cubes (walls as planes), one of
//! each turned so no normal is along an axis.

use super::{MirrorCopy, MirrorFill, MirrorMake, WallCoef, WallForce};
use crate::modules::param::{NSTR, Segments};
use crate::modules::testkit::*;

/// A box of `side × side` particles (spacing dx, jittered) with four walls, turned by `angle`
/// so that no normal is along an axis. Returns the cloud (no virtual particles) and the walls.
fn walled_box(side: usize, angle: f64, seed: u64) -> (Cloud, Segments) {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let l = side as f64 * dx;
    let (cs, sn) = (angle.cos(), angle.sin());
    let rot = |p: [f64; 2]| [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1]];
    let n = side * side;
    let mut x = Vec::with_capacity(2 * n);
    for k in 0..n {
        let (a, b) = ((k % side) as f64, (k / side) as f64);
        let p = rot([(a + 0.5 + g.range(-0.35, 0.35)) * dx, (b + 0.5 + g.range(-0.35, 0.35)) * dx]);
        x.extend_from_slice(&p);
    }
    // corners counter-clockwise; inward normals; the end node kept on two of the four walls
    let corners = [[0.0, 0.0], [l, 0.0], [l, l], [0.0, l]];
    let normals = [[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]];
    let mut segs = Segments::default();
    for s in 0..4 {
        segs.seg.extend_from_slice(&rot(corners[s]));
        segs.seg.extend_from_slice(&rot(corners[(s + 1) % 4]));
        segs.seg.extend_from_slice(&rot(normals[s]));
        segs.endnode.push(i32::from(s % 2 == 0));
    }
    (filled(&mut g, 2, n, dx, x, 0.1, 0.2), segs)
}

/// A cube of `side³` particles (spacing dx, jittered) in the corner of three walls x = 0, y = 0,
/// z = 0 and a fourth x = l (3D walls: `seg(12, nseg)`, a corner, two edge vectors, the inward
/// normal; the edge masks drop the edges an earlier wall owns), turned by `angle` about z and
/// then about x so no normal is along an axis.
fn walled_cube(side: usize, angle: f64, seed: u64) -> (Cloud, Segments) {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let l = side as f64 * dx;
    let (cs, sn) = (angle.cos(), angle.sin());
    let rot = |p: [f64; 3]| {
        let q = [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1], p[2]];
        [q[0], cs * q[1] - sn * q[2], sn * q[1] + cs * q[2]]
    };
    let n = side * side * side;
    let mut x = Vec::with_capacity(3 * n);
    for k in 0..n {
        let (a, b, c) = ((k % side) as f64, ((k / side) % side) as f64, (k / (side * side)) as f64);
        let j = |t: f64, g: &mut Rng| (t + 0.5 + g.range(-0.35, 0.35)) * dx;
        let p = [j(a, &mut g), j(b, &mut g), j(c, &mut g)];
        x.extend_from_slice(&rot(p));
    }
    // ([corner, u, v, normal], edge mask)
    type Wall = ([[f64; 3]; 4], i32);
    let walls: [Wall; 4] = [
        ([[0.0, 0.0, 0.0], [l, 0.0, 0.0], [0.0, l, 0.0], [0.0, 0.0, 1.0]], 15),
        ([[0.0, 0.0, 0.0], [l, 0.0, 0.0], [0.0, 0.0, l], [0.0, 1.0, 0.0]], 7),
        ([[0.0, 0.0, 0.0], [0.0, l, 0.0], [0.0, 0.0, l], [1.0, 0.0, 0.0]], 3),
        ([[l, 0.0, 0.0], [0.0, l, 0.0], [0.0, 0.0, l], [-1.0, 0.0, 0.0]], 3),
    ];
    let mut segs = Segments::default();
    for ([a, u, v, nrm], mask) in walls {
        segs.seg.extend_from_slice(&rot(a));
        segs.seg.extend_from_slice(&rot(u));
        segs.seg.extend_from_slice(&rot(v));
        segs.seg.extend_from_slice(&rot(nrm));
        segs.endnode.push(mask);
    }
    (filled(&mut g, 3, n, dx, x, 0.1, 0.2), segs)
}

/// A 1D column between two point walls.
fn walled_column(n: usize, seed: u64) -> (Cloud, Segments) {
    let mut g = Rng::new(seed);
    let dx = 0.01;
    let l = n as f64 * dx;
    let x = (0..n).map(|k| (k as f64 + 0.5 + g.range(-0.35, 0.35)) * dx).collect();
    let segs = Segments { seg: vec![0.0, 0.0, 1.0, l, l, -1.0], endnode: vec![1, 1] };
    (filled(&mut g, 1, n, dx, x, 10.0, 20.0), segs)
}

/// A cloud of `n` real particles at `x` with random fields; masses in [m0, m1].
fn filled(g: &mut Rng, dim: usize, n: usize, dx: f64, x: Vec<f64>, m0: f64, m1: f64) -> Cloud {
    Cloud {
        dim,
        nreal: n,
        nt: n,
        dx,
        v: g.vec(dim * n, -60.0, 60.0),
        h: (0..n).map(|_| dx * g.range(1.0, 1.5)).collect(),
        rho: g.vec(n, 1000.0, 2000.0),
        mass: g.vec(n, m0, m1),
        p: g.vec(n, -1e5, 1e7),
        c: g.vec(n, 300.0, 1500.0),
        e: g.vec(n, 0.0, 1e4),
        mat: (0..n).map(|_| g.below(3) as i32).collect(),
        tau: g.vec(NSTR * n, -1e6, 1e6),
        x,
    }
}

fn walled_cases() -> Vec<(String, Cloud, Segments)> {
    let mut v = Vec::new();
    let (c, s) = walled_column(60, 121);
    v.push(("1D column".to_string(), c, s));
    let (c, s) = walled_box(16, 0.0, 122);
    v.push(("2D box".to_string(), c, s));
    let (c, s) = walled_box(16, 0.37, 123);
    v.push(("2D turned box".to_string(), c, s));
    let (c, s) = walled_cube(8, 0.0, 124);
    v.push(("3D cube".to_string(), c, s));
    let (c, s) = walled_cube(8, 0.37, 125);
    v.push(("3D turned cube".to_string(), c, s));
    v
}

#[test]
fn boundary_wall_force() {
    for (name, cl, segs) in walled_cases() {
        let dim = cl.dim;
        for (spacing, r0, d, n1, n2) in [(0.25 * cl.dx, 0.5 * cl.dx, 1e4, 12, 4), (cl.dx, cl.dx, 5.0 * 9.81 * 0.2, 4, 2)]
        {
            let coef = WallCoef { spacing, r0, d, n1, n2 };
            let tag = format!("boundary::wall_force {name} r0 {r0}");
            let [acc] = parity(&tag, 0, ["dvdt"], [sentinel(dim * cl.nreal)], |b, [dvdt]| {
                run(WallForce { dim, x: &cl.x, segs: &segs, coef, dvdt }, b)
            });
            nonzero(&tag, &acc);
        }
    }
}

/// Mirrors of the walled cases: the lists, then the fill (free and no slip, with and without
/// τ), then the copy of one field.
#[test]
fn boundary_mirrors_make_fill_copy() {
    for (name, cl, segs) in walled_cases() {
        let dim = cl.dim;
        let n = cl.nreal;
        let kappa = 2.0;
        let (mut sf, mut gf) = (vec![7; 3], vec![7; 5]);
        let (mut sr, mut gr) = (vec![7; 3], vec![7; 5]);
        for (b, gsrc, gseg) in [(F, &mut sf, &mut gf), (R, &mut sr, &mut gr)] {
            run(MirrorMake { dim, x: &cl.x, h: &cl.h, kappa, segs: &segs, gsrc, gseg }, b);
        }
        check_i(&format!("boundary::mirror_make {name} gsrc"), &sf, &sr);
        check_i(&format!("boundary::mirror_make {name} gseg"), &gf, &gr);
        let ng = sf.len();
        assert!(ng > 0);
        if dim == 2 {
            let second = (0..ng).filter(|&g| gf[2 * g + 1] >= 0).count();
            assert!(second > 0, "{name}: no second-generation (corner) mirror");
        }
        if dim == 3 {
            let third = (0..ng).filter(|&g| gf[3 * g + 2] >= 0).count();
            assert!(third > 0, "{name}: no third-generation (corner of three walls) mirror");
        }
        let nt = n + ng;
        // real part copied from the cloud, mirror part a sentinel
        let grow = |a: &[f64], w: usize| {
            let mut v = a[..w * n].to_vec();
            v.resize(w * nt, SENTINEL);
            v
        };
        for noslip in [false, true] {
            for with_tau in [false, true] {
                let tag = format!(
                    "boundary::mirror_fill {name} {} {}",
                    if noslip { "no slip" } else { "free slip" },
                    if with_tau { "with tau" } else { "no tau" }
                );
                let mut mat = cl.mat[..n].to_vec();
                mat.resize(nt, -9);
                let (mut mf, mut mr) = (mat.clone(), mat);
                let tau = if with_tau { grow(&cl.tau, NSTR) } else { vec![] };
                let init = [
                    grow(&cl.x, dim),
                    grow(&cl.v, dim),
                    grow(&cl.rho, 1),
                    grow(&cl.p, 1),
                    grow(&cl.c, 1),
                    grow(&cl.e, 1),
                    grow(&cl.h, 1),
                    grow(&cl.mass, 1),
                    tau,
                ];
                let names = ["x", "v", "rho", "p", "c", "e", "h", "mass", "tau"];
                let mats = std::cell::RefCell::new((&mut mf, &mut mr));
                let f = parity(&tag, 0, names, init, |b, [x, v, rho, p, c, e, h, mass, tau]| {
                    let mut m = mats.borrow_mut();
                    let mat = if b == F { &mut *m.0 } else { &mut *m.1 };
                    let (gsrc, gseg, segs) = (&sf, &gf, &segs);
                    run(MirrorFill { dim, n, gsrc, gseg, segs, noslip, x, v, rho, p, c, e, h, mass, mat, tau }, b)
                });
                for (k, field) in names.iter().enumerate() {
                    assert!(f[k].iter().all(|v| *v != SENTINEL), "{tag} {field} left unwritten");
                }
                check_i(&format!("{tag} mat"), &mf, &mr);
            }
        }
        let mut e = cl.e[..n].to_vec();
        e.resize(nt, SENTINEL);
        parity(&format!("boundary::mirror_copy {name}"), 0, ["f"], [e], |b, [f]| {
            run(MirrorCopy { n, gsrc: &sf, f }, b)
        });
    }
}

/// The mirror band is wide enough for the particle that reaches farthest: a lattice above the wall
/// y = 0, one particle beside the wall with h = 4 h0 (a blast's hot centre) and the rest at h0.
/// Every particle j that the hot one reaches, |x_j − x_hot| < κ (h_hot + h_j)/2, has its image
/// listed when that image is within the same reach (with each particle's band its own κ h_j, the
/// images of the particles beyond κ h0 of the wall were missing: the hot particle felt the real side
/// only and was pushed through the mirror). Both twins.
#[test]
fn boundary_mirror_band_covers_the_largest_h() {
    let (dx, side) = (0.01, 12usize);
    let mut x = Vec::new();
    let mut h = Vec::new();
    for b in 0..side {
        for a in 0..side {
            x.extend_from_slice(&[(a as f64 + 0.5) * dx, (b as f64 + 0.5) * dx]);
            h.push(dx);
        }
    }
    let hot = side / 2; // (6.5 dx, 0.5 dx): on the first row
    h[hot] = 4.0 * dx;
    let mut segs = Segments::default();
    segs.seg.extend_from_slice(&[0.0, 0.0, side as f64 * dx, 0.0, 0.0, 1.0]);
    segs.endnode.push(1);
    let kappa = 2.0;
    let (mut sf, mut gf) = (Vec::new(), Vec::new());
    let (mut sr, mut gr) = (Vec::new(), Vec::new());
    for (b, gsrc, gseg) in [(F, &mut sf, &mut gf), (R, &mut sr, &mut gr)] {
        run(MirrorMake { dim: 2, x: &x, h: &h, kappa, segs: &segs, gsrc, gseg }, b);
    }
    check_i("boundary::mirror_make band gsrc", &sf, &sr);
    check_i("boundary::mirror_make band gseg", &gf, &gr);
    let (xh, yh) = (x[2 * hot], x[2 * hot + 1]);
    let mut needed = 0;
    for j in 0..side * side {
        let (xj, yj) = (x[2 * j], -x[2 * j + 1]);
        let reach = kappa * 0.5 * (h[hot] + h[j]);
        if ((xj - xh).powi(2) + (yj - yh).powi(2)).sqrt() < reach {
            needed += 1;
            assert!(sf.contains(&(j as i32)), "the image of particle {j} (y = {}) is missing", x[2 * j + 1]);
        }
    }
    assert!(needed > 20, "the hot particle reaches {needed} images");
}

/// The repulsion of boundary particles: a cloud whose first layers and every seventh particle are
/// boundary particles (held or integrated), half the pairs swapped so that the boundary member is
/// first in some and second in others, the mirrors neither; the book's constants and
/// non-integer exponents, with and without gravity. 1D to 3D.
#[test]
fn boundary_repulsion_pairs_either_order() {
    use super::{Repulsion, RepulsionCoef};
    let book_d = f64::from(9.8f32.sqrt()).powi(2);
    let coefs = [
        RepulsionCoef { r0: f64::from(0.01f32), d: book_d, p1: 12.0, p2: 4.0 },
        RepulsionCoef { r0: 0.0115, d: 1e2, p1: 6.5, p2: 2.5 },
    ];
    for (dim, seed) in clouds(131) {
        let cl = cloud(dim, side(dim), seed);
        let mut pl = pairs(&cl, 2.0);
        for k in (0..pl.len()).step_by(2) {
            (pl.i[k], pl.j[k]) = (pl.j[k], pl.i[k]);
        }
        let bnd: Vec<i32> = (0..cl.nreal)
            .map(|i| if cl.x[dim * i] < 1.5 * cl.dx { 2 } else if i % 7 == 3 { 1 } else { 0 })
            .collect();
        // pairs in reach with the ordinary member first, and with it second
        let reach = |first_ordinary: bool| {
            (0..pl.len()).any(|k| {
                let (i, j) = (pl.i[k] as usize, pl.j[k] as usize);
                let r2: f64 = (0..dim).map(|d| (cl.x[d + dim * i] - cl.x[d + dim * j]).powi(2)).sum();
                let (o, b) = if first_ordinary { (i, j) } else { (j, i) };
                o < cl.nreal && b < cl.nreal && bnd[o] == 0 && bnd[b] != 0 && r2.sqrt() < coefs[0].r0
            })
        };
        assert!(reach(true) && reach(false), "{dim}D seed {seed}: no pair in reach in one of the orders");
        let grav = vec![-3.0; dim];
        for coef in coefs {
            for g in [&[][..], &grav[..]] {
                let tag = format!("boundary::repulsion {dim}D seed {seed} p1 {} gravity {}", coef.p1, !g.is_empty());
                let [acc] = parity(&tag, 0, ["dvdt"], [sentinel(dim * cl.nt)], |b, [dvdt]| {
                    let (x, bnd) = (&cl.x[..], &bnd[..]);
                    run(Repulsion { dim, pairs: &pl, x, bnd, coef, grav: g, dvdt }, b)
                });
                // pushed: an ordinary particle's term differs from the gravity
                let base = if g.is_empty() { 0.0 } else { -3.0 };
                assert!(acc.iter().any(|&a| a != base), "{tag}: no particle pushed");
                // no term on a boundary particle or a mirror: the gravity alone
                for i in (0..cl.nt).filter(|&i| i >= cl.nreal || bnd[i] != 0) {
                    assert!(acc[dim * i..dim * i + dim].iter().all(|&a| a == base), "{tag}: particle {i} pushed");
                }
            }
        }
    }
}
