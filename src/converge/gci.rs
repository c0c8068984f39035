//! The discretisation error of one figure from runs at several spacings: the observed order,
//! the Richardson-extrapolated value and Roache's grid convergence index (GCI), by the procedure
//! of Celik et al. (2008), "Procedure for estimation and reporting of uncertainty due to
//! discretization in CFD applications", J. Fluids Eng. 130(7), 078001.
//!
//! With spacings h1 < h2 < h3 (fine, medium, coarse), values f1, f2, f3, ratios r21 = h2/h1 and
//! r32 = h3/h2, differences ε21 = f2 − f1 and ε32 = f3 − f2, s = sign(ε32/ε21):
//!
//! - the observed order p solves p = |ln|ε32/ε21| + q(p)| / ln r21, with
//!   q(p) = ln((r21^p − s)/(r32^p − s)) (q = 0 for a constant ratio);
//! - the extrapolated value f_ext = (r21^p f1 − f2)/(r21^p − 1);
//! - the fine-grid index GCI21 = F_s |(f1 − f2)/f1| / (r21^p − 1), F_s = 1.25 with three grids;
//!   the coarse-grid index GCI32 = F_s |(f2 − f3)/f2| / (r32^p − 1);
//! - the asymptotic ratio GCI32 / (r21^p GCI21), near 1 in the asymptotic range.
//!
//! With two grids the order is not observed: the formal order is assumed and F_s = 3.

use serde::Serialize;

/// Roache's safety factor with three or more grids.
pub const FS_THREE: f64 = 1.25;
/// Roache's safety factor with two grids (the order assumed, not observed).
pub const FS_TWO: f64 = 3.0;
/// The asymptotic ratio GCI32 / (r^p GCI21) counts as near 1 within this relative distance.
pub const ASYMPTOTIC_TOLERANCE: f64 = 0.1;

/// One figure's estimate.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Estimate {
    /// The observed order p (the assumed order with two grids).
    pub order: f64,
    /// Whether the order was observed (three grids) or assumed (two).
    pub order_observed: bool,
    /// The Richardson-extrapolated value (the figure's unit).
    pub extrapolated: f64,
    /// The fine-grid GCI21, a fraction of f1 (0.02 = 2 %).
    pub gci_fine: f64,
    /// The coarse-grid GCI32, a fraction of f2 (three grids only).
    pub gci_coarse: Option<f64>,
    /// GCI32 / (r21^p GCI21) (three grids only).
    pub asymptotic_ratio: Option<f64>,
    /// The safety factor used.
    pub safety_factor: f64,
    /// Why the runs are not in the asymptotic range (None: they are, as far as three grids show).
    pub not_asymptotic: Option<String>,
}

