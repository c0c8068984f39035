//! Distances between doubles in units in the last place: the measure of the dual run and of the
//! twins' parity tests.

/// Distance in units in the last place between two doubles (0 for +0 and −0).
pub fn ulp_diff(a: f64, b: f64) -> u64 {
    if a == b {
        return 0;
    }
    if a.is_nan() || b.is_nan() {
        return u64::MAX;
    }
    let key = |x: f64| -> i64 {
        let bits = x.to_bits() as i64;
        if bits < 0 { i64::MIN.wrapping_sub(bits) } else { bits }
    };
    (key(a) as i128 - key(b) as i128).unsigned_abs().min(u64::MAX as u128) as u64
}
