//! Fitting splines on SO(3) (seed 003's 拟合样条; MATH.md §12); minimum-energy
//! interpolation (seed 003's Spicv/Sping; MATH.md §13) is in `min_energy.rs`.
//!
//! Model: a cumulative B-spline of order k on SO(3) (`model.rs`; k = 4 for the acceleration
//! penalty, 6 for jerk), knots at t₀ + jΔt or at given breakpoints (`layout.rs`) spanning
//! exactly the data's time range.
//! Objective, on the rotation group (never on quaternion components):
//!   Σ_s w_s ρ(|r_s|²) + λ ∫ |p(t)|² dt,   r_s = Log(q(t_s)⁻¹ y_s)  (rotation vector, sign-safe),
//! with p = ω̇ (body angular acceleration, `Penalty::Acceleration`) or p = ω̈ (body jerk,
//! `Penalty::Jerk`), the integral by Gauss–Legendre quadrature on every knot interval with
//! k − 1 − m points (exact in the small-rotation limit; k points when interpolating, λ = 0).
//! |ω̇| is the same in body and world frames; |ω̈| is taken in the body frame, which makes the
//! objective invariant under q ↦ a q b for fixed rotations a, b.
//!
//! Solver: Gauss–Newton with Levenberg–Marquardt fallback on the manifold (R_m ← R_m Exp(δ_m)),
//! analytic Jacobians (`model.rs`), the normal matrix block-banded with half-bandwidth 3k − 1 and
//! factored by banded Cholesky (`banded.rs`): O(samples + knots) time and memory per iteration.
//! Both Gauss–Newton matrices are assembled straight into band storage, in parallel (rayon)
//! over fixed chunks of knot intervals with an ordered reduction, so the result is
//! bit-identical on any number of threads; an accepted step's cost comes from its
//! linearisation, which the next iteration reuses.
//! Robust losses by iteratively reweighted least squares (Huber: w = min(1, c/|r|),
//! c = 1.628 σ̂; Cauchy: w = 1/(1 + (|r|/c)²), c = 2.666 σ̂ — each 95 % efficient for ℝ³
//! residuals of per-axis σ; or c = `robust_scale`) as an MM-estimate (Yohai 1987): a
//! high-breakdown pilot — from a running medoid of ±20 samples, the redescending Cauchy loss
//! with its scale from the start's residuals, then from its own — gives σ̂ (median |r| / 1.5382,
//! then three reweighted truncated mean squares: breakdown point 50 %; at least √tol) and the
//! start of the loss asked for; beyond the breakdown point (3.06 σ̂ ≥ π) the fit is an error
//! (`solver.rs`). Before the pilot, a robust fit drops bursts of glitches longer than the
//! medoid window by a consensus of runs (`start.rs`, `consensus_mask`): the samples are cut
//! where consecutive ones jump, the chain of runs holding the most samples is kept and the
//! other runs get weight 0; a run that the frames it contradicts do not outnumber two to one
//! is an error naming its time range.
//! For samples far from the curve (glitches up to a half turn): the data term's matrix is the
//! Riemannian Hessian of ½ dist² (`so3::dist_hess_sqrt`) rather than J_l⁻¹ᵀJ_l⁻¹, which is 17×
//! too stiff across a residual of 170° (the same to O(θ²) for noise; the gradient is the same);
//! the start is a curve through a running medoid of the samples ([`medoid_filter`]); a large
//! fixed λ is reached by continuation (×100 per stage from the bandwidth of 10 samples).
//!
//! Choosing λ ("auto"): generalised cross-validation (Craven & Wahba 1979) on the Gauss–Newton
//! linearisation (Gu 1992, "performance-oriented iteration"):
//!   GCV(λ) = n_obs · RSS(λ) / (n_obs − tr A(λ))²,  tr A = tr(H(λ)⁻¹ G),  H = G + λP,
//! G = JᵀWJ (data; J = S(r)·∂δ/∂c with the Hessian root S above), P = the penalty's Gauss–Newton matrix, n_obs = 3 × samples of positive weight;
//! tr(H⁻¹G) from the band of H⁻¹ (selected inversion). Why GCV: it needs one factorisation per
//! candidate λ and no refits (K-fold needs K fits per λ), the trace is exact and O(n), and it is
//! the standard criterion of smoothing splines. λ is searched as λ = ρ h^{2m+2} over the
//! equivalent kernel bandwidth h (ρ = samples per time unit, m = 1 or 2): the first step (from
//! the curve through the noisy samples, whose linearisation says little about λ) uses h = 10
//! sample spacings; the second linearisation takes a coarse log grid and Brent's method (golden
//! section with parabolic steps) between the best point's neighbours; every later one Brent's
//! method from a bracket around the previous λ, until λ moves less than 1 % or the step at
//! the λ chosen is below the tolerance (the curve no longer depends on λ: samples at rest or
//! noise-free, where GCV is flat). A move of ln λ back against the previous one is at most
//! half as long, so λ cannot alternate between two GCV minima for ever; ties in the grid go to
//! the larger λ. Each accepted Gauss–Newton step is followed along its direction to the
//! minimum of the parabola through the cost at both ends when that lies well off the full
//! step (Gauss–Newton is only linear where residuals are large).
//!
//! Locally adaptive smoothing (`adaptive.rs`): the penalty λ Σᵢ wᵢ ∫_{interval i} |p|² dt with
//! weights wᵢ = r̄ᵢ^{−α} from the roughness r̄ of a global-GCV pilot fit, the exponent α and λ
//! chosen by GCV at the pilot's linearisation (one parameter more than a global λ);
//! [`fit_adaptive`] with [`Adaptivity::Auto`] keeps it only where it lowers GCV.
//!
//! λ = 0 (interpolation, also [`min_energy::min_energy_bspline`]): the limit λ → 0⁺, i.e. the minimum-penalty curve
//! of the spline space through every sample, by Bregman iteration (iterated Tikhonov): fit with
//! a small λ to targets shifted by eₛ, then eₛ ← eₛ − r_s, until max |r_s| ≤ 1e-11 rad
//! (Osher et al. 2005; for linear problems this is the augmented-Lagrangian method).
//!
//! Never silently unconverged: a solver that does not reach its tolerance within `max_iter`
//! iterations returns [`Error::NotConverged`] with the iteration count and the last step.

