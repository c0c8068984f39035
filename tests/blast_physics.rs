//! The thesis's blast routines of the legacy Fortran core, through their argument lists run with
//! `Backend::Fortran`, against values computed by hand: Drucker–Prager radial return, the
//! Jaumann rate under rigid rotation, the penalty force, mirror particles, the type I wall force,
//! the programmed burn.

use blastsph::case::KernelKind;
use blastsph::modules::Backend::Fortran as F;
use blastsph::modules::nnps::{PairList, Search};
use blastsph::modules::param::{
    MatTable, NPAR, NSTR, SPH_EOS_JWL, SPH_EOS_SOIL, SPH_MP_ECHEM, SPH_MP_ETA_CJ, SPH_MP_UNR_C, Segments,
};
use blastsph::modules::{Twin, boundary, detonation, eos, kernel, penalty, strength};

/// One soil-like material with strength (G, α_φ, k) and one without (G = 0).
fn soil_table(g: f64, alpha: f64, k: f64) -> MatTable {
    let mut mpar = vec![0.0; 2 * NPAR];
    for m in 0..2 {
        mpar[NPAR * m] = 1450.0; // rho0
        mpar[1 + NPAR * m] = 1440.0; // C
        mpar[2 + NPAR * m] = 1.6; // S
        mpar[3 + NPAR * m] = 0.11; // Gamma
        mpar[7 + NPAR * m] = -f64::MAX; // pmin
    }
    mpar[8] = g;
    mpar[9] = alpha;
    mpar[10] = k;
    MatTable { mtype: vec![SPH_EOS_SOIL as i32; 2], mpar, group: vec![0, 1] }
}

fn sqrt_j2(t: &[f64]) -> f64 {
    (0.5 * (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) + t[3] * t[3] + t[4] * t[4] + t[5] * t[5]).sqrt()
}

#[test]
fn drucker_prager_radial_return() {
    let (g, alpha, k) = (63.58e6, 0.25, 200.0);
    let mt = soil_table(g, alpha, k);
    let p = [1.0e6, 1.0e6, -1.0e6, 1.0e6];
    let y = 3.0 * alpha * p[0] + k; // yield value at p = 1 MPa: 750 200 Pa
    // particle 0: outside the surface (sqrt J2 = 2Y); 1: inside (0.5 Y);
    // 2: tension with Y <= 0; 3: no strength (material 1, G = 0)
    let dir = [0.3, -0.5, 0.2, 0.4, 0.1, -0.2];
    let dn = sqrt_j2(&dir);
    let mut tau = Vec::new();
    for (i, s) in [2.0, 0.5, 1.0, 3.0].iter().enumerate() {
        let _ = i;
        tau.extend(dir.iter().map(|d| d / dn * s * y));
    }
    let before = tau.clone();
    strength::Yield { mat: &[0, 0, 0, 1], mt: &mt, p: &p, tau: &mut tau }.run(F);
    let t0 = &tau[0..NSTR];
    assert!((sqrt_j2(t0) - y).abs() <= 1e-12 * y, "returned onto the surface: {} vs {y}", sqrt_j2(t0));
    for q in 0..NSTR {
        assert!((t0[q] / before[q] - 0.5).abs() < 1e-12, "radial: every component scaled by Y/sqrt(J2) = 1/2");
    }
    assert_eq!(&tau[NSTR..2 * NSTR], &before[NSTR..2 * NSTR], "inside the surface: unchanged");
    assert!(tau[2 * NSTR..3 * NSTR].iter().all(|v| *v == 0.0), "tension cut-off: 3 alpha p + k <= 0 gives tau = 0");
    assert_eq!(&tau[3 * NSTR..], &before[3 * NSTR..], "a material without strength is left alone");
}

/// Positions, velocities, h, rho and masses of a lattice.
type Lattice = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// A 2D lattice of particles (spacing dx, h = dx) with velocity v(x) = f(x).
fn lattice(nside: usize, dx: f64, vel: impl Fn(f64, f64) -> (f64, f64)) -> Lattice {
    let n = nside * nside;
    let mut x = Vec::with_capacity(2 * n);
    let mut v = Vec::with_capacity(2 * n);
    for j in 0..nside {
        for i in 0..nside {
            let (px, py) = ((i as f64 - (nside / 2) as f64) * dx, (j as f64 - (nside / 2) as f64) * dx);
            x.extend([px, py]);
            let (a, b) = vel(px, py);
            v.extend([a, b]);
        }
    }
    (x, v, vec![dx; n], vec![1450.0; n], vec![1450.0 * dx * dx; n])
}