/// The estimate from three values `f` = [f1, f2, f3] at spacings `h` = [h1, h2, h3]
/// (fine to coarse). None when the spacings do not grow, or a value is not finite.
/// `to_zero`: the figure's exact value is 0 (an error norm); its asymptotic ratio is then left
/// out of the verdict. At a constant ratio r the asymptotic ratio equals
/// f1/f2, which is 1 only for a value that settles away from 0; an error norm that converges at
/// order p has f1/f2 = r^-p instead (0.5 at first order and r = 2).
pub fn three(h: [f64; 3], f: [f64; 3], to_zero: bool) -> Option<Estimate> {
    if !(h[0] > 0.0 && h[1] > h[0] && h[2] > h[1]) || f.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let (r21, r32) = (h[1] / h[0], h[2] / h[1]);
    let (e21, e32) = (f[1] - f[0], f[2] - f[1]);
    if e21 == 0.0 && e32 == 0.0 {
        return Some(Estimate {
            order: f64::NAN,
            order_observed: true,
            extrapolated: f[0],
            gci_fine: 0.0,
            gci_coarse: Some(0.0),
            asymptotic_ratio: None,
            safety_factor: FS_THREE,
            not_asymptotic: Some("the three values are equal: no error is seen at these spacings".into()),
        });
    }
    if e21 == 0.0 || e32 == 0.0 {
        return Some(undetermined(f[0], "two neighbouring levels give the same value: the order is undefined"));
    }
    let s = (e32 / e21).signum();
    let lr = (e32 / e21).abs().ln();
    // fixed-point iteration on p (Celik et al., eq. 3); q = 0 for a constant ratio
    let mut p = (lr / r21.ln()).abs();
    for _ in 0..200 {
        let q = ((r21.powf(p) - s) / (r32.powf(p) - s)).ln();
        let next = ((lr + q) / r21.ln()).abs();
        if !next.is_finite() {
            break;
        }
        let done = (next - p).abs() < 1e-12 * p.max(1.0);
        p = next;
        if done {
            break;
        }
    }
    let (rp21, rp32) = (r21.powf(p), r32.powf(p));
    let extrapolated = (rp21 * f[0] - f[1]) / (rp21 - 1.0);
    let gci_fine = FS_THREE * (e21 / f[0]).abs() / (rp21 - 1.0);
    let gci_coarse = FS_THREE * (e32 / f[1]).abs() / (rp32 - 1.0);
    let ratio = gci_coarse / (rp21 * gci_fine);
    let mut why = Vec::new();
    if s < 0.0 {
        why.push(format!(
            "the differences change sign (f3 - f2 = {e32:.4e}, f2 - f1 = {e21:.4e}): the values oscillate with refinement"
        ));
    }
    if e21.abs() > e32.abs() {
        why.push(format!(
            "the change grows with refinement (|f2 - f1| = {:.4e} > |f3 - f2| = {:.4e}): the values move away",
            e21.abs(),
            e32.abs()
        ));
    }
    if !p.is_finite() || !(0.5..=4.0).contains(&p) {
        why.push(format!("the observed order {p:.3} is outside 0.5 to 4"));
    }
    if !to_zero && !((1.0 - ASYMPTOTIC_TOLERANCE)..=(1.0 + ASYMPTOTIC_TOLERANCE)).contains(&ratio) {
        why.push(format!("GCI32 / (r^p GCI21) = {ratio:.3}, not within {:.0} % of 1", 100.0 * ASYMPTOTIC_TOLERANCE));
    }
    Some(Estimate {
        order: p,
        order_observed: true,
        extrapolated,
        gci_fine,
        gci_coarse: Some(gci_coarse),
        asymptotic_ratio: Some(ratio),
        safety_factor: FS_THREE,
        not_asymptotic: (!why.is_empty()).then(|| why.join("; ")),
    })
}

/// The estimate from two values `f` = [f1, f2] at spacings `h` = [h1, h2] (fine, coarse), with
/// the order `p_formal` assumed and F_s = 3. None when the spacings do not grow.
pub fn two(h: [f64; 2], f: [f64; 2], p_formal: f64) -> Option<Estimate> {
    if !(h[0] > 0.0 && h[1] > h[0]) || f.iter().any(|v| !v.is_finite()) || p_formal <= 0.0 {
        return None;
    }
    let rp = (h[1] / h[0]).powf(p_formal);
    Some(Estimate {
        order: p_formal,
        order_observed: false,
        extrapolated: (rp * f[0] - f[1]) / (rp - 1.0),
        gci_fine: FS_TWO * ((f[1] - f[0]) / f[0]).abs() / (rp - 1.0),
        gci_coarse: None,
        asymptotic_ratio: None,
        safety_factor: FS_TWO,
        not_asymptotic: Some(format!("two levels only: the order {p_formal} is assumed, not observed")),
    })
}

