//! Minimum-energy interpolation through keys (seed 003's Spicv/Sping; MATH.md §13).
//!
//! **Acceleration penalty** ([`MinEnergySpline`], C²): minimise E(q) = ∫ |ω̇|² dt subject to
//! q(tᵢ) = qᵢ. The continuous optimum is a Riemannian cubic between keys (ω‴ + ω × ω″ = 0,
//! C² at keys; Noakes, Heinzinger & Paden 1989). Representation, chosen so that the
//! natural spline N (MATH.md §6b, `spline/natural_spline.rs`) is a feasible point:
//!   q(t) = N(t) · Exp(δ(t)),  t ∈ [tᵢ, tᵢ₊₁], s = (t − tᵢ)/hᵢ,
//!   δ(t) = hᵢ vᵢ H₁(s) + hᵢ² aᵢ H₂(s) + hᵢ vᵢ₊₁ H₄(s) + hᵢ² aᵢ₊₁ H₅(s)
//!          + Σ_{k<K} c_{i,k} · 64 s³(1−s)³ P_k(2s − 1),
//! with H₁ = s − 6s³ + 8s⁴ − 3s⁵, H₂ = ½s² − 3⁄2 s³ + 3⁄2 s⁴ − ½s⁵, H₄ = −4s³ + 7s⁴ − 3s⁵,
//! H₅ = ½s³ − s⁴ + ½s⁵ (the quintic Hermite basis with zero end values), P_k Legendre, K =
//! `resolution`. δ vanishes at every key (interpolation is exact: q(tᵢ) = N(tᵢ) = qᵢ) and
//! δ, δ′, δ″ are continuous there (shared vᵢ, aᵢ), so q is C² like N. δ ≡ 0 is N itself.
//! The energy is the composite Gauss–Legendre sum with 8 equal pieces × 10 nodes per key
//! interval (the integrand is analytic inside a key interval; this is the quadrature the
//! tests and `benchmarks/fit.py` use for every spline, whose joints are the same keys), and
//! it is minimised by Levenberg–Marquardt accepting only steps that lower it, from the exact
//! optimum ([`super::riemannian_cubic`]) projected onto this space when that lowers the
//! energy below δ = 0's, else from δ = 0:
//! the result's energy is ≤ the natural spline's by construction, equal only when no
//! descent exists (N already optimal to the solver's precision). Jacobians of the residuals
//! √wₘ ω̇(tₘ): the chain rule through δ's Taylor coefficients at each node (linear in the
//! parameters, exact) times ∂ω̇/∂coefficients by central differences; the normal matrix is
//! banded (a key interval couples its two keys' (v, a) and its own bubbles).
//! The intervals' shares of the energy, the normal equations and the gradient are computed in
//! parallel and added in interval order (the same sums at any thread count); a pass of the
//! Jacobian over every quadrature node (19 evaluations of ω̇ per node) is the descent's
//! dominant cost, and the gradient at the result reuses the last pass when no later step moved
//! the parameters.
//! Raising K nests the spaces (energy non-increasing) and, the polynomials being dense,
//! converges to the continuous optimum: this is the Sping (discrete numerical) route to
//! Spicv (the analytic optimum).
//! Ends: `Natural` (v, a free at the ends: the optimum's natural boundary conditions, ω̇ = 0,
//! arise by themselves), `Rest` / `Clamped` (N with those rates, v = 0 at both ends so the end
//! rates are kept), `Closed` (N's periodic loop, δ periodic; dense solve).
//!
//! **Jerk penalty** ([`min_energy_bspline`], C⁴): the minimum-∫|ω̈|² curve through the keys in
//! a uniform cumulative B-spline space of order 6 with `resolution` knot intervals per mean
//! key interval, by the fitting solver with λ → 0⁺ (`fit::solve`, Bregman iteration).

use super::banded::Band;
use super::{
    initial_controls, knot_layout, solve, validate, FitOptions, FitResult, Knots, Penalty, Progress,
};
use super::{Robust, Smoothing};
use crate::error::{Error, Result};
use crate::jet::{angular, JQuat, Jet};
use crate::quat::Quat;
use crate::spline::{local, same_rotation, segment_jets, NaturalEnds, NaturalSpline, Spline};
use crate::vec3::Vec3;
use rayon::prelude::*;

/// Pieces per key interval and Gauss–Legendre nodes per piece of the energy quadrature.
pub const PIECES: usize = 8;
pub const NODES: usize = 10;

/// The minimum-∫|ω̇|² interpolant N · Exp(δ) (see the module documentation).
#[derive(Debug, Clone)]
pub struct MinEnergySpline {
    nat: NaturalSpline,
    /// Per key: v (3), a (3), then per interval the 3K bubble coefficients (stride 6 + 3K).
    x: Vec<f64>,
    k: usize,
    closed: bool,
    /// ∫|ω̇|² of the natural spline and of the result (the quadrature above).
    pub energy_natural: f64,
    pub energy: f64,
    pub iterations: usize,
    /// Whether the descent stopped by its criterion (no step lowers the energy, or the last
    /// lowered it by less than 1e-13 of the natural energy) rather than at the iteration cap;
    /// either way the spline is the best iterate found (never above the natural spline).
    pub converged: bool,
    /// |∂(½E)/∂x| over the free parameters at the returned iterate.
    pub gradient_norm: f64,
    /// Jacobian passes over all quadrature nodes (the descent's dominant cost): one per
    /// iteration plus one for the gradient at the result when the last step was accepted.
    pub jacobian_passes: usize,
    /// Per key interval: whether it joins two equal keys (a hold: exactly constant).
    holds: Vec<bool>,
}