fn pairs_of(x: &[f64], h: &[f64]) -> (PairList, Vec<f64>, Vec<f64>) {
    let n = h.len();
    let mut pl = PairList::default();
    Search { cell: false, dim: 2, nreal: n, x, h, kappa: 2.0, pairs: &mut pl }.run(F);
    let np = pl.len();
    let mut w = vec![0.0; np];
    let mut dwdx = vec![0.0; 2 * np];
    kernel::Pairs { dim: 2, kind: KernelKind::Cubic, pairs: &pl, x, h, w: &mut w, dwdx: &mut dwdx, gscale: 1.0 }.run(F);
    (pl, w, dwdx)
}

/// The strength module's rates (Fortran twin) of one soil material over `pl`: ε̇, R, dτ/dt, De/Dt.
fn strength_rates(
    pl: &PairList,
    dwdx: &[f64],
    mass: &[f64],
    rho: &[f64],
    v: &[f64],
    mt: &MatTable,
    tau: &[f64],
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = mass.len();
    let mat = vec![0i32; n];
    let (mut eps, mut rot, mut dtau, mut de) =
        (vec![0.0; NSTR * n], vec![0.0; 3 * n], vec![0.0; NSTR * n], vec![0.0; n]);
    strength::Rates {
        dim: 2,
        nreal: n,
        pairs: pl,
        dwdx,
        mass,
        rho,
        v,
        mat: &mat,
        mt,
        tau,
        rinv: &[],
        eps: &mut eps,
        rot: &mut rot,
        dtau: &mut dtau,
        dedt: &mut de,
    }
    .run(F);
    (eps, rot, dtau, de)
}

#[test]
fn jaumann_rate_is_objective_under_rigid_rotation() {
    let omega = 250.0; // rad/s, counter-clockwise
    let (x, v, h, rho, mass) = lattice(9, 0.01, |px, py| (-omega * py, omega * px));
    let n = h.len();
    let (pl, _w, dwdx) = pairs_of(&x, &h);
    let mt = soil_table(63.58e6, 0.25, 200.0);
    let mut tau = vec![0.0; NSTR * n];
    for i in 0..n {
        tau[NSTR * i..NSTR * i + NSTR].copy_from_slice(&[2.0e5, -1.5e5, -0.5e5, 0.8e5, 0.0, 0.0]);
    }
    let (eps, rot, dtau, de) = strength_rates(&pl, &dwdx, &mass, &rho, &v, &mt, &tau);
    let c = n / 2; // the centre particle: a full, symmetric neighbourhood
    let e = &eps[NSTR * c..NSTR * c + NSTR];
    let r = rot[3 * c];
    // a rigid rotation strains nothing (the lattice sum is symmetric, so exactly zero up to rounding)
    for (q, eq) in e.iter().enumerate() {
        assert!(eq.abs() < 1e-9 * omega, "strain rate {q} = {eq} under rigid rotation");
    }
    // R_xy = (dvx/dy - dvy/dx)/2 = -omega, up to the lattice sum of the kernel gradient
    assert!((r + omega).abs() < 0.05 * omega, "R_xy = {r}, expected about -{omega}");
    // dtau/dt = tau R^T + R tau: hand-computed from the R the routine found
    let t = &tau[NSTR * c..NSTR * c + NSTR];
    let (txx, tyy, txy) = (t[0], t[1], t[3]);
    // R = [[0, r], [-r, 0]]: (R tau + tau R^T)_xx = 2 r txy, _yy = -2 r txy, _xy = r (tyy - txx)
    let d = &dtau[NSTR * c..NSTR * c + NSTR];
    assert!((d[0] - 2.0 * r * txy).abs() < 1e-6 * (r * txy).abs());
    assert!((d[1] + 2.0 * r * txy).abs() < 1e-6 * (r * txy).abs());
    assert!((d[3] - r * (tyy - txx)).abs() < 1e-6 * (r * (tyy - txx)).abs());
    assert!(d[2].abs() < 1e-9 * (r * txy).abs(), "tau_zz does not rotate in plane");
    // objectivity: the rate leaves the invariant tau:tau unchanged, d(tau:tau)/dt = 2 tau:dtau = 0
    let taudot = t[0] * d[0] + t[1] * d[1] + t[2] * d[2] + 2.0 * (t[3] * d[3] + t[4] * d[4] + t[5] * d[5]);
    let scale = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + 2.0 * t[3] * t[3]) * omega;
    assert!(taudot.abs() < 1e-9 * scale, "tau:dtau = {taudot} (scale {scale})");
    // and no deviatoric work is done by a rotation
    assert!(de[c].abs() < 1e-9 * scale / 1450.0);
}

