//! Uniform cumulative B-spline on SO(3) (Kim, Kim & Shin 1995; Sommer et al., CVPR 2020;
//! Sophus/basalt lineage; MATH.md §6).
//!
//! Order k (degree k−1), knot spacing Δt, start t₀. Segment i ∈ [0, n−k] spans
//! [t₀ + iΔt, t₀ + (i+1)Δt] and uses control rotations qᵢ … q_{i+k−1}:
//! q(u) = qᵢ Π_{j=1..k−1} exp(B̃ⱼ(u) ω_{i+j}), ω_m = log(q_{m−1}* q_m), u = (t − tᵢ)/Δt,
//! with the cumulative basis B̃ⱼ(u) = Σ_m M̃[j][m] u^m from the cumulative blending matrix.
//! Cubic (k = 4): B̃₁ = (5 + 3u − 3u² + u³)/6, B̃₂ = (1 + 3u + 3u² − 2u³)/6, B̃₃ = u³/6.
//! C^(k−2) in time (C² for the cubic default); approximating: it does not pass through the
//! control rotations. The domain is [t₀, t₀ + (n−k+1)Δt].

use super::{local, prepare_keys, segment_jets, Spline};
use crate::error::{Error, Result, Short};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable};

/// The cumulative blending matrix M̃ (k×k, row j = coefficients of B̃ⱼ in powers of u).
pub fn cumulative_blending_matrix(k: usize) -> Vec<Vec<f64>> {
    let binom = |n: usize, r: usize| -> f64 {
        if r > n {
            return 0.0;
        }
        (0..r).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    };
    let mut m = vec![vec![0.0; k]; k];
    for i in 0..k {
        for (j, row) in m.iter_mut().enumerate() {
            let mut sum = 0.0;
            for s in j..k {
                let sign = if (s - j) % 2 == 0 { 1.0 } else { -1.0 };
                sum += sign * binom(k, s - j) * ((k - s - 1) as f64).powi((k - 1 - i) as i32);
            }
            row[i] = binom(k - 1, k - 1 - i) * sum;
        }
    }
    for i in 0..k {
        for j in i + 1..k {
            for c in 0..k {
                m[i][c] += m[j][c];
            }
        }
    }
    let fact: f64 = (2..k).map(|v| v as f64).product();
    for row in m.iter_mut() {
        for v in row.iter_mut() {
            *v /= fact;
        }
    }
    m
}

/// Uniform cumulative B-spline of order k.
#[derive(Debug, Clone)]
pub struct CumulativeBSpline {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    basis: Vec<Vec<f64>>,
    order: usize,
    joints: Vec<f64>,
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`), built on the
    /// first batch evaluation: 640 bytes a segment for the cubic (20× the control points),
    /// which a spline that is never evaluated in bulk (a fit's result at 10⁶ samples) does
    /// not pay for.
    batch: std::sync::OnceLock<Option<CumulativeTable>>,
    closed: bool,
}

impl CumulativeBSpline {
    /// `ctrl`: n ≥ k control rotations; `dt` > 0; `order` k ≥ 2.
    pub fn new(ctrl: &[Quat], dt: f64, t0: f64, order: usize, canonicalize: bool) -> Result<Self> {
        Self::with_closed(ctrl, dt, t0, order, false, canonicalize)
    }

    /// `closed`: a periodic B-spline — the control rotations are used cyclically (the first
    /// k − 1 appended after the last), n segments over [t₀, t₀ + n Δt], C^(k−2) across the
    /// seam exactly as inside (it is the same uniform B-spline). Needs n ≥ k.
    pub fn with_closed(
        ctrl: &[Quat],
        dt: f64,
        t0: f64,
        order: usize,
        closed: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        if !(2..=12).contains(&order) {
            return Err(Error::invalid("order", format!("expected 2 ≤ order ≤ 12, got {order}")));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid(
                "dt",
                format!("expected a finite positive spacing, got {}", Short(dt)),
            ));
        }
        if !t0.is_finite() {
            return Err(Error::NonFinite { arg: "t0", index: 0 });
        }
        let mut ctrl = prepare_keys(ctrl, "control_quats", order, canonicalize)?;
        if closed {
            let n = ctrl.len();
            for j in 0..order - 1 {
                let next = ctrl[j];
                let prev = ctrl[n - 1 + j];
                ctrl.push(if canonicalize { next.canonical_to(prev) } else { next });
            }
        }
        let segs = ctrl.len() - order + 1;
        super::check_span("dt", t0, t0 + dt, 1)?;
        super::check_span("dt", t0, t0 + segs as f64 * dt, segs)?;
        // logs[j] = log(c_{j−1}* c_j), logs[0] unused (zero)
        let logs: Vec<Axis> = super::par_map(ctrl.len(), |j| {
            if j == 0 {
                Axis::default()
            } else {
                Axis::from_log((ctrl[j - 1].conj() * ctrl[j]).log().vec())
            }
        });
        let joints: Vec<f64> = (0..=segs).map(|i| t0 + i as f64 * dt).collect();
        let basis = cumulative_blending_matrix(order);
        let batch = std::sync::OnceLock::new();
        Ok(CumulativeBSpline { ctrl, logs, basis, order, joints, batch, closed })
    }

    /// The batch kernels' table (see the field `batch`).
    fn table(&self) -> Option<&CumulativeTable> {
        self.batch
            .get_or_init(|| {
                let (order, basis, logs, ctrl) = (self.order, &self.basis, &self.logs, &self.ctrl);
                let degree = basis[1..order].iter().map(|c| c.len().saturating_sub(1)).max().unwrap_or(0);
                CumulativeTable::with_shape(&self.joints, Basis::Power, order - 1, degree, |i, factors| {
                    factors.extend((1..order).map(|j| (logs[i + j], basis[j].as_slice())));
                    ctrl[i]
                })
            })
            .as_ref()
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.joints[i], self.joints[i + 1]);
        let mut q = JQuat::constant(self.ctrl[i]);
        for j in 1..self.order {
            let b = Jet::poly(&self.basis[j], u);
            q = q * JQuat::exp_axis(&self.logs[i + j], b);
        }
        q
    }
}

impl Spline for CumulativeBSpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "bspline"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        (self.order - 2) as u8
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.table().map(|b| b as &dyn crate::simd::BatchKernel)
    }
    fn closed(&self) -> bool {
        self.closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_basis_matches_math_md() {
        let m = cumulative_blending_matrix(4);
        let expect =
            [[1.0, 0.0, 0.0, 0.0], [5.0, 3.0, -3.0, 1.0], [1.0, 3.0, 3.0, -2.0], [0.0, 0.0, 0.0, 1.0]];
        for j in 0..4 {
            for c in 0..4 {
                let e = if j == 0 { expect[j][c] } else { expect[j][c] / 6.0 };
                assert!((m[j][c] - e).abs() < 1e-15, "M̃[{j}][{c}] = {}", m[j][c]);
            }
        }
    }
}
