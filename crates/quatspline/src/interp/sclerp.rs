//! ScLerp, screw linear interpolation of poses (Kavan et al.; seed 001; MATH.md §3).
//!
//! ScLerp(q̂₀, q̂₁; t) = q̂₀ (q̂₀* q̂₁)^t, the power taken on the screw parameters (tθ, td):
//! the body turns about, and slides along, one fixed screw axis at constant rates. C^∞ in t.
//! Shortest screw: the relative pose is negated when its real part has w < 0.
//! Defined for equal rotations (pure translation) and identical poses.

use crate::dual_quat::DualQuat;

/// Screw interpolation from pose `a` (t = 0) to pose `b` (t = 1); both unit dual quaternions.
#[inline]
pub fn sclerp(a: DualQuat, b: DualQuat, t: f64) -> DualQuat {
    let mut rel = a.conj() * b;
    if rel.r.w < 0.0 {
        rel = -rel;
    }
    a * rel.powf(t)
}
