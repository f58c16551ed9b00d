//! Gyro-aided fitting: the SO(3) fit of [`super`] with a gyroscope term, jointly estimating the
//! gyroscope's bias, time offset, mounting rotation and (optionally) scale.
//!
//! Measurement model (the convention of `quatspline.imu.calibrate` and `SensorModel`; rates in
//! rad/s, the sensor frame on the left): a gyroscope sample stamped t_j measures
//!   m_j = K R_bsᵀ ω_b(t_j + δ) + b + noise,
//! ω_b the fitted curve's body angular velocity, R_bs the sensor's orientation in the body
//! frame, b the bias (sensor frame), δ the time offset (δ > 0: the IMU's stamps run behind the
//! orientations' clock), K = diag(1 + s) the scale (1 unless estimated).
//!
//! Objective (orientation noise σ_q per axis, gyroscope noise σ_g per axis and sample), scaled
//! by σ_q² so that λ keeps the meaning it has without a gyroscope:
//!   Σ_s w_s |r_s|² + κ Σ_j |e_j|² + λ ∫ |p(t)|² dt,   κ = σ_q² / σ_g²,
//!   r_s = Log(q(t_s)⁻¹ y_s),   e_j = K R_bsᵀ ω_b(t_j + δ) + b − m_j.
//!
//! Jacobians of e_j (analytic; tested against finite differences): the curve moves as
//! q ← q Exp(ξ), ξ = Σ_m X_m(t) δ_m (`model.rs`), under which ω_b ← ω_b + ξ̇ + ω_b × ξ, so
//!   ∂e/∂δ_m = K R_bsᵀ (Ẋ_m + [ω_b]× X_m)   (the columns of [`Model::value_and_factors`]),
//!   ∂e/∂b = I,   ∂e/∂δ = K R_bsᵀ ω̇_b(t_j + δ),
//!   ∂e/∂θ = K [R_bsᵀ ω_b]×   (R_bs ← R_bs Exp(θ): R_bsᵀ v ← R_bsᵀ v − θ × R_bsᵀ v),
//!   ∂e/∂s_c = (R_bsᵀ ω_b)_c e_c.
//!
//! Normal equations: the control points' block is banded exactly as without the gyroscope
//! (each sample touches the k control points of its knot interval); the p ≤ 10 global
//! parameters border it,
//!   [H  B] [Δc]   [−g_c]
//!   [Bᵀ C] [Δθ] = [−g_θ],
//! and are eliminated by the Schur complement S = C − Bᵀ H⁻¹ B (p banded solves with the
//! factor of H, then a dense p × p Cholesky): Δθ = S⁻¹(−g_θ − Bᵀ y), y = H⁻¹(−g_c),
//! Δc = y − H⁻¹ B Δθ. Time and memory stay linear in the samples.
//! Gauss–Newton with Levenberg–Marquardt damping when a step does not lower the cost.
//!
//! Uncertainty: the covariance of the global parameters is σ_q² S⁻¹ at the solution: the
//! (θ, θ) block of σ_q² M⁻¹, M the whole bordered Gauss–Newton matrix (block inversion), i.e.
//! the marginal covariance with the curve integrated out, not the corner C alone. σ_q² is
//! the scale of the objective above (the orientation residuals have variance σ_q², the
//! gyroscope's σ_g² = σ_q²/κ); the penalty acts as the curve's prior, as in
//! [`super::covariance`] (H = G + λP + κ G_g there), so this is conditional on the stated
//! σ_q and σ_g. Effective degrees of freedom and score (of the orientation term, so that
//! they read as those of a plain fit; see [`marginal`]): tr A_q = tr((M⁻¹)_cc G_q) and
//! n_obs RSS_q / (n_obs − tr A_q)².
//! Bias of the estimates (not of the covariance): with knots commensurate with the gyroscope
//! samples (the default, one per sample) every sample sits at the same phase t_j + δ − knot
//! inside its interval, so the spline's capacity to follow the gyroscope's noise (the trace
//! of the gyroscope term's hat matrix) varies periodically with δ and the joint minimum
//! prefers the δ of the largest capacity (measured, 10 Hz keys: δ off by 2.5 standard
//! deviations at 100 Hz, 8 at 200 Hz); a penalty one sample wide flattens ω enough to bias
//! the bias and rotation by about one standard deviation. At knots 0.618 spacings (the
//! golden ratio's conjugate: the phases equidistribute) and a bandwidth of 0.1 spacings the
//! estimates are unbiased to 0.3 standard deviations and the covariance matches their
//! scatter (Monte Carlo, `tests/fitting/test_fit_gyro.py`); not the default, because the
//! Gauss–Newton iteration then converges slowly or not at all on some inputs (measured:
//! 56–122 iterations at bandwidth 1, none in 1000 on a short noise-free record at 0.1).

use super::assembly::{data_half, pen_half, penalty_nodes, sums_only};
use super::banded::Band;
use super::lambda::dotv;
use super::layout::Layout;
use super::model::{Factors, Model, MAXK};
use super::so3;
use super::types::{validate, FitOptions, FitResult, Knots, Penalty, Progress, Robust, Smoothing};
use crate::error::{Error, Result, Short};
use crate::jet::Jet;
use crate::quadrature::gauss_legendre01;
use crate::quat::Quat;
use crate::vec3::{self, Vec3};

/// Which sensor parameters the gyro-aided fit estimates (the others are held at their
/// starting values).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Estimate {
    pub bias: bool,
    pub time_offset: bool,
    pub rotation: bool,
    pub scale: bool,
}

impl Estimate {
    /// Parses names among "bias", "time_offset", "rotation", "scale".
    pub fn parse<'s>(names: impl IntoIterator<Item = &'s str>) -> Result<Self> {
        let mut e = Estimate::default();
        for n in names {
            let slot = match n {
                "bias" => &mut e.bias,
                "time_offset" => &mut e.time_offset,
                "rotation" => &mut e.rotation,
                "scale" => &mut e.scale,
                _ => {
                    return Err(Error::invalid(
                        "estimate",
                        format!("unknown parameter {n:?}; valid: bias, time_offset, rotation, scale"),
                    ))
                }
            };
            if *slot {
                return Err(Error::invalid("estimate", format!("{n:?} named twice")));
            }
            *slot = true;
        }
        Ok(e)
    }

    /// The names of the global parameters in the order of the covariance's rows.
    pub fn names(&self) -> Vec<&'static str> {
        let mut v = vec![];
        if self.bias {
            v.extend(["bias_x", "bias_y", "bias_z"]);
        }
        if self.time_offset {
            v.push("time_offset");
        }
        if self.rotation {
            v.extend(["rotation_x", "rotation_y", "rotation_z"]);
        }
        if self.scale {
            v.extend(["scale_x", "scale_y", "scale_z"]);
        }
        v
    }

    fn count(&self) -> usize {
        self.names().len()
    }
}