/// Iteration cap of the Levenberg–Marquardt descent.
pub const MAX_ITER: usize = 200;

fn quintic_hermite<const N: usize>(s: Jet<N>) -> [Jet<N>; 4] {
    [
        Jet::poly(&[0.0, 1.0, 0.0, -6.0, 8.0, -3.0], s),
        Jet::poly(&[0.0, 0.0, 0.5, -1.5, 1.5, -0.5], s),
        Jet::poly(&[0.0, 0.0, 0.0, -4.0, 7.0, -3.0], s),
        Jet::poly(&[0.0, 0.0, 0.0, 0.5, -1.0, 0.5], s),
    ]
}

/// 64 s³(1−s)³ P_k(2s − 1), k < K.
fn bubbles<const N: usize>(s: Jet<N>, k: usize, out: &mut Vec<Jet<N>>) {
    out.clear();
    let w = s - s * s;
    let b = w * w * w * 64.0;
    let x = s * 2.0 + (-1.0);
    let (mut p0, mut p1) = (Jet::constant(1.0), x);
    for j in 0..k {
        let pj = if j == 0 { p0 } else { p1 };
        out.push(b * pj);
        if j >= 1 {
            let jf = j as f64;
            let p2 = (x * p1 * (2.0 * jf + 1.0) - p0 * jf) * (1.0 / (jf + 1.0));
            p0 = p1;
            p1 = p2;
        }
    }
}

/// δ on interval i from its local parameters p = [vᵢ, aᵢ, bubbles (3K), vᵢ₊₁, aᵢ₊₁].
fn delta<const N: usize>(p: &[f64], k: usize, h: f64, herm: &[Jet<N>; 4], bub: &[Jet<N>]) -> [Jet<N>; 3] {
    let st = 6 + 3 * k;
    std::array::from_fn(|c| {
        let mut d = herm[0] * (h * p[c])
            + herm[1] * (h * h * p[3 + c])
            + herm[2] * (h * p[st + c])
            + herm[3] * (h * h * p[st + 3 + c]);
        for (j, b) in bub.iter().enumerate() {
            d = d + *b * p[6 + 3 * j + c];
        }
        d
    })
}

fn exp_rotvec<const N: usize>(d: [Jet<N>; 3]) -> JQuat<N> {
    JQuat::exp_pure([d[0] * 0.5, d[1] * 0.5, d[2] * 0.5])
}

/// Body angular acceleration from a 3-jet.
fn alpha_body(q: JQuat<3>) -> Vec3 {
    angular(&q.derivatives(), 2, true)
}

impl MinEnergySpline {
    fn stride(&self) -> usize {
        6 + 3 * self.k
    }

    fn intervals(&self) -> usize {
        self.nat.segments()
    }

    /// Local parameters of interval i (wrapping to key 0 at a closed loop's seam).
    fn local_params(&self, i: usize) -> Vec<f64> {
        local_params(&self.x, i, self.stride(), self.intervals(), self.closed)
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        if self.holds[i] {
            // A hold: δ ≡ 0 there and N is the constant key; return it exactly (zero ω, α, jerk).
            return JQuat::constant(self.nat.segment::<1>(i, self.nat.joints()[i]).value());
        }
        let j = self.nat.joints();
        let (a, b) = (j[i], j[i + 1]);
        let s = local::<N>(t, a, b);
        let herm = quintic_hermite(s);
        let mut bub = Vec::with_capacity(self.k);
        bubbles(s, self.k, &mut bub);
        let p = self.local_params(i);
        self.nat.segment::<N>(i, t) * exp_rotvec(delta(&p, self.k, b - a, &herm, &bub))
    }

