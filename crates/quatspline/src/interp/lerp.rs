//! Lerp and NLerp (seed 001; MATH.md §2).
//!
//! Lerp(q₀, q₁; t) = (1−t) q₀ + t q₁ — a straight chord, not a unit quaternion.
//! NLerp = Lerp / ‖Lerp‖ — unit, on the shortest arc (q₁ flipped when q₀·q₁ < 0 unless
//! `long_path`), but with non-constant angular speed. Continuity between keys: C^∞ in t.

use crate::error::{Error, Result};
use crate::quat::Quat;

/// (1−t) q₀ + t q₁, componentwise (no normalisation, no sign flip).
#[inline]
pub fn lerp(q0: Quat, q1: Quat, t: f64) -> Quat {
    q0.scale(1.0 - t) + q1.scale(t)
}

/// Normalised lerp on the shortest arc (or the long one). Errors only when the chord passes
/// through zero: q₁ = −q₀ with `long_path` at t = ½.
#[inline]
pub fn try_nlerp(q0: Quat, q1: Quat, t: f64, long_path: bool) -> Result<Quat> {
    let q1 = if !long_path && q0.dot(q1) < 0.0 { -q1 } else { q1 };
    lerp(q0, q1, t)
        .try_normalize()
        .map_err(|_| Error::invalid("t", "nlerp of antipodal keys passes through zero"))
}
