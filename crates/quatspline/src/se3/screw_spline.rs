//! Screw-motion splines on unit dual quaternions (seed 001; MATH.md §3, §8), with exact
//! derivatives.
//!
//! Pose keys Q̂ₖ = rₖ + ε ½ (0, pₖ) rₖ at times τₖ, consecutive keys sign-aligned:
//! - piecewise (`smooth = false`): Q̂(τ) = Q̂ᵢ (Q̂ᵢ* Q̂ᵢ₊₁)^u, u = (τ − τᵢ)/hᵢ — one constant
//!   screw motion per segment (ScLerp); interpolating, C⁰ at keys.
//! - smooth: the C³ spline's cumulative form Q̂(τ) = P̂ᵢ₋₁ Ŵᵢ^{C̃₁(u)} Ŵᵢ₊₁^{C̃₂(u)} Ŵᵢ₊₂^{C̃₃(u)},
//!   Ŵₖ = P̂ₖ₋₁* P̂ₖ (P̂ the keys with the ends doubled), C̃ⱼ the knot-variant weights of
//!   [`crate::spline::C3Spline`] (α, β per key): interpolating and C³ in time for rotation and
//!   translation together (the weights are C³ and the factors smooth screw motions; the
//!   argument of MATH.md §8 holds in any Lie group).
//!
//! Every factor is a [`ScrewPow`] to a jet exponent, so the rotation and the position have
//! exact first to third time derivatives; the continuity claim is checked by the certificate
//! on both the real and the dual part.

use super::{pose_keys, trunc, JDual, PoseCurve, ScrewPow};
use crate::dual_quat::DualQuat;
use crate::error::Result;
use crate::jet::{JQuat, Jet};
use crate::quat::Quat;
use crate::spline::{prepare_times, C3Spline, C3Variant, Spline};
use crate::vec3::Vec3;

/// A screw-motion spline through pose keys.
#[derive(Debug, Clone)]
pub struct ScrewSpline {
    keys: Vec<DualQuat>,
    times: Vec<f64>,
    smooth: bool,
    /// piecewise: ScLerp factors per segment; smooth: Ŵ₁ … Ŵ_{N+1}.
    pows: Vec<ScrewPow>,
    /// smooth: the padded keys P̂₀ … P̂_{N+1}.
    padded: Vec<DualQuat>,
    weights: Vec<[[f64; 8]; 3]>,
}

impl ScrewSpline {
    /// Keys (rotations, positions) at `times` (default 0, 1, …); `alpha`, `beta` (one value or
    /// one per key) only matter for `smooth`.
    pub fn new(
        quats: &[Quat],
        positions: &[Vec3],
        times: Option<&[f64]>,
        smooth: bool,
        alpha: &[f64],
        beta: &[f64],
    ) -> Result<Self> {
        let keys = pose_keys(quats, positions, "quats", 2)?;
        let n = keys.len();
        let times = prepare_times(times, n)?;
        if !smooth {
            let pows = keys.windows(2).map(|w| ScrewPow::new(w[0].conj() * w[1])).collect();
            return Ok(ScrewSpline { keys, times, smooth, pows, padded: Vec::new(), weights: Vec::new() });
        }
        let rots: Vec<Quat> = keys.iter().map(|k| k.r).collect();
        let c3 = C3Spline::new(&rots, Some(&times), alpha, beta, C3Variant::Knot, false)?;
        let weights = c3.cumulative_weights();
        let mut padded = Vec::with_capacity(n + 2);
        padded.push(keys[0]);
        padded.extend_from_slice(&keys);
        padded.push(keys[n - 1]);
        let pows = padded.windows(2).map(|w| ScrewPow::new(w[0].conj() * w[1])).collect();
        Ok(ScrewSpline { keys, times, smooth, pows, padded, weights })
    }

    /// The pose keys as unit dual quaternions (sign-aligned).
    pub fn keys(&self) -> &[DualQuat] {
        &self.keys
    }

    #[inline]
    fn pose<const N: usize>(&self, i: usize, t: f64) -> JDual<N> {
        let (t0, t1) = (self.times[i], self.times[i + 1]);
        let u = Jet::<N>::variable((t - t0) / (t1 - t0), 1.0 / (t1 - t0));
        if !self.smooth {
            return JDual::constant(self.keys[i]) * self.pows[i].pow(u);
        }
        let mut q = JDual::constant(self.padded[i]);
        for j in 0..3 {
            let w = Jet::poly(&self.weights[i][j], u);
            q = q * self.pows[i + j].pow(w);
        }
        q
    }
}

impl PoseCurve for ScrewSpline {
    fn pose_jet1(&self, seg: usize, t: f64) -> JDual<1> {
        self.pose::<1>(seg, t)
    }
    fn pose_jet4(&self, seg: usize, t: f64) -> JDual<4> {
        self.pose::<4>(seg, t)
    }
}

impl Spline for ScrewSpline {
    fn name(&self) -> &'static str {
        if self.smooth {
            "screw_smooth"
        } else {
            "screw"
        }
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        if self.smooth {
            3
        } else {
            0
        }
    }
    fn segment_jet1(&self, seg: usize, t: f64) -> JQuat<1> {
        self.pose::<1>(seg, t).r
    }
    fn segment_jet2(&self, seg: usize, t: f64) -> JQuat<2> {
        self.pose::<2>(seg, t).r
    }
    fn segment_jet3(&self, seg: usize, t: f64) -> JQuat<3> {
        self.pose::<3>(seg, t).r
    }
    fn segment_jet4(&self, seg: usize, t: f64) -> JQuat<4> {
        trunc(self.pose::<4>(seg, t).r)
    }
}
