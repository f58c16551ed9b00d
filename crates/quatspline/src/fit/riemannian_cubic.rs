//! The exact minimum-∫|ω̇|² interpolant: the Riemannian cubic spline of SO(3) (seed 003's
//! Spicv, the analytic optimum of which [`super::min_energy::MinEnergySpline`] is the discrete
//! approximation; MATH.md §13).
//!
//! **Equations.** With body angular velocity ω (q̇ = ½ q ⊗ (0, ω)) and the variation
//! q ↦ q·Exp(εη), δω = η̇ + ω × η, so ½ δ∫|ω̇|² = [⟨ω̇, η̇⟩ + ⟨ω̇ × ω − ω̈, η⟩] + ∫⟨ω⃛ + ω × ω̈, η⟩
//! (integrate by parts twice; ⟨a, b × c⟩ = ⟨a × b, c⟩). Hence between keys
//!   **ω⃛ + ω × ω̈ = 0**
//! (Noakes, Heinzinger & Paden, "Cubic splines on curved spaces", IMA J. Math. Control Inf.
//! 6, 1989; Crouch & Silva Leite, "The dynamic interpolation problem: on Riemannian manifolds,
//! Lie groups, and symmetric spaces", J. Dyn. Control Syst. 1, 1995), i.e. ω̈ + ω × ω̇ is
//! constant on each key interval. At an interior key η = 0 but η̇ is free, so ω (the curve is
//! C¹) and ω̇ are continuous; the jump of ω̈ there is the Lagrange multiplier of the
//! interpolation constraint. Ends: `Natural` gives ω̇ = 0 (η̇ free); `Rest` / `Clamped` fix ω
//! (η̇ = 0 there, no further condition); `Closed` makes ω, ω̇ continuous across the seam. A
//! hold (equal consecutive keys) is exactly constant with ω = 0 at its keys (as in the
//! natural and the discrete minimum-energy splines): C¹ there, and the runs between holds are
//! independent problems with rest ends at the hold.
//!
//! **Solution by multiple shooting.** Unknowns: the state z = (ω, ω̇, ω̈) at the start of every
//! key interval (q there is the key). One interval is integrated by a Taylor series method of
//! order [`ORDER`]: the ODE is polynomial, so the Taylor coefficients wₖ of ω and qₖ of q follow
//! exactly from the recurrences
//!   (k+1)(k+2)(k+3) w_{k+3} = −Σ_{m≤k} (k−m+1)(k−m+2) wₘ × w_{k−m+2},
//!   (k+1) q_{k+1} = ½ Σ_{m≤k} qₘ ⊗ (0, w_{k−m}),
//! with steps τ = min over k ∈ {P−1, P} of (ε/‖cₖ‖)^{1/k}, ε = 1e-16 relative (Jorba & Zou, "A
//! software package for the numerical integration of ODEs by means of high-order Taylor
//! methods", Exp. Math. 14, 2005). The sensitivities to z follow from the linearised
//! recurrences (δw) and, for q, from the right perturbation q·Exp(e) with ė = δω − ω × e.
//! Equations: Log(qᵢ₊₁⁻¹ q(tᵢ₊₁⁻)) = 0, ω and ω̇ continuous at interior keys, the end
//! conditions; Newton's method with backtracking on ‖F‖ solves them. The Jacobian is banded
//! (each interval couples its own state and the next one's ω, ω̇): a band LU with partial
//! pivoting, O(keys) per iteration; a closed loop adds a rank-6 corner (Woodbury). Start: the
//! natural spline's (ω, ω̇, ω̈) at the keys. Stop: the largest scaled mismatch (radians; ω·h,
//! ω̇·h²) below [`TOL`].
//!
//! **Evaluation.** The Taylor polynomials of q of every step are kept (dense output); q(t) and
//! its derivatives are those of the polynomial (normalised), so ω, ω̇, jerk are exact up to
//! the series' truncation (~1e-15). `energy` is ∫|ω̇|² integrated exactly from the series.

use super::so3;
use super::Progress;
use crate::error::{Error, Result};
use crate::jet::{angular, JQuat, Jet};
use crate::kinematics::{jr_inv, mat_vec};
use crate::quat::Quat;
use crate::spline::{same_rotation, segment_jets, NaturalEnds, NaturalSpline, Spline};
use crate::vec3::{self, Vec3};
use rayon::prelude::*;

