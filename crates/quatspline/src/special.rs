//! Singular ratios, each in one named helper with its switch and series stated.
//!
//! Every ratio of the crate that is 0/0 (or ∞·0) somewhere lives here, once; callers use the
//! helper. Each is listed in [`by_name`] (the table the Python binding's test hook
//! `_core.special_fn(name, arr)` reads), and `tests/test_special.py` compares every entry
//! with mpmath at 50 digits just below and just above its switch (a test there fails when a
//! ratio is added here without a test). A lesson from scipy: a Taylor coefficient typo
//! (1/12604 for 1/1260) passed tests at rtol 1e-7, so the series are tested at ~1e-15.
//!
//! | name | ratio | switch | below the switch |
//! |---|---|---|---|
//! | `sinc` | sin x / x | [`SINC_SWITCH`] | Taylor, 4 terms |
//! | `atan2_over` | atan2(s, c) / s | [`ATAN2_OVER_SWITCH`] (s/c) | Taylor in s/c, 4 terms |
//! | `sin_ratio` | sin(a x) / sin x | via `sinc` | a·sinc(a x)/sinc(x) |
//! | `one_minus_cos_over_sq` | (1 − cos x)/x² | [`KIN_SWITCH`] | Taylor, 10 terms |
//! | `x_minus_sin_over_cube` | (x − sin x)/x³ | [`KIN_SWITCH`] | Taylor, 10 terms |
//! | `one_minus_half_cot_over_sq` | (1 − (x/2)cot(x/2))/x² | [`HALF_COT_SQ_SWITCH`] | Bernoulli series, 7 terms |
//! | `half_cot` | (x/2)cot(x/2) | [`HALF_COT_SWITCH`] | Taylor, 4 terms |
//! | `one_minus_half_cot_over_sq_fit` | the same, as the fit computes it | [`HALF_COT_SWITCH`] | Taylor, 4 terms |
//! | `one_minus_sqrt_half_cot_over_sq` | (1 − √((x/2)cot(x/2)))/x², of x² | [`HALF_COT_SWITCH`] | Taylor, 3 terms |
//! | `accel_k1` | (−x sin x − 2(cos x − 1))/x⁴ | [`KIN_SWITCH`] | Taylor, 10 terms |
//! | `accel_k2` | (−2x + 3 sin x − x cos x)/x⁵ | [`KIN_SWITCH`] | Taylor, 10 terms |
//! | `cos_sqrt`, `sinc_sqrt` | n-th derivative of cos√x, sin√x/√x | [`CS_SERIES`] | Taylor tables, 12 terms |
//! | `theta_over_sin` | n-th derivative in w = cos θ of θ/sin θ | [`G_SERIES`] (1 − w) | series in 1 − w, 20 terms |
//! | `sinc_jet` | n-th derivative of sin x / x through jets | [`SINC_JET_SWITCH`] | Taylor, 5 terms |
//! | `one_minus_cos_ba_over_a`, `b_minus_sin_ba_over_a` | (1 − cos(ba))/a, b − sin(ba)/a | [`SCALED_JR_SWITCH`] (a) | Taylor, 3 terms |

// fdlibm's kernel constants are kept digit for digit as published.
#![allow(clippy::excessive_precision)]

use crate::jet::Jet;

/// Below this |x|, [`sinc`] uses its Taylor series.
pub const SINC_SWITCH: f64 = 1e-3;
/// Below this s/|c|, [`atan2_over`] uses its Taylor series.
pub const ATAN2_OVER_SWITCH: f64 = 1e-3;
/// Below this x, the ratios of the rotation-vector kinematics ([`one_minus_cos_over_sq`],
/// [`x_minus_sin_over_cube`], [`accel_k1`], [`accel_k2`]) use their Taylor series.
pub const KIN_SWITCH: f64 = 0.5;
/// Below this x, [`one_minus_half_cot_over_sq`] uses its Bernoulli series.
pub const HALF_COT_SQ_SWITCH: f64 = 0.3;
/// Below this x, [`half_cot`], [`one_minus_half_cot_over_sq_fit`] and
/// [`one_minus_sqrt_half_cot_over_sq`] use their series.
pub const HALF_COT_SWITCH: f64 = 0.1;
/// Below this |x|, [`sinc_jet`] uses its Taylor series.
pub const SINC_JET_SWITCH: f64 = 1e-2;
/// Below this a, [`scaled_jr_coefficients`] uses its Taylor series.
pub const SCALED_JR_SWITCH: f64 = 0.02;

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
/// `log` (θ/|v| with θ = atan2(|v|, w)); at c = cos θ, s = sin θ this is θ / sin θ.
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

