//! Pose (SE(3)) splines with exact derivatives: dual quaternions on jets.
//!
//! A pose curve Q̂(t) = r(t) + ε d(t), d = ½ p r (MATH.md §3), is evaluated as a
//! [`JDual<N>`] — the real and dual parts as quaternion jets — so r', r'', r''' and p', p'', p'''
//! are exact (Taylor-mode differentiation, see [`crate::jet`]). The screw power of a constant
//! unit dual quaternion to a jet exponent ([`ScrewPow`]) is the building block of both
//! [`ScrewSpline`] (piecewise ScLerp and the cumulative C³ form) and [`PoseBSpline`] (the
//! cumulative B-spline on SE(3)).
//!
//! Twists from the derivatives (all exact for a unit Q̂):
//! body ξ_b = 2 Q̂* Q̂' = ω_b + ε Rᵀṗ, ξ_b' = 2(Q̂'* Q̂' + Q̂* Q̂''),
//! ξ_b'' = 2(Q̂''* Q̂' + 2 Q̂'* Q̂'' + Q̂* Q̂''');
//! spatial ξ_s = 2 Q̂' Q̂* = ω + ε (ṗ − ω × p), ξ_s' = 2(Q̂'' Q̂* + Q̂' Q̂'*),
//! ξ_s'' = 2(Q̂''' Q̂* + 2 Q̂'' Q̂'* + Q̂' Q̂''*).

mod pose_bspline;
mod screw_spline;

pub use pose_bspline::{PoseBSpline, PoseFormulation};
pub use screw_spline::ScrewSpline;

use crate::dual_quat::DualQuat;
use crate::error::{Error, Result};
use crate::jet::{JQuat, Jet};
use crate::quat::Quat;
use crate::special::sinc_jet;
use crate::spline::{Extrapolate, Spline};
use crate::vec3::{self, Vec3};
use std::ops::Mul;

/// A dual quaternion whose components are jets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JDual<const N: usize> {
    pub r: JQuat<N>,
    pub d: JQuat<N>,
}

impl<const N: usize> JDual<N> {
    #[inline(always)]
    pub fn constant(q: DualQuat) -> Self {
        JDual { r: JQuat::constant(q.r), d: JQuat::constant(q.d) }
    }

    /// [Q̂, Q̂', …] up to order N − 1.
    #[inline]
    pub fn derivatives(self) -> [DualQuat; N] {
        let (r, d) = (self.r.derivatives(), self.d.derivatives());
        std::array::from_fn(|k| DualQuat::new(r[k], d[k]))
    }

    /// The position p = 2 vec(d r*) as jets.
    #[inline]
    pub fn position(self) -> [Jet<N>; 3] {
        let p = self.d * self.r.conj();
        [p.x * 2.0, p.y * 2.0, p.z * 2.0]
    }
}

impl<const N: usize> Mul for JDual<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        JDual { r: self.r * b.r, d: self.r * b.d + self.d * b.r }
    }
}

/// A constant unit dual quaternion prepared for powers Q̂^s with a jet exponent s:
/// Q̂^s = cos(sθ̂/2) + û sin(sθ̂/2) expanded with dual-number sin/cos (as [`DualQuat::powf`]):
/// real (cos sh, sin sh · u), dual (−½ s d sin sh, ½ sin sh (t × u) + ½ (t − d u) cos h
/// sin(sh)/sin h + ½ s d cos sh · u), h = θ/2, d = u·t; smooth through h → 0 (a pure
/// translation gives 1 + ε ½ s t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScrewPow {
    half: f64,
    u: Vec3,
    d: f64,
    txu: Vec3,
    perp: Vec3,
    cos_half: f64,
    sin_half: f64,
}

impl ScrewPow {
    /// `q` must be a unit dual quaternion (its real part with w ≥ 0 for the shortest screw).
    pub fn new(q: DualQuat) -> Self {
        let (r, t) = q.to_rotation_translation();
        let v = r.vec();
        let sn = vec3::norm(v);
        let half = sn.atan2(r.w);
        let u = if sn > 0.0 { vec3::scale(v, 1.0 / sn) } else { [1.0, 0.0, 0.0] };
        let d = vec3::dot(u, t);
        ScrewPow {
            half,
            u,
            d,
            txu: vec3::cross(t, u),
            perp: vec3::sub(t, vec3::scale(u, d)),
            cos_half: half.cos(),
            sin_half: sn,
        }
    }

