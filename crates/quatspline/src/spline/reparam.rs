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
//!   halves agree to 1e-13 of the estimated total length). The inverse s(φ) is tabulated too
//!   ([`InversePiece`]): on each quadrature piece, halved where needed, the septic Hermite
//!   interpolant in φ of s with s and its first three φ-derivatives at both ends
//!   (ds/dφ = 1/v, d²s/dφ² = −v'/v³, d³s/dφ³ = (3v'² − v v'')/v⁵; v, v', v'' from the inner
//!   jet of order 4). A piece is kept when (i) its Bernstein coefficients increase strictly,
//!   so s(φ) is strictly increasing on it (sufficient: the derivative's Bernstein
//!   coefficients are 7× their differences), and (ii) at the three check points
//!   s = lo + (hi − lo)·{¼, ½, ¾} (the Hermite error u⁴(1 − u)⁴ w⁸ s⁽⁸⁾/8! peaks inside) the
//!   table maps φ(s), integrated by 8-point Gauss–Legendre, back to within [`INVERSE_TOL`] of
//!   the segment's arc length: v(s)·|s_tab(φ(s)) − s| ≤ 1e-12 Lᵢ, with Lᵢ the arc length of
//!   inner segment i. φ at the middle comes from the quadrature (or the parent's check), so a
//!   check costs two 8-point rules and three speeds; a piece that fails is halved, its check
//!   values at ¼ and ¾ becoming the halves' middles. A piece whose own arc length Δφ is
//!   ≤ 1e-12 Lᵢ (next to a point where the inner curve stops, where s(φ) has an infinite
//!   slope) is linear in φ: monotone and within Δφ of the true inverse, so within the bound
//!   too. After 40 halvings of a quadrature piece, or beyond 256 table pieces per segment on
//!   average, a piece is kept without the check. Evaluating s(t) is then a binary search
//!   among the segment's pieces (a few for smooth curves) and a polynomial of degree 7,
//!   clamped to the piece: no inner evaluation. The derivatives
//!   of s come from s' = c / v(s) solved in Taylor mode with the inner speed v as a jet in s,
//!   so the composed derivatives are exact: s'' = −c² v'/v³, s''' = c³ (3v'² − v v'')/v⁵.
//!
//! Batch evaluation ([`crate::simd::BatchKernel`]): where the inner spline has batch kernels,
//! a run of samples is mapped first — t → (inner segment, s(t)), the same numbers as the
//! per-sample path — and the inner kernel then evaluates the whole run of s at once. Values
//! (and first derivatives) and ω take this path; the rows equal the per-sample path's to the
//! inner kernel's own bound. With c the constant speed and ω_in the inner angular velocity at
//! s, the chain rule gives q'(t) = q_in'(s)·s'(t) and ω(t) = ω_in(s)·s'(t), s'(t) = c/v(s),
//! v = |ω_in(s)| = 2|q_in'(s)|; for a time stretch s' = 1/λ and the k-th derivative or rate
//! scales by λ⁻ᵏ. Higher orders of an arc-length map keep the jets.
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

/// One quadrature piece of φ(s): [lo, hi] in inner segment `seg`, φ(lo) = `phi`, and
/// φ at the middle `mid_phi` (the left half's integral, computed by the quadrature's check).
#[derive(Debug, Clone, Copy)]
struct Piece {
    seg: usize,
    lo: f64,
    hi: f64,
    phi: f64,
    mid_phi: f64,
}

/// Bound on the tabulated inverse, relative to the arc length Lᵢ of the inner segment:
/// v(s)·|s_tab(φ(s)) − s| ≤ `INVERSE_TOL`·Lᵢ at the check points of every piece (module doc).
pub const INVERSE_TOL: f64 = 1e-12;

/// Halvings of a quadrature piece before a table piece is kept unchecked.
const INVERSE_MAX_DEPTH: u32 = 40;

/// Degree of the table's pieces (Hermite data: s and its first three derivatives at both ends).
const DEG: usize = 7;

/// One piece of the tabulated inverse s(φ): for φ in [`phi`, φ of the next piece],
/// s = c₀ + u (c₁ + u (c₂ + ⋯ + u c₇)) with u = (φ − `phi`)·`inv_width`, clamped to
/// [c₀, `hi`] (see the module doc).
#[derive(Debug, Clone, Copy)]
struct InversePiece {
    phi: f64,
    /// 1/Δφ (0 for a piece of zero arc length).
    inv_width: f64,
    c: [f64; DEG + 1],
    /// s at the end of the piece.
    hi: f64,
}

