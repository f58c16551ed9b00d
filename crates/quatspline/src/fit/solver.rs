//! The solver: validation of the options, then Gauss–Newton / Levenberg–Marquardt steps with
//! λ chosen by GCV, continuation to a large fixed λ, IRLS for robust losses and Bregman
//! iteration for interpolation (see the module doc of [`super`]).

use super::assembly::{data_half, pen_half, penalty_nodes, residuals, Half, Lin};
use super::banded::Band;
use super::knots::{fit_layout, schoenberg_whitney};
use super::lambda::{dotv, gcv_at, lambda_cap, select_lambda};
use super::model::{Model, MAXK};
use super::start::{initial_controls_from, medoid_filter};
use super::types::{pen_name, validate, Data, FitOptions, FitResult, Progress, Robust, Smoothing};
use crate::error::{Error, Result, Short};
use crate::quadrature::gauss_legendre01;
use crate::quat::Quat;
use crate::vec3;

/// Step (radians) that ends a stage of the λ continuation of a fixed, large λ (see `solve`).
pub(super) const STAGE_TOL: f64 = 1e-3;

/// Fits a cumulative B-spline on SO(3) to orientations `quats` at `times`.
pub fn fit(
    times: &[f64],
    quats: &[Quat],
    weights: Option<&[f64]>,
    opts: &FitOptions,
    progress: Progress<'_>,
) -> Result<FitResult> {
    let m = opts.penalty.m();
    let min = m + 1;
    let data = validate(
        times,
        quats,
        weights,
        min,
        &format!(
            "for penalty={:?} (its minimum-penalty curves have {} parameters per axis)",
            pen_name(opts.penalty),
            m + 1
        ),
    )?;
    let k = opts.order.unwrap_or(opts.penalty.default_order());
    if !(m + 3..=MAXK).contains(&k) {
        return Err(Error::invalid(
            "order",
            format!("expected {} ≤ order ≤ {MAXK} for this penalty, got {k}", m + 3),
        ));
    }
    if let Smoothing::Fixed(l) = opts.smoothing {
        if !(l.is_finite() && l >= 0.0) {
            return Err(Error::invalid(
                "smoothing",
                format!("expected \"auto\" or a finite λ ≥ 0, got {}", Short(l)),
            ));
        }
    }
    if let Some(c) = opts.robust_scale {
        if opts.robust == Robust::None {
            return Err(Error::invalid(
                "robust_scale",
                "only with a robust loss (robust='huber' or 'cauchy')".to_string(),
            ));
        }
        if !(c.is_finite() && c > 0.0) {
            return Err(Error::invalid(
                "robust_scale",
                format!("expected a finite positive angle (radians), got {}", Short(c)),
            ));
        }
    }
    if opts.max_iter == 0 || opts.max_iter > 100_000 {
        return Err(Error::invalid("max_iter", format!("expected 1 … 100000, got {}", opts.max_iter)));
    }
    if !(opts.tol.is_finite() && opts.tol > 0.0) {
        return Err(Error::invalid(
            "tol",
            format!("expected a finite positive tolerance, got {}", Short(opts.tol)),
        ));
    }
    let lay = fit_layout(&opts.knots, &data.t, k)?;
    let segs = lay.segs;
    let used = data.w.iter().filter(|w| **w > 0.0).count();
    if opts.smoothing == Smoothing::Fixed(0.0) && segs + k - 1 < used {
        return Err(Error::invalid(
            "smoothing",
            format!(
                "smoothing=0 interpolates every sample and needs at least as many control points as samples: \
                 {} control points for {used} samples (use denser knots)",
                segs + k - 1
            ),
        ));
    }
    if opts.smoothing == Smoothing::Fixed(0.0) {
        schoenberg_whitney(&data, &lay)?;
    }
    let init = if opts.smoothing == Smoothing::Fixed(0.0) {
        initial_controls_from(&data, &data.y, &lay)
    } else {
        initial_controls_from(&data, &medoid_filter(&data), &lay)
    };
    let model = Model::with_layout(init, lay);
    solve(model, &data, opts, progress)
}

