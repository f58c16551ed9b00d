//! The global interpolating C² spline: "natural cubic spline" of seed 002 §9.4, in the
//! rotation-vector construction scipy's `RotationSpline` uses (MATH.md §6b).
//!
//! Segment i, s = τ − τᵢ ∈ [0, hᵢ]: q(τ) = qᵢ exp(½ rᵢ(s)), rᵢ a cubic in the rotation
//! vector with rᵢ(0) = 0, rᵢ'(0) = ωᵢ, rᵢ(hᵢ) = ρᵢ = rotvec(qᵢ* qᵢ₊₁), rᵢ'(hᵢ) = A(ρᵢ) ωᵢ₊₁,
//! where ωₖ is the body angular velocity at key k and A maps angular rate to rotation-vector
//! rate. Continuity of angular acceleration at every interior key gives a block-tridiagonal
//! system in the ωₖ whose only non-linearity (the quadratic term of the acceleration, at key k
//! a function of ωₖ alone) is solved by Newton's method: the Jacobian keeps the
//! block-tridiagonal pattern, so each step is one block Thomas elimination — linear in the
//! keys, ~4–6 steps to |Δω| ≤ 1e-14 (1 + |ω|). The earlier fixed-point iteration (same
//! criterion, ~55 sweeps on random keys) remains as the fallback when Newton does not
//! converge, and as the reference the tests compare against.
//! End conditions: `Natural` (zero angular acceleration at both ends) or `Clamped` (given body
//! rates at both ends; default the end segments' chord rates ρ/h — exactly scipy's choice).
//! C² in time, interpolating, global support (moving one key moves every segment).
//! Two keys: slerp, under both end conditions (with the default clamped rates).
//! Keyframe control (`with_keyframes`): `Rest` ends (zero rates at both ends), `Closed` loops
//! (cyclic system, C² across the seam, at least 3 keys), holds (rates pinned to zero at the
//! keys that bound a hold: exactly constant in between, C¹ there). The segments are the
//! Hermite segments of `rotvec_segments.rs` (shared with `hermite.rs`) with the solved rates;
//! A(ρ), A⁻¹(ρ) and N are in [`crate::kinematics`].

use super::keyframe::prepare_loop;
use super::rotvec_segments::{bases_and_chords, RotvecSegments};
use super::{segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::JQuat;
use crate::kinematics::{
    accel_coefficients, accel_nonlinear_jacobian, accel_nonlinear_with, rate_to_rotvec_dot,
    rotvec_dot_to_rate,
};
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

/// How the rates are solved (Newton by default; the fixed-point iteration is the fallback
/// and the reference the tests compare Newton against).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) enum Solver {
    Newton,
    /// Newton without the fallback (an error if it does not converge).
    NewtonOnly,
    FixedPoint,
}

#[cfg(test)]
thread_local! {
    /// The relative residual of the last construction on this thread (tests).
    static LAST_RESIDUAL: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

/// Newton steps before giving up (and falling back to the fixed-point iteration).
const NEWTON_STEPS: usize = 40;

/// The system T w + N(w) = b₀: T block-tridiagonal (l, d, u; cyclic when closed), N the
/// quadratic acceleration term, which at key k depends on w_k alone (block-diagonal Jacobian).
struct System<'a> {
    rows: &'a [Row],
    l: &'a [Matrix3<f64>],
    d: &'a [Matrix3<f64>],
    u: &'a [Matrix3<f64>],
    b0: &'a [Vector3<f64>],
    a: &'a [Matrix3<f64>],
    rho: &'a [Vec3],
    ks: &'a [(f64, f64, f64)],
    closed: bool,
    segs: usize,
}

