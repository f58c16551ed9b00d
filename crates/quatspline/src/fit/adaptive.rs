//! Locally adaptive smoothing: a penalty weight that varies along the recording,
//! λ(t) = λ·w(t), w piecewise constant on the knot intervals (see the module doc of [`super`]
//! and docs/maths/fitting.rst, "Locally adaptive smoothing").
//!
//! Method (a plug-in local penalty in the spirit of Ruppert & Carroll 2000, "Spatially-adaptive
//! penalties for spline fitting", Aust. N. Z. J. Stat. 42, and of the plug-in local bandwidths
//! of kernel smoothing, with its one shape parameter chosen by GCV):
//! 1. the pilot: the fit with one λ chosen by GCV;
//! 2. its local roughness r̄ᵢ: the mean of |p|² (p = ω̇ or ω̈, the penalised quantity) over a
//!    window of ±5 local equivalent-kernel bandwidths h = (λwᵢ/ρ)^{1/(2m+2)} around knot
//!    interval i, floored at 10⁻⁴ × its mean (intervals at rest);
//! 3. weights wᵢ(α) = r̄ᵢ^{−α}, scaled to geometric mean 1: the penalty is relaxed where the
//!    motion is rough and stiffened where it is smooth. The asymptotically optimal local λ of a
//!    penalised spline of derivative order q = m + 1 is ∝ |f^{(2q)}|^{−4q/(4q+1)}; r̄ stands in
//!    for |f^{(q)}|², which gives α = 4q/(4q+1) where the motion's frequency varies and
//!    2q/(4q+1) where its amplitude does — so α is not fixed but chosen by the data from
//!    {¼, ½, ¾, 1} together with λ;
//! 4. (α, λ) by GCV on the pilot's Gauss–Newton linearisation (one factorisation per
//!    candidate, Brent's method in ln λ from the pilot's λ), each score counting α as one
//!    more parameter: n·RSS/(n − tr A − 1)²;
//! 5. the adaptive fit from the pilot's curve with the chosen weights, λ re-chosen by GCV at
//!    every linearisation as for a global fit (the weights stay fixed);
//! 6. iterated plug-in: steps 2–5 again from the adaptive fit (whose roughness is less noisy
//!    where it smooths more), at most [`ROUNDS`] rounds in all, while GCV falls.
//!
//! [`Adaptivity::Auto`] keeps the pilot unless the best adaptive candidate's GCV (with the
//! extra parameter) is below the pilot's at its linearisation, and then keeps whichever of
//! the two fits has the lower GCV (the adaptive one's again with the extra parameter): on
//! uniformly rough motion r̄ is nearly constant, the weights are nearly 1 and the fit stays
//! the global one.
//!
//! Cost: the pilot, then per round O(samples) per candidate (a penalty assembly and ~10 GCV
//! evaluations for each of the 4 exponents) and, only when the round lowers GCV, a fit started
//! from the previous one: on motion where one λ serves, the pilot and one round of
//! candidates; where adaptive smoothing wins, up to 3 rounds.

use super::assembly::{data_half, pen_half, penalty_nodes, Lin};
use super::banded::Band;
use super::knots::fit_layout;
use super::lambda::{gcv_at, lambda_cap, select_lambda};
use super::model::Model;
use super::solver::{fit, solve_weighted};
use super::types::{validate, FitOptions, FitResult, Penalty, Progress, Smoothing};
use crate::error::{Error, Result};
use crate::jet::Jet;
use crate::quadrature::gauss_legendre01;
use crate::quat::Quat;
use crate::vec3;
use rayon::prelude::*;

/// How λ = "auto" may vary along the recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Adaptivity {
    /// One λ for the whole recording, by GCV.
    Global,
    /// λ(t) = λ·w(t) by the plug-in weights above, always.
    Adaptive,
    /// Adaptive where it lowers GCV (counting its extra parameter), else global.
    Auto,
}

impl std::str::FromStr for Adaptivity {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "gcv" => Ok(Adaptivity::Global),
            "adaptive" => Ok(Adaptivity::Adaptive),
            "auto" => Ok(Adaptivity::Auto),
            _ => Err(Error::invalid(
                "smoothing",
                format!("unknown smoothing {s:?}; valid: auto, gcv, adaptive or a number ≥ 0"),
            )),
        }
    }
}