/// Σ_{m<10} coef(m) x2^m: the truncated even series of the rotation-vector kinematics ratios
/// (each below its switch; the coefficients are derived in the doc of each).
fn series(x2: f64, coef: impl Fn(usize) -> f64) -> f64 {
    let mut acc = 0.0;
    let mut p = 1.0;
    for m in 0..10 {
        acc += coef(m) * p;
        p *= x2;
    }
    acc
}

fn fact(n: usize) -> f64 {
    (1..=n).map(|v| v as f64).product()
}

fn alt(m: usize) -> f64 {
    if m.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

/// (1 − cos x)/x² for x ≥ 0; ½ at x = 0.
///
/// Below [`KIN_SWITCH`]: Σ_{m<10} (−1)^m x^(2m)/(2m+2)! (truncation below x²⁰/22! ≈ 1e-27).
/// Above: the closed form (1 − cos x)/x².
pub fn one_minus_cos_over_sq(x: f64) -> f64 {
    if x < KIN_SWITCH {
        series(x * x, |m| alt(m) / fact(2 * m + 2))
    } else {
        (1.0 - x.cos()) / (x * x)
    }
}

/// (x − sin x)/x³ for x ≥ 0; 1/6 at x = 0.
///
/// Below [`KIN_SWITCH`]: Σ_{m<10} (−1)^m x^(2m)/(2m+3)!. Above: the closed form.
pub fn x_minus_sin_over_cube(x: f64) -> f64 {
    if x < KIN_SWITCH {
        series(x * x, |m| alt(m) / fact(2 * m + 3))
    } else {
        (x - x.sin()) / (x * x * x)
    }
}

/// (1 − (x/2) cot(x/2))/x² = 1/x² − (1 + cos x)/(2x sin x) for x ∈ [0, 2π); 1/12 at x = 0.
/// The coefficient of [ρ]×² in A(ρ) = J_r⁻¹(ρ) (see [`crate::kinematics`]).
///
/// Below [`HALF_COT_SQ_SWITCH`]: −Σ_{n=1..7} (−1)^n B₂ₙ x^(2n−2)/(2n)! (Bernoulli numbers
/// B₂ … B₁₄; = 1/12 + x²/720 + x⁴/30240 + …, truncation below 2e-20 relative there).
/// Above: (1 − (x/2)/tan(x/2))/x².
pub fn one_minus_half_cot_over_sq(x: f64) -> f64 {
    if x < HALF_COT_SQ_SWITCH {
        const B: [f64; 7] =
            [1.0 / 6.0, -1.0 / 30.0, 1.0 / 42.0, -1.0 / 30.0, 5.0 / 66.0, -691.0 / 2730.0, 7.0 / 6.0];
        let x2 = x * x;
        let mut acc = 0.0;
        let mut p = 1.0;
        for (k, b) in B.iter().enumerate() {
            let n = k + 1;
            acc -= alt(n) * b * p / fact(2 * n);
            p *= x2;
        }
        acc
    } else {
        (1.0 - 0.5 * x / (0.5 * x).tan()) / (x * x)
    }
}

/// (x/2)·cot(x/2) for x ∈ [0, π]: 1 at x = 0, 0 at x = π (clamped at 0 against rounding).
///
/// Below [`HALF_COT_SWITCH`]: 1 − x²/12 − x⁴/720 − x⁶/30240 (the next term, x⁸/1209600, is
/// below 8.3e-15 there). Above: h cos h / sin h with h = x/2.
pub fn half_cot(x: f64) -> f64 {
    if x < HALF_COT_SWITCH {
        let t2 = x * x;
        1.0 - t2 * (1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 / 30240.0))
    } else {
        let h = 0.5 * x;
        (h * h.cos() / h.sin()).max(0.0)
    }
}

