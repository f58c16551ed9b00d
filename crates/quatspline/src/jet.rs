//! Truncated Taylor series ("jets") for exact derivatives of every spline.
//!
//! A `Jet<N>` holds the Taylor coefficients c₀ … c_{N−1} of a scalar function of time at one
//! instant: f(t + h) = c₀ + c₁h + c₂h² + c₃h³ + O(h⁴), so f' = c₁, f'' = 2c₂, f''' = 6c₃.
//! Arithmetic on jets is the chain and product rule carried out exactly (Taylor-mode
//! automatic differentiation): a spline written once in terms of `JQuat<N>` gives its value
//! (N = 1, compiled to plain f64 code), velocity (2), acceleration (3) and jerk (4) in closed
//! form — never by finite differences.
//!
//! The transcendental pieces are compositions with known derivatives at c₀ (Faà di Bruno):
//! - exp of a pure quaternion u uses C(x) = cos√x and S(x) = sin√x/√x of x = u·u, both
//!   entire in x; their derivatives come from series for x < 1/2 and from
//!   S' = (C − S)/(2x), S'' = (C' − 3S')/(2x), S''' = (C'' − 5S'')/(2x), C^(n) = −S^(n−1)/2
//!   otherwise;
//! - log of a unit quaternion uses g(w) = θ/sin θ (w = cos θ), analytic at w = 1, with
//!   (1−w²)g' = wg − 1, (1−w²)g'' = 3wg' + g, (1−w²)g''' = 5wg'' + 4g', and the series
//!   g = Σ aₖ yᵏ, y = 1 − w, a₀ = 1, aₖ = aₖ₋₁·k/(2k+1) for y < 0.05.
//!
//! Both derivative tables live with the other singular ratios in [`crate::special`]
//! (`cos_sinc_sqrt`, `theta_over_sin`).

use crate::quat::Quat;
use crate::special::{cos_sinc_sqrt, theta_over_sin};
/// Re-exported for the batch kernel of the natural spline (`crate::simd::natural`).
pub(crate) use crate::special::{CS_SERIES, CS_TABLE};

use std::ops::{Add, Mul, Neg, Sub};

/// Taylor coefficients of a scalar at one instant. N ≤ 6 (value and five derivatives): the
/// splines use N ≤ 4 for evaluation and N = 6 for the continuity certificate up to C⁴.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet<const N: usize>(pub [f64; N]);

impl<const N: usize> Jet<N> {
    #[inline(always)]
    pub fn constant(c: f64) -> Self {
        let mut a = [0.0; N];
        a[0] = c;
        Jet(a)
    }

    /// The independent variable: value `x`, first derivative `dx` (e.g. 1/h for a local
    /// parameter u = (t − tᵢ)/h).
    #[inline(always)]
    pub fn variable(x: f64, dx: f64) -> Self {
        let mut a = [0.0; N];
        a[0] = x;
        if N > 1 {
            a[1] = dx;
        }
        Jet(a)
    }

    /// A polynomial in the independent variable, evaluated with its derivatives: `coef[k]`
    /// multiplies xᵏ. The variable is `x` (value) with derivative `dx`.
    #[inline(always)]
    pub fn poly(coef: &[f64], x: Jet<N>) -> Self {
        let mut acc = Jet::constant(0.0);
        for &c in coef.iter().rev() {
            acc = acc * x + c;
        }
        acc
    }

    #[inline(always)]
    pub fn value(self) -> f64 {
        self.0[0]
    }