fn undetermined(f1: f64, why: &str) -> Estimate {
    Estimate {
        order: f64::NAN,
        order_observed: true,
        extrapolated: f64::NAN,
        gci_fine: f64::NAN,
        gci_coarse: None,
        asymptotic_ratio: None,
        safety_factor: FS_THREE,
        not_asymptotic: Some(format!("{why} (finest value {f1:.4e})")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Celik et al. (2008), Table 1: three grids of 18000, 8000 and 4500 cells in 2D
    /// (r21 = 1.5, r32 = 1.333), the reattachment length 6.063, 5.972, 5.863: p = 1.53,
    /// φ_ext = 6.1685, GCI_fine = 2.2 %.
    #[test]
    fn celik_table_1_reattachment_length() {
        let h = [1.0, 1.5, 2.0];
        let e = three(h, [6.063, 5.972, 5.863], false).unwrap();
        assert!((e.order - 1.53).abs() < 0.005, "{e:?}");
        assert!((e.extrapolated - 6.1685).abs() < 0.0005, "{e:?}");
        assert!((e.gci_fine - 0.022).abs() < 0.0005, "{e:?}");
    }

    /// Oscillating values by hand, a constant ratio 2 (q = 0): f = 1.0, 0.9, 1.1 at h = 1, 2, 4:
    /// ε21 = −0.1, ε32 = 0.2, p = ln 2 / ln 2 = 1, f_ext = (2·1.0 − 0.9)/1 = 1.1, GCI21 =
    /// 1.25·0.1/1 = 0.125; flagged: the differences change sign.
    #[test]
    fn oscillating_values_by_hand() {
        let e = three([1.0, 2.0, 4.0], [1.0, 0.9, 1.1], false).unwrap();
        assert!((e.order - 1.0).abs() < 1e-12, "{e:?}");
        assert!((e.extrapolated - 1.1).abs() < 1e-12, "{e:?}");
        assert!((e.gci_fine - 0.125).abs() < 1e-12, "{e:?}");
        assert!(e.not_asymptotic.as_deref().is_some_and(|w| w.contains("change sign")), "{e:?}");
    }

    /// A second-order figure by hand: f = 1 + h² at h = 1, 2, 4 (1 + 1, 1 + 4, 1 + 16): p = 2
    /// exactly, f_ext = (4·2 − 5)/3 = 1, GCI21 = 1.25·|3/2|/3 = 0.625, GCI32 = 1.25·(12/5)/3 =
    /// 1.0, the ratio 1.0/(4·0.625) = 0.4 (far from 1: the fine value's 2 is far from 1).
    #[test]
    fn a_second_order_figure_by_hand() {
        let e = three([1.0, 2.0, 4.0], [2.0, 5.0, 17.0], false).unwrap();
        assert!((e.order - 2.0).abs() < 1e-12, "{e:?}");
        assert!((e.extrapolated - 1.0).abs() < 1e-12, "{e:?}");
        assert!((e.gci_fine - 0.625).abs() < 1e-12, "{e:?}");
        assert!((e.gci_coarse.unwrap() - 1.0).abs() < 1e-12, "{e:?}");
        assert!((e.asymptotic_ratio.unwrap() - 0.4).abs() < 1e-12, "{e:?}");
        assert!(e.not_asymptotic.is_some());
        // the same error on a large value: f = 100 + h²: the ratio is f1/f2 = 101/104
        let e = three([1.0, 2.0, 4.0], [101.0, 104.0, 116.0], false).unwrap();
        assert!((e.asymptotic_ratio.unwrap() - 101.0 / 104.0).abs() < 1e-12, "{e:?}");
        assert!(e.not_asymptotic.is_none(), "{e:?}");
    }

    /// An error norm at first order, 0.0036, 0.0071, 0.0143 (fine to coarse; noh_1d's L1): the
    /// asymptotic ratio is f1/f2 ≈ 0.5, which marks it only when its exact value is not 0.
    #[test]
    fn an_error_norm_converging_to_zero_is_asymptotic() {
        let (h, f) = ([1.0, 2.0, 4.0], [0.0036, 0.0071, 0.0143]);
        let e = three(h, f, false).unwrap();
        assert!(e.not_asymptotic.as_deref().is_some_and(|w| w.contains("GCI32")), "{e:?}");
        let e = three(h, f, true).unwrap();
        assert!((e.order - 1.0).abs() < 0.05 && e.not_asymptotic.is_none(), "{e:?}");
        // the other criteria still apply to it: an error that grows is marked
        assert!(three(h, [0.0036, 0.0030, 0.0143], true).unwrap().not_asymptotic.is_some());
    }

    /// Two grids: f = 10 and 10.4 at h and 2h, first order assumed: f_ext = (2·10 − 10.4)/1 =
    /// 9.6, GCI = 3·0.04/1 = 0.12.
    #[test]
    fn two_grids_with_the_assumed_order() {
        let e = two([1.0, 2.0], [10.0, 10.4], 1.0).unwrap();
        assert!((e.extrapolated - 9.6).abs() < 1e-12);
        assert!((e.gci_fine - 0.12).abs() < 1e-12);
        assert_eq!(e.safety_factor, 3.0);
        assert!(three([2.0, 1.0, 4.0], [1.0, 2.0, 3.0], false).is_none());
    }
}