pub(super) fn solve(
    mut model: Model,
    data: &Data,
    opts: &FitOptions,
    progress: Progress<'_>,
) -> Result<FitResult> {
    let pen = opts.penalty;
    let m = pen.m();
    let k = model.order;
    let nodes = gauss_legendre01(penalty_nodes(k, m, opts.smoothing == Smoothing::Fixed(0.0)));
    let n = data.t.len();
    let span = data.t[n - 1] - data.t[0];
    let rho = n as f64 / span;
    let lam_of = |h: f64| rho * h.powi(2 * m as i32 + 2);
    let dts = span / (n - 1) as f64;
    let interpolate = opts.smoothing == Smoothing::Fixed(0.0);
    // λ for the inner problems of interpolation: bandwidth about one sample spacing.
    let mut lam = match opts.smoothing {
        Smoothing::Fixed(0.0) => lam_of(dts) * 1e-6,
        Smoothing::Fixed(l) => l,
        Smoothing::Auto => f64::NAN,
    };
    let auto = opts.smoothing == Smoothing::Auto;
    // A fixed λ above the bandwidth of 10 sample spacings is reached by continuation: start
    // there, multiply by 100 whenever the step falls below `STAGE_TOL`. One Gauss–Newton step
    // from the curve through the samples straight to a stiff curve lands in whichever local
    // minimum its linearisation points at (measured: λ = 1e10 on 8 s of motion reached a
    // constant-velocity rotation with 47 % more cost than the one λ = 1e9 found).
    let mut lam_target = lam;
    let mut lam_requested = None;
    if !auto && !interpolate {
        lam = lam.min(lam_of(10.0 * dts));
    }
    let mut lam_frozen = !auto;
    // Whether the grid search for λ has run (auto).
    let mut searched = false;
    // The last change of ln λ between linearisations (after the search).
    let mut lam_move = 0.0f64;
    let mut offs = vec![[0.0; 3]; n];
    let mut w = data.w.clone();
    let mut robust_on = false;
    let mut c_robust = f64::INFINITY;
    let mut step = f64::INFINITY;
    let mut it = 0usize;
    let mut mu = 0.0f64;
    let mut bregman = 0usize;
    // The two halves of the linearisation at `model`, kept from the accepted trial step (the
    // trial's cost comes from its linearisation, so an accepted step is linearised once). The
    // data half is dropped whenever the weights or offsets change; band storage is recycled.
    let mut pen_cache: Option<Half> = None;
    let mut data_cache: Option<Half> = None;
    let mut spare: Vec<Band> = Vec::new();
    let mut hbuf = Band::zeros(0, 0);
    // The halves at the model before a final step below the tolerance (not relinearised).
    let mut near_halves: Option<(Half, Half)> = None;
    // The storage of the last replaced or rejected model, for the next trial.
    let mut spare_model: Option<Model> = None;
    loop {
        it += 1;
        if it > opts.max_iter {
            return Err(Error::NotConverged { what: "fit", iterations: opts.max_iter, step, tol: opts.tol });
        }
        if let Some((dh, ph)) = near_halves.take() {
            // The loop went on after a step below the tolerance: linearise afresh.
            spare.push(dh.band);
            spare.push(ph.band);
        }
        if robust_on {
            let (_, ang) = residuals(&model, data, &offs);
            for s in 0..n {
                w[s] = data.w[s] * opts.robust.weight(ang[s], c_robust);
            }
            if let Some(h) = data_cache.take() {
                spare.push(h.band);
            }
        }
        let ph = match pen_cache.take() {
            Some(h) => h,
            None => pen_half(&model, pen, &nodes, spare.pop().unwrap_or(Band::zeros(0, 0))),
        };
        let dh = match data_cache.take() {
            Some(h) => h,
            None => data_half(&model, data, &w, &offs, spare.pop().unwrap_or(Band::zeros(0, 0))),
        };
        let mut lin = Lin::new(dh, ph);
        // The largest λ double precision resolves here (the curve and the weights move it a
        // little): a fixed λ beyond it is fitted at it, and the result says so.
        let lam_max = lambda_cap(&lin.g, &lin.p);
        if !auto && !interpolate && lam_target > lam_max {
            lam_requested.get_or_insert(lam_target);
            lam_target = lam_max;
            lam = lam.min(lam_target);
        }
        let mut lam_changed = false;
        if !lam_frozen {
            let hi = lam_of(span).min(lam_max);
            let lo = lam_of(0.3 * dts).min(hi / 1e6);
            if lam.is_nan() {
                // The first linearisation is at the initial curve through the noisy samples,
                // whose penalty matrix carries the noise's ω: its GCV minimum is no guide
                // (measured: 6 units of ln λ below the final one). The first step smooths with
                // the bandwidth of 10 sample spacings; the search starts at the next one.
                lam = lam_of(10.0 * dts).clamp(lo, hi);
                lam_changed = true;
            } else {
                let prev = if searched { Some(lam) } else { None };
                if !searched {
                    // The grid holds one H per thread: free what the search does not use.
                    hbuf = Band::zeros(0, 0);
                    spare_model = None;
                }
                let (mut l_new, _) = select_lambda(&lin, lo, hi, 13, prev, &mut hbuf)?;
                if searched {
                    // A move back against the last one is at most half as long: where the
                    // GCV minima of two curves point at each other (two basins of GCV), λ
                    // alternated between them for ever (measured: 4.9 ↔ 92 on random samples);
                    // halving brackets the λ where the choice turns.
                    let mut dl = (l_new / lam).ln();
                    if dl * lam_move < 0.0 {
                        dl = dl.signum() * dl.abs().min(0.5 * lam_move.abs());
                        l_new = lam * dl.exp();
                    }
                    lam_move = dl;
                }
                lam_changed = !searched || (l_new / lam).ln().abs() > 0.01;
                if searched && !lam_changed {
                    lam_frozen = true;
                }
                searched = true;
                lam = l_new;
            }
        }
        let c0 = lin.rwr + lam * lin.pcp;
        // Gauss–Newton step; Levenberg–Marquardt damping when the cost does not decrease.
        let mut accepted = None;
        let mut near = false;
        for _ in 0..30 {
            lin.g.axpy_into(lam, &lin.p, &mut hbuf);
            if mu > 0.0 {
                let diag = hbuf.diag();
                let dmax = diag.iter().cloned().fold(0.0, f64::max);
                for (i, d) in diag.iter().enumerate() {
                    let idx = hbuf.idx(i, i);
                    hbuf.a[idx] += mu * d.max(1e-12 * dmax);
                }
            }
            if hbuf.cholesky_in_place().is_err() {
                mu = if mu == 0.0 { 1e-6 } else { mu * 10.0 };
                continue;
            }
            let rhs: Vec<f64> = lin.gd.iter().zip(&lin.gp).map(|(a, b)| -(a + lam * b)).collect();
            let d = hbuf.solve(&rhs);
            let trial = model.retracted(&d, spare_model.take());
            let smax = (0..d.len() / 3)
                .map(|i| {
                    (d[3 * i] * d[3 * i] + d[3 * i + 1] * d[3 * i + 1] + d[3 * i + 2] * d[3 * i + 2]).sqrt()
                })
                .fold(0.0, f64::max);
            if smax < opts.tol {
                // A step below the tolerance is accepted whatever its cost, so the trial is not
                // linearised here: the halves at `model` (within `tol` of the trial) are kept
                // for the final score and edf, and dropped if the loop goes on.
                accepted = Some((trial, smax));
                near = true;
                mu = if mu > 0.0 { mu / 10.0 } else { 0.0 };
                if mu < 1e-9 {
                    mu = 0.0;
                }
                break;
            }
            // The trial's cost from its linearisation (kept if the step is accepted), in the
            // storage of G and P (three bands at most are alive: H, and G and P or the trial's).
            let (gs, ps) = (
                std::mem::replace(&mut lin.g, Band::zeros(0, 0)),
                std::mem::replace(&mut lin.p, Band::zeros(0, 0)),
            );
            let tp = pen_half(&trial, pen, &nodes, ps);
            let td = data_half(&trial, data, &w, &offs, gs);
            let c1 = td.sum + lam * tp.sum;
            if c1 <= c0 * (1.0 + 1e-12) + 1e-300 {
                let (mut trial, mut smax, mut tp, mut td) = (trial, smax, tp, td);
                // Gauss–Newton converges only linearly where the residuals are large (far
                // samples, fast motion under a small λ): the neglected curvature of the model
                // makes its steps overshoot or fall short along the step. The cost along the
                // step is a parabola through c0 (slope 2gᵀd) and c1; a minimum well off α = 1
                // is tried and kept when it is lower (measured on 234 random 30-sample fits:
                // 22 ran out of 100 iterations, 248 at most; with this, 81 at most).
                let slope = -2.0 * dotv(&d, &rhs);
                let curv = c1 - c0 - slope;
                if slope < 0.0 && curv > 0.0 {
                    let alpha = -slope / (2.0 * curv);
                    if !(0.8..=1.25).contains(&alpha) && alpha.is_finite() {
                        let da: Vec<f64> = d.iter().map(|v| v * alpha).collect();
                        let t2 = model.retracted(&da, None);
                        let tp2 = pen_half(&t2, pen, &nodes, Band::zeros(0, 0));
                        let td2 = data_half(&t2, data, &w, &offs, Band::zeros(0, 0));
                        if td2.sum + lam * tp2.sum < c1 {
                            (trial, smax, tp, td) = (t2, smax * alpha, tp2, td2);
                        }
                    }
                }
                accepted = Some((trial, smax));
                pen_cache = Some(tp);
                data_cache = Some(td);
                mu = if mu > 0.0 { mu / 10.0 } else { 0.0 };
                if mu < 1e-9 {
                    mu = 0.0;
                }
                break;
            }
            // Rejected (rare): linearise at `model` again for the damped retry.
            spare_model = Some(trial);
            let ph = pen_half(&model, pen, &nodes, tp.band);
            lin = Lin::new(data_half(&model, data, &w, &offs, td.band), ph);
            mu = if mu == 0.0 { 1e-4 } else { mu * 10.0 };
        }
        if near {
            // Keep the halves at the previous model (see above).
            near_halves = Some(lin.into_halves());
        } else {
            drop(lin);
        }
        let Some((trial, smax)) = accepted else {
            return Err(Error::NotConverged {
                what: "fit (no descent step found)",
                iterations: it,
                step,
                tol: opts.tol,
            });
        };
        spare_model = Some(std::mem::replace(&mut model, trial));
        step = smax;
        if !progress("fit", it, step) {
            return Err(Error::invalid("progress", "fit cancelled by the progress callback"));
        }
        // A robust fit starts reweighting once the non-robust pilot's step is below √tol: its
        // scale needs the residuals, not their last digits, and a pilot pulled by far glitches
        // converges slowly (the robust fit itself then converges to `tol`).
        if lam < lam_target && step <= STAGE_TOL {
            lam = (lam * 100.0).min(lam_target);
            continue;
        }
        let pilot_done = opts.robust != Robust::None
            && !robust_on
            && !interpolate
            && step <= opts.tol.sqrt().max(opts.tol);
        // A step below the tolerance at the λ that GCV chose at this linearisation is a fixed
        // point of the curve and λ together, whatever λ moved: the curve no longer depends on
        // it (samples at rest, noise-free motion: the residuals vanish for every λ and GCV is
        // flat, so λ wandered while every step was 0).
        if step <= opts.tol && searched && !lam_frozen {
            lam_frozen = true;
            lam_changed = false;
        }
        if (step > opts.tol && !pilot_done) || lam_changed {
            continue;
        }
        // Converged at this λ, weights and offsets (or the robust fit's pilot, above).
        if !lam_frozen {
            continue;
        }
        if interpolate {
            let (rv, ang) = residuals(&model, data, &offs);
            // zero-weight samples are not data: nothing interpolates them
            let worst =
                ang.iter().zip(&data.w).filter(|(_, w)| **w > 0.0).map(|(a, _)| *a).fold(0.0, f64::max);
            if worst <= 1e-11 {
                break;
            }
            bregman += 1;
            if bregman > 200 {
                return Err(Error::NotConverged {
                    what: "fit (interpolation)",
                    iterations: it,
                    step: worst,
                    tol: 1e-11,
                });
            }
            for s in 0..n {
                // rv = r − e, so r = rv + e; Bregman update e ← e − r.
                let r = vec3::add(rv[s], offs[s]);
                offs[s] = vec3::sub(offs[s], r);
            }
            if let Some(h) = data_cache.take() {
                spare.push(h.band);
            }
            continue;
        }
        if opts.robust != Robust::None && !robust_on {
            let (_, ang) = residuals(&model, data, &offs);
            c_robust = match opts.robust_scale {
                Some(c) => c,
                None => {
                    let mut a: Vec<f64> =
                        ang.iter().zip(&data.w).filter(|(_, w)| **w > 0.0).map(|(a, _)| *a).collect();
                    let mid = a.len() / 2;
                    a.select_nth_unstable_by(mid, |x, y| x.total_cmp(y));
                    let sigma = 1.4826 * a[mid];
                    opts.robust.tuning() * sigma.max(1e-12)
                }
            };
            robust_on = true;
            if auto {
                // λ is chosen afresh under the robust weights: a new search, not a reversal
                lam_frozen = false;
                lam_move = 0.0;
            }
            continue;
        }
        // IRLS (robust_on): converged when the weights no longer move the curve (step ≤ tol).
        break;
    }
    drop(spare_model);
    let (_, ang) = residuals(&model, data, &vec![[0.0; 3]; n]);
    // Score and edf at the solution (for fixed λ: the GCV of the fixed λ).
    let (score, edf) = if !interpolate {
        // The halves kept from the last accepted step are at `model` with the final weights,
        // or, after a step below the tolerance, at the model one step (≤ tol) before; the
        // score's linearised RSS includes that step.
        if let Some((dh, ph)) = near_halves.take() {
            pen_cache = Some(ph);
            data_cache = Some(dh);
        }
        let ph = match pen_cache.take() {
            Some(h) => h,
            None => pen_half(&model, pen, &nodes, spare.pop().unwrap_or(Band::zeros(0, 0))),
        };
        let dh = match data_cache.take() {
            Some(h) => h,
            None => data_half(&model, data, &w, &offs, spare.pop().unwrap_or(Band::zeros(0, 0))),
        };
        drop(spare);
        gcv_at(&Lin::new(dh, ph), lam, &mut hbuf)?
    } else {
        lam = 0.0;
        (f64::INFINITY, 3.0 * data.w.iter().filter(|w| **w > 0.0).count() as f64)
    };
    let robust_weights =
        (0..n).map(|s| if robust_on { opts.robust.weight(ang[s], c_robust) } else { 1.0 }).collect();
    Ok(FitResult {
        ctrl: model.ctrl.clone(),
        dt: model.dt,
        t0: model.t0,
        breaks: model.layout.breaks.as_ref().map(|b| b.to_vec()),
        order: k,
        residuals: ang,
        robust_weights,
        robust_scale: c_robust,
        lambda: lam,
        lambda_requested: lam_requested,
        edf,
        score,
        iterations: it,
        final_step: step,
        converged: true,
    })
}