impl System<'_> {
    /// The segment to the left of key k (cyclic when closed).
    fn left(&self, k: usize) -> usize {
        if k == 0 {
            self.segs - 1
        } else {
            k - 1
        }
    }

    fn has_nonlinear(&self, k: usize) -> bool {
        matches!(self.rows[k], Row::Continuity | Row::NaturalEnd)
    }

    /// max_k |F_k(w)|∞ / (1 + |b₀_k|∞), F = b₀ − T w − N(w) (tests).
    #[cfg(test)]
    fn residual(&self, w: &[Vec3]) -> f64 {
        let n = w.len();
        (0..n)
            .map(|k| {
                let wk = v3(w[k]);
                let mut res = self.b0[k]
                    - self.d[k] * wk
                    - self.l[k] * v3(w[(k + n - 1) % n])
                    - self.u[k] * v3(w[(k + 1) % n]);
                if self.has_nonlinear(k) {
                    let p = self.left(k);
                    res -= v3(accel_nonlinear_with(self.rho[p], a3(self.a[p] * wk), self.ks[p]));
                }
                res.amax() / (1.0 + self.b0[k].amax())
            })
            .fold(0.0, f64::max)
    }

    /// The original solve: w ← T⁻¹(b₀ − N(w)) until |Δw| ≤ 1e-14 (1 + |w|), at most 100
    /// sweeps (linear convergence; ~55 sweeps on random keys). None: a singular block.
    fn fixed_point(&self, w: &mut [Vec3]) -> Option<()> {
        let n = w.len();
        let thomas = if self.closed { None } else { Some(BlockThomas::factor(self.l, self.d, self.u)?) };
        let mut b = self.b0.to_vec();
        for _ in 0..100 {
            b.copy_from_slice(self.b0);
            for k in 0..n {
                if self.has_nonlinear(k) {
                    let p = self.left(k);
                    let rd = a3(self.a[p] * v3(w[k]));
                    b[k] -= v3(accel_nonlinear_with(self.rho[p], rd, self.ks[p]));
                }
            }
            let cyclic;
            let x: &[Vector3<f64>] = match &thomas {
                Some(f) => {
                    f.solve(&mut b);
                    &b
                }
                None => {
                    cyclic = solve_cyclic(self.l, self.d, self.u, &b)?;
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
        Some(())
    }

    /// Newton's method on F(w) = b₀ − T w − N(w): the Jacobian T + diag(∂N_k/∂w_k) keeps T's
    /// block-tridiagonal pattern, so each step is one block Thomas elimination (cyclic
    /// bordering when closed), linear in the keys; quadratic convergence takes ~4–6 steps
    /// where the fixed-point iteration takes ~55 sweeps. Stops at |Δw| ≤ 1e-14 (1 + |w|)
    /// (the fixed point's criterion), when Δ stops shrinking below 1e-11 (rounding floor),
    /// or in the quadratic phase when the error left after a step (≈ (δ/δ_prev²) δ²) is below
    /// 1e-16.
    /// None when it does not converge (or meets a singular block): the caller falls back.
    fn newton(&self, w0: &[Vec3]) -> Option<Vec<Vec3>> {
        let n = w0.len();
        let mut w = w0.to_vec();
        let mut r = vec![Vector3::zeros(); n];
        let mut g = vec![Matrix3::zeros(); n];
        let mut inv = vec![Matrix3::zeros(); if self.closed { 0 } else { n }];
        let mut prev = f64::INFINITY;
        for _ in 0..NEWTON_STEPS {
            for k in 0..n {
                let wk = v3(w[k]);
                // l[0] and u[n−1] are zero on an open curve: the wrap-around is harmless
                let mut res = self.b0[k]
                    - self.d[k] * wk
                    - self.l[k] * v3(w[(k + n - 1) % n])
                    - self.u[k] * v3(w[(k + 1) % n]);
                let mut dk = self.d[k];
                if self.has_nonlinear(k) {
                    let p = self.left(k);
                    let rd = a3(self.a[p] * wk);
                    res -= v3(accel_nonlinear_with(self.rho[p], rd, self.ks[p]));
                    dk += accel_nonlinear_jacobian(self.rho[p], rd, self.ks[p]) * self.a[p];
                }
                r[k] = res;
                g[k] = dk;
            }
            let cyclic;
            let x: &[Vector3<f64>] = if self.closed {
                cyclic = solve_cyclic(self.l, &g, self.u, &r)?;
                &cyclic
            } else {
                inv[0] = g[0].try_inverse()?;
                for k in 1..n {
                    let m = self.l[k] * inv[k - 1];
                    let rk = r[k] - m * r[k - 1];
                    r[k] = rk;
                    inv[k] = (g[k] - m * self.u[k - 1]).try_inverse()?;
                }
                r[n - 1] = inv[n - 1] * r[n - 1];
                for k in (0..n - 1).rev() {
                    r[k] = inv[k] * (r[k] - self.u[k] * r[k + 1]);
                }
                &r
            };
            let mut delta: f64 = 0.0;
            for k in 0..n {
                for c in 0..3 {
                    let new = w[k][c] + x[k][c];
                    delta = delta.max((new - w[k][c]).abs() / (1.0 + new.abs()));
                    w[k][c] = new;
                }
            }
            if !delta.is_finite() {
                return None;
            }
            // done when the step is below the criterion, when rounding stops it shrinking, or in
            // the quadratic phase (δ < 1e-10) when the error left after this step, estimated
            // (δ/δ_prev²) δ², is below 1e-16
            if delta <= 1e-14
                || (delta < 1e-11 && delta >= prev)
                || (delta < 1e-10 && delta.powi(3) <= 1e-16 * prev * prev)
            {
                return Some(w);
            }
            prev = delta;
        }
        None
    }
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
        Self::with_solver(keys, times, ends, holds, canonicalize, Solver::Newton)
    }

    /// [`with_keyframes`](Self::with_keyframes) with a choice of solver (tests compare them).
    pub(crate) fn with_solver(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: NaturalEnds,
        holds: bool,
        canonicalize: bool,
        solver: Solver,
    ) -> Result<Self> {
        let closed = ends == NaturalEnds::Closed;
        let kl =
            prepare_loop(keys, times, closed, if closed { 3 } else { 2 }, "natural spline", canonicalize)?;
        let n = kl.keys.len();
        let segs = kl.segments();
        let (base, rho) = bases_and_chords(&kl);
        let h: Vec<f64> = (0..segs).map(|i| kl.h(i)).collect();
        let a: Vec<Matrix3<f64>> = super::par_map(rho.len(), |i| rate_to_rotvec_dot(rho[i]));
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
                    l[k] = rotvec_dot_to_rate(rho[m]) * (2.0 / h[m]);
                    d[k] = eye * (4.0 / h[m]);
                    b0[k] = v3(rho[m]) * (6.0 / (h[m] * h[m]));
                }
                Row::Continuity => {
                    let (p, q) = (left(k), k);
                    l[k] = rotvec_dot_to_rate(rho[p]) * (2.0 / h[p]);
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
        let ks: Vec<(f64, f64, f64)> = super::par_map(rho.len(), |i| accel_coefficients(rho[i]));
        let sys =
            System { rows: &rows, l: &l, d: &d, u: &u, b0: &b0, a: &a, rho: &rho, ks: &ks, closed, segs };
        let newton = if solver == Solver::FixedPoint { None } else { sys.newton(&w) };
        match newton {
            Some(x) => w = x,
            None if solver == Solver::NewtonOnly => {
                return Err(Error::Internal("natural spline: Newton did not converge".into()))
            }
            None => sys.fixed_point(&mut w).ok_or_else(singular)?,
        }
        #[cfg(test)]
        LAST_RESIDUAL.set(sys.residual(&w));
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

    /// A deterministic generator: uniform in [0, 1).
    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Keys a random walk of step up to `step` radians (with holds: a key repeated).
    fn walk(n: usize, step: f64, holds: bool, seed: u64) -> (Vec<Quat>, Vec<f64>) {
        let mut r = lcg(seed);
        let mut q = Quat::new(1.0, 0.0, 0.0, 0.0);
        let (mut keys, mut times) = (vec![q], vec![0.0]);
        for i in 1..n {
            if !(holds && i % 5 == 2) {
                let v = [r() - 0.5, r() - 0.5, r() - 0.5];
                let s = step * r() / vec3::norm(v).max(1e-9);
                q = q * crate::convert::from_rotvec(vec3::scale(v, s));
            }
            keys.push(q);
            times.push(times[i - 1] + 0.05 + 2.0 * r());
        }
        (keys, times)
    }

    #[test]
    fn accel_jacobian_matches_finite_differences() {
        let mut r = lcg(3);
        for _ in 0..200 {
            let scale = [1e-3, 0.3, 1.0, 3.0][(4.0 * r()) as usize];
            let rho: Vec3 = std::array::from_fn(|_| scale * (2.0 * r() - 1.0));
            let rd: Vec3 = std::array::from_fn(|_| 4.0 * r() - 2.0);
            let ks = accel_coefficients(rho);
            let jac = accel_nonlinear_jacobian(rho, rd, ks);
            for c in 0..3 {
                let eps = 1e-6;
                let (mut p, mut m) = (rd, rd);
                p[c] += eps;
                m[c] -= eps;
                let (fp, fm) = (accel_nonlinear_with(rho, p, ks), accel_nonlinear_with(rho, m, ks));
                for row in 0..3 {
                    let fd = (fp[row] - fm[row]) / (2.0 * eps);
                    // central differences of a quadratic are exact up to rounding
                    assert!(
                        (fd - jac[(row, c)]).abs() <= 1e-8 * (1.0 + fd.abs()),
                        "{fd} vs {}",
                        jac[(row, c)]
                    );
                }
            }
        }
    }

    /// Newton's rates equal the fixed-point iteration's (the construction before Newton) for
    /// every end condition, holds, small and large steps between keys.
    #[test]
    fn newton_equals_fixed_point() {
        let ends = [
            NaturalEnds::Natural,
            NaturalEnds::Clamped { start: None, end: None },
            NaturalEnds::Clamped { start: Some([0.3, -0.2, 0.1]), end: Some([0.0, 0.5, 0.0]) },
            NaturalEnds::Rest,
            NaturalEnds::Closed,
        ];
        let mut worst: f64 = 0.0;
        for (case, &(n, step, holds)) in
            // step 100 rad: independent, uniformly spread keys (chords up to π)
            [
                (2, 1.0, false),
                (3, 0.5, false),
                (4, 2.5, false),
                (9, 0.01, false),
                (40, 1.5, false),
                (60, 2.8, true),
                (300, 2.0, false),
                (500, 100.0, false),
            ]
            .iter()
            .enumerate()
        {
            let (keys, times) = walk(n, step, holds, 11 + case as u64);
            for e in ends {
                if e == NaturalEnds::Closed && n < 3 {
                    continue;
                }
                let mut tt = times.clone();
                if e == NaturalEnds::Closed {
                    tt.push(times[n - 1] + 0.7);
                }
                let build = |solver| NaturalSpline::with_solver(&keys, Some(&tt), e, holds, true, solver);
                let a = build(Solver::NewtonOnly).unwrap();
                let res_newton = LAST_RESIDUAL.get();
                let b = build(Solver::FixedPoint).unwrap();
                let res_fixed = LAST_RESIDUAL.get();
                // Newton solves the C² equations at least as well as the fixed point did
                assert!(
                    res_newton <= 1e-13 && res_newton <= 2.0 * res_fixed.max(1e-15),
                    "residuals {res_newton:e} vs {res_fixed:e}"
                );
                eprintln!(
                    "n={n} step={step} {e:?}: residual newton {res_newton:e}, fixed point {res_fixed:e}"
                );
                if res_fixed > 1e-12 {
                    // the fixed point stopped at its 100-sweep cap unconverged (uniformly
                    // spread keys): Newton's rates are the solution, not a copy of those
                    assert!(step > 10.0, "fixed point unconverged on a walk: {res_fixed:e}");
                    continue;
                }
                assert_eq!(a.key_rates().len(), b.key_rates().len());
                for (x, y) in a.key_rates().iter().zip(b.key_rates()) {
                    for c in 0..3 {
                        let err = (x[c] - y[c]).abs() / (1.0 + y[c].abs());
                        worst = worst.max(err);
                        assert!(err <= 1e-12, "n={n} step={step} {e:?}: {x:?} vs {y:?}");
                    }
                }
            }
        }
        eprintln!("newton vs fixed point: worst relative difference {worst:e}");
    }
}