/// The sensor parameters (estimated or held).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    /// b, rad/s, sensor frame.
    pub bias: Vec3,
    /// δ, seconds.
    pub time_offset: f64,
    /// R_bs (the sensor's orientation in the body frame).
    pub rotation: Quat,
    /// s in K = diag(1 + s).
    pub scale: Vec3,
}

impl Default for Sensor {
    fn default() -> Self {
        Sensor { bias: [0.0; 3], time_offset: 0.0, rotation: Quat::IDENTITY, scale: [0.0; 3] }
    }
}

impl Sensor {
    /// The parameters moved by Δθ (laid out as [`Estimate::names`]).
    fn retracted(&self, est: &Estimate, d: &[f64]) -> Sensor {
        let mut s = *self;
        let mut i = 0;
        if est.bias {
            s.bias = vec3::add(s.bias, [d[i], d[i + 1], d[i + 2]]);
            i += 3;
        }
        if est.time_offset {
            s.time_offset += d[i];
            i += 1;
        }
        if est.rotation {
            s.rotation = (s.rotation * so3::exp([d[i], d[i + 1], d[i + 2]])).normalize();
            i += 3;
        }
        if est.scale {
            s.scale = vec3::add(s.scale, [d[i], d[i + 1], d[i + 2]]);
        }
        s
    }
}

/// Options of [`fit_gyro`] beyond [`FitOptions`].
#[derive(Debug, Clone)]
pub struct GyroOptions {
    /// σ_g: the gyroscope's noise per axis and sample, rad/s.
    pub sigma_gyro: f64,
    /// σ_q: the orientations' noise per axis, radians.
    pub sigma_orientation: f64,
    pub estimate: Estimate,
    /// Starting (or held) values.
    pub start: Sensor,
    /// The knot spacing for `Knots::Default` in gyroscope sample spacings (default 1; see
    /// the module doc on the time offset's bias).
    pub knots_per_sample: f64,
    /// The bandwidth of the default λ (`Smoothing::Auto`) in gyroscope sample spacings.
    pub bandwidth: f64,
}

impl Default for GyroOptions {
    fn default() -> Self {
        GyroOptions {
            sigma_gyro: 1e-3,
            sigma_orientation: 1e-3,
            estimate: Estimate { bias: true, time_offset: true, rotation: true, scale: false },
            start: Sensor::default(),
            knots_per_sample: 1.0,
            bandwidth: 1.0,
        }
    }
}

/// What [`fit_gyro`] returns.
#[derive(Debug, Clone)]
pub struct GyroFit {
    /// The curve; `edf` is the trace of the orientation term's hat matrix in the whole
    /// (curve and parameters) Gauss–Newton system and `score` the GCV score of the
    /// orientation term, n_obs RSS / (n_obs − edf)² ([`marginal`]).
    pub fit: FitResult,
    pub sensor: Sensor,
    pub estimate: Estimate,
    /// σ_q² S⁻¹, p × p row-major over [`Estimate::names`].
    pub covariance: Vec<f64>,
    /// e_j per gyroscope sample (sensor frame, rad/s).
    pub gyro_residuals: Vec<Vec3>,
    /// κ = σ_q² / σ_g².
    pub gyro_weight: f64,
}

/// A validated gyroscope record.
pub struct GyroData {
    pub t: Vec<f64>,
    pub w: Vec<Vec3>,
}

/// Checks the gyroscope record: finite, times strictly increasing inside [t_first, t_last].
pub fn validate_gyro(t: &[f64], w: &[Vec3], domain: (f64, f64)) -> Result<GyroData> {
    if w.len() != t.len() {
        return Err(Error::invalid(
            "gyro",
            format!("expected {} rates (one per gyro time), got {}", t.len(), w.len()),
        ));
    }
    if t.len() < 2 {
        return Err(Error::invalid("gyro", format!("needs at least 2 samples, got {}", t.len())));
    }
    for (i, &v) in t.iter().enumerate() {
        if !v.is_finite() {
            return Err(Error::NonFinite { arg: "gyro times", index: i });
        }
        if i > 0 && v <= t[i - 1] {
            return Err(Error::invalid(
                "gyro",
                format!(
                    "times not strictly increasing at index {i} ({} after {})",
                    Short(v),
                    Short(t[i - 1])
                ),
            ));
        }
        if v < domain.0 || v > domain.1 {
            return Err(Error::invalid(
                "gyro",
                format!(
                    "time {} at index {i} outside the orientations' time range [{}, {}]",
                    Short(v),
                    Short(domain.0),
                    Short(domain.1)
                ),
            ));
        }
    }
    for (i, r) in w.iter().enumerate() {
        if !r.iter().all(|x| x.is_finite()) {
            return Err(Error::NonFinite { arg: "gyro", index: i });
        }
    }
    Ok(GyroData { t: t.to_vec(), w: w.to_vec() })
}

/// The gyroscope term at `model`: value of Σ|e|² and, when `full`, its Gauss–Newton pieces
/// (band block added into `h` scaled by κ, gradients, border and corner).
struct GyroLin {
    sum: f64,
    grad: Vec<f64>,
    /// n × p row-major.
    border: Vec<f64>,
    /// p × p row-major.
    corner: Vec<f64>,
    grad_g: Vec<f64>,
}

/// Per sample: e_j, ∂e/∂(the 3k control coordinates of its interval) and ∂e/∂θ.
struct SampleJac {
    seg: usize,
    e: Vec3,
    /// jac[a] = ∂e/∂c_a (a over 3k).
    jac: [Vec3; 3 * MAXK],
    /// ∂e/∂θ_p columns.
    glob: [Vec3; 10],
}

