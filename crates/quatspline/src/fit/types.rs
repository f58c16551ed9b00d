//! The fit's options, results and validated data (see the module doc of [`super`]).

use crate::error::{Error, Result, Short};
use crate::quat::Quat;

/// What the roughness penalty integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Penalty {
    /// ∫ |ω̇|² dt (minimum-penalty curve: constant angular velocity).
    Acceleration,
    /// ∫ |ω̈|² dt (body frame; minimum-penalty curves have ω̈ ≡ 0).
    Jerk,
}

impl Penalty {
    /// m: the penalised derivative of ω.
    pub fn m(self) -> usize {
        match self {
            Penalty::Acceleration => 1,
            Penalty::Jerk => 2,
        }
    }
    /// The default spline order for this penalty (C² cubic; C⁴ quintic).
    pub fn default_order(self) -> usize {
        match self {
            Penalty::Acceleration => 4,
            Penalty::Jerk => 6,
        }
    }
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "acceleration" => Ok(Penalty::Acceleration),
            "jerk" => Ok(Penalty::Jerk),
            _ => Err(Error::invalid("penalty", format!("unknown penalty {s:?}; valid: acceleration, jerk"))),
        }
    }
}

/// Robust loss of the data term.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Robust {
    None,
    Huber,
    Cauchy,
}

impl Robust {
    pub fn parse(s: Option<&str>) -> Result<Self> {
        match s {
            None => Ok(Robust::None),
            Some("huber") => Ok(Robust::Huber),
            Some("cauchy") => Ok(Robust::Cauchy),
            Some(o) => {
                Err(Error::invalid("robust", format!("unknown robust loss {o:?}; valid: huber, cauchy")))
            }
        }
    }
    /// The one-dimensional constants (95 % efficient for a scalar residual), which the
    /// position fit applies to 1.4826 · median |r|.
    pub(crate) fn tuning(self) -> f64 {
        match self {
            Robust::None => f64::INFINITY,
            Robust::Huber => 1.345,
            Robust::Cauchy => 2.385,
        }
    }
    /// The tuning constant c of the M-step for residuals in ℝ³ — rotation vectors on SO(3),
    /// position errors — in units of the per-axis noise σ: c = 1.628 σ (Huber) and 2.666 σ
    /// (Cauchy), each 95 % efficient at Gaussian noise, the usual choice for the final step of
    /// an MM-estimate (Yohai 1987; Maronna, Martin & Yohai 2006, ch. 5: the high-breakdown
    /// start and scale give the robustness, the M-step from them the efficiency). For
    /// ψ(r) = u(|r|) r in ℝ³ with r ~ N(0, σ²I) the efficiency is A²/B with A = E[u + |r|u′/3]
    /// and B = E[u²|r|²]/3 (the asymptotic variance of an M-estimate of location in ℝᵖ,
    /// Maronna 1976, for p = 3; checked by quadrature in the tests). They
    /// are smaller than the one-dimensional 1.345 and 2.385 since |r| of a good sample is
    /// χ₃-distributed (median 1.538 σ): Huber leaves the 55 % of good samples within c at
    /// weight 1, Cauchy gives the median good sample weight 0.75. The one-dimensional
    /// constants applied to 1.4826 · median |r| (3.067 σ and 5.439 σ, 99.9 % and 99.3 %
    /// efficient) let each far glitch pull twice as hard: with 20 % of 170°–180° flips (six
    /// draws) Huber lay up to 1.68× the clean fit's error off and Cauchy 1.52×, against 1.48×
    /// and 1.39× with these.
    pub(crate) fn tuning_r3(self) -> f64 {
        match self {
            Robust::None => f64::INFINITY,
            Robust::Huber => 1.628,
            Robust::Cauchy => 2.666,
        }
    }
    pub(crate) fn weight(self, r: f64, c: f64) -> f64 {
        match self {
            Robust::None => 1.0,
            Robust::Huber => {
                if r <= c {
                    1.0
                } else {
                    c / r
                }
            }
            Robust::Cauchy => 1.0 / (1.0 + (r / c) * (r / c)),
        }
    }
}

/// The smoothing parameter λ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Smoothing {
    /// Chosen by generalised cross-validation.
    Auto,
    /// A fixed λ ≥ 0 (0 interpolates).
    Fixed(f64),
}

/// Knot placement (uniform knots spanning exactly [t_first, t_last]).
#[derive(Debug, Clone, PartialEq)]
pub enum Knots {
    /// One knot interval per median sample spacing.
    Default,
    /// About this spacing (rounded so the knots span the data exactly).
    Spacing(f64),
    /// Exactly these knots (uniform, first = t_first, last = t_last).
    Array(Vec<f64>),
}

