//! Reparameterised splines q(s(t)): the same path on a new clock, with exact derivatives.
//!
//! For any inner spline q(s) and a smooth increasing map s(t), the composed curve's Taylor
//! series at t is q's series at s(t) composed with the series of s (Faà di Bruno, carried out
//! on jets): q(s(t + h)) = Σₘ qₘ σ(h)ᵐ with σ(h) = s(t + h) − s(t) and qₘ the inner Taylor
//! coefficients. Two maps:
//!
//! - [`TimeMap::Scale`]: s = s₀ + (t − t₀)/λ (uniform time stretch by λ; ω scales by 1/λ, the
//!   angular acceleration by 1/λ², the jerk by 1/λ³).
//! - arc length ([`Reparameterized::arc_length`]): φ(s) = ∫ |ω(σ)| dσ from the start (|ω| =
//!   2|q'| for a unit q), t = t₀ + φ(s)/c with c = L/(t₁ − t₀), so the domain is kept and the
//!   angular speed is the constant c everywhere the inner curve moves. φ is tabulated with
//!   adaptive Gauss–Legendre quadrature (8 nodes; a piece is split until one rule and its two
//!   halves agree to 1e-13 of the estimated total length), and s(t) is found by safeguarded
//!   Newton on φ(s) = c (t − t₀) inside the piece (φ' = |ω|). The derivatives of s come from
//!   s' = c / v(s) solved in Taylor mode with the inner speed v as a jet in s, so the
//!   composed derivatives are exact: s'' = −c² v'/v³, s''' = c³ (3v'² − v v'')/v⁵.
//!
//! Continuity: the same order as the inner spline (v is C^(k−1) where q is C^k, so s is C^k).
//! Holds — stretches where the inner curve does not move — take no time after arc-length
//! reparameterisation (a segment of zero length is dropped); at an isolated point where the
//! inner speed is exactly zero the derivatives of s are infinite and are reported as zero.

use super::{segment_jets, Spline};
use crate::error::{Error, Result, Short};
use crate::jet::{JQuat, Jet};
use crate::quadrature::{GL8_W, GL8_X};
use std::sync::Arc;

/// Angular speed |ω| = 2|q'| of segment `seg` at s.
#[inline]
fn speed(s: &dyn Spline, seg: usize, x: f64) -> f64 {
    2.0 * s.segment_jet2(seg, x).derivative(1).norm()
}

fn gauss(s: &dyn Spline, seg: usize, a: f64, b: f64) -> f64 {
    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
    GL8_X.iter().zip(GL8_W).map(|(&x, w)| w * speed(s, seg, m + h * x)).sum::<f64>() * h
}

/// One tabulated piece of φ(s): [lo, hi] in inner segment `seg`, φ(lo) = `phi`.
#[derive(Debug, Clone, Copy)]
struct Piece {
    seg: usize,
    lo: f64,
    hi: f64,
    phi: f64,
    /// Angular speed at `lo` and `hi` (for the Hermite first guess of the inverse).
    v_lo: f64,
    v_hi: f64,
}

/// The clock of a reparameterised spline.
#[derive(Debug, Clone)]
pub enum TimeMap {
    /// s = s0 + (t − t0) / factor.
    Scale { t0: f64, s0: f64, factor: f64 },
    /// Constant angular speed `c` (arc length φ = c (t − t0)).
    ArcLength { t0: f64, c: f64 },
}

/// A spline traced on a new clock (see the module doc).
pub struct Reparameterized {
    inner: Arc<dyn Spline>,
    map: TimeMap,
    joints: Vec<f64>,
    /// Inner segment of each outer segment.
    inner_seg: Vec<usize>,
    /// Arc-length pieces (empty for `Scale`), sorted by φ; `ranges[i]` are the pieces of outer
    /// segment i and `seg_end_phi[i]` is φ at its end.
    pieces: Vec<Piece>,
    ranges: Vec<(usize, usize)>,
    seg_end_phi: Vec<f64>,
    length: f64,
    name: &'static str,
}