#[test]
fn strength_rates_give_2g_times_deviatoric_strain_rate() {
    // pure shear v = (gamma_dot * y, 0): eps_xy = gamma_dot/2, so dtau_xy = 2 G eps_xy (tau = 0)
    let gd = 100.0;
    let (x, v, h, rho, mass) = lattice(9, 0.01, |_, py| (gd * py, 0.0));
    let n = h.len();
    let (pl, _w, dwdx) = pairs_of(&x, &h);
    let g = 63.58e6;
    let mt = soil_table(g, 0.25, 200.0);
    let tau = vec![0.0; NSTR * n];
    let (eps, _, dtau, _) = strength_rates(&pl, &dwdx, &mass, &rho, &v, &mt, &tau);
    let c = n / 2;
    let exy = eps[NSTR * c + 3];
    assert!((exy - 0.5 * gd).abs() < 0.05 * gd, "eps_xy = {exy}");
    assert!(
        (dtau[NSTR * c + 3] - 2.0 * g * exy).abs() <= 1e-12 * (2.0 * g * exy).abs(),
        "2G, not G (docs/theory.md §7)"
    );
    assert!(dtau[NSTR * c].abs() < 1e-6 * g * gd, "no normal stress rate in pure shear");
}

#[test]
fn penalty_pushes_different_materials_apart() {
    let mt = soil_table(0.0, 0.0, 0.0); // groups 0 and 1
    let (pbar, n1, n2) = (1.0e5, 12, 6);
    let h = [0.01, 0.012];
    let r = 0.008; // pe = (h_i + h_j)/(2 r) = 1.375 > 1
    let x = [0.1, 0.2, 0.1 + 0.6 * r, 0.2 - 0.8 * r]; // x_i - x_j = (-0.6 r, 0.8 r)
    let mass = [0.145, 0.2];
    let pl = PairList::new(vec![0], vec![1]);
    let coef = penalty::Coef { pbar, n1, n2 };
    let force = |x: &[f64], mat: &[i32], a: &mut [f64]| {
        penalty::Force { dim: 2, pairs: &pl, x, h: &h, mass: &mass, mat, mt: &mt, coef, dvdt: a }.run(F)
    };
    let mut a = [0.0; 4];
    force(&x, &[0, 1], &mut a);
    let pe: f64 = (h[0] + h[1]) / (2.0 * r);
    let f = pbar * (pe.powi(12) - pe.powi(6)) / (r * r); // PB = f x_ij
    let (dx, dy) = (-0.6 * r, 0.8 * r);
    let expect = [f * dx / mass[0], f * dy / mass[0], -f * dx / mass[1], -f * dy / mass[1]];
    for q in 0..4 {
        assert!((a[q] - expect[q]).abs() <= 1e-12 * expect[q].abs(), "component {q}: {} vs {}", a[q], expect[q]);
    }
    // repulsive: particle i is pushed along x_i - x_j
    assert!(a[0] * dx + a[1] * dy > 0.0);
    // momentum conserved
    assert!((mass[0] * a[0] + mass[1] * a[2]).abs() < 1e-9 * (mass[0] * a[0]).abs());
    // same group or pe <= 1: no force
    let mut b = [0.0; 4];
    force(&x, &[0, 0], &mut b);
    assert!(b.iter().all(|v| *v == 0.0));
    let far = [0.1, 0.2, 0.1, 0.2 + 0.02];
    force(&far, &[0, 1], &mut b);
    assert!(b.iter().all(|v| *v == 0.0), "pe < 1: the penalty is off (only repulsive)");
}