    /// Builds the spline: keys, times (default 0 … N−1), end conditions, K = `resolution`
    /// bubble polynomials per key interval (0 … 16). Consecutive equal keys (a hold, see
    /// [`same_rotation`]) give an exactly constant interval: N pins the rate at both its keys
    /// (as the natural spline's holds do), and δ's rates there and bubbles inside are held at 0.
    /// The descent stops after [`MAX_ITER`] iterations at the latest; the result is then the
    /// best iterate with `converged` false (never an error while a valid curve is at hand).
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        ends: NaturalEnds,
        resolution: usize,
        progress: Progress<'_>,
    ) -> Result<Self> {
        if resolution > 16 {
            return Err(Error::invalid(
                "resolution",
                format!("expected 0 … 16 bubble polynomials per key interval, got {resolution}"),
            ));
        }
        let nat = NaturalSpline::with_keyframes(keys, times, ends, true, true)?;
        let closed = ends == NaturalEnds::Closed;
        let k = resolution;
        let st = 6 + 3 * k;
        let segs = nat.segments();
        let nkeys = if closed { segs } else { segs + 1 };
        let npar = if closed { segs * st } else { segs * st + 6 };
        let mut fixed = vec![false; npar];
        if matches!(ends, NaturalEnds::Rest | NaturalEnds::Clamped { .. }) {
            for c in 0..3 {
                fixed[c] = true;
                fixed[(nkeys - 1) * st + c] = true;
            }
        }
        // Holds: the keys bounding one keep δ′ = δ″ = 0 and its bubbles stay 0, so δ ≡ 0 on it.
        let j = nat.joints();
        let holds: Vec<bool> = (0..segs)
            .map(|i| {
                let a = nat.segment::<1>(i, j[i]).value();
                let b = nat.segment::<1>(i, j[i + 1]).value();
                same_rotation(a, b)
            })
            .collect();
        for (i, _) in holds.iter().enumerate().filter(|(_, &h)| h) {
            let next = if closed && i + 1 == segs { 0 } else { i + 1 };
            fixed[i * st..i * st + st].iter_mut().for_each(|f| *f = true);
            fixed[next * st..next * st + 6].iter_mut().for_each(|f| *f = true);
        }
        let mut me = MinEnergySpline {
            nat,
            x: vec![0.0; npar],
            k,
            closed,
            energy_natural: 0.0,
            energy: 0.0,
            iterations: 0,
            converged: true,
            gradient_norm: 0.0,
            jacobian_passes: 0,
            holds,
        };
        let cache = Cache::new(&me);
        let e0 = cache.energy(&me.x);
        me.energy_natural = e0;
        me.energy = e0;
        if e0 <= 0.0 || !e0.is_finite() {
            return Ok(me);
        }
        let mut e = e0;
        // Warm start: the exact optimum (the Riemannian cubic) projected onto this space. The
        // descent from δ = 0 converges linearly (Gauss–Newton on a non-zero residual) and took
        // more iterations the more keys there were (12, 20, 65 for 100, 300, 1000 random keys);
        // from the projection it needs a few. Used only when it lowers the energy; if Newton's
        // method for the exact curve fails, the descent starts from δ = 0 as before.
        let mut cancelled = false;
        let start = me.projection_of_exact(ends, &fixed, &mut |stage, it, r| {
            cancelled = !progress(stage, it, r);
            !cancelled
        });
        if cancelled {
            return Err(Error::invalid("progress", "cancelled by the progress callback"));
        }
        if let Some(x) = start {
            let e1 = cache.energy(&x);
            if e1 < e0 {
                me.x = x;
                e = e1;
            }
        }
        let mut mu = 0.0f64;
        let mut it = 0;
        let mut converged = false;
        // The gradient at the last point whose normal equations were formed: the returned
        // gradient norm when no later step was accepted.
        let mut g_last: Option<Vec<f64>> = None;
        while it < MAX_ITER {
            it += 1;
            let mut step = 0.0;
            let (h, g) = cache.normal_equations(&me.x, &fixed);
            let mut accepted = false;
            g_last = Some(g.clone());
            for _ in 0..40 {
                let d = match h.solve_damped(&g, mu) {
                    Some(d) => d,
                    None => {
                        mu = if mu == 0.0 { 1e-9 } else { mu * 10.0 };
                        continue;
                    }
                };
                let trial: Vec<f64> = me.x.iter().zip(&d).map(|(a, b)| a + b).collect();
                let e1 = cache.energy(&trial);
                if e1 < e {
                    g_last = None;
                    step = (e - e1) / e0;
                    me.x = trial;
                    e = e1;
                    accepted = true;
                    mu = if mu > 1e-12 { mu / 10.0 } else { 0.0 };
                    break;
                }
                mu = if mu == 0.0 { 1e-9 } else { mu * 10.0 };
                if mu > 1e8 {
                    break;
                }
            }
            if !progress("descent", it, step) {
                return Err(Error::invalid("progress", "cancelled by the progress callback"));
            }
            // Converged: no step lowers the energy any more (the finite-difference Jacobian's
            // precision), or the last one lowered it by less than 1e-13 of the natural energy.
            if !accepted || step <= 1e-13 {
                converged = true;
                break;
            }
        }
        me.jacobian_passes = it + usize::from(g_last.is_none());
        let g = g_last.unwrap_or_else(|| cache.gradient(&me.x, &fixed));
        me.gradient_norm = g.iter().zip(&fixed).filter(|(_, &f)| !f).map(|(v, _)| v * v).sum::<f64>().sqrt();
        me.energy = e;
        me.iterations = it;
        me.converged = converged;
        Ok(me)
    }

    /// Parameters whose δ matches Log(N⁻¹ R) for the exact optimum R: vᵢ, aᵢ its first two
    /// derivatives at the keys, the bubbles by least squares of the remainder at 2K + 4
    /// Gauss–Legendre nodes per key interval. None when R cannot be computed.
    fn projection_of_exact(
        &self,
        ends: NaturalEnds,
        fixed: &[bool],
        progress: Progress<'_>,
    ) -> Option<Vec<f64>> {
        let exact = super::riemannian_cubic::RiemannianCubic::from_natural(&self.nat, ends, progress).ok()?;
        let j = self.nat.joints();
        let segs = self.intervals();
        let (k, st) = (self.k, self.stride());
        let mut x = vec![0.0; self.x.len()];
        let delta_at = |i: usize, t: f64| -> [Jet<3>; 3] {
            let mut r = self.nat.segment::<3>(i, t).conj() * exact.segment_jet3(i, t);
            if r.w.0[0] < 0.0 {
                r = JQuat { w: -r.w, x: -r.x, y: -r.y, z: -r.z };
            }
            let l = r.log_unit();
            [l[0] * 2.0, l[1] * 2.0, l[2] * 2.0]
        };
        let nkeys = if self.closed { segs } else { segs + 1 };
        for key in 0..nkeys {
            let i = key.min(segs - 1);
            let d = delta_at(i, j[key]);
            for c in 0..3 {
                x[key * st + c] = d[c].derivative(1);
                x[key * st + 3 + c] = d[c].derivative(2);
            }
        }
        if k > 0 {
            // Per key interval (in parallel; each writes only its own bubbles).
            let gl = crate::quadrature::gauss_legendre01(2 * k + 4);
            let xs = &x;
            let sols: Vec<Option<Vec<f64>>> = (0..segs)
                .into_par_iter()
                .map(|i| {
                    if self.holds[i] {
                        return Some(Vec::new());
                    }
                    let mut bub = Vec::new();
                    let (a, b) = (j[i], j[i + 1]);
                    let p = local_params(xs, i, st, segs, self.closed);
                    let mut ata = nalgebra::DMatrix::<f64>::zeros(k, k);
                    let mut atb = nalgebra::DMatrix::<f64>::zeros(k, 3);
                    for &(u, w) in &gl {
                        let t = a + u * (b - a);
                        let s = crate::spline::local::<3>(t, a, b);
                        bubbles(s, k, &mut bub);
                        let herm = quintic_hermite(s);
                        let base = delta(&p, k, b - a, &herm, &[]);
                        let target = delta_at(i, t);
                        for r in 0..k {
                            for c in 0..k {
                                ata[(r, c)] += w * bub[r].0[0] * bub[c].0[0];
                            }
                            for c in 0..3 {
                                atb[(r, c)] += w * bub[r].0[0] * (target[c].0[0] - base[c].0[0]);
                            }
                        }
                    }
                    let sol = ata.cholesky()?.solve(&atb);
                    Some((0..3 * k).map(|rc| sol[(rc / 3, rc % 3)]).collect())
                })
                .collect();
            for (i, sol) in sols.into_iter().enumerate() {
                let sol = sol?;
                x[i * st + 6..i * st + 6 + sol.len()].copy_from_slice(&sol);
            }
        }
        for (v, &f) in x.iter_mut().zip(fixed) {
            if f || !v.is_finite() {
                *v = 0.0;
            }
        }
        Some(x)
    }

    /// ∫|ω̇|² by the module's quadrature (same nodes as at construction).
    pub fn energy_of(&self) -> f64 {
        Cache::new(self).energy(&self.x)
    }
}