impl Reparameterized {
    /// Uniform time stretch by `factor` > 0 about the start of the domain.
    pub fn scaled(inner: Arc<dyn Spline>, factor: f64) -> Result<Self> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(Error::invalid(
                "factor",
                format!("expected a finite positive factor, got {}", Short(factor)),
            ));
        }
        let (a, _) = inner.domain();
        let joints: Vec<f64> = inner.joints().iter().map(|&s| a + (s - a) * factor).collect();
        for i in 1..joints.len() {
            super::check_span("factor", joints[i - 1], joints[i], i)?;
        }
        let n = joints.len() - 1;
        Ok(Reparameterized {
            inner,
            map: TimeMap::Scale { t0: a, s0: a, factor },
            joints,
            inner_seg: (0..n).collect(),
            pieces: Vec::new(),
            ranges: Vec::new(),
            seg_end_phi: Vec::new(),
            length: f64::NAN,
            name: "retimed",
        })
    }

    /// Arc-length (constant angular speed) reparameterisation on the same domain.
    /// Errors when the inner spline does not rotate at all (zero path length).
    pub fn arc_length(inner: Arc<dyn Spline>) -> Result<Self> {
        let s: &dyn Spline = &*inner;
        let j = s.joints().to_vec();
        let (a, b) = (j[0], j[j.len() - 1]);
        // A first estimate of the total length sets the absolute tolerance.
        let mut estimate = 0.0;
        for seg in 0..j.len() - 1 {
            for p in 0..16 {
                let (x0, x1) = (
                    j[seg] + (j[seg + 1] - j[seg]) * p as f64 / 16.0,
                    j[seg] + (j[seg + 1] - j[seg]) * (p + 1) as f64 / 16.0,
                );
                estimate += gauss(s, seg, x0, x1);
            }
        }
        if !estimate.is_finite() {
            return Err(Error::invalid("spline", "the angular speed is not finite"));
        }
        // Rounding in the keys alone leaves ~1e-16 rad per segment: below 1e-14 rad per
        // segment there is no path to follow.
        let floor = 1e-14 * (j.len() - 1) as f64;
        if estimate <= floor {
            return Err(Error::invalid(
                "spline",
                format!("the spline does not rotate (path length {estimate:.3e} rad ≤ {floor:.0e})"),
            ));
        }
        let tol = 1e-13 * estimate;
        // Memory bound: at most 256 pieces per segment on average (plus slack); beyond, the
        // remaining pieces are kept unsplit (still 8-point Gauss–Legendre accurate).
        let cap = 256 * (j.len() - 1) + 4096;
        let mut pieces = Vec::new();
        let mut phi = 0.0;
        let mut seg_phi = vec![0.0];
        for seg in 0..j.len() - 1 {
            let (lo, hi) = (j[seg], j[seg + 1]);
            // recursion on an explicit stack, left to right
            let mut stack = Vec::new();
            for p in (0..4).rev() {
                let x0 = lo + (hi - lo) * p as f64 / 4.0;
                let x1 = if p == 3 { hi } else { lo + (hi - lo) * (p + 1) as f64 / 4.0 };
                stack.push((x0, x1, 0u32));
            }
            while let Some((x0, x1, depth)) = stack.pop() {
                let whole = gauss(s, seg, x0, x1);
                let m = 0.5 * (x0 + x1);
                let halves = gauss(s, seg, x0, m) + gauss(s, seg, m, x1);
                let width_share = (x1 - x0) / (b - a);
                let budget_spent = pieces.len() + stack.len() >= cap;
                if (whole - halves).abs() <= tol * width_share.max(1e-6)
                    || depth >= 30
                    || budget_spent
                    || m <= x0
                    || m >= x1
                {
                    pieces.push(Piece {
                        seg,
                        lo: x0,
                        hi: x1,
                        phi,
                        v_lo: speed(s, seg, x0),
                        v_hi: speed(s, seg, x1),
                    });
                    phi += halves;
                } else {
                    stack.push((m, x1, depth + 1));
                    stack.push((x0, m, depth + 1));
                }
            }
            seg_phi.push(phi);
        }
        let length = phi;
        let c = length / (b - a);
        // Outer joints: images of inner joints, dropping segments of (near) zero length.
        let mut joints = vec![a];
        let mut inner_seg = Vec::new();
        let mut ranges = Vec::new();
        let mut seg_end_phi = Vec::new();
        for seg in 0..j.len() - 1 {
            let t1 = if seg == j.len() - 2 { b } else { a + seg_phi[seg + 1] / c };
            let t0 = *joints.last().unwrap_or(&a);
            if t1 - t0 > super::MIN_RELATIVE_SPACING * 1f64.max(t0.abs()).max(t1.abs()) * 16.0 {
                joints.push(t1);
                inner_seg.push(seg);
                let start = pieces.partition_point(|p| p.seg < seg);
                let end = pieces.partition_point(|p| p.seg <= seg);
                ranges.push((start, end));
                seg_end_phi.push(seg_phi[seg + 1]);
            } else if seg == j.len() - 2 && !inner_seg.is_empty() {
                // the last segment is too short: the previous outer segment ends at b
                *joints.last_mut().unwrap() = b;
            }
        }
        if inner_seg.is_empty() {
            return Err(Error::invalid("spline", "the spline's rotation is too small to reparameterise"));
        }
        Ok(Reparameterized {
            inner,
            map: TimeMap::ArcLength { t0: a, c },
            joints,
            inner_seg,
            pieces,
            ranges,
            seg_end_phi,
            length,
            name: "arc_length",
        })
    }

    /// The total rotation angle ∫|ω| (arc length map only; NaN for a time stretch).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The time map.
    pub fn map(&self) -> &TimeMap {
        &self.map
    }

    /// The inner parameter s at t on outer segment `i`.
    fn inner_time(&self, i: usize, t: f64) -> f64 {
        match self.map {
            TimeMap::Scale { t0, s0, factor } => s0 + (t - t0) / factor,
            TimeMap::ArcLength { t0, c } => self.invert(i, c * (t - t0)),
        }
    }

    /// s with φ(s) = target, within the pieces of outer segment i.
    fn invert(&self, i: usize, target: f64) -> f64 {
        let s: &dyn Spline = &*self.inner;
        let (start, end) = self.ranges[i];
        let ps = &self.pieces[start..end];
        let k = ps.partition_point(|p| p.phi <= target).saturating_sub(1);
        let p = ps[k];
        let next_phi = if k + 1 < ps.len() { ps[k + 1].phi } else { self.seg_end_phi[i] };
        if target <= p.phi {
            return p.lo;
        }
        if target >= next_phi {
            return p.hi;
        }
        let (mut lo, mut hi) = (p.lo, p.hi);
        // First guess: the cubic Hermite interpolant of s(φ) with ds/dφ = 1/v at the piece's
        // ends (error O(width⁴)), so one Newton step usually reaches rounding level.
        let dphi = next_phi - p.phi;
        let u = (target - p.phi) / dphi;
        let linear = lo + (hi - lo) * u;
        let mut x = if p.v_lo > 0.0 && p.v_hi > 0.0 {
            let (m0, m1) = (dphi / p.v_lo, dphi / p.v_hi);
            let (u2, u3) = (u * u, u * u * u);
            let g = (2.0 * u3 - 3.0 * u2 + 1.0) * lo
                + (u3 - 2.0 * u2 + u) * m0
                + (3.0 * u2 - 2.0 * u3) * hi
                + (u3 - u2) * m1;
            if g > lo && g < hi {
                g
            } else {
                linear
            }
        } else {
            linear
        };
        for _ in 0..60 {
            let f = p.phi + gauss(s, p.seg, p.lo, x) - target;
            if f == 0.0 {
                return x;
            }
            if f > 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            let v = speed(s, p.seg, x);
            let mut nx = if v > 0.0 { x - f / v } else { f64::NAN };
            if !(nx > lo && nx < hi) {
                nx = 0.5 * (lo + hi);
            }
            // Newton converges quadratically: after a step below 1e-12 of the piece the next
            // one would change nothing (1e-8 was measurably too loose: 1.4e-9 rad off the path).
            let tiny_step = (nx - x).abs() <= 1e-12 * (p.hi - p.lo) && v > 0.0;
            if tiny_step
                || (nx - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE)
                || hi - lo <= 2.0 * f64::EPSILON * x.abs()
            {
                return nx;
            }
            x = nx;
        }
        x
    }

    #[inline]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let seg = self.inner_seg[i];
        let s = self.inner_time(i, t);
        let inner = self.inner.segment_jet4(seg, s);
        if N == 1 {
            return compose_quat(&inner, Jet::<N>::constant(0.0));
        }
        let sigma = match self.map {
            TimeMap::Scale { factor, .. } => Jet::<N>::variable(0.0, 1.0 / factor),
            TimeMap::ArcLength { c, .. } => {
                // v(s) = 2|q'(s)| as a jet in s from the inner coefficients (q' has (k+1) q_{k+1}).
                let qs = [inner.w, inner.x, inner.y, inner.z]
                    .map(|j| Jet::<3>([j.0[1], 2.0 * j.0[2], 3.0 * j.0[3]]));
                let vv = (qs[0] * qs[0] + qs[1] * qs[1] + qs[2] * qs[2] + qs[3] * qs[3]).sqrt() * 2.0;
                if vv.0[0] <= 1e-300 || !vv.0[0].is_finite() {
                    Jet::<N>::constant(0.0)
                } else {
                    let f = vv.recip() * c; // s'(t) = F(s) = c / v(s)
                    let mut sigma = Jet::<N>::constant(0.0);
                    for _ in 1..N {
                        let fs = compose_scalar(&f.0, sigma);
                        let mut next = Jet::<N>::constant(0.0);
                        for k in 0..N - 1 {
                            next.0[k + 1] = fs.0[k] / (k + 1) as f64;
                        }
                        sigma = next;
                    }
                    sigma
                }
            }
        };
        compose_quat(&inner, sigma)
    }
}