/// Order P of the Taylor series method (coefficients 0 … P).
pub const ORDER: usize = 20;
const P1: usize = ORDER + 1;
/// Order of the sensitivity series (the Jacobian of Newton's method): its truncation,
/// ~(τ/ρ)^11 ≈ 1e-9 relative at the chosen steps, only slows the quadratic convergence (the
/// residual itself is computed to full order).
const TORDER: usize = 10;
/// Newton stops when the largest scaled mismatch is at or below this.
pub const TOL: f64 = 1e-12;
/// Newton iteration cap.
pub const MAX_ITER: usize = 60;
/// Steps per key interval above which the integration is abandoned (the state blew up).
const MAX_STEPS: usize = 4096;

/// One Taylor step: its start time and the coefficients of q's four components.
#[derive(Debug, Clone)]
struct Step {
    t0: f64,
    q: [[f64; P1]; 4],
}

/// The Riemannian cubic spline through the keys (see the module documentation).
#[derive(Debug, Clone)]
pub struct RiemannianCubic {
    joints: Vec<f64>,
    /// Steps of key interval i: `steps[first[i]..first[i + 1]]`.
    first: Vec<usize>,
    steps: Vec<Step>,
    closed: bool,
    holds: bool,
    /// ∫|ω̇|² (exact integral of the series) and of the natural spline (8 × 10 Gauss–Legendre
    /// per key interval).
    pub energy: f64,
    pub energy_natural: f64,
    /// Newton iterations (the largest over the independent runs) and the final largest scaled
    /// mismatch.
    pub iterations: usize,
    pub residual: f64,
}

#[inline(always)]
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    vec3::cross(a, b)
}

#[inline(always)]
fn axpy(acc: &mut Vec3, s: f64, v: Vec3) {
    acc[0] += s * v[0];
    acc[1] += s * v[1];
    acc[2] += s * v[2];
}

/// Taylor coefficients of ω from w₀, w₁, w₂ (ω, ω̇, ω̈/2).
#[inline]
fn omega_series(w: &mut [Vec3; P1]) {
    for k in 0..=ORDER - 3 {
        let mut s = [0.0; 3];
        for m in 0..=k {
            let c = ((k - m + 1) * (k - m + 2)) as f64;
            axpy(&mut s, c, cross(w[m], w[k - m + 2]));
        }
        let d = ((k + 1) * (k + 2) * (k + 3)) as f64;
        w[k + 3] = vec3::scale(s, -1.0 / d);
    }
}

/// Linearised ω recurrence: δw from δw₀, δw₁, δw₂ along the base series w.
#[inline]
fn omega_tangent(w: &[Vec3; P1], dw: &mut [Vec3; P1]) {
    for k in 0..=TORDER - 3 {
        let mut s = [0.0; 3];
        for m in 0..=k {
            let c = ((k - m + 1) * (k - m + 2)) as f64;
            axpy(&mut s, c, cross(dw[m], w[k - m + 2]));
            axpy(&mut s, c, cross(w[m], dw[k - m + 2]));
        }
        let d = ((k + 1) * (k + 2) * (k + 3)) as f64;
        dw[k + 3] = vec3::scale(s, -1.0 / d);
    }
}

/// Taylor coefficients of q (components w, x, y, z) from q₀ and ω's series.
#[inline]
fn quat_series(q0: Quat, w: &[Vec3; P1], q: &mut [[f64; P1]; 4]) {
    q[0][0] = q0.w;
    q[1][0] = q0.x;
    q[2][0] = q0.y;
    q[3][0] = q0.z;
    for k in 0..ORDER {
        let mut acc = [0.0; 4];
        for m in 0..=k {
            let (a, v) = ([q[0][m], q[1][m], q[2][m], q[3][m]], w[k - m]);
            // a ⊗ (0, v)
            acc[0] -= a[1] * v[0] + a[2] * v[1] + a[3] * v[2];
            acc[1] += a[0] * v[0] + a[2] * v[2] - a[3] * v[1];
            acc[2] += a[0] * v[1] + a[3] * v[0] - a[1] * v[2];
            acc[3] += a[0] * v[2] + a[1] * v[1] - a[2] * v[0];
        }
        let s = 0.5 / (k + 1) as f64;
        for c in 0..4 {
            q[c][k + 1] = acc[c] * s;
        }
    }
}

/// e's series for ė = δω − ω × e from e₀ (the right perturbation of q).
#[inline]
fn perturbation_series(w: &[Vec3; P1], dw: &[Vec3; P1], e: &mut [Vec3; P1]) {
    for k in 0..TORDER {
        let mut s = dw[k];
        for m in 0..=k {
            axpy(&mut s, -1.0, cross(w[m], e[k - m]));
        }
        e[k + 1] = vec3::scale(s, 1.0 / (k + 1) as f64);
    }
}