/// (1 − √f)/x² with f = [`half_cot`](x), x ∈ [0, π], taking x² (the squared norm the caller
/// has); 1/24 at x = 0: the coefficient of r rᵀ in the square root of the squared-distance
/// Hessian (`fit::so3::dist_hess_sqrt`).
///
/// Below x < [`HALF_COT_SWITCH`]: ((1 − f)/x²)/(1 + √f) with (1 − f)/x² by its first three
/// terms 1/12 + x²/720 + x⁴/30240 (truncation below x⁶/1209600, 1e-11 relative at the switch;
/// kept so that fits stay bit-identical). Above: (1 − √f)/x².
pub fn one_minus_sqrt_half_cot_over_sq(x2: f64) -> f64 {
    let g = half_cot(x2.sqrt()).sqrt();
    if x2.sqrt() < HALF_COT_SWITCH {
        (1.0 / 12.0 + x2 * (1.0 / 720.0 + x2 / 30240.0)) / (1.0 + g)
    } else {
        (1.0 - g) / x2
    }
}

/// [`one_minus_half_cot_over_sq`] as the fit computes it (the coefficient of [φ]×² in the fit's
/// J_r⁻¹, `fit::so3::jr_inv`): below x < [`HALF_COT_SWITCH`] the four terms 1/12 + x²/720 +
/// x⁴/30240 + x⁶/1209600 (next term below 2.5e-15 relative there), above the closed form
/// 1/x² − (1 + cos x)/(2x sin x) (which loses up to ~1e-13 relative to cancellation just above
/// the switch). Kept apart from [`one_minus_half_cot_over_sq`] only so that fits stay
/// bit-identical: the fit's λ search amplifies a change in these last bits.
pub fn one_minus_half_cot_over_sq_fit(x: f64) -> f64 {
    if x < HALF_COT_SWITCH {
        let t2 = x * x;
        1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0 + t2 / 1_209_600.0))
    } else {
        let (s, c) = x.sin_cos();
        1.0 / (x * x) - (1.0 + c) / (2.0 * x * s)
    }
}

/// (−x sin x − 2(cos x − 1))/x⁴ for x ≥ 0; 1/12 at x = 0: k₁ of the quadratic term of the
/// angular acceleration in the rotation-vector rate ([`crate::kinematics::accel_nonlinear`]).
///
/// Below [`KIN_SWITCH`]: Σ_{m<10} (−1)^m (2m+2) x^(2m)/(2m+4)!. Above: the closed form.
pub fn accel_k1(x: f64) -> f64 {
    if x < KIN_SWITCH {
        series(x * x, |m| alt(m) * (2 * m + 2) as f64 / fact(2 * m + 4))
    } else {
        (-x * x.sin() - 2.0 * (x.cos() - 1.0)) / x.powi(4)
    }
}

/// (−2x + 3 sin x − x cos x)/x⁵ for x ≥ 0; −1/60 at x = 0: k₂ of
/// [`crate::kinematics::accel_nonlinear`].
///
/// Below [`KIN_SWITCH`]: Σ_{m<10} (−1)^(m+1) (2m+2) x^(2m)/(2m+5)! (scipy has 1/12604 for the
/// x² coefficient 1/1260). Above: the closed form.
pub fn accel_k2(x: f64) -> f64 {
    if x < KIN_SWITCH {
        series(x * x, |m| -alt(m) * (2 * m + 2) as f64 / fact(2 * m + 5))
    } else {
        (-2.0 * x + 3.0 * x.sin() - x * x.cos()) / x.powi(5)
    }
}

/// The largest derivative count of the derivative tables below (value and five derivatives).
const MAXN: usize = 6;