/// The exponents α tried (see the module doc).
pub(super) const ALPHAS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];
/// Half-width of the roughness window, in local equivalent-kernel bandwidths: ±5h spans about
/// one period of the fastest oscillation a smoother of bandwidth h follows (its equivalent
/// kernel passes periods down to ≈ 2πh), so the roughness is averaged over the motion's cycle
/// rather than following |p|² within it. (Measured on the synthetic slow-then-fast motion of
/// the tests: ±2h followed the cycle and lost ω in the fast half; ±5h and ±10h did not.)
const WINDOW_BANDWIDTHS: f64 = 5.0;
/// Rounds of the iterated plug-in: the roughness of each adaptive fit (less noisy where it
/// smooths more) gives the next weights, while GCV keeps falling.
const ROUNDS: usize = 3;
/// Floor of the local roughness, as a fraction of its mean.
const ROUGHNESS_FLOOR: f64 = 1e-4;

/// Fits with λ = "auto" chosen globally, locally or by the data ([`Adaptivity`]); a fixed λ
/// (or [`Adaptivity::Global`]) is [`fit`].
pub fn fit_adaptive(
    times: &[f64],
    quats: &[Quat],
    weights: Option<&[f64]>,
    opts: &FitOptions,
    mode: Adaptivity,
    progress: Progress<'_>,
) -> Result<FitResult> {
    let pilot = fit(times, quats, weights, opts, progress)?;
    if mode == Adaptivity::Global || opts.smoothing != Smoothing::Auto {
        return Ok(pilot);
    }
    let data = validate(times, quats, weights, 1, "")?;
    let lay = fit_layout(&opts.knots, &data.t, pilot.order)?;
    if lay.segs < 2 {
        return Ok(pilot);
    }
    let m = opts.penalty.m();
    let n = data.t.len();
    let span = data.t[n - 1] - data.t[0];
    let rho = n as f64 / span;
    let dts = span / (n - 1) as f64;
    let lam_of = |h: f64| rho * h.powi(2 * m as i32 + 2);
    let nodes = gauss_legendre01(penalty_nodes(lay.order, m, false));
    let offs = vec![[0.0; 3]; n];
    // The current fit and its score (the adaptive ones counting α as a parameter).
    let mut cur = pilot;
    let mut cur_score = cur.score;
    for round in 0..ROUNDS {
        let model = Model::with_layout(cur.ctrl.clone(), lay.clone());
        let rough = local_roughness(&model, opts.penalty, cur.lambda, rho, cur.penalty_weights.as_deref());
        // The current fit's linearisation (its final IRLS weights), shared by every candidate.
        let w: Vec<f64> = data.w.iter().zip(&cur.robust_weights).map(|(a, b)| a * b).collect();
        let dh = data_half(&model, &data, &w, &offs, Band::zeros(0, 0));
        let ph = pen_half(&model, opts.penalty, &nodes, Band::zeros(0, 0), cur.penalty_weights.as_deref());
        let mut lin = Lin::new(dh, ph);
        let mut hbuf = Band::zeros(0, 0);
        let (g0, tr0) = gcv_at(&lin, cur.lambda, &mut hbuf)?;
        let here = if round == 0 { g0 } else { with_extra_parameter(g0, tr0, lin.nobs) };
        let mut best: Option<(f64, f64, Vec<f64>)> = None;
        for &alpha in &ALPHAS {
            let wts = penalty_weights(&rough, alpha);
            let p = std::mem::replace(&mut lin.p, Band::zeros(0, 0));
            let ph = pen_half(&model, opts.penalty, &nodes, p, Some(&wts));
            (lin.p, lin.gp, lin.pcp) = (ph.band, ph.grad, ph.sum);
            let hi = lam_of(span).min(lambda_cap(&lin.g, &lin.p));
            let lo = lam_of(0.3 * dts).min(hi / 1e6);
            let (lam, _) = select_lambda(&lin, lo, hi, 13, Some(cur.lambda), &mut hbuf)?;
            let (score, tr) = gcv_at(&lin, lam, &mut hbuf)?;
            let s = with_extra_parameter(score, tr, lin.nobs);
            if best.as_ref().is_none_or(|b| s < b.0) {
                best = Some((s, lam, wts));
            }
        }
        let nobs = lin.nobs;
        drop((lin, hbuf));
        let Some((s_best, lam, wts)) = best else { break };
        let lower = s_best < here; // false for NaN too
        if !lower && (mode == Adaptivity::Auto || round > 0) {
            break;
        }
        // "auto" never fails where the global fit succeeded: an adaptive solve that does not
        // converge within `max_iter` leaves the fit it started from.
        let next = match solve_weighted(model, &data, opts, Some((wts, lam)), progress) {
            Ok(r) => r,
            Err(Error::NotConverged { .. }) if mode == Adaptivity::Auto || round > 0 => break,
            Err(e) => return Err(e),
        };
        let s_next = with_extra_parameter(next.score, next.edf, nobs);
        let lower = s_next < cur_score;
        if !lower && (mode == Adaptivity::Auto || round > 0) {
            break;
        }
        (cur, cur_score) = (next, s_next);
    }
    Ok(cur)
}

