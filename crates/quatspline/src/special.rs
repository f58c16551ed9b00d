//! Singular ratios, each in one named helper with its Taylor branch stated.
//!
//! Every helper is exact to a few ulps on both sides of its switch point; the Python tests
//! compare them with mpmath at 50 digits just below and just above each switch
//! (`tests/test_special.py`). A lesson from scipy: a Taylor coefficient typo (1/12604 for
//! 1/1260) passed tests at rtol 1e-7, so ours are tested at 1e-15.

// fdlibm's kernel constants are kept digit for digit as published.
#![allow(clippy::excessive_precision)]

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
        sin_cos(x).0 / x
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

// ---- sin and cos ---------------------------------------------------------------------------
//
// The splines' hot loops spend most of their time in sin/cos of bounded angles. This is
// fdlibm's algorithm (Sun Microsystems, freely redistributable): Cody–Waite reduction by
// multiples of π/2 in three parts (exact for |k| < 2²⁰), then the minimax kernels
// __kernel_sin / __kernel_cos on [−π/4, π/4], each below one ulp. Inlined and branch-light,
// it is several times faster than a libm call and vectorises. Beyond |x| < 2¹⁹·π/2 it
// defers to libm. Tested against libm in `tests` below (≤ 1 ulp apart).

const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;

const S1: f64 = -1.666_666_666_666_663_243_48e-1;
const S2: f64 = 8.333_333_333_322_489_461_24e-3;
const S3: f64 = -1.984_126_982_985_794_931_34e-4;
const S4: f64 = 2.755_731_370_707_006_767_89e-6;
const S5: f64 = -2.505_076_025_340_686_341_95e-8;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-2;
const C2: f64 = -1.388_888_888_887_410_957_49e-3;
const C3: f64 = 2.480_158_728_947_672_941_78e-5;
const C4: f64 = -2.755_731_435_139_066_330_35e-7;
const C5: f64 = 2.087_572_321_298_174_827_90e-9;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// __kernel_sin's S1…S6 and __kernel_cos's C1…C6 (for the vector kernels).
pub(crate) const SIN_KERNEL: [f64; 6] = [S1, S2, S3, S4, S5, S6];
/// See [`SIN_KERNEL`].
pub(crate) const COS_KERNEL: [f64; 6] = [C1, C2, C3, C4, C5, C6];

#[inline(always)]
fn kernel_sin(x: f64) -> f64 {
    let z = x * x;
    let r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    x + x * z * (S1 + z * r)
}

#[inline(always)]
fn kernel_cos(x: f64) -> f64 {
    let z = x * x;
    let r = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * r)
}

/// (sin x, cos x), within one ulp of libm (fdlibm's kernels; see the note above).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() <= std::f64::consts::FRAC_PI_4 {
        return (kernel_sin(x), kernel_cos(x));
    }
    if x.is_nan() || x.abs() >= 823_549.6 {
        return x.sin_cos();
    }
    // round to nearest by the 1.5·2⁵² trick (f64::round is a libm call on baseline x86-64)
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let k = (x * INV_PIO2 + MAGIC) - MAGIC;
    let r = (x - k * PIO2_1) - k * PIO2_2 - k * PIO2_2T;
    let (s, c) = (kernel_sin(r), kernel_cos(r));
    match (k as i64) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

#[cfg(test)]
mod trig_tests {
    use super::sin_cos;

    fn ulps(a: f64, b: f64) -> f64 {
        let scale = b.abs().max(f64::MIN_POSITIVE);
        (a - b).abs() / (scale * f64::EPSILON)
    }

    #[test]
    fn sin_cos_within_one_ulp_of_libm() {
        let mut worst: f64 = 0.0;
        let mut x = -40.0;
        while x < 40.0 {
            let (s, c) = sin_cos(x);
            let (rs, rc) = x.sin_cos();
            // absolute comparison near zeros of sin/cos, ulps elsewhere
            for (a, b) in [(s, rs), (c, rc)] {
                if b.abs() > 1e-3 {
                    worst = worst.max(ulps(a, b));
                } else {
                    assert!((a - b).abs() < 2e-19 + 1e-16 * b.abs(), "{x}: {a} vs {b}");
                }
            }
            x += 0.000_731;
        }
        assert!(worst <= 1.0, "worst {worst} ulp");
        for x in [
            0.0,
            -0.0,
            1e-300,
            1e-8,
            std::f64::consts::FRAC_PI_4,
            std::f64::consts::FRAC_PI_2,
            std::f64::consts::PI,
            1e6,
            -1e7,
        ] {
            let (s, c) = sin_cos(x);
            let (rs, rc) = x.sin_cos();
            assert!((s - rs).abs() <= 2.3e-16 && (c - rc).abs() <= 2.3e-16, "{x}");
        }
        assert!(sin_cos(f64::NAN).0.is_nan());
    }
}
