//! A spherical blast in axisymmetric (RZ) geometry measured along its axis and along its equator.
//! The axis holds few particles, so an artefact there (a jet of rings on the axis) hides in the
//! all-angle profile of `verify`; these measures see it (docs/axis_results.md).

use crate::output::Frame;

/// Half-width of the axis and equator sectors (degrees).
const SECTOR_DEG: f64 = 10.0;

/// The shock radius (m) among the particles within 10° of the axis, the same within 10° of the
/// equator, and the densest particle within 3 `dx` of the axis (kg/m³). `r` is each particle's
/// distance from `centre` = (r, z) of the blast (m); `peak_radius(r, ρ)` is the caller's shock
/// radius of a set of particles (by the binned density peak).
pub(super) fn measures(
    f: &Frame,
    r: &[f64],
    centre: [f64; 2],
    dx: f64,
    peak_radius: &dyn Fn(&[f64], &[f64]) -> f64,
) -> [f64; 3] {
    let tan = SECTOR_DEG.to_radians().tan();
    let sector = |keep: &dyn Fn(f64, f64) -> bool| -> f64 {
        let (mut rr, mut rh) = (Vec::new(), Vec::new());
        for i in 0..r.len() {
            let (a, z) = ((f.x[i] - centre[0]).abs(), (f.y[i] - centre[1]).abs());
            if keep(a, z) {
                rr.push(r[i]);
                rh.push(f.rho[i]);
            }
        }
        peak_radius(&rr, &rh)
    };
    let axis = sector(&|a, z| a <= tan * z);
    let equator = sector(&|a, z| z <= tan * a);
    let near = (0..r.len()).filter(|&i| (f.x[i] - centre[0]).abs() < 3.0 * dx).map(|i| f.rho[i]);
    [axis, equator, near.fold(0.0, f64::max)]
}
