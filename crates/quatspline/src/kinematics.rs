//! Rotation-vector kinematics: the maps between angular velocity and the rate of a rotation
//! vector, and the quadratic term of the angular acceleration — shared by the natural spline,
//! the Hermite spline (`spline/natural_spline.rs`, `spline/hermite.rs`) and the fit
//! (`fit/so3.rs`, `fit/model.rs`).
//!
//! For q(s) = q₀ Exp(ρ(s)) with body angular velocity ω (Chirikjian, Stochastic Models,
//! Information Theory and Lie Groups, vol. 2, §10.6; Solà, Deray & Atchuthan, "A micro Lie
//! theory", 2018, eqs. 143–146; MATH.md §6b):
//! - ω = J_r(ρ) ρ̇ with J_r(ρ) = I − (1 − cos θ)/θ² [ρ]× + (θ − sin θ)/θ³ [ρ]×², θ = |ρ|;
//! - ρ̇ = A(ρ) ω with A(ρ) = J_r⁻¹(ρ) = I + ½[ρ]× + (1 − (θ/2) cot(θ/2))/θ² [ρ]×²;
//! - J_l(ρ) = J_r(−ρ), J_l⁻¹(ρ) = J_r⁻¹(−ρ);
//! - ω̇ = J_r(ρ) ρ̈ + N(ρ, ρ̇), N quadratic in ρ̇ ([`accel_nonlinear`]).
//!
//! Every coefficient is a singular ratio of [`crate::special`] (series below its switch).
//! The natural and Hermite splines use [`a_of`] for A; the fit's J_r⁻¹ ([`jr_inv`]) is the same
//! matrix with the coefficient by the fit's own older series
//! ([`crate::special::one_minus_half_cot_over_sq_fit`]), kept so that fits stay bit-identical
//! (their λ search amplifies a change in the last bits).

use crate::special::{
    accel_k1, accel_k2, one_minus_cos_over_sq, one_minus_half_cot_over_sq, one_minus_half_cot_over_sq_fit,
    x_minus_sin_over_cube,
};
use crate::vec3::{self, Vec3};
use nalgebra::{Matrix3, Vector3};

/// A 3×3 matrix, row-major.
pub type M3 = [[f64; 3]; 3];

/// [v]× (so that [v]× u = v × u).
#[inline]
pub fn skew(v: Vec3) -> M3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

/// a b (3×3).
#[inline]
pub fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// a v.
#[inline]
pub fn mat_vec(a: &M3, v: Vec3) -> Vec3 {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

/// I − a[φ]× + b[φ]×² with (a, b) = `coef`(|φ|).
#[inline]
fn identity_plus(phi: Vec3, a: f64, b: f64) -> M3 {
    let k = skew(phi);
    let k2 = mul(&k, &k);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { 1.0 } else { 0.0 }) - a * k[i][j] + b * k2[i][j])
    })
}

/// J_r(φ) = I − (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×² (θ = |φ|): body angular rate of
/// Exp(φ(s)) per rotation-vector rate, A⁻¹(φ).
pub fn jr(phi: Vec3) -> M3 {
    let t = vec3::norm(phi);
    identity_plus(phi, one_minus_cos_over_sq(t), x_minus_sin_over_cube(t))
}

/// I + ½[φ]× + c[φ]×².
#[inline]
fn identity_half_plus(phi: Vec3, c: f64) -> M3 {
    let k = skew(phi);
    let k2 = mul(&k, &k);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { 1.0 } else { 0.0 }) + 0.5 * k[i][j] + c * k2[i][j])
    })
}

/// A(φ) = J_r⁻¹(φ) = I + ½[φ]× + (1 − (θ/2) cot(θ/2))/θ² [φ]×² (θ = |φ|): rotation-vector rate
/// per body angular rate, with the coefficient [`one_minus_half_cot_over_sq`].
pub fn a_of(phi: Vec3) -> M3 {
    identity_half_plus(phi, one_minus_half_cot_over_sq(vec3::norm(phi)))
}

