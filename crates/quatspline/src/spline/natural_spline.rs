//! The global interpolating C² spline: "natural cubic spline" of seed 002 §9.4, in the
//! rotation-vector construction scipy's `RotationSpline` uses (MATH.md §6b).
//!
//! Segment i, s = τ − τᵢ ∈ [0, hᵢ]: q(τ) = qᵢ exp(½ rᵢ(s)), rᵢ a cubic in the rotation
//! vector with rᵢ(0) = 0, rᵢ'(0) = ωᵢ, rᵢ(hᵢ) = ρᵢ = rotvec(qᵢ* qᵢ₊₁), rᵢ'(hᵢ) = A(ρᵢ) ωᵢ₊₁,
//! where ωₖ is the body angular velocity at key k and A maps angular rate to rotation-vector
//! rate. Continuity of angular acceleration at every interior key gives a block-tridiagonal
//! system in the ωₖ whose only non-linearity (the quadratic term of the acceleration) is
//! iterated to convergence (|Δω| ≤ 1e-14 (1 + |ω|), at most 100 sweeps).
//! End conditions: `Natural` (zero angular acceleration at both ends) or `Clamped` (given body
//! rates at both ends; default the end segments' chord rates ρ/h — exactly scipy's choice).
//! C² in time, interpolating, global support (moving one key moves every segment).
//! Two keys: slerp, under both end conditions (with the default clamped rates).

use super::{prepare_keys, prepare_times, segment_jets, Spline};
use crate::convert::to_rotvec;
use crate::error::{Error, Result};
use crate::jet::{JQuat, Jet};
use crate::quat::Quat;
use crate::vec3::{self, Vec3};
use nalgebra::{Matrix3, Vector3};

/// End conditions of [`NaturalSpline`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NaturalEnds {
    /// Zero angular acceleration at the first and last key.
    Natural,
    /// Given body angular velocities at the first and last key (None: the chord rate of the
    /// end segment, which is what scipy's `RotationSpline` uses).
    Clamped { start: Option<Vec3>, end: Option<Vec3> },
}

/// Σ c_m x^(2m) for |x| below `switch`, else the closed form: named singular ratios of the
/// rotation-vector kinematics, each with its series (coefficients derived in the doc of each).
fn series(x2: f64, coef: impl Fn(usize) -> f64) -> f64 {
    let mut acc = 0.0;
    let mut p = 1.0;
    for m in 0..10 {
        acc += coef(m) * p;
        p *= x2;
    }
    acc
}

fn fact(n: usize) -> f64 {
    (1..=n).map(|v| v as f64).product()
}