/// Options of [`fit`].
#[derive(Debug, Clone)]
pub struct FitOptions {
    pub penalty: Penalty,
    pub order: Option<usize>,
    pub smoothing: Smoothing,
    pub knots: Knots,
    pub robust: Robust,
    pub robust_scale: Option<f64>,
    pub max_iter: usize,
    /// Convergence: largest control-point step, radians.
    pub tol: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            penalty: Penalty::Acceleration,
            order: None,
            smoothing: Smoothing::Auto,
            knots: Knots::Default,
            robust: Robust::None,
            robust_scale: None,
            max_iter: 1000,
            tol: 1e-10,
        }
    }
}

/// What [`fit`] returns.
#[derive(Debug, Clone)]
pub struct FitResult {
    pub ctrl: Vec<Quat>,
    pub dt: f64,
    pub t0: f64,
    pub order: usize,
    /// The breakpoints τ₀ … τ_S of a non-uniform fit (None: uniform t₀ + jΔt).
    pub breaks: Option<Vec<f64>>,
    /// |r_s|, radians, per sample.
    pub residuals: Vec<f64>,
    /// Final IRLS weights (1 without a robust loss), per sample.
    pub robust_weights: Vec<f64>,
    /// The robust scale c used (∞ without a robust loss).
    pub robust_scale: f64,
    pub lambda: f64,
    /// The λ asked for when it was beyond what double precision resolves and the fit used
    /// the largest λ that it does ([`lambda_cap`]) instead; None otherwise.
    pub lambda_requested: Option<f64>,
    /// tr A (effective degrees of freedom, in scalar observations).
    pub edf: f64,
    /// GCV(λ) at the solution.
    pub score: f64,
    pub iterations: usize,
    pub final_step: f64,
    pub converged: bool,
    /// Locally adaptive smoothing: the penalty's weight wᵢ on knot interval i (the local λ is
    /// λ·wᵢ; geometric mean 1); None for a global λ.
    pub penalty_weights: Option<Vec<f64>>,
}

/// Progress callback: (stage, iteration, last step). Returning false cancels the fit.
pub type Progress<'a> = &'a mut dyn FnMut(&str, usize, f64) -> bool;

/// The data of a fit after validation.
pub(super) struct Data {
    pub(super) t: Vec<f64>,
    pub(super) y: Vec<Quat>,
    pub(super) w: Vec<f64>,
}

/// Validates times (finite, strictly increasing), quaternions and weights (finite, ≥ 0, not
/// all zero); weights are normalised to mean 1 over all samples.
pub(super) fn validate(
    times: &[f64],
    quats: &[Quat],
    weights: Option<&[f64]>,
    min: usize,
    why: &str,
) -> Result<Data> {
    let n = times.len();
    if quats.len() != n {
        return Err(Error::invalid(
            "quats",
            format!("expected {n} quaternions (one per time), got {}", quats.len()),
        ));
    }
    if n < min {
        return Err(Error::invalid("times", format!("needs at least {min} samples {why}, got {n}")));
    }
    for (i, &v) in times.iter().enumerate() {
        if !v.is_finite() {
            return Err(Error::NonFinite { arg: "times", index: i });
        }
        if i > 0 {
            if v == times[i - 1] {
                return Err(Error::invalid("times", format!("duplicate time {} at index {i}", Short(v))));
            }
            if v < times[i - 1] {
                return Err(Error::invalid(
                    "times",
                    format!("not increasing at index {i} ({} after {})", Short(v), Short(times[i - 1])),
                ));
            }
            crate::spline::check_span("times", times[i - 1], v, i)?;
        }
    }
    let y = crate::spline::prepare_keys(quats, "quats", 0, true)?;
    let w = match weights {
        None => vec![1.0; n],
        Some(w) => {
            if w.len() != n {
                return Err(Error::invalid(
                    "weights",
                    format!("expected {n} weights (one per sample), got {}", w.len()),
                ));
            }
            let mut sum = 0.0;
            for (i, &v) in w.iter().enumerate() {
                if !v.is_finite() {
                    return Err(Error::NonFinite { arg: "weights", index: i });
                }
                if v < 0.0 {
                    return Err(Error::invalid(
                        "weights",
                        format!("negative weight {} at index {i}", Short(v)),
                    ));
                }
                if v > 1e12 {
                    return Err(Error::invalid(
                        "weights",
                        format!("weight {} at index {i} exceeds 1e12", Short(v)),
                    ));
                }
                sum += v;
            }
            if sum == 0.0 {
                return Err(Error::invalid("weights", "all weights are zero"));
            }
            let mean = sum / n as f64;
            w.iter().map(|v| v / mean).collect()
        }
    };
    Ok(Data { t: times.to_vec(), y, w })
}

pub(super) fn pen_name(p: Penalty) -> &'static str {
    match p {
        Penalty::Acceleration => "acceleration",
        Penalty::Jerk => "jerk",
    }
}
