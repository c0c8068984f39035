//! The set-up a verification problem is measured against (centre, ambient state, finest spacing,
//! released energy), and the Sedov blast's exact shock radius at the end time set against the
//! domain's edge: the warning `check` and `run` print when the front would reach an edge.

use crate::analysis::sedov::Sedov;
use crate::case::{AnalysisKind, Case, EosCfg};
use crate::error::Result;

/// What the problem needs from the case and its initial particles (the ambient state is read
/// by the measures of `verify`, which need `io`).
#[cfg_attr(not(feature = "io"), allow(dead_code))]
pub(crate) struct Setup {
    pub(crate) dim: usize,
    /// Geometry of the blast: 1 planar, 2 cylindrical, 3 spherical (3D, or 2D axisymmetric).
    pub(crate) j: u32,
    pub(crate) centre: [f64; 3],
    pub(crate) gamma: f64,
    /// Density and energy of the ambient gas (the region with the most particles).
    pub(crate) rho0: f64,
    pub(crate) e_amb: f64,
    /// Speed of the ambient gas (Noh, reflection), m/s.
    pub(crate) u0: f64,
    /// Finest initial spacing (m).
    pub(crate) dx: f64,
    /// Sedov: the released energy.
    pub(crate) energy: f64,
}

pub(crate) fn setup_of(case: &Case) -> Result<Setup> {
    let init = crate::setup::particles(case)?;
    let d = case.dim;
    let big = (0..init.counts.len()).max_by_key(|&r| init.counts[r]).unwrap_or(0);
    let first = init.region.iter().position(|&r| r as usize == big).unwrap_or(0);
    let (rho0, e_amb) = (init.rho[first], init.e[first]);
    let u0 = (0..d).map(|a| init.v[a + d * first] * init.v[a + d * first]).sum::<f64>().sqrt();
    let gamma = case
        .materials
        .iter()
        .find_map(|m| if let EosCfg::IdealGas { gamma, .. } = m.eos { Some(gamma) } else { None })
        .unwrap_or(1.4);
    let mut centre = [0.0; 3];
    if let Some(c) = &case.analysis.center_m {
        centre[..d].copy_from_slice(&c[..d]);
    }
    let energy = case.analysis.energy_j.unwrap_or_else(|| {
        mirror_factor(case, &centre) * (0..init.mass.len()).map(|i| init.mass[i] * (init.e[i] - e_amb)).sum::<f64>()
    });
    let j = if case.axisymmetric() { 3 } else { d as u32 };
    Ok(Setup { dim: d, j, centre, gamma, rho0, e_amb, u0, dx: init.dx_min, energy })
}

/// A Sedov case's exact shock radius at its end time and its finest initial spacing (m), from the
/// set-up the report measures against (the energy as the report takes it); None when the case
/// is no Sedov blast or the set-up fails.
pub(crate) fn sedov_end_radius(case: &Case) -> Option<(f64, f64)> {
    sedov_at_end(case).map(|(s, _, r)| (r, s.dx))
}

/// A Sedov case's set-up as the report takes it, its similarity solution and the exact shock
/// radius at the end time (m); None when the case is no Sedov blast or the set-up fails.
fn sedov_at_end(case: &Case) -> Option<(Setup, Sedov, f64)> {
    if case.analysis.kind != AnalysisKind::Sedov {
        return None;
    }
    let s = setup_of(case).ok()?;
    let sd = Sedov::new(s.j, s.gamma)?;
    let r = sd.radius(s.energy, s.rho0, case.time.end_s);
    Some((s, sd, r))
}