/// J_r⁻¹(φ) as the fit computes it: [`a_of`] with the coefficient
/// [`one_minus_half_cot_over_sq_fit`] (the same ratio by the fit's older series, kept so that
/// fits stay bit-identical).
pub fn jr_inv(phi: Vec3) -> M3 {
    identity_half_plus(phi, one_minus_half_cot_over_sq_fit(vec3::norm(phi)))
}

/// J_l⁻¹(φ) = J_r⁻¹(−φ).
pub fn jl_inv(phi: Vec3) -> M3 {
    jr_inv(vec3::scale(phi, -1.0))
}

fn na(m: M3) -> Matrix3<f64> {
    Matrix3::new(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2])
}

fn skew_na(v: Vec3) -> Matrix3<f64> {
    na(skew(v))
}

fn v3(a: Vec3) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// A(ρ) = [`a_of`](ρ) as a nalgebra matrix (for the natural spline's block solver).
pub(crate) fn rate_to_rotvec_dot(r: Vec3) -> Matrix3<f64> {
    na(a_of(r))
}

/// A⁻¹(ρ) = [`jr`](ρ) as a nalgebra matrix.
pub(crate) fn rotvec_dot_to_rate(r: Vec3) -> Matrix3<f64> {
    na(jr(r))
}

/// The quadratic term N(ρ, ρ̇) of the body angular acceleration in the rotation-vector rate:
/// with d = ρ·ρ̇ and c = ρ × ρ̇, N = k₁ d c + k₂ d (ρ × c) + k₃ (ρ̇ × c), where
/// k₁ = [`accel_k1`], k₂ = [`accel_k2`], k₃ = [`x_minus_sin_over_cube`] of |ρ|.
pub(crate) fn accel_nonlinear(r: Vec3, rd: Vec3) -> Vec3 {
    accel_nonlinear_with(r, rd, accel_coefficients(r))
}

/// The three coefficients (k₁, k₂, k₃) of [`accel_nonlinear`] for one rotation vector (they
/// depend on |ρ| only: computed once per segment, not once per sweep of a solve).
pub(crate) fn accel_coefficients(r: Vec3) -> (f64, f64, f64) {
    let x = vec3::norm(r);
    (accel_k1(x), accel_k2(x), x_minus_sin_over_cube(x))
}

/// [`accel_nonlinear`] with its coefficients precomputed (bit-identical).
pub(crate) fn accel_nonlinear_with(r: Vec3, rd: Vec3, (k1, k2, k3): (f64, f64, f64)) -> Vec3 {
    let dp = vec3::dot(r, rd);
    let cp = vec3::cross(r, rd);
    let ccp = vec3::cross(r, cp);
    let dccp = vec3::cross(rd, cp);
    vec3::add(vec3::add(vec3::scale(cp, dp * k1), vec3::scale(ccp, dp * k2)), vec3::scale(dccp, k3))
}

/// ∂N/∂ρ̇ of [`accel_nonlinear_with`] (ρ fixed): with d = ρ·ρ̇, c = ρ × ρ̇,
/// ∂N/∂ρ̇ = k₁ (c ρᵀ + d [ρ]×) + k₂ ((ρ × c) ρᵀ + d [ρ]×²) + k₃ ([ρ̇]×[ρ]× − [c]×).
pub(crate) fn accel_nonlinear_jacobian(r: Vec3, rd: Vec3, (k1, k2, k3): (f64, f64, f64)) -> Matrix3<f64> {
    let dp = vec3::dot(r, rd);
    let cp = vec3::cross(r, rd);
    let ccp = vec3::cross(r, cp);
    let (rv, sr) = (v3(r), skew_na(r));
    v3(cp) * rv.transpose() * k1
        + sr * (dp * k1)
        + v3(ccp) * rv.transpose() * k2
        + sr * sr * (dp * k2)
        + (skew_na(rd) * sr - skew_na(cp)) * k3
}