/// Σ cₖ τᵏ and its first two derivatives in τ.
#[inline]
fn horner3(c: &[Vec3; P1], tau: f64, order: usize) -> [Vec3; 3] {
    let mut v = [[0.0; 3]; 3];
    for k in (0..=order).rev() {
        for i in 0..3 {
            v[2][i] = v[2][i] * tau + 2.0 * v[1][i];
            v[1][i] = v[1][i] * tau + v[0][i];
            v[0][i] = v[0][i] * tau + c[k][i];
        }
    }
    v
}

#[inline]
fn horner(c: &[f64; P1], tau: f64) -> f64 {
    c.iter().rev().fold(0.0, |a, &x| a * tau + x)
}

/// The state at the end of one key interval, with sensitivities when asked for.
struct Shot {
    q: Quat,
    /// ω, ω̇, ω̈ at the end.
    z: [Vec3; 3],
    /// ∂(e, ω, ω̇) at the end / ∂(ω₀, ω̇₀, ω̈₀): [direction][quantity].
    dz: Option<Box<[[Vec3; 3]; 9]>>,
    energy: f64,
}

fn step_size(w: &[Vec3; P1], q: &[[f64; P1]; 4], h: f64) -> f64 {
    let wscale = vec3::norm(w[0]).max(vec3::norm(w[1]) * h).max(vec3::norm(w[2]) * h * h) + 1e-300;
    let mut tau = f64::INFINITY;
    for k in [ORDER - 1, ORDER] {
        let cq = (0..4).map(|c| q[c][k].abs()).fold(0.0, f64::max);
        let cw = vec3::norm(w[k]) / wscale;
        let c = cq.max(cw);
        if c > 0.0 {
            tau = tau.min((1e-16 / c).powf(1.0 / k as f64));
        }
    }
    tau
}

/// Integrates one key interval of length h from (q0, z), optionally recording the steps.
fn shoot(
    q0: Quat,
    z: [Vec3; 3],
    t0: f64,
    h: f64,
    tangents: bool,
    mut store: Option<&mut Vec<Step>>,
) -> Result<Shot> {
    let mut w = [[0.0; 3]; P1];
    let mut qc = [[0.0; P1]; 4];
    let (mut q, mut zz) = (q0, z);
    // Sensitivities, per direction (0–2: ω₀, 3–5: ω̇₀, 6–8: ω̈₀): [e, δω, δω̇] (e starts at 0)
    // and δω̈ in `dj`.
    let mut dz: Option<Box<[[Vec3; 3]; 9]>> = tangents.then(|| Box::new([[[0.0; 3]; 3]; 9]));
    if let Some(dz) = dz.as_mut() {
        for (d, v) in dz.iter_mut().enumerate().take(6) {
            v[1 + d / 3][d % 3] = 1.0;
        }
    }
    let mut dj = [[0.0f64; 3]; 9];
    for (d, v) in dj.iter_mut().enumerate() {
        if d >= 6 {
            v[d % 3] = 1.0;
        }
    }
    let mut t = 0.0;
    let mut energy = 0.0;
    let mut n = 0;
    while t < h {
        n += 1;
        if n > MAX_STEPS || !q.is_finite() || zz.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::invalid("quats", "the Riemannian cubic's integration diverged"));
        }
        w[0] = zz[0];
        w[1] = zz[1];
        w[2] = vec3::scale(zz[2], 0.5);
        omega_series(&mut w);
        quat_series(q, &w, &mut qc);
        let mut tau = step_size(&w, &qc, h);
        if t + tau >= h * (1.0 - 1e-14) {
            tau = h - t;
        }
        // ∫|ω̇|² over the step, exactly from the series.
        let mut pw = [0.0; 2 * P1];
        pw[0] = 1.0;
        for k in 1..2 * P1 {
            pw[k] = pw[k - 1] * tau;
        }
        for a in 1..P1 {
            for b in 1..P1 {
                let p = a + b - 1;
                energy += (a * b) as f64 * vec3::dot(w[a], w[b]) * pw[p] / p as f64;
            }
        }
        if let Some(st) = store.as_deref_mut() {
            st.push(Step { t0: t0 + t, q: qc });
        }
        if let Some(dz) = dz.as_mut() {
            let mut dw = [[0.0; 3]; P1];
            let mut e = [[0.0; 3]; P1];
            for d in 0..9 {
                dw[0] = dz[d][1];
                dw[1] = dz[d][2];
                dw[2] = vec3::scale(dj[d], 0.5);
                omega_tangent(&w, &mut dw);
                e[0] = dz[d][0];
                perturbation_series(&w, &dw, &mut e);
                let s = horner3(&dw, tau, TORDER);
                dz[d] = [horner3(&e, tau, TORDER)[0], s[0], s[1]];
                dj[d] = s[2];
            }
        }
        let s = horner3(&w, tau, ORDER);
        zz = [s[0], s[1], s[2]];
        q = Quat::new(horner(&qc[0], tau), horner(&qc[1], tau), horner(&qc[2], tau), horner(&qc[3], tau))
            .normalize();
        t += tau;
    }
    Ok(Shot { q, z: zz, dz, energy })
}

