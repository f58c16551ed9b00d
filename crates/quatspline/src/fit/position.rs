//! Positions: a penalised least-squares B-spline in ℝ³ with the same knots, order and
//! penalty as the orientation fit (Eilers & Marx 1996 style, with the exact integral penalty).
//!
//! p(t) = Σ_{j=0}^{k−1} c_{i+j} B_j(u) on segment i, u = (t − t₀)/Δt − i, where the uniform
//! B-spline basis B_j = B̃_j − B̃_{j+1} comes from the cumulative blending matrix (B̃₀ = 1,
//! B̃_k = 0; MATH.md §6), equivalently p = c_i + Σ_{j≥1} B̃_j(u)(c_{i+j} − c_{i+j−1}).
//! Objective Σ_s w_s ρ(|p(t_s) − x_s|²) + λ ∫ |p^(m+1)|² dt (m = 1: acceleration, 2: jerk),
//! the integral exact by k-point Gauss–Legendre (the integrand is a polynomial of degree
//! ≤ 2(k − 3)). Linear: one banded Cholesky (half-bandwidth k − 1) shared by x, y, z; λ by
//! GCV with tr A = 3 tr(H⁻¹G) from the selected inverse; robust losses by IRLS.

use super::banded::Band;
use super::layout::Layout;
use super::{fit_layout, Knots, Penalty, Robust, Smoothing};
use crate::error::{Error, Result};
use crate::quadrature::gauss_legendre01;
use rayon::prelude::*;

/// The fitted positions.
#[derive(Debug, Clone)]
pub struct PositionFit {
    pub ctrl: Vec<[f64; 3]>,
    pub dt: f64,
    pub t0: f64,
    pub order: usize,
    /// Breakpoints of a non-uniform layout (None: uniform t₀ + jΔt).
    pub breaks: Option<Vec<f64>>,
    pub residuals: Vec<f64>,
    pub robust_weights: Vec<f64>,
    pub lambda: f64,
    /// The λ asked for when it was beyond [`super::lambda_cap`] (the fit used the cap).
    pub lambda_requested: Option<f64>,
    pub edf: f64,
    pub score: f64,
    pub iterations: usize,
}

/// A polynomial of the penalty's null space fitted to the data, as samples' remainders and
/// as B-spline control points.
struct NullSpaceFit {
    /// x − P(t) per sample.
    residuals: Vec<[f64; 3]>,
    /// The control points that represent P exactly (empty when no polynomial was fitted).
    ctrl: Vec<[f64; 3]>,
}

/// The weighted least-squares polynomial P of degree `deg` (≤ 2) of the positions x, and its
/// B-spline control points by Marsden's identity: cⱼ is P's blossom at the interior knots
/// u_{j+1} … u_{j+k−1} of Bⱼ (for degree 2 in the scaled time τ: a₀ + a₁·mean τᵢ +
/// a₂·e₂(τ)/C(k−1, 2), e₂ the sum of the products of pairs). Time is centred and scaled to
/// [−1, 1], so the (deg+1)² normal equations are well conditioned (solved as a dense band).
/// No polynomial when fewer than deg + 1 distinct times carry weight (a pivot below 1e-10 of
/// the total weight) or the order cannot represent it.
fn null_space_fit(t: &[f64], x: &[[f64; 3]], w: &[f64], deg: usize, knots: &[f64], k: usize) -> NullSpaceFit {
    let n = t.len();
    let none = || NullSpaceFit { residuals: x.to_vec(), ctrl: Vec::new() };
    let (tc, ts) = (0.5 * (t[0] + t[n - 1]), 0.5 * (t[n - 1] - t[0]));
    if deg > 2 || deg + 1 > k || ts.is_nan() || ts <= 0.0 {
        return none();
    }
    let m = deg + 1;
    let mut gram = Band::zeros(m, deg);
    let mut rhs = vec![vec![0.0; m]; 3];
    let mut blk = vec![0.0; m * m];
    for s in (0..n).filter(|&s| w[s] != 0.0) {
        let tau = (t[s] - tc) / ts;
        let mono = [1.0, tau, tau * tau];
        for r in 0..m {
            for c in 0..m {
                blk[r * m + c] = mono[r] * mono[c];
            }
            for d in 0..3 {
                rhs[d][r] += w[s] * mono[r] * x[s][d];
            }
        }
        gram.add_block(0, m, &blk, w[s]);
    }
    let total = gram.get(0, 0);
    if gram.cholesky_in_place().is_err() || gram.diag().iter().any(|l| l * l <= 1e-10 * total) {
        return none();
    }
    let mut coef = [[0.0f64; 3]; 3];
    for (d, r) in rhs.iter().enumerate() {
        for (i, v) in gram.solve(r).into_iter().enumerate() {
            coef[i][d] = v;
        }
    }
    let residuals = (0..n)
        .map(|s| {
            let tau = (t[s] - tc) / ts;
            std::array::from_fn(|d| x[s][d] - (coef[0][d] + tau * (coef[1][d] + tau * coef[2][d])))
        })
        .collect();
    NullSpaceFit { residuals, ctrl: blossom_ctrl(&coef, tc, ts, knots, k) }
}

