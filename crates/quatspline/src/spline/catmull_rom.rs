//! Catmull–Rom quaternion spline (Gortler, "Foundations of 3D Computer Graphics" ch. 9;
//! seed 002; MATH.md §4): the Kochanek–Bartels spline of `kochanek_bartels.rs` at
//! tension = continuity = bias = 0.
//!
//! Segment i is a cubic spherical Bézier (de Casteljau with slerp) with control points
//! cᵢ, dᵢ, eᵢ, cᵢ₊₁, where dᵢ = exp(hᵢ Wᵢ/3) cᵢ and eᵢ = exp(−hᵢ Wᵢ₊₁/3) cᵢ₊₁ and the key's
//! world-frame rate is Wᵢ = ½(λ + μ) log(cᵢ₊₁ cᵢ₋₁⁻¹) + ½(μ − λ)(Δ⁺ − Δ⁻),
//! λ = h⁺/(h⁻(h⁻ + h⁺)), μ = h⁻/(h⁺(h⁻ + h⁺)) (the non-uniform Catmull–Rom / Barry–Goldman
//! tangent λΔ⁻ + μΔ⁺ lifted to the group). For uniform times λ = μ and this is exactly
//! Gortler's dᵢ = (cᵢ₊₁ cᵢ₋₁⁻¹)^{1/6} cᵢ, eᵢ = (cᵢ₊₂ cᵢ⁻¹)^{−1/6} cᵢ₊₁; both sides of a key get
//! the same rate Wᵢ in time, so the curve is C¹ in time. Interpolating.
//! Ends: phantom keys by reflection (W₀ = log(c₁ c₀⁻¹)/h₀, so two keys give exactly slerp), by
//! duplication (c₋₁ = c₀ as in MATH.md §4: W₀ = log(c₁ c₀⁻¹)/(2h₀)), at rest (W = 0) or closed.
//! α parametrisation for keys without times (0 uniform, ½ centripetal, 1 chordal): see
//! `kochanek_bartels.rs`.

use super::kochanek_bartels::{KochanekBartels, TcbEnds, CATMULL_ROM};
use super::{segment_jets, Spline};
use crate::error::Result;
use crate::jet::JQuat;
use crate::quat::Quat;

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
    inner: KochanekBartels,
}

impl CatmullRom {
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: CatmullRomEnds,
        canonicalize: bool,
    ) -> Result<Self> {
        let ends = match ends {
            CatmullRomEnds::Reflect => TcbEnds::Reflect,
            CatmullRomEnds::Duplicate => TcbEnds::Duplicate,
        };
        Self::with_keyframes(keys, times, None, ends, false, canonicalize)
    }

    /// With keyframe control: α for keys without times, rest/closed ends, holds.
    pub fn with_keyframes(
        keys: &[Quat],
        times: Option<&[f64]>,
        alpha: Option<f64>,
        ends: TcbEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        let inner = KochanekBartels::build(
            keys,
            times,
            alpha,
            CATMULL_ROM,
            ends,
            holds,
            canonicalize,
            "catmull_rom",
        )?;
        Ok(CatmullRom { inner })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        self.inner.segment_jet_n::<N>(i, t)
    }
}

impl Spline for CatmullRom {
    segment_jets!();
    fn name(&self) -> &'static str {
        "catmull_rom"
    }
    fn joints(&self) -> &[f64] {
        self.inner.joints()
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        self.inner.continuity()
    }
    fn closed(&self) -> bool {
        self.inner.closed()
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.inner.batch_kernel()
    }
}