    /// The k-th derivative (k! cₖ).
    #[inline(always)]
    pub fn derivative(self, k: usize) -> f64 {
        const FACT: [f64; 6] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];
        self.0[k] * FACT[k]
    }

    /// f(self) given d[m] = f^(m)(c₀) for m < N (Faà di Bruno by powers of h = self − c₀).
    #[inline(always)]
    pub fn compose(self, d: [f64; N]) -> Self {
        let mut h = self;
        h.0[0] = 0.0;
        let mut out = Jet::constant(d[0]);
        let mut hp = Jet::constant(1.0);
        let mut fact = 1.0;
        for (m, dm) in d.iter().enumerate().skip(1) {
            hp = hp * h;
            fact *= m as f64;
            out = out + hp * (dm / fact);
        }
        out
    }

    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let r = self.0[0].sqrt();
        if N == 1 {
            return Jet::constant(r);
        }
        let x = self.0[0];
        // d^n/dx^n √x = (1/2)(−1/2)⋯(3/2 − n) x^(1/2 − n)
        let mut d = [r; MAXN];
        for n in 1..N {
            d[n] = d[n - 1] * (1.5 - n as f64) / x;
        }
        self.compose(take(d))
    }

    #[inline(always)]
    pub fn recip(self) -> Self {
        let i = 1.0 / self.0[0];
        if N == 1 {
            return Jet::constant(i);
        }
        // d^n/dx^n x⁻¹ = (−1)ⁿ n! x^(−1−n)
        let mut d = [i; MAXN];
        for n in 1..N {
            d[n] = -d[n - 1] * n as f64 * i;
        }
        self.compose(take(d))
    }

    #[inline(always)]
    pub fn sin_cos(self) -> (Self, Self) {
        let (s, c) = crate::special::sin_cos(self.0[0]);
        if N == 1 {
            return (Jet::constant(s), Jet::constant(c));
        }
        (self.compose(take([s, c, -s, -c, s, c])), self.compose(take([c, -s, -c, s, c, -s])))
    }
}

/// The largest jet length supported by the transcendental pieces.
pub const MAXN: usize = 6;

/// The first N of six derivative values.
#[inline(always)]
fn take<const N: usize>(d: [f64; MAXN]) -> [f64; N] {
    std::array::from_fn(|k| d[k])
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        Jet(std::array::from_fn(|k| self.0[k] + b.0[k]))
    }
}

impl<const N: usize> Add<f64> for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: f64) -> Self {
        self.0[0] += b;
        self
    }
}

impl<const N: usize> Sub for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        Jet(std::array::from_fn(|k| self.0[k] - b.0[k]))
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Jet(std::array::from_fn(|k| -self.0[k]))
    }
}

impl<const N: usize> Mul for Jet<N> {
    type Output = Self;
    /// The truncated Cauchy product (Leibniz rule).
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let mut out = [0.0; N];
        for k in 0..N {
            let mut acc = self.0[0] * b.0[k];
            for i in 1..=k {
                acc += self.0[i] * b.0[k - i];
            }
            out[k] = acc;
        }
        Jet(out)
    }
}

impl<const N: usize> Mul<f64> for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: f64) -> Self {
        Jet(std::array::from_fn(|k| self.0[k] * s))
    }
}

/// A logarithm (pure quaternion) stored as unit axis × angle, so exp(s·log) needs no square
/// root or division per evaluation: exp(s a n) = (cos(s a), sin(s a) n).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Axis {
    pub n: [f64; 3],
    pub a: f64,
}

impl Axis {
    /// From the vector part of a logarithm (zero gives a = 0 and a zero axis).
    pub fn from_log(v: [f64; 3]) -> Self {
        let a = crate::vec3::norm_robust(v);
        if a > 0.0 {
            Axis { n: [v[0] / a, v[1] / a, v[2] / a], a }
        } else {
            Axis { n: [0.0; 3], a: 0.0 }
        }
    }
}

/// A quaternion whose components are jets: q(t) with its derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JQuat<const N: usize> {
    pub w: Jet<N>,
    pub x: Jet<N>,
    pub y: Jet<N>,
    pub z: Jet<N>,
}

impl<const N: usize> JQuat<N> {
    /// A constant quaternion (zero derivatives).
    #[inline(always)]
    pub fn constant(q: Quat) -> Self {
        JQuat { w: Jet::constant(q.w), x: Jet::constant(q.x), y: Jet::constant(q.y), z: Jet::constant(q.z) }
    }

    /// The value q(t).
    #[inline(always)]
    pub fn value(self) -> Quat {
        Quat::new(self.w.0[0], self.x.0[0], self.y.0[0], self.z.0[0])
    }

    /// The k-th time derivative as a quaternion.
    #[inline(always)]
    pub fn derivative(self, k: usize) -> Quat {
        Quat::new(self.w.derivative(k), self.x.derivative(k), self.y.derivative(k), self.z.derivative(k))
    }

    /// [q, q', q'', …] up to order N − 1.
    #[inline(always)]
    pub fn derivatives(self) -> [Quat; N] {
        std::array::from_fn(|k| self.derivative(k))
    }

    #[inline(always)]
    pub fn conj(self) -> Self {
        JQuat { w: self.w, x: -self.x, y: -self.y, z: -self.z }
    }

