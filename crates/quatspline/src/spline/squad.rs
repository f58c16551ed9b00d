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

use super::{local, prepare_keys, prepare_times, segment_jets, Spline};
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
}

impl Squad {
    pub fn new(keys: &[Quat], times: Option<&[f64]>, canonicalize: bool) -> Result<Self> {
        let keys = prepare_keys(keys, "quats", 2, canonicalize)?;
        let times = prepare_times(times, keys.len())?;
        let n = keys.len();
        let raw: Vec<[f64; 3]> = keys.windows(2).map(|w| (w[0].conj() * w[1]).log().vec()).collect();
        let h: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let mut s_out = keys.clone();
        let mut s_in = keys.clone();
        for i in 1..n - 1 {
            let m0 = vec3::scale(raw[i - 1], 1.0 / h[i - 1]);
            let m1 = vec3::scale(raw[i], 1.0 / h[i]);
            let v = vec3::scale(
                vec3::add(vec3::scale(m0, h[i]), vec3::scale(m1, h[i - 1])),
                1.0 / (h[i - 1] + h[i]),
            );
            let lo = vec3::scale(vec3::sub(vec3::scale(v, h[i]), raw[i]), 0.5);
            let li = vec3::scale(vec3::sub(raw[i - 1], vec3::scale(v, h[i - 1])), 0.5);
            s_out[i] = keys[i] * Quat::pure(lo).exp();
            s_in[i] = keys[i] * Quat::pure(li).exp();
        }
        let inner_logs =
            (0..n - 1).map(|i| Axis::from_log((s_out[i].conj() * s_in[i + 1]).log().vec())).collect();
        let logs = raw.iter().map(|&v| Axis::from_log(v)).collect();
        Ok(Squad { keys, times, logs, s_out, inner_logs })
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
}