fn alt(m: usize) -> f64 {
    if m.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

/// (1 − cos x)/x² = Σ (−1)^m x^(2m)/(2m+2)!
fn one_minus_cos_over_sq(x: f64) -> f64 {
    if x < 0.5 {
        series(x * x, |m| alt(m) / fact(2 * m + 2))
    } else {
        (1.0 - x.cos()) / (x * x)
    }
}

/// (x − sin x)/x³ = Σ (−1)^m x^(2m)/(2m+3)!
fn x_minus_sin_over_cube(x: f64) -> f64 {
    if x < 0.5 {
        series(x * x, |m| alt(m) / fact(2 * m + 3))
    } else {
        (x - x.sin()) / (x * x * x)
    }
}

/// (1 − (x/2) cot(x/2))/x² = −Σ_{n≥1} (−1)^n B₂ₙ x^(2n−2)/(2n)!  (Bernoulli numbers)
fn one_minus_half_cot_over_sq(x: f64) -> f64 {
    if x < 0.3 {
        const B: [f64; 7] =
            [1.0 / 6.0, -1.0 / 30.0, 1.0 / 42.0, -1.0 / 30.0, 5.0 / 66.0, -691.0 / 2730.0, 7.0 / 6.0];
        let x2 = x * x;
        let mut acc = 0.0;
        let mut p = 1.0;
        for (k, b) in B.iter().enumerate() {
            let n = k + 1;
            acc -= alt(n) * b * p / fact(2 * n);
            p *= x2;
        }
        acc
    } else {
        (1.0 - 0.5 * x / (0.5 * x).tan()) / (x * x)
    }
}

/// (−x sin x − 2(cos x − 1))/x⁴ = Σ (−1)^m (2m+2) x^(2m)/(2m+4)!
fn accel_k1(x: f64) -> f64 {
    if x < 0.5 {
        series(x * x, |m| alt(m) * (2 * m + 2) as f64 / fact(2 * m + 4))
    } else {
        (-x * x.sin() - 2.0 * (x.cos() - 1.0)) / x.powi(4)
    }
}

/// (−2x + 3 sin x − x cos x)/x⁵ = Σ (−1)^(m+1) (2m+2) x^(2m)/(2m+5)!  (scipy has 1/12604
/// for the x² coefficient 1/1260)
fn accel_k2(x: f64) -> f64 {
    if x < 0.5 {
        series(x * x, |m| -alt(m) * (2 * m + 2) as f64 / fact(2 * m + 5))
    } else {
        (-2.0 * x + 3.0 * x.sin() - x * x.cos()) / x.powi(5)
    }
}

fn skew(v: Vec3) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// A(ρ): angular rate → rotation-vector rate, I + ½[ρ]× + k [ρ]×².
fn rate_to_rotvec_dot(r: Vec3) -> Matrix3<f64> {
    let s = skew(r);
    Matrix3::identity() + s * 0.5 + s * s * one_minus_half_cot_over_sq(vec3::norm(r))
}

/// A⁻¹(ρ): rotation-vector rate → angular rate, I − k₁[ρ]× + k₂[ρ]×².
fn rotvec_dot_to_rate(r: Vec3) -> Matrix3<f64> {
    let s = skew(r);
    let x = vec3::norm(r);
    Matrix3::identity() - s * one_minus_cos_over_sq(x) + s * s * x_minus_sin_over_cube(x)
}

/// The quadratic term of the angular acceleration in the rotation-vector rate.
fn accel_nonlinear(r: Vec3, rd: Vec3) -> Vec3 {
    let x = vec3::norm(r);
    let dp = vec3::dot(r, rd);
    let cp = vec3::cross(r, rd);
    let ccp = vec3::cross(r, cp);
    let dccp = vec3::cross(rd, cp);
    let (k1, k2, k3) = (accel_k1(x), accel_k2(x), x_minus_sin_over_cube(x));
    vec3::add(vec3::add(vec3::scale(cp, dp * k1), vec3::scale(ccp, dp * k2)), vec3::scale(dccp, k3))
}

fn v3(a: Vec3) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

fn a3(v: Vector3<f64>) -> Vec3 {
    [v[0], v[1], v[2]]
}

/// Solves L_k x_{k−1} + D_k x_k + U_k x_{k+1} = b_k (3×3 blocks) by block Thomas elimination.
fn solve_block_tridiagonal(
    l: &[Matrix3<f64>],
    d: &[Matrix3<f64>],
    u: &[Matrix3<f64>],
    b: &[Vector3<f64>],
) -> Option<Vec<Vector3<f64>>> {
    let n = d.len();
    let mut dp = d.to_vec();
    let mut bp = b.to_vec();
    for k in 1..n {
        let m = l[k] * dp[k - 1].try_inverse()?;
        dp[k] -= m * u[k - 1];
        bp[k] = bp[k] - m * bp[k - 1];
    }
    let mut x = vec![Vector3::zeros(); n];
    x[n - 1] = dp[n - 1].try_inverse()? * bp[n - 1];
    for k in (0..n - 1).rev() {
        x[k] = dp[k].try_inverse()? * (bp[k] - u[k] * x[k + 1]);
    }
    Some(x)
}

/// The global C² interpolating spline.
#[derive(Debug, Clone)]
pub struct NaturalSpline {
    keys: Vec<Quat>,
    times: Vec<f64>,
    /// Per segment: coefficients of s, s², s³ of rᵢ(s).
    coef: Vec<[Vec3; 3]>,
    /// Body angular velocity at each key.
    rates: Vec<Vec3>,
}

impl NaturalSpline {
    pub fn new(keys: &[Quat], times: Option<&[f64]>, ends: NaturalEnds, canonicalize: bool) -> Result<Self> {
        let keys = prepare_keys(keys, "quats", 2, canonicalize)?;
        let times = prepare_times(times, keys.len())?;
        let n = keys.len();
        let h: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let rho: Vec<Vec3> = keys.windows(2).map(|w| to_rotvec(w[0].conj() * w[1])).collect();
        let a: Vec<Matrix3<f64>> = rho.iter().map(|&r| rate_to_rotvec_dot(r)).collect();
        let ai: Vec<Matrix3<f64>> = rho.iter().map(|&r| rotvec_dot_to_rate(r)).collect();
        let chord = |i: usize| vec3::scale(rho[i], 1.0 / h[i]);
        let (start, end) = match ends {
            NaturalEnds::Natural => (None, None),
            NaturalEnds::Clamped { start, end } => {
                for (name, v) in [("start_rate", start), ("end_rate", end)] {
                    if v.is_some_and(|v| v.iter().any(|c| !c.is_finite())) {
                        return Err(Error::NonFinite { arg: name, index: 0 });
                    }
                }
                (Some(start.unwrap_or_else(|| chord(0))), Some(end.unwrap_or_else(|| chord(n - 2))))
            }
        };
        let zero = Matrix3::zeros();
        let eye = Matrix3::identity();
        let (mut l, mut d, mut u) = (vec![zero; n], vec![zero; n], vec![zero; n]);
        let mut b0 = vec![Vector3::zeros(); n];
        // Row 0
        if let Some(w0) = start {
            d[0] = eye;
            b0[0] = v3(w0);
        } else {
            d[0] = eye * (4.0 / h[0]);
            u[0] = a[0] * (2.0 / h[0]);
            b0[0] = v3(rho[0]) * (6.0 / (h[0] * h[0]));
        }
        // Interior rows: continuity of angular acceleration at key k.
        for k in 1..n - 1 {
            l[k] = ai[k - 1] * (2.0 / h[k - 1]);
            d[k] = eye * (4.0 * (1.0 / h[k - 1] + 1.0 / h[k]));
            u[k] = a[k] * (2.0 / h[k]);
            b0[k] = v3(rho[k - 1]) * (6.0 / (h[k - 1] * h[k - 1])) + v3(rho[k]) * (6.0 / (h[k] * h[k]));
        }
        // Last row
        let m = n - 1;
        if let Some(we) = end {
            d[m] = eye;
            b0[m] = v3(we);
        } else {
            l[m] = ai[m - 1] * (2.0 / h[m - 1]);
            d[m] = eye * (4.0 / h[m - 1]);
            b0[m] = v3(rho[m - 1]) * (6.0 / (h[m - 1] * h[m - 1]));
        }
        // Initial guess: chord rates.
        let mut w: Vec<Vec3> = (0..n).map(|k| chord(k.min(n - 2))).collect();
        for _ in 0..100 {
            let mut b = b0.clone();
            for k in 1..n {
                let constrained = k < n - 1 || end.is_none();
                if constrained {
                    let rd = a3(a[k - 1] * v3(w[k]));
                    b[k] -= v3(accel_nonlinear(rho[k - 1], rd));
                }
            }
            let x = solve_block_tridiagonal(&l, &d, &u, &b)
                .ok_or_else(|| Error::Internal("natural spline: singular tridiagonal block".into()))?;
            let mut delta: f64 = 0.0;
            for k in 0..n {
                let new = a3(x[k]);
                for c in 0..3 {
                    delta = delta.max((new[c] - w[k][c]).abs() / (1.0 + new[c].abs()));
                }
                w[k] = new;
            }
            if delta <= 1e-14 {
                break;
            }
        }
        if w.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::invalid("quats", "natural spline solve diverged (keys too far apart?)"));
        }
        let coef = (0..n - 1)
            .map(|i| {
                let hi = h[i];
                let rd1 = a3(a[i] * v3(w[i + 1]));
                let c3: Vec3 =
                    std::array::from_fn(|c| (-2.0 * rho[i][c] + hi * w[i][c] + hi * rd1[c]) / hi.powi(3));
                let c2: Vec3 =
                    std::array::from_fn(|c| (3.0 * rho[i][c] - 2.0 * hi * w[i][c] - hi * rd1[c]) / (hi * hi));
                [w[i], c2, c3]
            })
            .collect();
        Ok(NaturalSpline { keys, times, coef, rates: w })
    }

    /// Body angular velocity at each key (the solved unknowns).
    pub fn key_rates(&self) -> &[Vec3] {
        &self.rates
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let s = Jet::<N>::variable(t - self.times[i], 1.0);
        let [c1, c2, c3] = self.coef[i];
        let r: [Jet<N>; 3] =
            std::array::from_fn(|c| Jet::poly(&[0.0, 0.5 * c1[c], 0.5 * c2[c], 0.5 * c3[c]], s));
        JQuat::constant(self.keys[i]) * JQuat::exp_pure(r)
    }
}

impl Spline for NaturalSpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "natural"
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_switches_are_continuous() {
        type Helper = fn(f64) -> f64;
        let f: [(Helper, f64); 5] = [
            (one_minus_cos_over_sq, 0.5),
            (x_minus_sin_over_cube, 0.5),
            (one_minus_half_cot_over_sq, 0.3),
            (accel_k1, 0.5),
            (accel_k2, 0.5),
        ];
        for (g, s) in f {
            let (a, b) = (g(s * (1.0 - 1e-13)), g(s * (1.0 + 1e-13)));
            assert!((a - b).abs() < 1e-14 * a.abs().max(1.0), "{a} vs {b}");
        }
        assert!((accel_k2(0.0) + 1.0 / 60.0).abs() < 1e-17);
        assert!((one_minus_half_cot_over_sq(0.0) - 1.0 / 12.0).abs() < 1e-17);
    }
}
