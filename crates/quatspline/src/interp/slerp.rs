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
//! Long path between opposite keys: with q₁ = −q₀ exactly the arc has no axis of its own; we
//! define it as the key's body x axis: slerp(q, −q; t) = q · (cos πt, sin πt, 0, 0), a unit
//! quaternion turning by 2πt about the body x axis (the world axis R(q) eₓ). Nearly opposite
//! keys take the axis of their (tiny) difference, computed from q₀ + q₁ without cancellation.

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
    // r = q₁ − (q₀·q₁) q₀, the part of q₁ orthogonal to q₀. For d < 0 (only with long_path)
    // q₁ ≈ −q₀ would make that a difference of nearly equal vectors, whose rounding error points
    // along q₀ (not orthogonal to it) and destroyed the norm; the sum e = q₀ + q₁ is exact there
    // and its orthogonal part e − (q₀·e)/|q₀|² q₀ is the same vector.
    let r = if d < 0.0 {
        let e = q1 + q0;
        e - q0.scale(q0.dot(e) / q0.norm_squared())
    } else {
        q1 - q0.scale(d)
    };
    let s = r.norm();
    if d < 0.0 && s <= 1e-150 {
        // Exactly opposite keys (long_path): the documented body-x axis, a 2πt turn.
        let (sp, cp) = crate::special::sin_cos(std::f64::consts::PI * t);
        return q0 * Quat::new(cp, sp, 0.0, 0.0);
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

    /// Regression (issue 2.1 item 2): for q = (0, 0, 1, 1)/√2 the long path to −q lost its norm
    /// (0 at t = 0.75): r = q₁ − (q₀·q₁) q₀ was rounding noise parallel to q₀.
    #[test]
    fn long_path_to_minus_q_is_a_unit_full_turn_about_body_x() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let keys = [Quat::new(0.0, 0.0, h, h), Quat::new(0.6, 0.8, 0.0, 0.0), Quat::new(0.5, 0.5, 0.5, 0.5)];
        for q in keys {
            for k in 0..=40 {
                let t = k as f64 / 40.0;
                let m = slerp(q, -q, t, true);
                assert!((m.norm() - 1.0).abs() < 1e-15, "norm {} at t = {t}", m.norm());
                let want = q * Quat::new(
                    (std::f64::consts::PI * t).cos(),
                    (std::f64::consts::PI * t).sin(),
                    0.0,
                    0.0,
                );
                assert!((m - want).norm() < 1e-15, "t = {t}");
            }
        }
    }

    proptest! {
        /// Nearly opposite keys on the long path: unit everywhere and the end is the key.
        #[test]
        fn long_path_nearly_opposite_is_unit(a in unit(), e in -1e-9..1e-9f64, t in 0.0..1.0f64) {
            let b = (-a + Quat::new(e, -e, 0.5 * e, 0.0)).normalize();
            let m = slerp(a, b, t, true);
            prop_assert!((m.norm() - 1.0).abs() < 1e-14, "norm {}", m.norm());
        }
    }
}
