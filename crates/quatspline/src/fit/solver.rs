//! The solver: validation of the options, then Gauss–Newton / Levenberg–Marquardt steps with
//! λ chosen by GCV, continuation to a large fixed λ, IRLS for robust losses and Bregman
//! iteration for interpolation (see the module doc of [`super`]).

use super::assembly::{data_half, pen_half, penalty_nodes, residuals, sums_only, Half, Lin};
use super::banded::Band;
use super::knots::{fit_layout, schoenberg_whitney};
use super::lambda::{dotv, gcv_final, lambda_cap, select_lambda};
use super::model::{Model, MAXK};
use super::start::{
    consensus_mask, initial_controls_from, medoid_filter, medoid_filter_half, ROBUST_MEDOID_HALF,
};
use super::types::{pen_name, validate, Data, FitOptions, FitResult, Progress, Robust, Smoothing};
use crate::error::{Error, Result, Short};
use crate::quadrature::gauss_legendre01;
use crate::quat::Quat;
use crate::vec3;
use crate::vec3::Vec3;

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
    // The start: a curve through a running medoid of the samples of positive weight (a
    // zero-weight sample is no anchor: a run of them would drag the start off the data).
    let kept = |d: &Data| {
        let keep: Vec<usize> = (0..d.w.len()).filter(|&i| d.w[i] > 0.0).collect();
        Data {
            t: keep.iter().map(|&i| d.t[i]).collect(),
            y: keep.iter().map(|&i| d.y[i]).collect(),
            w: keep.iter().map(|&i| d.w[i]).collect(),
        }
    };
    let (init, data) = if opts.smoothing == Smoothing::Fixed(0.0) {
        (initial_controls_from(&data, &data.y, &lay), data)
    } else if opts.robust != Robust::None {
        // The high-breakdown start of a robust fit (see `Solver::start_pilot`): the runs that
        // the consensus rejects are dropped (weight 0: a redescending loss does not hold a
        // curve where a long run of glitches is the only data, since even their tiny weights
        // outweigh the penalty there; Huber's pull c follows them), then the running medoid
        // of what is left; the curve slerps across each dropped run.
        let mask = consensus_mask(&data)?;
        let mut data = data;
        for (w, k) in data.w.iter_mut().zip(&mask) {
            if !k {
                *w = 0.0;
            }
        }
        let sum: f64 = data.w.iter().sum();
        let scale = data.w.len() as f64 / sum;
        data.w.iter_mut().for_each(|w| *w *= scale);
        let k = kept(&data);
        (initial_controls_from(&k, &medoid_filter_half(&k, ROBUST_MEDOID_HALF), &lay), data)
    } else {
        let k = kept(&data);
        (initial_controls_from(&k, &medoid_filter(&k), &lay), data)
    };
    let model = Model::with_layout(init, lay);
    solve(model, &data, opts, progress)
}

/// The state of one fit between Gauss–Newton iterations: the curve, λ and its search, the
/// weights and offsets of the outer loops (IRLS, Bregman), and the storage kept across
/// iterations. [`solve`] runs its stages in order; each stage is one method.
struct Solver<'a> {
    data: &'a Data,
    opts: &'a FitOptions,
    model: Model,
    nodes: Vec<(f64, f64)>,
    n: usize,
    span: f64,
    /// Samples per time unit (λ = ρ h^{2m+2} for a bandwidth h).
    rho: f64,
    /// The mean sample spacing.
    dts: f64,
    interpolate: bool,
    auto: bool,
    // λ and its search
    lam: f64,
    /// The fixed λ asked for (continuation climbs to it; capped at what double resolves).
    lam_target: f64,
    lam_requested: Option<f64>,
    lam_frozen: bool,
    /// Whether the grid search for λ has run (auto).
    searched: bool,
    /// The last change of ln λ between linearisations (after the search).
    lam_move: f64,
    // the outer loops: Bregman offsets, IRLS weights
    offs: Vec<Vec3>,
    w: Vec<f64>,
    robust_on: bool,
    /// The loss of the current IRLS phase: Cauchy in the pilot, then the one asked for.
    loss: Robust,
    /// Robust pilot phases still to run (see [`Solver::start_pilot`]); 0 in the final phase.
    pilot: usize,
    c_robust: f64,
    bregman: usize,
    // iterations
    step: f64,
    it: usize,
    /// Levenberg–Marquardt damping.
    mu: f64,
    // The two halves of the linearisation at `model`, kept from the accepted trial step (the
    // trial's cost comes from its linearisation, so an accepted step is linearised once). The
    // data half is dropped whenever the weights or offsets change; band storage is recycled.
    pen_cache: Option<Half>,
    data_cache: Option<Half>,
    spare: Vec<Band>,
    /// The penalty half at the model before a final step below the tolerance (not
    /// relinearised; that model is `spare_model`, where `finish` assembles the data half).
    near_pen: Option<Half>,
    /// The storage of the last replaced or rejected model, for the next trial.
    spare_model: Option<Model>,
    /// Per-knot-interval weights of the penalty (locally adaptive smoothing, `adaptive.rs`).
    pen_w: Option<Vec<f64>>,
}