impl InversePiece {
    #[inline(always)]
    fn eval(&self, target: f64) -> f64 {
        let u = (target - self.phi) * self.inv_width;
        let c = &self.c;
        if u >= 1.0 {
            self.hi
        } else if u > 0.0 {
            let p = c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * (c[5] + u * (c[6] + u * c[7])))));
            (c[0] + u * p).clamp(c[0], self.hi)
        } else if u.is_nan() {
            u
        } else {
            c[0]
        }
    }
}

/// The inverse map's local data at s = `x`: the angular speed v = 2|q'| and the Taylor
/// coefficients [s', s''/2, s'''/6] of s(φ) in φ (`None` where the curve stops or the data
/// are not finite).
#[derive(Debug, Clone, Copy)]
struct Node {
    x: f64,
    taylor: Option<[f64; 3]>,
}

/// [`Node`] at s = `x` of segment `seg`: ds/dφ = 1/v(s) solved in Taylor mode with v a jet in
/// s from the inner jet of order 4 (s' = 1/v, s'' = −v'/v³, s''' = (3v'² − v v'')/v⁵).
fn node(s: &dyn Spline, seg: usize, x: f64) -> Node {
    let j = s.segment_jet4(seg, x);
    let qs = [j.w, j.x, j.y, j.z].map(|c| Jet::<3>([c.0[1], 2.0 * c.0[2], 3.0 * c.0[3]]));
    let vv = (qs[0] * qs[0] + qs[1] * qs[1] + qs[2] * qs[2] + qs[3] * qs[3]).sqrt() * 2.0;
    let v = vv.0[0];
    if !(v > 1e-300 && v.is_finite()) {
        return Node { x, taylor: None };
    }
    let f = vv.recip();
    let mut sigma = Jet::<4>::constant(0.0);
    for _ in 1..4 {
        let fs = compose_scalar(&f.0, sigma);
        let mut next = Jet::<4>::constant(0.0);
        for k in 0..3 {
            next.0[k + 1] = fs.0[k] / (k + 1) as f64;
        }
        sigma = next;
    }
    let t = [sigma.0[1], sigma.0[2], sigma.0[3]];
    Node { x, taylor: t.iter().all(|c| c.is_finite()).then_some(t) }
}

/// C(7, k).
const BINOM7: [f64; DEG + 1] = [1.0, 7.0, 21.0, 35.0, 35.0, 21.0, 7.0, 1.0];

/// The septic Hermite piece of s(φ) between nodes `n0` and `n1` with φ(n0.x) = φ0,
/// φ(n1.x) = φ1; `None` when data are missing or the piece is not strictly increasing.
///
/// In u = (φ − φ0)/w, w = φ1 − φ0, with Taylor coefficients Aₖ = aₖ wᵏ at u = 0 and Bₖ at
/// u = 1, the Bernstein coefficients relative to s₀ are b₀ = 0, b₁ = A₁/7,
/// b₂ = 2A₁/7 + A₂/21, b₃ = 3A₁/7 + 3A₂/21 + A₃/35 and, with Δ = s₁ − s₀, b₇ = Δ,
/// b₆ = Δ − B₁/7, b₅ = Δ − 2B₁/7 + B₂/21, b₄ = Δ − 3B₁/7 + 3B₂/21 − B₃/35 (the end
/// derivatives of a Bézier curve by its differences). Strictly increasing Bernstein
/// coefficients make the derivative's (7× their differences) positive: s(φ) strictly
/// increases on the piece.
fn septic_piece(n0: &Node, n1: &Node, phi0: f64, phi1: f64) -> Option<InversePiece> {
    let w = phi1 - phi0;
    let (a, b) = (n0.taylor?, n1.taylor?);
    if !(w > 0.0 && w.is_finite()) {
        return None;
    }
    let (a1, a2, a3) = (a[0] * w, a[1] * w * w, a[2] * w * w * w);
    let (b1, b2, b3) = (b[0] * w, b[1] * w * w, b[2] * w * w * w);
    let dy = n1.x - n0.x;
    let bz = [
        0.0,
        a1 / 7.0,
        2.0 * a1 / 7.0 + a2 / 21.0,
        3.0 * a1 / 7.0 + 3.0 * a2 / 21.0 + a3 / 35.0,
        dy - 3.0 * b1 / 7.0 + 3.0 * b2 / 21.0 - b3 / 35.0,
        dy - 2.0 * b1 / 7.0 + b2 / 21.0,
        dy - b1 / 7.0,
        dy,
    ];
    if !bz.windows(2).all(|p| p[1] > p[0]) {
        return None;
    }
    // power basis: c_k = C(7, k) Σᵢ (−1)^(k−i) C(k, i) bᵢ
    let mut c = [0.0; DEG + 1];
    for (k, ck) in c.iter_mut().enumerate().skip(1) {
        let mut acc = 0.0;
        let mut binom = 1.0; // C(k, i)
        for (i, bi) in bz.iter().enumerate().take(k + 1) {
            let sign = if (k - i) % 2 == 0 { 1.0 } else { -1.0 };
            acc += sign * binom * bi;
            binom = binom * (k - i) as f64 / (i + 1) as f64;
        }
        *ck = BINOM7[k] * acc;
    }
    c[0] = n0.x;
    Some(InversePiece { phi: phi0, inv_width: 1.0 / w, c, hi: n1.x })
}