/// ∫|ω̇|² of the natural spline by the module's quadrature ([`PIECES`] × [`NODES`]
/// Gauss–Legendre per key interval; the same value as the discrete spline's at δ = 0).
pub(crate) fn natural_energy(nat: &NaturalSpline) -> f64 {
    let gl = crate::quadrature::gauss_legendre01(NODES);
    let j = nat.joints();
    let mut e = 0.0;
    for i in 0..nat.segments() {
        let piece = (j[i + 1] - j[i]) / PIECES as f64;
        for p in 0..PIECES {
            let lo = j[i] + p as f64 * piece;
            for &(u, wt) in &gl {
                let al = alpha_body(nat.segment::<3>(i, lo + u * piece));
                e += wt * piece * (al[0] * al[0] + al[1] * al[1] + al[2] * al[2]);
            }
        }
    }
    e
}

fn local_params(x: &[f64], i: usize, st: usize, segs: usize, closed: bool) -> Vec<f64> {
    let mut p = Vec::with_capacity(st + 6);
    p.extend_from_slice(&x[i * st..i * st + st]);
    let nxt = if closed && i + 1 == segs { 0 } else { (i + 1) * st };
    p.extend_from_slice(&x[nxt..nxt + 6]);
    p
}

/// Per interval and quadrature node: N's 3-jet, the basis jets and the weight.
struct Cache {
    k: usize,
    segs: usize,
    closed: bool,
    h: Vec<f64>,
    /// [interval][node]
    nq: Vec<JQuat<3>>,
    herm: Vec<[Jet<3>; 4]>,
    bub: Vec<Vec<Jet<3>>>,
    w: Vec<f64>,
}

/// A symmetric system: banded (open curves) or dense (closed loops).
enum Normal {
    Band(Band),
    Dense(nalgebra::DMatrix<f64>),
}

impl Normal {
    fn solve_damped(&self, g: &[f64], mu: f64) -> Option<Vec<f64>> {
        let rhs: Vec<f64> = g.iter().map(|v| -v).collect();
        match self {
            Normal::Band(b) => {
                let mut h = b.clone();
                let diag = h.diag();
                let dmax = diag.iter().cloned().fold(0.0, f64::max);
                for (i, d) in diag.iter().enumerate() {
                    let idx = h.idx(i, i);
                    h.a[idx] += mu * d.max(1e-12 * dmax) + 1e-14 * dmax;
                }
                let l = h.cholesky().ok()?;
                Some(l.solve(&rhs))
            }
            Normal::Dense(m) => {
                let mut h = m.clone();
                let dmax = (0..h.nrows()).map(|i| h[(i, i)]).fold(0.0, f64::max);
                for i in 0..h.nrows() {
                    h[(i, i)] += mu * h[(i, i)].max(1e-12 * dmax) + 1e-14 * dmax;
                }
                let c = h.cholesky()?;
                Some(c.solve(&nalgebra::DVector::from_vec(rhs)).iter().copied().collect())
            }
        }
    }
}