/// What the loop does after a step ([`Solver::next_stage`]).
#[derive(PartialEq)]
enum Next {
    Iterate,
    Done,
}

impl<'a> Solver<'a> {
    fn new(model: Model, data: &'a Data, opts: &'a FitOptions) -> Self {
        let m = opts.penalty.m();
        let k = model.order;
        let interpolate = opts.smoothing == Smoothing::Fixed(0.0);
        let nodes = gauss_legendre01(penalty_nodes(k, m, interpolate));
        let n = data.t.len();
        let span = data.t[n - 1] - data.t[0];
        let rho = n as f64 / span;
        let dts = span / (n - 1) as f64;
        let auto = opts.smoothing == Smoothing::Auto;
        let mut s = Solver {
            data,
            opts,
            model,
            nodes,
            n,
            span,
            rho,
            dts,
            interpolate,
            auto,
            lam: f64::NAN,
            lam_target: f64::NAN,
            lam_requested: None,
            lam_frozen: !auto,
            searched: false,
            lam_move: 0.0,
            offs: vec![[0.0; 3]; n],
            w: data.w.clone(),
            robust_on: false,
            loss: Robust::None,
            pilot: 0,
            c_robust: f64::INFINITY,
            bregman: 0,
            step: f64::INFINITY,
            it: 0,
            mu: 0.0,
            pen_cache: None,
            data_cache: None,
            spare: Vec::new(),
            near_pen: None,
            spare_model: None,
            pen_w: None,
        };
        // λ for the inner problems of interpolation: bandwidth about one sample spacing.
        s.lam = match opts.smoothing {
            Smoothing::Fixed(0.0) => s.lam_of(dts) * 1e-6,
            Smoothing::Fixed(l) => l,
            Smoothing::Auto => f64::NAN,
        };
        // A fixed λ above the bandwidth of 10 sample spacings is reached by continuation: start
        // there, multiply by 100 whenever the step falls below `STAGE_TOL`. One Gauss–Newton
        // step from the curve through the samples straight to a stiff curve lands in whichever
        // local minimum its linearisation points at (measured: λ = 1e10 on 8 s of motion
        // reached a constant-velocity rotation with 47 % more cost than the one λ = 1e9 found).
        s.lam_target = s.lam;
        if !auto && !interpolate {
            s.lam = s.lam.min(s.lam_of(10.0 * dts));
        }
        s
    }

    /// A robust fit is an MM-estimate (Yohai 1987): (1) the high-breakdown pilot — from the
    /// curve through a running medoid of ±[`ROBUST_MEDOID_HALF`] samples, the Cauchy loss
    /// (redescending: a sample at 170° has weight ≈ (c/θ)², nothing) with its scale from the
    /// start's residuals ([`robust_sigma`]), then once more with the scale σ̂ of its own
    /// residuals (the start's are those of a curve through medoids, wider than the noise);
    /// (2) the loss asked for with c = [`Robust::tuning_r3`] · σ̂ (or `robust_scale`), σ̂
    /// from the pilot's residuals, started from the pilot. Each pilot phase ends at a step of
    /// √tol, the last phase at tol. Least squares is no pilot: with 20 % of far glitches it
    /// lies 30°–50° off and its median residual is no scale.
    fn start_pilot(&mut self) -> Result<()> {
        if self.opts.robust == Robust::None || self.interpolate {
            return Ok(());
        }
        let (_, ang) = residuals(&self.model, self.data, &self.offs);
        let sigma = check_breakdown(robust_sigma(&ang, &self.data.w))?;
        self.loss = Robust::Cauchy;
        self.c_robust = Robust::Cauchy.tuning_r3() * sigma.max(self.sigma_floor());
        self.robust_on = true;
        self.pilot = 2;
        Ok(())
    }