pub mod adaptive;
pub mod banded;
pub mod covariance;
pub mod gyro;
pub mod layout;
pub mod min_energy;
pub mod model;
pub mod position;
pub mod riemannian_cubic;
pub mod so3;

mod assembly;
mod knots;
mod lambda;
mod solver;
mod start;
mod types;

pub use crate::quadrature::gauss_legendre01;
pub use adaptive::{fit_adaptive, Adaptivity};
pub use covariance::{fitted_layout, Posterior, Quantity};
pub use gyro::{fit_gyro, Estimate, GyroFit, GyroOptions, Sensor};
pub(crate) use lambda::lambda_cap;
pub use solver::fit;
pub use types::{FitOptions, FitResult, Knots, Penalty, Progress, Robust, Smoothing};

// Shared with the position fit and the minimum-energy B-spline.
use knots::{fit_layout, knot_layout};
use solver::solve;
use start::initial_controls;
use types::{pen_name, validate};

#[cfg(test)]
mod tests {
    use super::assembly::*;
    use super::banded::Band;
    use super::knots::*;
    use super::lambda::*;
    use super::model::Model;
    use super::start::*;
    use super::types::*;
    use super::*;
    use crate::error::Error;
    use crate::quat::Quat;

    /// Every knot option covers the last sample time exactly as the spline computes its last
    /// joint (t₀ + segments·Δt), on spans and spacings where span/segments rounds down.
    #[test]
    fn knot_layouts_cover_the_last_sample() {
        let mut rng = crate::testing::XorShift64::new(17);
        let mut next = || rng.uniform();
        let mut short_before = 0;
        for _ in 0..20_000 {
            let a = (next() - 0.5) * 10f64.powi((next() * 8.0) as i32);
            let n = 2 + (next() * 3000.0) as usize;
            let dt = 10f64.powf(-3.0 * next());
            let t: Vec<f64> = (0..n).map(|i| a + i as f64 * dt).collect();
            let b = t[n - 1];
            let span = b - a;
            let spacing = span * (0.0005 + next()).min(1.0);
            for knots in [Knots::Default, Knots::Spacing(spacing)] {
                let (t0, h, segs) = knot_layout(&knots, &t).unwrap();
                let (_, h_raw, _) = knot_layout_raw(&knots, &t).unwrap();
                short_before += usize::from(t0 + segs as f64 * h_raw < b);
                assert!(t0 + segs as f64 * h >= b, "{knots:?}: {t0} + {segs}·{h} < {b}");
                assert!(h - h_raw <= 8.0 * f64::EPSILON * h_raw, "{h} vs {h_raw}");
            }
        }
        // the rounding this guards against does occur on such grids
        assert!(short_before > 100, "{short_before}");
    }

