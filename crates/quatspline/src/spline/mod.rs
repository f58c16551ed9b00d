//! Keyframe splines behind one interface, each method in its own file.
//!
//! Every spline is a sequence of segments between joint times. A segment is written once,
//! generically over [`Jet<N>`](crate::jet::Jet): N = 1 gives the orientation, N = 2…4 add
//! q', q'', q''' exactly (Taylor-mode differentiation of the same formula, see
//! [`crate::jet`]). Derivatives are with respect to time, in rad per time unit.
//!
//! | method | file | interpolates | continuity |
//! |---|---|---|---|
//! | piecewise slerp | `piecewise_slerp.rs` | yes | C⁰ |
//! | piecewise NLerp / LinEuler / LinMat (baselines) | `nlerp.rs`, `lin_euler.rs`, `lin_mat.rs` | yes | C⁰ |
//! | spherical Bézier (de Casteljau) | `spherical_bezier.rs` | ends | C^∞ (one curve) |
//! | cumulative Bézier (Kim–Kim–Shin) | `cumulative_bezier.rs` | ends | C^∞ (one curve) |
//! | Squad | `squad.rs` | yes | C¹ |
//! | Catmull–Rom (Gortler) | `catmull_rom.rs` | yes | C¹ |
//! | cumulative B-spline, order k | `cumulative_bspline.rs` | no | C^(k−2) |
//! | non-uniform cumulative B-spline, knots | `nonuniform_bspline.rs` | no | C^(k−1−multiplicity) |
//! | global natural C² spline | `natural_spline.rs` | yes | C² |
//! | Beta spline (β₁, β₂) | `beta.rs` | no | G¹ (not G² in general) |
//! | C³ parametric spline (α, β) | `c3.rs` | yes | C³ |
//! | Hermite keys (rates; + accelerations) | `hermite.rs` | yes | C¹ (C² quintic) |
//! | Kochanek–Bartels (tension, continuity, bias) | `kochanek_bartels.rs` | yes | C¹ (C⁰ where continuity ≠ 0) |
//!
//! Keyframe control shared by the interpolating methods (closed loops, holds, rest ends) is
//! in `keyframe.rs`; extrapolation beyond the ends (raise, clamp, linear, periodic) in `eval.rs`.

mod beta;
mod c3;
mod catmull_rom;
mod cumulative_bezier;
mod cumulative_bspline;
mod engine;
mod eval;
mod hermite;
mod keyframe;
mod keys;
mod kochanek_bartels;
mod lin_euler;
mod lin_mat;
mod natural_spline;
mod nlerp;
mod nonuniform_bspline;
mod piecewise_slerp;
mod reparam;
mod rotvec_segments;
mod spherical_bezier;
mod squad;

pub use crate::frame::Frame;
pub use beta::{BetaJoint, BetaSpline};
pub use c3::{patent_blending, C3Spline, C3Variant};
pub use catmull_rom::{CatmullRom, CatmullRomEnds};
pub use cumulative_bezier::CumulativeBezier;
pub use cumulative_bspline::{cumulative_blending_matrix, CumulativeBSpline};
pub use eval::{
    angular_into, angular_reference_into, derivatives_on, evaluate_into, evaluate_reference_into,
    linear_extrapolation, Cursor, Extrapolate,
};
pub use hermite::Hermite;
pub use keyframe::{prepare_loop, same_rotation, KeyEnds, KeyLoop};
pub use keys::{
    canonicalize_chain, chain_logs, check_domain, check_increasing, check_shape, check_span, prepare_keys,
    prepare_times, MAX_TIME, MIN_RELATIVE_SPACING,
};
pub(crate) use keys::{par_copy, par_map};
pub use kochanek_bartels::{alpha_times, KochanekBartels, Tcb, TcbEnds, CATMULL_ROM};
pub use lin_euler::PiecewiseLinEuler;
pub use lin_mat::PiecewiseLinMat;
pub use natural_spline::{NaturalEnds, NaturalSpline};
pub use nlerp::PiecewiseNlerp;
pub use nonuniform_bspline::{basis_jets, check_knots, NonUniformBSpline};
pub use piecewise_slerp::PiecewiseSlerp;
pub use reparam::{max_rate, Reparameterized, TimeMap};
pub use spherical_bezier::{de_casteljau, SphericalBezier};
pub use squad::Squad;