    #[inline(always)]
    pub fn scale(self, s: Jet<N>) -> Self {
        JQuat { w: self.w * s, x: self.x * s, y: self.y * s, z: self.z * s }
    }

    #[inline(always)]
    pub fn dot(self, o: Self) -> Jet<N> {
        self.w * o.w + self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// exp(s · log) for a precomputed axis–angle logarithm and a scalar jet s: the factor of
    /// every cumulative form.
    #[inline(always)]
    pub fn exp_axis(ax: &Axis, s: Jet<N>) -> Self {
        let (sn, cs) = (s * ax.a).sin_cos();
        JQuat { w: cs, x: sn * ax.n[0], y: sn * ax.n[1], z: sn * ax.n[2] }
    }

    /// exp of a pure quaternion (0, u) whose components are jets.
    #[inline(always)]
    pub fn exp_pure(u: [Jet<N>; 3]) -> Self {
        let x = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        let (dc, ds) = cos_sinc_sqrt::<N>(x.0[0].max(0.0));
        let c = x.compose(dc);
        let s = x.compose(ds);
        JQuat { w: c, x: u[0] * s, y: u[1] * s, z: u[2] * s }
    }

    /// The vector part of log of a unit quaternion: θ n with θ = atan2(|v|, w).
    #[inline(always)]
    pub fn log_unit(self) -> [Jet<N>; 3] {
        let q0 = self.value();
        let s = crate::vec3::norm_robust(q0.vec());
        let d = theta_over_sin::<N>(q0.w, s);
        let g = self.w.compose(d);
        if s == 0.0 && q0.w < 0.0 {
            // log(−1): no axis; the value matches Quat::log's deterministic choice.
            let mut l = [Jet::constant(0.0); 3];
            l[0] = Jet::constant(std::f64::consts::PI);
            return l;
        }
        [self.x * g, self.y * g, self.z * g]
    }

    /// slerp(a, b; u) = a exp(u log(a* b)) for jet endpoints and a jet parameter
    /// (no shortest-path flip: callers choose the representatives).
    #[inline(always)]
    pub fn slerp(a: Self, b: Self, u: Jet<N>) -> Self {
        let l = (a.conj() * b).log_unit();
        a * JQuat::exp_pure([l[0] * u, l[1] * u, l[2] * u])
    }
}

impl<const N: usize> Mul for JQuat<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        JQuat {
            // grouped as `Quat`'s product: q* q has an exactly zero vector part
            w: a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            x: (a.w * b.x + a.x * b.w) + (a.y * b.z - a.z * b.y),
            y: (a.w * b.y + a.y * b.w) + (a.z * b.x - a.x * b.z),
            z: (a.w * b.z + a.z * b.w) + (a.x * b.y - a.y * b.x),
        }
    }
}

impl<const N: usize> Add for JQuat<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        JQuat { w: self.w + b.w, x: self.x + b.x, y: self.y + b.y, z: self.z + b.z }
    }
}

/// Angular velocity, acceleration and jerk (k = 1, 2, 3) from q and its derivatives.
///
/// World frame: ω = 2 vec(q' q*), α = dω/dt = 2 vec(q'' q*) (q' q'* is real),
/// jerk = dα/dt = 2 vec(q''' q* + q'' q'*). Body frame: ω_b = 2 vec(q* q'),
/// α_b = 2 vec(q* q''), jerk_b = 2 vec(q'* q'' + q* q'''). For a unit q these are exact.
pub fn angular(d: &[Quat], order: usize, body: bool) -> [f64; 3] {
    let (q, q1) = (d[0], d[1]);
    let v = match (order, body) {
        (1, false) => q1 * q.conj(),
        (1, true) => q.conj() * q1,
        (2, false) => d[2] * q.conj(),
        (2, true) => q.conj() * d[2],
        (3, false) => d[3] * q.conj() + d[2] * q1.conj(),
        (_, true) => q1.conj() * d[2] + q.conj() * d[3],
        _ => unreachable_order(),
    };
    [2.0 * v.x, 2.0 * v.y, 2.0 * v.z]
}

#[cold]
fn unreachable_order() -> Quat {
    Quat::new(f64::NAN, f64::NAN, f64::NAN, f64::NAN)
}