    /// Q̂^s with its derivatives in time (s a jet).
    #[inline]
    pub fn pow<const N: usize>(&self, s: Jet<N>) -> JDual<N> {
        let x = s * self.half;
        let (sh, ch) = x.sin_cos();
        // sin(s h)/sin h, smooth at h = 0: s · sinc(s h)/sinc(h)
        let ratio = if self.half > 1e-2 {
            sh * (1.0 / self.sin_half)
        } else {
            s * sinc_jet(x) * (1.0 / crate::special::sinc(self.half))
        } * self.cos_half;
        let hd = s * (0.5 * self.d);
        let u = self.u;
        let comp = |k: usize| sh * (0.5 * self.txu[k]) + ratio * (0.5 * self.perp[k]) + hd * ch * u[k];
        JDual {
            r: JQuat { w: ch, x: sh * u[0], y: sh * u[1], z: sh * u[2] },
            d: JQuat { w: -(hd * sh), x: comp(0), y: comp(1), z: comp(2) },
        }
    }
}

/// Pose keys as unit dual quaternions, consecutive keys sign-aligned (shortest screws).
pub fn pose_keys(quats: &[Quat], positions: &[Vec3], arg: &'static str, min: usize) -> Result<Vec<DualQuat>> {
    if positions.len() != quats.len() {
        return Err(Error::invalid(
            "positions",
            format!("expected {} positions (one per rotation), got {}", quats.len(), positions.len()),
        ));
    }
    let r = crate::spline::prepare_keys(quats, arg, min, true)?;
    for (i, p) in positions.iter().enumerate() {
        if !p.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite { arg: "positions", index: i });
        }
        if p.iter().any(|v| v.abs() > 1e15) {
            return Err(Error::invalid("positions", format!("position {i} is beyond |x| ≤ 1e15")));
        }
    }
    Ok(r.iter().zip(positions).map(|(&q, &p)| DualQuat::from_rotation_translation(q, p)).collect())
}

/// A pose curve: the rotation part is a [`Spline`]; `pose_jetN` adds the dual part.
pub trait PoseCurve: Spline {
    fn pose_jet1(&self, seg: usize, t: f64) -> JDual<1>;
    fn pose_jet4(&self, seg: usize, t: f64) -> JDual<4>;
}

/// The pose jets at a time after the extrapolation rule (see [`crate::spline::Extrapolate`]);
/// the flag is true for a held (clamped) pose, whose derivatives are zero. `Linear`: constant
/// body angular velocity (as the rotation splines, `spline::eval`) and constant world linear
/// velocity from the nearest end (as `PoseSpline`); `Periodic`: t wrapped into the domain.
fn pose_at(s: &dyn PoseCurve, i: usize, t: f64, ex: Extrapolate) -> Result<(JDual<4>, bool)> {
    if !t.is_finite() {
        return Err(Error::NonFinite { arg: "t", index: i });
    }
    let (a, b) = s.domain();
    let at = |x: f64| s.pose_jet4(s.locate(x), x);
    if t >= a && t <= b {
        return Ok((at(t), false));
    }
    match ex {
        Extrapolate::Raise => Err(Error::OutOfDomain { index: i, t, start: a, end: b }),
        Extrapolate::Clamp => Ok((at(t.clamp(a, b)), true)),
        Extrapolate::Periodic => {
            let w = (a + (t - a).rem_euclid(b - a)).clamp(a, b);
            Ok((at(w), false))
        }
        Extrapolate::Linear => {
            let (end, seg) = if t < a { (a, 0) } else { (b, s.segments() - 1) };
            let e = s.pose_jet4(seg, end);
            let r0 = e.r.value();
            let w = crate::jet::angular(&e.r.derivatives()[..2], 1, true);
            let p = e.position();
            let x = Jet::<4>::variable(t - end, 1.0);
            let rot: [Jet<4>; 3] = std::array::from_fn(|c| x * (0.5 * w[c]));
            let r = JQuat::constant(r0) * JQuat::exp_pure(rot);
            let pos: [Jet<4>; 3] = std::array::from_fn(|c| x * p[c].0[1] + p[c].0[0]);
            let half = JQuat { w: Jet::constant(0.0), x: pos[0] * 0.5, y: pos[1] * 0.5, z: pos[2] * 0.5 };
            Ok((JDual { r, d: half * r }, false))
        }
    }
}

/// Per sample: position (3) then, for order ≥ 1, its first to third derivatives (3 each) up
/// to `order`, world coordinates, after the rule `ex` (clamp: the end pose, zero derivatives).
pub fn positions_into(
    s: &dyn PoseCurve,
    t: &[f64],
    order: usize,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    let w = 3 * (order + 1);
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(w)).enumerate() {
        let (jet, held) = pose_at(s, k, ti, ex)?;
        let p = jet.position();
        for m in 0..=order {
            for c in 0..3 {
                row[3 * m + c] = if held && m > 0 { 0.0 } else { p[c].derivative(m) };
            }
        }
    }
    Ok(())
}

