//! Piecewise LinMat: rotation matrices interpolated entrywise and projected back to SO(3)
//! (seed 002's naive baseline; MATH.md §2).
//!
//! For keys Rᵢ, Rᵢ₊₁ with relative rotation Rᵢᵀ Rᵢ₊₁ by φ about n, the polar factor of
//! (1−u) Rᵢ + u Rᵢ₊₁ is Rᵢ · Rot(n, ψ(u)) with ψ(u) = atan2(u sin φ, 1 − u + u cos φ): the
//! same path as slerp with a non-uniform speed (closed form, so derivatives are exact). At
//! φ = π and u = ½ the mean matrix is singular and the projection is undefined (ψ jumps).
//! C⁰ at keys; interpolating.

use super::{local, prepare_keys, prepare_times, segment_jets, Spline};
use crate::error::Result;
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;

/// Projected matrix lerp between consecutive keys.
#[derive(Debug, Clone)]
pub struct PiecewiseLinMat {
    keys: Vec<Quat>,
    axis: Vec<Axis>,
    angle: Vec<f64>,
    times: Vec<f64>,
}

impl PiecewiseLinMat {
    pub fn new(keys: &[Quat], times: Option<&[f64]>) -> Result<Self> {
        let keys = prepare_keys(keys, "quats", 2, true)?;
        let times = prepare_times(times, keys.len())?;
        let (mut axis, mut angle) = (Vec::new(), Vec::new());
        for w in keys.windows(2) {
            let l = Axis::from_log((w[0].conj() * w[1]).log().vec());
            // unit-angle axis: exp_axis(ψ/2) = exp(ψ/2 · n)
            axis.push(Axis { n: if l.a > 0.0 { l.n } else { [1.0, 0.0, 0.0] }, a: 1.0 });
            angle.push(2.0 * l.a);
        }
        Ok(PiecewiseLinMat { keys, axis, angle, times })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        let (s, c) = self.angle[i].sin_cos();
        let psi = Jet::atan2(u * s, Jet::<N>::constant(1.0) - u + u * c);
        JQuat::constant(self.keys[i]) * JQuat::exp_axis(&self.axis[i], psi * 0.5)
    }
}

impl Spline for PiecewiseLinMat {
    segment_jets!();
    fn name(&self) -> &'static str {
        "lin_mat"
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