/// The particles' nearest edge from a point blast's centre, at t = 0: over the bounding box of
/// the initial positions `pos(i)` (n particles), the least distance from the centre to a side,
/// leaving out the sides within two spacings of the centre (a symmetry plane through it, the
/// axis of an RZ run: their images carry the blast on). The distance (m) and the side named
/// (`+x`, `-z`, ...); None when every side is such a plane.
pub(crate) fn nearest_edge(s: &Setup, n: usize, pos: &dyn Fn(usize) -> [f64; 3]) -> Option<(f64, String)> {
    if n == 0 {
        return None;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for i in 0..n {
        let q = pos(i);
        for k in 0..s.dim {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let axis = ["x", "y", "z"];
    (0..s.dim)
        .flat_map(|k| [(hi[k] - s.centre[k], format!("+{}", axis[k])), (s.centre[k] - lo[k], format!("-{}", axis[k]))])
        .filter(|(d, _)| d.is_finite() && *d > 2.0 * s.dx)
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// A point blast whose exact shock radius at time `t` comes within the kernel's reach (κ h0, h0
/// = `h_over_dx` Δx) of the particles' nearest edge (at t = 0, [`nearest_edge`]): the shock
/// then leaves the gas (or has left it) into the void beyond, and the measures no longer
/// compare with the Sedov solution, whose gas is unbounded. One line naming the radius, the
/// edge and the last time the blast stays clear of it; None otherwise or for no Sedov case.
pub(crate) fn sedov_edge_warning(case: &Case, t: f64, n: usize, pos: &dyn Fn(usize) -> [f64; 3]) -> Option<String> {
    if case.analysis.kind != AnalysisKind::Sedov {
        return None;
    }
    let s = setup_of(case).ok()?;
    let r = Sedov::new(s.j, s.gamma)?.radius(s.energy, s.rho0, t);
    edge_warning(case, &s, t, r, nearest_edge(&s, n, pos).as_ref())
}

/// [`sedov_edge_warning`] for a set-up, its exact radius `r` at `t` and its nearest edge.
pub(crate) fn edge_warning(case: &Case, s: &Setup, t: f64, r: f64, edge: Option<&(f64, String)>) -> Option<String> {
    let (edge, side) = (edge?.0, &edge?.1);
    let reach = case.sph.kernel.support() * case.sph.h_over_dx * s.dx;
    if !(r.is_finite() && r + reach > edge) {
        return None;
    }
    // R ∝ t^(2/(j+2)): the time at which R = edge − κ h0
    let clear = edge - reach;
    let t_ok = if clear > 0.0 {
        format!("{:.3e} s", t * (clear / r).powf(0.5 * (f64::from(s.j) + 2.0)))
    } else {
        "none".into()
    };
    Some(format!(
        "the point blast's exact shock radius at t = {t:.4e} s, R = {r:.4e} m, reaches within the kernel's reach ({reach:.3e} m) of the particles' edge {edge:.4e} m from the centre (side {side}): the shock leaves the gas there and the measures are not the Sedov solution's; enlarge the gas or end by {t_ok}"
    ))
}

/// What `blastsph check` says of a Sedov case before it runs: the energy, ambient density and γ
/// the report will measure against, ξ0, and the exact shock radius at the end in metres and in
/// spacings; None when the case is no Sedov blast or the set-up fails.
#[cfg(feature = "cli")]
pub(crate) fn sedov_check_line(case: &Case) -> Option<String> {
    let (s, sd, r) = sedov_at_end(case)?;
    let (geo, unit) = match (s.j, case.axisymmetric()) {
        (1, _) => ("planar", "J/m2"),
        (2, _) => ("cylindrical", "J/m"),
        (_, true) => ("spherical, RZ", "J"),
        _ => ("spherical", "J"),
    };
    let given =
        if case.analysis.energy_j.is_some() { "analysis.energy_j" } else { "the hot particles, mirrors counted" };
    Some(format!(
        "Sedov ({geo}): E = {:.6e} {unit} ({given}), rho0 = {:.6e} kg/m3, gamma = {}, xi0 = {:.5}: exact shock radius at the end ({:e} s) R = {:.5e} m = {:.1} spacings",
        s.energy,
        s.rho0,
        s.gamma,
        sd.xi0,
        case.time.end_s,
        r,
        r / s.dx
    ))
}

/// 2^k for the k mirror walls (symmetry planes) through the centre: a half, quarter or eighth of
/// a blast holds that fraction of its energy. The axis of an axisymmetric run is not a wall (its
/// rings already hold the whole revolution).
pub(crate) fn mirror_factor(case: &Case, c: &[f64; 3]) -> f64 {
    let d = case.dim;
    let mut f = 1.0;
    for w in case.walls.iter().filter(|w| w.kind.mirrors()) {
        let dist = match d {
            1 => (w.from_m[0] - c[0]).abs(),
            2 => {
                let (a, b) = ([w.from_m[0], w.from_m[1]], [w.to_m[0], w.to_m[1]]);
                let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
                ((ux * (c[1] - a[1]) - uy * (c[0] - a[0])) / ux.hypot(uy)).abs()
            }
            _ => {
                let [a, e, b] = crate::setup::corners(w);
                let u = [e[0] - a[0], e[1] - a[1], e[2] - a[2]];
                let v = [b[0] - e[0], b[1] - e[1], b[2] - e[2]];
                let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
                let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                ((0..3).map(|k| (c[k] - a[k]) * n[k]).sum::<f64>() / l).abs()
            }
        };
        if dist <= 1e-9 * (1.0 + c.iter().map(|v| v.abs()).fold(0.0, f64::max)) {
            f *= 2.0;
        }
    }
    f
}