/// The first N of six derivative values.
#[inline(always)]
fn take<const N: usize>(d: [f64; MAXN]) -> [f64; N] {
    std::array::from_fn(|k| d[k])
}

/// Below this x = |u|², C and S take their derivatives from series.
pub const CS_SERIES: f64 = 0.5;

/// Derivatives 0..5 of C(x) = cos√x and S(x) = sin√x/√x at x ≥ 0 (values exact by libm).
/// Closed forms: C^(n) = −S^(n−1)/2, S^(n) = (C^(n−1) − (2n − 1) S^(n−1))/(2x).
pub(crate) fn cos_sinc_sqrt<const N: usize>(x: f64) -> ([f64; N], [f64; N]) {
    let r = x.sqrt();
    let c0 = sin_cos(r).1;
    let s0 = sinc(r);
    let (mut c, mut s) = ([0.0; MAXN], [0.0; MAXN]);
    c[0] = c0;
    s[0] = s0;
    if N == 1 {
        return (take(c), take(s));
    }
    if x < CS_SERIES {
        // S^(n)(x) = Σ_{k≥n} (−1)^k k!/(k−n)! x^(k−n)/(2k+1)!, C likewise with (2k)!:
        // coefficient tables CS_TABLE[n − 1][m] for k = n + m.
        for n in 1..N {
            let (tc, ts) = (&CS_TABLE.0[n - 1], &CS_TABLE.1[n - 1]);
            let (mut sc, mut ss) = (0.0, 0.0);
            for m in (0..CS_TERMS).rev() {
                sc = sc * x + tc[m];
                ss = ss * x + ts[m];
            }
            c[n] = sc;
            s[n] = ss;
        }
    } else {
        for n in 1..N {
            s[n] = (c[n - 1] - (2 * n - 1) as f64 * s[n - 1]) / (2.0 * x);
            c[n] = -0.5 * s[n - 1];
        }
    }
    (take(c), take(s))
}

pub(crate) const CS_TERMS: usize = 12;

/// Series coefficients of C^(n) and S^(n), n = 1..5 (computed once, at compile time).
pub(crate) const CS_TABLE: ([[f64; CS_TERMS]; 5], [[f64; CS_TERMS]; 5]) = {
    let mut c = [[0.0; CS_TERMS]; 5];
    let mut s = [[0.0; CS_TERMS]; 5];
    let mut n = 1;
    while n <= 5 {
        let mut m = 0;
        while m < CS_TERMS {
            let k = n + m;
            let falling = const_falling(k, n);
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            c[n - 1][m] = sign * falling / const_factorial(2 * k);
            s[n - 1][m] = sign * falling / const_factorial(2 * k + 1);
            m += 1;
        }
        n += 1;
    }
    (c, s)
};

/// k!/(k−n)! = (k−n+1)(k−n+2)…k, the n-th derivative's factor of x^k.
const fn const_falling(k: usize, n: usize) -> f64 {
    let mut f = 1.0;
    let mut v = k + 1 - n;
    while v <= k {
        f *= v as f64;
        v += 1;
    }
    f
}

const fn const_factorial(n: usize) -> f64 {
    let mut f = 1.0;
    let mut v = 2;
    while v <= n {
        f *= v as f64;
        v += 1;
    }
    f
}

/// Below this y = 1 − w, g(w) = θ/sin θ takes its derivatives from its series.
pub const G_SERIES: f64 = 0.05;

const G_TERMS: usize = 20;

/// a_k = a_{k−1} k/(2k+1), a₀ = 1, times k!/(k−n)!, for n = 1..5 and k = n + m.
const G_TABLE: [[f64; G_TERMS]; 5] = {
    let mut a = [0.0; G_TERMS + 5];
    a[0] = 1.0;
    let mut k = 1;
    while k < G_TERMS + 5 {
        a[k] = a[k - 1] * k as f64 / (2 * k + 1) as f64;
        k += 1;
    }
    let mut t = [[0.0; G_TERMS]; 5];
    let mut n = 1;
    while n <= 5 {
        let mut m = 0;
        while m < G_TERMS {
            let k = n + m;
            t[n - 1][m] = const_falling(k, n) * a[k];
            m += 1;
        }
        n += 1;
    }
    t
};

