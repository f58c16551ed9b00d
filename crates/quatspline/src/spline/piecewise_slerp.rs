//! Piecewise slerp: the C⁰ baseline (seeds 001, 003; MATH.md §2).
//!
//! Segment i on [τᵢ, τᵢ₊₁], u = (τ − τᵢ)/hᵢ: q(τ) = qᵢ exp(u ωᵢ), ωᵢ = log(qᵢ* qᵢ₊₁).
//! Constant angular speed 2|ωᵢ|/hᵢ within a segment; the velocity jumps at keys, so the curve
//! is C⁰ (interpolating). Two keys: plain slerp.

use super::{local, prepare_keys, prepare_times, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable};

/// Slerp between consecutive keys.
#[derive(Debug, Clone)]
pub struct PiecewiseSlerp {
    keys: Vec<Quat>,
    times: Vec<f64>,
    logs: Vec<Axis>,
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
}

impl PiecewiseSlerp {
    /// Keys (normalised; consecutive keys sign-aligned unless `canonicalize` is false) at
    /// `times` (default 0, 1, …). Needs two keys.
    pub fn new(keys: &[Quat], times: Option<&[f64]>, canonicalize: bool) -> Result<Self> {
        let keys = prepare_keys(keys, "quats", 2, canonicalize)?;
        let times = prepare_times(times, keys.len())?;
        let logs = super::chain_logs(&keys);
        const LINEAR: [f64; 2] = [0.0, 1.0];
        let batch = CumulativeTable::with_shape(&times, Basis::Power, 1, 1, |i, factors| {
            factors.push((logs[i], &LINEAR[..]));
            keys[i]
        });
        Ok(PiecewiseSlerp { keys, times, logs, batch })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        JQuat::constant(self.keys[i]) * JQuat::exp_axis(&self.logs[i], u)
    }
}

impl Spline for PiecewiseSlerp {
    segment_jets!();
    fn name(&self) -> &'static str {
        "slerp"
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
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
}