impl Cache {
    fn new(me: &MinEnergySpline) -> Self {
        let gl = crate::quadrature::gauss_legendre01(NODES);
        let j = me.nat.joints();
        let segs = me.intervals();
        type Part = (Vec<JQuat<3>>, Vec<[Jet<3>; 4]>, Vec<Vec<Jet<3>>>, Vec<f64>);
        let parts: Vec<Part> = (0..segs)
            .into_par_iter()
            .map(|i| {
                let m = PIECES * NODES;
                let (mut nq, mut herm, mut bub, mut w) = (
                    Vec::with_capacity(m),
                    Vec::with_capacity(m),
                    Vec::with_capacity(m),
                    Vec::with_capacity(m),
                );
                let (a, b) = (j[i], j[i + 1]);
                let piece = (b - a) / PIECES as f64;
                for p in 0..PIECES {
                    let lo = a + p as f64 * piece;
                    for &(u, wt) in &gl {
                        let t = lo + u * piece;
                        nq.push(me.nat.segment::<3>(i, t));
                        let s = local::<3>(t, a, b);
                        herm.push(quintic_hermite(s));
                        let mut bb = Vec::with_capacity(me.k);
                        bubbles(s, me.k, &mut bb);
                        bub.push(bb);
                        w.push(wt * piece);
                    }
                }
                (nq, herm, bub, w)
            })
            .collect();
        let h = (0..segs).map(|i| j[i + 1] - j[i]).collect();
        let (mut nq, mut herm, mut bub, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (a, b, c, d) in parts {
            nq.extend(a);
            herm.extend(b);
            bub.extend(c);
            w.extend(d);
        }
        Cache { k: me.k, segs, closed: me.closed, h, nq, herm, bub, w }
    }

    /// √w ω̇_body at every node of interval i for local parameters p (appends 3 per node).
    fn residuals(&self, i: usize, p: &[f64], out: &mut Vec<f64>) {
        out.clear();
        let m = PIECES * NODES;
        for n in i * m..(i + 1) * m {
            let q = self.nq[n] * exp_rotvec(delta(p, self.k, self.h[i], &self.herm[n], &self.bub[n]));
            let al = alpha_body(q);
            let sw = self.w[n].sqrt();
            out.extend(al.iter().map(|v| v * sw));
        }
    }

    /// E(x): the intervals' sums in parallel, added in interval order.
    fn energy(&self, x: &[f64]) -> f64 {
        let st = 6 + 3 * self.k;
        let parts: Vec<f64> = (0..self.segs)
            .into_par_iter()
            .map_init(Vec::new, |r, i| {
                let p = local_params(x, i, st, self.segs, self.closed);
                self.residuals(i, &p, r);
                r.iter().map(|v| v * v).sum::<f64>()
            })
            .collect();
        parts.iter().fold(0.0, |e, v| e + v)
    }

    /// Global indices of interval i's local parameters.
    fn gidx(&self, i: usize, st: usize, nl: usize) -> Vec<usize> {
        (0..nl)
            .map(|c| {
                if c < st {
                    i * st + c
                } else if self.closed && i + 1 == self.segs {
                    c - st
                } else {
                    (i + 1) * st + c - st
                }
            })
            .collect()
    }

    /// Interval i's share of JᵀJ (lower triangle, row-major nl × nl; empty unless `hessian`)
    /// and of Jᵀr.
    fn interval_normal(&self, i: usize, x: &[f64], fixed: &[bool], hessian: bool) -> (Vec<f64>, Vec<f64>) {
        let st = 6 + 3 * self.k;
        let nl = st + 6;
        let p = local_params(x, i, st, self.segs, self.closed);
        let gidx = self.gidx(i, st, nl);
        let mut r0 = Vec::new();
        self.residuals(i, &p, &mut r0);
        let nr = r0.len();
        let mut jac = vec![0.0; nr * nl];
        let h = self.h[i];
        let m = PIECES * NODES;
        for (node, n) in (i * m..(i + 1) * m).enumerate() {
            // Chain rule: ω̇ depends on δ's Taylor coefficients (9 numbers) and those are
            // linear in the parameters. ∂ω̇/∂coefficients by central differences (steps
            // that move δ by about 1e-6 rad), then exact products with the basis jets.
            let d = delta(&p, self.k, h, &self.herm[n], &self.bub[n]);
            let sw = self.w[n].sqrt();
            let mut dm = [[0.0f64; 9]; 3];
            for c in 0..3 {
                for o in 0..3 {
                    let e = 1e-6 / h.powi(o as i32);
                    let mut dp = d;
                    dp[c].0[o] += e;
                    let ap = alpha_body(self.nq[n] * exp_rotvec(dp));
                    dp[c].0[o] -= 2.0 * e;
                    let am = alpha_body(self.nq[n] * exp_rotvec(dp));
                    for r in 0..3 {
                        dm[r][3 * c + o] = sw * (ap[r] - am[r]) / (2.0 * e);
                    }
                }
            }
            for j in 0..nl {
                if fixed[gidx[j]] {
                    continue;
                }
                let (basis, scale, comp) = if j < 3 {
                    (self.herm[n][0], h, j)
                } else if j < 6 {
                    (self.herm[n][1], h * h, j - 3)
                } else if j < st {
                    (self.bub[n][(j - 6) / 3], 1.0, (j - 6) % 3)
                } else if j < st + 3 {
                    (self.herm[n][2], h, j - st)
                } else {
                    (self.herm[n][3], h * h, j - st - 3)
                };
                for r in 0..3 {
                    let mut v = 0.0;
                    for o in 0..3 {
                        v += dm[r][3 * comp + o] * scale * basis.0[o];
                    }
                    jac[j * nr + 3 * node + r] = v;
                }
            }
        }
        // Columns of J are contiguous (dot products of length nr); JᵀJ's lower triangle only
        // (the band stores it; a closed loop's dense matrix mirrors it).
        let col = |a: usize| &jac[a * nr..a * nr + nr];
        let dot = |u: &[f64], v: &[f64]| {
            // Eight running sums (vectorised), added pairwise at the end.
            let mut acc = [0.0f64; 8];
            for (a, b) in u.chunks_exact(8).zip(v.chunks_exact(8)) {
                for l in 0..8 {
                    acc[l] += a[l] * b[l];
                }
            }
            let mut s = ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
            let tail = u.len() - u.len() % 8;
            for (a, b) in u[tail..].iter().zip(&v[tail..]) {
                s += a * b;
            }
            s
        };
        let g: Vec<f64> = (0..nl).map(|a| dot(col(a), &r0)).collect();
        let mut blk = Vec::new();
        if hessian {
            blk = vec![0.0; nl * nl];
            for a in 0..nl {
                for b in 0..=a {
                    blk[a * nl + b] = dot(col(a), col(b));
                }
            }
        }
        (blk, g)
    }

    /// Jᵀr alone (= ∇(½E)), fixed parameters left out (zero).
    fn gradient(&self, x: &[f64], fixed: &[bool]) -> Vec<f64> {
        let st = 6 + 3 * self.k;
        let nl = st + 6;
        let parts: Vec<Vec<f64>> =
            (0..self.segs).into_par_iter().map(|i| self.interval_normal(i, x, fixed, false).1).collect();
        let mut g = vec![0.0; x.len()];
        for (i, gl) in parts.iter().enumerate() {
            for (a, j) in self.gidx(i, st, nl).into_iter().enumerate() {
                g[j] += gl[a];
            }
        }
        g
    }

    /// JᵀJ and Jᵀr (for ½E's Gauss–Newton model), fixed parameters held at zero step. The
    /// intervals' shares are computed in parallel and added in interval order (the same sums
    /// at any thread count).
    fn normal_equations(&self, x: &[f64], fixed: &[bool]) -> (Normal, Vec<f64>) {
        let st = 6 + 3 * self.k;
        let nl = st + 6;
        let npar = x.len();
        let mut normal = if self.closed {
            Normal::Dense(nalgebra::DMatrix::zeros(npar, npar))
        } else {
            Normal::Band(Band::zeros(npar, nl - 1))
        };
        let mut g = vec![0.0; npar];
        let parts: Vec<(Vec<f64>, Vec<f64>)> =
            (0..self.segs).into_par_iter().map(|i| self.interval_normal(i, x, fixed, true)).collect();
        for (i, (blk, gl)) in parts.iter().enumerate() {
            let gidx = self.gidx(i, st, nl);
            for a in 0..nl {
                g[gidx[a]] += gl[a];
            }
            match &mut normal {
                Normal::Band(band) => band.add_block(i * st, nl, blk, 1.0),
                Normal::Dense(m) => {
                    for a in 0..nl {
                        for b in 0..nl {
                            m[(gidx[a], gidx[b])] += blk[a.max(b) * nl + a.min(b)];
                        }
                    }
                }
            }
        }
        // Fixed parameters: identity rows (zero step).
        for (j, &f) in fixed.iter().enumerate() {
            if f {
                match &mut normal {
                    Normal::Band(band) => {
                        let idx = band.idx(j, j);
                        band.a[idx] = 1.0;
                    }
                    Normal::Dense(m) => m[(j, j)] = 1.0,
                }
            }
        }
        (normal, g)
    }
}

impl Spline for MinEnergySpline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "min_energy"
    }
    fn joints(&self) -> &[f64] {
        self.nat.joints()
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        // C¹ at the keys bounding a hold (N's rate is pinned to zero there), C² elsewhere.
        if self.holds.iter().any(|&h| h) {
            1
        } else {
            2
        }
    }
    fn closed(&self) -> bool {
        self.closed
    }
}

