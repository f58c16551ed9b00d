//! The posterior covariance of a fitted orientation curve (and its angular velocity), from the
//! banded factor of the fit's Gauss–Newton normal matrix.
//!
//! Model: the Bayesian reading of the penalised fit (Wahba 1983, "Bayesian 'confidence
//! intervals' for the cross-validated smoothing spline", JRSS B 45; Nychka 1988, "Bayesian
//! confidence intervals for smoothing splines", JASA 83; Gu 1992 for the Gauss–Newton
//! linearisation of a non-Gaussian or non-linear fit). Residuals rₛ = Log(q(tₛ)⁻¹ yₛ) are
//! taken as N(0, σ²/wₛ · I₃) and the penalty as a (partially improper) Gaussian prior with
//! precision λP/σ², so at the solution the control-point perturbations δ (R_m ← R_m Exp(δ_m))
//! have the posterior covariance
//!   Cov(δ) = σ̂² H⁻¹,   H = G + λP,   σ̂² = RSS / (n_obs − tr A),   tr A = tr(H⁻¹G),
//! with G = JᵀWJ and P the penalty's Gauss–Newton matrix assembled by the solver's own
//! functions at the fitted curve (the data term with the Riemannian Hessian root of
//! `so3::dist_hess_sqrt`), RSS = Σ wₛ|rₛ|², n_obs = 3 × the samples of positive weight.
//! With a robust loss W holds the final IRLS weights (the fit is the weighted least-squares
//! fit with those weights, and this is that fit's posterior; the weights are taken as
//! fixed, which understates the variance near down-weighted samples a little).
//!
//! At a time t the curve moves as q(t) ← q(t) Exp(ξ(t)), ξ(t) = Σ_m X_m(t) δ_m over the k
//! control points of t's knot interval (`model.rs`), so
//!   Cov(ξ(t)) = J(t) Cov(δ) J(t)ᵀ,   J(t) = [X_i(t) … X_{i+k−1}(t)]   (3 × 3k),
//! which needs only the 3k × 3k diagonal block of H⁻¹ at the interval: inside the band that
//! the selected inversion of `banded.rs` gives (Takahashi, Fagan & Chen 1973) in O(n p²)
//! time and O(n p) memory. Frames: "body" is ξ itself (the tangent space at q(t), right
//! perturbation, radians²); "world" is the left perturbation Exp(R(t)ξ) q(t): R Cov Rᵀ.
//! Angular velocity (first order): the body rate moves by δω_b = ξ̇ + ω_b × ξ, the world rate
//! ω_w = R(q)ω_b by δω_w = R ξ̇ (the rotation of the frame cancels ω_b × ξ), both linear in
//! δ with the jets of the same columns: Cov(ω) = D(t) Cov(δ) D(t)ᵀ, (rad/s)².

use super::assembly::{data_half, pen_half, penalty_nodes};
use super::banded::Band;
use super::layout::Layout;
use super::model::{Cols, Model, MAXK};
use super::types::{validate, Penalty};
use crate::error::{Error, Result, Short};
use crate::frame::Frame;
use crate::jet::Jet;
use crate::quadrature::gauss_legendre01;
use crate::quat::Quat;
use crate::vec3::Vec3;
use rayon::prelude::*;
use std::str::FromStr;

/// What a covariance describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The orientation q(t) (radians²).
    Orientation,
    /// The angular velocity ω(t) ((rad/s)²).
    AngularVelocity,
}

impl FromStr for Quantity {
    type Err = Error;
    /// "orientation" or "angular_velocity".
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "orientation" => Ok(Quantity::Orientation),
            "angular_velocity" => Ok(Quantity::AngularVelocity),
            _ => Err(Error::invalid(
                "quantity",
                format!("unknown quantity {s:?}; valid: orientation, angular_velocity"),
            )),
        }
    }
}