/// A unit box's bottom and left walls with inward normals.
fn corner_walls() -> Segments {
    Segments { seg: vec![0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0], endnode: vec![1, 1] }
}

#[test]
fn mirror_particles_reflect_position_velocity_and_stress() {
    let segs = corner_walls();
    // particle 0 near the bottom only, particle 1 near the corner, particle 2 far from both
    let x = [0.3, 0.004, 0.004, 0.003, 0.5, 0.5];
    let h = [0.01, 0.01, 0.01];
    let (mut gsrc, mut gseg) = (Vec::new(), Vec::new());
    boundary::MirrorMake { dim: 2, x: &x, h: &h, kappa: 2.0, segs: &segs, gsrc: &mut gsrc, gseg: &mut gseg }.run(F);
    let ng = gsrc.len();
    assert_eq!(ng, 4, "one mirror for particle 0, three (two walls and the corner) for particle 1");
    let n = 3;
    let nt = n + ng;
    let mut xa = vec![0.0; 2 * nt];
    xa[..6].copy_from_slice(&x);
    let mut v = vec![0.0; 2 * nt];
    v[..6].copy_from_slice(&[3.0, -2.0, -1.0, -4.0, 0.0, 0.0]);
    let mut tau = vec![0.0; NSTR * nt];
    tau[..NSTR].copy_from_slice(&[1.0, 2.0, -3.0, 5.0, 0.0, 0.0]);
    tau[NSTR..2 * NSTR].copy_from_slice(&[1.0, 2.0, -3.0, 5.0, 0.0, 0.0]);
    let (mut rho, mut p, mut c, mut e, mut hh, mut m) =
        (vec![1.0; nt], vec![7.0; nt], vec![1.0; nt], vec![1.0; nt], vec![0.01; nt], vec![1.0; nt]);
    let mut mat = vec![0i32; nt];
    let src = gsrc[..ng].to_vec();
    let sg = gseg[..2 * ng].to_vec();
    boundary::MirrorFill {
        dim: 2,
        n,
        gsrc: &src,
        gseg: &sg,
        segs: &segs,
        noslip: false,
        x: &mut xa,
        v: &mut v,
        rho: &mut rho,
        p: &mut p,
        c: &mut c,
        e: &mut e,
        h: &mut hh,
        mass: &mut m,
        mat: &mut mat,
        tau: &mut tau,
    }
    .run(F);
    let mut found: Vec<(i32, [f64; 2], [f64; 2], f64)> = (0..ng)
        .map(|g| {
            (
                src[g],
                [xa[2 * (n + g)], xa[2 * (n + g) + 1]],
                [v[2 * (n + g)], v[2 * (n + g) + 1]],
                tau[NSTR * (n + g) + 3],
            )
        })
        .collect();
    found.sort_by(|a, b| a.0.cmp(&b.0).then(a.1[0].total_cmp(&b.1[0])).then(a.1[1].total_cmp(&b.1[1])));
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15;
    // particle 0 mirrored in the bottom wall: y -> -y, vy -> -vy (free slip), tau_xy -> -tau_xy
    assert_eq!(found[0].0, 0);
    assert!(close(found[0].1, [0.3, -0.004]) && close(found[0].2, [3.0, 2.0]) && found[0].3 == -5.0);
    // particle 1: left wall image, bottom wall image, and the corner image (both reflected)
    let corner: Vec<_> = found[1..].to_vec();
    assert!(corner.iter().all(|g| g.0 == 1));
    assert!(close(corner[0].1, [-0.004, -0.003]) && close(corner[0].2, [1.0, 4.0]) && corner[0].3 == 5.0);
    assert!(close(corner[1].1, [-0.004, 0.003]) && close(corner[1].2, [1.0, -4.0]) && corner[1].3 == -5.0);
    assert!(close(corner[2].1, [0.004, -0.003]) && close(corner[2].2, [-1.0, 4.0]) && corner[2].3 == -5.0);
    // scalars are copied from the source
    assert!(p[n..].iter().all(|v| *v == 7.0));
    // no slip: the velocity of every mirror is minus its source's
    let mut v2 = vec![0.0; 2 * nt];
    v2[..6].copy_from_slice(&[3.0, -2.0, -1.0, -4.0, 0.0, 0.0]);
    let mut xb = xa.clone();
    boundary::MirrorFill {
        dim: 2,
        n,
        gsrc: &src,
        gseg: &sg,
        segs: &segs,
        noslip: true,
        x: &mut xb,
        v: &mut v2,
        rho: &mut rho,
        p: &mut p,
        c: &mut c,
        e: &mut e,
        h: &mut hh,
        mass: &mut m,
        mat: &mut mat,
        tau: &mut [],
    }
    .run(F);
    for g in 0..ng {
        let s = src[g] as usize;
        assert_eq!([v2[2 * (n + g)], v2[2 * (n + g) + 1]], [-v2[2 * s], -v2[2 * s + 1]]);
    }
}