/// Σ_{m<min(M,N)} g[m] σᵐ for σ with zero constant term (terms m ≥ N vanish).
#[inline]
fn compose_scalar<const M: usize, const N: usize>(g: &[f64; M], sigma: Jet<N>) -> Jet<N> {
    let mut out = Jet::<N>::constant(0.0);
    let mut p = Jet::<N>::constant(1.0);
    for (m, &gm) in g.iter().enumerate().take(N) {
        if m > 0 {
            p = p * sigma;
        }
        out = out + p * gm;
    }
    out
}

#[inline]
fn compose_quat<const N: usize>(q: &JQuat<4>, sigma: Jet<N>) -> JQuat<N> {
    JQuat {
        w: compose_scalar(&q.w.0, sigma),
        x: compose_scalar(&q.x.0, sigma),
        y: compose_scalar(&q.y.0, sigma),
        z: compose_scalar(&q.z.0, sigma),
    }
}

impl Spline for Reparameterized {
    segment_jets!();
    fn name(&self) -> &'static str {
        self.name
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        self.inner.interpolates()
    }
    fn continuity(&self) -> u8 {
        self.inner.continuity()
    }
}

/// The largest |ω| (order 1), |dω/dt| (order 2) or |d²ω/dt²| (order 3) over the domain, and a
/// time where it is reached: every segment sampled at 64 points (its own formula, ends
/// included), then each sampled local maximum refined by golden-section search to 1e-13 of
/// the segment. The norm is the same in the world and body frames.
pub fn max_rate(s: &dyn Spline, order: usize) -> Result<(f64, f64)> {
    if !(1..=3).contains(&order) {
        return Err(Error::invalid("order", format!("expected 1, 2 or 3, got {order}")));
    }
    let j = s.joints();
    let f = |seg: usize, t: f64| -> f64 {
        let d = super::derivatives_on(s, seg, t, order);
        let v = crate::jet::angular(&d, order, false);
        crate::vec3::norm(v)
    };
    let (mut best, mut arg) = (0.0f64, j[0]);
    const M: usize = 64;
    for seg in 0..j.len() - 1 {
        let (a, b) = (j[seg], j[seg + 1]);
        let x: Vec<f64> =
            (0..=M).map(|i| if i == M { b } else { a + (b - a) * i as f64 / M as f64 }).collect();
        let y: Vec<f64> = x.iter().map(|&t| f(seg, t)).collect();
        if let Some(k) = y.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid("spline", format!("non-finite rate at t = {}", Short(x[k]))));
        }
        for i in 0..=M {
            let left = if i > 0 { y[i - 1] } else { f64::NEG_INFINITY };
            let right = if i < M { y[i + 1] } else { f64::NEG_INFINITY };
            if y[i] < left || y[i] < right {
                continue;
            }
            let (mut lo, mut hi) = (x[i.saturating_sub(1)], x[(i + 1).min(M)]);
            let g = 0.618_033_988_749_894_9;
            let mut c = hi - g * (hi - lo);
            let mut d = lo + g * (hi - lo);
            let (mut fc, mut fd) = (f(seg, c), f(seg, d));
            while hi - lo > 1e-13 * (b - a) {
                if fc >= fd {
                    hi = d;
                    d = c;
                    fd = fc;
                    c = hi - g * (hi - lo);
                    fc = f(seg, c);
                } else {
                    lo = c;
                    c = d;
                    fc = fd;
                    d = lo + g * (hi - lo);
                    fd = f(seg, d);
                }
            }
            for (t, v) in [(x[i], y[i]), (c, fc), (d, fd)] {
                if v > best {
                    best = v;
                    arg = t;
                }
            }
        }
    }
    Ok((best, arg))
}
