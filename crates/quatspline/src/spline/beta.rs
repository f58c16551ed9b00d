//! The Beta quaternion spline with shape parameters β₁, β₂ (seed 000; MATH.md §7, verified,
//! with the paper's errata corrected).
//!
//! Data: auxiliary vertices p₀ … p_{l+2} ∈ S³ and per-vertex β_{i,1} > 0, β_{i,2}.
//! γᵢ = 2(1+β_{i,1}) / (β_{i,2} + 2β_{i,1}(1+β_{i,1})),  Δᵢ = γᵢ + 1 + β_{i+1,1}² γᵢ₊₁.
//! Inner points (i = 0 … l+1): q_{i,1} = pᵢ (pᵢ* pᵢ₊₁)^{γᵢ/Δᵢ}, q_{i,2} = pᵢ (pᵢ* pᵢ₊₁)^{(γᵢ+1)/Δᵢ}.
//! Joints: q_{i,0} = q_{i−1,2} (q_{i−1,2}* q_{i,1})^{1/(1+β_{i,1})},
//!         q_{i,3} = q_{i,2} (q_{i,2}* q_{i+1,1})^{1/(1+β_{i+1,1})}, so q_{i,3} = q_{i+1,0}.
//! Segment i = 1 … l, u ∈ [0, 1]: sᵢ(u) = q_{i,0} Π_{j=1..3} (q_{i,j−1}* q_{i,j})^{B̃_{j,3}(u)}
//! (cumulative cubic Bernstein: 1−(1−u)³, 3u²−2u³, u³).
//! Continuity: G¹ exactly (sᵢ'(0) = β_{i,1} s_{i−1}'(1)); **not G² in general** — the paper's
//! claim is false; the G² residual equals (6/γᵢ) × the residual of the corrected Theorem-2
//! condition, which [`BetaSpline::joint_residuals`] reports. β₁ = 1, β₂ = 0 gives the uniform
//! cubic B-spline's Bézier points. Approximating (does not pass through the vertices).
//! `times` maps the l+1 segment joints to times (default 0 … l); derivatives in time scale by
//! 1/h per order, the β relations hold in the local parameter u.

use super::{prepare_keys, prepare_times, segment_jets, Spline};
use crate::error::{Error, Result, Short};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable, SegmentForm};

/// Residuals of the geometric constraints at one interior joint (local parameter u).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BetaJoint {
    /// Joint index i (between segment i−1 and i, 1-based as in the paper).
    pub joint: usize,
    /// sᵢ'(0) − β_{i,1} s_{i−1}'(1).
    pub g1: Quat,
    /// sᵢ''(0) − β_{i,1}² s_{i−1}''(1) − β_{i,2} s_{i−1}'(1).
    pub g2: Quat,
    /// Corrected Theorem 2, right side minus left side (signed so that g2 = (6/γᵢ) theorem2):
    /// (γᵢ/Δᵢ) q_{i,0} log(pᵢ* pᵢ₊₁) + (β_{i,1}² γᵢ/Δ_{i−1}) log(pᵢ p_{i−1}*) q_{i−1,3}
    /// − q_{i−1,3} log(q_{i−1,2}* q_{i,1}).
    pub theorem2: Quat,
    /// γᵢ (so that g2 = (6/γᵢ) theorem2).
    pub gamma: f64,
    /// The magnitude |sᵢ''(0)| the G² residual is measured against.
    pub second_derivative: f64,
}

/// The Beta quaternion spline.
#[derive(Debug, Clone)]
pub struct BetaSpline {
    p: Vec<Quat>,
    beta1: Vec<f64>,
    beta2: Vec<f64>,
    gamma: Vec<f64>,
    delta: Vec<f64>,
    ctrl: Vec<[Quat; 4]>,
    logs: Vec<[Axis; 3]>,
    times: Vec<f64>,
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
}

/// One value per vertex from a scalar (len 1) or a full list.
fn per_vertex(v: &[f64], n: usize, arg: &'static str) -> Result<Vec<f64>> {
    let out = match v.len() {
        1 => vec![v[0]; n],
        m if m == n => v.to_vec(),
        m => return Err(Error::invalid(arg, format!("expected 1 or {n} values (one per vertex), got {m}"))),
    };
    super::check_shape(arg, &out)?;
    Ok(out)
}