/// End condition of a run: ω̇ = 0 (natural) or ω given.
#[derive(Debug, Clone, Copy)]
enum End {
    Natural,
    Rate(Vec3),
}

/// Consecutive key intervals solved together.
struct Run {
    segs: Vec<usize>,
    periodic: bool,
    start: End,
    end: End,
}

/// A banded matrix with LU factorisation by partial pivoting (LAPACK's gbtf2 layout: column j
/// holds rows j − kl − ku … j + kl).
struct BandLu {
    n: usize,
    kl: usize,
    ku: usize,
    ld: usize,
    ab: Vec<f64>,
    piv: Vec<usize>,
}

impl BandLu {
    fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let ld = 2 * kl + ku + 1;
        BandLu { n, kl, ku, ld, ab: vec![0.0; ld * n], piv: vec![0; n] }
    }

    #[inline(always)]
    fn at(&mut self, i: usize, j: usize) -> &mut f64 {
        debug_assert!(i + self.kl + self.ku >= j && j + self.kl >= i);
        &mut self.ab[j * self.ld + self.kl + self.ku + i - j]
    }

    fn factor(&mut self) -> bool {
        let (n, kl, kv) = (self.n, self.kl, self.kl + self.ku);
        for j in 0..n {
            let last = (j + kl).min(n - 1);
            let (mut p, mut best) = (j, self.at(j, j).abs());
            for i in j + 1..=last {
                let v = self.at(i, j).abs();
                if v > best {
                    p = i;
                    best = v;
                }
            }
            self.piv[j] = p;
            if best == 0.0 || !best.is_finite() {
                return false;
            }
            let cmax = (j + kv).min(n - 1);
            if p != j {
                for c in j..=cmax {
                    let a = *self.at(j, c);
                    let b = *self.at(p, c);
                    *self.at(j, c) = b;
                    *self.at(p, c) = a;
                }
            }
            let d = *self.at(j, j);
            for i in j + 1..=last {
                let l = *self.at(i, j) / d;
                *self.at(i, j) = l;
                if l != 0.0 {
                    for c in j + 1..=cmax {
                        let u = *self.at(j, c);
                        *self.at(i, c) -= l * u;
                    }
                }
            }
        }
        true
    }

    fn solve(&mut self, b: &mut [f64]) {
        let (n, kl, kv) = (self.n, self.kl, self.kl + self.ku);
        for j in 0..n {
            b.swap(j, self.piv[j]);
            let last = (j + kl).min(n - 1);
            for i in j + 1..=last {
                b[i] -= *self.at(i, j) * b[j];
            }
        }
        for j in (0..n).rev() {
            let cmax = (j + kv).min(n - 1);
            let mut s = b[j];
            for c in j + 1..=cmax {
                s -= *self.at(j, c) * b[c];
            }
            b[j] = s / *self.at(j, j);
        }
    }
}

/// The Jacobian: its banded part and a periodic run's corner entries (row, column, value).
type Linear = (BandLu, Vec<(usize, usize, f64)>);

/// The shooting problem of one run.
struct Problem<'a> {
    keys: &'a [Quat],
    joints: &'a [f64],
    run: &'a Run,
    nkeys: usize,
}