/// Minimum-∫|ω̈|² interpolation (C⁴): the minimum-penalty curve through every key of a uniform
/// cumulative B-spline space of order 6 with `per_interval` knot intervals per mean key
/// interval, doubled until no knot interval holds more than two keys. Refining `per_interval`
/// by an integer factor nests the spaces. See [`super::fit`] with λ = 0. (Also accepts the
/// acceleration penalty, order 4: the previous discrete form, kept for comparison.)
pub fn min_energy_bspline(
    times: &[f64],
    quats: &[Quat],
    penalty: Penalty,
    per_interval: usize,
    progress: Progress<'_>,
) -> Result<FitResult> {
    let m = penalty.m();
    if !(1..=64).contains(&per_interval) {
        return Err(Error::invalid(
            "resolution",
            format!("expected 1 … 64 knot intervals per key interval, got {per_interval}"),
        ));
    }
    let data = validate(times, quats, None, m + 1, &format!("for penalty={:?}", super::pen_name(penalty)))?;
    let n = data.t.len();
    let span = data.t[n - 1] - data.t[0];
    let crowded = |segs: usize| {
        let h = span / segs as f64;
        let mut count = vec![0u8; segs];
        data.t.iter().any(|&t| {
            let i = (((t - data.t[0]) / h) as usize).min(segs - 1);
            count[i] += 1;
            count[i] > 2
        })
    };
    let mut segs = (n - 1) * per_interval;
    while crowded(segs) {
        if segs > 64 * n {
            return Err(Error::invalid(
                "times",
                format!(
                    "key spacing too uneven for a uniform knot grid ({} knot intervals would be needed)",
                    2 * segs
                ),
            ));
        }
        segs *= 2;
    }
    let opts = FitOptions {
        penalty,
        order: None,
        smoothing: Smoothing::Fixed(0.0),
        knots: Knots::Spacing(span / segs as f64),
        robust: Robust::None,
        robust_scale: None,
        max_iter: 2000,
        tol: 1e-12,
    };
    let k = penalty.default_order();
    let (t0, dt, segs) = knot_layout(&opts.knots, &data.t)?;
    let model = super::model::Model::new(initial_controls(&data, t0, dt, segs, k), dt, t0, k);
    solve(model, &data, &opts, progress)
}

