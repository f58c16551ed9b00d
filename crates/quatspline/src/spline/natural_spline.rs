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
//! Keyframe control (`with_keyframes`): `Rest` ends (zero rates at both ends), `Closed` loops
//! (cyclic system, C² across the seam, at least 3 keys), holds (rates pinned to zero at the
//! keys that bound a hold: exactly constant in between, C¹ there). The segments are the
//! Hermite segments of `hermite.rs` with the solved rates.

use super::hermite::{bases_and_chords, RotvecSegments};
use super::keyframe::prepare_loop;
use super::{segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::JQuat;
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
    /// Rest to rest: zero angular velocity at both ends (the acceleration is then free: a
    /// cubic cannot also zero it).
    Rest,
    /// A periodic loop (see `keyframe.rs`): C² at every key and across the seam, solved as a
    /// cyclic block-tridiagonal system.
    Closed,
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
pub(crate) fn rate_to_rotvec_dot(r: Vec3) -> Matrix3<f64> {
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
pub(crate) fn accel_nonlinear(r: Vec3, rd: Vec3) -> Vec3 {
    let x = vec3::norm(r);
    let dp = vec3::dot(r, rd);
    let cp = vec3::cross(r, rd);
    let ccp = vec3::cross(r, cp);
    let dccp = vec3::cross(rd, cp);
    let (k1, k2, k3) = (accel_k1(x), accel_k2(x), x_minus_sin_over_cube(x));
    vec3::add(vec3::add(vec3::scale(cp, dp * k1), vec3::scale(ccp, dp * k2)), vec3::scale(dccp, k3))
}

/// The three coefficients of [`accel_nonlinear`] for one rotation vector (they depend on |r|
/// only: computed once per segment, not once per sweep of the solve).
fn accel_coefficients(r: Vec3) -> (f64, f64, f64) {
    let x = vec3::norm(r);
    (accel_k1(x), accel_k2(x), x_minus_sin_over_cube(x))
}

/// [`accel_nonlinear`] with its coefficients precomputed (bit-identical).
fn accel_nonlinear_with(r: Vec3, rd: Vec3, (k1, k2, k3): (f64, f64, f64)) -> Vec3 {
    let dp = vec3::dot(r, rd);
    let cp = vec3::cross(r, rd);
    let ccp = vec3::cross(r, cp);
    let dccp = vec3::cross(rd, cp);
    vec3::add(vec3::add(vec3::scale(cp, dp * k1), vec3::scale(ccp, dp * k2)), vec3::scale(dccp, k3))
}

/// Block Thomas elimination factored once: the multipliers L_k D'_{k−1}⁻¹ and the inverted
/// pivots D'_k⁻¹ do not change between the sweeps of the non-linear iteration (only the right
/// side does), so each sweep is two linear passes of 3×3 products. Same operations as
/// [`solve_block_tridiagonal`], so the same bits.
struct BlockThomas {
    m: Vec<Matrix3<f64>>,
    dinv: Vec<Matrix3<f64>>,
    u: Vec<Matrix3<f64>>,
}

impl BlockThomas {
    fn factor(l: &[Matrix3<f64>], d: &[Matrix3<f64>], u: &[Matrix3<f64>]) -> Option<Self> {
        let n = d.len();
        let mut dp = d.to_vec();
        let mut m = vec![Matrix3::zeros(); n];
        for k in 1..n {
            m[k] = l[k] * dp[k - 1].try_inverse()?;
            let upd = m[k] * u[k - 1];
            dp[k] -= upd;
        }
        let dinv = dp.iter().map(|x| x.try_inverse()).collect::<Option<Vec<_>>>()?;
        Some(BlockThomas { m, dinv, u: u.to_vec() })
    }

    fn solve(&self, b: &mut [Vector3<f64>]) {
        let n = b.len();
        for k in 1..n {
            let r = self.m[k] * b[k - 1];
            b[k] -= r;
        }
        b[n - 1] = self.dinv[n - 1] * b[n - 1];
        for k in (0..n - 1).rev() {
            b[k] = self.dinv[k] * (b[k] - self.u[k] * b[k + 1]);
        }
    }
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
    seg: RotvecSegments,
    /// Body angular velocity at each key.
    rates: Vec<Vec3>,
    closed: bool,
    /// C² everywhere, or C¹ where holds pin the rate to zero.
    order: u8,
}

/// What fixes the rate at one key.
#[derive(Debug, Clone, Copy)]
enum Row {
    /// Continuity of angular acceleration with the neighbours (segments on both sides).
    Continuity,
    /// The rate is given.
    Fixed(Vec3),
    /// Zero angular acceleration at the start (first key) or end (last key) of an open curve.
    NaturalStart,
    NaturalEnd,
}

/// Solves the cyclic block-tridiagonal system (l[0] couples x[n−1], u[n−1] couples x[0]) by
/// bordering: x_k = y_k + Z_k x₀ from the open system of rows 1 … n−1, then row 0 for x₀.
fn solve_cyclic(
    l: &[Matrix3<f64>],
    d: &[Matrix3<f64>],
    u: &[Matrix3<f64>],
    b: &[Vector3<f64>],
) -> Option<Vec<Vector3<f64>>> {
    let n = d.len();
    let (li, di, ui) = (&l[1..], &d[1..], &u[1..]);
    let y = solve_block_tridiagonal(li, di, ui, &b[1..])?;
    // Columns of Z: T Z = −E, E = L₁ in the first row and U_{n−1} in the last.
    let mut z = vec![Matrix3::zeros(); n - 1];
    for c in 0..3 {
        let mut e = vec![Vector3::zeros(); n - 1];
        e[0] -= l[1].column(c);
        e[n - 2] -= u[n - 1].column(c);
        let col = solve_block_tridiagonal(li, di, ui, &e)?;
        for (k, v) in col.iter().enumerate() {
            z[k].set_column(c, v);
        }
    }
    let m = d[0] + l[0] * z[n - 2] + u[0] * z[0];
    let x0 = m.try_inverse()? * (b[0] - l[0] * y[n - 2] - u[0] * y[0]);
    let mut x = vec![x0];
    x.extend((0..n - 1).map(|k| y[k] + z[k] * x0));
    Some(x)
}

impl NaturalSpline {
    pub fn new(keys: &[Quat], times: Option<&[f64]>, ends: NaturalEnds, canonicalize: bool) -> Result<Self> {
        Self::with_keyframes(keys, times, ends, false, canonicalize)
    }

    /// With keyframe control: `ends` may also be `Rest` or `Closed`; `holds` pins the rate of
    /// every key that starts or ends a hold (consecutive equal keys) to zero, so the hold is
    /// exactly constant; the curve is then C¹ (not C²) at those keys.
    pub fn with_keyframes(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: NaturalEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        let closed = ends == NaturalEnds::Closed;
        let kl =
            prepare_loop(keys, times, closed, if closed { 3 } else { 2 }, "natural spline", canonicalize)?;
        let n = kl.keys.len();
        let segs = kl.segments();
        let (base, rho) = bases_and_chords(&kl);
        let h: Vec<f64> = (0..segs).map(|i| kl.h(i)).collect();
        let a: Vec<Matrix3<f64>> = rho.iter().map(|&r| rate_to_rotvec_dot(r)).collect();
        let ai: Vec<Matrix3<f64>> = rho.iter().map(|&r| rotvec_dot_to_rate(r)).collect();
        let chord = |i: usize| vec3::scale(rho[i], 1.0 / h[i]);
        let mut rows: Vec<Row> = (0..n)
            .map(|k| {
                if closed || (k > 0 && k < n - 1) {
                    return Row::Continuity;
                }
                let first = k == 0;
                match ends {
                    NaturalEnds::Natural | NaturalEnds::Closed => {
                        if first {
                            Row::NaturalStart
                        } else {
                            Row::NaturalEnd
                        }
                    }
                    NaturalEnds::Rest => Row::Fixed([0.0; 3]),
                    NaturalEnds::Clamped { start, end } => Row::Fixed(if first {
                        start.unwrap_or_else(|| chord(0))
                    } else {
                        end.unwrap_or_else(|| chord(n - 2))
                    }),
                }
            })
            .collect();
        if let NaturalEnds::Clamped { start, end } = ends {
            for (name, v) in [("start_rate", start), ("end_rate", end)] {
                if v.is_some_and(|v| v.iter().any(|c| !c.is_finite())) {
                    return Err(Error::NonFinite { arg: name, index: 0 });
                }
            }
        }
        let mut pinned = false;
        if holds {
            for (k, hold) in kl.hold_keys().into_iter().enumerate() {
                if hold {
                    rows[k] = Row::Fixed([0.0; 3]);
                    pinned = true;
                }
            }
        }
        let zero = Matrix3::zeros();
        let eye = Matrix3::identity();
        let (mut l, mut d, mut u) = (vec![zero; n], vec![zero; n], vec![zero; n]);
        let mut b0 = vec![Vector3::zeros(); n];
        // Segment to the left / right of key k (cyclic when closed).
        let left = |k: usize| if k == 0 { segs - 1 } else { k - 1 };
        for k in 0..n {
            match rows[k] {
                Row::Fixed(w) => {
                    d[k] = eye;
                    b0[k] = v3(w);
                }
                Row::NaturalStart => {
                    d[k] = eye * (4.0 / h[0]);
                    u[k] = a[0] * (2.0 / h[0]);
                    b0[k] = v3(rho[0]) * (6.0 / (h[0] * h[0]));
                }
                Row::NaturalEnd => {
                    let m = k - 1;
                    l[k] = ai[m] * (2.0 / h[m]);
                    d[k] = eye * (4.0 / h[m]);
                    b0[k] = v3(rho[m]) * (6.0 / (h[m] * h[m]));
                }
                Row::Continuity => {
                    let (p, q) = (left(k), k);
                    l[k] = ai[p] * (2.0 / h[p]);
                    d[k] = eye * (4.0 * (1.0 / h[p] + 1.0 / h[q]));
                    u[k] = a[q] * (2.0 / h[q]);
                    b0[k] = v3(rho[p]) * (6.0 / (h[p] * h[p])) + v3(rho[q]) * (6.0 / (h[q] * h[q]));
                }
            }
        }
        // Initial guess: chord rates (zero where pinned).
        let mut w: Vec<Vec3> = (0..n)
            .map(|k| match rows[k] {
                Row::Fixed(v) => v,
                _ => chord(k.min(segs - 1)),
            })
            .collect();
        let singular = || Error::Internal("natural spline: singular tridiagonal block".into());
        let ks: Vec<(f64, f64, f64)> = rho.iter().map(|&r| accel_coefficients(r)).collect();
        let thomas = if closed { None } else { Some(BlockThomas::factor(&l, &d, &u).ok_or_else(singular)?) };
        let mut b = b0.clone();
        for _ in 0..100 {
            b.copy_from_slice(&b0);
            for k in 0..n {
                if matches!(rows[k], Row::Continuity | Row::NaturalEnd) {
                    let p = left(k);
                    let rd = a3(a[p] * v3(w[k]));
                    b[k] -= v3(accel_nonlinear_with(rho[p], rd, ks[p]));
                }
            }
            let cyclic;
            let x: &[Vector3<f64>] = match &thomas {
                Some(f) => {
                    f.solve(&mut b);
                    &b
                }
                None => {
                    cyclic = solve_cyclic(&l, &d, &u, &b).ok_or_else(singular)?;
                    &cyclic
                }
            };
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
        let mut joint_rates = w.clone();
        if closed {
            joint_rates.push(w[0]);
        }
        let seg = RotvecSegments::new(base, &rho, kl.times, &joint_rates, None);
        Ok(NaturalSpline { seg, rates: w, closed, order: if pinned { 1 } else { 2 } })
    }

    /// Body angular velocity at each key (the solved unknowns).
    pub fn key_rates(&self) -> &[Vec3] {
        &self.rates
    }

    #[inline(always)]
    pub(crate) fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        self.seg.segment::<N>(i, t)
    }
}

impl Spline for NaturalSpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "natural"
    }
    fn joints(&self) -> &[f64] {
        self.seg.joints()
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        self.order
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        Some(&self.seg.batch)
    }
    fn closed(&self) -> bool {
        self.closed
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
