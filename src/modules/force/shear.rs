//! The physical viscosity on a sinusoidal shear flow v_x = U sin(k y) over a 2D lattice: in the
//! interior the heating must approach (η/ρ)(U k cos k y)² and the acceleration ν ∂²v_x/∂y² =
//! −(η/ρ) k² U sin(k y), both twins. Measured (h = 1.2 dx, cubic spline): 6.1 % at 20 spacings
//! per wavelength, 2.9 % at 40, the same for both quantities and both twins.

use super::Newtonian;
use crate::modules::Backend;
use crate::modules::testkit::*;

/// The largest relative errors (acceleration, heating) in the interior, both twins, with a
/// wavelength of `ppw` spacings on an n × n lattice.
fn errors(n: usize, ppw: f64) -> (f64, f64) {
    let (dx, rho0, eta0, u0) = (0.01, 1000.0, 1.0e-3, 1.0);
    let k = 2.0 * std::f64::consts::PI / (ppw * dx);
    let mut out = (0.0, 0.0);
    let nt = n * n;
    let mut x = Vec::with_capacity(2 * nt);
    let mut v = Vec::with_capacity(2 * nt);
    for iy in 0..n {
        for ix in 0..n {
            let y = iy as f64 * dx;
            x.extend([ix as f64 * dx, y]);
            v.extend([u0 * (k * y).sin(), 0.0]);
        }
    }
    let cl = Cloud {
        dim: 2,
        nreal: nt,
        nt,
        dx,
        x,
        v,
        h: vec![1.2 * dx; nt],
        rho: vec![rho0; nt],
        mass: vec![rho0 * dx * dx; nt],
        p: vec![0.0; nt],
        c: vec![0.0; nt],
        e: vec![0.0; nt],
        mat: vec![0; nt],
        tau: vec![],
    };
    let mut pl = search(Backend::Fortran, false, &cl, 2.0);
    pl.build_incidence(nt);
    let (_, dwdx) = kernel_values(&cl, &pl);
    let eta = vec![eta0; nt];
    for b in [Backend::Fortran, Backend::Rust] {
        let (mut dvdt, mut dedt) = (vec![0.0; 2 * nt], vec![0.0; nt]);
        let (mass, rho, v) = (&cl.mass, &cl.rho, &cl.v);
        run(Newtonian { dim: 2, pairs: &pl, dwdx: &dwdx, mass, rho, v, eta: &eta, dvdt: &mut dvdt, dedt: &mut dedt }, b);
        let (mut ea, mut ee, mut amax, mut emax) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        // the interior: beyond two supports (4.8 dx) of every edge
        for iy in 6..n - 6 {
            for ix in 6..n - 6 {
                let i = ix + n * iy;
                let y = iy as f64 * dx;
                let a = -(eta0 / rho0) * k * k * u0 * (k * y).sin();
                let g = u0 * k * (k * y).cos();
                let e = eta0 / rho0 * g * g;
                ea = ea.max((dvdt[2 * i] - a).abs());
                ee = ee.max((dedt[i] - e).abs());
                amax = amax.max(a.abs());
                emax = emax.max(e.abs());
                assert!(dvdt[2 * i + 1].abs() < 1e-9 * amax.max(1e-30) + 1e-18, "{b:?}: a_y = {}", dvdt[2 * i + 1]);
            }
        }
        eprintln!("{b:?} {ppw} spacings: acceleration error {:.4}, heating error {:.4}", ea / amax, ee / emax);
        out = (ea / amax, ee / emax);
    }
    out
}

#[test]
fn force_newtonian_sinusoidal_shear() {
    let (a20, e20) = errors(40, 20.0);
    let (a40, e40) = errors(60, 40.0);
    assert!(a20 < 0.1 && e20 < 0.1, "20 spacings: errors {a20}, {e20}");
    assert!(a40 < 0.6 * a20 && e40 < 0.6 * e20, "no convergence: {a20} -> {a40}, {e20} -> {e40}");
}