/// The knot layout of a fitted spline: uniform t₀ + jΔt, or `breaks` (S + 1 increasing
/// breakpoints), for `nctrl` control points of order `order`.
pub fn fitted_layout(nctrl: usize, dt: f64, t0: f64, order: usize, breaks: Option<&[f64]>) -> Result<Layout> {
    if !(2..=MAXK).contains(&order) || nctrl < order {
        return Err(Error::invalid(
            "order",
            format!("expected 2 … {MAXK} with at least order control points, got order {order} and {nctrl} points"),
        ));
    }
    let segs = nctrl + 1 - order;
    match breaks {
        Some(b) => {
            if b.len() != segs + 1 || b.iter().any(|v| !v.is_finite()) || b.windows(2).any(|w| w[1] <= w[0]) {
                return Err(Error::invalid(
                    "breaks",
                    format!("expected {} increasing breakpoints, got {}", segs + 1, b.len()),
                ));
            }
            Ok(Layout::nonuniform(b.to_vec(), order))
        }
        None => {
            if !(dt.is_finite() && dt > 0.0 && t0.is_finite()) {
                return Err(Error::invalid(
                    "dt",
                    format!("expected a finite positive knot spacing, got {}", Short(dt)),
                ));
            }
            Ok(Layout::uniform(t0, dt, segs, order))
        }
    }
}

/// The samples' weights times the final IRLS weights (checked: one per sample, finite, ≥ 0).
pub(super) fn effective_weights(w: &[f64], robust_weights: Option<&[f64]>) -> Result<Vec<f64>> {
    let Some(rw) = robust_weights else { return Ok(w.to_vec()) };
    if rw.len() != w.len() {
        return Err(Error::invalid(
            "robust_weights",
            format!("expected {} weights (one per sample), got {}", w.len(), rw.len()),
        ));
    }
    for (i, &v) in rw.iter().enumerate() {
        if !v.is_finite() {
            return Err(Error::NonFinite { arg: "robust_weights", index: i });
        }
        if !(0.0..=1.0).contains(&v) {
            return Err(Error::invalid(
                "robust_weights",
                format!("expected IRLS weights in [0, 1], got {} at index {i}", Short(v)),
            ));
        }
    }
    Ok(w.iter().zip(rw).map(|(a, b)| a * b).collect())
}

/// σ̂² = RSS / (n_obs − tr A) (see the module doc); an error when no residual degrees of
/// freedom are left (or the count is not a number).
pub(super) fn noise_variance(rss: f64, nobs: f64, edf: f64) -> Result<f64> {
    let den = nobs - edf;
    if den.is_nan() || den <= 1e-9 * nobs {
        return Err(Error::invalid(
            "smoothing",
            format!(
                "the fit spends all {nobs} observations on its {} effective degrees of freedom: \
                 no residual is left to estimate the noise from (an interpolating fit has no posterior)",
                Short(edf)
            ),
        ));
    }
    Ok(rss.max(0.0) / den)
}

/// The posterior of a fitted orientation curve (see the module doc).
#[derive(Debug, Clone)]
pub struct Posterior {
    model: Model,
    /// The band of H⁻¹ (selected inverse; half-bandwidth 3k − 1).
    inv: Band,
    /// σ̂², radians² per component of a unit-weight residual.
    pub sigma2: f64,
    /// Σ wₛ|rₛ|² at the solution.
    pub rss: f64,
    /// n_obs: 3 × the samples of positive weight.
    pub nobs: f64,
    /// tr A = tr(H⁻¹G).
    pub edf: f64,
}

