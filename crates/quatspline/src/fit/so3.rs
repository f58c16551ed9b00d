//! SO(3) in rotation-vector coordinates for the fitting solver: Exp, Log (sign-invariant),
//! and the inverse left and right Jacobians (Chirikjian, Stochastic Models, Information Theory
//! and Lie Groups, vol. 2, §10.6; Solà, Deray & Atchuthan, "A micro Lie theory", 2018, eqs.
//! 143–146).
//!
//! Exp(φ + ε) ≈ Exp(φ) Exp(J_r(φ) ε) and Log(Exp(φ) Exp(ε)) ≈ φ + J_r⁻¹(φ) ε, with
//! J_r(φ) = I − (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×²,
//! J_r⁻¹(φ) = I + ½[φ]× + (1/θ² − (1 + cos θ)/(2θ sin θ)) [φ]×², θ = |φ|, and
//! J_l(φ) = J_r(−φ). The coefficient of [φ]×² in J_r⁻¹ takes its Taylor series
//! 1/12 + θ²/720 + θ⁴/30240 + θ⁶/1209600 below θ = 0.1 (next term < 1e-16 relative).

use crate::quat::Quat;
use crate::vec3::{self, Vec3};

/// A 3×3 matrix, row-major.
pub type M3 = [[f64; 3]; 3];

/// Exp: rotation vector → unit quaternion (rotation by |v| about v).
#[inline]
pub fn exp(v: Vec3) -> Quat {
    Quat::pure(vec3::scale(v, 0.5)).exp()
}

/// Log: unit quaternion → rotation vector with angle in [0, π]; q and −q give the same vector.
#[inline]
pub fn log(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    vec3::scale(q.log().vec(), 2.0)
}

/// [v]× (so that [v]× u = v × u).
#[inline]
pub fn skew(v: Vec3) -> M3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

#[inline]
pub fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

#[inline]
pub fn mat_vec(a: &M3, v: Vec3) -> Vec3 {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

/// The coefficient of [φ]×² in J_r⁻¹(φ).
fn inv_coef(theta: f64) -> f64 {
    if theta < 0.1 {
        let t2 = theta * theta;
        1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 * (1.0 / 30240.0 + t2 / 1_209_600.0))
    } else {
        let (s, c) = theta.sin_cos();
        1.0 / (theta * theta) - (1.0 + c) / (2.0 * theta * s)
    }
}

/// J_r⁻¹(φ).
pub fn jr_inv(phi: Vec3) -> M3 {
    let k = skew(phi);
    let k2 = mul(&k, &k);
    let c = inv_coef(vec3::norm(phi));
    std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { 1.0 } else { 0.0 }) + 0.5 * k[i][j] + c * k2[i][j])
    })
}

/// J_l⁻¹(φ) = J_r⁻¹(−φ).
pub fn jl_inv(phi: Vec3) -> M3 {
    jr_inv(vec3::scale(phi, -1.0))
}

/// J_r(φ) (used by the tests).
pub fn jr(phi: Vec3) -> M3 {
    let t = vec3::norm(phi);
    let k = skew(phi);
    let k2 = mul(&k, &k);
    let (a, b) = if t < 1e-4 {
        (0.5 - t * t / 24.0, 1.0 / 6.0 - t * t / 120.0)
    } else {
        ((1.0 - t.cos()) / (t * t), (t - t.sin()) / (t * t * t))
    };
    std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { 1.0 } else { 0.0 }) - a * k[i][j] + b * k2[i][j])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_exp_round_trip_and_sign_invariance() {
        for v in [[0.3, -0.2, 0.1], [1e-9, 2e-9, 0.0], [2.0, 1.0, -0.5]] {
            let q = exp(v);
            let w = log(q);
            let w2 = log(-q);
            for i in 0..3 {
                assert!((w[i] - v[i]).abs() < 1e-14);
                assert!((w2[i] - v[i]).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn jacobians_match_finite_differences() {
        for phi in [[0.3, -0.2, 0.1], [0.01, 0.02, -0.03], [1.5, 0.7, -1.1], [0.05, 0.0, 0.0]] {
            let ji = jr_inv(phi);
            let jl = jl_inv(phi);
            let h = 1e-6;
            for c in 0..3 {
                let mut e = [0.0; 3];
                e[c] = h;
                let mut em = [0.0; 3];
                em[c] = -h;
                // Log(Exp(φ) Exp(ε)) ≈ φ + J_r⁻¹ ε;  Log(Exp(ε) Exp(φ)) ≈ φ + J_l⁻¹ ε.
                let rp = log(exp(phi) * exp(e));
                let rm = log(exp(phi) * exp(em));
                let lp = log(exp(e) * exp(phi));
                let lm = log(exp(em) * exp(phi));
                for r in 0..3 {
                    let fr = (rp[r] - rm[r]) / (2.0 * h);
                    let fl = (lp[r] - lm[r]) / (2.0 * h);
                    assert!((fr - ji[r][c]).abs() < 1e-8, "J_r⁻¹ {r}{c}");
                    assert!((fl - jl[r][c]).abs() < 1e-8, "J_l⁻¹ {r}{c}");
                }
            }
            // J_r J_r⁻¹ = I
            let p = mul(&jr(phi), &ji);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((p[i][j] - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn inverse_jacobian_series_meets_closed_form() {
        let a = inv_coef(0.1 - 1e-12);
        let b = inv_coef(0.1 + 1e-12);
        assert!((a - b).abs() < 1e-13);
    }
}