/// The linear piece of s(φ) on [x0, x1] (monotone; used where Δφ is within the bound).
fn linear_piece(x0: f64, x1: f64, phi0: f64, phi1: f64) -> InversePiece {
    let w = phi1 - phi0;
    let inv_width = if w > 0.0 { 1.0 / w } else { 0.0 };
    let mut c = [0.0; DEG + 1];
    (c[0], c[1]) = (x0, x1 - x0);
    InversePiece { phi: phi0, inv_width, c, hi: x1 }
}

/// Appends the table pieces of quadrature piece `p` (φ at its end `phi1`) to `out`, left to
/// right; `tol` is the absolute bound in φ. A piece [a, b] with φ known at a, m = (a + b)/2
/// and b is checked at ¼, ½ and ¾ (φ at ¼ and ¾ by 8-point Gauss–Legendre from a and from
/// m); when it fails it is halved, and those two values are the halves' φ at their middles.
fn tabulate_inverse(s: &dyn Spline, p: &Piece, phi1: f64, tol: f64, cap: usize, out: &mut Vec<InversePiece>) {
    let seg = p.seg;
    // (left node, right node, φ at a, φ at m, φ at b, depth)
    type Job = (Node, Node, f64, f64, f64, u32);
    let mut stack: Vec<Job> = vec![(node(s, seg, p.lo), node(s, seg, p.hi), p.phi, p.mid_phi, phi1, 0)];
    while let Some((na, nb, pa, pm, pb, depth)) = stack.pop() {
        let (a, b) = (na.x, nb.x);
        if pb - pa <= tol {
            out.push(linear_piece(a, b, pa, pb));
            continue;
        }
        let m = 0.5 * (a + b);
        let last_chance = depth >= INVERSE_MAX_DEPTH || out.len() + stack.len() >= cap || m <= a || m >= b;
        let piece = septic_piece(&na, &nb, pa, pb);
        if last_chance {
            out.push(piece.unwrap_or_else(|| linear_piece(a, b, pa, pb)));
            continue;
        }
        let (q1, q3) = (0.5 * (a + m), 0.5 * (m + b));
        let p1 = pa + gauss(s, seg, a, q1);
        let p3 = pm + gauss(s, seg, m, q3);
        if let Some(piece) = piece {
            let ok = [(q1, p1), (m, pm), (q3, p3)]
                .iter()
                .all(|&(x, phi)| (piece.eval(phi) - x).abs() * speed(s, seg, x) <= tol);
            if ok {
                out.push(piece);
                continue;
            }
        }
        let nm = node(s, seg, m);
        stack.push((nm, nb, pm, p3, pb, depth + 1));
        stack.push((na, nm, pa, p1, pm, depth + 1));
    }
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
    /// The tabulated inverse s(φ) (empty for `Scale`), sorted by φ; `ranges[i]` are the
    /// pieces of outer segment i.
    table: Vec<InversePiece>,
    ranges: Vec<(usize, usize)>,
    length: f64,
    name: &'static str,
    /// Segment search over `joints` for the batch path.
    locator: crate::simd::Locator,
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
            inner_seg: (0..n).collect(),
            table: Vec::new(),
            ranges: Vec::new(),
            length: f64::NAN,
            name: "retimed",
            locator: crate::simd::Locator::new(&joints),
            joints,
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
                let left = gauss(s, seg, x0, m);
                let halves = left + gauss(s, seg, m, x1);
                let width_share = (x1 - x0) / (b - a);
                let budget_spent = pieces.len() + stack.len() >= cap;
                if (whole - halves).abs() <= tol * width_share.max(1e-6)
                    || depth >= 30
                    || budget_spent
                    || m <= x0
                    || m >= x1
                {
                    pieces.push(Piece { seg, lo: x0, hi: x1, phi, mid_phi: phi + left });
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
        // The inverse table, segment by segment (`table_start[seg]` = its first piece).
        let mut table = Vec::with_capacity(pieces.len());
        let mut table_start = vec![0];
        for (k, p) in pieces.iter().enumerate() {
            let end_phi = match pieces.get(k + 1) {
                Some(q) if q.seg == p.seg => q.phi,
                _ => seg_phi[p.seg + 1],
            };
            let tol = INVERSE_TOL * (seg_phi[p.seg + 1] - seg_phi[p.seg]);
            tabulate_inverse(s, p, end_phi, tol, cap, &mut table);
            if k + 1 == pieces.len() || pieces[k + 1].seg != p.seg {
                table_start.push(table.len());
            }
        }
        // Outer joints: images of inner joints, dropping segments of (near) zero length.
        let mut joints = vec![a];
        let mut inner_seg = Vec::new();
        let mut ranges = Vec::new();
        for seg in 0..j.len() - 1 {
            let t1 = if seg == j.len() - 2 { b } else { a + seg_phi[seg + 1] / c };
            let t0 = *joints.last().unwrap_or(&a);
            if t1 - t0 > super::MIN_RELATIVE_SPACING * 1f64.max(t0.abs()).max(t1.abs()) * 16.0 {
                joints.push(t1);
                inner_seg.push(seg);
                ranges.push((table_start[seg], table_start[seg + 1]));
            } else if seg == j.len() - 2 && !inner_seg.is_empty() {
                // the last segment is too short: the previous outer segment ends at b
                *joints.last_mut().unwrap() = b;
            }
        }
        if inner_seg.is_empty() {
            return Err(Error::invalid("spline", "the spline's rotation is too small to reparameterise"));
        }
        table.shrink_to_fit();
        Ok(Reparameterized {
            inner,
            map: TimeMap::ArcLength { t0: a, c },
            inner_seg,
            table,
            ranges,
            length,
            name: "arc_length",
            locator: crate::simd::Locator::new(&joints),
            joints,
        })
    }

    /// The total rotation angle ∫|ω| (arc length map only; NaN for a time stretch).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Pieces of the tabulated inverse of the arc-length map (0 for a time stretch); each
    /// takes 88 bytes.
    pub fn table_pieces(&self) -> usize {
        self.table.len()
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

    /// s with φ(s) = target, within the pieces of outer segment i: the tabulated inverse.
    #[inline]
    fn invert(&self, i: usize, target: f64) -> f64 {
        let (start, end) = self.ranges[i];
        let ps = &self.table[start..end];
        let k = ps.partition_point(|p| p.phi <= target).saturating_sub(1);
        ps[k].eval(target)
    }

    /// [`Self::invert`] starting from the piece `hint` (an index into the table) of the
    /// previous sample: for increasing targets a short walk forward replaces the binary
    /// search. The piece is the same (the last one whose start is ≤ target, else the first),
    /// so is s.
    #[inline]
    fn invert_from(&self, i: usize, target: f64, hint: &mut usize) -> f64 {
        let (start, end) = self.ranges[i];
        let mut k = *hint;
        if !(k >= start && k < end && self.table[k].phi <= target) {
            k = start + self.table[start..end].partition_point(|p| p.phi <= target).saturating_sub(1);
        } else {
            let mut steps = 0;
            while k + 1 < end && self.table[k + 1].phi <= target {
                k += 1;
                steps += 1;
                if steps == 8 {
                    k += self.table[k..end].partition_point(|p| p.phi <= target).saturating_sub(1);
                    break;
                }
            }
        }
        *hint = k;
        self.table[k].eval(target)
    }

    /// The inner segments and parameters of a run of samples on outer segments `seg` (the
    /// numbers [`Self::segment`] evaluates the inner spline at).
    fn inner_times(&self, seg: &[u32], t: &[f64], iseg: &mut [u32], s: &mut [f64]) {
        let mut hint = usize::MAX;
        for (k, (&o, &tk)) in seg.iter().zip(t).enumerate() {
            let o = o as usize;
            iseg[k] = self.inner_seg[o] as u32;
            s[k] = match self.map {
                TimeMap::Scale { t0, s0, factor } => s0 + (tk - t0) / factor,
                TimeMap::ArcLength { t0, c } => self.invert_from(o, c * (tk - t0), &mut hint),
            };
        }
    }

    #[inline]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let seg = self.inner_seg[i];
        let s = self.inner_time(i, t);
        if N == 1 {
            return JQuat::constant(self.inner.segment_jet1(seg, s).value());
        }
        let inner = self.inner.segment_jet4(seg, s);
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
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.inner.batch().map(|_| self as &dyn crate::simd::BatchKernel)
    }
}