/// GCV = n·RSS/(n − tr A)² recomputed with one more parameter: n·RSS/(n − tr A − 1)².
fn with_extra_parameter(score: f64, tr: f64, nobs: f64) -> f64 {
    let den = nobs - tr - 1.0;
    if !(score.is_finite() && den > 1e-9 * nobs) {
        return f64::INFINITY;
    }
    score * ((nobs - tr) / den).powi(2)
}

/// The pilot's local roughness per knot interval: the mean of |p|² (p = ω^(m)) over a window
/// of ±[`WINDOW_BANDWIDTHS`] equivalent-kernel bandwidths (λ/ρ)^{1/(2m+2)} (at least ±1
/// interval), floored at [`ROUGHNESS_FLOOR`] × its mean over the recording.
pub(super) fn local_roughness(
    model: &Model,
    pen: Penalty,
    lam: f64,
    rho: f64,
    wts: Option<&[f64]>,
) -> Vec<f64> {
    let m = pen.m();
    let k = model.order;
    let nodes = gauss_legendre01(k);
    let segs = model.segments();
    // ∫ |p|² over each interval (Gauss–Legendre, k points).
    let e: Vec<f64> = (0..segs)
        .into_par_iter()
        .map(|i| {
            let h = model.width(i);
            nodes
                .iter()
                .map(|&(u, w)| {
                    let p = match pen {
                        Penalty::Acceleration => {
                            let q = model.value::<3>(i, Jet::variable(u, 1.0 / h));
                            let om = Model::omega(&q);
                            std::array::from_fn::<f64, 3, _>(|r| om[r].derivative(m))
                        }
                        Penalty::Jerk => {
                            let q = model.value::<4>(i, Jet::variable(u, 1.0 / h));
                            let om = Model::omega(&q);
                            std::array::from_fn::<f64, 3, _>(|r| om[r].derivative(m))
                        }
                    };
                    w * h * vec3::dot(p, p)
                })
                .sum()
        })
        .collect();
    let span: f64 = (0..segs).map(|i| model.width(i)).sum();
    let mean_width = span / segs as f64;
    // the window of interval i: ± WINDOW_BANDWIDTHS local bandwidths (λ wᵢ/ρ)^{1/(2m+2)}
    let half = |i: usize| {
        let bw = (lam * wts.map_or(1.0, |v| v[i]) / rho).powf(1.0 / (2 * m + 2) as f64);
        ((WINDOW_BANDWIDTHS * bw / mean_width).round().max(1.0) as usize).min(segs)
    };
    // Prefix sums of the integral and of the widths: the window's mean.
    let mut ce = vec![0.0; segs + 1];
    let mut cw = vec![0.0; segs + 1];
    for i in 0..segs {
        ce[i + 1] = ce[i] + e[i];
        cw[i + 1] = cw[i] + model.width(i);
    }
    let mut r: Vec<f64> = (0..segs)
        .map(|i| {
            let hw = half(i);
            let (a, b) = (i.saturating_sub(hw), (i + hw + 1).min(segs));
            (ce[b] - ce[a]) / (cw[b] - cw[a])
        })
        .collect();
    let mean = ce[segs] / cw[segs];
    let floor = (ROUGHNESS_FLOOR * mean).max(f64::MIN_POSITIVE);
    r.iter_mut().for_each(|v| *v = v.max(floor));
    r
}

/// wᵢ = r̄ᵢ^{−α}, scaled to geometric mean 1.
pub(super) fn penalty_weights(rough: &[f64], alpha: f64) -> Vec<f64> {
    let logs: Vec<f64> = rough.iter().map(|r| -alpha * r.ln()).collect();
    let mean = logs.iter().sum::<f64>() / logs.len() as f64;
    logs.iter().map(|l| (l - mean).exp()).collect()
}