impl Problem<'_> {
    fn h(&self, s: usize) -> f64 {
        self.joints[s + 1] - self.joints[s]
    }
    fn next_key(&self, s: usize) -> Quat {
        self.keys[(s + 1) % self.nkeys]
    }

    /// Residual rows (and Jacobian when `jac`) at the states z (9 per interval of the run).
    /// Row layout: open runs [start 3][interval 0: 9]…[last interval: 6]; periodic runs
    /// [interval: 9]… (the last one's continuity rows refer to the first state).
    fn eval(&self, z: &[f64], jac: bool) -> Result<(Vec<f64>, Option<Linear>)> {
        let m = self.run.segs.len();
        let n = 9 * m;
        let off = if self.run.periodic { 0 } else { 3 };
        let (kl, ku) = if self.run.periodic { (8, 8) } else { (11, 5) };
        let mut f = vec![0.0; n];
        let mut a = if jac { Some(BandLu::zeros(n, kl, ku)) } else { None };
        let mut corner = Vec::new();
        let state = |i: usize| -> [Vec3; 3] {
            std::array::from_fn(|c| [z[9 * i + 3 * c], z[9 * i + 3 * c + 1], z[9 * i + 3 * c + 2]])
        };
        if !self.run.periodic {
            let h0 = self.h(self.run.segs[0]);
            let s0 = state(0);
            match self.run.start {
                End::Natural => {
                    for c in 0..3 {
                        f[c] = s0[1][c] * h0 * h0;
                        if let Some(a) = a.as_mut() {
                            *a.at(c, 3 + c) = h0 * h0;
                        }
                    }
                }
                End::Rate(w) => {
                    for c in 0..3 {
                        f[c] = (s0[0][c] - w[c]) * h0;
                        if let Some(a) = a.as_mut() {
                            *a.at(c, c) = h0;
                        }
                    }
                }
            }
        }
        // The intervals are integrated in parallel (independent given z), then assembled in order.
        let shots: Vec<Shot> = self
            .run
            .segs
            .par_iter()
            .enumerate()
            .map(|(i, &s)| shoot(self.keys[s], state(i), 0.0, self.h(s), jac, None))
            .collect::<Result<_>>()?;
        for ((i, &s), shot) in self.run.segs.iter().enumerate().zip(shots) {
            let h = self.h(s);
            let target = self.next_key(s);
            let r = so3::log(target.conj() * shot.q);
            let jinv = jr_inv(r);
            let row = off + 9 * i;
            let last = i + 1 == m;
            f[row..row + 3].copy_from_slice(&r);
            let scale = [1.0, h, h * h];
            if let Some(a) = a.as_mut() {
                let dz = shot.dz.as_ref().expect("tangents");
                for d in 0..9 {
                    let de = mat_vec(&jinv, dz[d][0]);
                    for c in 0..3 {
                        *a.at(row + c, 9 * i + d) = de[c];
                    }
                }
            }
            if last && !self.run.periodic {
                match self.run.end {
                    End::Natural => {
                        for c in 0..3 {
                            f[row + 3 + c] = shot.z[1][c] * scale[2];
                        }
                        if let Some(a) = a.as_mut() {
                            let dz = shot.dz.as_ref().expect("tangents");
                            for d in 0..9 {
                                for c in 0..3 {
                                    *a.at(row + 3 + c, 9 * i + d) = dz[d][2][c] * scale[2];
                                }
                            }
                        }
                    }
                    End::Rate(w) => {
                        for c in 0..3 {
                            f[row + 3 + c] = (shot.z[0][c] - w[c]) * scale[1];
                        }
                        if let Some(a) = a.as_mut() {
                            let dz = shot.dz.as_ref().expect("tangents");
                            for d in 0..9 {
                                for c in 0..3 {
                                    *a.at(row + 3 + c, 9 * i + d) = dz[d][1][c] * scale[1];
                                }
                            }
                        }
                    }
                }
                continue;
            }
            let nx = if last { 0 } else { i + 1 };
            let sn = state(nx);
            for q in 0..2 {
                for c in 0..3 {
                    f[row + 3 + 3 * q + c] = (shot.z[q][c] - sn[q][c]) * scale[q + 1];
                }
            }
            if let Some(a) = a.as_mut() {
                let dz = shot.dz.as_ref().expect("tangents");
                for d in 0..9 {
                    for q in 0..2 {
                        for c in 0..3 {
                            *a.at(row + 3 + 3 * q + c, 9 * i + d) = dz[d][1 + q][c] * scale[q + 1];
                        }
                    }
                }
                for q in 0..2 {
                    for c in 0..3 {
                        let (r, col, v) = (row + 3 + 3 * q + c, 9 * nx + 3 * q + c, -scale[q + 1]);
                        if last {
                            corner.push((r, col, v));
                        } else {
                            *a.at(r, col) = v;
                        }
                    }
                }
            }
        }
        Ok((f, a.map(|a| (a, corner))))
    }

    /// The Newton step d solving J d = −f (Woodbury for a periodic run's corner).
    fn step(&self, mut a: BandLu, corner: &[(usize, usize, f64)], f: &[f64]) -> Option<Vec<f64>> {
        if !a.factor() {
            return None;
        }
        let mut y: Vec<f64> = f.iter().map(|v| -v).collect();
        a.solve(&mut y);
        if corner.is_empty() {
            return Some(y);
        }
        // A = B + U Vᵀ, U's column k = corner value at its row, V's column k = e_col.
        let k = corner.len();
        let n = f.len();
        let mut zc = Vec::with_capacity(k);
        for &(r, _, v) in corner {
            let mut u = vec![0.0; n];
            u[r] = v;
            a.solve(&mut u);
            zc.push(u);
        }
        // (I + Vᵀ Z) c = Vᵀ y; x = y − Z c.
        let mut s = nalgebra::DMatrix::<f64>::identity(k, k);
        let mut rhs = nalgebra::DVector::<f64>::zeros(k);
        for (i, &(_, col, _)) in corner.iter().enumerate() {
            for (j, z) in zc.iter().enumerate() {
                s[(i, j)] += z[col];
            }
            rhs[i] = y[col];
        }
        let c = s.lu().solve(&rhs)?;
        for (j, z) in zc.iter().enumerate() {
            for (yi, zi) in y.iter_mut().zip(z) {
                *yi -= c[j] * zi;
            }
        }
        Some(y)
    }
}