    /// The least robust scale σ̂ (radians): √tol (1e-5 rad = 2″ at the default tol, below the
    /// noise of any orientation tracker but star trackers), at least √ε. Each pilot phase ends
    /// at a step of √tol, so its residuals are resolved to about √tol and a smaller scale is
    /// none. On noise-free samples the pilot's σ̂ is that resolution or rounding (down to 0):
    /// a scale there divided by zero, or gave every good sample a residual of many c, so the
    /// M-step was an L1 fit crawling from the pilot's 1e-6 rad towards the 1e-16 rad the plain
    /// fit reaches (measured with a floor of √ε: 100–750 iterations on a noise-free motion
    /// with 5 % of exact half turns, one draw of 12 past 1000, one 19° off). With the floor the
    /// good samples keep weight 1, the far ones ≈ c/π (Huber) or (c/π)² (Cauchy), and the
    /// M-step converges as the plain fit does.
    fn sigma_floor(&self) -> f64 {
        self.opts.tol.sqrt().max(f64::EPSILON.sqrt())
    }

    /// λ of the equivalent kernel bandwidth h.
    fn lam_of(&self, h: f64) -> f64 {
        self.rho * h.powi(2 * self.opts.penalty.m() as i32 + 2)
    }

    /// Counts the iteration; refuses to go past `max_iter`.
    fn count_iteration(&mut self) -> Result<()> {
        self.it += 1;
        if self.it > self.opts.max_iter {
            return Err(Error::NotConverged {
                what: "fit",
                iterations: self.opts.max_iter,
                step: self.step,
                tol: self.opts.tol,
            });
        }
        Ok(())
    }

    /// The penalty half at `model` into recycled storage.
    fn pen_half_at_model(&mut self) -> Half {
        let band = self.spare.pop().unwrap_or(Band::zeros(0, 0));
        pen_half(&self.model, self.opts.penalty, &self.nodes, band, self.pen_w.as_deref())
    }

    /// The data half at `model` (current weights and offsets) into recycled storage.
    fn data_half_at_model(&mut self) -> Half {
        let band = self.spare.pop().unwrap_or(Band::zeros(0, 0));
        data_half(&self.model, self.data, &self.w, &self.offs, band)
    }

    /// The Gauss–Newton pieces at `model`: the halves kept from the accepted step, else
    /// assembled afresh (after reweighting, under a robust loss).
    fn linearise(&mut self) -> Lin {
        if let Some(ph) = self.near_pen.take() {
            // The loop went on after a step below the tolerance: linearise afresh.
            self.spare.push(ph.band);
        }
        if self.robust_on {
            let (_, ang) = residuals(&self.model, self.data, &self.offs);
            for s in 0..self.n {
                self.w[s] = self.data.w[s] * self.loss.weight(ang[s], self.c_robust);
            }
            if let Some(h) = self.data_cache.take() {
                self.spare.push(h.band);
            }
        }
        let ph = match self.pen_cache.take() {
            Some(h) => h,
            None => self.pen_half_at_model(),
        };
        let dh = match self.data_cache.take() {
            Some(h) => h,
            None => self.data_half_at_model(),
        };
        Lin::new(dh, ph)
    }

    /// The largest λ double precision resolves at this linearisation (the curve and the
    /// weights move it a little): a fixed λ beyond it is fitted at it, and the result says so.
    fn cap_lambda(&mut self, lin: &Lin) -> f64 {
        let lam_max = lambda_cap(&lin.g, &lin.p);
        if !self.auto && !self.interpolate && self.lam_target > lam_max {
            self.lam_requested.get_or_insert(self.lam_target);
            self.lam_target = lam_max;
            self.lam = self.lam.min(self.lam_target);
        }
        lam_max
    }

    /// λ by GCV at this linearisation (auto, until frozen); whether λ changed.
    fn choose_lambda(&mut self, lin: &Lin, lam_max: f64) -> Result<bool> {
        if self.lam_frozen {
            return Ok(false);
        }
        let hi = self.lam_of(self.span).min(lam_max);
        let lo = self.lam_of(0.3 * self.dts).min(hi / 1e6);
        if self.lam.is_nan() {
            // The first linearisation is at the initial curve through the noisy samples,
            // whose penalty matrix carries the noise's ω: its GCV minimum is no guide
            // (measured: 6 units of ln λ below the final one). The first step smooths with
            // the bandwidth of 10 sample spacings; the search starts at the next one.
            self.lam = self.lam_of(10.0 * self.dts).clamp(lo, hi);
            return Ok(true);
        }
        let prev = if self.searched { Some(self.lam) } else { None };
        if !self.searched {
            // Free what the first search does not use (the storage of the next trial).
            self.spare_model = None;
        }
        // H for the search, alive only during it (G, P and H: three bands).
        let mut h = Band::zeros(0, 0);
        let (mut l_new, _) = select_lambda(lin, lo, hi, 13, prev, &mut h)?;
        drop(h);
        if self.searched {
            // A move back against the last one is at most half as long: where the GCV minima
            // of two curves point at each other (two basins of GCV), λ alternated between them
            // for ever (measured: 4.9 ↔ 92 on random samples); halving brackets the λ where
            // the choice turns.
            let mut dl = (l_new / self.lam).ln();
            if dl * self.lam_move < 0.0 {
                dl = dl.signum() * dl.abs().min(0.5 * self.lam_move.abs());
                l_new = self.lam * dl.exp();
            }
            self.lam_move = dl;
        }
        let lam_changed = !self.searched || (l_new / self.lam).ln().abs() > 0.01;
        if self.searched && !lam_changed {
            self.lam_frozen = true;
        }
        self.searched = true;
        self.lam = l_new;
        Ok(lam_changed)
    }