fn sample<const N: usize>(
    model: &Model,
    sen: &Sensor,
    est: &Estimate,
    t: f64,
    m: Vec3,
    with_jac: bool,
    mats: &mut Factors<N>,
) -> SampleJac {
    let k = model.order;
    let (i, u) = model.locate(t + sen.time_offset);
    let h = model.width(i);
    let q = model.value_and_factors::<N>(i, Jet::variable(u, 1.0 / h), mats);
    let om = Model::omega(&q);
    let w: Vec3 = std::array::from_fn(|r| om[r].value());
    let rt = sen.rotation.conj();
    let v = rt.rotate(w);
    let kd = vec3::add([1.0; 3], sen.scale);
    let kv: Vec3 = std::array::from_fn(|r| kd[r] * v[r]);
    let e = vec3::sub(vec3::add(kv, sen.bias), m);
    let mut out = SampleJac { seg: i, e, jac: [[0.0; 3]; 3 * MAXK], glob: [[0.0; 3]; 10] };
    if !with_jac {
        return out;
    }
    let kr = |x: Vec3| -> Vec3 {
        let y = rt.rotate(x);
        std::array::from_fn(|r| kd[r] * y[r])
    };
    // δω_b of each factor column, then the chain-Jacobian right factors (as the penalty).
    let mut ef = [[[0.0f64; 3]; 3]; MAXK];
    for (j, efj) in ef.iter_mut().enumerate().take(k) {
        for (cc, efjc) in efj.iter_mut().enumerate() {
            let col = [mats[j][0][cc], mats[j][1][cc], mats[j][2][cc]];
            *efjc = super::assembly::delta_omega_deriv(&om, &col, 0);
        }
    }
    for mm in 0..k {
        for cc in 0..3 {
            let mut x = if mm == 0 { ef[0][cc] } else { [0.0; 3] };
            if mm >= 1 {
                let jr = model.chain_jacobians(i + mm).0;
                for l in 0..3 {
                    x = vec3::add(x, vec3::scale(ef[mm][l], jr[l][cc]));
                }
            }
            if mm + 1 < k {
                let jl = model.chain_jacobians(i + mm + 1).1;
                for l in 0..3 {
                    x = vec3::sub(x, vec3::scale(ef[mm + 1][l], jl[l][cc]));
                }
            }
            out.jac[3 * mm + cc] = kr(x);
        }
    }
    let mut p = 0;
    if est.bias {
        for c in 0..3 {
            let mut col = [0.0; 3];
            col[c] = 1.0;
            out.glob[p] = col;
            p += 1;
        }
    }
    if est.time_offset {
        let wd: Vec3 = std::array::from_fn(|r| om[r].derivative(1));
        out.glob[p] = kr(wd);
        p += 1;
    }
    if est.rotation {
        // K [v]× e_c = K (v × e_c)
        for c in 0..3 {
            let mut ec = [0.0; 3];
            ec[c] = 1.0;
            let x = vec3::cross(v, ec);
            out.glob[p] = std::array::from_fn(|r| kd[r] * x[r]);
            p += 1;
        }
    }
    if est.scale {
        for c in 0..3 {
            let mut col = [0.0; 3];
            col[c] = v[c];
            out.glob[p] = col;
            p += 1;
        }
    }
    out
}

/// Σ|e|², and with `h` the Gauss–Newton pieces (κ-weighted band blocks added into `h`).
fn gyro_lin(
    model: &Model,
    g: &GyroData,
    sen: &Sensor,
    est: &Estimate,
    kappa: f64,
    h: Option<&mut Band>,
) -> GyroLin {
    let k = model.order;
    let nb = 3 * k;
    let np = est.count();
    let n = 3 * model.ctrl.len();
    let full = h.is_some();
    let mut mats: Factors<3> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
    let mut out = GyroLin {
        sum: 0.0,
        grad: if full { vec![0.0; n] } else { vec![] },
        border: if full { vec![0.0; n * np] } else { vec![] },
        corner: vec![0.0; np * np],
        grad_g: vec![0.0; np],
    };
    let mut blk = vec![0.0; nb * nb];
    let mut cur = usize::MAX;
    let mut hb = h;
    for (&tj, &wj) in g.t.iter().zip(&g.w) {
        let s = sample::<3>(model, sen, est, tj, wj, full, &mut mats);
        out.sum += vec3::dot(s.e, s.e);
        let Some(h) = hb.as_deref_mut() else { continue };
        if s.seg != cur {
            if cur != usize::MAX {
                h.add_block(3 * cur, nb, &blk, kappa);
            }
            blk.iter_mut().for_each(|v| *v = 0.0);
            cur = s.seg;
        }
        let off = 3 * s.seg;
        for a in 0..nb {
            out.grad[off + a] += kappa * vec3::dot(s.jac[a], s.e);
            for b in 0..=a {
                blk[a * nb + b] += vec3::dot(s.jac[a], s.jac[b]);
            }
            for p in 0..np {
                out.border[(off + a) * np + p] += kappa * vec3::dot(s.jac[a], s.glob[p]);
            }
        }
        for p in 0..np {
            out.grad_g[p] += kappa * vec3::dot(s.glob[p], s.e);
            for q in 0..np {
                out.corner[p * np + q] += kappa * vec3::dot(s.glob[p], s.glob[q]);
            }
        }
    }
    if let Some(h) = hb {
        if cur != usize::MAX {
            h.add_block(3 * cur, nb, &blk, kappa);
        }
    }
    out
}

/// Dense Cholesky of a p × p SPD matrix (row-major, in place, lower factor); Err if not PD.
fn dense_cholesky(a: &mut [f64], p: usize) -> Result<()> {
    for j in 0..p {
        let mut d = a[j * p + j];
        for l in 0..j {
            d -= a[j * p + l] * a[j * p + l];
        }
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::invalid("gyro", "the sensor parameters are not determined by the data"));
        }
        let d = d.sqrt();
        a[j * p + j] = d;
        for i in j + 1..p {
            let mut s = a[i * p + j];
            for l in 0..j {
                s -= a[i * p + l] * a[j * p + l];
            }
            a[i * p + j] = s / d;
        }
    }
    Ok(())
}

fn dense_solve(l: &[f64], p: usize, b: &[f64]) -> Vec<f64> {
    let mut y = b.to_vec();
    for i in 0..p {
        for k in 0..i {
            y[i] -= l[i * p + k] * y[k];
        }
        y[i] /= l[i * p + i];
    }
    for i in (0..p).rev() {
        for k in i + 1..p {
            y[i] -= l[k * p + i] * y[k];
        }
        y[i] /= l[i * p + i];
    }
    y
}