#[test]
fn wall_force_repels_and_vanishes_beyond_r0() {
    let segs = Segments { seg: vec![0.0, 0.0, 1.0, 0.0, 0.0, 1.0], endnode: vec![1] };
    let (spacing, r0, d, n1, n2) = (0.0025, 0.005, 1.0e4, 12, 4);
    // particle right above a wall node at 0.5 (node k = 200), at height 0.004 < r0
    let x = [0.5, 0.004, 0.5, 0.02];
    let mut a = [0.0; 4];
    let coef = boundary::WallCoef { spacing, r0, d, n1, n2 };
    boundary::WallForce { dim: 2, x: &x, segs: &segs, coef, dvdt: &mut a }.run(F);
    // hand sum over the nodes within r0: k = 199, 200, 201 (dx = -0.0025, 0, 0.0025)
    let mut ey = 0.0;
    for k in [-1.0f64, 0.0, 1.0] {
        let (dx, dy): (f64, f64) = (-k * spacing, 0.004);
        let r2 = dx * dx + dy * dy;
        if r2 < r0 * r0 {
            let q = r0 / r2.sqrt();
            ey += d * (q.powi(12) - q.powi(4)) / r2 * dy;
        }
    }
    assert!(a[1] > 0.0, "pushed into the domain");
    assert!((a[1] - ey).abs() < 1e-9 * ey, "{} vs hand sum {ey}", a[1]);
    assert!(a[0].abs() < 1e-9 * ey, "symmetric nodes: no tangential force");
    assert_eq!(&a[2..], &[0.0, 0.0], "beyond r0: no force");
}

