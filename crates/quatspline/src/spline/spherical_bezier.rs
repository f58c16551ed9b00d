//! Spherical Bézier curve by de Casteljau's algorithm with slerp (Shoemake 1985; seeds 002,
//! 003; MATH.md §4).
//!
//! Degree n, control points b₀ … bₙ: b_j^r = slerp(b_j^{r−1}, b_{j+1}^{r−1}; u), the curve is
//! b₀ⁿ(u), u ∈ [0, 1]. It passes through b₀ and bₙ with end tangents q'(0) = n b₀ log(b₀* b₁),
//! q'(1) = n bₙ log(bₙ₋₁* bₙ). One curve: C^∞ on [0, 1]. A cubic costs 6 slerps (seed 003's
//! eq. 5.2 is misprinted). Consecutive control points are sign-aligned by default.
//!
//! Cost: de Casteljau takes n(n+1)/2 slerps per sample, so the degree is capped at
//! [`MAX_DEGREE`] (a curve through 400 keys took 149 s for a 3,000-sample comparison). Values
//! of every degree go through the batch kernel (`crate::simd::slerp`: one lane per sample, the
//! pyramid of slerps vectorised across samples); its cost is the slerp count times the vector
//! slerp's, so it grows as n²: on one idle AVX-512 core about 35 ns per sample at 8 control
//! points, 1 µs near 56 and 1.4 µs at 65, about 0.7 ns per slerp (`benchmarks/corners.py`).
//! One Bézier curve of high
//! degree through many keys is not a useful method anyway: it only passes through the end
//! points and averages the rest away. For many keys use a spline with local support
//! (`CumulativeBSpline`, registry "bspline") or `CumulativeBezier` (O(n) per sample).

use super::{prepare_keys, segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;

/// de Casteljau with slerp on jets. `logs[j]` = log(ctrl[j]* ctrl[j+1]) (vector part) saves the
/// first level's logarithms, which do not depend on u.
#[inline(always)]
pub fn de_casteljau<const N: usize>(ctrl: &[Quat], logs: &[Axis], u: Jet<N>) -> JQuat<N> {
    let n = ctrl.len();
    if n == 1 {
        return JQuat::constant(ctrl[0]);
    }
    const STACK: usize = 8;
    let mut stack = [JQuat::constant(Quat::IDENTITY); STACK];
    let mut heap = Vec::new();
    let b: &mut [JQuat<N>] = if n - 1 <= STACK {
        &mut stack[..n - 1]
    } else {
        heap.resize(n - 1, JQuat::constant(Quat::IDENTITY));
        &mut heap
    };
    for (j, bj) in b.iter_mut().enumerate() {
        *bj = JQuat::constant(ctrl[j]) * JQuat::exp_axis(&logs[j], u);
    }
    for level in (1..n - 1).rev() {
        for j in 0..level {
            b[j] = JQuat::slerp(b[j], b[j + 1], u);
        }
    }
    b[0]
}

/// The highest degree a spherical Bézier curve takes (65 control points, 2,080 slerps per sample).
pub const MAX_DEGREE: usize = 64;

/// One spherical Bézier curve of degree up to [`MAX_DEGREE`] on u ∈ [0, 1].
#[derive(Debug, Clone)]
pub struct SphericalBezier {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    joints: [f64; 2],
    /// Flat data of the batch kernel (`crate::simd::slerp`), up to its point limit.
    batch: Option<crate::simd::slerp::SlerpTable>,
}

impl SphericalBezier {
    /// Control points b₀ … bₙ (n ≥ 1).
    /// `domain` (t₀, t₁) maps u = (t − t₀)/(t₁ − t₀); (0, 1) is the plain curve.
    pub fn new(ctrl: &[Quat], domain: (f64, f64), canonicalize: bool) -> Result<Self> {
        let joints = super::check_domain(domain)?;
        if ctrl.len() > MAX_DEGREE + 1 {
            return Err(Error::invalid(
                "control_points",
                format!(
                    "{} control points (degree {}): a spherical Bézier curve is limited to degree \
                     {MAX_DEGREE} ({} control points), since de Casteljau costs O(n²) slerps per \
                     sample; for many keys use the cumulative B-spline (CumulativeBSpline, method \
                     'bspline') or CumulativeBezier (O(n) per sample)",
                    ctrl.len(),
                    ctrl.len() - 1,
                    MAX_DEGREE + 1
                ),
            ));
        }
        let ctrl = prepare_keys(ctrl, "control_points", 2, canonicalize)?;
        let logs = super::chain_logs(&ctrl);
        let batch = crate::simd::slerp::SlerpTable::casteljau(&joints, &[&ctrl[..]], &[&logs[..]]);
        Ok(SphericalBezier { ctrl, logs, joints, batch })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, _seg: usize, t: f64) -> JQuat<N> {
        de_casteljau(&self.ctrl, &self.logs, super::local::<N>(t, self.joints[0], self.joints[1]))
    }
}

impl Spline for SphericalBezier {
    segment_jets!();
    fn name(&self) -> &'static str {
        "bezier"
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (issue 2.1 item 6): degree was unbounded and cost O(n²) per sample.
    #[test]
    fn degree_above_the_cap_is_refused_naming_limit_and_alternative() {
        let ok = vec![Quat::IDENTITY; MAX_DEGREE + 1];
        assert!(SphericalBezier::new(&ok, (0.0, 1.0), false).is_ok());
        let bad = vec![Quat::IDENTITY; MAX_DEGREE + 2];
        let e = SphericalBezier::new(&bad, (0.0, 1.0), false).unwrap_err().to_string();
        assert!(e.starts_with("control_points: 66 control points (degree 65)"), "{e}");
        assert!(e.contains("degree 64") && e.contains("bspline"), "{e}");
    }
}