/// Control points of the polynomial a₀ + a₁τ + a₂τ² (τ = (t − tc)/ts) as a B-spline of order
/// k on the full knot vector `knots` (Marsden's identity; see [`null_space_fit`]).
fn blossom_ctrl(coef: &[[f64; 3]; 3], tc: f64, ts: f64, knots: &[f64], k: usize) -> Vec<[f64; 3]> {
    let nc = knots.len() - k;
    let pairs = ((k - 1) * (k - 2) / 2).max(1) as f64;
    (0..nc)
        .map(|j| {
            let tau: Vec<f64> = knots[j + 1..j + k].iter().map(|u| (u - tc) / ts).collect();
            let sum: f64 = tau.iter().sum();
            let sq: f64 = tau.iter().map(|v| v * v).sum();
            let (mean, e2) = (sum / (k - 1) as f64, 0.5 * (sum * sum - sq) / pairs);
            std::array::from_fn(|d| coef[0][d] + mean * coef[1][d] + e2 * coef[2][d])
        })
        .collect()
}

/// Basis values B_j(u) and their d-th derivatives in u, j = 0 … k−1, on segment i.
pub fn basis(lay: &Layout, i: usize, u: f64, d: usize) -> Vec<f64> {
    let k = lay.order;
    let cum = |j: usize| -> f64 {
        if j == 0 {
            return if d == 0 { 1.0 } else { 0.0 };
        }
        if j >= k {
            return 0.0;
        }
        // d-th derivative of Σ_c M[j][c] u^c
        let mut acc = 0.0;
        for c in d..k {
            let mut f = 1.0;
            for t in 0..d {
                f *= (c - t) as f64;
            }
            acc += lay.row(i, j)[c] * f * u.powi((c - d) as i32);
        }
        acc
    };
    (0..k).map(|j| cum(j) - cum(j + 1)).collect()
}

/// Evaluates a position B-spline (uniform t₀ + jΔt, or the given breakpoints): rows p, p',
/// p'', p''' (12 values) per time.
pub fn evaluate(
    ctrl: &[[f64; 3]],
    dt: f64,
    t0: f64,
    order: usize,
    breaks: Option<&[f64]>,
    t: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let segs = ctrl.len() + 1 - order;
    let lay = match breaks {
        Some(b) => {
            if b.len() != segs + 1 || b.iter().any(|v| !v.is_finite()) || b.windows(2).any(|w| w[1] <= w[0]) {
                return Err(Error::invalid(
                    "breaks",
                    format!("expected {} increasing breakpoints, got {}", segs + 1, b.len()),
                ));
            }
            Layout::nonuniform(b.to_vec(), order)
        }
        None => Layout::uniform(t0, dt, segs, order),
    };
    let t0 = lay.t0;
    let end = match breaks {
        Some(b) => b[segs],
        None => t0 + segs as f64 * dt,
    };
    let dt = lay.dt;
    for (s, &ti) in t.iter().enumerate() {
        if !ti.is_finite() {
            return Err(Error::NonFinite { arg: "t", index: s });
        }
        if ti < t0 - 1e-9 * dt || ti > end + 1e-9 * dt {
            return Err(Error::OutOfDomain { index: s, t: ti, start: t0, end });
        }
        let (i, u) = lay.locate(ti);
        let h = lay.width(i);
        for d in 0..4 {
            let b = basis(&lay, i, u, d);
            let sc = h.powi(-(d as i32));
            for c in 0..3 {
                out[12 * s + 3 * d + c] = sc * (0..order).map(|j| b[j] * ctrl[i + j][c]).sum::<f64>();
            }
        }
    }
    Ok(())
}

