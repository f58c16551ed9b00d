//! Catmull–Rom quaternion spline (Gortler, "Foundations of 3D Computer Graphics" ch. 9;
//! seed 002; MATH.md §4).
//!
//! Segment i is a cubic spherical Bézier (de Casteljau with slerp) with control points
//! cᵢ, dᵢ, eᵢ, cᵢ₊₁, where dᵢ = exp(hᵢ Wᵢ/3) cᵢ and eᵢ = exp(−hᵢ Wᵢ₊₁/3) cᵢ₊₁ and the key's
//! world-frame tangent is Wᵢ = log(cᵢ₊₁ cᵢ₋₁⁻¹)/(hᵢ₋₁ + hᵢ) (the base negated when its w < 0).
//! For uniform times this is exactly Gortler's dᵢ = (cᵢ₊₁ cᵢ₋₁⁻¹)^{1/6} cᵢ,
//! eᵢ = (cᵢ₊₂ cᵢ⁻¹)^{−1/6} cᵢ₊₁; for non-uniform times both sides of a key get the tangent
//! Wᵢ cᵢ in time, so the curve is C¹ in time. Interpolating.
//! Ends: phantom keys by reflection (W₀ = log(c₁ c₀⁻¹)/h₀, so two keys give exactly slerp), or
//! by duplication (c₋₁ = c₀ as in MATH.md §4: W₀ = log(c₁ c₀⁻¹)/(2h₀)).

use super::{de_casteljau, local, prepare_keys, prepare_times, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::vec3;

/// How the missing neighbours of the end keys are made up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CatmullRomEnds {
    /// c₋₁ = c₀ c₁⁻¹ c₀ (mirror): end tangent = chord rate; two keys give slerp.
    Reflect,
    /// c₋₁ = c₀ (Gortler / MATH.md): end tangent = half the chord rate.
    Duplicate,
}

/// Catmull–Rom spline through keys at times.
#[derive(Debug, Clone)]
pub struct CatmullRom {
    times: Vec<f64>,
    ctrl: Vec<[Quat; 4]>,
    logs: Vec<[Axis; 3]>,
}

fn log_canonical(q: Quat) -> [f64; 3] {
    q.canonical().log().vec()
}

impl CatmullRom {
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: CatmullRomEnds,
        canonicalize: bool,
    ) -> Result<Self> {
        let c = prepare_keys(keys, "quats", 2, canonicalize)?;
        let times = prepare_times(times, c.len())?;
        let n = c.len();
        let h: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let end_div = match ends {
            CatmullRomEnds::Reflect => 1.0,
            CatmullRomEnds::Duplicate => 2.0,
        };
        let tangent: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                if i == 0 {
                    vec3::scale(log_canonical(c[1] * c[0].conj()), 1.0 / (end_div * h[0]))
                } else if i == n - 1 {
                    vec3::scale(log_canonical(c[n - 1] * c[n - 2].conj()), 1.0 / (end_div * h[n - 2]))
                } else {
                    vec3::scale(log_canonical(c[i + 1] * c[i - 1].conj()), 1.0 / (h[i - 1] + h[i]))
                }
            })
            .collect();
        let mut ctrl = Vec::with_capacity(n - 1);
        let mut logs = Vec::with_capacity(n - 1);
        for i in 0..n - 1 {
            let d = Quat::pure(vec3::scale(tangent[i], h[i] / 3.0)).exp() * c[i];
            let e = Quat::pure(vec3::scale(tangent[i + 1], -h[i] / 3.0)).exp() * c[i + 1];
            let seg = [c[i], d.canonical_to(c[i]), e.canonical_to(c[i + 1]), c[i + 1]];
            logs.push(std::array::from_fn(|j| Axis::from_log((seg[j].conj() * seg[j + 1]).log().vec())));
            ctrl.push(seg);
        }
        Ok(CatmullRom { times, ctrl, logs })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        de_casteljau(&self.ctrl[i], &self.logs[i], u)
    }
}

impl Spline for CatmullRom {
    segment_jets!();
    fn name(&self) -> &'static str {
        "catmull_rom"
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