/// Derivatives 0..5 in w of g(w) = θ/sin θ (w = cos θ) for a unit quaternion with scalar
/// part `w` and vector norm `s` = sin θ. Closed form (differentiating (1−w²)g' = wg − 1):
/// (1−w²)g^(n) = (2n − 1) w g^(n−1) + (n − 1)² g^(n−2).
pub(crate) fn theta_over_sin<const N: usize>(w: f64, s: f64) -> [f64; N] {
    let g0 = if s == 0.0 && w > 0.0 { 1.0 / w } else { atan2_over(s, w) };
    let mut g = [0.0; MAXN];
    g[0] = g0;
    if N == 1 {
        return take(g);
    }
    let y = if w > 0.0 { s * s / (1.0 + w) } else { 1.0 - w };
    if y < G_SERIES {
        // g^(n)(w) = (−1)^n Σ_{k≥n} k!/(k−n)! a_k y^(k−n): tables G_TABLE[n − 1][m], k = n + m.
        for (n, gn) in g.iter_mut().enumerate().take(N).skip(1) {
            let t = &G_TABLE[n - 1];
            let mut acc = 0.0;
            for m in (0..G_TERMS).rev() {
                acc = acc * y + t[m];
            }
            *gn = if n % 2 == 0 { acc } else { -acc };
        }
    } else {
        let s2 = s * s;
        g[1] = (w * g0 - 1.0) / s2;
        for n in 2..N {
            let m = (n - 1) as f64;
            g[n] = ((2 * n - 1) as f64 * w * g[n - 1] + m * m * g[n - 2]) / s2;
        }
    }
    take(g)
}

/// sin(x)/x of a jet (its value and time derivatives), for the screw powers of `se3`.
///
/// Below |x| < [`SINC_JET_SWITCH`]: Σ_{m<5} (−1)^m x^(2m)/(2m+1)! composed on the jet x²
/// (truncation below x¹⁰/11! ≈ 3e-28). Above: sin(x) · x⁻¹ on jets.
#[inline]
pub fn sinc_jet<const N: usize>(x: Jet<N>) -> Jet<N> {
    if x.0[0].abs() < SINC_JET_SWITCH {
        let x2 = x * x;
        let c = [1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362_880.0];
        Jet::poly(&c, x2)
    } else {
        x.sin_cos().0 * x.recip()
    }
}

/// ((1 − cos(b a))/a, b − sin(b a)/a) for a ≥ 0 and a jet b: the coefficients of [n]× and
/// [n]×² in b·J_r(b a n) (`fit::model`), both 0 at a = 0.
///
/// Below a < [`SCALED_JR_SWITCH`]: the first three terms of Σ (−1)^m b^(2m+2) a^(2m+1)/(2m+2)!
/// and Σ (−1)^m b^(2m+3) a^(2m+2)/(2m+3)! (truncation below b⁸a⁷/8! and b⁹a⁸/9!, i.e. below
/// 3.2e-15 and 1.1e-15 relative at b ≤ 1). Above: the closed forms with 1/a (cancellation
/// costs up to ~3e-12 and ~2e-11 relative just above the switch).
#[inline(always)]
pub fn scaled_jr_coefficients<const N: usize>(b: Jet<N>, a: f64) -> (Jet<N>, Jet<N>) {
    if a < SCALED_JR_SWITCH {
        let b2 = b * b;
        let a2 = a * a;
        let f1 = b2 * (0.5 * a) - b2 * b2 * (a * a2 / 24.0) + b2 * b2 * b2 * (a * a2 * a2 / 720.0);
        let b3 = b2 * b;
        let f2 = b3 * (a2 / 6.0) - b3 * b2 * (a2 * a2 / 120.0) + b3 * b2 * b2 * (a2 * a2 * a2 / 5040.0);
        (f1, f2)
    } else {
        let (sn, cs) = (b * a).sin_cos();
        ((-cs + 1.0) * (1.0 / a), b - sn * (1.0 / a))
    }
}