impl Posterior {
    /// The posterior of the fit with controls `ctrl` on `layout` to orientations `quats` at
    /// `times` with sample `weights` (normalised to mean 1, as the fit does) and the fit's
    /// final `robust_weights` (None: all 1), penalty `penalty` and smoothing `lambda` > 0,
    /// with the penalty's weight on each knot interval when the smoothing was locally adaptive
    /// (`penalty_weights`, one per interval; None: one global λ).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        times: &[f64],
        quats: &[Quat],
        weights: Option<&[f64]>,
        robust_weights: Option<&[f64]>,
        ctrl: Vec<Quat>,
        layout: Layout,
        penalty: Penalty,
        lambda: f64,
        penalty_weights: Option<&[f64]>,
    ) -> Result<Posterior> {
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(Error::invalid(
                "smoothing",
                format!(
                    "the posterior needs a smoothing fit (λ > 0), got λ = {}: an interpolating fit \
                     has no residuals to estimate the noise from",
                    Short(lambda)
                ),
            ));
        }
        if ctrl.len() != layout.segs + layout.order - 1 {
            return Err(Error::invalid(
                "ctrl",
                format!(
                    "expected {} control points for the layout, got {}",
                    layout.segs + layout.order - 1,
                    ctrl.len()
                ),
            ));
        }
        if let Some(pw) = penalty_weights {
            if pw.len() != layout.segs || !pw.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(Error::invalid(
                    "penalty_weights",
                    format!(
                        "expected {} finite positive weights (one per knot interval), got {}",
                        layout.segs,
                        pw.len()
                    ),
                ));
            }
        }
        let data = validate(times, quats, weights, 1, "")?;
        let w = effective_weights(&data.w, robust_weights)?;
        let k = layout.order;
        let model = Model::with_layout(ctrl, layout);
        let nodes = gauss_legendre01(penalty_nodes(k, penalty.m(), false));
        let offs: Vec<Vec3> = vec![[0.0; 3]; data.t.len()];
        let dh = data_half(&model, &data, &w, &offs, Band::zeros(0, 0));
        drop(offs);
        let ph = pen_half(&model, penalty, &nodes, Band::zeros(0, 0), penalty_weights);
        let (rss, nobs, g) = (dh.sum, dh.count, dh.band);
        // H = G + λP in the penalty's storage.
        let mut h = ph.band;
        for (x, y) in h.a.iter_mut().zip(&g.a) {
            *x = y + lambda * *x;
        }
        h.cholesky_in_place().map_err(|e| {
            Error::Internal(format!(
                "the fit's normal matrix G + λP is not positive definite at the solution: {e}"
            ))
        })?;
        // tr(H⁻¹G) by the fused pass first, so G is freed before the band of H⁻¹ is made:
        // two bands at a time, never three.
        let edf = h.trace_inverse_product(&g);
        drop(g);
        let inv = h.selected_inverse();
        drop(h);
        let sigma2 = noise_variance(rss, nobs, edf)?;
        Ok(Posterior { model, inv, sigma2, rss, nobs, edf })
    }

    /// The time domain [t₀, t_S] of the curve.
    pub fn domain(&self) -> (f64, f64) {
        let l = &self.model.layout;
        match &l.breaks {
            Some(b) => (b[0], b[l.segs]),
            None => (l.t0, l.t0 + l.segs as f64 * l.dt),
        }
    }

    /// (first control index i, J(t)) with J (3 × 3k, row-major, 3k columns used) the map from
    /// the perturbations of controls i … i+k−1 to the quantity's perturbation in `frame`.
    pub fn jacobian(&self, t: f64, what: Quantity, frame: Frame) -> (usize, [[f64; 3 * MAXK]; 3]) {
        let m = &self.model;
        let k = m.order;
        let (i, u) = m.locate(t);
        let mut jac = [[0.0; 3 * MAXK]; 3];
        let rot = |q: Quat, v: Vec3| -> Vec3 {
            match frame {
                Frame::Body => v,
                Frame::World => q.rotate(v),
            }
        };
        match what {
            Quantity::Orientation => {
                let mut cols: Cols<1> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
                let q = m.value_and_columns::<1>(i, Jet::constant(u), &mut cols).value();
                for mm in 0..k {
                    for c in 0..3 {
                        let x = rot(q, std::array::from_fn(|r| cols[mm][c][r].value()));
                        for r in 0..3 {
                            jac[r][3 * mm + c] = x[r];
                        }
                    }
                }
            }
            Quantity::AngularVelocity => {
                let mut cols: Cols<2> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
                let qj = m.value_and_columns::<2>(i, Jet::variable(u, 1.0 / m.width(i)), &mut cols);
                let q = qj.value();
                let om = Model::omega(&qj);
                for mm in 0..k {
                    for c in 0..3 {
                        let x: Vec3 = match frame {
                            // δω_b = ξ̇ + ω_b × ξ
                            Frame::Body => {
                                let d = Model::delta_omega(&om, &cols[mm][c]);
                                std::array::from_fn(|r| d[r].value())
                            }
                            // δω_w = R ξ̇
                            Frame::World => q.rotate(std::array::from_fn(|r| cols[mm][c][r].derivative(1))),
                        };
                        for r in 0..3 {
                            jac[r][3 * mm + c] = x[r];
                        }
                    }
                }
            }
        }
        (i, jac)
    }

    /// Cov at one time t (clamped to the domain), radians² or (rad/s)².
    pub fn covariance_at(&self, t: f64, what: Quantity, frame: Frame) -> [[f64; 3]; 3] {
        let (i, jac) = self.jacobian(t, what, frame);
        let nb = 3 * self.model.order;
        let off = 3 * i;
        // T = J S (3 × 3k) with S the 3k × 3k block of H⁻¹ at the interval (inside the band).
        let mut tm = [[0.0; 3 * MAXK]; 3];
        for a in 0..nb {
            for b in 0..nb {
                let s = self.inv.get(off + a, off + b);
                for r in 0..3 {
                    tm[r][b] += jac[r][a] * s;
                }
            }
        }
        let mut c = [[0.0; 3]; 3];
        for r in 0..3 {
            for q in 0..3 {
                let v: f64 = (0..nb).map(|b| tm[r][b] * jac[q][b]).sum();
                c[r][q] = self.sigma2 * v;
            }
        }
        // exactly symmetric
        for r in 0..3 {
            for q in 0..r {
                let v = 0.5 * (c[r][q] + c[q][r]);
                c[r][q] = v;
                c[q][r] = v;
            }
        }
        c
    }

    /// Cov at every time of `t` (9 values per time, row-major), in parallel (each time on its
    /// own: the result does not depend on the thread count). Times must be finite and inside
    /// the domain (to 1e-9 of a knot interval).
    pub fn covariances(&self, t: &[f64], what: Quantity, frame: Frame) -> Result<Vec<f64>> {
        let (a, b) = self.domain();
        let tol = 1e-9 * self.model.dt;
        for (s, &v) in t.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFinite { arg: "t", index: s });
            }
            if v < a - tol || v > b + tol {
                return Err(Error::OutOfDomain { index: s, t: v, start: a, end: b });
            }
        }
        let mut out = vec![0.0; 9 * t.len()];
        out.par_chunks_mut(9 * 256).zip(t.par_chunks(256)).for_each(|(o, ts)| {
            for (j, &v) in ts.iter().enumerate() {
                let c = self.covariance_at(v, what, frame);
                for r in 0..3 {
                    o[9 * j + 3 * r..9 * j + 3 * r + 3].copy_from_slice(&c[r]);
                }
            }
        });
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::assembly::data_half;
    use super::super::so3;
    use super::super::types::{FitOptions, Smoothing};
    use super::*;
    use crate::testing::XorShift64;

    fn gauss(rng: &mut XorShift64) -> f64 {
        // Box–Muller
        let u1 = rng.uniform().max(1e-300);
        let u2 = rng.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    fn truth(s: f64) -> Quat {
        so3::exp([0.6 * (1.3 * s).sin(), 0.4 * (0.9 * s).cos(), 0.3 * s + 0.2 * (2.1 * s).sin()])
    }

    fn noisy(t: &[f64], sigma: f64, rng: &mut XorShift64) -> Vec<Quat> {
        t.iter()
            .map(|&s| truth(s) * so3::exp([sigma * gauss(rng), sigma * gauss(rng), sigma * gauss(rng)]))
            .collect()
    }

    fn layout_of(r: &super::super::FitResult) -> Layout {
        fitted_layout(r.ctrl.len(), r.dt, r.t0, r.order, r.breaks.as_deref()).unwrap()
    }

    /// Dense n × n from a band.
    fn dense(b: &Band) -> Vec<Vec<f64>> {
        (0..b.n)
            .map(|i| (0..b.n).map(|j| if i.abs_diff(j) <= b.p { b.get(i, j) } else { 0.0 }).collect())
            .collect()
    }

    /// The Jacobians J(t) (orientation, angular velocity; body and world frames) against
    /// central finite differences of the curve under control perturbations, for both
    /// penalties' orders, uniform and uneven knots.
    #[test]
    fn jacobians_match_finite_differences() {
        let t: Vec<f64> = (0..40).map(|i| 0.1 * i as f64).collect();
        let mut rng = XorShift64::new(5);
        let y = noisy(&t, 0.01, &mut rng);
        for (pen, knots) in [
            (Penalty::Acceleration, super::super::Knots::Default),
            (Penalty::Jerk, super::super::Knots::Default),
            (Penalty::Acceleration, super::super::Knots::Array(vec![0.0, 0.3, 0.5, 1.4, 2.0, 2.2, 3.1, 3.9])),
        ] {
            let opts =
                FitOptions { penalty: pen, smoothing: Smoothing::Fixed(1e-3), knots, ..Default::default() };
            let r = super::super::fit(&t, &y, None, &opts, &mut |_, _, _| true).unwrap();
            let post = Posterior::new(&t, &y, None, None, r.ctrl.clone(), layout_of(&r), pen, r.lambda, None)
                .unwrap();
            let m0 = &post.model;
            let k = m0.order;
            for &tt in &[0.0, 0.77, 1.55, 3.9] {
                let (i, u) = m0.locate(tt);
                let at = |m: &Model| {
                    let qj = m.value::<3>(i, Jet::variable(u, 1.0 / m.width(i)));
                    let q = qj.value();
                    let wb = Model::omega(&qj);
                    let wb: Vec3 = std::array::from_fn(|r| wb[r].value());
                    (q, wb, q.rotate(wb))
                };
                let (q0, _, _) = at(m0);
                for what in [Quantity::Orientation, Quantity::AngularVelocity] {
                    for frame in [Frame::Body, Frame::World] {
                        let (i2, jac) = post.jacobian(tt, what, frame);
                        assert_eq!(i2, i);
                        for col in 0..3 * k {
                            let h = 1e-6;
                            let pert = |s: f64| {
                                let mut d = vec![0.0; 3 * m0.ctrl.len()];
                                d[3 * i + col] = s;
                                at(&m0.retracted(&d, None))
                            };
                            let (qp, bp, wp) = pert(h);
                            let (qm, bm, wm) = pert(-h);
                            let fd: Vec3 = match (what, frame) {
                                (Quantity::Orientation, Frame::Body) => {
                                    let (a, b) = (so3::log(q0.conj() * qp), so3::log(q0.conj() * qm));
                                    std::array::from_fn(|r| (a[r] - b[r]) / (2.0 * h))
                                }
                                (Quantity::Orientation, Frame::World) => {
                                    let (a, b) = (so3::log(qp * q0.conj()), so3::log(qm * q0.conj()));
                                    std::array::from_fn(|r| (a[r] - b[r]) / (2.0 * h))
                                }
                                (Quantity::AngularVelocity, Frame::Body) => {
                                    std::array::from_fn(|r| (bp[r] - bm[r]) / (2.0 * h))
                                }
                                (Quantity::AngularVelocity, Frame::World) => {
                                    std::array::from_fn(|r| (wp[r] - wm[r]) / (2.0 * h))
                                }
                            };
                            for r in 0..3 {
                                assert!(
                                    (jac[r][col] - fd[r]).abs() < 1e-6 * (1.0 + fd[r].abs()),
                                    "{pen:?} {what:?} {frame:?} t {tt} col {col} r {r}: {} vs {}",
                                    jac[r][col],
                                    fd[r]
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// The covariance from the selected inverse equals σ̂² J H⁻¹ Jᵀ with H⁻¹ from dense solves,
    /// σ̂² = RSS/(n_obs − tr(H⁻¹G)) with the trace from dense H⁻¹, and the edf the fit reports.
    #[test]
    fn covariance_matches_dense_inverse() {
        let t: Vec<f64> = (0..50).map(|i| 0.08 * i as f64 + 0.01 * ((i * 7) % 3) as f64).collect();
        let mut rng = XorShift64::new(9);
        let y = noisy(&t, 0.02, &mut rng);
        let w: Vec<f64> =
            (0..t.len()).map(|i| if i == 7 { 0.0 } else { 0.5 + (i % 4) as f64 * 0.3 }).collect();
        for pen in [Penalty::Acceleration, Penalty::Jerk] {
            let opts = FitOptions { penalty: pen, ..Default::default() };
            let r = super::super::fit(&t, &y, Some(&w), &opts, &mut |_, _, _| true).unwrap();
            let post =
                Posterior::new(&t, &y, Some(&w), None, r.ctrl.clone(), layout_of(&r), pen, r.lambda, None)
                    .unwrap();
            assert!(
                (post.edf - r.edf).abs() < 1e-6 * r.edf,
                "{pen:?}: edf {} vs the fit's {}",
                post.edf,
                r.edf
            );
            assert_eq!(post.nobs, 3.0 * (t.len() - 1) as f64);
            // Dense H from the same assembly.
            let k = post.model.order;
            let data = validate(&t, &y, Some(&w), 1, "").unwrap();
            let offs = vec![[0.0; 3]; t.len()];
            let g = data_half(&post.model, &data, &data.w, &offs, Band::zeros(0, 0)).band;
            let nodes = gauss_legendre01(penalty_nodes(k, pen.m(), false));
            let p = pen_half(&post.model, pen, &nodes, Band::zeros(0, 0), None).band;
            let h = g.axpy(r.lambda, &p);
            let l = h.cholesky().unwrap();
            let n = h.n;
            let hinv: Vec<Vec<f64>> = (0..n)
                .map(|j| l.solve(&(0..n).map(|i| if i == j { 1.0 } else { 0.0 }).collect::<Vec<_>>()))
                .collect();
            let gd = dense(&g);
            let tr: f64 = (0..n).map(|i| (0..n).map(|j| hinv[i][j] * gd[j][i]).sum::<f64>()).sum();
            assert!((tr - post.edf).abs() < 1e-9 * tr);
            let s2 = post.rss / (post.nobs - tr);
            assert!((s2 - post.sigma2).abs() < 1e-9 * s2);
            for &tt in &[0.0, 0.5, 1.234, t[t.len() - 1]] {
                for (what, frame) in
                    [(Quantity::Orientation, Frame::Body), (Quantity::AngularVelocity, Frame::World)]
                {
                    let (i, jac) = post.jacobian(tt, what, frame);
                    let c = post.covariance_at(tt, what, frame);
                    for r in 0..3 {
                        for q in 0..3 {
                            let mut want = 0.0;
                            for a in 0..3 * k {
                                for b in 0..3 * k {
                                    want += jac[r][a] * hinv[3 * i + a][3 * i + b] * jac[q][b];
                                }
                            }
                            want *= s2;
                            assert!(
                                (c[r][q] - want).abs() < 1e-9 * (c[r][r] * c[q][q]).sqrt(),
                                "{pen:?} {what:?} t {tt} [{r}][{q}]: {} vs {want}",
                                c[r][q]
                            );
                        }
                    }
                }
            }
        }
    }

    /// Monte Carlo on a small problem at a fixed λ: the sample covariance of the fitted
    /// orientation over 200 noise draws of known σ (about the draws' mean curve, in the tangent
    /// space at the noise-free fit q₀(t)) against the frequentist (sandwich) covariance
    /// σ² J H⁻¹ G H⁻¹ Jᵀ of the linearised smoother, H and G dense at q₀. The Bayesian
    /// covariance σ² J H⁻¹ Jᵀ (what the intervals use) is larger by σ² J H⁻¹ λP H⁻¹ Jᵀ, the
    /// allowance for the smoother's bias: the test also checks that the sample covariance
    /// tells the two apart at this λ, so it would fail if the Bayesian one were compared.
    #[test]
    fn sandwich_covariance_matches_monte_carlo() {
        let t: Vec<f64> = (0..40).map(|i| 0.1 * i as f64).collect();
        let sigma = 0.02;
        let pen = Penalty::Acceleration;
        let lam = 3e-3;
        let opts = FitOptions { penalty: pen, smoothing: Smoothing::Fixed(lam), ..Default::default() };
        let clean: Vec<Quat> = t.iter().map(|&s| truth(s)).collect();
        let r0 = super::super::fit(&t, &clean, None, &opts, &mut |_, _, _| true).unwrap();
        let post =
            Posterior::new(&t, &clean, None, None, r0.ctrl.clone(), layout_of(&r0), pen, lam, None).unwrap();
        let m0 = &post.model;
        let k = m0.order;
        let data = validate(&t, &clean, None, 1, "").unwrap();
        let offs = vec![[0.0; 3]; t.len()];
        let g = dense(&data_half(m0, &data, &data.w, &offs, Band::zeros(0, 0)).band);
        let nodes = gauss_legendre01(penalty_nodes(k, pen.m(), false));
        let hb = data_half(m0, &data, &data.w, &offs, Band::zeros(0, 0))
            .band
            .axpy(lam, &pen_half(m0, pen, &nodes, Band::zeros(0, 0), None).band);
        let l = hb.cholesky().unwrap();
        let n = hb.n;
        let hinv: Vec<Vec<f64>> = (0..n)
            .map(|j| l.solve(&(0..n).map(|i| if i == j { 1.0 } else { 0.0 }).collect::<Vec<_>>()))
            .collect();
        // M = H⁻¹ G H⁻¹
        let hg: Vec<Vec<f64>> =
            (0..n).map(|i| (0..n).map(|j| (0..n).map(|a| hinv[i][a] * g[a][j]).sum()).collect()).collect();
        let sand: Vec<Vec<f64>> =
            (0..n).map(|i| (0..n).map(|j| (0..n).map(|a| hg[i][a] * hinv[a][j]).sum()).collect()).collect();
        let evals: Vec<f64> = (0..=13).map(|j| 0.3 * j as f64).collect();
        let quad = |mat: &Vec<Vec<f64>>, tt: f64| -> [[f64; 3]; 3] {
            let (i, jac) = post.jacobian(tt, Quantity::Orientation, Frame::Body);
            std::array::from_fn(|r| {
                std::array::from_fn(|q| {
                    let mut v = 0.0;
                    for a in 0..3 * k {
                        for b in 0..3 * k {
                            v += jac[r][a] * mat[3 * i + a][3 * i + b] * jac[q][b];
                        }
                    }
                    sigma * sigma * v
                })
            })
        };
        let draws = 200;
        let mut rng = XorShift64::new(2024);
        let mut e = vec![vec![[0.0; 3]; evals.len()]; draws];
        for d in 0..draws {
            let y = noisy(&t, sigma, &mut rng);
            let r = super::super::fit(&t, &y, None, &opts, &mut |_, _, _| true).unwrap();
            let m = Model::with_layout(r.ctrl, layout_of(&r0));
            for (j, &tt) in evals.iter().enumerate() {
                let (i, u) = m.locate(tt);
                let q = m.value::<1>(i, Jet::constant(u)).value();
                let q0 = m0.value::<1>(i, Jet::constant(u)).value();
                e[d][j] = so3::log(q0.conj() * q);
            }
        }
        let (mut worst, mut sum_s, mut sum_b) = (0.0f64, 0.0, 0.0);
        for (j, &tt) in evals.iter().enumerate() {
            let mean: Vec3 = std::array::from_fn(|r| e.iter().map(|x| x[j][r]).sum::<f64>() / draws as f64);
            let tr_mc: f64 = (0..3)
                .map(|r| e.iter().map(|x| (x[j][r] - mean[r]).powi(2)).sum::<f64>() / (draws - 1) as f64)
                .sum();
            let s = quad(&sand, tt);
            let b = quad(&hinv, tt);
            let tr_s = s[0][0] + s[1][1] + s[2][2];
            let tr_b = b[0][0] + b[1][1] + b[2][2];
            // The band-based Bayesian covariance at the same σ equals the dense one.
            let c = post.covariance_at(tt, Quantity::Orientation, Frame::Body);
            let tr_c = (c[0][0] + c[1][1] + c[2][2]) * sigma * sigma / post.sigma2;
            assert!((tr_c - tr_b).abs() < 1e-9 * tr_b, "t {tt}: {tr_c} vs {tr_b}");
            worst = worst.max((tr_mc / tr_s - 1.0).abs());
            sum_s += tr_mc / tr_s;
            sum_b += tr_mc / tr_b;
        }
        let (ms, mb) = (sum_s / evals.len() as f64, sum_b / evals.len() as f64);
        // 199 degrees of freedom: a variance to about ±10 % (one standard error per axis).
        assert!(worst < 0.3, "sample/sandwich trace ratio off by {worst}");
        assert!((ms - 1.0).abs() < 0.12, "mean sample/sandwich ratio {ms}");
        assert!(mb < 0.85, "the Bayesian covariance should exceed the variance at this λ: ratio {mb}");
    }
}