/// Samples per block of the batch path (the inner times live on the stack).
const BLOCK: usize = super::engine::CHUNK;

/// s'(t) = c/v at inner speed `v` (0 where the inner curve stops, as the jet path reports).
#[inline(always)]
fn arc_rate(c: f64, v: f64) -> f64 {
    if v <= 1e-300 || !v.is_finite() {
        0.0
    } else {
        (1.0 / v) * c
    }
}

impl crate::simd::BatchKernel for Reparameterized {
    fn locator(&self) -> &crate::simd::Locator {
        &self.locator
    }

    /// Rows q, q', … for a time stretch (q⁽ᵏ⁾ scaled by λ⁻ᵏ), q and q' for arc length; the
    /// inner kernel evaluates them at the mapped times (module doc).
    fn evaluate(&self, isa: crate::simd::Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool {
        let Some(k) = self.inner.batch() else { return false };
        if matches!(self.map, TimeMap::ArcLength { .. }) && order > 1 {
            return false;
        }
        let w = 4 * (order + 1);
        let (mut iseg, mut s) = ([0u32; BLOCK], [0.0; BLOCK]);
        for ((sc, tc), oc) in seg.chunks(BLOCK).zip(t.chunks(BLOCK)).zip(out.chunks_mut(BLOCK * w)) {
            let n = sc.len();
            self.inner_times(sc, tc, &mut iseg[..n], &mut s[..n]);
            // the inner kernel covers an order for every sample or for none
            if !k.evaluate(isa, &iseg[..n], &s[..n], order, oc) {
                return false;
            }
            for row in oc.chunks_exact_mut(w) {
                let d = match self.map {
                    TimeMap::Scale { factor, .. } => 1.0 / factor,
                    TimeMap::ArcLength { c, .. } => {
                        if order == 0 {
                            break;
                        }
                        let q1 = &row[4..8];
                        let v = 2.0 * (q1[0] * q1[0] + q1[1] * q1[1] + q1[2] * q1[2] + q1[3] * q1[3]).sqrt();
                        arc_rate(c, v)
                    }
                };
                let mut f = 1.0;
                for m in 1..=order {
                    f *= d;
                    row[4 * m..4 * m + 4].iter_mut().for_each(|x| *x *= f);
                }
            }
        }
        true
    }

    /// ω (arc length and stretch), dω/dt and d²ω/dt² (stretch: scaled by λ⁻²,λ⁻³) from the
    /// inner kernel's rates at the mapped times (module doc).
    fn angular(
        &self,
        isa: crate::simd::Isa,
        seg: &[u32],
        t: &[f64],
        order: usize,
        frame: crate::frame::Frame,
        out: &mut [f64],
    ) -> bool {
        let Some(k) = self.inner.batch() else { return false };
        if matches!(self.map, TimeMap::ArcLength { .. }) && order != 1 {
            return false;
        }
        let (mut iseg, mut s) = ([0u32; BLOCK], [0.0; BLOCK]);
        for ((sc, tc), oc) in seg.chunks(BLOCK).zip(t.chunks(BLOCK)).zip(out.chunks_mut(BLOCK * 3)) {
            let n = sc.len();
            self.inner_times(sc, tc, &mut iseg[..n], &mut s[..n]);
            if !k.angular(isa, &iseg[..n], &s[..n], order, frame, oc) {
                return false;
            }
            for row in oc.chunks_exact_mut(3) {
                let f = match self.map {
                    TimeMap::Scale { factor, .. } => (1.0 / factor).powi(order as i32),
                    TimeMap::ArcLength { c, .. } => {
                        arc_rate(c, (row[0] * row[0] + row[1] * row[1] + row[2] * row[2]).sqrt())
                    }
                };
                row.iter_mut().for_each(|x| *x *= f);
            }
        }
        true
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quat::Quat;
    use crate::spline::*;
    use crate::testing::XorShift64;

    /// A random walk of `n` unit quaternions with steps of up to `step` rad.
    fn walk(n: usize, step: f64, rng: &mut XorShift64) -> Vec<Quat> {
        let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
        for _ in 1..n {
            let v = [rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5];
            let r = crate::convert::from_rotvec(v.map(|x| x * step));
            let last = q[q.len() - 1];
            q.push(last * r);
        }
        q
    }

    fn times(n: usize, rng: &mut XorShift64) -> Vec<f64> {
        let mut t = vec![0.0];
        for _ in 1..n {
            let last = t[t.len() - 1];
            t.push(last + 0.3 + rng.uniform());
        }
        t
    }

    /// Random splines of every family (seeded).
    fn families(seed: u64) -> Vec<(&'static str, Arc<dyn Spline>)> {
        let mut rng = XorShift64::new(seed);
        let q = walk(7, 1.2, &mut rng);
        let t = times(7, &mut rng);
        let w: Vec<[f64; 3]> = (0..7).map(|k| [(k as f64).sin(), 0.3, -(k as f64).cos()]).collect();
        let knots: Vec<f64> = (0..11).map(|k| k as f64 + 0.2 * ((k * k) % 3) as f64).collect();
        vec![
            ("slerp", Arc::new(PiecewiseSlerp::new(&q, Some(&t), true).unwrap())),
            ("squad", Arc::new(Squad::new(&q, Some(&t), true).unwrap())),
            ("catmull_rom", Arc::new(CatmullRom::new(&q, Some(&t), CatmullRomEnds::Reflect, true).unwrap())),
            (
                "kochanek_bartels",
                Arc::new(
                    KochanekBartels::new(&q, Some(&t), None, CATMULL_ROM, TcbEnds::Duplicate, false, true)
                        .unwrap(),
                ),
            ),
            ("natural", Arc::new(NaturalSpline::new(&q, Some(&t), NaturalEnds::Natural, true).unwrap())),
            ("c3", Arc::new(C3Spline::new(&q, Some(&t), &[0.3], &[0.1], C3Variant::Knot, true).unwrap())),
            ("bspline", Arc::new(CumulativeBSpline::new(&q, 0.7, 0.0, 4, true).unwrap())),
            ("nonuniform", Arc::new(NonUniformBSpline::new(&q, &knots, 4, true).unwrap())),
            ("beta", Arc::new(BetaSpline::new(&q, &[1.5], &[2.0], Some(&t[..5]), true).unwrap())),
            ("bezier", Arc::new(SphericalBezier::new(&q, (0.0, 2.0), true).unwrap())),
            ("cumulative_bezier", Arc::new(CumulativeBezier::new(&q, (0.0, 2.0), true).unwrap())),
            ("nlerp", Arc::new(PiecewiseNlerp::new(&q, Some(&t)).unwrap())),
            ("lin_euler", Arc::new(PiecewiseLinEuler::new(&q, Some(&t), "xyz").unwrap())),
            (
                "hermite",
                Arc::new(Hermite::new(&q, Some(&t), &w, None, Frame::World, KeyEnds::Open, true).unwrap()),
            ),
        ]
    }

    /// φ(x) − φ(start of segment `seg`), by composite 8-point Gauss–Legendre on 64 pieces.
    fn phi_from_start(s: &dyn Spline, seg: usize, x: f64) -> f64 {
        let a = s.joints()[seg];
        (0..64)
            .map(|k| gauss(s, seg, a + (x - a) * k as f64 / 64.0, a + (x - a) * (k + 1) as f64 / 64.0))
            .sum()
    }

    /// The accurate inverse the table replaced: bisection-safeguarded Newton on
    /// φ(x) = target within inner segment `seg` (φ' = v), to rounding.
    fn newton_inverse(s: &dyn Spline, seg: usize, phi_start: f64, target: f64) -> f64 {
        let (mut lo, mut hi) = (s.joints()[seg], s.joints()[seg + 1]);
        let mut x = 0.5 * (lo + hi);
        for _ in 0..200 {
            let f = phi_start + phi_from_start(s, seg, x) - target;
            if f > 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            let v = speed(s, seg, x);
            let mut nx = x - f / v;
            if !(nx > lo && nx < hi) {
                nx = 0.5 * (lo + hi);
            }
            if (nx - x).abs() <= 4.0 * f64::EPSILON * x.abs().max(1.0) {
                return nx;
            }
            x = nx;
        }
        x
    }

    /// A node of the known map s(φ) = p(φ) (value and Taylor coefficients from `p`'s
    /// coefficients `c`, lowest first).
    fn poly_node(c: &[f64], phi: f64) -> Node {
        let at = |d: usize| -> f64 {
            // p⁽ᵈ⁾(φ)/d!
            let mut acc = 0.0;
            for k in (d..c.len()).rev() {
                let mut b = 1.0;
                for i in 0..d {
                    b *= (k - i) as f64 / (i + 1) as f64;
                }
                acc = acc * phi + b * c[k];
            }
            acc
        };
        Node { x: at(0), taylor: Some([at(1), at(2), at(3)]) }
    }

    #[test]
    fn septic_piece_reproduces_a_septic() {
        // an increasing degree-7 map on φ ∈ [0.5, 2]: reproduced from its end data alone
        let c = [1.0, 2.0, 0.3, -0.1, 0.05, 0.01, -0.002, 0.0005];
        let (phi0, phi1) = (0.5, 2.0);
        let p = septic_piece(&poly_node(&c, phi0), &poly_node(&c, phi1), phi0, phi1).unwrap();
        for k in 0..=30 {
            let phi = phi0 + (phi1 - phi0) * k as f64 / 30.0;
            let want = poly_node(&c, phi).x;
            assert!((p.eval(phi) - want).abs() < 1e-13, "{phi}: {} vs {want}", p.eval(phi));
        }
        // and a quintic's data (s''' included) are not enough: a degree-6 term is seen
        let c6 = [1.0, 2.0, 0.3, -0.1, 0.05, 0.01, -0.002];
        let p6 = septic_piece(&poly_node(&c6, phi0), &poly_node(&c6, phi1), phi0, phi1).unwrap();
        assert!((p6.eval(1.2) - poly_node(&c6, 1.2).x).abs() < 1e-13);
    }

    #[test]
    fn septic_piece_refuses_a_non_monotone_interpolant() {
        let n = |x: f64, slope: f64| Node { x, taylor: Some([slope, 0.0, 0.0]) };
        // end slopes far larger than the secant: the septic would overshoot (b₁ > b₆)
        assert!(septic_piece(&n(0.0, 100.0), &n(1.0, 100.0), 0.0, 1.0).is_none());
        // a stop at one end (no data) is refused; a line is kept
        assert!(septic_piece(&Node { x: 0.0, taylor: None }, &n(1.0, 1.0), 0.0, 1.0).is_none());
        assert!(septic_piece(&n(0.0, 1.0), &n(1.0, 1.0), 0.0, 1.0).is_some());
        // zero slope at an end is not strictly increasing (b₀ = b₁)
        assert!(septic_piece(&n(0.0, 0.0), &n(1.0, 1.0), 0.0, 1.0).is_none());
    }

    #[test]
    fn tabulated_inverse_matches_newton_on_every_family() {
        for seed in [3u64, 17] {
            for (name, inner) in families(seed) {
                let r = Reparameterized::arc_length(inner.clone()).unwrap();
                let TimeMap::ArcLength { t0, c } = *r.map() else { unreachable!() };
                let s: &dyn Spline = &*inner;
                let mut rng = XorShift64::new(seed + 1);
                let mut worst = 0.0f64;
                for i in 0..r.joints().len() - 1 {
                    let seg = r.inner_seg[i];
                    // φ at the start of the inner segment: that of the outer segment's start
                    let phi_start = c * (r.joints()[i] - t0);
                    let lseg = c * (r.joints()[i + 1] - r.joints()[i]);
                    for _ in 0..12 {
                        let t = r.joints()[i] + (r.joints()[i + 1] - r.joints()[i]) * rng.uniform();
                        let target = c * (t - t0);
                        let got = r.invert(i, target);
                        let want = newton_inverse(s, seg, phi_start, target);
                        // in φ: the table's s reaches the same arc length
                        let err = (phi_start + phi_from_start(s, seg, got) - target).abs();
                        assert!(
                            err <= 2e-12 * lseg + 1e-14 * r.length(),
                            "{name} seed {seed}: φ error {err:e} (segment length {lseg:e})"
                        );
                        worst = worst.max((got - want).abs() * speed(s, seg, want) / lseg);
                    }
                }
                assert!(worst <= 2e-12, "{name} seed {seed}: {worst:e}");
            }
        }
    }

    #[test]
    fn tabulated_inverse_is_monotone_and_reaches_the_ends() {
        for (name, inner) in families(5) {
            let r = Reparameterized::arc_length(inner.clone()).unwrap();
            let TimeMap::ArcLength { t0, c } = *r.map() else { unreachable!() };
            for i in 0..r.joints().len() - 1 {
                let (a, b) = (r.joints()[i], r.joints()[i + 1]);
                let seg = r.inner_seg[i];
                let (lo, hi) = (inner.joints()[seg], inner.joints()[seg + 1]);
                let mut last = f64::NEG_INFINITY;
                for k in 0..=20_000 {
                    let x = r.invert(i, c * (a + (b - a) * k as f64 / 20_000.0 - t0));
                    assert!(x >= last && (lo..=hi).contains(&x), "{name} segment {i} at {k}");
                    last = x;
                }
                // the pieces join: every piece starts where the previous one ends
                let (p0, p1) = r.ranges[i];
                for w in r.table[p0..p1].windows(2) {
                    assert_eq!(w[0].hi, w[1].c[0], "{name}");
                    assert!(w[0].phi <= w[1].phi, "{name}");
                }
                assert_eq!(r.table[p0].c[0], lo);
                assert_eq!(r.table[p1 - 1].hi, hi);
            }
        }
    }

    #[test]
    fn table_checks_hold_at_points_it_did_not_check() {
        // between the check points: 15 points per piece, φ by composite quadrature
        for (name, inner) in families(23).into_iter().take(6) {
            let r = Reparameterized::arc_length(inner.clone()).unwrap();
            let TimeMap::ArcLength { t0, c } = *r.map() else { unreachable!() };
            let s: &dyn Spline = &*inner;
            for i in 0..r.joints().len() - 1 {
                let seg = r.inner_seg[i];
                let phi_start = c * (r.joints()[i] - t0);
                let lseg = c * (r.joints()[i + 1] - r.joints()[i]);
                let (p0, p1) = r.ranges[i];
                for p in &r.table[p0..p1] {
                    for k in 1..16 {
                        let x = p.c[0] + (p.hi - p.c[0]) * k as f64 / 16.0;
                        let phi = phi_start + phi_from_start(s, seg, x);
                        let err = (r.invert(i, phi) - x).abs() * speed(s, seg, x);
                        assert!(err <= 2e-12 * lseg, "{name}: {err:e} vs {lseg:e}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_stop_inside_a_segment_gets_linear_pieces_within_the_bound() {
        // rest ends: the speed is zero at both ends of the spline (s(φ) has infinite slope)
        let mut rng = XorShift64::new(8);
        let q = walk(4, 1.0, &mut rng);
        let inner: Arc<dyn Spline> =
            Arc::new(Squad::with_keyframes(&q, None, KeyEnds::Rest, false, true).unwrap());
        let r = Reparameterized::arc_length(inner.clone()).unwrap();
        let TimeMap::ArcLength { t0, c } = *r.map() else { unreachable!() };
        assert!(r.table.iter().any(|p| p.c[2..] == [0.0; DEG - 1]));
        let s: &dyn Spline = &*inner;
        let lseg = c * (r.joints()[1] - r.joints()[0]);
        for k in 0..=200 {
            let target = lseg * (k as f64 / 200.0).powi(4);
            let x = r.invert(0, target);
            let err = (phi_from_start(s, 0, x) - target).abs();
            assert!(err <= 2e-12 * lseg, "{k}: {err:e}");
        }
        let _ = t0;
    }
}