#[test]
fn programmed_burn_lights_at_distance_over_d() {
    let mut mpar = vec![0.0; 2 * NPAR];
    mpar[0] = 1630.0;
    mpar[6] = 6930.0; // D
    mpar[NPAR] = 1450.0;
    let mt = MatTable { mtype: vec![SPH_EOS_JWL as i32, SPH_EOS_SOIL as i32], mpar, group: vec![0, 1] };
    let x = [0.5, 0.97, 0.53, 0.97, 0.5, 0.5];
    let mat = [0, 0, 1];
    let mut tl = [0.0; 3];
    detonation::Light { dim: 2, x: &x, mat: &mat, mt: &mt, xdet: &[0.5, 0.97], nrm: None, sf: 1.0, tlight: &mut tl }
        .run(F);
    assert_eq!(tl[0], 0.0);
    assert!((tl[1] - 0.03 / 6930.0).abs() < 1e-18);
    assert_eq!(tl[2], 0.0, "only explosives are lit");
    // a lighting front at 0.95 D lights particle 1 later by 1/0.95
    let mut tl95 = [0.0; 3];
    detonation::Light { dim: 2, x: &x, mat: &mat, mt: &mt, xdet: &[0.5, 0.97], nrm: None, sf: 0.95, tlight: &mut tl95 }
        .run(F);
    assert!((tl95[1] - 0.03 / (0.95 * 6930.0)).abs() < 1e-18);
    let h = [0.01; 3];
    let mut lam = [0.0; 3];
    let burn = |mt: &MatTable, t: f64, rho: &[f64], width: f64, lam: &mut [f64]| {
        detonation::Burn { t, mat: &mat, mt, tlight: &tl, h: &h, rho, width, burn: lam }.run(F)
    };
    let rho0 = [1630.0, 1630.0, 1450.0];
    burn(&mt, 0.5 * 0.03 / 6930.0, &rho0, 0.0, &mut lam);
    assert_eq!(lam[..2], [1.0, 0.0], "the front has not reached particle 1 yet");
    burn(&mt, tl[1] + 0.5 * 0.01 / 6930.0, &rho0, 1.0, &mut lam);
    assert!((lam[1] - 0.5).abs() < 1e-12, "ramp of one h: half burnt half an h behind the front");
    // the beta burn (η_CJ = 1.3666): unlit but compressed halfway to the CJ density → λ = 0.5; then
    // expanded again, it keeps what it burnt; compressed beyond ρ_CJ, it has burnt completely
    let mut mtb = mt.clone();
    mtb.mpar[SPH_MP_ETA_CJ as usize - 1] = 1.3666;
    let eta_half = 1.0 / (1.0 - 0.5 * (1.0 - 1.0 / 1.3666));
    let mut lam = [0.0; 3];
    burn(&mtb, 0.0, &[1630.0, 1630.0 * eta_half, 1450.0], 1.0, &mut lam);
    assert!((lam[1] - 0.5).abs() < 1e-12, "beta burn halfway: {}", lam[1]);
    burn(&mtb, 0.0, &rho0, 1.0, &mut lam);
    assert!((lam[1] - 0.5).abs() < 1e-12, "the beta burn never un-burns");
    burn(&mtb, 0.0, &[1630.0, 2300.0, 1450.0], 1.0, &mut lam);
    assert_eq!(lam[1], 1.0, "beyond the CJ density: burnt");
    // the JWL pressure is scaled by the burn fraction
    let (mut p, mut c) = ([0.0; 1], [0.0; 1]);
    let jwl = {
        let mut m = vec![0.0; NPAR];
        m[..7].copy_from_slice(&[1630.0, 3.712e11, 3.21e9, 4.15, 0.95, 0.30, 6930.0]);
        m[7] = -f64::MAX;
        MatTable { mtype: vec![SPH_EOS_JWL as i32], mpar: m, group: vec![0] }
    };
    eos::Eval {
        mt: &jwl,
        mat: &[0],
        burn: &[0.25],
        rho_max: &mut [],
        rho: &[1630.0],
        e: &[4.29e6],
        p: &mut p,
        c: &mut c,
    }
    .run(F);
    let full = 8.376e9;
    assert!((p[0] / (0.25 * full) - 1.0).abs() < 5e-3, "p = {} = a quarter of the constant-volume burn", p[0]);
    // with an unreacted explosive (C = 2390 m/s, S = 2.05, Γ = 1, e_chem = 4.29 MJ/kg): unlit and
    // compressed to μ = 0.2 with e = e_chem + 1e5 J/kg, p = (1 − Γμ/2) p_H + Γ ρ (e − e_chem) with
    // p_H = a0 μ + b0 μ² + c0 μ³ (4-42…4-46 with the unreacted constants); a quarter burnt, the
    // mixture p = ¼ p_JWL + ¾ p_u
    let mut un = jwl.clone();
    un.mpar[SPH_MP_UNR_C as usize - 1..SPH_MP_ECHEM as usize].copy_from_slice(&[2390.0, 2.05, 1.0, 4.29e6]);
    let (rho, e, mu) = (1630.0 * 1.2, 4.29e6 + 1e5, 0.2);
    let a0 = 1630.0 * 2390.0 * 2390.0;
    let (b0, c0) = (a0 * (1.0 + 2.0 * 1.05), a0 * (2.0 * 1.05 + 3.0 * 1.05 * 1.05));
    let pu = (1.0 - 0.5 * mu) * (a0 * mu + b0 * mu * mu + c0 * mu * mu * mu) + rho * 1e5;
    let (mut p0, mut pj, mut pq) = ([0.0; 1], [0.0; 1], [0.0; 1]);
    let mut eval = |mt: &MatTable, lam: f64, p: &mut [f64]| {
        eos::Eval { mt, mat: &[0], burn: &[lam], rho_max: &mut [], rho: &[rho], e: &[e], p, c: &mut c }.run(F)
    };
    eval(&un, 0.0, &mut p0);
    assert!((p0[0] / pu - 1.0).abs() < 1e-12, "unreacted p = {} against {pu}", p0[0]);
    eval(&jwl, 1.0, &mut pj);
    eval(&un, 0.25, &mut pq);
    assert!((pq[0] / (0.25 * pj[0] + 0.75 * pu) - 1.0).abs() < 1e-12, "mixture p = {}", pq[0]);
}
