//! DLB, dual-quaternion linear blending (Kavan et al. 2008; seed 001; MATH.md §3).
//!
//! DLB(w; q̂) = normalise(Σ wᵢ q̂ᵢ), each q̂ᵢ first negated if its real part points away from
//! the first one's (sign alignment). The skinning operator: cheap, always a rigid motion, but for
//! two keys it is NLerp of dual quaternions — it keeps ScLerp's screw axis, not its angle.

use crate::dual_quat::DualQuat;
use crate::error::{Error, Result};

/// Blends poses `q` with weights `w` (same length, at least one). Errors when the weighted sum
/// has a zero real part (e.g. weights summing to zero).
pub fn try_dlb(q: &[DualQuat], w: &[f64]) -> Result<DualQuat> {
    if q.is_empty() || q.len() != w.len() {
        return Err(Error::invalid(
            "weights",
            format!("expected {} weights for {} poses (at least one)", q.len(), q.len()),
        ));
    }
    let pivot = q[0].r;
    let mut acc = DualQuat::default();
    for (qi, &wi) in q.iter().zip(w) {
        let qi = if qi.r.dot(pivot) < 0.0 { -*qi } else { *qi };
        acc = acc + qi.scale(wi);
    }
    acc.try_normalize().map_err(|_| Error::invalid("weights", "the weighted sum has zero rotation part"))
}
