//! Positions: a penalised least-squares uniform B-spline in ℝ³ with the same knots, order and
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
use super::{gauss_legendre01, knot_layout, Knots, Penalty, Robust, Smoothing};
use crate::error::{Error, Result};

/// The fitted positions.
#[derive(Debug, Clone)]
pub struct PositionFit {
    pub ctrl: Vec<[f64; 3]>,
    pub dt: f64,
    pub t0: f64,
    pub order: usize,
    pub residuals: Vec<f64>,
    pub robust_weights: Vec<f64>,
    pub lambda: f64,
    pub edf: f64,
    pub score: f64,
    pub iterations: usize,
}

/// Basis values B_j(u) and their d-th derivatives in u, j = 0 … k−1.
pub fn basis(m: &[Vec<f64>], u: f64, d: usize) -> Vec<f64> {
    let k = m.len();
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
            acc += m[j][c] * f * u.powi((c - d) as i32);
        }
        acc
    };
    (0..k).map(|j| cum(j) - cum(j + 1)).collect()
}

/// Evaluates a position B-spline: rows p, p', p'', p''' (12 values) per time.
pub fn evaluate(ctrl: &[[f64; 3]], dt: f64, t0: f64, order: usize, t: &[f64], out: &mut [f64]) -> Result<()> {
    let m = crate::spline::cumulative_blending_matrix(order);
    let segs = ctrl.len() + 1 - order;
    let end = t0 + segs as f64 * dt;
    for (s, &ti) in t.iter().enumerate() {
        if !ti.is_finite() {
            return Err(Error::NonFinite { arg: "t", index: s });
        }
        if ti < t0 - 1e-9 * dt || ti > end + 1e-9 * dt {
            return Err(Error::OutOfDomain { index: s, t: ti, start: t0, end });
        }
        let x = (ti - t0) / dt;
        let i = (x.floor().max(0.0) as usize).min(segs - 1);
        let u = x - i as f64;
        for d in 0..4 {
            let b = basis(&m, u, d);
            let sc = dt.powi(-(d as i32));
            for c in 0..3 {
                out[12 * s + 3 * d + c] = sc * (0..order).map(|j| b[j] * ctrl[i + j][c]).sum::<f64>();
            }
        }
    }
    Ok(())
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
    let (t0, dt, segs) = knot_layout(knots, &data.t)?;
    let nc = segs + k - 1;
    let bm = crate::spline::cumulative_blending_matrix(k);
    // Penalty matrix P (exact) and data rows.
    let mut pm = Band::zeros(nc, k - 1);
    let nodes = gauss_legendre01(k);
    let mut blk = vec![0.0; k * k];
    for i in 0..segs {
        blk.iter_mut().for_each(|v| *v = 0.0);
        for &(u, w) in &nodes {
            let b = basis(&bm, u, dm);
            let sc = dt.powi(-(dm as i32));
            for a in 0..k {
                for c in 0..=a {
                    blk[a * k + c] += w * dt * sc * sc * b[a] * b[c];
                }
            }
        }
        pm.add_block(i, k, &blk, 1.0);
    }
    let loc: Vec<(usize, Vec<f64>)> = data
        .t
        .iter()
        .map(|&t| {
            let xx = (t - t0) / dt;
            let i = (xx.floor().max(0.0) as usize).min(segs - 1);
            (i, basis(&bm, xx - i as f64, 0))
        })
        .collect();
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
        let mut g = Band::zeros(nc, k - 1);
        let mut rhs = vec![[0.0; 3]; nc];
        let mut nobs = 0.0;
        let mut xwx = 0.0;
        for (s, (i, b)) in loc.iter().enumerate() {
            if w[s] == 0.0 {
                continue;
            }
            nobs += 3.0;
            blk.iter_mut().for_each(|v| *v = 0.0);
            for a in 0..k {
                for c in 0..=a {
                    blk[a * k + c] = w[s] * b[a] * b[c];
                }
                for d in 0..3 {
                    rhs[i + a][d] += w[s] * b[a] * x[s][d];
                }
            }
            xwx += w[s] * (x[s][0] * x[s][0] + x[s][1] * x[s][1] + x[s][2] * x[s][2]);
            g.add_block(*i, k, &blk, 1.0);
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
        let lam = match smoothing {
            Smoothing::Fixed(l) if l > 0.0 => l,
            Smoothing::Fixed(_) => lam_of(dts) * 1e-10,
            Smoothing::Auto => {
                let (a, b) = (lam_of(0.3 * dts).ln(), lam_of(span).ln());
                let f = |x: f64| solve_at(x.exp()).map(|r| r.0).unwrap_or(f64::INFINITY);
                let grid = 25;
                let xs: Vec<f64> = (0..grid).map(|i| a + (b - a) * i as f64 / (grid - 1) as f64).collect();
                let vals: Vec<f64> = xs.iter().map(|&x| f(x)).collect();
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
                cand.iter().min_by(|p, q| p.0.total_cmp(&q.0)).map(|p| p.1.exp()).unwrap_or(1.0)
            }
        };
        let (score, tr, cs) = solve_at(lam)?;
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
                residuals: res,
                robust_weights: rw,
                lambda: if smoothing == Smoothing::Fixed(0.0) { 0.0 } else { lam },
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
                    robust.tuning() * (1.4826 * a[mid]).max(1e-300)
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