/// The Schur complement of the bordered matrix [H B; Bᵀ C] on the p global parameters, with
/// `hf` the banded Cholesky factor of H: X = H⁻¹ B (p banded solves, column q in `x[q]`) and
/// the dense Cholesky factor of S = C − Bᵀ X. S⁻¹ is the (θ, θ) block of the inverse of the
/// whole matrix, and (H⁻¹ + X S⁻¹ Xᵀ) its (c, c) block (block inversion).
struct Schur {
    x: Vec<Vec<f64>>,
    /// Lower factor of S, p × p row-major.
    s: Vec<f64>,
    np: usize,
}

impl Schur {
    fn new(hf: &Band, border: &[f64], corner: &[f64], np: usize) -> Result<Schur> {
        let n = hf.n;
        let x: Vec<Vec<f64>> = (0..np)
            .map(|p| {
                let col: Vec<f64> = (0..n).map(|i| border[i * np + p]).collect();
                hf.solve(&col)
            })
            .collect();
        let mut s = corner.to_vec();
        for p in 0..np {
            for q in 0..np {
                let mut acc = 0.0;
                for i in 0..n {
                    acc += border[i * np + p] * x[q][i];
                }
                s[p * np + q] -= acc;
            }
        }
        // symmetrise (rounding)
        for p in 0..np {
            for q in 0..p {
                let m = 0.5 * (s[p * np + q] + s[q * np + p]);
                s[p * np + q] = m;
                s[q * np + p] = m;
            }
        }
        dense_cholesky(&mut s, np)?;
        Ok(Schur { x, s, np })
    }

    /// S⁻¹, p × p row-major.
    fn inverse(&self) -> Vec<f64> {
        let np = self.np;
        let mut inv = vec![0.0; np * np];
        for p in 0..np {
            let mut e = vec![0.0; np];
            e[p] = 1.0;
            let col = dense_solve(&self.s, np, &e);
            for q in 0..np {
                inv[q * np + p] = col[q];
            }
        }
        inv
    }
}

/// The bordered solve of [H B; Bᵀ C][x; θ] = [r; r_θ] with `hf` the banded Cholesky factor of
/// H, by the Schur complement on the p global parameters: y = H⁻¹ r,
/// θ = S⁻¹ (r_θ − Bᵀ y), x = y − X θ. Returns (x, θ).
fn bordered_solve(
    hf: &Band,
    border: &[f64],
    corner: &[f64],
    np: usize,
    r: &[f64],
    rg: &[f64],
) -> Result<(Vec<f64>, Vec<f64>)> {
    let n = r.len();
    let y = hf.solve(r);
    if np == 0 {
        return Ok((y, vec![]));
    }
    let sc = Schur::new(hf, border, corner, np)?;
    let mut rhs = rg.to_vec();
    for (p, v) in rhs.iter_mut().enumerate() {
        for i in 0..n {
            *v -= border[i * np + p] * y[i];
        }
    }
    let th = dense_solve(&sc.s, np, &rhs);
    let mut x = y;
    for (q, xq) in sc.x.iter().enumerate() {
        for i in 0..n {
            x[i] -= xq[i] * th[q];
        }
    }
    Ok((x, th))
}

/// At the solution, from the factor `hf` of H = G_q + λP + κ G_g (the control points' block)
/// and the orientation term's G_q: (S⁻¹, tr A_q) with S the Schur complement of the
/// bordered matrix on the global parameters and A_q the hat matrix of the orientation term,
///   tr A_q = tr((M⁻¹)_cc G_q) = tr(H⁻¹ G_q) + tr(S⁻¹ Xᵀ G_q X),   X = H⁻¹ B,
/// M the whole bordered matrix ((M⁻¹)_cc = H⁻¹ + X S⁻¹ Xᵀ by block inversion; tr(H⁻¹ G_q) by
/// the selected inversion of `banded.rs`).
fn marginal(hf: &Band, gq: &Band, border: &[f64], corner: &[f64], np: usize) -> Result<(Vec<f64>, f64)> {
    let base = hf.trace_inverse_product(gq);
    if np == 0 {
        return Ok((vec![], base));
    }
    let sc = Schur::new(hf, border, corner, np)?;
    let inv = sc.inverse();
    let gx: Vec<Vec<f64>> = sc.x.iter().map(|x| gq.matvec(x)).collect();
    let mut extra = 0.0;
    for p in 0..np {
        for q in 0..np {
            extra += inv[p * np + q] * dotv(&sc.x[p], &gx[q]);
        }
    }
    Ok((inv, base + extra))
}

/// λ of the default (`Smoothing::Auto` with a gyroscope): the penalty's equivalent kernel
/// bandwidth h = `bandwidth` gyroscope spacings against the gyroscope term, which constrains
/// ω at ρ_g samples per time unit with weight κ: λ = κ ρ_g h^{2m} (smoothing ω with the m-th
/// derivative penalised, Silverman 1984).
pub fn default_lambda(kappa: f64, rate: f64, h: f64, pen: Penalty) -> f64 {
    kappa * rate * h.powi(2 * pen.m() as i32)
}

