//! Cumulative B-spline of poses, order k, uniform or non-uniform knots (Sommer, Usenko,
//! Schubert, Demmel & Cremers, "Efficient Derivative Computation for Cumulative B-Splines on
//! Lie Groups", CVPR 2020; basalt's `se3_spline`; knots as in
//! [`crate::spline::NonUniformBSpline`]).
//!
//! Control poses T₀ … T_{n−1} (unit dual quaternions, sign-aligned), knots u₀ ≤ … ≤ u_{n+k−1},
//! domain [u_{k−1}, u_n]; on [u_m, u_{m+1}):
//! - [`PoseFormulation::Se3`]: T(t) = T_{m−k+1} Π_{j=m−k+2..m} (T_{j−1}⁻¹ Tⱼ)^{B̃ⱼ(t)} — the
//!   cumulative form on SE(3) itself (screw powers: rotation and translation coupled);
//! - [`PoseFormulation::Split`]: the rotation is the SO(3) cumulative B-spline and the position
//!   the Euclidean B-spline p(t) = Σ Bₗ(t) pₗ (the "split" representation of Sommer et al.,
//!   which basalt uses for its trajectories): positions are linear in the control points.
//!
//! B̃ⱼ are the cumulative basis functions (uniform knots: the blending matrix M̃ of
//! `cumulative_bspline.rs`, the fast path; otherwise the De Boor recursion on jets of
//! `nonuniform_bspline.rs`). Both formulations are C^(k−1−μ) at a joint of knot multiplicity μ
//! (C^(k−2) for simple knots) for rotation and position, approximating, exact derivatives.

use super::{pose_keys, trunc, JDual, PoseCurve, ScrewPow};
use crate::dual_quat::DualQuat;
use crate::error::{Error, Result};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::spline::{basis_jets, check_knots, cumulative_blending_matrix, Spline};
use crate::vec3::Vec3;

/// How the pose B-spline couples rotation and translation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseFormulation {
    /// Cumulative form on SE(3) (screw powers of relative poses).
    Se3,
    /// SO(3) cumulative B-spline × Euclidean B-spline of positions.
    Split,
}

/// A cumulative B-spline of poses.
#[derive(Debug, Clone)]
pub struct PoseBSpline {
    ctrl: Vec<DualQuat>,
    positions: Vec<Vec3>,
    pows: Vec<ScrewPow>,
    logs: Vec<Axis>,
    knots: Vec<f64>,
    order: usize,
    seg: Vec<usize>,
    joints: Vec<f64>,
    continuity: u8,
    /// Uniform knots: the cumulative blending matrix (fast path).
    uniform: Option<Vec<Vec<f64>>>,
    formulation: PoseFormulation,
}

impl PoseBSpline {
    /// n ≥ k control poses, n + k knots, 2 ≤ k ≤ 12.
    pub fn new(
        quats: &[Quat],
        positions: &[Vec3],
        knots: &[f64],
        order: usize,
        formulation: PoseFormulation,
    ) -> Result<Self> {
        if !(2..=12).contains(&order) {
            return Err(Error::invalid("order", format!("expected 2 ≤ order ≤ 12, got {order}")));
        }
        let ctrl = pose_keys(quats, positions, "control_quats", order)?;
        let (seg, joints, continuity) = check_knots(knots, ctrl.len(), order)?;
        let spacing = knots[1] - knots[0];
        let uniform = knots.windows(2).all(|w| w[1] - w[0] == spacing);
        let pows = std::iter::once(ScrewPow::new(DualQuat::IDENTITY))
            .chain(ctrl.windows(2).map(|w| ScrewPow::new(w[0].conj() * w[1])))
            .collect();
        let rots: Vec<Quat> = ctrl.iter().map(|c| c.r).collect();
        let mut logs = vec![Axis::default()];
        logs.extend(crate::spline::chain_logs(&rots));
        Ok(PoseBSpline {
            positions: ctrl.iter().map(|c| c.to_rotation_translation().1).collect(),
            ctrl,
            pows,
            logs,
            knots: knots.to_vec(),
            order,
            seg,
            joints,
            continuity,
            uniform: uniform.then(|| cumulative_blending_matrix(order)),
            formulation,
        })
    }

    /// The k basis values B_{m−k+1..m} (as jets) on segment i.
    #[inline]
    fn basis<const N: usize>(&self, i: usize, t: f64) -> [Jet<N>; 12] {
        let m = self.seg[i];
        let k = self.order;
        match &self.uniform {
            Some(mt) => {
                let (a, b) = (self.knots[m], self.knots[m + 1]);
                let u = Jet::<N>::variable((t - a) / (b - a), 1.0 / (b - a));
                // cumulative values B̃_r from M̃, then differences give Bₗ
                let mut cum = [Jet::<N>::constant(0.0); 13];
                for r in 0..k {
                    cum[r] = Jet::poly(&mt[r], u);
                }
                std::array::from_fn(|r| if r < k { cum[r] - cum[r + 1] } else { Jet::constant(0.0) })
            }
            None => basis_jets::<N>(&self.knots, m, k, t),
        }
    }

    #[inline]
    fn pose<const N: usize>(&self, i: usize, t: f64) -> JDual<N> {
        let k = self.order;
        let b = self.basis::<N>(i, t);
        let first = self.seg[i] + 1 - k;
        let mut cum = [Jet::<N>::constant(0.0); 12];
        let mut acc = Jet::constant(0.0);
        for r in (1..k).rev() {
            acc = acc + b[r];
            cum[r] = acc;
        }
        match self.formulation {
            PoseFormulation::Se3 => {
                let mut q = JDual::constant(self.ctrl[first]);
                for r in 1..k {
                    q = q * self.pows[first + r].pow(cum[r]);
                }
                q
            }
            PoseFormulation::Split => {
                let mut rot = JQuat::constant(self.ctrl[first].r);
                for r in 1..k {
                    rot = rot * JQuat::exp_axis(&self.logs[first + r], cum[r]);
                }
                let mut p = [Jet::<N>::constant(0.0); 3];
                for r in 0..k {
                    for c in 0..3 {
                        p[c] = p[c] + b[r] * self.positions[first + r][c];
                    }
                }
                let half = JQuat { w: Jet::constant(0.0), x: p[0] * 0.5, y: p[1] * 0.5, z: p[2] * 0.5 };
                JDual { r: rot, d: half * rot }
            }
        }
    }
}

impl PoseCurve for PoseBSpline {
    fn pose_jet1(&self, seg: usize, t: f64) -> JDual<1> {
        self.pose::<1>(seg, t)
    }
    fn pose_jet4(&self, seg: usize, t: f64) -> JDual<4> {
        self.pose::<4>(seg, t)
    }
}

impl Spline for PoseBSpline {
    fn name(&self) -> &'static str {
        match self.formulation {
            PoseFormulation::Se3 => "pose_bspline",
            PoseFormulation::Split => "pose_bspline_split",
        }
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        self.continuity
    }
    fn segment_jet1(&self, seg: usize, t: f64) -> JQuat<1> {
        self.pose::<1>(seg, t).r
    }
    fn segment_jet2(&self, seg: usize, t: f64) -> JQuat<2> {
        self.pose::<2>(seg, t).r
    }
    fn segment_jet3(&self, seg: usize, t: f64) -> JQuat<3> {
        self.pose::<3>(seg, t).r
    }
    fn segment_jet4(&self, seg: usize, t: f64) -> JQuat<4> {
        trunc(self.pose::<4>(seg, t).r)
    }
}