fn max_abs(f: &[f64]) -> f64 {
    f.iter().fold(0.0, |a, v| a.max(v.abs()))
}

fn norm2(f: &[f64]) -> f64 {
    f.iter().map(|v| v * v).sum::<f64>()
}

/// Solves one run by Newton's method from z (in place); returns (iterations, final residual).
fn newton(
    p: &Problem<'_>,
    z: &mut [f64],
    progress: &mut dyn FnMut(usize, f64) -> bool,
) -> Result<(usize, f64)> {
    let (mut f, _) = p.eval(z, false)?;
    let mut res = max_abs(&f);
    let mut it = 0;
    while res > TOL && it < MAX_ITER {
        it += 1;
        let (_, j) = p.eval(z, true)?;
        let (a, corner) = j.expect("jacobian");
        let Some(d) = p.step(a, &corner, &f) else { break };
        let f2 = norm2(&f);
        let mut lam = 1.0;
        let mut accepted = false;
        for _ in 0..30 {
            let trial: Vec<f64> = z.iter().zip(&d).map(|(a, b)| a + lam * b).collect();
            if let Ok((ft, _)) = p.eval(&trial, false) {
                let ft2 = norm2(&ft);
                if ft2.is_finite() && ft2 < f2 * (1.0 - 1e-4 * lam) || (max_abs(&ft) <= TOL) {
                    z.copy_from_slice(&trial);
                    f = ft;
                    accepted = true;
                    break;
                }
            }
            lam *= 0.5;
        }
        if !progress(it, max_abs(&f)) {
            return Err(Error::invalid("progress", "cancelled by the progress callback"));
        }
        res = max_abs(&f);
        if !accepted {
            break;
        }
    }
    Ok((it, res))
}

