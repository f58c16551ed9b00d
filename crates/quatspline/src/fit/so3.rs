//! SO(3) in rotation-vector coordinates for the fitting solver: Exp, Log (sign-invariant),
//! and the inverse left and right Jacobians (Chirikjian, Stochastic Models, Information Theory
//! and Lie Groups, vol. 2, §10.6; Solà, Deray & Atchuthan, "A micro Lie theory", 2018, eqs.
//! 143–146).
//!
//! Exp(φ + ε) ≈ Exp(φ) Exp(J_r(φ) ε) and Log(Exp(φ) Exp(ε)) ≈ φ + J_r⁻¹(φ) ε, with
//! J_r(φ) = I − (1 − cos θ)/θ² [φ]× + (θ − sin θ)/θ³ [φ]×²,
//! J_r⁻¹(φ) = I + ½[φ]× + (1/θ² − (1 + cos θ)/(2θ sin θ)) [φ]×², θ = |φ|, and
//! J_l(φ) = J_r(−φ). The Jacobians live in [`crate::kinematics`] (shared with the natural
//! and Hermite splines, re-exported here); their coefficients are the singular ratios of
//! [`crate::special`], each with its series below its switch.

pub use crate::kinematics::{jl_inv, jr, jr_inv, mat_vec, mul, skew, M3};
use crate::quat::Quat;
use crate::special::{half_cot, one_minus_sqrt_half_cot_over_sq};
use crate::vec3::{self, Vec3};

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

/// S(r) = P + √f·(I − P), P = r̂r̂ᵀ, f = (θ/2)·cot(θ/2), θ = |r| ≤ π: the symmetric square root
/// of the Riemannian Hessian of ½·dist²(q·Exp(δ), y) in δ at δ = 0, where r = Log(q⁻¹y).
/// Its gradient is −r, as for the Gauss–Newton form −J_l⁻¹(r)ᵀr (S r = r = J_l⁻¹(r)ᵀ r),
/// but its transverse curvature is f instead of J_l⁻¹'s (θ/2)²/sin²(θ/2): equal to O(θ²)
/// (1 − θ²/12 vs 1 + θ²/12), apart by 17× at θ = 170°, where Gauss–Newton's steps for a
/// far sample are that much too short (a fit with 5 % of 170° glitches took 300+ iterations).
/// (Hessian of the squared distance on a space of constant curvature ¼: radial 1,
/// transverse (θ/2) cot(θ/2); e.g. Absil, Mahony & Sepulchre, Optimization Algorithms on
/// Matrix Manifolds, 2008, §5.5; Manton 2004, "A globally convergent numerical algorithm for
/// computing the centre of mass on compact Lie groups".)
pub fn dist_hess_sqrt(r: Vec3) -> M3 {
    let t2 = vec3::dot(r, r);
    let g = half_cot(t2.sqrt()).sqrt();
    // S = g·I + (1 − g)·r rᵀ/θ² (no 0/0 at r = 0: see the helper's series)
    let c = one_minus_sqrt_half_cot_over_sq(t2);
    std::array::from_fn(|i| std::array::from_fn(|j| (if i == j { g } else { 0.0 }) + c * (r[i] * r[j])))
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
        let inv_coef = crate::special::one_minus_half_cot_over_sq_fit;
        let a = inv_coef(0.1 - 1e-12);
        let b = inv_coef(0.1 + 1e-12);
        assert!((a - b).abs() < 1e-13);
    }

    /// S(r)² is the Hessian of ½·dist²(q·Exp(δ), y) = ½|Log(Exp(−δ) q⁻¹y)|² at δ = 0 (second
    /// central differences), with S r = r, from 1e-3 rad to 179.4° (both sides of the series
    /// switch at 0.1 included).
    #[test]
    fn distance_hessian_matches_finite_differences() {
        let dirs = [[0.6, -0.48, 0.64], [0.0, 0.0, 1.0], [0.3, 0.9, -0.316_227_766]];
        for theta in [1e-3, 0.05, 0.1 - 1e-9, 0.1 + 1e-9, 0.7, 2.0, 2.9, 3.13] {
            for d in dirs {
                let n = vec3::norm(d);
                let r = vec3::scale(d, theta / n);
                let y = exp(r); // q = identity, q⁻¹y = Exp(r)
                let f = |e: Vec3| {
                    let v = log(exp(vec3::scale(e, -1.0)) * y);
                    0.5 * vec3::dot(v, v)
                };
                let s = dist_hess_sqrt(r);
                let h2 = mul(&s, &s);
                let h = 1e-4;
                for i in 0..3 {
                    for j in 0..3 {
                        let (mut a, mut b, mut c, mut e) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
                        a[i] += h;
                        a[j] += h;
                        b[i] += h;
                        b[j] -= h;
                        c[i] -= h;
                        c[j] += h;
                        e[i] -= h;
                        e[j] -= h;
                        let fd = (f(a) - f(b) - f(c) + f(e)) / (4.0 * h * h);
                        assert!(
                            (fd - h2[i][j]).abs() < 2e-6,
                            "θ {theta} H[{i}][{j}]: fd {fd} vs {}",
                            h2[i][j]
                        );
                        assert_eq!(s[i][j].to_bits(), s[j][i].to_bits());
                    }
                }
                let sr = mat_vec(&s, r);
                for i in 0..3 {
                    assert!((sr[i] - r[i]).abs() < 1e-15 * (1.0 + theta));
                }
            }
        }
        // Continuity across the series switch and the ends: S(0) = I, S(π r̂) = r̂r̂ᵀ.
        let (a, b) = (dist_hess_sqrt([0.1 - 1e-12, 0.0, 0.0]), dist_hess_sqrt([0.1 + 1e-12, 0.0, 0.0]));
        for i in 0..3 {
            for j in 0..3 {
                assert!((a[i][j] - b[i][j]).abs() < 1e-13);
            }
        }
        let z = dist_hess_sqrt([0.0; 3]);
        assert_eq!(z, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let p = dist_hess_sqrt([0.0, std::f64::consts::PI, 0.0]);
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == 1 && j == 1 { 1.0 } else { 0.0 };
                assert!((p[i][j] - want).abs() < 1e-7, "S(π ŷ)[{i}][{j}] = {}", p[i][j]);
            }
        }
    }
}
