//! Slerp, spherical linear interpolation (Shoemake 1985; seeds 001 and 003; MATH.md §2).
//!
//! slerp(q₀, q₁; t) = [sin((1−t)θ) q₀ + sin(tθ) q₁] / sin θ = q₀ (q₀* q₁)^t, with θ the angle
//! between q₀ and q₁ on S³ (half the rotation angle). Constant angular speed 2θ per unit t,
//! about a fixed axis; C^∞ in t between its keys.
//!
//! Numerics: θ = 2 atan2(|q₁ − q₀|, |q₁ + q₀|), exact for nearly equal and nearly opposite
//! keys; the weights sin(aθ)/sin θ come from [`crate::special::sin_ratio`] (Taylor near θ = 0).
//! Shortest path: q₁ is replaced by −q₁ when q₀·q₁ < 0, so the result at t = 1 is that
//! representative; `long_path = true` opts out. Exact at t = 0 and t = 1.
//! The long path between exactly opposite quaternions (a full turn) has no defined axis; it
//! goes through `log`'s deterministic choice (the x axis).

use crate::quat::Quat;
use crate::special::{atan2_over, sinc};

/// Slerp from `q0` (t = 0) to `q1` (t = 1); t outside [0, 1] extrapolates along the same arc.
///
/// Written as cos(tθ) q₀ + sin(tθ)/sin θ · (q₁ − cos θ q₀): r = q₁ − (q₀·q₁) q₀ is orthogonal
/// to q₀ with |r| = sin θ, so θ = atan2(|r|, q₀·q₁) is exact at both ends of [0, π], and the
/// weight sin(tθ)/sin θ = t · sinc(tθ) · θ/|r| stays finite as θ → 0 (Taylor branches).
/// One atan2 and one sin/cos pair per call.
#[inline]
pub fn slerp(q0: Quat, q1: Quat, t: f64, long_path: bool) -> Quat {
    let mut d = q0.dot(q1);
    let q1 = if !long_path && d < 0.0 {
        d = -d;
        -q1
    } else {
        q1
    };
    if t == 0.0 {
        return q0;
    }
    if t == 1.0 {
        return q1;
    }
    let r = q1 - q0.scale(d);
    let s = r.norm();
    if s < 1e-150 && d < 0.0 {
        // Only reachable with long_path between opposite keys: the exp/log form picks the axis.
        return q0 * (q0.conj() * q1).powf(t);
    }
    let theta = s.atan2(d);
    let (st, ct) = crate::special::sin_cos(t * theta);
    let w = if theta < SMALL { t * sinc(t * theta) * atan2_over(s, d) } else { st / s };
    q0.scale(ct) + r.scale(w)
}

/// Below this angle θ the weight uses its Taylor-safe form t·sinc(tθ)·θ/sin θ.
const SMALL: f64 = 1e-3;

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn unit() -> impl Strategy<Value = Quat> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("not tiny", |(w, x, y, z)| w * w + x * x + y * y + z * z > 1e-4)
            .prop_map(|(w, x, y, z)| Quat::new(w, x, y, z).normalize())
    }

    proptest! {
        #[test]
        fn equals_power_form(a in unit(), b in unit(), t in 0.0..1.0f64) {
            let b = b.canonical_to(a);
            let s = slerp(a, b, t, false);
            let p = a * (a.conj() * b).powf(t);
            prop_assert!((s - p).to_wxyz().iter().all(|c| c.abs() < 1e-14));
            prop_assert!((s.norm() - 1.0).abs() < 1e-15);
        }

        #[test]
        fn left_invariant(a in unit(), b in unit(), g in unit(), t in 0.0..1.0f64) {
            let l = g * slerp(a, b, t, false);
            let r = slerp(g * a, g * b, t, false);
            prop_assert!((l - r).to_wxyz().iter().all(|c| c.abs() < 1e-14));
        }
    }

    #[test]
    fn exact_at_ends_and_antipodal_long_path_is_finite() {
        let a = Quat::new(0.6, 0.8, 0.0, 0.0);
        let b = Quat::new(0.0, 0.0, 0.6, 0.8);
        assert_eq!(slerp(a, b, 0.0, false), a);
        assert_eq!(slerp(a, b, 1.0, false), b);
        let m = slerp(a, -a, 0.5, true);
        assert!(m.is_finite() && (m.norm() - 1.0).abs() < 1e-15);
    }
}