/// The penalty matrix P = ∫ B^(dm) B^(dm)ᵀ dt (exact: k-point Gauss–Legendre per segment) of
/// the position fit, half-bandwidth k − 1.
fn penalty_band(lay: &Layout, dm: usize) -> Band {
    let k = lay.order;
    let mut pm = Band::zeros(lay.segs + k - 1, k - 1);
    let nodes = gauss_legendre01(k);
    let mut blk = vec![0.0; k * k];
    for i in 0..lay.segs {
        blk.iter_mut().for_each(|v| *v = 0.0);
        let h = lay.width(i);
        for &(u, w) in &nodes {
            let b = basis(lay, i, u, dm);
            let sc = h.powi(-(dm as i32));
            for a in 0..k {
                for c in 0..=a {
                    blk[a * k + c] += w * h * sc * sc * b[a] * b[c];
                }
            }
        }
        pm.add_block(i, k, &blk, 1.0);
    }
    pm
}

/// (segment, basis values B_j(u)) of every sample time.
fn sample_bases(lay: &Layout, t: &[f64]) -> Vec<(usize, Vec<f64>)> {
    t.iter()
        .map(|&t| {
            let (i, u) = lay.locate(t);
            (i, basis(lay, i, u, 0))
        })
        .collect()
}

/// The data's normal matrix G = Σ wₛ bₛ bₛᵀ (one block per sample of positive weight).
fn gram_band(loc: &[(usize, Vec<f64>)], w: &[f64], nc: usize, k: usize) -> Band {
    let mut g = Band::zeros(nc, k - 1);
    let mut blk = vec![0.0; k * k];
    for (s, (i, b)) in loc.iter().enumerate() {
        if w[s] == 0.0 {
            continue;
        }
        blk.iter_mut().for_each(|v| *v = 0.0);
        for a in 0..k {
            for c in 0..=a {
                blk[a * k + c] = w[s] * b[a] * b[c];
            }
        }
        g.add_block(*i, k, &blk, 1.0);
    }
    g
}

/// The posterior of a position fit (the linear case of `covariance.rs`): the coordinates
/// share H = G + λP (half-bandwidth k − 1), so Cov(c_x) = Cov(c_y) = Cov(c_z) = σ̂² H⁻¹ and
/// Cov(p(t)) = σ̂² b(t)ᵀ H⁻¹ b(t) · I₃ (b the k basis values of t's knot interval, inside the
/// band of the selected inverse), σ̂² = RSS / (n_obs − 3 tr(H⁻¹G)), n_obs = 3 × the samples of
/// positive weight (Wahba 1983; Nychka 1988). The polynomial of the penalty's null space
/// that the fit removes first passes through the smoother unchanged: the smoother, hence
/// its posterior, is the same.
#[derive(Debug, Clone)]
pub struct PositionPosterior {
    lay: Layout,
    inv: Band,
    /// σ̂², length² per coordinate of a unit-weight residual.
    pub sigma2: f64,
    pub rss: f64,
    pub nobs: f64,
    /// tr A = 3 tr(H⁻¹G).
    pub edf: f64,
}