/// Per sample the twist (order 1) or its first (2) or second (3) time derivative, 6 numbers
/// (angular, linear), body or spatial (see the module doc), after the extrapolation rule.
pub fn twists_into(
    s: &dyn PoseCurve,
    t: &[f64],
    order: usize,
    body: bool,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    if !(1..=3).contains(&order) {
        return Err(Error::invalid("order", format!("expected 1, 2 or 3, got {order}")));
    }
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(6)).enumerate() {
        let (jet, held) = pose_at(s, k, ti, ex)?;
        if held {
            row.copy_from_slice(&[0.0; 6]);
            continue;
        }
        let d = jet.derivatives();
        let c = |q: DualQuat| q.conj();
        let v = match (order, body) {
            (1, true) => c(d[0]) * d[1],
            (2, true) => c(d[1]) * d[1] + c(d[0]) * d[2],
            (3, true) => c(d[2]) * d[1] + (c(d[1]) * d[2]).scale(2.0) + c(d[0]) * d[3],
            (1, false) => d[1] * c(d[0]),
            (2, false) => d[2] * c(d[0]) + d[1] * c(d[1]),
            _ => d[3] * c(d[0]) + (d[2] * c(d[1])).scale(2.0) + d[1] * c(d[2]),
        };
        row.copy_from_slice(&[2.0 * v.r.x, 2.0 * v.r.y, 2.0 * v.r.z, 2.0 * v.d.x, 2.0 * v.d.y, 2.0 * v.d.z]);
    }
    Ok(())
}

/// The dual part of a pose curve seen as a quaternion curve, so the continuity certificate
/// ([`crate::analysis::continuity`]) can check positions at the joints too.
pub struct DualPart(pub std::sync::Arc<dyn PoseCurve>);

impl Spline for DualPart {
    fn name(&self) -> &'static str {
        "dual_part"
    }
    fn joints(&self) -> &[f64] {
        self.0.joints()
    }
    fn interpolates(&self) -> bool {
        self.0.interpolates()
    }
    fn continuity(&self) -> u8 {
        self.0.continuity()
    }
    fn segment_jet1(&self, seg: usize, t: f64) -> JQuat<1> {
        self.0.pose_jet1(seg, t).d
    }
    fn segment_jet2(&self, seg: usize, t: f64) -> JQuat<2> {
        trunc(self.0.pose_jet4(seg, t).d)
    }
    fn segment_jet3(&self, seg: usize, t: f64) -> JQuat<3> {
        trunc(self.0.pose_jet4(seg, t).d)
    }
    fn segment_jet4(&self, seg: usize, t: f64) -> JQuat<4> {
        self.0.pose_jet4(seg, t).d
    }
}

/// The first M coefficients of a jet quaternion.
#[inline]
pub fn trunc<const M: usize>(q: JQuat<4>) -> JQuat<M> {
    let f = |j: Jet<4>| Jet::<M>(std::array::from_fn(|k| j.0[k]));
    JQuat { w: f(q.w), x: f(q.x), y: f(q.y), z: f(q.z) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screw_pow_matches_powf_and_is_smooth_at_zero_angle() {
        for (axis_angle, t) in [
            ([0.3, -0.2, 0.9], [1.0, 2.0, -0.5]),
            ([1e-9, 0.0, 0.0], [0.0, 3.0, 0.0]),
            ([0.0, 0.0, 0.0], [2.0, 0.0, -4.0]),
            ([0.0, 0.005, 0.0], [1.0, 1.0, 1.0]),
            ([0.0, 0.0, 2.9], [0.1, -0.2, 0.3]),
        ] {
            let r = Quat::pure(vec3::scale(axis_angle, 0.5)).exp();
            let q = DualQuat::from_rotation_translation(r, t);
            let p = ScrewPow::new(q);
            for s in [0.0, 0.25, 0.5, 1.0, 1.7] {
                let a = p.pow::<1>(Jet::constant(s));
                let b = q.powf(s);
                let got = DualQuat::new(a.r.value(), a.d.value());
                for (x, y) in got.to_array().iter().zip(b.to_array()) {
                    assert!((x - y).abs() < 1e-14, "{axis_angle:?} s={s}: {x} vs {y}");
                }
            }
        }
    }
}