/// Gyro-aided fit: orientations (`times`, `quats`, `weights`) with a gyroscope record
/// (`gyro_t`, `gyro_w`, rad/s, sensor frame), see the module doc. The orientation part of
/// `opts` is used as in [`super::fit`] except: `Knots::Default` puts one knot interval per
/// `knots_per_sample` gyroscope spacings; `Smoothing::Auto` is [`default_lambda`]; robust
/// losses and adaptive smoothing are not available.
#[allow(clippy::too_many_arguments)]
pub fn fit_gyro(
    times: &[f64],
    quats: &[Quat],
    weights: Option<&[f64]>,
    gyro_t: &[f64],
    gyro_w: &[Vec3],
    opts: &FitOptions,
    gopts: &GyroOptions,
    progress: Progress<'_>,
) -> Result<GyroFit> {
    let m = opts.penalty.m();
    let data = validate(times, quats, weights, m + 1, "for a gyro-aided fit")?;
    if opts.robust != Robust::None {
        return Err(Error::invalid("robust", "robust losses are not available with a gyroscope"));
    }
    let n = data.t.len();
    let g = validate_gyro(gyro_t, gyro_w, (data.t[0], data.t[n - 1]))?;
    for (name, v) in [("gyro_noise", gopts.sigma_gyro), ("noise_std", gopts.sigma_orientation)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(
                name,
                format!("expected a finite positive standard deviation, got {}", Short(v)),
            ));
        }
    }
    for (name, v) in [("knots_per_sample", gopts.knots_per_sample), ("bandwidth", gopts.bandwidth)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(name, format!("expected a finite positive number, got {}", Short(v))));
        }
    }
    let k = opts.order.unwrap_or(opts.penalty.default_order());
    if !(m + 3..=MAXK).contains(&k) {
        return Err(Error::invalid(
            "order",
            format!("expected {} ≤ order ≤ {MAXK} for this penalty, got {k}", m + 3),
        ));
    }
    let mut gaps: Vec<f64> = g.t.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = gaps.len() / 2;
    gaps.select_nth_unstable_by(mid, |x, y| x.total_cmp(y));
    let dtg = gaps[mid];
    let span = data.t[n - 1] - data.t[0];
    let knots = match &opts.knots {
        Knots::Default => Knots::Spacing((gopts.knots_per_sample * dtg).min(span)),
        o => o.clone(),
    };
    let lay = super::fit_layout(&knots, &data.t, k)?;
    let kappa = (gopts.sigma_orientation / gopts.sigma_gyro).powi(2);
    let lam = match opts.smoothing {
        Smoothing::Auto => default_lambda(kappa, 1.0 / dtg, gopts.bandwidth * dtg, opts.penalty),
        Smoothing::Fixed(l) => {
            if !(l.is_finite() && l > 0.0) {
                return Err(Error::invalid(
                    "smoothing",
                    format!("expected \"auto\" or a finite λ > 0 with a gyroscope, got {}", Short(l)),
                ));
            }
            l
        }
    };
    // Start: the plain fit of the orientations (their own knots, λ by GCV), resampled.
    let start_opts = FitOptions { knots: Knots::Default, smoothing: Smoothing::Auto, ..opts.clone() };
    let plain = super::fit(times, quats, weights, &start_opts, &mut |_, _, _| true)?;
    let pm = Model::with_layout(plain.ctrl.clone(), {
        let b = plain.breaks.clone();
        match b {
            Some(b) => Layout::nonuniform(b, plain.order),
            None => Layout::uniform(plain.t0, plain.dt, plain.ctrl.len() + 1 - plain.order, plain.order),
        }
    });
    let ns = 2 * (lay.segs + k);
    let ts: Vec<f64> = (0..=ns).map(|i| data.t[0] + span * i as f64 / ns as f64).collect();
    let ys: Vec<Quat> = ts
        .iter()
        .map(|&t| {
            let (i, u) = pm.locate(t);
            pm.value::<1>(i, Jet::constant(u)).value()
        })
        .collect();
    let anchors = super::types::Data { t: ts, y: ys.clone(), w: vec![1.0; ys.len()] };
    let init = super::start::initial_controls_from(&anchors, &ys, &lay);
    let model = Model::with_layout(init, lay);
    solve_gyro(model, &data, &g, opts, gopts, kappa, lam, progress)
}

