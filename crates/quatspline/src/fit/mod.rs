//! Fitting splines on SO(3) (seed 003's 拟合样条; MATH.md §12); minimum-energy
//! interpolation (seed 003's Spicv/Sping; MATH.md §13) is in `min_energy.rs`.
//!
//! Model: a uniform cumulative B-spline of order k on SO(3) (`model.rs`; k = 4 for the
//! acceleration penalty, 6 for jerk), knots at t₀ + jΔt spanning exactly the data's time range.
//! Objective, on the rotation group (never on quaternion components):
//!   Σ_s w_s ρ(|r_s|²) + λ ∫ |p(t)|² dt,   r_s = Log(q(t_s)⁻¹ y_s)  (rotation vector, sign-safe),
//! with p = ω̇ (body angular acceleration, `Penalty::Acceleration`) or p = ω̈ (body jerk,
//! `Penalty::Jerk`), the integral by k-point Gauss–Legendre quadrature on every knot interval.
//! |ω̇| is the same in body and world frames; |ω̈| is taken in the body frame, which makes the
//! objective invariant under q ↦ a q b for fixed rotations a, b.
//!
//! Solver: Gauss–Newton with Levenberg–Marquardt fallback on the manifold (R_m ← R_m Exp(δ_m)),
//! analytic Jacobians (`model.rs`), the normal matrix block-banded with half-bandwidth 3k − 1 and
//! factored by banded Cholesky (`banded.rs`): O(samples + knots) time and memory per iteration.
//! Robust losses by iteratively reweighted least squares (Huber: w = min(1, c/|r|),
//! c = 1.345 σ̂; Cauchy: w = 1/(1 + (|r|/c)²), c = 2.385 σ̂; σ̂ = 1.4826 · median |r| of the
//! converged non-robust fit, or `robust_scale`).
//!
//! Choosing λ ("auto"): generalised cross-validation (Craven & Wahba 1979) on the Gauss–Newton
//! linearisation (Gu 1992, "performance-oriented iteration"):
//!   GCV(λ) = n_obs · RSS(λ) / (n_obs − tr A(λ))²,  tr A = tr(H(λ)⁻¹ G),  H = G + λP,
//! G = JᵀWJ (data), P = the penalty's Gauss–Newton matrix, n_obs = 3 × samples of positive weight;
//! tr(H⁻¹G) from the band of H⁻¹ (selected inversion). Why GCV: it needs one factorisation per
//! candidate λ and no refits (K-fold needs K fits per λ), the trace is exact and O(n), and it is
//! the standard criterion of smoothing splines. λ is searched as λ = ρ h^{2m+2} over the
//! equivalent kernel bandwidth h (ρ = samples per time unit, m = 1 or 2), a coarse log grid then
//! golden-section refinement; it is re-selected at every linearisation until it settles.
//!
//! λ = 0 (interpolation, also [`min_energy::min_energy_bspline`]): the limit λ → 0⁺, i.e. the minimum-penalty curve
//! of the spline space through every sample, by Bregman iteration (iterated Tikhonov): fit with
//! a small λ to targets shifted by eₛ, then eₛ ← eₛ − r_s, until max |r_s| ≤ 1e-11 rad
//! (Osher et al. 2005; for linear problems this is the augmented-Lagrangian method).
//!
//! Never silently unconverged: a solver that does not reach its tolerance within `max_iter`
//! iterations returns [`Error::NotConverged`] with the iteration count and the last step.

pub mod banded;
pub mod min_energy;
pub mod model;
pub mod position;
pub mod so3;