    fn data(n: usize) -> Data {
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.1 + 0.03 * ((i * 7) % 5) as f64).collect();
        let y = t
            .iter()
            .map(|&s| so3::exp([0.4 * s.sin(), 0.3 * (0.7 * s).cos(), 0.2 * s + 0.05 * (13.0 * s).sin()]))
            .collect();
        Data { t, y, w: (0..n).map(|i| 0.5 + (i % 3) as f64 * 0.25).collect() }
    }

    /// The Gauss–Newton gradient Jᵀ W r + λ Jₚᵀ C p (data and penalty Jacobians, analytic)
    /// against central finite differences of the objective, for both penalties and several
    /// orders.
    #[test]
    fn gradient_matches_finite_differences() {
        let d = data(40);
        for (pen, k) in
            [(Penalty::Acceleration, 4), (Penalty::Acceleration, 5), (Penalty::Jerk, 5), (Penalty::Jerk, 6)]
        {
            let span = d.t[d.t.len() - 1] - d.t[0];
            let segs = 9;
            let dt = span / segs as f64;
            let mut model = Model::new(initial_controls(&d, d.t[0], dt, segs, k), dt, d.t[0], k);
            // Move away from the data so residuals are not small.
            let wiggle: Vec<f64> =
                (0..3 * model.ctrl.len()).map(|i| 0.05 * ((i * 37 % 11) as f64 - 5.0) / 5.0).collect();
            model.retract(&wiggle);
            let nodes = gauss_legendre01(k);
            let offs = vec![[0.0; 3]; d.t.len()];
            let lam = 0.37;
            let lin = linearise(&model, &d, &d.w, &offs, pen, &nodes);
            // ½·cost has gradient gd + λ gp.
            let c0 = cost(&model, &d, &d.w, &offs, pen, &nodes, lam);
            assert!((c0 - (lin.rwr + lam * lin.pcp)).abs() < 1e-12 * c0);
            let h = 1e-6;
            for idx in 0..3 * model.ctrl.len() {
                let mut e = vec![0.0; 3 * model.ctrl.len()];
                e[idx] = h;
                let mut mp = model.clone();
                mp.retract(&e);
                e[idx] = -h;
                let mut mm = model.clone();
                mm.retract(&e);
                let fd = 0.5
                    * (cost(&mp, &d, &d.w, &offs, pen, &nodes, lam)
                        - cost(&mm, &d, &d.w, &offs, pen, &nodes, lam))
                    / (2.0 * h);
                let an = lin.gd[idx] + lam * lin.gp[idx];
                assert!(
                    (fd - an).abs() < 1e-6 * (1.0 + an.abs()),
                    "{pen:?} k={k} idx {idx}: fd {fd} analytic {an}"
                );
            }
            // The Gauss–Newton matrix against finite differences of the residual Jacobian
            // is implied by the gradient check at two points; check symmetry positive
            // definiteness instead: H = G + λP factors.
            assert!(lin.g.axpy(lam, &lin.p).cholesky().is_ok());
        }
    }

    /// The parallel assembly uses fixed chunks and ordered reductions: the fit (controls,
    /// λ, score, edf, residuals) is bit-identical on 1, 2 and 3 threads, with fixed and "auto"
    /// λ, a robust loss and the jerk penalty, and with more segments than one chunk.
    #[test]
    fn fit_is_identical_on_any_number_of_threads() {
        let n = 3 * CHUNK + 77;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / 100.0).collect();
        let y: Vec<Quat> = t
            .iter()
            .enumerate()
            .map(|(i, &s)| {
                let e = 0.01 * (((i * 7919) % 101) as f64 / 50.0 - 1.0);
                so3::exp([0.8 * (0.5 * s).sin() + e, 0.6 * (0.37 * s).cos() - e, 0.2 * s])
            })
            .collect();
        let cases = [
            FitOptions { smoothing: Smoothing::Fixed(1e-6), ..Default::default() },
            FitOptions { smoothing: Smoothing::Auto, robust: Robust::Huber, ..Default::default() },
            FitOptions {
                smoothing: Smoothing::Auto,
                penalty: Penalty::Jerk,
                knots: Knots::Spacing(0.05),
                ..Default::default()
            },
        ];
        for opts in &cases {
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| fit(&t, &y, None, opts, &mut |_, _, _| true).unwrap())
            };
            let one = run(1);
            for threads in [2, 3] {
                let r = run(threads);
                assert_eq!(r.ctrl, one.ctrl, "{opts:?}: {threads} threads");
                assert_eq!(r.lambda.to_bits(), one.lambda.to_bits());
                assert_eq!(r.score.to_bits(), one.score.to_bits());
                assert_eq!(r.edf.to_bits(), one.edf.to_bits());
                assert_eq!(r.residuals, one.residuals);
                assert_eq!(r.iterations, one.iterations);
            }
        }
    }

    /// Brent's minimiser finds the minimum of a smooth function to its tolerance from an
    /// off-centre start, and survives non-finite values.
    /// The medoid start: an isolated glitch (and two in five, far apart) is replaced by a
    /// neighbour, zero-weight samples are never chosen, signs do not matter, clean data stays.
    #[test]
    fn medoid_filter_skips_glitches_and_zero_weights() {
        let n = 30;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.1).collect();
        let clean: Vec<Quat> = t.iter().map(|&s| so3::exp([0.3 * s, -0.2 * s, 0.1])).collect();
        let mut y = clean.clone();
        y[7] = so3::exp([0.0, 3.0, 0.0]) * y[7];
        y[14] = so3::exp([2.9, 0.0, 0.0]) * y[14];
        y[16] = so3::exp([0.0, 0.0, -3.1]) * y[16];
        y[20] = -y[20];
        let mut w = vec![1.0; n];
        w[25] = 0.0;
        let out = medoid_filter(&Data { t: t.clone(), y: y.clone(), w: w.clone() });
        let ang = |a: Quat, b: Quat| 2.0 * a.dot(b).abs().min(1.0).acos();
        for i in 0..n {
            assert!(ang(out[i], clean[i]) <= 0.11, "sample {i}: {}", ang(out[i], clean[i]));
            assert!(out[i] != y[25], "sample {i}: the zero-weight sample was chosen");
        }
        // Inside (symmetric windows) a clean sample on smooth motion is its own medoid; at the
        // ends the window is one-sided and the medoid one sample in (checked above: ≤ 0.11).
        for i in [3, 10, 20] {
            assert_eq!(out[i], y[i], "a clean sample is its own medoid ({i})");
        }
    }

    #[test]
    fn brent_finds_minimum() {
        let mut calls = 0;
        let mut f = |x: f64| {
            calls += 1;
            if x > 2.5 {
                f64::INFINITY
            } else {
                (x - 0.7).powi(2) + 0.1 * (x - 0.7).powi(4)
            }
        };
        let f0 = f(-0.5);
        let (x, fx) = brent(&mut f, -1.0, 3.0, -0.5, f0, 1e-6, 100);
        assert!((x - 0.7).abs() < 1e-5, "{x}");
        assert!(fx < 1e-9);
        assert!(calls < 40, "{calls}");
    }

    /// Assembly straight into band storage equals block-by-block accumulation (reference:
    /// every segment's block added in order), across chunk boundaries.
    #[test]
    fn chunked_assembly_matches_sequential() {
        let (k, segs) = (4, 2 * CHUNK + 5);
        let nctrl = segs + k - 1;
        let nb = 3 * k;
        let blk = |i: usize| -> Vec<f64> {
            (0..nb * nb)
                .map(|j| ((i * 31 + j * 7) % 17) as f64 / 17.0 + if j % (nb + 1) == 0 { 3.0 } else { 0.0 })
                .collect()
        };
        let h = assemble(nctrl, segs, k, Band::zeros(0, 0), |s0, s1, b, g| {
            for i in s0..s1 {
                b.add_block(3 * (i - s0), nb, &blk(i), 1.0);
                for a in 0..nb {
                    g[3 * (i - s0) + a] += (i + a) as f64;
                }
            }
            ((s1 - s0) as f64, 1.0)
        });
        let mut want = Band::zeros(3 * nctrl, nb - 1);
        let mut wg = vec![0.0; 3 * nctrl];
        for i in 0..segs {
            want.add_block(3 * i, nb, &blk(i), 1.0);
            for a in 0..nb {
                wg[3 * i + a] += (i + a) as f64;
            }
        }
        assert_eq!(h.band.a.len(), want.a.len());
        for (x, y) in h.band.a.iter().zip(&want.a) {
            assert!((x - y).abs() <= 1e-12 * y.abs().max(1.0));
        }
        assert_eq!(h.grad, wg);
        assert_eq!(h.sum, segs as f64);
        assert_eq!(h.count, segs.div_ceil(CHUNK) as f64);
    }

    /// The smoothing fit's quadrature (k − 1 − m points per knot interval) against an 8-point
    /// rule: exact in the small-rotation limit, close at large rotations per interval.
    #[test]
    fn penalty_quadrature_accuracy() {
        for (scale, bound) in [(1e-4, 1e-8), (0.01, 5e-6), (0.1, 5e-4), (0.5, 5e-3), (1.0, 5e-3)] {
            let ctrl: Vec<Quat> = (0..14)
                .map(|m| {
                    let x = m as f64;
                    so3::exp([3.0 * scale * (0.7 * x).sin(), scale * x, -0.1 * scale * x * x])
                })
                .collect();
            for (k, pen) in [(4, Penalty::Acceleration), (5, Penalty::Acceleration), (6, Penalty::Jerk)] {
                let model = Model::new(ctrl.clone(), 0.4, 0.0, k);
                let m = pen.m();
                let val = |q: usize| match pen {
                    Penalty::Acceleration => penalty_value::<3>(&model, m, &gauss_legendre01(q)),
                    Penalty::Jerk => penalty_value::<4>(&model, m, &gauss_legendre01(q)),
                };
                let rel = (val(penalty_nodes(k, m, false)) / val(8) - 1.0).abs();
                assert!(rel < bound, "scale {scale} k {k}: relative error {rel:e}");
            }
        }
    }

    /// Samples at rest (GCV is flat: the residuals vanish for every λ) and noise-free
    /// constant-rate motion fit with λ = "auto" to the exact curve, for both penalties.
    #[test]
    fn auto_fit_of_samples_at_rest_or_noise_free_converges_to_them() {
        let t: Vec<f64> = (0..30).map(|i| 0.1 * i as f64).collect();
        let rest = so3::exp([0.3, -1.0, 2.0]);
        for pen in [Penalty::Acceleration, Penalty::Jerk] {
            for rate in [0.0, 0.3] {
                let y: Vec<Quat> =
                    t.iter().map(|&s| rest * so3::exp([rate * s, 0.1 * rate * s, 0.0])).collect();
                let opts = FitOptions { penalty: pen, ..Default::default() };
                let r = fit(&t, &y, None, &opts, &mut |_, _, _| true).unwrap();
                assert!(r.residuals.iter().all(|a| *a < 1e-9), "{pen:?} {rate}: {:?}", r.residuals);
                assert!(r.lambda.is_finite() && r.lambda > 0.0);
            }
        }
    }

    #[test]
    fn unconverged_fit_is_an_error_naming_iterations_and_step() {
        let d = data(60);
        let opts = FitOptions { max_iter: 1, smoothing: Smoothing::Fixed(1e-3), ..Default::default() };
        let e = fit(&d.t, &d.y, None, &opts, &mut |_, _, _| true).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, Error::NotConverged { .. }), "{msg}");
        assert!(msg.contains("did not converge in 1 iterations") && msg.contains("last step"), "{msg}");
    }
}