    /// Lowers the Levenberg–Marquardt damping after an accepted step.
    fn relax_damping(&mut self) {
        self.mu = if self.mu > 0.0 { self.mu / 10.0 } else { 0.0 };
        if self.mu < 1e-9 {
            self.mu = 0.0;
        }
    }

    /// One accepted step from `model`: Gauss–Newton, with Levenberg–Marquardt damping when the
    /// cost does not decrease, and a line search along the step where Gauss–Newton over- or
    /// undershoots. Replaces `model` and sets `step`.
    fn descend(&mut self, mut lin: Lin) -> Result<()> {
        let (lam, pen, data) = (self.lam, self.opts.penalty, self.data);
        let c0 = lin.rwr + lam * lin.pcp;
        let mut accepted = None;
        let mut near = false;
        for _ in 0..30 {
            // H = G + λP in the storage of G (two bands are alive at any time: H, or G, and P;
            // then the trial's halves in the same two). G is assembled again where it is
            // needed after this (a failed factorisation, the final score after a step below
            // the tolerance): the assembly is deterministic, so the result is the same.
            let mut h = std::mem::replace(&mut lin.g, Band::zeros(0, 0));
            let factored = if self.mu > 0.0 {
                h.axpy_assign(lam, &lin.p);
                let diag = h.diag();
                let dmax = diag.iter().cloned().fold(0.0, f64::max);
                for (i, d) in diag.iter().enumerate() {
                    let idx = h.idx(i, i);
                    h.a[idx] += self.mu * d.max(1e-12 * dmax);
                }
                h.cholesky_in_place()
            } else {
                // H = G + λP formed row by row inside the factorisation (the same sums)
                h.cholesky_plus(lam, &lin.p)
            };
            if factored.is_err() {
                lin.g = data_half(&self.model, data, &self.w, &self.offs, h).band;
                self.mu = if self.mu == 0.0 { 1e-6 } else { self.mu * 10.0 };
                continue;
            }
            let rhs: Vec<f64> = lin.gd.iter().zip(&lin.gp).map(|(a, b)| -(a + lam * b)).collect();
            let d = h.solve(&rhs);
            let trial = self.model.retracted(&d, self.spare_model.take());
            let smax = (0..d.len() / 3)
                .map(|i| {
                    (d[3 * i] * d[3 * i] + d[3 * i + 1] * d[3 * i + 1] + d[3 * i + 2] * d[3 * i + 2]).sqrt()
                })
                .fold(0.0, f64::max);
            if smax < self.opts.tol {
                // A step below the tolerance is accepted whatever its cost, so the trial is not
                // linearised here: the halves at `model` (within `tol` of the trial) are kept
                // for the final score and edf (G assembled again there), and dropped if the
                // loop goes on.
                lin.g = h;
                accepted = Some((trial, smax));
                near = true;
                self.relax_damping();
                break;
            }
            // The trial's cost from its linearisation (kept if the step is accepted), in the
            // storage of H and P.
            let ps = std::mem::replace(&mut lin.p, Band::zeros(0, 0));
            let tp = pen_half(&trial, pen, &self.nodes, ps, self.pen_w.as_deref());
            let td = data_half(&trial, data, &self.w, &self.offs, h);
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
                        // The point at α by its cost alone (no matrices), in the trial's
                        // storage; linearised only when kept (else the trial is rebuilt:
                        // the retraction is deterministic).
                        let da: Vec<f64> = d.iter().map(|v| v * alpha).collect();
                        let t2 = self.model.retracted(&da, Some(trial));
                        let c2 = data_half(&t2, data, &self.w, &self.offs, sums_only()).sum
                            + lam * pen_half(&t2, pen, &self.nodes, sums_only(), self.pen_w.as_deref()).sum;
                        if c2 < c1 {
                            tp = pen_half(&t2, pen, &self.nodes, tp.band, self.pen_w.as_deref());
                            td = data_half(&t2, data, &self.w, &self.offs, td.band);
                            (trial, smax) = (t2, smax * alpha);
                        } else {
                            trial = self.model.retracted(&d, Some(t2));
                        }
                    }
                }
                accepted = Some((trial, smax));
                self.pen_cache = Some(tp);
                self.data_cache = Some(td);
                self.relax_damping();
                break;
            }
            // Rejected (rare): linearise at `model` again for the damped retry.
            self.spare_model = Some(trial);
            let ph = pen_half(&self.model, pen, &self.nodes, tp.band, self.pen_w.as_deref());
            lin = Lin::new(data_half(&self.model, data, &self.w, &self.offs, td.band), ph);
            self.mu = if self.mu == 0.0 { 1e-4 } else { self.mu * 10.0 };
        }
        if near {
            // Keep the penalty half at the previous model (the data half's band holds the
            // factor of H: assembled again by `finish` if the fit ends here).
            let (dh, ph) = lin.into_halves();
            self.spare.push(dh.band);
            self.near_pen = Some(ph);
        } else {
            drop(lin);
        }
        let Some((trial, smax)) = accepted else {
            return Err(Error::NotConverged {
                what: "fit (no descent step found)",
                iterations: self.it,
                step: self.step,
                tol: self.opts.tol,
            });
        };
        self.spare_model = Some(std::mem::replace(&mut self.model, trial));
        self.step = smax;
        Ok(())
    }

    /// After a step: the next stage of the outer loops (continuation of a large fixed λ, the
    /// robust pilot, λ frozen, Bregman updates for interpolation, IRLS), or done.
    fn next_stage(&mut self, mut lam_changed: bool) -> Result<Next> {
        let opts = self.opts;
        // A robust fit's pilot ends once its step is below √tol: the scale needs its
        // residuals, not their last digits (the robust fit itself then converges to `tol`).
        if self.lam < self.lam_target && self.step <= STAGE_TOL {
            self.lam = (self.lam * 100.0).min(self.lam_target);
            return Ok(Next::Iterate);
        }
        let pilot_done = self.pilot > 0 && self.step <= opts.tol.sqrt().max(opts.tol);
        // A step below the tolerance at the λ that GCV chose at this linearisation is a fixed
        // point of the curve and λ together, whatever λ moved: the curve no longer depends on
        // it (samples at rest, noise-free motion: the residuals vanish for every λ and GCV is
        // flat, so λ wandered while every step was 0).
        if self.step <= opts.tol && self.searched && !self.lam_frozen {
            self.lam_frozen = true;
            lam_changed = false;
        }
        if (self.step > opts.tol && !pilot_done) || lam_changed {
            return Ok(Next::Iterate);
        }
        // Converged at this λ, weights and offsets (or the robust fit's pilot, above).
        if !self.lam_frozen {
            return Ok(Next::Iterate);
        }
        if self.interpolate {
            return self.bregman_update();
        }
        if self.pilot > 0 {
            self.next_robust_phase()?;
            return Ok(Next::Iterate);
        }
        // IRLS (robust_on): converged when the weights no longer move the curve (step ≤ tol).
        Ok(Next::Done)
    }

    /// Interpolation: done when every sample of positive weight is within 1e-11 rad, else one
    /// Bregman update of the offsets (e ← e − r).
    fn bregman_update(&mut self) -> Result<Next> {
        let (rv, ang) = residuals(&self.model, self.data, &self.offs);
        // zero-weight samples are not data: nothing interpolates them
        let worst =
            ang.iter().zip(&self.data.w).filter(|(_, w)| **w > 0.0).map(|(a, _)| *a).fold(0.0, f64::max);
        if worst <= 1e-11 {
            return Ok(Next::Done);
        }
        self.bregman += 1;
        if self.bregman > 200 {
            return Err(Error::NotConverged {
                what: "fit (interpolation)",
                iterations: self.it,
                step: worst,
                tol: 1e-11,
            });
        }
        for s in 0..self.n {
            // rv = r − e, so r = rv + e; Bregman update e ← e − r.
            let r = vec3::add(rv[s], self.offs[s]);
            self.offs[s] = vec3::sub(self.offs[s], r);
        }
        if let Some(h) = self.data_cache.take() {
            self.spare.push(h.band);
        }
        Ok(Next::Iterate)
    }

    /// The next phase of a robust fit after a converged pilot phase: the Cauchy pilot again,
    /// or the loss asked for; the scale from the residuals (or `robust_scale` in the last
    /// phase), λ searched afresh under the new weights (but see below).
    fn next_robust_phase(&mut self) -> Result<()> {
        let opts = self.opts;
        let (_, ang) = residuals(&self.model, self.data, &self.offs);
        let sigma = check_breakdown(robust_sigma(&ang, &self.data.w))?;
        self.pilot -= 1;
        self.loss = if self.pilot > 0 { Robust::Cauchy } else { opts.robust };
        self.c_robust = match opts.robust_scale {
            Some(c) if self.pilot == 0 => c,
            _ => self.loss.tuning_r3() * sigma.max(self.sigma_floor()),
        };
        if let Some(h) = self.data_cache.take() {
            self.spare.push(h.band);
        }
        if self.auto && self.loss == Robust::Cauchy {
            // λ is chosen afresh under the new weights: a new search, not a reversal. Not
            // under Huber's: a far sample keeps w·r² = c·|r| in the weighted RSS (at 170°
            // as much as a hundred noise residuals), so GCV reads the glitches as noise and
            // oversmooths (measured: 4× the clean fit's error at 20 % of far glitches); under
            // the redescending loss w·r² ≤ c², and Huber keeps the pilot's λ.
            self.lam_frozen = false;
            self.lam_move = 0.0;
        }
        Ok(())
    }

    /// The result: residuals, and the score and edf at the solution (for a fixed λ: the GCV of
    /// the fixed λ).
    fn finish(mut self) -> Result<FitResult> {
        let prev = self.spare_model.take();
        let n = self.n;
        let (_, ang) = residuals(&self.model, self.data, &vec![[0.0; 3]; n]);
        let (score, edf) = if !self.interpolate {
            // The halves kept from the last accepted step are at `model` with the final
            // weights, or, after a step below the tolerance, at the model one step (≤ tol)
            // before; the score's linearised RSS includes that step.
            if let Some(ph) = self.near_pen.take() {
                let band = self.spare.pop().unwrap_or(Band::zeros(0, 0));
                let m = prev.as_ref().expect("the model before the last step is kept");
                self.data_cache = Some(data_half(m, self.data, &self.w, &self.offs, band));
                self.pen_cache = Some(ph);
            }
            drop(prev);
            let ph = match self.pen_cache.take() {
                Some(h) => h,
                None => self.pen_half_at_model(),
            };
            let dh = match self.data_cache.take() {
                Some(h) => h,
                None => self.data_half_at_model(),
            };
            drop(std::mem::take(&mut self.spare));
            gcv_final(Lin::new(dh, ph), self.lam)?
        } else {
            self.lam = 0.0;
            (f64::INFINITY, 3.0 * self.data.w.iter().filter(|w| **w > 0.0).count() as f64)
        };
        let (robust_on, c_robust, robust) = (self.robust_on, self.c_robust, self.opts.robust);
        let robust_weights =
            (0..n).map(|s| if robust_on { robust.weight(ang[s], c_robust) } else { 1.0 }).collect();
        let model = &self.model;
        Ok(FitResult {
            ctrl: model.ctrl.clone(),
            dt: model.dt,
            t0: model.t0,
            breaks: model.layout.breaks.as_ref().map(|b| b.to_vec()),
            order: model.order,
            residuals: ang,
            robust_weights,
            robust_scale: c_robust,
            lambda: self.lam,
            lambda_requested: self.lam_requested,
            edf,
            score,
            iterations: self.it,
            final_step: self.step,
            converged: true,
            penalty_weights: self.pen_w.take(),
        })
    }
}