impl PositionPosterior {
    /// The posterior of the position fit with control points `ctrl` on `lay` to positions
    /// `x` at `times`, sample `weights` (normalised to mean 1, as the fit does), the fit's
    /// final `robust_weights` (None: all 1), `penalty` and λ = `lambda` > 0.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        times: &[f64],
        x: &[[f64; 3]],
        weights: Option<&[f64]>,
        robust_weights: Option<&[f64]>,
        ctrl: &[[f64; 3]],
        lay: Layout,
        penalty: Penalty,
        lambda: f64,
    ) -> Result<PositionPosterior> {
        let n = times.len();
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(Error::invalid(
                "smoothing",
                format!(
                    "the posterior needs a smoothing fit (λ > 0), got λ = {}: an interpolating fit \
                     has no residuals to estimate the noise from",
                    crate::error::Short(lambda)
                ),
            ));
        }
        if x.len() != n {
            return Err(Error::invalid(
                "positions",
                format!("expected {n} positions (one per time), got {}", x.len()),
            ));
        }
        let k = lay.order;
        let nc = lay.segs + k - 1;
        if ctrl.len() != nc {
            return Err(Error::invalid(
                "ctrl",
                format!("expected {nc} control points for the layout, got {}", ctrl.len()),
            ));
        }
        let ident = vec![crate::quat::Quat::IDENTITY; n];
        let data = super::validate(times, &ident, weights, 1, "")?;
        let w = super::covariance::effective_weights(&data.w, robust_weights)?;
        let loc = sample_bases(&lay, &data.t);
        let g = gram_band(&loc, &w, nc, k);
        let mut h = penalty_band(&lay, penalty.m() + 1);
        for (a, b) in h.a.iter_mut().zip(&g.a) {
            *a = b + lambda * *a;
        }
        h.cholesky_in_place().map_err(|e| {
            Error::Internal(format!("the position fit's normal matrix G + λP is not positive definite: {e}"))
        })?;
        let edf = 3.0 * h.trace_inverse_product(&g);
        let inv = h.selected_inverse();
        drop(h);
        let (mut rss, mut nobs) = (0.0, 0.0);
        for (s, (i, b)) in loc.iter().enumerate() {
            if w[s] == 0.0 {
                continue;
            }
            nobs += 3.0;
            for d in 0..3 {
                let p: f64 = (0..k).map(|j| b[j] * ctrl[i + j][d]).sum();
                rss += w[s] * (p - x[s][d]).powi(2);
            }
        }
        let sigma2 = super::covariance::noise_variance(rss, nobs, edf)?;
        Ok(PositionPosterior { lay, inv, sigma2, rss, nobs, edf })
    }

    /// The variance of each coordinate of p(t) (derivative 0) or of the velocity p'(t)
    /// (derivative 1) at every time of `t` (the covariance is that times I₃), in parallel.
    /// Times must be finite and inside the domain (to 1e-9 of a knot interval).
    pub fn variances(&self, t: &[f64], derivative: usize) -> Result<Vec<f64>> {
        if derivative > 3 {
            return Err(Error::invalid("derivative", format!("expected 0 … 3, got {derivative}")));
        }
        let lay = &self.lay;
        let (a, b) = match &lay.breaks {
            Some(br) => (br[0], br[lay.segs]),
            None => (lay.t0, lay.t0 + lay.segs as f64 * lay.dt),
        };
        let tol = 1e-9 * lay.dt;
        for (s, &v) in t.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFinite { arg: "t", index: s });
            }
            if v < a - tol || v > b + tol {
                return Err(Error::OutOfDomain { index: s, t: v, start: a, end: b });
            }
        }
        use rayon::prelude::*;
        let k = lay.order;
        Ok(t.par_iter()
            .with_min_len(256)
            .map(|&v| {
                let (i, u) = lay.locate(v);
                let sc = lay.width(i).powi(-(derivative as i32));
                let bb = basis(lay, i, u, derivative);
                let mut q = 0.0;
                for x in 0..k {
                    for y in 0..k {
                        q += bb[x] * self.inv.get(i + x, i + y) * bb[y];
                    }
                }
                self.sigma2 * sc * sc * q
            })
            .collect())
    }
}

