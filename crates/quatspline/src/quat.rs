//! The unit-quaternion algebra everything else is built on.
//!
//! Convention (MATH.md §1): q = (w, x, y, z) = w + xi + yj + zk, scalar first, Hamilton product.
//! A unit quaternion maps body coordinates to world coordinates by v ↦ q v q*. q and −q are the
//! same rotation. `log` uses atan2 (never acos), `exp` and `log` switch to Taylor series near the
//! identity through the helpers in [`crate::special`].

use crate::error::{Error, Result};
use crate::special::{atan2_over, sinc};
use crate::vec3::{self, Vec3};
use std::ops::{Add, Mul, Neg, Sub};

/// A quaternion w + xi + yj + zk (f64, scalar first; laid out as [w, x, y, z], so that an
/// (N, 4) array of keys can be read as quaternions in place).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct Quat {
    pub w: f64,
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl Quat {
    /// The identity rotation 1.
    pub const IDENTITY: Quat = Quat { w: 1.0, x: 0.0, y: 0.0, z: 0.0 };

    #[inline]
    pub const fn new(w: f64, x: f64, y: f64, z: f64) -> Self {
        Quat { w, x, y, z }
    }

    /// From components in (w, x, y, z) order.
    #[inline]
    pub const fn from_wxyz(a: [f64; 4]) -> Self {
        Quat { w: a[0], x: a[1], y: a[2], z: a[3] }
    }

    /// From components in (x, y, z, w) order (scalar last, as scipy, Eigen storage, ROS).
    #[inline]
    pub const fn from_xyzw(a: [f64; 4]) -> Self {
        Quat { w: a[3], x: a[0], y: a[1], z: a[2] }
    }

    /// A pure quaternion (0, v).
    #[inline]
    pub const fn pure(v: Vec3) -> Self {
        Quat { w: 0.0, x: v[0], y: v[1], z: v[2] }
    }

    #[inline]
    pub const fn to_wxyz(self) -> [f64; 4] {
        [self.w, self.x, self.y, self.z]
    }

    #[inline]
    pub const fn to_xyzw(self) -> [f64; 4] {
        [self.x, self.y, self.z, self.w]
    }

    /// The vector part (x, y, z).
    #[inline]
    pub const fn vec(self) -> Vec3 {
        [self.x, self.y, self.z]
    }

    #[inline]
    pub fn dot(self, o: Quat) -> f64 {
        self.w * o.w + self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline]
    pub fn norm_squared(self) -> f64 {
        self.dot(self)
    }

    #[inline]
    pub fn norm(self) -> f64 {
        self.norm_squared().sqrt()
    }

    /// The conjugate q* = (w, −x, −y, −z); the inverse of a unit quaternion.
    #[inline]
    pub fn conj(self) -> Quat {
        Quat { w: self.w, x: -self.x, y: -self.y, z: -self.z }
    }

    #[inline]
    pub fn scale(self, s: f64) -> Quat {
        Quat { w: self.w * s, x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// True when every component is finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.w.is_finite() && self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// q / |q| (returned unchanged when |q|² is within 4ε of 1). Scales by the largest
    /// component first, so tiny and huge (but not denormal)
    /// inputs normalise without underflow or overflow.
    ///
    /// Errors: [`Error::ZeroNorm`] when every component is zero or denormal, [`Error::NonFinite`]
    /// for NaN or inf.
    pub fn try_normalize(self) -> Result<Quat> {
        if !self.is_finite() {
            return Err(Error::NonFinite { arg: "q", index: 0 });
        }
        if (self.norm_squared() - 1.0).abs() <= 4.0 * f64::EPSILON {
            // Already unit to rounding: keep the bits, so keys pass through exactly.
            return Ok(self);
        }
        let m = self.w.abs().max(self.x.abs()).max(self.y.abs()).max(self.z.abs());
        if m < f64::MIN_POSITIVE {
            return Err(Error::ZeroNorm { arg: "q", index: 0 });
        }
        let s = Quat::new(self.w / m, self.x / m, self.y / m, self.z / m);
        Ok(s.scale(1.0 / s.norm()))
    }

    /// [`Quat::try_normalize`] for callers that have already checked the input.
    ///
    /// # Panics
    /// When the quaternion is zero, denormal or not finite.
    pub fn normalize(self) -> Quat {
        match self.try_normalize() {
            Ok(q) => q,
            Err(e) => panic!("Quat::normalize: {e}"),
        }
    }

    /// q⁻¹ = q* / |q|². Errors for a zero quaternion.
    pub fn try_inverse(self) -> Result<Quat> {
        let n2 = self.norm_squared();
        if n2 <= 0.0 || !n2.is_finite() {
            return Err(Error::ZeroNorm { arg: "q", index: 0 });
        }
        Ok(self.conj().scale(1.0 / n2))
    }

    /// The exponential of any quaternion: e^w (cos|v|, sin|v| v/|v|).
    /// For a pure quaternion (0, u) this is the unit quaternion rotating by 2|u| about u.
    #[inline]
    pub fn exp(self) -> Quat {
        let v = self.vec();
        let a = vec3::norm_robust(v);
        let ca = crate::special::sin_cos(a).1;
        let s = sinc(a);
        let e = if self.w == 0.0 { 1.0 } else { self.w.exp() };
        Quat { w: e * ca, x: e * s * v[0], y: e * s * v[1], z: e * s * v[2] }
    }

    /// The principal logarithm: (ln|q|, θ v/|v|) with θ = atan2(|v|, w) ∈ [0, π].
    ///
    /// For a unit quaternion the scalar part is 0 (exactly, when |q| rounds to 1) and θ is half
    /// the rotation angle. A negative real q = (w < 0, 0, 0, 0) has no defined axis; we return
    /// (ln|w|, π, 0, 0) — the x axis — deterministically.
    #[inline]
    pub fn log(self) -> Quat {
        let v = self.vec();
        let s = vec3::norm_robust(v);
        let w0 = self.ln_norm();
        if s == 0.0 && self.w < 0.0 {
            return Quat { w: w0, x: std::f64::consts::PI, y: 0.0, z: 0.0 };
        }
        if self.w < 0.0 && s < 1e-150 {
            // θ ≈ π and θ/|v| would overflow: take the unit axis by scaling instead.
            let m = v[0].abs().max(v[1].abs()).max(v[2].abs());
            let b = [v[0] / m, v[1] / m, v[2] / m];
            let n = vec3::scale(b, s.atan2(self.w) / vec3::norm(b));
            return Quat { w: w0, x: n[0], y: n[1], z: n[2] };
        }
        let r = atan2_over(s, self.w);
        Quat { w: w0, x: r * v[0], y: r * v[1], z: r * v[2] }
    }

    /// ln|q|: exactly 0 when |q|² rounds to within 4ε of 1; scaled by the largest component
    /// first when |q|² would underflow or overflow (|q| below ~1e-154 or above ~1e154), so
    /// tiny and huge quaternions get their finite logarithm (−inf only for q = 0).
    #[inline]
    pub fn ln_norm(self) -> f64 {
        let n2 = self.norm_squared();
        if (n2 - 1.0).abs() <= 4.0 * f64::EPSILON {
            return 0.0;
        }
        if n2 >= f64::MIN_POSITIVE && n2.is_finite() {
            return 0.5 * n2.ln();
        }
        let m = self.w.abs().max(self.x.abs()).max(self.y.abs()).max(self.z.abs());
        if m == 0.0 || !m.is_finite() {
            return m.ln();
        }
        m.ln() + 0.5 * self.scale(1.0 / m).norm_squared().ln()
    }

    /// q^t = exp(t log q). For a unit q this rotates by t times the angle of q about its axis
    /// (the angle of q itself taken in [0, 2π], i.e. no shortest-path flip here).
    #[inline]
    pub fn powf(self, t: f64) -> Quat {
        self.log().scale(t).exp()
    }

    /// Rotates a vector: q v q* for a unit q (body → world), via v + 2w(u×v) + 2u×(u×v).
    #[inline]
    pub fn rotate(self, v: Vec3) -> Vec3 {
        let u = self.vec();
        let t = vec3::scale(vec3::cross(u, v), 2.0);
        vec3::add(vec3::add(v, vec3::scale(t, self.w)), vec3::cross(u, t))
    }

    /// The representative with w ≥ 0 (ties at w = 0 broken by the first non-zero of x, y, z
    /// being positive), so equal rotations get equal quaternions.
    #[inline]
    pub fn canonical(self) -> Quat {
        let positive = if self.w != 0.0 {
            self.w > 0.0
        } else if self.x != 0.0 {
            self.x > 0.0
        } else if self.y != 0.0 {
            self.y > 0.0
        } else {
            self.z >= 0.0
        };
        if positive {
            self
        } else {
            -self
        }
    }

    /// The representative in the same hemisphere as `reference` (dot ≥ 0): the shortest-path
    /// convention for consecutive keyframes.
    #[inline]
    pub fn canonical_to(self, reference: Quat) -> Quat {
        if self.dot(reference) < 0.0 {
            -self
        } else {
            self
        }
    }

    /// The rotation angle of a unit quaternion, in [0, π] (q and −q give the same angle).
    #[inline]
    pub fn angle(self) -> f64 {
        2.0 * vec3::norm(self.vec()).atan2(self.w.abs())
    }
}

impl Mul for Quat {
    type Output = Quat;
    /// The Hamilton product (MATH.md §1). The vector part is summed as
    /// (a.w b.v + b.w a.v) + a.v × b.v, each pair rounded on its own, so q* q and q q* have an
    /// exactly zero vector part (both pairs cancel exactly): the relative rotation of two equal
    /// keys is exactly the identity, and holds and constant attitudes give exact zeros.
    #[inline]
    fn mul(self, b: Quat) -> Quat {
        let a = self;
        Quat {
            w: a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            x: (a.w * b.x + a.x * b.w) + (a.y * b.z - a.z * b.y),
            y: (a.w * b.y + a.y * b.w) + (a.z * b.x - a.x * b.z),
            z: (a.w * b.z + a.z * b.w) + (a.x * b.y - a.y * b.x),
        }
    }
}

impl Mul<f64> for Quat {
    type Output = Quat;
    #[inline]
    fn mul(self, s: f64) -> Quat {
        self.scale(s)
    }
}

impl Add for Quat {
    type Output = Quat;
    #[inline]
    fn add(self, b: Quat) -> Quat {
        Quat { w: self.w + b.w, x: self.x + b.x, y: self.y + b.y, z: self.z + b.z }
    }
}

impl Sub for Quat {
    type Output = Quat;
    #[inline]
    fn sub(self, b: Quat) -> Quat {
        Quat { w: self.w - b.w, x: self.x - b.x, y: self.y - b.y, z: self.z - b.z }
    }
}

impl Neg for Quat {
    type Output = Quat;
    #[inline]
    fn neg(self) -> Quat {
        Quat { w: -self.w, x: -self.x, y: -self.y, z: -self.z }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn close(a: Quat, b: Quat, tol: f64) -> bool {
        (a - b).to_wxyz().iter().all(|c| c.abs() <= tol)
    }

    #[test]
    fn hamilton_units() {
        let i = Quat::new(0.0, 1.0, 0.0, 0.0);
        let j = Quat::new(0.0, 0.0, 1.0, 0.0);
        let k = Quat::new(0.0, 0.0, 0.0, 1.0);
        assert_eq!(i * j, k);
        assert_eq!(j * k, i);
        assert_eq!(k * i, j);
        assert_eq!(i * j * k, Quat::new(-1.0, 0.0, 0.0, 0.0));
    }

    #[test]
    fn log_of_negative_real_is_deterministic() {
        let l = Quat::new(-1.0, 0.0, 0.0, 0.0).log();
        assert_eq!(l, Quat::new(0.0, std::f64::consts::PI, 0.0, 0.0));
        assert!(close(l.exp(), Quat::new(-1.0, 0.0, 0.0, 0.0), 1e-15));
    }

    #[test]
    fn relative_rotation_of_equal_keys_is_exactly_the_identity() {
        let mut seed = 7u64;
        for _ in 0..1000 {
            let mut c = [0.0; 4];
            for v in c.iter_mut() {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                *v = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            }
            let q = Quat::from_wxyz(c).normalize();
            for p in [q.conj() * q, q * q.conj(), (-q).conj() * q] {
                assert_eq!(p.vec(), [0.0; 3], "{q:?}");
            }
        }
    }

    #[test]
    fn log_of_tiny_and_huge_quaternions_is_finite() {
        for (scale, want) in
            [(1e-170, (1e-170f64).ln()), (1e-300, (1e-300f64).ln()), (1e200, (1e200f64).ln())]
        {
            let l = Quat::new(0.6 * scale, 0.8 * scale, 0.0, 0.0).log();
            assert!((l.w - want).abs() <= 1e-13 * want.abs(), "{scale}: {}", l.w);
            assert!((l.x - 0.8f64.atan2(0.6)).abs() < 1e-15, "{scale}: {}", l.x);
        }
    }

    #[test]
    fn zero_quaternion_does_not_normalize() {
        assert!(matches!(Quat::default().try_normalize(), Err(Error::ZeroNorm { .. })));
        let tiny = Quat::new(1e-310, 0.0, 0.0, 0.0);
        assert!(tiny.try_normalize().is_err());
        let small = Quat::new(3e-300, 4e-300, 0.0, 0.0).try_normalize().unwrap();
        assert!(close(small, Quat::new(0.6, 0.8, 0.0, 0.0), 4e-16));
    }

    #[test]
    fn rotate_quarter_turn_about_z() {
        let q = Quat::new(0.5f64.sqrt(), 0.0, 0.0, 0.5f64.sqrt());
        let v = q.rotate([1.0, 0.0, 0.0]);
        assert!(v[0].abs() < 4e-16 && (v[1] - 1.0).abs() < 4e-16 && v[2].abs() < 4e-16);
    }

    fn unit_quat() -> impl Strategy<Value = Quat> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("not tiny", |(w, x, y, z)| w * w + x * x + y * y + z * z > 1e-6)
            .prop_map(|(w, x, y, z)| Quat::new(w, x, y, z).normalize())
    }

    proptest! {
        #[test]
        fn exp_log_round_trip(q in unit_quat()) {
            prop_assert!(close(q.log().exp(), q, 2e-15));
        }

        #[test]
        fn product_of_units_is_unit(a in unit_quat(), b in unit_quat()) {
            prop_assert!(((a * b).norm() - 1.0).abs() < 1e-15);
        }

        #[test]
        fn rotate_matches_sandwich(q in unit_quat(), x in -5.0..5.0f64, y in -5.0..5.0f64) {
            let v = [x, y, 1.0];
            let s = q * Quat::pure(v) * q.conj();
            let r = q.rotate(v);
            for (a, b) in r.iter().zip(s.vec()) { prop_assert!((a - b).abs() < 1e-13); }
        }

        #[test]
        fn canonical_is_same_rotation(q in unit_quat()) {
            let c = q.canonical();
            prop_assert!(c.w >= 0.0);
            prop_assert!(close(c, q, 0.0) || close(c, -q, 0.0));
        }

        #[test]
        fn power_adds_exponents(q in unit_quat(), a in -2.0..2.0f64, b in -2.0..2.0f64) {
            prop_assert!(close(q.powf(a) * q.powf(b), q.powf(a + b), 1e-13));
        }
    }
}