/// One helper of [`TABLE`]: two numbers in, one out.
pub type Helper = fn(f64, f64) -> f64;

/// The n of a derivative-table entry (its second number).
fn nth(n: f64) -> usize {
    (n as usize).min(MAXN - 1)
}

/// Every helper by name (for the binding's test hook `_core.special_fn` and diagnostics;
/// `tests/test_special.py` reads this list). Each takes two numbers (x, y): one-argument ratios
/// ignore y; `atan2_over` is (s, c), `sin_ratio` is (a, x); `one_minus_sqrt_half_cot_over_sq`
/// takes x²; the derivative tables are (x, n) → the n-th derivative (n = 0 … 5);
/// `theta_over_sin` is (w, n) with sin θ = √((1 − w)(1 + w)); the scaled-J_r coefficients are
/// (b, a).
pub const TABLE: [(&str, Helper); 17] = [
    ("sinc", |x, _| sinc(x)),
    ("atan2_over", atan2_over),
    ("sin_ratio", sin_ratio),
    ("one_minus_cos_over_sq", |x, _| one_minus_cos_over_sq(x)),
    ("x_minus_sin_over_cube", |x, _| x_minus_sin_over_cube(x)),
    ("one_minus_half_cot_over_sq", |x, _| one_minus_half_cot_over_sq(x)),
    ("half_cot", |x, _| half_cot(x)),
    ("one_minus_sqrt_half_cot_over_sq", |x2, _| one_minus_sqrt_half_cot_over_sq(x2)),
    ("one_minus_half_cot_over_sq_fit", |x, _| one_minus_half_cot_over_sq_fit(x)),
    ("accel_k1", |x, _| accel_k1(x)),
    ("accel_k2", |x, _| accel_k2(x)),
    ("cos_sqrt", |x, n| cos_sinc_sqrt::<MAXN>(x).0[nth(n)]),
    ("sinc_sqrt", |x, n| cos_sinc_sqrt::<MAXN>(x).1[nth(n)]),
    ("theta_over_sin", |w, n| theta_over_sin::<MAXN>(w, ((1.0 - w) * (1.0 + w)).sqrt())[nth(n)]),
    ("sinc_jet", |x, n| sinc_jet(Jet::<MAXN>::variable(x, 1.0)).derivative(nth(n))),
    ("one_minus_cos_ba_over_a", |b, a| scaled_jr_coefficients(Jet::<1>::constant(b), a).0.value()),
    ("b_minus_sin_ba_over_a", |b, a| scaled_jr_coefficients(Jet::<1>::constant(b), a).1.value()),
];

/// Looks a helper of [`TABLE`] up by name.
pub fn by_name(name: &str) -> Option<Helper> {
    TABLE.iter().find(|(n, _)| *n == name).map(|&(_, f)| f)
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
    fn by_name_knows_every_name_in_the_table() {
        for (name, _) in TABLE {
            assert!(by_name(name).is_some(), "{name}");
        }
        assert!(by_name("nonsense").is_none());
    }

    #[test]
    fn series_switches_are_continuous() {
        for (f, s) in [
            (one_minus_cos_over_sq as fn(f64) -> f64, KIN_SWITCH),
            (x_minus_sin_over_cube, KIN_SWITCH),
            (one_minus_half_cot_over_sq, HALF_COT_SQ_SWITCH),
            (half_cot, HALF_COT_SWITCH),
            (one_minus_half_cot_over_sq_fit, HALF_COT_SWITCH),
            (accel_k1, KIN_SWITCH),
            (accel_k2, KIN_SWITCH),
        ] {
            let (a, b) = (f(s * (1.0 - 1e-13)), f(s * (1.0 + 1e-13)));
            assert!((a - b).abs() < 1e-14 * a.abs().max(1.0), "{a} vs {b}");
        }
        assert!((accel_k2(0.0) + 1.0 / 60.0).abs() < 1e-17);
        assert!((one_minus_half_cot_over_sq(0.0) - 1.0 / 12.0).abs() < 1e-17);
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
