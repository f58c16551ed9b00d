//! Singular ratios, each in one named helper with its Taylor branch stated.
//!
//! Every helper is exact to a few ulps on both sides of its switch point; the Python tests
//! compare them with mpmath at 50 digits just below and just above each switch
//! (`tests/test_special.py`). A lesson from scipy: a Taylor coefficient typo (1/12604 for
//! 1/1260) passed tests at rtol 1e-7, so ours are tested at 1e-15.

/// Below this |x|, [`sinc`] uses its Taylor series.
pub const SINC_SWITCH: f64 = 1e-3;
/// Below this s/|c|, [`atan2_over`] uses its Taylor series.
pub const ATAN2_OVER_SWITCH: f64 = 1e-3;

/// sin(x) / x, with the value 1 at x = 0.
///
/// Taylor branch for |x| < [`SINC_SWITCH`]: 1 − x²/6 + x⁴/120 − x⁶/5040 (truncation error below
/// x⁸/9! ≈ 3e-30 there).
#[inline]
pub fn sinc(x: f64) -> f64 {
    if x.abs() < SINC_SWITCH {
        let x2 = x * x;
        1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0))
    } else {
        x.sin() / x
    }
}

/// atan2(s, c) / s for s ≥ 0: the angle of a quaternion over the sine of that angle, used by
/// `log` (θ/|v| with θ = atan2(|v|, w)).
///
/// Taylor branch for c > 0 and s < [`ATAN2_OVER_SWITCH`]·c, with r = s/c:
/// (1/c)(1 − r²/3 + r⁴/5 − r⁶/7). At s = 0 and c ≤ 0 the ratio is infinite (θ = π, no axis);
/// callers handle that case before calling (see [`crate::Quat::log`]).
#[inline]
pub fn atan2_over(s: f64, c: f64) -> f64 {
    if c > 0.0 && s < ATAN2_OVER_SWITCH * c {
        let r = s / c;
        let r2 = r * r;
        (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0 - r2 / 7.0))) / c
    } else {
        s.atan2(c) / s
    }
}

/// sin(a·x) / sin(x) for x ∈ [0, π), the slerp weight; equals a at x = 0.
///
/// Written as a · sinc(a x) / sinc(x), so it inherits the Taylor branch of [`sinc`].
#[inline]
pub fn sin_ratio(a: f64, x: f64) -> f64 {
    a * sinc(a * x) / sinc(x)
}

/// Looks a helper up by name (for the binding's test hook and diagnostics).
pub fn by_name(name: &str) -> Option<fn(f64, f64) -> f64> {
    match name {
        "sinc" => Some(|x, _| sinc(x)),
        "atan2_over" => Some(atan2_over),
        "sin_ratio" => Some(sin_ratio),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinc_is_continuous_across_its_switch() {
        let below = sinc(SINC_SWITCH * (1.0 - 1e-12));
        let above = sinc(SINC_SWITCH * (1.0 + 1e-12));
        assert!((below - above).abs() < 1e-15);
        assert_eq!(sinc(0.0), 1.0);
    }

    #[test]
    fn atan2_over_limits() {
        assert_eq!(atan2_over(0.0, 1.0), 1.0);
        assert!((atan2_over(0.0, 2.0) - 0.5).abs() < 1e-16);
        let s = ATAN2_OVER_SWITCH;
        assert!((atan2_over(s * (1.0 - 1e-12), 1.0) - atan2_over(s * (1.0 + 1e-12), 1.0)).abs() < 1e-15);
    }

    #[test]
    fn sin_ratio_at_zero_is_a() {
        assert_eq!(sin_ratio(0.25, 0.0), 0.25);
        let x = 0.7;
        assert!((sin_ratio(0.25, x) - (0.25f64 * x).sin() / x.sin()).abs() < 1e-15);
    }
}
