//! Orientations from angular-velocity samples (gyro-like rates).
//!
//! Given times t₀ < … < t_{n−1}, rates ωₖ and the start orientation q₀, solve
//! body frame q' = ½ q ω (ω in body coordinates) or world frame q' = ½ ω q, one step per
//! sample interval h = t_{k+1} − tₖ, each step a rotation vector φ applied as
//! q_{k+1} = qₖ exp(φ/2) (body) or exp(φ/2) qₖ (world), renormalised:
//!
//! - [`RateModel::Zoh`] (zero-order hold, ω = ωₖ on [tₖ, t_{k+1})): φ = h ωₖ — exact for
//!   piecewise-constant rates (the last sample's rate is not used).
//! - [`RateModel::Linear`] (ω linear between samples): the fourth-order Magnus step with the
//!   two Gauss–Legendre nodes c₁,₂ = ½ ∓ √3/6 (Iserles & Nørsett 1999; Blanes, Casas & Ros
//!   2000), φ = h (ω₁ + ω₂)/2 ± (√3 h²/12) ω₁ × ω₂ (+ body, − world: the commutator of the
//!   right multiplications in q' = ½ q ω has the opposite sign). For linear ω it reduces to
//!   the classical coning correction φ = h (ωₖ + ωₖ₊₁)/2 ± (h²/12) ωₖ × ωₖ₊₁ (Bortz 1971).
//!   Global error O(h⁴) for piecewise-linear rates; for rates that are samples of a smooth
//!   function the linear model itself is only second order (trapezoid).
//! - [`RateModel::Cubic`] (ω interpolated by the cubic through the four nearest samples,
//!   fewer when there are fewer): the same Magnus step, global error O(h⁴) for samples of
//!   any smooth rate.
//!
//! The Magnus step is one exponential per interval (commutator-free in the sense that only
//! the single cross product above appears), so every output is a rotation to rounding.

use crate::error::{Error, Result, Short};
use crate::frame::Frame;
use crate::quadrature::GL2_01;
use crate::quat::Quat;
use crate::vec3::{self, Vec3};

/// How the rate varies between samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RateModel {
    /// Piecewise constant (zero-order hold): exact.
    Zoh,
    /// Piecewise linear: fourth-order Magnus.
    Linear,
    /// Local cubic through four samples: fourth-order Magnus for smooth rates.
    Cubic,
}

/// |q₀| may differ from 1 by at most this (relative) before q₀ is "not a rotation".
pub const Q0_NORM_TOLERANCE: f64 = 1e-6;

/// The two Gauss–Legendre nodes ½ ∓ √3/6 of the Magnus step ([`crate::quadrature::GL2_01`]).
const C1: f64 = GL2_01[0];
const C2: f64 = GL2_01[1];
const SQRT3_12: f64 = 0.144_337_567_297_406_43; // √3/12

/// The rate at time `x` from the cubic (or lower-degree) Lagrange interpolant through the
/// samples `lo .. lo + m`.
fn lagrange(times: &[f64], rates: &[Vec3], lo: usize, m: usize, x: f64) -> Vec3 {
    let mut out = [0.0; 3];
    for i in lo..lo + m {
        let mut l = 1.0;
        for j in lo..lo + m {
            if j != i {
                l *= (x - times[j]) / (times[i] - times[j]);
            }
        }
        out = vec3::add(out, vec3::scale(rates[i], l));
    }
    out
}

/// Checks the inputs: `times` strictly increasing and finite, one finite rate per time,
/// `q0` finite with |q0| = 1 to [`Q0_NORM_TOLERANCE`]. Returns the normalised q0.
pub fn check_inputs(times: &[f64], rates: &[Vec3], q0: Quat) -> Result<Quat> {
    if times.is_empty() {
        return Err(Error::invalid("times", "expected at least one time, got none"));
    }
    if rates.len() != times.len() {
        return Err(Error::invalid(
            "angular_velocity",
            format!("expected {} rates (one per time), got {}", times.len(), rates.len()),
        ));
    }
    crate::spline::check_increasing("times", times, false)?;
    for (i, r) in rates.iter().enumerate() {
        if !r.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite { arg: "angular_velocity", index: i });
        }
    }
    if !q0.is_finite() {
        return Err(Error::NonFinite { arg: "q0", index: 0 });
    }
    let n = q0.norm();
    if (n - 1.0).abs() > Q0_NORM_TOLERANCE || n.is_nan() {
        return Err(Error::invalid(
            "q0",
            format!(
                "not a rotation: |q0| = {}, expected a unit quaternion (within {Q0_NORM_TOLERANCE})",
                Short(n)
            ),
        ));
    }
    Ok(q0.scale(1.0 / n))
}

