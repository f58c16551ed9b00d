//! Piecewise LinEuler: Euler angles interpolated linearly between keys (seed 002's naive
//! baseline; MATH.md §2).
//!
//! Each key's angles in sequence `seq` (scipy's convention); segment i lerps them, each
//! difference wrapped to (−π, π]: a(u) = aᵢ + u dᵢ, q = q_{axis1}(a₁) q_{axis2}(a₂) q_{axis3}(a₃)
//! (intrinsic) or the reverse product (extrinsic). The axis wanders and the speed varies; it
//! breaks down near gimbal lock. C⁰ at keys; interpolating.

use super::{local, prepare_keys, prepare_times, segment_jets, Spline};
use crate::convert::{to_euler, EulerSeq};
use crate::error::Result;
use crate::jet::{JQuat, Jet};
use crate::quat::Quat;
use std::f64::consts::PI;

/// Linear interpolation of Euler angles between consecutive keys.
#[derive(Debug, Clone)]
pub struct PiecewiseLinEuler {
    seq: EulerSeq,
    angles: Vec<[f64; 3]>,
    steps: Vec<[f64; 3]>,
    times: Vec<f64>,
}

impl PiecewiseLinEuler {
    pub fn new(keys: &[Quat], times: Option<&[f64]>, seq: &str) -> Result<Self> {
        let seq = EulerSeq::parse(seq)?;
        let keys = prepare_keys(keys, "quats", 2, true)?;
        let times = prepare_times(times, keys.len())?;
        let angles: Vec<[f64; 3]> = keys.iter().map(|&q| to_euler(seq, q).0).collect();
        let steps = angles
            .windows(2)
            .map(|w| {
                std::array::from_fn(|k| {
                    let d = w[1][k] - w[0][k];
                    if d > PI {
                        d - 2.0 * PI
                    } else if d <= -PI {
                        d + 2.0 * PI
                    } else {
                        d
                    }
                })
            })
            .collect();
        Ok(PiecewiseLinEuler { seq, angles, steps, times })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        let elem = |k: usize| -> JQuat<N> {
            let half = (u * self.steps[i][k] + self.angles[i][k]) * 0.5;
            let (s, c) = half.sin_cos();
            let z = Jet::constant(0.0);
            let mut v = [z, z, z];
            v[self.seq.axes[k]] = s;
            JQuat { w: c, x: v[0], y: v[1], z: v[2] }
        };
        let (a, b, c) = (elem(0), elem(1), elem(2));
        if self.seq.extrinsic {
            c * b * a
        } else {
            a * b * c
        }
    }
}

impl Spline for PiecewiseLinEuler {
    segment_jets!();
    fn name(&self) -> &'static str {
        "lin_euler"
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