#[allow(clippy::too_many_arguments)]
/// Fits positions `x` at `times` (validated by the caller's orientation fit or here).
pub fn fit_positions(
    times: &[f64],
    x: &[[f64; 3]],
    weights: Option<&[f64]>,
    penalty: Penalty,
    order: Option<usize>,
    smoothing: Smoothing,
    knots: &Knots,
    robust: Robust,
    robust_scale: Option<f64>,
) -> Result<PositionFit> {
    let n = times.len();
    if x.len() != n {
        return Err(Error::invalid(
            "positions",
            format!("expected {n} positions (one per time), got {}", x.len()),
        ));
    }
    for (i, p) in x.iter().enumerate() {
        if !p.iter().all(|v| v.is_finite()) {
            return Err(Error::NonFinite { arg: "positions", index: i });
        }
    }
    // Reuse the orientation validation for times and weights.
    let ident = vec![crate::quat::Quat::IDENTITY; n];
    let data = super::validate(times, &ident, weights, penalty.m() + 1, "")?;
    let k = order.unwrap_or(penalty.default_order());
    let dm = penalty.m() + 1;
    let lay = fit_layout(knots, &data.t, k)?;
    let (t0, dt, segs) = (lay.t0, lay.dt, lay.segs);
    let nc = segs + k - 1;
    // Penalty matrix P (exact) and data rows.
    let pm = penalty_band(&lay, dm);
    let loc = sample_bases(&lay, &data.t);
    let span = data.t[n - 1] - data.t[0];
    let rho = n as f64 / span;
    let lam_of = |h: f64| rho * h.powi(2 * dm as i32);
    let dts = span / (n - 1) as f64;
    let mut w = data.w.clone();
    let mut robust_on = false;
    let mut c_rob = f64::INFINITY;
    let mut prev: Option<Vec<[f64; 3]>> = None;
    let mut it = 0;
    let mut last_move = f64::INFINITY;
    let (mut lam_prev, mut lam_frozen) = (f64::NAN, false);
    let mut lam_requested = None;
    let knots_full = match &lay.breaks {
        Some(b) => super::layout::full_knots(b, k),
        None => (0..segs + 2 * k - 1).map(|j| t0 + (j as f64 - (k - 1) as f64) * dt).collect(),
    };
    loop {
        it += 1;
        if it > 1000 {
            return Err(Error::NotConverged {
                what: "fit (positions, IRLS)",
                iterations: 1000,
                step: last_move,
                tol: 1e-9,
            });
        }
        let g = gram_band(&loc, &w, nc, k);
        let mut rhs = vec![[0.0; 3]; nc];
        let mut nobs = 0.0;
        let mut xwx = 0.0;
        // The penalty's null space (polynomials of degree < dm) passes through the smoother
        // unchanged, so the fit of x is that polynomial's weighted least-squares fit plus the
        // fit of what it leaves: solving for the remainder only keeps a stiff penalty (large
        // λ) from rounding away the polynomial part (measured: a fixed λ near the largest
        // resolved one lost 1e-3–2e-2 of a unit-size curve when solving for x itself).
        let poly = null_space_fit(&data.t, x, &w, dm - 1, &knots_full, k);
        let xr = &poly.residuals;
        for (s, (i, b)) in loc.iter().enumerate() {
            if w[s] == 0.0 {
                continue;
            }
            nobs += 3.0;
            for a in 0..k {
                for d in 0..3 {
                    rhs[i + a][d] += w[s] * b[a] * xr[s][d];
                }
            }
            xwx += w[s] * (xr[s][0] * xr[s][0] + xr[s][1] * xr[s][1] + xr[s][2] * xr[s][2]);
        }
        let solve_at = |lam: f64| -> Result<(f64, f64, Vec<[f64; 3]>)> {
            let mut l = g.axpy(lam, &pm);
            l.cholesky_in_place()?;
            let mut cs = vec![[0.0; 3]; nc];
            let mut rss = xwx;
            for d in 0..3 {
                let r: Vec<f64> = rhs.iter().map(|v| v[d]).collect();
                let c = l.solve(&r);
                let gc = g.matvec(&c);
                rss += -2.0 * c.iter().zip(&r).map(|(a, b)| a * b).sum::<f64>()
                    + c.iter().zip(&gc).map(|(a, b)| a * b).sum::<f64>();
                for j in 0..nc {
                    cs[j][d] = c[j];
                }
            }
            let tr = 3.0 * l.trace_inverse_product(&g);
            let den = nobs - tr;
            let score = if den > 1e-9 * nobs { nobs * rss.max(0.0) / (den * den) } else { f64::INFINITY };
            Ok((score, tr, cs))
        };
        // The largest λ double precision resolves for this G (see `lambda_cap`).
        let cap = super::lambda_cap(&g, &pm);
        let lam = match smoothing {
            Smoothing::Fixed(l) if l > cap => {
                lam_requested = Some(l);
                cap
            }
            Smoothing::Fixed(l) if l > 0.0 => l,
            Smoothing::Fixed(_) => lam_of(dts) * 1e-10,
            Smoothing::Auto if lam_frozen => lam_prev,
            Smoothing::Auto => {
                let b = lam_of(span).min(cap);
                let (a, b) = (lam_of(0.3 * dts).min(b / 1e6).ln(), b.ln());
                let f = |x: f64| solve_at(x.exp()).map(|r| r.0).unwrap_or(f64::INFINITY);
                let grid = 25;
                let xs: Vec<f64> = (0..grid).map(|i| a + (b - a) * i as f64 / (grid - 1) as f64).collect();
                // The grid's candidates are independent: in parallel (each its own factor of
                // nc × k doubles; the values, hence the choice, do not depend on the threads).
                let vals: Vec<f64> = xs.par_iter().map(|&x| f(x)).collect();
                let ib = (0..grid).min_by(|&i, &j| vals[i].total_cmp(&vals[j])).unwrap_or(0);
                let (mut l, mut r) = (xs[ib.saturating_sub(1)], xs[(ib + 1).min(grid - 1)]);
                let gr = 0.5 * (5f64.sqrt() - 1.0);
                let (mut c, mut d) = (r - gr * (r - l), l + gr * (r - l));
                let (mut fc, mut fd) = (f(c), f(d));
                for _ in 0..20 {
                    if fc < fd {
                        r = d;
                        d = c;
                        fd = fc;
                        c = r - gr * (r - l);
                        fc = f(c);
                    } else {
                        l = c;
                        c = d;
                        fc = fd;
                        d = l + gr * (r - l);
                        fd = f(d);
                    }
                }
                let cand = [(vals[ib], xs[ib]), (fc, c), (fd, d)];
                let l = cand.iter().min_by(|p, q| p.0.total_cmp(&q.0)).map(|p| p.1.exp()).unwrap_or(1.0);
                // Robust fits: λ is chosen on the non-robust pilot and once more under the
                // first robust weights, then kept for the IRLS rounds. Re-choosing it every
                // round let weights and λ feed each other: robust fits of a cubic with 1–5 %
                // outliers often ran out of their 1000 rounds (10 of the first cases of a grid
                // tried). Keeping the pilot's λ (fitted to the outliers too) let Cauchy weights
                // cascade along clean samples (RMS errors 7–93 units); two or five re-choices
                // converged too, with 1.6–4.1 % larger errors (geometric mean of the RMS).
                lam_frozen = robust_on;
                lam_prev = l;
                l
            }
        };
        let (score, tr, mut cs) = solve_at(lam)?;
        for (c, pc) in cs.iter_mut().zip(&poly.ctrl) {
            for d in 0..3 {
                c[d] += pc[d];
            }
        }
        let res: Vec<f64> = loc
            .iter()
            .enumerate()
            .map(|(s, (i, b))| {
                let p: [f64; 3] = std::array::from_fn(|d| (0..k).map(|j| b[j] * cs[i + j][d]).sum());
                ((p[0] - x[s][0]).powi(2) + (p[1] - x[s][1]).powi(2) + (p[2] - x[s][2]).powi(2)).sqrt()
            })
            .collect();
        let moved = match &prev {
            None => f64::INFINITY,
            Some(p) => p
                .iter()
                .zip(&cs)
                .map(|(a, b)| (0..3).map(|d| (a[d] - b[d]).abs()).fold(0.0, f64::max))
                .fold(0.0, f64::max),
        };
        let scale = cs.iter().flat_map(|v| v.iter()).map(|v| v.abs()).fold(1e-300, f64::max);
        last_move = moved / scale;
        let done = robust == Robust::None || (robust_on && moved <= 1e-9 * scale);
        if done {
            let rw = (0..n).map(|s| if robust_on { robust.weight(res[s], c_rob) } else { 1.0 }).collect();
            return Ok(PositionFit {
                ctrl: cs,
                dt,
                t0,
                order: k,
                breaks: lay.breaks.as_ref().map(|b| b.to_vec()),
                residuals: res,
                robust_weights: rw,
                lambda: if smoothing == Smoothing::Fixed(0.0) { 0.0 } else { lam },
                lambda_requested: lam_requested,
                edf: tr,
                score,
                iterations: it,
            });
        }
        if !robust_on {
            c_rob = match robust_scale {
                Some(c) => c,
                None => {
                    let mut a: Vec<f64> = res.clone();
                    let mid = a.len() / 2;
                    a.select_nth_unstable_by(mid, |p, q| p.total_cmp(q));
                    // σ̂ is at least 1e-6 × the positions' extent (10 µm on 10 m, below any
                    // tracker's noise): smaller residuals are rounding and λ's bias, not
                    // outliers. Without the floor, noise-free samples (median residual at
                    // rounding level) were all downweighted until the data term vanished: the
                    // fit ran 1000 iterations or returned a curve 100–500 units off a cubic
                    // spanning 512.
                    let extent = (0..3)
                        .map(|d| {
                            let (lo, hi) = x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                                (l.min(p[d]), h.max(p[d]))
                            });
                            hi - lo
                        })
                        .fold(0.0, f64::max);
                    robust.tuning() * (1.4826 * a[mid]).max(1e-6 * extent).max(1e-300)
                }
            };
            robust_on = true;
        }
        for s in 0..n {
            w[s] = data.w[s] * robust.weight(res[s], c_rob);
        }
        prev = Some(cs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The posterior variances from the selected inverse against σ̂² bᵀH⁻¹b with H⁻¹ from dense
    /// solves (positions and velocities, uniform and uneven knots, weights with a zero), with
    /// σ̂² = RSS/(n_obs − tr A) and tr A the edf the fit reports; an interpolating fit is refused.
    #[test]
    fn posterior_matches_dense_inverse() {
        let t: Vec<f64> = (0..60).map(|i| 0.05 * i as f64 + 0.01 * ((i * 3) % 4) as f64).collect();
        let mut rng = crate::testing::XorShift64::new(3);
        let x: Vec<[f64; 3]> =
            t.iter().map(|&s| [s.sin() + 0.01 * (rng.uniform() - 0.5), s * s, 0.1 * rng.uniform()]).collect();
        let w: Vec<f64> = (0..t.len()).map(|i| if i == 5 { 0.0 } else { 1.0 + (i % 3) as f64 }).collect();
        let rw: Vec<f64> = (0..t.len()).map(|i| if i == 9 { 0.3 } else { 1.0 }).collect();
        for (pen, knots) in [
            (Penalty::Acceleration, Knots::Default),
            (Penalty::Jerk, Knots::Default),
            (Penalty::Acceleration, Knots::Array(vec![t[0], 0.4, 0.5, 1.9, t[59]])),
        ] {
            let f = fit_positions(&t, &x, Some(&w), pen, None, Smoothing::Auto, &knots, Robust::None, None)
                .unwrap();
            let lay =
                super::super::fitted_layout(f.ctrl.len(), f.dt, f.t0, f.order, f.breaks.as_deref()).unwrap();
            let post =
                PositionPosterior::new(&t, &x, Some(&w), None, &f.ctrl, lay.clone(), pen, f.lambda).unwrap();
            assert!((post.edf - f.edf).abs() < 1e-8 * f.edf, "{pen:?}: {} vs {}", post.edf, f.edf);
            // With IRLS weights, against dense algebra.
            let post =
                PositionPosterior::new(&t, &x, Some(&w), Some(&rw), &f.ctrl, lay.clone(), pen, f.lambda)
                    .unwrap();
            let data =
                super::super::validate(&t, &vec![crate::quat::Quat::IDENTITY; 60], Some(&w), 1, "").unwrap();
            let we: Vec<f64> = data.w.iter().zip(&rw).map(|(a, b)| a * b).collect();
            let k = lay.order;
            let nc = f.ctrl.len();
            let loc = sample_bases(&lay, &t);
            let g = gram_band(&loc, &we, nc, k);
            let h = g.axpy(f.lambda, &penalty_band(&lay, pen.m() + 1));
            let l = h.cholesky().unwrap();
            let hinv: Vec<Vec<f64>> = (0..nc)
                .map(|j| l.solve(&(0..nc).map(|i| if i == j { 1.0 } else { 0.0 }).collect::<Vec<_>>()))
                .collect();
            let tr: f64 = (0..nc)
                .map(|i| {
                    (0..nc).filter(|j| i.abs_diff(*j) < k).map(|j| hinv[i][j] * g.get(j, i)).sum::<f64>()
                })
                .sum();
            let mut rss = 0.0;
            for (s, (i, b)) in loc.iter().enumerate() {
                for d in 0..3 {
                    let p: f64 = (0..k).map(|j| b[j] * f.ctrl[i + j][d]).sum();
                    rss += we[s] * (p - x[s][d]).powi(2);
                }
            }
            let s2 = rss / (3.0 * 59.0 - 3.0 * tr);
            assert!((s2 - post.sigma2).abs() < 1e-9 * s2, "{s2} vs {}", post.sigma2);
            let ts = [t[0], 0.33, 1.0, 2.2, t[59]];
            for d in [0usize, 1] {
                let v = post.variances(&ts, d).unwrap();
                for (j, &tt) in ts.iter().enumerate() {
                    let (i, u) = lay.locate(tt);
                    let b = basis(&lay, i, u, d);
                    let sc = lay.width(i).powi(-(d as i32));
                    let mut want = 0.0;
                    for a in 0..k {
                        for c in 0..k {
                            want += b[a] * hinv[i + a][i + c] * b[c];
                        }
                    }
                    want *= s2 * sc * sc;
                    assert!((v[j] - want).abs() < 1e-9 * want, "{pen:?} d {d} t {tt}: {} vs {want}", v[j]);
                }
            }
            assert!(post.variances(&[t[59] + 0.1], 0).is_err());
            assert!(post.variances(&[f64::NAN], 0).is_err());
            assert!(PositionPosterior::new(&t, &x, Some(&w), None, &f.ctrl, lay, pen, 0.0).is_err());
        }
    }

    /// Marsden's identity: the control points of a parabola, as B-spline coefficients on
    /// uniform and uneven knots of orders 3–6, give back the parabola everywhere.
    #[test]
    fn blossom_control_points_reproduce_polynomials() {
        let coef = [[0.3, -1.0, 2.0], [1.5, 0.25, -0.5], [-0.7, 2.0, 0.0]];
        let (tc, ts) = (1.2, 0.8);
        let breaks = vec![0.4, 0.5, 0.9, 1.0, 1.45, 1.6, 2.0];
        for k in 3..=6 {
            for lay in [Layout::uniform(0.4, 0.2, 8, k), Layout::nonuniform(breaks.clone(), k)] {
                let knots = match &lay.breaks {
                    Some(b) => super::super::layout::full_knots(b, k),
                    None => (0..lay.segs + 2 * k - 1)
                        .map(|j| lay.t0 + (j as f64 - (k - 1) as f64) * lay.dt)
                        .collect(),
                };
                let c = blossom_ctrl(&coef, tc, ts, &knots, k);
                assert_eq!(c.len(), lay.segs + k - 1);
                for q in 0..=40 {
                    let t = 0.4 + 1.6 * q as f64 / 40.0;
                    let (i, u) = lay.locate(t);
                    let b = basis(&lay, i, u, 0);
                    let tau = (t - tc) / ts;
                    for d in 0..3 {
                        let got: f64 = (0..k).map(|j| b[j] * c[i + j][d]).sum();
                        let want = coef[0][d] + tau * (coef[1][d] + tau * coef[2][d]);
                        assert!((got - want).abs() < 1e-12, "k {k} t {t}: {got} vs {want}");
                    }
                }
            }
        }
    }

    /// The weighted least-squares polynomial: exact on polynomial data (zero-weight samples
    /// ignored), and none when fewer distinct times than coefficients carry weight.
    #[test]
    fn null_space_fit_is_weighted_least_squares() {
        let t: Vec<f64> = (0..9).map(|i| 0.25 * i as f64).collect();
        let mut x: Vec<[f64; 3]> = t.iter().map(|&s| [1.0 + s * s, 2.0 - s, 0.5 * s * s]).collect();
        x[4] = [100.0, -50.0, 7.0];
        let mut w = vec![1.0; 9];
        w[4] = 0.0;
        let knots: Vec<f64> = (0..8 + 7).map(|j| (j as f64 - 3.0) * 0.25).collect();
        let f = null_space_fit(&t, &x, &w, 2, &knots, 4);
        for s in (0..9).filter(|&s| s != 4) {
            assert!(f.residuals[s].iter().all(|r| r.abs() < 1e-12), "sample {s}: {:?}", f.residuals[s]);
        }
        let mut w2 = vec![0.0; 9];
        w2[2] = 1.0;
        w2[6] = 3.0;
        let g = null_space_fit(&t, &x, &w2, 2, &knots, 4);
        assert!(g.ctrl.is_empty() && g.residuals == x);
    }
}
