//! Cumulative spherical Bézier curve (Kim, Kim & Shin 1995; seeds 002, 003; MATH.md §4).
//!
//! q(u) = q₀ Π_{j=1..n} (q_{j−1}* q_j)^{B̃_{j,n}(u)}, B̃_{j,n} = Σ_{i≥j} B_{i,n} (Bernstein).
//! Cubic: B̃₁ = 1−(1−u)³, B̃₂ = 3u²−2u³, B̃₃ = u³. Passes through q₀ and qₙ with the same end
//! tangents as the de Casteljau curve, but it is a different curve in between. One curve on
//! u ∈ [0, 1]: C^∞. Every factor has a constant logarithm, so it is cheap to evaluate.

use super::{prepare_keys, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable, SegmentForm};

/// One cumulative Bézier curve of any degree on u ∈ [0, 1].
#[derive(Debug, Clone)]
pub struct CumulativeBezier {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    binom: Vec<f64>,
    joints: [f64; 2],
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
}

impl CumulativeBezier {
    /// Control points q₀ … qₙ (n ≥ 1).
    /// `domain` (t₀, t₁) maps u = (t − t₀)/(t₁ − t₀); (0, 1) is the plain curve.
    pub fn new(ctrl: &[Quat], domain: (f64, f64), canonicalize: bool) -> Result<Self> {
        let joints = super::check_domain(domain)?;
        let ctrl = prepare_keys(ctrl, "control_points", 2, canonicalize)?;
        let logs = super::chain_logs(&ctrl);
        let n = ctrl.len() - 1;
        let mut binom = vec![1.0; n + 1];
        for i in 1..=n {
            binom[i] = binom[i - 1] * (n + 1 - i) as f64 / i as f64;
        }
        // factor j's weight B̃_j = Σ_{l≥j} B_{l,n}: Bernstein coefficients 1 from l = j on
        let batch = CumulativeTable::new(&joints, Basis::Bernstein, |_| SegmentForm {
            base: ctrl[0],
            factors: (1..=n)
                .map(|j| (logs[j - 1], (0..=n).map(|l| if l >= j { 1.0 } else { 0.0 }).collect()))
                .collect(),
        });
        Ok(CumulativeBezier { ctrl, logs, binom, joints, batch })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, _seg: usize, t: f64) -> JQuat<N> {
        let n = self.ctrl.len() - 1;
        let u = super::local::<N>(t, self.joints[0], self.joints[1]);
        let v = Jet::<N>::constant(1.0) - u;
        // Bernstein B_{i,n} as jets, then suffix sums B̃_j.
        let mut up = vec![Jet::<N>::constant(1.0); n + 1];
        let mut vp = vec![Jet::<N>::constant(1.0); n + 1];
        for i in 1..=n {
            up[i] = up[i - 1] * u;
            vp[i] = vp[i - 1] * v;
        }
        let mut q = JQuat::constant(self.ctrl[0]);
        let mut tail = Jet::<N>::constant(0.0);
        let mut cum = vec![Jet::<N>::constant(0.0); n + 1];
        for i in (1..=n).rev() {
            tail = tail + up[i] * vp[n - i] * self.binom[i];
            cum[i] = tail;
        }
        for j in 1..=n {
            q = q * JQuat::exp_axis(&self.logs[j - 1], cum[j]);
        }
        q
    }
}

impl Spline for CumulativeBezier {
    segment_jets!();
    fn name(&self) -> &'static str {
        "cumulative_bezier"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        u8::MAX
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
}