impl BetaSpline {
    /// `vertices` p₀ … p_{l+2} (at least 4), `beta1`/`beta2` one value or one per vertex,
    /// `times` l+1 joint times (default 0 … l). With `canonicalize` (default in the Python
    /// API) consecutive vertices are sign-aligned; the paper's Example 1 needs it off.
    pub fn new(
        vertices: &[Quat],
        beta1: &[f64],
        beta2: &[f64],
        times: Option<&[f64]>,
        canonicalize: bool,
    ) -> Result<Self> {
        let p = prepare_keys(vertices, "vertices", 4, canonicalize)?;
        let n = p.len();
        let l = n - 3;
        let b1 = per_vertex(beta1, n, "beta1")?;
        let b2 = per_vertex(beta2, n, "beta2")?;
        if let Some(i) = b1.iter().position(|&b| b <= 0.0) {
            return Err(Error::invalid("beta1", format!("beta1[{i}] = {} must be > 0", Short(b1[i]))));
        }
        if let Some(i) = b1.iter().position(|&b| b < 1e-6) {
            return Err(Error::invalid(
                "beta1",
                format!("beta1[{i}] = {} is below the supported 1e-6", Short(b1[i])),
            ));
        }
        let mut gamma = Vec::with_capacity(n);
        for i in 0..n {
            let den = b2[i] + 2.0 * b1[i] * (1.0 + b1[i]);
            if den <= 1e-9 * (1.0 + b2[i].abs()) {
                return Err(Error::invalid(
                    "beta2",
                    format!(
                        "beta2[{i}] = {} makes β₂ + 2β₁(1+β₁) = {} ≤ 0 (γ_{i} infinite or negative)",
                        Short(b2[i]),
                        Short(den)
                    ),
                ));
            }
            gamma.push(2.0 * (1.0 + b1[i]) / den);
        }
        let delta: Vec<f64> =
            (0..n - 1).map(|i| gamma[i] + 1.0 + b1[i + 1] * b1[i + 1] * gamma[i + 1]).collect();
        let times = prepare_times(times, l + 1)?;
        // inner points i = 0 … l+1
        let (mut q1, mut q2) = (Vec::with_capacity(l + 2), Vec::with_capacity(l + 2));
        for i in 0..=l + 1 {
            let rel = p[i].conj() * p[i + 1];
            q1.push(p[i] * rel.powf(gamma[i] / delta[i]));
            q2.push(p[i] * rel.powf((gamma[i] + 1.0) / delta[i]));
        }
        let mut ctrl = Vec::with_capacity(l);
        for i in 1..=l {
            let q0 = q2[i - 1] * (q2[i - 1].conj() * q1[i]).powf(1.0 / (1.0 + b1[i]));
            let q3 = q2[i] * (q2[i].conj() * q1[i + 1]).powf(1.0 / (1.0 + b1[i + 1]));
            ctrl.push([q0, q1[i], q2[i], q3]);
        }
        let logs: Vec<[Axis; 3]> = ctrl
            .iter()
            .map(|c| std::array::from_fn(|j| Axis::from_log((c[j].conj() * c[j + 1]).log().vec())))
            .collect();
        // cumulative cubic Bernstein weights 1 − (1−u)³, 3u² − 2u³, u³
        const W: [[f64; 4]; 3] = [[0.0, 1.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 0.0, 1.0]];
        let batch = CumulativeTable::new(&times, Basis::Bernstein, |s| SegmentForm {
            base: ctrl[s][0],
            factors: (0..3).map(|j| (logs[s][j], W[j].to_vec())).collect(),
        });
        Ok(BetaSpline { p, beta1: b1, beta2: b2, gamma, delta, ctrl, logs, times, batch })
    }

    /// The Bézier points [q_{i,0}, q_{i,1}, q_{i,2}, q_{i,3}] of segments i = 1 … l.
    pub fn bezier_points(&self) -> &[[Quat; 4]] {
        &self.ctrl
    }

    /// Segment `s` (0-based: the paper's segment s+1) at local parameter u (a jet).
    #[inline(always)]
    fn local<const N: usize>(&self, s: usize, u: Jet<N>) -> JQuat<N> {
        let one = Jet::<N>::constant(1.0);
        let v = one - u;
        let u2 = u * u;
        let b = [one - v * v * v, u2 * 3.0 - u2 * u * 2.0, u2 * u];
        let mut q = JQuat::constant(self.ctrl[s][0]);
        for j in 0..3 {
            q = q * JQuat::exp_axis(&self.logs[s][j], b[j]);
        }
        q
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, s: usize, t: f64) -> JQuat<N> {
        let (t0, t1) = (self.times[s], self.times[s + 1]);
        self.local(s, Jet::variable((t - t0) / (t1 - t0), 1.0 / (t1 - t0)))
    }

    /// The G¹, G² and corrected Theorem-2 residuals at every interior joint i = 2 … l.
    pub fn joint_residuals(&self) -> Vec<BetaJoint> {
        let l = self.ctrl.len();
        (2..=l)
            .map(|i| {
                let left = self.local::<3>(i - 2, Jet::variable(1.0, 1.0)).derivatives();
                let right = self.local::<3>(i - 1, Jet::variable(0.0, 1.0)).derivatives();
                let (b1, b2) = (self.beta1[i], self.beta2[i]);
                let g1 = right[1] - left[1].scale(b1);
                let g2 = right[2] - left[2].scale(b1 * b1) - left[1].scale(b2);
                let q_prev3 = self.ctrl[i - 2][3];
                let q_prev2 = self.ctrl[i - 2][2];
                let q_i0 = self.ctrl[i - 1][0];
                let q_i1 = self.ctrl[i - 1][1];
                let (g, d, dm) = (self.gamma[i], self.delta[i], self.delta[i - 1]);
                let lhs = q_prev3 * (q_prev2.conj() * q_i1).log();
                let rhs = q_i0 * (self.p[i].conj() * self.p[i + 1]).log().scale(g / d)
                    + ((self.p[i] * self.p[i - 1].conj()).log() * q_prev3).scale(b1 * b1 * g / dm);
                BetaJoint {
                    joint: i,
                    g1,
                    g2,
                    theorem2: rhs - lhs,
                    gamma: g,
                    second_derivative: right[2].norm(),
                }
            })
            .collect()
    }
}

impl Spline for BetaSpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "beta"
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        0
    }
    fn beta_residuals(&self) -> Option<Vec<BetaJoint>> {
        Some(self.joint_residuals())
    }
    fn control_points(&self) -> Option<Vec<[Quat; 4]>> {
        Some(self.ctrl.clone())
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
}