use crate::error::{Error, Result};
use crate::jet::Jet;
use crate::quat::Quat;
use crate::vec3::{self, Vec3};
use banded::Band;
use model::{Cols, Model, MAXK};

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
    pub(crate) fn tuning(self) -> f64 {
        match self {
            Robust::None => f64::INFINITY,
            Robust::Huber => 1.345,
            Robust::Cauchy => 2.385,
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
            max_iter: 100,
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
    /// |r_s|, radians, per sample.
    pub residuals: Vec<f64>,
    /// Final IRLS weights (1 without a robust loss), per sample.
    pub robust_weights: Vec<f64>,
    /// The robust scale c used (∞ without a robust loss).
    pub robust_scale: f64,
    pub lambda: f64,
    /// tr A (effective degrees of freedom, in scalar observations).
    pub edf: f64,
    /// GCV(λ) at the solution.
    pub score: f64,
    pub iterations: usize,
    pub final_step: f64,
    pub converged: bool,
}

/// Progress callback: (stage, iteration, last step). Returning false cancels the fit.
pub type Progress<'a> = &'a mut dyn FnMut(&str, usize, f64) -> bool;

/// The data of a fit after validation.
struct Data {
    t: Vec<f64>,
    y: Vec<Quat>,
    w: Vec<f64>,
}

/// Validates times (finite, strictly increasing), quaternions and weights (finite, ≥ 0, not
/// all zero); weights are normalised to mean 1 over all samples.
fn validate(times: &[f64], quats: &[Quat], weights: Option<&[f64]>, min: usize, why: &str) -> Result<Data> {
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
                return Err(Error::invalid("times", format!("duplicate time {v} at index {i}")));
            }
            if v < times[i - 1] {
                return Err(Error::invalid(
                    "times",
                    format!("not increasing at index {i} ({v} after {})", times[i - 1]),
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
                    return Err(Error::invalid("weights", format!("negative weight {v} at index {i}")));
                }
                if v > 1e12 {
                    return Err(Error::invalid("weights", format!("weight {v} at index {i} exceeds 1e12")));
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

/// (t₀, Δt, segments) from the knot option.
fn knot_layout(knots: &Knots, t: &[f64]) -> Result<(f64, f64, usize)> {
    let (a, b) = (t[0], t[t.len() - 1]);
    let span = b - a;
    let segs_for = |h: f64| -> Result<usize> {
        let s = (span / h).round().max(1.0);
        if s > 5e7 {
            return Err(Error::invalid(
                "knots",
                format!("spacing {h} gives {s:e} knot intervals (limit 5e7)"),
            ));
        }
        Ok(s as usize)
    };
    match knots {
        Knots::Default => {
            let mut gaps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            let mid = gaps.len() / 2;
            gaps.select_nth_unstable_by(mid, |x, y| x.total_cmp(y));
            let s = segs_for(gaps[mid])?;
            Ok((a, span / s as f64, s))
        }
        Knots::Spacing(h) => {
            if !(h.is_finite() && *h > 0.0) {
                return Err(Error::invalid("knots", format!("expected a finite positive spacing, got {h}")));
            }
            if *h > span {
                return Err(Error::invalid(
                    "knots",
                    format!("spacing {h} exceeds the data's time span {span}"),
                ));
            }
            let s = segs_for(*h)?;
            Ok((a, span / s as f64, s))
        }
        Knots::Array(k) => {
            if k.len() < 2 {
                return Err(Error::invalid("knots", format!("expected at least 2 knots, got {}", k.len())));
            }
            for (i, &v) in k.iter().enumerate() {
                if !v.is_finite() {
                    return Err(Error::NonFinite { arg: "knots", index: i });
                }
                if i > 0 && v <= k[i - 1] {
                    return Err(Error::invalid(
                        "knots",
                        format!("not strictly increasing at index {i} ({v} after {})", k[i - 1]),
                    ));
                }
            }
            let tol = 1e-9 * span.max(1e-300);
            if (k[0] - a).abs() > tol || (k[k.len() - 1] - b).abs() > tol {
                return Err(Error::invalid(
                    "knots",
                    format!(
                        "knots must span the data's time range exactly: [{}, {}] given, data [{a}, {b}]",
                        k[0],
                        k[k.len() - 1]
                    ),
                ));
            }
            let s = k.len() - 1;
            let h = span / s as f64;
            for (i, &v) in k.iter().enumerate() {
                if (v - (a + i as f64 * h)).abs() > 1e-6 * h {
                    return Err(Error::invalid(
                        "knots",
                        format!("the fitted spline uses uniform knots; knot {i} = {v} is off the uniform grid (spacing {h})"),
                    ));
                }
            }
            Ok((a, h, s))
        }
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] (n ≤ 8), Golub–Welsch by Newton on P_n.
pub fn gauss_legendre01(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pm = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * pn - pm) / (x * x - 1.0);
            let dx = pn / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (1.0 - x), 0.5 * w));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// The Gauss–Newton pieces at one linearisation.
struct Lin {
    g: Band,
    p: Band,
    gd: Vec<f64>,
    gp: Vec<f64>,
    rwr: f64,
    pcp: f64,
    nobs: f64,
}

/// Data residual vectors r_s − e_s and angles |r_s| at the current model.
fn residuals(model: &Model, data: &Data, offs: &[Vec3]) -> (Vec<Vec3>, Vec<f64>) {
    let mut rv = Vec::with_capacity(data.t.len());
    let mut ang = Vec::with_capacity(data.t.len());
    for (s, &t) in data.t.iter().enumerate() {
        let (i, u) = model.locate(t);
        let q = model.value::<1>(i, Jet::constant(u)).value();
        let r = so3::log(q.conj() * data.y[s]);
        ang.push(vec3::norm(r));
        rv.push(vec3::sub(r, offs[s]));
    }
    (rv, ang)
}

fn penalty_value<const N: usize>(model: &Model, m: usize, nodes: &[(f64, f64)]) -> f64 {
    let mut acc = 0.0;
    for i in 0..model.segments() {
        for &(u, w) in nodes {
            let q = model.value::<N>(i, Jet::variable(u, 1.0 / model.dt));
            let om = Model::omega(&q);
            let p: Vec3 = std::array::from_fn(|r| om[r].derivative(m));
            acc += w * model.dt * vec3::dot(p, p);
        }
    }
    acc
}

fn penalty_lin<const N: usize>(
    model: &Model,
    m: usize,
    nodes: &[(f64, f64)],
    pb: &mut Band,
    gp: &mut [f64],
) -> f64 {
    let k = model.order;
    let nb = 3 * k;
    let mut blk = vec![0.0; nb * nb];
    let mut jac = vec![[0.0f64; 3]; nb];
    let mut cols: Cols<N> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
    let mut pcp = 0.0;
    for i in 0..model.segments() {
        blk.iter_mut().for_each(|v| *v = 0.0);
        for &(u, w) in nodes {
            let c = w * model.dt;
            let q = model.value_and_columns::<N>(i, Jet::variable(u, 1.0 / model.dt), &mut cols);
            let om = Model::omega(&q);
            let p: Vec3 = std::array::from_fn(|r| om[r].derivative(m));
            pcp += c * vec3::dot(p, p);
            for mm in 0..k {
                for cc in 0..3 {
                    let dw = Model::delta_omega(&om, &cols[mm][cc]);
                    jac[3 * mm + cc] = std::array::from_fn(|r| dw[r].derivative(m));
                }
            }
            for a in 0..nb {
                gp[3 * i + a] += c * vec3::dot(jac[a], p);
                for b in 0..=a {
                    blk[a * nb + b] += c * vec3::dot(jac[a], jac[b]);
                }
            }
        }
        pb.add_block(3 * i, nb, &blk, 1.0);
    }
    pcp
}

fn linearise(
    model: &Model,
    data: &Data,
    w: &[f64],
    offs: &[Vec3],
    pen: Penalty,
    nodes: &[(f64, f64)],
) -> Lin {
    let k = model.order;
    let nb = 3 * k;
    let n = 3 * model.ctrl.len();
    let mut g = Band::zeros(n, nb - 1);
    let mut p = Band::zeros(n, nb - 1);
    let mut gd = vec![0.0; n];
    let mut gp = vec![0.0; n];
    let mut cols: Cols<1> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
    let mut blk = vec![0.0; nb * nb];
    let mut cur = usize::MAX;
    let mut rwr = 0.0;
    let mut nobs = 0.0;
    let mut jac = vec![[0.0f64; 3]; nb];
    for (s, &t) in data.t.iter().enumerate() {
        if w[s] == 0.0 {
            continue;
        }
        nobs += 3.0;
        let (i, u) = model.locate(t);
        if i != cur {
            if cur != usize::MAX {
                g.add_block(3 * cur, nb, &blk, 1.0);
            }
            blk.iter_mut().for_each(|v| *v = 0.0);
            cur = i;
        }
        let q = model.value_and_columns::<1>(i, Jet::constant(u), &mut cols).value();
        let r0 = so3::log(q.conj() * data.y[s]);
        let r = vec3::sub(r0, offs[s]);
        let jl = so3::jl_inv(r0);
        for mm in 0..k {
            for c in 0..3 {
                let x: Vec3 = std::array::from_fn(|t| cols[mm][c][t].value());
                let jx = so3::mat_vec(&jl, x);
                jac[3 * mm + c] = [-jx[0], -jx[1], -jx[2]];
            }
        }
        let ws = w[s];
        rwr += ws * vec3::dot(r, r);
        for a in 0..nb {
            gd[3 * i + a] += ws * vec3::dot(jac[a], r);
            for b in 0..=a {
                blk[a * nb + b] += ws * vec3::dot(jac[a], jac[b]);
            }
        }
    }
    if cur != usize::MAX {
        g.add_block(3 * cur, nb, &blk, 1.0);
    }
    let pcp = match pen {
        Penalty::Acceleration => penalty_lin::<3>(model, 1, nodes, &mut p, &mut gp),
        Penalty::Jerk => penalty_lin::<4>(model, 2, nodes, &mut p, &mut gp),
    };
    Lin { g, p, gd, gp, rwr, pcp, nobs }
}

fn cost(
    model: &Model,
    data: &Data,
    w: &[f64],
    offs: &[Vec3],
    pen: Penalty,
    nodes: &[(f64, f64)],
    lam: f64,
) -> f64 {
    let (rv, _) = residuals(model, data, offs);
    let d: f64 = rv.iter().zip(w).map(|(r, w)| w * vec3::dot(*r, *r)).sum();
    let p = if lam > 0.0 {
        match pen {
            Penalty::Acceleration => penalty_value::<3>(model, 1, nodes),
            Penalty::Jerk => penalty_value::<4>(model, 2, nodes),
        }
    } else {
        0.0
    };
    d + lam * p
}

/// GCV of the linearised problem at λ: (score, tr A, step δ).
fn gcv_at(lin: &Lin, lam: f64) -> Result<(f64, f64, Vec<f64>)> {
    let h = lin.g.axpy(lam, &lin.p);
    let l = h.cholesky()?;
    let rhs: Vec<f64> = lin.gd.iter().zip(&lin.gp).map(|(a, b)| -(a + lam * b)).collect();
    let d = l.solve(&rhs);
    let gdd = lin.g.matvec(&d);
    let rss = (lin.rwr + 2.0 * dotv(&d, &lin.gd) + dotv(&d, &gdd)).max(0.0);
    let tr = l.selected_inverse().trace_product(&lin.g);
    let den = lin.nobs - tr;
    let score = if den > 1e-9 * lin.nobs { lin.nobs * rss / (den * den) } else { f64::INFINITY };
    Ok((score, tr, d))
}

fn dotv(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Minimises GCV over log λ in [lo, hi] (coarse grid of `grid` points, then 9 golden-section
/// steps inside the best grid cell's neighbours: 0.6⁹ ≈ 1 % of two cells).
fn select_lambda(lin: &Lin, lo: f64, hi: f64, grid: usize) -> Result<(f64, f64)> {
    let (a, b) = (lo.ln(), hi.ln());
    let mut best = (f64::INFINITY, a);
    let xs: Vec<f64> = (0..grid).map(|i| a + (b - a) * i as f64 / (grid - 1) as f64).collect();
    let mut vals = vec![];
    for &x in &xs {
        let v = gcv_at(lin, x.exp()).map(|r| r.0).unwrap_or(f64::INFINITY);
        vals.push(v);
        if v < best.0 {
            best = (v, x);
        }
    }
    let ib = xs.iter().position(|&x| x == best.1).unwrap_or(0);
    let (mut l, mut r) = (xs[ib.saturating_sub(1)], xs[(ib + 1).min(grid - 1)]);
    let gr = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = r - gr * (r - l);
    let mut d = l + gr * (r - l);
    let f = |x: f64| gcv_at(lin, x.exp()).map(|r| r.0).unwrap_or(f64::INFINITY);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..9 {
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
    for (x, v) in [(c, fc), (d, fd)] {
        if v < best.0 {
            best = (v, x);
        }
    }
    Ok((best.1.exp(), best.0))
}

/// Initial control rotations: the data slerped at each control point's Greville time.
fn initial_controls(data: &Data, t0: f64, dt: f64, segs: usize, k: usize) -> Vec<Quat> {
    let n = segs + k - 1;
    let t = &data.t;
    let mut out = Vec::with_capacity(n);
    let mut j = 0usize;
    for m in 0..n {
        let tau = (t0 + (m as f64 - (k as f64 - 2.0) / 2.0) * dt).clamp(t[0], t[t.len() - 1]);
        while j + 2 < t.len() && t[j + 1] <= tau {
            j += 1;
        }
        let (a, b) = (t[j], t[(j + 1).min(t.len() - 1)]);
        let u = if b > a { ((tau - a) / (b - a)).clamp(0.0, 1.0) } else { 0.0 };
        let qa = data.y[j];
        let qb = data.y[(j + 1).min(t.len() - 1)].canonical_to(qa);
        let r = so3::log(qa.conj() * qb);
        let q = (qa * so3::exp(vec3::scale(r, u))).normalize();
        out.push(match out.last() {
            Some(&p) => q.canonical_to(p),
            None => q,
        });
    }
    out
}

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
            return Err(Error::invalid("smoothing", format!("expected \"auto\" or a finite λ ≥ 0, got {l}")));
        }
    }
    if let Some(c) = opts.robust_scale {
        if !(c.is_finite() && c > 0.0) {
            return Err(Error::invalid(
                "robust_scale",
                format!("expected a finite positive angle (radians), got {c}"),
            ));
        }
    }
    if opts.max_iter == 0 || opts.max_iter > 100_000 {
        return Err(Error::invalid("max_iter", format!("expected 1 … 100000, got {}", opts.max_iter)));
    }
    if !(opts.tol.is_finite() && opts.tol > 0.0) {
        return Err(Error::invalid("tol", format!("expected a finite positive tolerance, got {}", opts.tol)));
    }
    let (t0, dt, segs) = knot_layout(&opts.knots, &data.t)?;
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
    let model = Model::new(initial_controls(&data, t0, dt, segs, k), dt, t0, k);
    solve(model, &data, opts, progress)
}

fn pen_name(p: Penalty) -> &'static str {
    match p {
        Penalty::Acceleration => "acceleration",
        Penalty::Jerk => "jerk",
    }
}

fn solve(mut model: Model, data: &Data, opts: &FitOptions, progress: Progress<'_>) -> Result<FitResult> {
    let pen = opts.penalty;
    let m = pen.m();
    let k = model.order;
    let nodes = gauss_legendre01(k);
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
    let mut lam_frozen = !auto;
    let mut offs = vec![[0.0; 3]; n];
    let mut w = data.w.clone();
    let mut robust_on = false;
    let mut c_robust = f64::INFINITY;
    let mut step = f64::INFINITY;
    let mut it = 0usize;
    let mut mu = 0.0f64;
    let mut bregman = 0usize;
    loop {
        it += 1;
        if it > opts.max_iter {
            return Err(Error::NotConverged { what: "fit", iterations: opts.max_iter, step, tol: opts.tol });
        }
        if robust_on {
            let (_, ang) = residuals(&model, data, &offs);
            for s in 0..n {
                w[s] = data.w[s] * opts.robust.weight(ang[s], c_robust);
            }
        }
        let lin = linearise(&model, data, &w, &offs, pen, &nodes);
        // The largest λ double precision resolves: beyond λ·max diag P / max diag G ≈ 3e16
        // the normal matrix loses positive definiteness in rounding (measured: 4e16 works,
        // 4e17 fails), and the curve is the minimum-penalty curve long before.
        let dmax = |b: &Band| b.diag().into_iter().fold(0.0, f64::max);
        let lam_max = 3e16 * dmax(&lin.g) / dmax(&lin.p).max(f64::MIN_POSITIVE);
        if !auto && !interpolate && lam > lam_max {
            return Err(Error::invalid(
                "smoothing",
                format!(
                    "λ = {lam:e} is beyond what double precision resolves for these knots and data \
                     (λ ≤ {lam_max:.1e}); the fit is the minimum-penalty curve well before that"
                ),
            ));
        }
        let mut lam_changed = false;
        if !lam_frozen {
            let (lo, hi, grid) = if lam.is_nan() {
                let hi = lam_of(span).min(lam_max);
                (lam_of(0.3 * dts).min(hi / 1e6), hi, 13)
            } else {
                (lam / 30.0, (lam * 30.0).min(lam_max), 5)
            };
            let (l_new, _) = select_lambda(&lin, lo, hi, grid)?;
            lam_changed = lam.is_nan() || (l_new / lam).ln().abs() > 0.01;
            if !lam.is_nan() && !lam_changed {
                lam_frozen = true;
            }
            lam = l_new;
        }
        let c0 = lin.rwr + lam * lin.pcp;
        // Gauss–Newton step; Levenberg–Marquardt damping when the cost does not decrease.
        let mut accepted = None;
        for _ in 0..30 {
            let mut h = lin.g.axpy(lam, &lin.p);
            if mu > 0.0 {
                let diag = h.diag();
                let dmax = diag.iter().cloned().fold(0.0, f64::max);
                for (i, d) in diag.iter().enumerate() {
                    let idx = h.idx(i, i);
                    h.a[idx] += mu * d.max(1e-12 * dmax);
                }
            }
            let l = match h.cholesky() {
                Ok(l) => l,
                Err(_) => {
                    mu = if mu == 0.0 { 1e-6 } else { mu * 10.0 };
                    continue;
                }
            };
            let rhs: Vec<f64> = lin.gd.iter().zip(&lin.gp).map(|(a, b)| -(a + lam * b)).collect();
            let d = l.solve(&rhs);
            let mut trial = model.clone();
            trial.retract(&d);
            let c1 = cost(&trial, data, &w, &offs, pen, &nodes, lam);
            let smax = (0..d.len() / 3)
                .map(|i| {
                    (d[3 * i] * d[3 * i] + d[3 * i + 1] * d[3 * i + 1] + d[3 * i + 2] * d[3 * i + 2]).sqrt()
                })
                .fold(0.0, f64::max);
            if c1 <= c0 * (1.0 + 1e-12) + 1e-300 || smax < opts.tol {
                accepted = Some((trial, smax));
                mu = if mu > 0.0 { mu / 10.0 } else { 0.0 };
                if mu < 1e-9 {
                    mu = 0.0;
                }
                break;
            }
            mu = if mu == 0.0 { 1e-4 } else { mu * 10.0 };
        }
        let Some((trial, smax)) = accepted else {
            return Err(Error::NotConverged {
                what: "fit (no descent step found)",
                iterations: it,
                step,
                tol: opts.tol,
            });
        };
        model = trial;
        step = smax;
        if !progress("fit", it, step) {
            return Err(Error::invalid("progress", "fit cancelled by the progress callback"));
        }
        if step > opts.tol || lam_changed {
            continue;
        }
        // Converged at this λ, weights and offsets.
        if !lam_frozen {
            continue;
        }
        if interpolate {
            let (rv, ang) = residuals(&model, data, &offs);
            let worst = ang.iter().cloned().fold(0.0, f64::max);
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
                lam_frozen = false;
            }
            continue;
        }
        // IRLS (robust_on): converged when the weights no longer move the curve (step ≤ tol).
        break;
    }
    let (_, ang) = residuals(&model, data, &vec![[0.0; 3]; n]);
    // Score and edf at the solution (for fixed λ: the GCV of the fixed λ).
    let (score, edf) = if !interpolate {
        let lin = linearise(&model, data, &w, &offs, pen, &nodes);
        let (s, tr, _) = gcv_at(&lin, lam)?;
        (s, tr)
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
        order: k,
        residuals: ang,
        robust_weights,
        robust_scale: c_robust,
        lambda: lam,
        edf,
        score,
        iterations: it,
        final_step: step,
        converged: true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for n in 1..=8 {
            let nodes = gauss_legendre01(n);
            for deg in 0..2 * n {
                let s: f64 = nodes.iter().map(|(x, w)| w * x.powi(deg as i32)).sum();
                assert!((s - 1.0 / (deg as f64 + 1.0)).abs() < 1e-14, "n {n} deg {deg}");
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
