//! Dual quaternions q̂ = r + ε d for rigid-body poses (MATH.md §3, seed 001).
//!
//! A pose with rotation r (unit) and translation t is q̂ = r + ε ½ (0, t) r; it maps a point p to
//! r p r* + t. The screw (Chasles) form q̂ = cos(θ̂/2) + û sin(θ̂/2) with θ̂ = θ + ε d and
//! û = u + ε m gives the power q̂^s (rotate s·θ about the screw axis while advancing s·d along
//! it), which is what ScLerp uses. Seed 001's erratum (MATH.md §11.4): the relative rotation is
//! cos θ + u sin θ with θ = arccos(q1·q2), and d = u·t is signed.

use crate::error::Result;
use crate::quat::Quat;
use crate::special::sin_ratio;
use crate::vec3::{self, Vec3};
use std::ops::{Add, Mul, Neg};

/// A dual quaternion: real part `r`, dual part `d`. As a flat array: (r.w, r.x, r.y, r.z,
/// d.w, d.x, d.y, d.z).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DualQuat {
    pub r: Quat,
    pub d: Quat,
}

/// The screw parameters of a unit dual quaternion (Chasles): rotation by `angle` about the
/// line with direction `axis` and moment `moment` (a point on the line is `axis × moment`),
/// combined with a translation `displacement` along it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Screw {
    pub axis: Vec3,
    pub angle: f64,
    pub displacement: f64,
    pub moment: Vec3,
}

impl DualQuat {
    pub const IDENTITY: DualQuat = DualQuat { r: Quat::IDENTITY, d: Quat::new(0.0, 0.0, 0.0, 0.0) };

    #[inline]
    pub const fn new(r: Quat, d: Quat) -> Self {
        DualQuat { r, d }
    }

    /// From the flat layout (w, x, y, z, dw, dx, dy, dz).
    #[inline]
    pub fn from_array(a: [f64; 8]) -> Self {
        DualQuat { r: Quat::new(a[0], a[1], a[2], a[3]), d: Quat::new(a[4], a[5], a[6], a[7]) }
    }

    #[inline]
    pub fn to_array(self) -> [f64; 8] {
        let (r, d) = (self.r, self.d);
        [r.w, r.x, r.y, r.z, d.w, d.x, d.y, d.z]
    }

    /// The pose "rotate by `r` (unit), then translate by `t`": r + ε ½ (0, t) r.
    #[inline]
    pub fn from_rotation_translation(r: Quat, t: Vec3) -> Self {
        DualQuat { r, d: (Quat::pure(t) * r).scale(0.5) }
    }

    /// The rotation and translation of a unit dual quaternion: t = 2 d r* (vector part).
    #[inline]
    pub fn to_rotation_translation(self) -> (Quat, Vec3) {
        let t = (self.d * self.r.conj()).scale(2.0);
        (self.r, t.vec())
    }

    /// Quaternion conjugate (r*, d*): the inverse of a unit dual quaternion.
    #[inline]
    pub fn conj(self) -> Self {
        DualQuat { r: self.r.conj(), d: self.d.conj() }
    }

    /// Dual-number conjugate (r, −d).
    #[inline]
    pub fn dual_conj(self) -> Self {
        DualQuat { r: self.r, d: -self.d }
    }

    /// Both conjugates at once (r*, −d*), used for point transforms p' = q̂ (1 + εp) q̂**.
    #[inline]
    pub fn full_conj(self) -> Self {
        DualQuat { r: self.r.conj(), d: -self.d.conj() }
    }

    /// Normalises so that |r| = 1 and r·d = 0: q̂/‖q̂‖ with ‖q̂‖ = |r| + ε (r·d)/|r|.
    /// Errors when r is zero.
    pub fn try_normalize(self) -> Result<Self> {
        let n = self.r.norm();
        let r = self.r.try_normalize()?;
        let d = self.d.scale(1.0 / n);
        let d = d - r.scale(r.dot(d));
        Ok(DualQuat { r, d })
    }

    /// The point transform r p r* + t of a unit dual quaternion.
    #[inline]
    pub fn transform_point(self, p: Vec3) -> Vec3 {
        let (r, t) = self.to_rotation_translation();
        vec3::add(r.rotate(p), t)
    }

    /// The screw parameters (MATH.md §3). For the shortest screw the caller passes q̂ with
    /// r.w ≥ 0. A pure translation (θ = 0) has axis t/|t| (x for no motion at all),
    /// displacement |t| and zero moment.
    pub fn screw(self) -> Screw {
        let (r, t) = self.to_rotation_translation();
        let v = r.vec();
        let s = vec3::norm(v);
        if s == 0.0 {
            let d = vec3::norm(t);
            let axis = if d > 0.0 { vec3::scale(t, 1.0 / d) } else { [1.0, 0.0, 0.0] };
            let angle = if r.w >= 0.0 { 0.0 } else { 2.0 * std::f64::consts::PI };
            return Screw { axis, angle, displacement: d, moment: [0.0; 3] };
        }
        let axis = vec3::scale(v, 1.0 / s);
        let half = s.atan2(r.w);
        let d = vec3::dot(axis, t);
        let cot = half.cos() / half.sin();
        let m = vec3::scale(
            vec3::add(vec3::cross(t, axis), vec3::scale(vec3::sub(t, vec3::scale(axis, d)), cot)),
            0.5,
        );
        Screw { axis, angle: 2.0 * half, displacement: d, moment: m }
    }

