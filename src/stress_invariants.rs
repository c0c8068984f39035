//! The stress a reader looks for, per particle: the mean stress σ_m = (σ_xx + σ_yy + σ_zz)/3, the
//! von Mises stress σ_vm = √(3/2 s:s) (s = σ − σ_m I, the deviator) and the principal stresses
//! σ1 ≥ σ2 ≥ σ3 (the eigenvalues of σ, by nalgebra's symmetric eigen-decomposition). σ is the
//! total stress −p I + τ (Pa, tension positive). Outside the twins: no bitwise contract.
//! In RZ the components are (r, z, θ): the hoop stress is the third normal component.

use crate::modules::param::NSTR;
use nalgebra::{Matrix3, SymmetricEigen};

/// The dataset names, in the order of [`fields`]' vectors.
pub const NAMES: [&str; 5] = ["sigma_mean", "von_mises", "sigma_1", "sigma_2", "sigma_3"];

/// The invariants of one stress tensor (Pa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants {
    pub mean: f64,
    pub von_mises: f64,
    /// σ1 ≥ σ2 ≥ σ3.
    pub principal: [f64; 3],
}

impl Invariants {
    /// The values in the order of [`NAMES`] (Pa).
    pub fn values(&self) -> [f64; 5] {
        [self.mean, self.von_mises, self.principal[0], self.principal[1], self.principal[2]]
    }
}

/// The invariants of σ given as [xx, yy, zz, xy, xz, yz] (Pa).
pub fn of(s: [f64; 6]) -> Invariants {
    let [xx, yy, zz, xy, xz, yz] = s;
    let mean = (xx + yy + zz) / 3.0;
    let (dx, dy, dz) = (xx - mean, yy - mean, zz - mean);
    let j2 = 0.5 * (dx * dx + dy * dy + dz * dz) + xy * xy + xz * xz + yz * yz;
    let m = Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    let e = if m.iter().all(|v| v.is_finite()) {
        let ev = SymmetricEigen::new(m).eigenvalues;
        let mut e = [ev[0], ev[1], ev[2]];
        e.sort_by(|a, b| b.total_cmp(a));
        e
    } else {
        [f64::NAN; 3]
    };
    Invariants { mean, von_mises: (3.0 * j2).sqrt(), principal: e }
}

/// [`NAMES`]' fields of the first `n` particles from the deviatoric stress `tau` (NSTR per
/// particle: xx yy zz xy xz yz) and the pressure `p` (Pa); xz and yz count only in 3D.
pub fn fields(tau: &[f64], p: &[f64], n: usize, dim: usize) -> [Vec<f64>; 5] {
    let mut out: [Vec<f64>; 5] = std::array::from_fn(|_| Vec::with_capacity(n));
    for i in 0..n {
        let t = &tau[NSTR * i..NSTR * i + 6];
        let shear_out = if dim == 3 { [t[4], t[5]] } else { [0.0, 0.0] };
        let inv = of([t[0] - p[i], t[1] - p[i], t[2] - p[i], t[3], shear_out[0], shear_out[1]]);
        for (k, v) in inv.values().into_iter().enumerate() {
            out[k].push(v);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9 * b.abs().max(1.0)
    }

    /// Uniaxial tension σ_xx = 100 Pa: σ_m = 100/3, σ_vm = 100, principal 100, 0, 0.
    #[test]
    fn uniaxial() {
        let i = of([100.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!(close(i.mean, 100.0 / 3.0) && close(i.von_mises, 100.0), "{i:?}");
        assert!(close(i.principal[0], 100.0) && i.principal[1].abs() < 1e-9 && i.principal[2].abs() < 1e-9, "{i:?}");
    }

    /// Pure shear τ_xy = 50 Pa: σ_vm = √3·50, principal 50, 0, −50; a pressure of 1 MPa alone:
    /// σ_m = −1 MPa, σ_vm = 0.
    #[test]
    fn shear_and_pressure() {
        let i = of([0.0, 0.0, 0.0, 50.0, 0.0, 0.0]);
        assert!(close(i.von_mises, 3f64.sqrt() * 50.0), "{i:?}");
        assert!(close(i.principal[0], 50.0) && close(i.principal[2], -50.0), "{i:?}");
        let i = of([-1e6, -1e6, -1e6, 0.0, 0.0, 0.0]);
        assert!(close(i.mean, -1e6) && i.von_mises.abs() < 1e-6, "{i:?}");
    }

    /// The principal stresses keep the trace (3 σ_m) of a general tensor.
    #[test]
    fn principal_stresses_keep_the_trace() {
        let s = [3.0, -2.0, 5.0, 1.5, -0.7, 2.2];
        let i = of(s);
        assert!(close(i.principal.iter().sum::<f64>(), s[0] + s[1] + s[2]), "{i:?}");
        assert!(i.principal[0] >= i.principal[1] && i.principal[1] >= i.principal[2]);
    }
}