#[allow(clippy::too_many_arguments)]
fn solve_gyro(
    mut model: Model,
    data: &super::types::Data,
    g: &GyroData,
    opts: &FitOptions,
    gopts: &GyroOptions,
    kappa: f64,
    lam: f64,
    progress: Progress<'_>,
) -> Result<GyroFit> {
    let est = gopts.estimate;
    let np = est.count();
    let pen = opts.penalty;
    let nodes = gauss_legendre01(penalty_nodes(model.order, pen.m(), false));
    let offs = vec![[0.0; 3]; data.t.len()];
    let w = &data.w;
    let mut sen = gopts.start;
    let span = data.t[data.t.len() - 1] - data.t[0];
    let cost_at = |model: &Model, sen: &Sensor| -> f64 {
        data_half(model, data, w, &offs, sums_only()).sum
            + lam * pen_half(model, pen, &nodes, sums_only(), None).sum
            + kappa * gyro_lin(model, g, sen, &est, kappa, None).sum
    };
    let mut mu = 0.0f64;
    let mut it = 0usize;
    let mut step = f64::INFINITY;
    let mut last_step;
    let tol = opts.tol.max(1e-12);
    loop {
        it += 1;
        last_step = step;
        if it > opts.max_iter {
            return Err(Error::NotConverged {
                what: "gyro-aided fit",
                iterations: opts.max_iter,
                step: last_step,
                tol,
            });
        }
        let dh = data_half(&model, data, w, &offs, Band::zeros(0, 0));
        let ph = pen_half(&model, pen, &nodes, Band::zeros(0, 0), None);
        let mut hm = dh.band;
        hm.axpy_assign(lam, &ph.band);
        let gl = gyro_lin(&model, g, &sen, &est, kappa, Some(&mut hm));
        let c0 = dh.sum + lam * ph.sum + kappa * gl.sum;
        let rc: Vec<f64> = (0..hm.n).map(|i| -(dh.grad[i] + lam * ph.grad[i] + gl.grad[i])).collect();
        let rg: Vec<f64> = gl.grad_g.iter().map(|v| -v).collect();
        let mut accepted = false;
        step = f64::INFINITY;
        for _ in 0..40 {
            let mut h = hm.clone();
            let mut corner = gl.corner.clone();
            if mu > 0.0 {
                for i in 0..h.n {
                    let idx = h.idx(i, i);
                    h.a[idx] *= 1.0 + mu;
                }
                for p in 0..np {
                    corner[p * np + p] *= 1.0 + mu;
                }
            }
            let solved =
                h.cholesky_in_place().and_then(|_| bordered_solve(&h, &gl.border, &corner, np, &rc, &rg));
            let (dx, dth) = match solved {
                Ok(v) => v,
                Err(_) => {
                    mu = if mu == 0.0 { 1e-6 } else { mu * 10.0 };
                    continue;
                }
            };
            let trial = model.retracted(&dx, None);
            let ts = sen.retracted(&est, &dth);
            let c1 = cost_at(&trial, &ts);
            // step size in radians: control steps, rotation, and what the bias, offset and
            // scale steps turn the curve by over the record
            let mut smax = (0..dx.len() / 3)
                .map(|i| vec3::norm([dx[3 * i], dx[3 * i + 1], dx[3 * i + 2]]))
                .fold(0.0, f64::max);
            let mut p = 0;
            if est.bias {
                smax = smax.max(vec3::norm([dth[0], dth[1], dth[2]]) * span);
                p += 3;
            }
            if est.time_offset {
                smax = smax.max(dth[p].abs());
                p += 1;
            }
            if est.rotation {
                smax = smax.max(vec3::norm([dth[p], dth[p + 1], dth[p + 2]]));
                p += 3;
            }
            if est.scale {
                smax = smax.max(vec3::norm([dth[p], dth[p + 1], dth[p + 2]]));
            }
            // the Gauss–Newton decrement −gᵀΔ (the cost the step is predicted to remove)
            let pred = dotv(&rc, &dx) + dotv(&rg, &dth);
            if c1 <= c0 * (1.0 + 1e-12) + 1e-300 || smax < tol {
                // Converged at the rounding level: the step removes (and would remove) a
                // negligible share of the cost — its Mahalanobis length is then ~1e-5 √n
                // standard errors — while its size stalls at the accuracy of the normal
                // equations (measured: 1e-8 … 1e-7 rad, the bias step × the record's span,
                // on 30 s at 200 Hz).
                if c0 - c1 <= 1e-12 * c0 && pred <= 1e-10 * c0 {
                    smax = smax.min(tol);
                }
                model = trial;
                sen = ts;
                step = smax;
                accepted = true;
                mu = if mu > 0.0 { mu / 10.0 } else { 0.0 };
                if mu < 1e-9 {
                    mu = 0.0;
                }
                break;
            }
            mu = if mu == 0.0 { 1e-4 } else { mu * 10.0 };
        }
        if !accepted {
            return Err(Error::NotConverged {
                what: "gyro-aided fit (no descent step found)",
                iterations: it,
                step,
                tol,
            });
        }
        if !progress("fit", it, step) {
            return Err(Error::invalid("progress", "fit cancelled by the progress callback"));
        }
        if step <= tol {
            break;
        }
    }
    // At the solution (undamped): the covariance of the global parameters σ_q² S⁻¹ and the
    // orientation term's effective degrees of freedom and GCV score (see the module doc).
    let dh = data_half(&model, data, w, &offs, Band::zeros(0, 0));
    let ph = pen_half(&model, pen, &nodes, Band::zeros(0, 0), None);
    let gq = dh.band;
    let mut hm = gq.clone();
    hm.axpy_assign(lam, &ph.band);
    drop(ph);
    let gl = gyro_lin(&model, g, &sen, &est, kappa, Some(&mut hm));
    hm.cholesky_in_place()?;
    let s2 = gopts.sigma_orientation * gopts.sigma_orientation;
    let (cov, edf) = marginal(&hm, &gq, &gl.border, &gl.corner, np)?;
    let cov: Vec<f64> = cov.iter().map(|v| s2 * v).collect();
    let den = dh.count - edf;
    let score = if den > 1e-9 * dh.count { dh.count * dh.sum / (den * den) } else { f64::INFINITY };
    let mut mats: Factors<3> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
    let gyro_residuals =
        (0..g.t.len()).map(|j| sample::<3>(&model, &sen, &est, g.t[j], g.w[j], false, &mut mats).e).collect();
    let (_, ang) = super::assembly::residuals(&model, data, &offs);
    let fit = FitResult {
        ctrl: model.ctrl.clone(),
        dt: model.dt,
        t0: model.t0,
        order: model.order,
        breaks: model.layout.breaks.as_ref().map(|b| b.to_vec()),
        robust_weights: vec![1.0; ang.len()],
        residuals: ang,
        robust_scale: f64::INFINITY,
        lambda: lam,
        lambda_requested: None,
        edf,
        score,
        iterations: it,
        final_step: step,
        converged: true,
        penalty_weights: None,
    };
    Ok(GyroFit { fit, sensor: sen, estimate: est, covariance: cov, gyro_residuals, gyro_weight: kappa })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::XorShift64;

    fn gauss(rng: &mut XorShift64) -> f64 {
        // Box–Muller
        let (u1, u2) = (rng.uniform().max(1e-300), rng.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// A random smooth motion: an order-4 B-spline through random rotation-vector walks.
    fn truth(rng: &mut XorShift64, span: f64) -> Model {
        let dt = 0.25;
        let segs = (span / dt).round() as usize;
        let mut rv = [0.0; 3];
        let ctrl: Vec<Quat> = (0..segs + 3)
            .map(|_| {
                for x in rv.iter_mut() {
                    *x += 0.35 * gauss(rng);
                }
                so3::exp(rv)
            })
            .collect();
        Model::new(ctrl, dt, -dt, 4)
    }

    fn rate_at(m: &Model, t: f64) -> (Quat, Vec3) {
        let (i, u) = m.locate(t);
        let q = m.value::<3>(i, Jet::variable(u, 1.0 / m.width(i)));
        let om = Model::omega(&q);
        (q.value(), std::array::from_fn(|r| om[r].value()))
    }

    /// ∂e/∂(controls) and ∂e/∂(b, δ, R, s) against central finite differences of e, for
    /// orders 4–6, at several times (inside intervals and at a joint) and a planted sensor.
    #[test]
    fn gyro_jacobians_match_finite_differences() {
        let est = Estimate { bias: true, time_offset: true, rotation: true, scale: true };
        for order in [4usize, 5, 6] {
            let mut rng = XorShift64::new(11 + order as u64);
            let ctrl: Vec<Quat> = (0..order + 6)
                .map(|_| so3::exp([gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)]))
                .collect();
            let model = Model::new(ctrl, 0.3, 0.1, order);
            let sen = Sensor {
                bias: [0.01, -0.02, 0.03],
                time_offset: 0.0123,
                rotation: so3::exp([0.2, -0.3, 0.4]),
                scale: [0.01, -0.02, 0.015],
            };
            let m = [0.3, -0.1, 0.2];
            for &t in &[0.37, 0.7 - 0.0123, 1.21] {
                let mut mats: Factors<3> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
                let s0 = sample::<3>(&model, &sen, &est, t, m, true, &mut mats);
                let h = 1e-6;
                for mm in 0..order {
                    for c in 0..3 {
                        let e_at = |x: f64| {
                            let mut d = vec![0.0; 3 * model.ctrl.len()];
                            d[3 * (s0.seg + mm) + c] = x;
                            let mo = model.retracted(&d, None);
                            let mut mats: Factors<3> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
                            sample::<3>(&mo, &sen, &est, t, m, false, &mut mats).e
                        };
                        let (p, q) = (e_at(h), e_at(-h));
                        for r in 0..3 {
                            let fd = (p[r] - q[r]) / (2.0 * h);
                            let an = s0.jac[3 * mm + c][r];
                            assert!(
                                (fd - an).abs() < 1e-6 * (1.0 + an.abs()),
                                "k {order} t {t} m {mm} c {c}: {fd} vs {an}"
                            );
                        }
                    }
                }
                for p in 0..est.count() {
                    let e_at = |x: f64| {
                        let mut d = vec![0.0; est.count()];
                        d[p] = x;
                        let s = sen.retracted(&est, &d);
                        let mut mats: Factors<3> = [[[Jet::constant(0.0); 3]; 3]; MAXK];
                        sample::<3>(&model, &s, &est, t, m, false, &mut mats).e
                    };
                    let (a, b) = (e_at(h), e_at(-h));
                    for r in 0..3 {
                        let fd = (a[r] - b[r]) / (2.0 * h);
                        let an = s0.glob[p][r];
                        // ω̈ jumps at a joint (t + δ = 0.7): the central difference in δ is
                        // only O(h) accurate there
                        let tol = if p == 3 { 1e-4 } else { 1e-6 };
                        assert!(
                            (fd - an).abs() < tol * (1.0 + an.abs()),
                            "k {order} global {p}: {fd} vs {an}"
                        );
                    }
                }
            }
        }
    }

    /// The bordered solve against a dense solve of the whole system.
    #[test]
    fn bordered_solve_matches_dense() {
        let mut rng = XorShift64::new(3);
        let (n, bw, np) = (30usize, 5usize, 4usize);
        let mut h = Band::zeros(n, bw);
        let mut dense = vec![vec![0.0; n + np]; n + np];
        for i in 0..n {
            for j in i.saturating_sub(bw)..=i {
                let v = if i == j { 10.0 + rng.uniform() } else { rng.uniform() - 0.5 };
                let idx = h.idx(i, j);
                h.a[idx] = v;
                dense[i][j] = v;
                dense[j][i] = v;
            }
        }
        let border: Vec<f64> = (0..n * np).map(|_| rng.uniform() - 0.5).collect();
        let mut corner = vec![0.0; np * np];
        for p in 0..np {
            for q in 0..np {
                let v = if p == q { 20.0 } else { 0.1 * (p + q) as f64 };
                corner[p * np + q] = v;
            }
        }
        for i in 0..n {
            for p in 0..np {
                dense[i][n + p] = border[i * np + p];
                dense[n + p][i] = border[i * np + p];
            }
        }
        for p in 0..np {
            for q in 0..np {
                dense[n + p][n + q] = corner[p * np + q];
            }
        }
        let r: Vec<f64> = (0..n).map(|_| rng.uniform()).collect();
        let rg: Vec<f64> = (0..np).map(|_| rng.uniform()).collect();
        h.cholesky_in_place().unwrap();
        let (x, th) = bordered_solve(&h, &border, &corner, np, &r, &rg).unwrap();
        let sol: Vec<f64> = x.iter().chain(&th).cloned().collect();
        let rhs: Vec<f64> = r.iter().chain(&rg).cloned().collect();
        for i in 0..n + np {
            let v: f64 = (0..n + np).map(|j| dense[i][j] * sol[j]).sum();
            assert!((v - rhs[i]).abs() < 1e-12, "row {i}: {v} vs {}", rhs[i]);
        }
        // The marginal covariance and the orientation term's trace against the dense inverse
        // of the whole bordered matrix (Gauss–Jordan): S⁻¹ = (M⁻¹)_θθ, tr A_q = tr((M⁻¹)_cc G_q).
        let mut gq = Band::zeros(n, bw);
        for i in 0..n {
            for j in i.saturating_sub(bw)..=i {
                let v = if i == j { 1.0 + rng.uniform() } else { 0.3 * (rng.uniform() - 0.5) };
                let idx = gq.idx(i, j);
                gq.a[idx] = v;
            }
        }
        let inv = dense_inverse(&dense);
        let (cov, tr) = marginal(&h, &gq, &border, &corner, np).unwrap();
        for p in 0..np {
            for q in 0..np {
                let want = inv[n + p][n + q];
                assert!((cov[p * np + q] - want).abs() < 1e-13 * (1.0 + want.abs()), "S⁻¹[{p}][{q}]");
            }
        }
        let mut want = 0.0;
        for i in 0..n {
            for j in 0..n {
                if i.abs_diff(j) <= bw {
                    want += inv[i][j] * gq.get(j, i);
                }
            }
        }
        assert!((tr - want).abs() < 1e-12 * want.abs(), "tr A_q {tr} vs dense {want}");
        // without parameters: the trace of H⁻¹ G_q alone
        let (_, tr0) = marginal(&h, &gq, &[], &[], 0).unwrap();
        assert!((tr0 - h.trace_inverse_product(&gq)).abs() == 0.0);
        assert!(tr > tr0, "the parameters add degrees of freedom: {tr} vs {tr0}");
    }

    /// The inverse of a dense matrix by Gauss–Jordan with partial pivoting (test oracle).
    fn dense_inverse(a: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let n = a.len();
        let mut m: Vec<Vec<f64>> = a
            .iter()
            .enumerate()
            .map(|(i, r)| r.iter().cloned().chain((0..n).map(|j| if i == j { 1.0 } else { 0.0 })).collect())
            .collect();
        for c in 0..n {
            let piv = (c..n).max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs())).unwrap();
            m.swap(c, piv);
            let d = m[c][c];
            for v in m[c].iter_mut() {
                *v /= d;
            }
            for r in 0..n {
                if r != c {
                    let f = m[r][c];
                    if f != 0.0 {
                        for j in 0..2 * n {
                            m[r][j] -= f * m[c][j];
                        }
                    }
                }
            }
        }
        m.into_iter().map(|r| r[n..].to_vec()).collect()
    }

    struct Sim {
        t: Vec<f64>,
        q: Vec<Quat>,
        gt: Vec<f64>,
        gw: Vec<Vec3>,
    }

    #[allow(clippy::too_many_arguments)]
    fn simulate(
        rng: &mut XorShift64,
        m: &Model,
        sen: &Sensor,
        key_rate: f64,
        sq: f64,
        rate: f64,
        sg: f64,
        span: f64,
    ) -> Sim {
        let nk = (span * key_rate).round() as usize;
        let t: Vec<f64> = (0..=nk).map(|i| i as f64 / key_rate).collect();
        let q = t
            .iter()
            .map(|&s| rate_at(m, s).0 * so3::exp([sq * gauss(rng), sq * gauss(rng), sq * gauss(rng)]))
            .collect();
        let ng = (span * rate).floor() as usize;
        let gt: Vec<f64> = (0..=ng).map(|i| i as f64 / rate).filter(|&s| s <= span).collect();
        let kd = vec3::add([1.0; 3], sen.scale);
        let gw = gt
            .iter()
            .map(|&s| {
                let w = sen.rotation.conj().rotate(rate_at(m, s + sen.time_offset).1);
                std::array::from_fn(|r| kd[r] * w[r] + sen.bias[r] + sg * gauss(rng))
            })
            .collect();
        Sim { t, q, gt, gw }
    }

    /// A planted bias, time offset and rotation recovered from random smooth motions (several
    /// seeds) at consumer-MEMS gyroscope noise (3e-4 rad/s/√Hz at 200 Hz: σ_g = 4.2e-3 rad/s)
    /// with 100 Hz orientations of 0.1° noise: within 0.5 ms and 0.05° (the targets) and
    /// 0.02 °/s (the target is 0.01 °/s: measured 0.008–0.014 °/s, missed), the bias within
    /// 5 of its stated standard errors.
    #[test]
    fn recovers_planted_bias_offset_and_rotation() {
        let (rate, sg, sq, span) = (200.0, 3e-4 * 200f64.sqrt(), 0.1f64.to_radians(), 20.0);
        for seed in 0..4u64 {
            let mut rng = XorShift64::new(100 + seed);
            let m = truth(&mut rng, span + 1.0);
            let sen = Sensor {
                bias: [0.009 * gauss(&mut rng), 0.009 * gauss(&mut rng), 0.009 * gauss(&mut rng)],
                time_offset: 0.005 * gauss(&mut rng),
                rotation: so3::exp([0.1 * gauss(&mut rng), 0.1 * gauss(&mut rng), 0.1 * gauss(&mut rng)]),
                scale: [0.0; 3],
            };
            let s = simulate(&mut rng, &m, &sen, 100.0, sq, rate, sg, span);
            let gopts = GyroOptions { sigma_gyro: sg, sigma_orientation: sq, ..Default::default() };
            let r =
                fit_gyro(&s.t, &s.q, None, &s.gt, &s.gw, &FitOptions::default(), &gopts, &mut |_, it, st| {
                    assert!(it < 60, "slow convergence: step {st:e}");
                    true
                })
                .unwrap();
            let sd = |p: usize| r.covariance[p * 7 + p].sqrt();
            let db: Vec<f64> = (0..3).map(|c| r.sensor.bias[c] - sen.bias[c]).collect();
            let dd = r.sensor.time_offset - sen.time_offset;
            let dr = so3::log(sen.rotation.conj() * r.sensor.rotation);
            eprintln!("seed {seed}: bias err {db:?} (sd {:.2e}), offset err {dd:.2e} (sd {:.2e}), rot err {dr:?} (sd {:.2e})", sd(0), sd(3), sd(4));
            for c in 0..3 {
                assert!(db[c].abs().to_degrees() < 0.02, "seed {seed} bias {c}: {} °/s", db[c].to_degrees());
                assert!(db[c].abs() < 5.0 * sd(c), "seed {seed} bias {c}: {} vs sd {}", db[c], sd(c));
            }
            assert!(dd.abs() < 5e-4, "seed {seed}: offset {dd}");
            assert!(
                vec3::norm(dr).to_degrees() < 0.05,
                "seed {seed}: rotation {}°",
                vec3::norm(dr).to_degrees()
            );
        }
    }

    /// With the gyroscope's weight → 0 (σ_g huge) and nothing estimated, the gyro-aided fit is
    /// the plain fit on the same knots and λ.
    #[test]
    fn reduces_to_the_plain_fit_as_the_gyro_weight_vanishes() {
        let mut rng = XorShift64::new(9);
        let m = truth(&mut rng, 6.0);
        let s = simulate(&mut rng, &m, &Sensor::default(), 20.0, 0.01, 100.0, 0.01, 5.0);
        let opts = FitOptions {
            knots: Knots::Spacing(0.1),
            smoothing: Smoothing::Fixed(1e-4),
            ..Default::default()
        };
        let plain = super::super::fit(&s.t, &s.q, None, &opts, &mut |_, _, _| true).unwrap();
        let gopts = GyroOptions {
            sigma_gyro: 1e9,
            sigma_orientation: 0.01,
            estimate: Estimate::default(),
            ..Default::default()
        };
        let r = fit_gyro(&s.t, &s.q, None, &s.gt, &s.gw, &opts, &gopts, &mut |_, _, _| true).unwrap();
        let mut worst = 0.0f64;
        for (a, b) in r.fit.ctrl.iter().zip(&plain.ctrl) {
            worst = worst.max(vec3::norm(so3::log(a.conj() * *b)));
        }
        assert!(worst < 1e-7, "{worst}");
        // and with a real weight the curve differs
        let gopts = GyroOptions { sigma_gyro: 0.01, ..gopts };
        let r = fit_gyro(&s.t, &s.q, None, &s.gt, &s.gw, &opts, &gopts, &mut |_, _, _| true).unwrap();
        let d = r
            .fit
            .ctrl
            .iter()
            .zip(&plain.ctrl)
            .map(|(a, b)| vec3::norm(so3::log(a.conj() * *b)))
            .fold(0.0, f64::max);
        assert!(d > 1e-4, "{d}");
    }

    /// Bad input: the gyroscope outside the orientations' range, non-increasing, NaN, wrong
    /// lengths, a bad σ, unknown estimate names.
    #[test]
    fn bad_gyro_input_is_refused_naming_it() {
        let t = [0.0, 0.5, 1.0, 1.5];
        let q = [Quat::IDENTITY; 4];
        let o = FitOptions::default();
        let g = GyroOptions::default();
        let run = |gt: &[f64], gw: &[Vec3], g: &GyroOptions| {
            fit_gyro(&t, &q, None, gt, gw, &o, g, &mut |_, _, _| true).unwrap_err().to_string()
        };
        let z = [[0.0; 3]; 3];
        assert!(run(&[0.0, 0.5, 2.0], &z, &g).contains("outside"));
        assert!(run(&[0.0, 0.5, 0.5], &z, &g).contains("not strictly increasing"));
        assert!(run(&[0.0, 0.5, 1.0], &[[0.0; 3], [f64::NAN, 0.0, 0.0], [0.0; 3]], &g).contains("gyro"));
        assert!(run(&[0.0, 0.5], &z, &g).contains("gyro"));
        let bad = GyroOptions { sigma_gyro: -1.0, ..GyroOptions::default() };
        assert!(run(&[0.0, 0.5, 1.0], &z, &bad).contains("gyro_noise"));
        assert!(Estimate::parse(["bias", "nope"]).unwrap_err().to_string().contains("estimate"));
    }
}