/// Solves the fit from the start curve `model`: one Gauss–Newton iteration per pass —
/// linearise, cap and choose λ, descend — then the outer loops' next stage.
pub(super) fn solve(
    model: Model,
    data: &Data,
    opts: &FitOptions,
    progress: Progress<'_>,
) -> Result<FitResult> {
    solve_weighted(model, data, opts, None, progress)
}

/// [`solve`] with per-knot-interval penalty weights `pen_w` (λ Σᵢ wᵢ ∫_{segment i} |p|² dt)
/// and, for λ = "auto", a first λ to search from (`start`, from a curve already fitted:
/// Brent's method around it from the first linearisation, no fixed first step).
pub(super) fn solve_weighted(
    model: Model,
    data: &Data,
    opts: &FitOptions,
    start: Option<(Vec<f64>, f64)>,
    progress: Progress<'_>,
) -> Result<FitResult> {
    let mut s = Solver::new(model, data, opts);
    if let Some((w, lam)) = start {
        s.pen_w = Some(w);
        if s.auto {
            s.lam = lam;
            s.searched = true;
        }
    }
    s.start_pilot()?;
    loop {
        s.count_iteration()?;
        let lin = s.linearise();
        let lam_max = s.cap_lambda(&lin);
        let lam_changed = s.choose_lambda(&lin, lam_max)?;
        s.descend(lin)?;
        if !progress("fit", s.it, s.step) {
            return Err(Error::invalid("progress", "fit cancelled by the progress callback"));
        }
        if s.next_stage(lam_changed)? == Next::Done {
            return s.finish();
        }
    }
}