    /// q̂^s via the screw form: cos(sθ̂/2) + û sin(sθ̂/2), expanded with dual-number sin/cos.
    ///
    /// The moment's cot(θ/2) is folded into sin(sθ/2)/sin(θ/2) (see [`sin_ratio`]), so the
    /// power is smooth through θ → 0 and exact for pure translations (q̂^s = 1 + ε ½ s t).
    pub fn powf(self, s: f64) -> Self {
        let (r, t) = self.to_rotation_translation();
        let v = r.vec();
        let sn = vec3::norm(v);
        if sn == 0.0 && r.w >= 0.0 {
            return DualQuat::from_rotation_translation(Quat::IDENTITY, vec3::scale(t, s));
        }
        let half = sn.atan2(r.w);
        let u = if sn > 0.0 { vec3::scale(v, 1.0 / sn) } else { [1.0, 0.0, 0.0] };
        let d = vec3::dot(u, t);
        let (sh, ch) = (s * half).sin_cos();
        // sin(sθ/2)·m = ½ sin(sθ/2)(t×u) + ½ (t − d u) cos(θ/2) sin(sθ/2)/sin(θ/2)
        let ratio = sin_ratio(s, half) * half.cos();
        let sm = vec3::scale(
            vec3::add(
                vec3::scale(vec3::cross(t, u), sh),
                vec3::scale(vec3::sub(t, vec3::scale(u, d)), ratio),
            ),
            0.5,
        );
        let hd = 0.5 * s * d;
        let real = Quat::new(ch, sh * u[0], sh * u[1], sh * u[2]);
        let dual =
            Quat::new(-hd * sh, sm[0] + hd * ch * u[0], sm[1] + hd * ch * u[1], sm[2] + hd * ch * u[2]);
        DualQuat { r: real, d: dual }
    }

    #[inline]
    pub fn scale(self, s: f64) -> Self {
        DualQuat { r: self.r.scale(s), d: self.d.scale(s) }
    }

    #[inline]
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.d.is_finite()
    }
}

impl Mul for DualQuat {
    type Output = DualQuat;
    /// (r₁ + εd₁)(r₂ + εd₂) = r₁r₂ + ε(r₁d₂ + d₁r₂).
    #[inline]
    fn mul(self, b: DualQuat) -> DualQuat {
        DualQuat { r: self.r * b.r, d: self.r * b.d + self.d * b.r }
    }
}

impl Add for DualQuat {
    type Output = DualQuat;
    #[inline]
    fn add(self, b: DualQuat) -> DualQuat {
        DualQuat { r: self.r + b.r, d: self.d + b.d }
    }
}

impl Neg for DualQuat {
    type Output = DualQuat;
    #[inline]
    fn neg(self) -> DualQuat {
        DualQuat { r: -self.r, d: -self.d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pose() -> impl Strategy<Value = DualQuat> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64, -3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64)
            .prop_map(|(x, y, z, w, a, b, c)| {
                DualQuat::from_rotation_translation(Quat::new(w, x, y, z).normalize(), [a, b, c])
            })
    }

    proptest! {
        #[test]
        fn rotation_translation_round_trip(q in pose()) {
            let (r, t) = q.to_rotation_translation();
            let back = DualQuat::from_rotation_translation(r, t);
            for (a, b) in back.to_array().iter().zip(q.to_array()) { prop_assert!((a - b).abs() < 1e-14); }
        }

        #[test]
        fn power_one_is_identity_map_and_halves_compose(q in pose()) {
            let one = q.powf(1.0);
            for (a, b) in one.to_array().iter().zip(q.to_array()) { prop_assert!((a - b).abs() < 1e-13); }
            let h = q.powf(0.5);
            let two = h * h;
            for (a, b) in two.to_array().iter().zip(q.to_array()) { prop_assert!((a - b).abs() < 1e-13); }
        }

        #[test]
        fn screw_displacement_is_signed_projection(q in pose()) {
            let s = q.screw();
            let (_, t) = q.to_rotation_translation();
            prop_assert!((s.displacement - vec3::dot(s.axis, t)).abs() < 1e-13);
        }
    }

    #[test]
    fn pure_translation_power() {
        let q = DualQuat::from_rotation_translation(Quat::IDENTITY, [2.0, 0.0, -4.0]);
        let (r, t) = q.powf(0.25).to_rotation_translation();
        assert_eq!(r, Quat::IDENTITY);
        assert!((t[0] - 0.5).abs() < 1e-16 && (t[2] + 1.0).abs() < 1e-16);
    }
}