#[cfg(test)]
mod tests {
    use super::super::assembly::{pen_half, penalty_nodes};
    use super::super::banded::Band;
    use super::super::model::Model;
    use super::super::so3;
    use super::super::types::Penalty;
    use super::*;

    fn model(k: usize, segs: usize) -> Model {
        let ctrl: Vec<Quat> = (0..segs + k - 1)
            .map(|m| {
                let x = m as f64;
                so3::exp([0.4 * (0.7 * x).sin(), 0.3 * x, -0.02 * x * x])
            })
            .collect();
        Model::new(ctrl, 0.3, 0.0, k)
    }

    /// The weighted penalty half: its value is Σᵢ wᵢ (segment i's penalty) — the sum of the
    /// unweighted halves of single segments — and its gradient ½∂(Σ wᵢ ∫|p|²)/∂δ matches
    /// central finite differences, for both penalties.
    #[test]
    fn weighted_penalty_is_the_weighted_sum_and_its_gradient_matches_finite_differences() {
        for (pen, k) in [(Penalty::Acceleration, 4), (Penalty::Jerk, 6)] {
            let segs = 7;
            let md = model(k, segs);
            let nodes = gauss_legendre01(penalty_nodes(k, pen.m(), false));
            let w: Vec<f64> = (0..segs).map(|i| 0.1 + (i * i % 5) as f64).collect();
            let full = pen_half(&md, pen, &nodes, Band::zeros(0, 0), Some(&w));
            let mut want = 0.0;
            for i in 0..segs {
                let e: Vec<f64> = (0..segs).map(|j| if j == i { 1.0 } else { 0.0 }).collect();
                want += w[i] * pen_half(&md, pen, &nodes, Band::zeros(0, 0), Some(&e)).sum;
            }
            assert!((full.sum - want).abs() < 1e-12 * want, "{pen:?}: {} vs {want}", full.sum);
            let plain = pen_half(&md, pen, &nodes, Band::zeros(0, 0), None);
            let ones = pen_half(&md, pen, &nodes, Band::zeros(0, 0), Some(&vec![1.0; segs]));
            assert_eq!(plain.sum, ones.sum);
            let h = 1e-6;
            for idx in 0..3 * md.ctrl.len() {
                let mut e = vec![0.0; 3 * md.ctrl.len()];
                e[idx] = h;
                let mut mp = md.clone();
                mp.retract(&e);
                e[idx] = -h;
                let mut mm = md.clone();
                mm.retract(&e);
                let val = |m: &Model| pen_half(m, pen, &nodes, Band::zeros(0, 0), Some(&w)).sum;
                let fd = 0.5 * (val(&mp) - val(&mm)) / (2.0 * h);
                let an = full.grad[idx];
                assert!((fd - an).abs() < 1e-6 * (1.0 + an.abs()), "{pen:?} {idx}: {fd} vs {an}");
            }
        }
    }

    /// Weights: geometric mean 1, α = 0 gives 1 everywhere, rougher intervals get less weight
    /// in proportion r^−α; the roughness is floored relative to its mean.
    #[test]
    fn penalty_weights_follow_the_roughness() {
        let r = vec![1.0, 4.0, 16.0, 0.25];
        let w0 = penalty_weights(&r, 0.0);
        assert!(w0.iter().all(|v| (v - 1.0).abs() < 1e-15));
        let w = penalty_weights(&r, 0.5);
        let gm = (w.iter().map(|v| v.ln()).sum::<f64>() / 4.0).exp();
        assert!((gm - 1.0).abs() < 1e-14);
        assert!((w[0] / w[1] - 2.0).abs() < 1e-12 && (w[3] / w[2] - 8.0).abs() < 1e-12);
        // a motion at rest in its first half: the floor bounds the roughness ratio
        let k = 4;
        let ctrl: Vec<Quat> = (0..20 + k - 1)
            .map(|m| so3::exp([0.0, 0.0, if m < 10 { 0.0 } else { 0.05 * ((m - 10) as f64).powi(2) }]))
            .collect();
        let md = Model::new(ctrl, 0.1, 0.0, k);
        let rough = local_roughness(&md, Penalty::Acceleration, 1e-9, 100.0, None);
        let mean = rough.iter().sum::<f64>() / rough.len() as f64;
        let lo = rough.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(lo > 0.0 && lo < 1e-3 * mean, "{lo} {mean}");
    }
}