#[cfg(test)]
mod tests {
    use super::super::so3;
    use super::*;

    fn keys(n: usize) -> (Vec<f64>, Vec<Quat>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 + 0.3 * ((i * 7 % 5) as f64) / 5.0).collect();
        let q = t.iter().map(|&s| so3_exp([0.8 * s.sin(), 0.6 * (0.7 * s).cos(), 0.4 * s])).collect();
        (t, q)
    }

    fn so3_exp(v: Vec3) -> Quat {
        super::super::so3::exp(v)
    }

    #[test]
    fn a_hold_between_equal_keys_is_exactly_constant() {
        let (t, mut q) = keys(7);
        q[3] = q[2];
        for ends in [NaturalEnds::Natural, NaturalEnds::Rest] {
            let me = MinEnergySpline::new(&q, Some(&t), ends, 2, &mut |_, _, _| true).unwrap();
            assert!(me.converged && me.energy <= me.energy_natural, "{ends:?}");
            assert_eq!(me.continuity(), 1);
            for k in 1..20 {
                let tk = t[2] + (t[3] - t[2]) * k as f64 / 20.0;
                let d = me.segment::<4>(2, tk).derivatives();
                assert!((d[0].dot(q[2]).abs() - 1.0).abs() <= 4e-16, "{ends:?} at {tk}");
                assert!(d[1..].iter().all(|x| x.to_wxyz() == [0.0; 4]), "{ends:?} at {tk}");
            }
        }
    }

    /// The normal equations as first written (serial, row-major Jacobian, full JᵀJ by plain
    /// sums): the reference the parallel, column-wise assembly is checked against.
    fn normal_equations_reference(c: &Cache, x: &[f64], fixed: &[bool]) -> (Vec<Vec<f64>>, Vec<f64>) {
        let st = 6 + 3 * c.k;
        let nl = st + 6;
        let npar = x.len();
        let mut hm = vec![vec![0.0; npar]; npar];
        let mut g = vec![0.0; npar];
        let mut r0 = Vec::new();
        for i in 0..c.segs {
            let p = local_params(x, i, st, c.segs, c.closed);
            let gidx = c.gidx(i, st, nl);
            c.residuals(i, &p, &mut r0);
            let nr = r0.len();
            let mut jac = vec![0.0; nr * nl];
            let h = c.h[i];
            let m = PIECES * NODES;
            for (node, n) in (i * m..(i + 1) * m).enumerate() {
                let d = delta(&p, c.k, h, &c.herm[n], &c.bub[n]);
                let sw = c.w[n].sqrt();
                let mut dm = [[0.0f64; 9]; 3];
                for cc in 0..3 {
                    for o in 0..3 {
                        let e = 1e-6 / h.powi(o as i32);
                        let mut dp = d;
                        dp[cc].0[o] += e;
                        let ap = alpha_body(c.nq[n] * exp_rotvec(dp));
                        dp[cc].0[o] -= 2.0 * e;
                        let am = alpha_body(c.nq[n] * exp_rotvec(dp));
                        for r in 0..3 {
                            dm[r][3 * cc + o] = sw * (ap[r] - am[r]) / (2.0 * e);
                        }
                    }
                }
                for j in 0..nl {
                    if fixed[gidx[j]] {
                        continue;
                    }
                    let (basis, scale, comp) = if j < 3 {
                        (c.herm[n][0], h, j)
                    } else if j < 6 {
                        (c.herm[n][1], h * h, j - 3)
                    } else if j < st {
                        (c.bub[n][(j - 6) / 3], 1.0, (j - 6) % 3)
                    } else if j < st + 3 {
                        (c.herm[n][2], h, j - st)
                    } else {
                        (c.herm[n][3], h * h, j - st - 3)
                    };
                    for r in 0..3 {
                        jac[(3 * node + r) * nl + j] =
                            (0..3).map(|o| dm[r][3 * comp + o] * scale * basis.0[o]).sum::<f64>();
                    }
                }
            }
            for a in 0..nl {
                for b in 0..nl {
                    hm[gidx[a]][gidx[b]] += (0..nr).map(|r| jac[r * nl + a] * jac[r * nl + b]).sum::<f64>();
                }
                g[gidx[a]] += (0..nr).map(|r| jac[r * nl + a] * r0[r]).sum::<f64>();
            }
        }
        for (j, &f) in fixed.iter().enumerate() {
            if f {
                hm[j][j] = 1.0;
            }
        }
        (hm, g)
    }

    #[test]
    fn normal_equations_and_gradient_match_the_serial_reference() {
        let (t, q) = keys(12);
        for (ends, res) in [(NaturalEnds::Natural, 3), (NaturalEnds::Rest, 2), (NaturalEnds::Closed, 2)] {
            let mut tt = t.clone();
            if ends == NaturalEnds::Closed {
                tt.push(t[t.len() - 1] + 1.0);
            }
            let me = MinEnergySpline::new(&q, Some(&tt), ends, res, &mut |_, _, _| true).unwrap();
            let cache = Cache::new(&me);
            let n = me.x.len();
            let mut fixed = vec![false; n];
            if ends == NaturalEnds::Rest {
                fixed[0..3].iter_mut().for_each(|f| *f = true);
                fixed[n - 6..n - 3].iter_mut().for_each(|f| *f = true);
            }
            // Away from the optimum too (a non-trivial residual and gradient).
            let x: Vec<f64> =
                me.x.iter().enumerate().map(|(i, v)| v + 1e-3 * ((i * 7 % 11) as f64 - 5.0)).collect();
            let (hm, gr) = normal_equations_reference(&cache, &x, &fixed);
            let (h, g) = cache.normal_equations(&x, &fixed);
            let gs = cache.gradient(&x, &fixed);
            let scale = hm.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
            let gscale = gr.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(gscale > 0.0 && scale > 0.0);
            for a in 0..n {
                assert!((g[a] - gr[a]).abs() <= 1e-12 * gscale, "{ends:?} g[{a}]");
                assert!((gs[a] - gr[a]).abs() <= 1e-12 * gscale, "{ends:?} gradient[{a}]");
                for b in 0..n {
                    let v = match &h {
                        Normal::Band(band) => {
                            let (r, c) = (a.max(b), a.min(b));
                            if r - c > band.p {
                                0.0
                            } else {
                                band.a[band.idx(r, c)]
                            }
                        }
                        Normal::Dense(m) => m[(a, b)],
                    };
                    assert!(
                        (v - hm[a][b]).abs() <= 1e-12 * scale,
                        "{ends:?} H[{a}, {b}]: {v} vs {}",
                        hm[a][b]
                    );
                }
            }
        }
    }

    #[test]
    fn hermite_basis_has_the_stated_end_derivatives() {
        for (idx, want0, want1) in [(0, [0.0, 1.0, 0.0], [0.0; 3]), (1, [0.0, 0.0, 1.0], [0.0; 3])]
            .into_iter()
            .chain([(2, [0.0; 3], [0.0, 1.0, 0.0]), (3, [0.0; 3], [0.0, 0.0, 1.0])])
        {
            for (u, want) in [(0.0, want0), (1.0, want1)] {
                let j = quintic_hermite::<3>(Jet::variable(u, 1.0))[idx];
                for d in 0..3 {
                    assert!((j.derivative(d) - want[d]).abs() < 1e-13, "H{idx} d{d} at {u}");
                }
            }
        }
        // Bubbles vanish with two derivatives at both ends.
        let mut b = Vec::new();
        for u in [0.0, 1.0] {
            bubbles::<3>(Jet::variable(u, 1.0), 5, &mut b);
            assert!(b.iter().all(|j| (0..3).all(|d| j.derivative(d).abs() < 1e-13)));
        }
    }

    #[test]
    fn interpolates_is_c2_and_never_above_the_natural_energy() {
        let (t, q) = keys(9);
        for ends in [NaturalEnds::Natural, NaturalEnds::Rest, NaturalEnds::Closed] {
            let mut tt = t.clone();
            if ends == NaturalEnds::Closed {
                tt.push(t[t.len() - 1] + 1.0);
            }
            let me = MinEnergySpline::new(&q, Some(&tt), ends, 3, &mut |_, _, _| true).unwrap();
            assert!(me.energy <= me.energy_natural, "{ends:?}");
            assert!(me.energy < me.energy_natural * (1.0 - 1e-6), "{ends:?}: natural not optimal here");
            assert!((me.energy_of() - me.energy).abs() <= 1e-12 * me.energy);
            for (i, &ti) in t.iter().enumerate() {
                let v = me.segment::<1>(i.min(me.intervals() - 1), ti).value();
                assert!(crate::vec3::norm(so3::log(v.conj() * q[i])) < 1e-12, "{ends:?} key {i}");
            }
            for i in 1..me.intervals() {
                let tj = me.joints()[i];
                let (l, r) = (me.segment::<3>(i - 1, tj).derivatives(), me.segment::<3>(i, tj).derivatives());
                for d in 0..3 {
                    let (a, b) = (l[d], r[d]);
                    let diff = (a.w - b.w).abs() + (a.x - b.x).abs() + (a.y - b.y).abs() + (a.z - b.z).abs();
                    assert!(diff < 1e-9, "{ends:?} joint {i} derivative {d}: {diff}");
                }
            }
        }
    }
}