impl RiemannianCubic {
    /// Builds the Riemannian cubic spline through the keys (times default 0 … N−1) with the
    /// given ends, from the natural spline's rates. Errors when Newton's method does not reach
    /// [`TOL`] within [`MAX_ITER`] iterations (the keys are then too far apart for the start
    /// to lie in its basin; the discrete [`super::min_energy::MinEnergySpline`] still returns
    /// a curve).
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: NaturalEnds,
        progress: Progress<'_>,
    ) -> Result<Self> {
        let nat = NaturalSpline::with_keyframes(keys, times, ends, true, true)?;
        Self::from_natural(&nat, ends, progress)
    }

    /// As [`new`](Self::new), from the natural spline through the same keys with the same ends
    /// (built with holds).
    pub fn from_natural(nat: &NaturalSpline, ends: NaturalEnds, progress: Progress<'_>) -> Result<Self> {
        let closed = ends == NaturalEnds::Closed;
        let joints = nat.joints().to_vec();
        let segs = joints.len() - 1;
        let nkeys = if closed { segs } else { segs + 1 };
        let keys: Vec<Quat> = (0..nkeys)
            .map(|k| {
                if k < segs {
                    nat.segment::<1>(k, joints[k]).value()
                } else {
                    nat.segment::<1>(segs - 1, joints[segs]).value()
                }
            })
            .collect();
        let holds: Vec<bool> = (0..segs).map(|i| same_rotation(keys[i], keys[(i + 1) % nkeys])).collect();
        // Initial states: the natural spline's (ω, ω̇, ω̈) at the start of every interval.
        let mut z = vec![0.0; 9 * segs];
        for i in 0..segs {
            let d = nat.segment::<4>(i, joints[i]).derivatives();
            for o in 0..3 {
                let v = angular(&d, o + 1, true);
                z[9 * i + 3 * o..9 * i + 3 * o + 3].copy_from_slice(&v);
            }
        }
        let rates = nat.key_rates();
        let end_of = |first: bool| match ends {
            NaturalEnds::Natural => End::Natural,
            _ => End::Rate(if first { rates[0] } else { rates[rates.len() - 1] }),
        };
        // Runs between holds.
        let mut runs = Vec::new();
        if !holds.iter().any(|&h| h) {
            runs.push(Run {
                segs: (0..segs).collect(),
                periodic: closed,
                start: end_of(true),
                end: end_of(false),
            });
        } else {
            let begin = if closed { holds.iter().position(|&h| h).unwrap_or(0) + 1 } else { 0 };
            let mut cur: Vec<usize> = Vec::new();
            let mut start = if closed { End::Rate([0.0; 3]) } else { end_of(true) };
            for k in 0..segs {
                let s = (begin + k) % segs;
                if holds[s] {
                    if !cur.is_empty() {
                        runs.push(Run {
                            segs: std::mem::take(&mut cur),
                            periodic: false,
                            start,
                            end: End::Rate([0.0; 3]),
                        });
                    }
                    start = End::Rate([0.0; 3]);
                } else {
                    cur.push(s);
                }
            }
            if !cur.is_empty() {
                let end = if closed { End::Rate([0.0; 3]) } else { end_of(false) };
                runs.push(Run { segs: cur, periodic: false, start, end });
            }
        }
        let mut iterations = 0;
        let mut residual = 0.0f64;
        let mut total = 0;
        for run in &runs {
            let p = Problem { keys: &keys, joints: &joints, run, nkeys };
            let mut zr: Vec<f64> = run.segs.iter().flat_map(|&s| z[9 * s..9 * s + 9].to_vec()).collect();
            let mut rep = |it: usize, r: f64| progress("exact", total + it, r);
            let (it, res) = newton(&p, &mut zr, &mut rep)?;
            total += it;
            if res > TOL || !res.is_finite() {
                return Err(Error::NotConverged {
                    what: "Riemannian cubic (Newton)",
                    iterations: it,
                    step: res,
                    tol: TOL,
                });
            }
            iterations = iterations.max(it);
            residual = residual.max(res);
            for (k, &s) in run.segs.iter().enumerate() {
                z[9 * s..9 * s + 9].copy_from_slice(&zr[9 * k..9 * k + 9]);
            }
        }
        // Dense output: integrate every interval once more, recording its steps; the start of
        // an interval takes the key's sign nearest the previous interval's end.
        // The intervals are integrated in parallel from their keys as given; a sign flip of
        // the start negates every coefficient (the series is linear in q₀), exactly.
        let shots: Vec<Option<(Shot, Vec<Step>)>> = (0..segs)
            .into_par_iter()
            .map(|i| {
                if holds[i] {
                    return Ok(None);
                }
                let st: [Vec3; 3] =
                    std::array::from_fn(|c| [z[9 * i + 3 * c], z[9 * i + 3 * c + 1], z[9 * i + 3 * c + 2]]);
                let mut own = Vec::new();
                let shot = shoot(keys[i], st, joints[i], joints[i + 1] - joints[i], false, Some(&mut own))?;
                Ok(Some((shot, own)))
            })
            .collect::<Result<_>>()?;
        let mut steps = Vec::new();
        let mut first = Vec::with_capacity(segs + 1);
        let mut energy = 0.0;
        let mut prev: Option<Quat> = None;
        for (i, shot) in shots.into_iter().enumerate() {
            first.push(steps.len());
            let flip = prev.is_some_and(|p| p.dot(keys[i]) < 0.0);
            let Some((shot, own)) = shot else {
                let q0 = if flip { -keys[i] } else { keys[i] };
                let mut q = [[0.0; P1]; 4];
                (q[0][0], q[1][0], q[2][0], q[3][0]) = (q0.w, q0.x, q0.y, q0.z);
                steps.push(Step { t0: joints[i], q });
                prev = Some(q0);
                continue;
            };
            for mut step in own {
                if flip {
                    step.q.iter_mut().flatten().for_each(|c| *c = -*c);
                }
                steps.push(step);
            }
            energy += shot.energy;
            prev = Some(if flip { -shot.q } else { shot.q });
        }
        first.push(steps.len());
        let energy_natural = super::min_energy::natural_energy(nat);
        Ok(RiemannianCubic {
            joints,
            first,
            steps,
            closed,
            holds: holds.iter().any(|&h| h),
            energy,
            energy_natural,
            iterations,
            residual,
        })
    }

    /// The body-frame state (ω, ω̇, ω̈) at the start of key interval i (right limits).
    pub fn start_state(&self, i: usize) -> [Vec3; 3] {
        let d = self.segment::<4>(i, self.joints[i]).derivatives();
        std::array::from_fn(|o| angular(&d, o + 1, true))
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let steps = &self.steps[self.first[i]..self.first[i + 1]];
        let k = steps.partition_point(|s| s.t0 <= t).saturating_sub(1);
        let s = &steps[k];
        let x = Jet::variable(t - s.t0, 1.0);
        let q = JQuat {
            w: Jet::poly(&s.q[0], x),
            x: Jet::poly(&s.q[1], x),
            y: Jet::poly(&s.q[2], x),
            z: Jet::poly(&s.q[3], x),
        };
        q.scale(q.dot(q).sqrt().recip())
    }
}