/// The median of |r| over ℝ³ Gaussian residuals of per-axis σ (the χ distribution with 3
/// degrees of freedom): σ = median |r| / 1.5382.
const CHI3_MEDIAN: f64 = 1.538_172_254_455_052;
/// The 97.5 % point of that χ: √(χ²₃(0.975)) (a Gaussian residual lies beyond 3.0575 σ with
/// probability 2.5 %).
const CHI3_CUT: f64 = 3.057_515_920_562_99;
/// E[|r|² | |r| ≤ 3.0575] for σ = 1: the consistency factor of the truncated mean square.
const CHI3_TRUNC_M2: f64 = 2.781_696_058_476_687;

/// The per-axis noise σ of residual angles `ang` (samples of positive weight), robustly:
/// σ₀ = median |r| / 1.5382 (breakdown point 50 %, consistent at Gaussian noise), then three
/// reweighting steps — the mean square of the residuals within 3.0575 σₖ, made consistent:
/// σₖ₊₁² = mean(|r|² : |r| ≤ 3.0575 σₖ) / 2.7817 (as the reweighted MCD of Rousseeuw & van
/// Zomeren 1990). The median's bias under contamination — 14 % at 20 % of far glitches, 80 %
/// at 45 % — is gone, since the cut excludes them; the steps converge to the consistent fixed
/// point (from 80 % too large: 4 %, then 0.5 %, then < 0.1 %).
pub(super) fn robust_sigma(ang: &[f64], w: &[f64]) -> f64 {
    let mut a: Vec<f64> = ang.iter().zip(w).filter(|(_, w)| **w > 0.0).map(|(a, _)| *a).collect();
    if a.is_empty() {
        return 0.0;
    }
    let mid = a.len() / 2;
    a.select_nth_unstable_by(mid, |x, y| x.total_cmp(y));
    let mut sigma = a[mid] / CHI3_MEDIAN;
    for _ in 0..3 {
        let cut = CHI3_CUT * sigma;
        let (mut sum, mut count) = (0.0, 0usize);
        for &r in &a {
            if r <= cut {
                sum += r * r;
                count += 1;
            }
        }
        if count == 0 || sum == 0.0 {
            break;
        }
        sigma = (sum / count as f64 / CHI3_TRUNC_M2).sqrt();
    }
    sigma
}