/// The rotation vector of step k (see the module doc).
#[inline]
fn step(times: &[f64], rates: &[Vec3], k: usize, frame: Frame, model: RateModel) -> Vec3 {
    let h = times[k + 1] - times[k];
    let (w1, w2) = match model {
        RateModel::Zoh => return vec3::scale(rates[k], h),
        RateModel::Linear => {
            let d = vec3::sub(rates[k + 1], rates[k]);
            (vec3::add(rates[k], vec3::scale(d, C1)), vec3::add(rates[k], vec3::scale(d, C2)))
        }
        RateModel::Cubic => {
            let n = times.len();
            let m = n.min(4);
            let lo = k.saturating_sub(1).min(n - m);
            let (x1, x2) = (times[k] + C1 * h, times[k] + C2 * h);
            (lagrange(times, rates, lo, m, x1), lagrange(times, rates, lo, m, x2))
        }
    };
    let sign = if frame == Frame::Body { 1.0 } else { -1.0 };
    vec3::add(
        vec3::scale(vec3::add(w1, w2), 0.5 * h),
        vec3::scale(vec3::cross(w1, w2), sign * SQRT3_12 * h * h),
    )
}

/// Orientations at every time (the first is q₀), see the module doc.
pub fn integrate(
    times: &[f64],
    rates: &[Vec3],
    q0: Quat,
    frame: Frame,
    model: RateModel,
) -> Result<Vec<Quat>> {
    let mut q = check_inputs(times, rates, q0)?;
    let mut out = Vec::with_capacity(times.len());
    out.push(q);
    for k in 0..times.len() - 1 {
        let phi = step(times, rates, k, frame, model);
        let e = Quat::pure(vec3::scale(phi, 0.5)).exp();
        q = if frame == Frame::Body { q * e } else { e * q };
        q = q.scale(1.0 / q.norm());
        if !q.is_finite() {
            return Err(Error::invalid(
                "angular_velocity",
                format!("the rotation overflowed at step {k}; rates × steps are too large"),
            ));
        }
        out.push(q);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Quat, b: Quat, tol: f64) -> bool {
        (a - b).norm() <= tol || (a + b).norm() <= tol
    }

    #[test]
    fn constant_rate_is_exact_for_every_model() {
        let w = [0.3, -1.2, 0.7];
        let t: Vec<f64> = (0..11).map(|i| 0.1 * i as f64 + 0.03 * (i % 3) as f64).collect();
        let r = vec![w; t.len()];
        let q0 = Quat::new(0.5, 0.5, -0.5, 0.5);
        let span = t[t.len() - 1] - t[0];
        let rot = Quat::pure(vec3::scale(w, 0.5 * span)).exp();
        for model in [RateModel::Zoh, RateModel::Linear, RateModel::Cubic] {
            let body = integrate(&t, &r, q0, Frame::Body, model).unwrap();
            assert!(close(body[t.len() - 1], q0 * rot, 1e-14), "{model:?}");
            let world = integrate(&t, &r, q0, Frame::World, model).unwrap();
            assert!(close(world[t.len() - 1], rot * q0, 1e-14), "{model:?}");
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        let q = Quat::IDENTITY;
        let r = [[0.0; 3]; 3];
        assert!(integrate(&[0.0, 1.0, 1.0], &r, q, Frame::Body, RateModel::Zoh).is_err());
        assert!(integrate(&[0.0, 1.0], &r, q, Frame::Body, RateModel::Zoh).is_err());
        assert!(integrate(&[0.0, 1.0, 2.0], &r, q.scale(2.0), Frame::Body, RateModel::Zoh).is_err());
        assert!(integrate(&[], &[], q, Frame::Body, RateModel::Zoh).is_err());
    }
}