impl Spline for RiemannianCubic {
    segment_jets!();
    fn name(&self) -> &'static str {
        "min_energy"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        if self.holds {
            1
        } else {
            2
        }
    }
    fn closed(&self) -> bool {
        self.closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::min_energy::MinEnergySpline;

    fn keys(n: usize, seed: u64) -> (Vec<f64>, Vec<Quat>) {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let mut u = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut t = vec![0.0];
        for _ in 1..n {
            let last = *t.last().unwrap();
            t.push(last + 0.5 + u());
        }
        let q = (0..n).map(|_| so3::exp([1.6 * u() - 0.8, 1.6 * u() - 0.8, 1.6 * u() - 0.8])).collect();
        (t, q)
    }

    fn body(s: &RiemannianCubic, i: usize, t: f64) -> [Vec3; 3] {
        let d = s.segment::<4>(i, t).derivatives();
        std::array::from_fn(|o| angular(&d, o + 1, true))
    }

    #[test]
    fn euler_lagrange_interpolation_and_c2() {
        let (t, q) = keys(12, 3);
        for ends in [NaturalEnds::Natural, NaturalEnds::Rest] {
            let s = RiemannianCubic::new(&q, Some(&t), ends, &mut |_, _, _| true).unwrap();
            assert!(s.residual <= TOL && s.energy < s.energy_natural, "{ends:?}");
            for (k, &tk) in t.iter().enumerate() {
                let i = k.min(s.segments() - 1);
                assert!(vec3::norm(so3::log(s.segment::<1>(i, tk).value().conj() * q[k])) < 1e-12);
                if k > 0 && k + 1 < t.len() {
                    let (l, r) = (body(&s, k - 1, tk), body(&s, k, tk));
                    for o in 0..2 {
                        assert!(
                            vec3::norm(vec3::sub(l[o], r[o])) < 1e-9 * (1.0 + vec3::norm(l[o])),
                            "{ends:?} key {k}"
                        );
                    }
                }
            }
            let mut worst = 0.0f64;
            for i in 0..s.segments() {
                let (a, b) = (t[i], t[i + 1]);
                for k in 1..8 {
                    let tk = a + (b - a) * k as f64 / 8.0;
                    let hh = 1e-3 * (b - a);
                    let j = |x: f64| body(&s, i, x)[2];
                    // 5-point derivative of ω̈
                    let d3: Vec3 = std::array::from_fn(|c| {
                        (j(tk - 2.0 * hh)[c] - 8.0 * j(tk - hh)[c] + 8.0 * j(tk + hh)[c]
                            - j(tk + 2.0 * hh)[c])
                            / (12.0 * hh)
                    });
                    let st = body(&s, i, tk);
                    let r = vec3::add(d3, cross(st[0], st[2]));
                    worst = worst.max(vec3::norm(r));
                }
            }
            assert!(worst < 1e-8);
        }
    }

    #[test]
    fn discrete_converges_to_exact() {
        let (t, q) = keys(10, 5);
        let s = RiemannianCubic::new(&q, Some(&t), NaturalEnds::Natural, &mut |_, _, _| true).unwrap();
        let gaps: Vec<f64> = [0, 1, 2, 4, 8]
            .iter()
            .map(|&r| {
                let d =
                    MinEnergySpline::new(&q, Some(&t), NaturalEnds::Natural, r, &mut |_, _, _| true).unwrap();
                d.energy - s.energy
            })
            .collect();
        assert!(gaps.iter().all(|&g| g > -1e-11 * s.energy), "{gaps:?}");
        assert!(gaps.windows(2).all(|w| w[1] < w[0]), "{gaps:?}");
        assert!(gaps[4] < 1e-6 * gaps[0], "{gaps:?}");
    }
}
