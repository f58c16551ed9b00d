//! Segments qᵢ exp(½ rᵢ(s)) with rᵢ a polynomial in the rotation vector (degree 3 or 5):
//! the segment form shared by the Hermite spline (`hermite.rs`, key rates given) and the
//! natural spline (`natural_spline.rs`, key rates solved). See `hermite.rs` for the end
//! conditions of each segment and [`crate::kinematics`] for A(ρ) and N(ρ, ρ̇).

use super::keyframe::KeyLoop;
use crate::convert::to_rotvec;
use crate::jet::{JQuat, Jet};
use crate::kinematics::{accel_nonlinear, rate_to_rotvec_dot};
use crate::quat::Quat;
use crate::vec3::Vec3;

/// Segments qᵢ exp(½ rᵢ(s)), rᵢ(s) = Σ_{m=1..5} c_m s^m — shared by the Hermite and the
/// natural spline.
#[derive(Debug, Clone)]
pub(crate) struct RotvecSegments {
    base: Vec<Quat>,
    times: Vec<f64>,
    /// Per segment, coefficients of ½ rᵢ: [0, c₁, …, c₅]/2 per component.
    half: Vec<[[f64; 6]; 3]>,
    pub(crate) degree: usize,
    /// Flat copy for the batch kernel (`crate::simd::natural`).
    pub(crate) batch: crate::simd::natural::RotvecTable,
}

fn mat_vec(m: &nalgebra::Matrix3<f64>, v: Vec3) -> Vec3 {
    let r = m * nalgebra::Vector3::new(v[0], v[1], v[2]);
    [r[0], r[1], r[2]]
}

impl RotvecSegments {
    /// Builds the segments from per-segment base keys, rotation vectors ρᵢ, joint times and
    /// body rates per joint (and accelerations per joint for the quintic).
    pub(crate) fn new(
        base: Vec<Quat>,
        rho: &[Vec3],
        times: Vec<f64>,
        rates: &[Vec3],
        accels: Option<&[Vec3]>,
    ) -> Self {
        let half: Vec<[[f64; 6]; 3]> = (0..base.len())
            .map(|i| {
                let h = times[i + 1] - times[i];
                let a = rate_to_rotvec_dot(rho[i]);
                let v1 = mat_vec(&a, rates[i + 1]);
                let v0 = rates[i];
                let (a0, a1) = match accels {
                    Some(acc) => {
                        let n = accel_nonlinear(rho[i], v1);
                        let d: Vec3 = std::array::from_fn(|c| acc[i + 1][c] - n[c]);
                        (acc[i], mat_vec(&a, d))
                    }
                    None => ([0.0; 3], [0.0; 3]),
                };
                std::array::from_fn(|c| {
                    let (p, v0, v1, a0, a1) = (rho[i][c], v0[c], v1[c], a0[c], a1[c]);
                    let mut k = [0.0; 6];
                    if accels.is_none() {
                        k[1] = v0;
                        k[2] = (3.0 * p - 2.0 * h * v0 - h * v1) / (h * h);
                        k[3] = (-2.0 * p + h * v0 + h * v1) / (h * h * h);
                    } else {
                        let d0 = p - v0 * h - 0.5 * a0 * h * h;
                        let d1 = v1 - v0 - a0 * h;
                        let d2 = a1 - a0;
                        k[1] = v0;
                        k[2] = 0.5 * a0;
                        k[3] = (10.0 * d0 - 4.0 * d1 * h + 0.5 * d2 * h * h) / h.powi(3);
                        k[4] = (-15.0 * d0 + 7.0 * d1 * h - d2 * h * h) / h.powi(4);
                        k[5] = (6.0 * d0 - 3.0 * d1 * h + 0.5 * d2 * h * h) / h.powi(5);
                    }
                    k.map(|x| 0.5 * x)
                })
            })
            .collect();
        let degree = if accels.is_some() { 5 } else { 3 };
        let batch = crate::simd::natural::RotvecTable::new(&times, &base, &half);
        RotvecSegments { base, times, half, degree, batch }
    }

    pub(crate) fn joints(&self) -> &[f64] {
        &self.times
    }

    #[inline(always)]
    pub(crate) fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let s = Jet::<N>::variable(t - self.times[i], 1.0);
        let d = self.degree + 1;
        let r: [Jet<N>; 3] = std::array::from_fn(|c| Jet::poly(&self.half[i][c][..d], s));
        JQuat::constant(self.base[i]) * JQuat::exp_pure(r)
    }
}

/// Per-segment base keys and rotation vectors ρᵢ = rotvec(qᵢ* qᵢ₊₁) of a key loop.
pub(crate) fn bases_and_chords(k: &KeyLoop) -> (Vec<Quat>, Vec<Vec3>) {
    let m = k.segments();
    let base: Vec<Quat> = (0..m).map(|i| k.key_at_joint(i)).collect();
    let rho = (0..m).map(|i| to_rotvec(base[i].conj() * k.key_at_joint(i + 1))).collect();
    (base, rho)
}
