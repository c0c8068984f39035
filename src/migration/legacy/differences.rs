//! Comparing the particles a legacy set-up routine made with the case's own.

use super::*;

/// What differs, material by material, between the case's own particles `base` and those a
/// legacy set-up routine made: the particle count (when the totals agree: another total is
/// warned of on its own), and the integrals Σ m (mass: kg in 3D and RZ,
/// kg/m in 2D plane, kg/m² in 1D), Σ m/ρ (volume, m^dim), Σ m e (internal energy, J in 3D),
/// Σ m v (momentum) and the centre of mass
/// Σ m x / Σ m. Sums agree to a relative 10⁻⁵ (a routine's single-precision literals move them
/// by about 10⁻⁷) and the centres to a twentieth of the finest spacing. None when nothing
/// differs; else the first differences, named.
pub(crate) fn state_differences(case: &Case, base: &Initial, made: &Initial) -> Option<String> {
    let dim = case.dim.max(1);
    #[derive(Default)]
    struct Sums {
        n: usize,
        m: f64,
        vol: f64,
        me: f64,
        mv: [f64; 3],
        mvabs: f64,
        mx: [f64; 3],
    }
    let sums = |p: &Initial, mat: usize| {
        let mut s = Sums::default();
        for (k, _) in p.mat.iter().enumerate().filter(|(_, m)| **m as usize == mat) {
            let m = p.mass[k];
            s.n += 1;
            s.m += m;
            s.vol += m / p.rho[k];
            s.me += m * p.e[k];
            for d in 0..dim {
                s.mv[d] += m * p.v[dim * k + d];
                s.mvabs += (m * p.v[dim * k + d]).abs();
                s.mx[d] += m * p.x[dim * k + d];
            }
        }
        s
    };
    let off =
        |a: f64, b: f64, scale: f64| (a - b).abs() > 1e-5 * scale.max(f64::MIN_POSITIVE) || a.is_nan() != b.is_nan();
    let mut out: Vec<String> = Vec::new();
    for (mi, mc) in case.materials.iter().enumerate() {
        let (c, g) = (sums(base, mi), sums(made, mi));
        if c.n == 0 && g.n == 0 {
            continue;
        }
        let name = &mc.name;
        // (another total count is said by its own warning)
        if c.n != g.n && base.mat.len() == made.mat.len() {
            out.push(format!("{name}: {} particles against the case's {}", g.n, c.n));
        }
        if off(g.m, c.m, c.m.abs().max(g.m.abs())) {
            out.push(format!("{name}: mass {:.6e} against the case's {:.6e}", g.m, c.m));
        }
        if off(g.vol, c.vol, c.vol.abs().max(g.vol.abs())) {
            out.push(format!("{name}: volume Σm/ρ {:.6e} against the case's {:.6e}", g.vol, c.vol));
        }
        if off(g.me, c.me, c.me.abs().max(g.me.abs())) {
            out.push(format!("{name}: internal energy Σme {:.6e} against the case's {:.6e}", g.me, c.me));
        }
        if (0..dim).any(|d| off(g.mv[d], c.mv[d], c.mvabs.max(g.mvabs))) {
            out.push(format!(
                "{name}: momentum Σmv ({}) against the case's ({})",
                fmt_vec(&g.mv[..dim]),
                fmt_vec(&c.mv[..dim])
            ));
        }
        if c.m > 0.0 && g.m > 0.0 {
            let cc: Vec<f64> = (0..dim).map(|d| c.mx[d] / c.m).collect();
            let gc: Vec<f64> = (0..dim).map(|d| g.mx[d] / g.m).collect();
            if (0..dim).any(|d| (cc[d] - gc[d]).abs() > 0.05 * base.dx_min || cc[d].is_nan() != gc[d].is_nan()) {
                out.push(format!(
                    "{name}: centre of mass ({}) m against the case's ({}) m",
                    fmt_vec(&gc),
                    fmt_vec(&cc)
                ));
            }
        }
    }
    if out.is_empty() {
        return None;
    }
    let more = out.len().saturating_sub(3);
    out.truncate(3);
    let mut t = out.join("; ");
    if more > 0 {
        t.push_str(&format!(" (and {more} more)"));
    }
    Some(t)
}

/// A short vector of values for a message, `a, b, c` with 6 significant digits.
fn fmt_vec(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:.6e}")).collect::<Vec<_>>().join(", ")
}