impl<const N: usize> Jet<N> {
    /// atan2(y, x) of jets, through θ' = (x y' − y x')/(x² + y²) integrated term by term
    /// (exact to the jet's order). The value is libm's atan2.
    #[inline(always)]
    pub fn atan2(y: Self, x: Self) -> Self {
        let mut out = Jet::constant(y.0[0].atan2(x.0[0]));
        if N == 1 {
            return out;
        }
        let (dy, dx) = (y.shifted(), x.shifted());
        let g = (x * dy - y * dx) * (x * x + y * y).recip();
        for k in 1..N {
            out.0[k] = g.0[k - 1] / k as f64;
        }
        out
    }

    /// The jet of the derivative: coefficients (k+1) c_{k+1}; the last one is unknown (0).
    #[inline(always)]
    fn shifted(self) -> Self {
        Jet(std::array::from_fn(|k| if k + 1 < N { (k + 1) as f64 * self.0[k + 1] } else { 0.0 }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::G_SERIES;

    fn fd<F: Fn(f64) -> f64>(f: F, x: f64, k: usize) -> f64 {
        let h = 1e-3;
        match k {
            1 => (f(x - 2.0 * h) - 8.0 * f(x - h) + 8.0 * f(x + h) - f(x + 2.0 * h)) / (12.0 * h),
            2 => {
                (-f(x - 2.0 * h) + 16.0 * f(x - h) - 30.0 * f(x) + 16.0 * f(x + h) - f(x + 2.0 * h))
                    / (12.0 * h * h)
            }
            _ => (-f(x - 2.0 * h) + 2.0 * f(x - h) - 2.0 * f(x + h) + f(x + 2.0 * h)) / (2.0 * h * h * h),
        }
    }

    #[test]
    fn cos_sinc_sqrt_derivatives_match_finite_differences() {
        for &x in &[0.01, 0.3, 0.49, 0.51, 1.0, 4.0, 9.0] {
            let (c, s) = cos_sinc_sqrt::<4>(x);
            for k in 1..4 {
                let fc = fd(|v: f64| v.sqrt().cos(), x, k);
                let fs = fd(|v: f64| v.sqrt().sin() / v.sqrt(), x, k);
                assert!((c[k] - fc).abs() < 1e-6 * (1.0 + fc.abs()), "C^{k}({x})");
                assert!((s[k] - fs).abs() < 1e-6 * (1.0 + fs.abs()), "S^{k}({x}): {} vs {fs}", s[k]);
            }
        }
    }

    #[test]
    fn theta_over_sin_derivatives_match_finite_differences() {
        let g = |w: f64| w.acos() / (1.0 - w * w).sqrt();
        for &w in &[0.9f64, 0.96, 0.94, 0.5, 0.0, -0.5] {
            let s = (1.0 - w * w).sqrt();
            let d = theta_over_sin::<4>(w, s);
            assert!((d[0] - g(w)).abs() < 1e-14);
            for k in 1..4 {
                let f = fd(g, w, k);
                assert!((d[k] - f).abs() < 1e-4 * (1.0 + f.abs()), "g^{k}({w}): {} vs {f}", d[k]);
            }
        }
    }

    #[test]
    fn series_and_closed_forms_agree_at_the_switches() {
        let below = cos_sinc_sqrt::<4>(CS_SERIES * (1.0 - 1e-12));
        let above = cos_sinc_sqrt::<4>(CS_SERIES * (1.0 + 1e-12));
        for k in 0..4 {
            assert!((below.0[k] - above.0[k]).abs() < 1e-11, "C^{k}: {} {}", below.0[k], above.0[k]);
            assert!((below.1[k] - above.1[k]).abs() < 1e-11, "S^{k}: {} {}", below.1[k], above.1[k]);
        }
        let y = G_SERIES;
        let wa = 1.0 - y * (1.0 - 1e-12);
        let wb = 1.0 - y * (1.0 + 1e-12);
        let ga = theta_over_sin::<4>(wa, (1.0 - wa * wa).sqrt());
        let gb = theta_over_sin::<4>(wb, (1.0 - wb * wb).sqrt());
        for k in 0..4 {
            assert!((ga[k] - gb[k]).abs() < 1e-11 * (1.0 + ga[k].abs()), "g^{k}: {} {}", ga[k], gb[k]);
        }
    }

    #[test]
    fn product_rule() {
        let t = Jet::<4>::variable(0.7, 1.0);
        let f = t * t * t; // t³
        assert!((f.derivative(1) - 3.0 * 0.49).abs() < 1e-15);
        assert!((f.derivative(2) - 6.0 * 0.7).abs() < 1e-15);
        assert!((f.derivative(3) - 6.0).abs() < 1e-15);
    }
}