/// `sigma`, unless the robust fit is beyond its breakdown point: when 3.0575 σ̂ ≥ π no rotation
/// is farther from the curve than noise would put it, so no sample can be told from an
/// outlier — more than half of the samples lie far from any smooth curve (σ̂ is the median's,
/// whose breakdown point is 50 %). An error, not a least-squares curve through the glitches.
fn check_breakdown(sigma: f64) -> Result<f64> {
    if CHI3_CUT * sigma >= std::f64::consts::PI {
        return Err(Error::invalid(
            "quats",
            format!(
                "more than half of the samples lie far from any smooth curve (robust noise scale \
                 {:.0}° per axis): beyond the robust fit's breakdown point (50 %)",
                sigma.to_degrees()
            ),
        ));
    }
    Ok(sigma)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::XorShift64;

    /// ∫₀^∞ f(s) χ₃(s) ds by composite Simpson on [0, 14] (χ₃'s density √(2/π) s² e^{−s²/2};
    /// its tail beyond 14 is below 1e-40).
    fn chi3_expect(f: impl Fn(f64) -> f64, hi: f64) -> f64 {
        let n = 200_000;
        let h = hi / n as f64;
        let pdf = |s: f64| (2.0 / std::f64::consts::PI).sqrt() * s * s * (-0.5 * s * s).exp();
        let g = |i: usize| {
            let s = i as f64 * h;
            f(s) * pdf(s)
        };
        let mut sum = g(0) + g(n);
        for i in 1..n {
            sum += if i % 2 == 1 { 4.0 } else { 2.0 } * g(i);
        }
        sum * h / 3.0
    }

    /// The scale's constants and the tuning constants from their definitions, by quadrature
    /// (independent of the values in the code): χ₃'s median and 97.5 % point, the truncated
    /// mean square, and the Gaussian efficiency of Huber and Cauchy for ℝ³ residuals,
    /// A²/B with A = E[u + s u′/3], B = E[u² s²]/3: 95 % for both tuning constants.
    #[test]
    fn robust_constants_are_derived_from_their_definitions() {
        let cdf = |x: f64| chi3_expect(|_| 1.0, x);
        assert!((cdf(CHI3_MEDIAN) - 0.5).abs() < 1e-10, "{}", cdf(CHI3_MEDIAN));
        assert!((cdf(CHI3_CUT) - 0.975).abs() < 1e-10, "{}", cdf(CHI3_CUT));
        let m2 = chi3_expect(|s| s * s, CHI3_CUT) / 0.975;
        assert!((m2 - CHI3_TRUNC_M2).abs() < 1e-9, "{m2}");
        let eff = |u: &dyn Fn(f64) -> f64, su: &dyn Fn(f64) -> f64| {
            let a = chi3_expect(|s| u(s) + su(s) / 3.0, 14.0);
            let b = chi3_expect(|s| u(s) * u(s) * s * s, 14.0) / 3.0;
            a * a / b
        };
        let c = Robust::Huber.tuning_r3();
        let e = eff(&|s| if s <= c { 1.0 } else { c / s }, &|s| if s <= c { 0.0 } else { -c / s });
        assert!((e - 0.95).abs() < 2e-4, "Huber: {e}");
        let c = Robust::Cauchy.tuning_r3();
        let e = eff(&|s| 1.0 / (1.0 + (s / c).powi(2)), &|s| {
            let x = (s / c).powi(2);
            -2.0 * x / (1.0 + x).powi(2)
        });
        assert!((e - 0.95).abs() < 2e-4, "Cauchy: {e}");
    }

    fn gaussian_angles(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut rng = XorShift64::new(seed);
        let mut normal = || {
            let (u, v) = (rng.uniform().max(1e-300), rng.uniform());
            (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
        };
        (0..n).map(|_| sigma * (normal().powi(2) + normal().powi(2) + normal().powi(2)).sqrt()).collect()
    }

    /// σ̂ is consistent for ℝ³ Gaussian residuals and stays so under 20 % and 45 % of far
    /// residuals, where the median alone is 14 % and 80 % too large; zero-weight samples do
    /// not count.
    #[test]
    fn robust_sigma_is_consistent_and_ignores_far_residuals() {
        let n = 40_000;
        for (frac, median_bias) in [(0.0, 0.0), (0.2, 0.1), (0.45, 0.5)] {
            let mut a = gaussian_angles(n, 0.01, 3);
            let bad = (frac * n as f64) as usize;
            for (i, v) in a.iter_mut().take(bad).enumerate() {
                *v = 2.9 + 0.2 * (i % 7) as f64 / 7.0;
            }
            let w = vec![1.0; n];
            let s = robust_sigma(&a, &w);
            assert!((s / 0.01 - 1.0).abs() < 0.02, "{frac}: {s}");
            let mut b = a.clone();
            b.sort_by(f64::total_cmp);
            let s0 = b[n / 2] / CHI3_MEDIAN;
            assert!(s0 / 0.01 - 1.0 >= median_bias, "{frac}: the median alone gives {s0}");
        }
        let mut a = gaussian_angles(1000, 0.01, 5);
        let mut w = vec![1.0; 1000];
        for (v, w) in a.iter_mut().zip(w.iter_mut()).take(600) {
            (*v, *w) = (3.0, 0.0);
        }
        assert!((robust_sigma(&a, &w) / 0.01 - 1.0).abs() < 0.1);
        assert_eq!(robust_sigma(&[0.0; 5], &[1.0; 5]), 0.0);
    }

    /// Beyond the breakdown point (3.0575 σ̂ ≥ π) the fit is an error naming the samples.
    #[test]
    fn breakdown_is_an_error() {
        assert_eq!(check_breakdown(0.5).unwrap(), 0.5);
        let e = check_breakdown(std::f64::consts::PI / CHI3_CUT).unwrap_err();
        assert!(matches!(e, Error::Invalid { arg: "quats", .. }), "{e}");
        assert!(e.to_string().contains("breakdown point (50 %)"), "{e}");
    }
}
