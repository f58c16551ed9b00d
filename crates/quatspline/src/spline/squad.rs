//! Squad, spherical quadrangle interpolation (Shoemake 1987; seed 003; MATH.md §5).
//!
//! Segment i, u = (τ − τᵢ)/hᵢ:
//! Squad(qᵢ, sᵢ⁺, sᵢ₊₁⁻, qᵢ₊₁; u) = Slerp(Slerp(qᵢ, qᵢ₊₁; u), Slerp(sᵢ⁺, sᵢ₊₁⁻; u); 2u(1−u)).
//! Control points: with ωᵢ = log(qᵢ* qᵢ₊₁) and a key velocity vᵢ (q' = qᵢ vᵢ in time), the
//! two derivative equations of MATH.md §5 give
//! log(qᵢ* sᵢ⁺) = (hᵢ vᵢ − ωᵢ)/2 and log(qᵢ* sᵢ⁻) = (ωᵢ₋₁ − hᵢ₋₁ vᵢ)/2,
//! with vᵢ the time-weighted Catmull–Rom average (hᵢ mᵢ₋₁ + hᵢ₋₁ mᵢ)/(hᵢ₋₁ + hᵢ), mₖ = ωₖ/hₖ.
//! For uniform keys both reduce to Shoemake's sᵢ = qᵢ exp((ωᵢ₋₁ − ωᵢ)/4). Ends: s₀⁺ = q₀,
//! sₙ⁻ = qₙ. C¹ in time (not C², seed 003 is wrong there); interpolating; 2 keys = slerp.
//! Keyframe control (`with_keyframes`): rest ends, closed loops and holds by the same key
//! velocity equations (zero velocity at rest ends and at the keys bounding a hold).

use super::keyframe::{prepare_loop, KeyEnds};
use super::{local, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::vec3;

/// Squad through keys at times, C¹ in time also for non-uniform times.
#[derive(Debug, Clone)]
pub struct Squad {
    keys: Vec<Quat>,
    times: Vec<f64>,
    logs: Vec<Axis>,
    s_out: Vec<Quat>,
    inner_logs: Vec<Axis>,
    closed: bool,
    /// Flat per-segment data of the batch kernel (`crate::simd::slerp`).
    batch: crate::simd::slerp::SlerpTable,
}

impl Squad {
    pub fn new(keys: &[Quat], times: Option<&[f64]>, canonicalize: bool) -> Result<Self> {
        Self::with_keyframes(keys, times, KeyEnds::Open, false, canonicalize)
    }

    /// With keyframe control (`keyframe.rs`): `Rest` ends (zero key velocity at both ends:
    /// s₀⁺ = q₀ exp(−ω₀/2), sₙ⁻ = qₙ exp(ωₙ₋₁/2)), `Closed` loops (every key interior, cyclic
    /// neighbours, at least 3 keys; C¹ across the seam), holds (zero key velocity at the keys
    /// bounding a hold: then sᵢ⁺ = qᵢ = sᵢ₊₁⁻ on the hold and it is exactly constant).
    pub fn with_keyframes(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: KeyEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        let closed = ends == KeyEnds::Closed;
        let mut kl = prepare_loop(keys, times, closed, if closed { 3 } else { 2 }, "squad", canonicalize)?;
        if holds {
            kl.align_holds();
        }
        let n = kl.keys.len();
        let segs = kl.segments();
        let joint_keys: Vec<Quat> = super::par_map(segs + 1, |j| kl.key_at_joint(j));
        let raw: Vec<[f64; 3]> =
            super::par_map(segs, |i| (joint_keys[i].conj() * joint_keys[i + 1]).log().vec());
        let h: Vec<f64> = (0..segs).map(|i| kl.h(i)).collect();
        let hold = if holds { kl.hold_keys() } else { vec![false; n] };
        // per joint j, (sⱼ⁺, sⱼ⁻): independent of every other joint's, computed in parallel
        let s_pair = super::par_map(segs + 1, |j| {
            let k = kl.key_index(j);
            let left = if j > 0 {
                Some(j - 1)
            } else if closed {
                Some(segs - 1)
            } else {
                None
            };
            let right = if j < segs {
                Some(j)
            } else if closed {
                Some(0)
            } else {
                None
            };
            let v = match (left, right) {
                _ if hold[k] => Some([0.0; 3]),
                (Some(l), Some(r)) => {
                    let m0 = vec3::scale(raw[l], 1.0 / h[l]);
                    let m1 = vec3::scale(raw[r], 1.0 / h[r]);
                    Some(vec3::scale(
                        vec3::add(vec3::scale(m0, h[r]), vec3::scale(m1, h[l])),
                        1.0 / (h[l] + h[r]),
                    ))
                }
                _ if ends == KeyEnds::Rest => Some([0.0; 3]),
                _ => None, // open ends: s₀⁺ = q₀, sₙ⁻ = qₙ
            };
            let (mut so, mut si) = (joint_keys[j], joint_keys[j]);
            let Some(v) = v else { return (so, si) };
            if let Some(r) = right {
                let lo = vec3::scale(vec3::sub(vec3::scale(v, h[r]), raw[r]), 0.5);
                so = joint_keys[j] * Quat::pure(lo).exp();
            }
            if let Some(l) = left {
                let li = vec3::scale(vec3::sub(raw[l], vec3::scale(v, h[l])), 0.5);
                si = joint_keys[j] * Quat::pure(li).exp();
            }
            (so, si)
        });
        let s_out: Vec<Quat> = super::par_map(segs + 1, |j| s_pair[j].0);
        let inner_logs: Vec<Axis> =
            super::par_map(segs, |i| Axis::from_log((s_out[i].conj() * s_pair[i + 1].1).log().vec()));
        drop(s_pair);
        let logs: Vec<Axis> = super::par_map(segs, |i| Axis::from_log(raw[i]));
        let batch = crate::simd::slerp::SlerpTable::squad(&kl.times, &joint_keys, &logs, &s_out, &inner_logs);
        Ok(Squad { keys: joint_keys, times: kl.times, logs, s_out, inner_logs, closed, batch })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        let a = JQuat::constant(self.keys[i]) * JQuat::exp_axis(&self.logs[i], u);
        let b = JQuat::constant(self.s_out[i]) * JQuat::exp_axis(&self.inner_logs[i], u);
        let w = (u - u * u) * 2.0;
        JQuat::slerp(a, b, w)
    }
}

impl Spline for Squad {
    segment_jets!();
    fn name(&self) -> &'static str {
        "squad"
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        1
    }
    fn closed(&self) -> bool {
        self.closed
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        Some(&self.batch)
    }
}
