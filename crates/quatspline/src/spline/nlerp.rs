//! Piecewise NLerp: normalised linear interpolation between consecutive keys (seed 001).
//!
//! Segment i, u = (τ − τᵢ)/hᵢ: q(τ) = ((1−u) qᵢ + u qᵢ₊₁) / |(1−u) qᵢ + u qᵢ₊₁|, keys
//! sign-aligned (shortest arc). Same path as slerp, non-constant speed (fastest mid-segment).
//! C⁰ at keys; interpolating. A baseline kept for comparison.

use super::{local, prepare_keys, prepare_times, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{JQuat, Jet};
use crate::quat::Quat;

/// NLerp between consecutive keys.
#[derive(Debug, Clone)]
pub struct PiecewiseNlerp {
    keys: Vec<Quat>,
    times: Vec<f64>,
}

impl PiecewiseNlerp {
    pub fn new(keys: &[Quat], times: Option<&[f64]>) -> Result<Self> {
        let keys = prepare_keys(keys, "quats", 2, true)?;
        let times = prepare_times(times, keys.len())?;
        Ok(PiecewiseNlerp { keys, times })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        let v = Jet::<N>::constant(1.0) - u;
        let l = JQuat::constant(self.keys[i]).scale(v) + JQuat::constant(self.keys[i + 1]).scale(u);
        l.scale(l.dot(l).sqrt().recip())
    }
}

impl Spline for PiecewiseNlerp {
    segment_jets!();
    fn name(&self) -> &'static str {
        "nlerp"
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        0
    }
}