use crate::jet::JQuat;

/// The contract every spline fulfils: segments between joint times, each evaluable with its
/// time derivatives. Implementations are immutable after construction (`Send + Sync`), so one
/// spline can be evaluated from many threads at once.
pub trait Spline: Send + Sync {
    /// The method's registry name (e.g. `"squad"`).
    fn name(&self) -> &'static str;

    /// Joint times: segment i spans `joints()[i] ..= joints()[i + 1]`. Strictly increasing,
    /// at least two entries.
    fn joints(&self) -> &[f64];

    /// Whether the curve passes through its keys (at the joints).
    fn interpolates(&self) -> bool;

    /// The parametric continuity order in time the method guarantees at interior joints.
    fn continuity(&self) -> u8;

    /// q on segment `seg` at time `t` (t may lie anywhere; the segment's formula is used).
    fn segment_jet1(&self, seg: usize, t: f64) -> JQuat<1>;
    /// q, q' on segment `seg` at time `t`.
    fn segment_jet2(&self, seg: usize, t: f64) -> JQuat<2>;
    /// q, q', q'' on segment `seg` at time `t`.
    fn segment_jet3(&self, seg: usize, t: f64) -> JQuat<3>;
    /// q, q', q'', q''' on segment `seg` at time `t`.
    fn segment_jet4(&self, seg: usize, t: f64) -> JQuat<4>;
    /// q … q^(5) on segment `seg` at time `t` (for the continuity certificate beyond C³);
    /// `None` for a spline that does not provide it (`segment_jets!` provides it).
    fn segment_jet6(&self, _seg: usize, _t: f64) -> Option<JQuat<6>> {
        None
    }

    /// (first joint, last joint).
    fn domain(&self) -> (f64, f64) {
        let j = self.joints();
        (j[0], j[j.len() - 1])
    }

    /// The number of segments.
    fn segments(&self) -> usize {
        self.joints().len() - 1
    }

    /// Whether the curve is a closed loop: the end joins the start (the seam) exactly as an
    /// interior joint, so the continuity certificate checks it too.
    fn closed(&self) -> bool {
        false
    }

    /// For the Beta spline: the residuals of its geometric constraints at interior joints.
    fn beta_residuals(&self) -> Option<Vec<BetaJoint>> {
        None
    }

    /// Bézier control points per segment, where the method has them (Beta spline).
    fn control_points(&self) -> Option<Vec<[crate::quat::Quat; 4]>> {
        None
    }

    /// The method's batch kernels (`crate::simd`), where it has them: the engine then hands
    /// runs of located samples to them instead of calling `segment_jetN` per sample.
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        None
    }

    /// The segment containing t (the right one at an interior joint; the last one at the end).
    fn locate(&self, t: f64) -> usize {
        let j = self.joints();
        let k = j.partition_point(|&x| x <= t);
        k.saturating_sub(1).min(j.len() - 2)
    }
}

/// Implements the four `segment_jetN` methods of [`Spline`] by calling the type's inherent
/// generic `fn segment<const N: usize>(&self, seg: usize, t: f64) -> JQuat<N>`.
macro_rules! segment_jets {
    () => {
        fn segment_jet1(&self, seg: usize, t: f64) -> $crate::jet::JQuat<1> {
            self.segment::<1>(seg, t)
        }
        fn segment_jet2(&self, seg: usize, t: f64) -> $crate::jet::JQuat<2> {
            self.segment::<2>(seg, t)
        }
        fn segment_jet3(&self, seg: usize, t: f64) -> $crate::jet::JQuat<3> {
            self.segment::<3>(seg, t)
        }
        fn segment_jet4(&self, seg: usize, t: f64) -> $crate::jet::JQuat<4> {
            self.segment::<4>(seg, t)
        }
        fn segment_jet6(&self, seg: usize, t: f64) -> Option<$crate::jet::JQuat<6>> {
            Some(self.segment::<6>(seg, t))
        }
    };
}
pub(crate) use segment_jets;

/// The local parameter u = (t − tᵢ)/hᵢ of a segment as a jet (du/dt = 1/hᵢ).
#[inline(always)]
pub(crate) fn local<const N: usize>(t: f64, t0: f64, t1: f64) -> crate::jet::Jet<N> {
    let h = t1 - t0;
    crate::jet::Jet::variable((t - t0) / h, 1.0 / h)
}
