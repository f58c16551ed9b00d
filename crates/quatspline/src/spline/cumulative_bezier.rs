//! Cumulative spherical Bézier curve (Kim, Kim & Shin 1995; seeds 002, 003; MATH.md §4).
//!
//! q(u) = q₀ Π_{j=1..n} (q_{j−1}* q_j)^{B̃_{j,n}(u)}, B̃_{j,n} = Σ_{i≥j} B_{i,n} (Bernstein).
//! Cubic: B̃₁ = 1−(1−u)³, B̃₂ = 3u²−2u³, B̃₃ = u³. Passes through q₀ and qₙ with the same end
//! tangents as the de Casteljau curve, but it is a different curve in between. One curve on
//! u ∈ [0, 1]: C^∞. Every factor has a constant logarithm, so it is cheap to evaluate.
//!
//! Basis without overflow for any degree: C(n, i) overflows f64 at n = 1030 and uᶦ underflows,
//! so the binomial-times-powers form returned NaN everywhere from 1,024 control points on.
//! Each row B_{·,m}(u) is computed from its largest term, exp(ln C(m, k) + k ln u + (m−k)
//! ln(1−u)) at the mode k = ⌊(m+1)u⌋ (ln C from a table of ln k!), then outwards by the term
//! ratios B_{i+1}/B_i = (m−i)/(i+1) · u/(1−u), which only shrink: no term can overflow. The
//! derivatives in u come from the Bernstein identity B_{i,m}' = m(B_{i−1,m−1} − B_{i,m−1}):
//! B̃_j^{(r)} = n(n−1)⋯(n−r+1) Σ_{k<r} (−1)ᵏ C(r−1, k) B_{j−r+k, n−r} (r = 1: n B_{j−1,n−1};
//! r = 2: n(n−1)(B_{j−2,n−2} − B_{j−1,n−2}); …), composed with u(t).
//!
//! **Window.** A row's terms fall off from the mode like a Gaussian of standard deviation
//! σ = √(m u(1−u)), so B̃_j is 1 for j well below n u and 0 well above. Each row is kept only
//! where its terms are at least [`WINDOW_THRESHOLD`] = 2⁻⁶⁰ times its largest term (the walk
//! from the mode stops at the first smaller term; the terms are log-concave in i, so none
//! further out is larger). The mass dropped on each side is below 2⁻⁶⁰ B_max · ρ/(1 − ρ), ρ
//! the term ratio at the cut; at the cut, |i − k| ≈ 9σ and ρ ≈ e^{−9/σ}, so the bound is
//! ≈ 2⁻⁶⁰ · B_max σ/9 ≤ 2⁻⁶⁰ /(9√(2π)) for large σ and ≤ 2⁻⁶⁰ for small σ: far below the
//! 2⁻⁵³ round-off of the row's sum, 1 (tested against the full rows: dropped mass ≤ 2⁻⁵⁶).
//! Each kept row is divided by its sum, so that it sums to 1 as the exact row does (this also
//! removes the common rounding of the largest term, whose exponent is a sum of terms of size
//! ~n). B̃_j is then 1 exactly below the window (prefix sums 1 − Σ_{i<j} B_i up to the mode,
//! suffix sums above it), and those factors are exp(log(q_{j−1}* q_j)) = q_{j−1}* q_j exactly
//! in exact arithmetic (principal logarithm, unit keys): their ordered product
//! q₀ Π_{j≤J} (q_{j−1}* q_j) telescopes to q_J, so the prefix table is the control points
//! themselves and the product starts from q_{J₀−1} (J₀ the first factor whose weight or
//! derivatives the window touches); factors above the window are the identity. Cost per
//! sample O(√(n u(1−u))): about 2 × 9σ ≤ 9√n factors (≈ 590 at n = 4,095, u = ½), each one
//! exp and one quaternion product of jets; the window's rows live in per-thread buffers
//! (no allocation per sample). The degree is capped at [`MAX_CONTROL_POINTS`] − 1.

use super::{prepare_keys, segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable, SegmentForm};
use std::cell::RefCell;

/// The most control points a cumulative Bézier curve takes (degree 4,095). The cost per sample
/// is that of the factors in the Bernstein window, about 9√(n u(1−u)) of them (see the module
/// comment), 27–32 ns each for values and 68–74 ns for ω on a loaded AMD EPYC core: on
/// average over u 13.6 µs per value and 31 µs per angular velocity at 4,096 points (457
/// factors), 1.5 µs per value at 64 points, 0.5 µs at 17 (benchmarks/corners.py). For more keys, a
/// spline with local support (`CumulativeBSpline`, registry name "bspline") costs O(1) per
/// sample.
pub const MAX_CONTROL_POINTS: usize = 4096;

/// The window's cut: Bernstein terms below this fraction (2⁻⁶⁰) of their row's largest term
/// are dropped (see the module comment for the bound on the dropped mass).
pub const WINDOW_THRESHOLD: f64 = 1.0 / (1u64 << 60) as f64;

/// Orders of derivative the jets carry at most (N ≤ 6).
const MAX_ROWS: usize = 6;

/// Per-thread buffers of one sample's window: the Bernstein rows n, n−1, … (kept terms) and
/// the cumulative weights B̃_j over the first row's window.
struct Scratch {
    rows: [Vec<f64>; MAX_ROWS],
    cum: Vec<f64>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> =
        RefCell::new(Scratch { rows: Default::default(), cum: Vec::new() });
}

/// One cumulative Bézier curve of degree up to 4,095 on u ∈ [0, 1].
#[derive(Debug, Clone)]
pub struct CumulativeBezier {
    ctrl: Vec<Quat>,
    logs: Vec<Axis>,
    /// ln k! for k = 0 … n.
    ln_fact: Vec<f64>,
    joints: [f64; 2],
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
}

impl CumulativeBezier {
    /// Control points q₀ … qₙ (2 ≤ n + 1 ≤ [`MAX_CONTROL_POINTS`]).
    /// `domain` (t₀, t₁) maps u = (t − t₀)/(t₁ − t₀); (0, 1) is the plain curve.
    pub fn new(ctrl: &[Quat], domain: (f64, f64), canonicalize: bool) -> Result<Self> {
        let joints = super::check_domain(domain)?;
        if ctrl.len() > MAX_CONTROL_POINTS {
            return Err(Error::invalid(
                "control_points",
                format!(
                    "{} control points: a cumulative Bézier curve takes at most {MAX_CONTROL_POINTS} \
                     (its cost per sample grows with the degree); for more keys use the cumulative \
                     B-spline (CumulativeBSpline, method 'bspline'), which costs the same at any size",
                    ctrl.len()
                ),
            ));
        }
        let ctrl = prepare_keys(ctrl, "control_points", 2, canonicalize)?;
        let logs = super::chain_logs(&ctrl);
        let n = ctrl.len() - 1;
        let mut ln_fact = vec![0.0; n + 1];
        for k in 2..=n {
            ln_fact[k] = ln_fact[k - 1] + (k as f64).ln();
        }
        // factor j's weight B̃_j = Σ_{l≥j} B_{l,n}: Bernstein coefficients 1 from l = j on
        // (only for degrees the kernels take: building the forms costs O(n²) memory)
        let small = n <= crate::simd::cumulative::MAX_FACTORS;
        let batch = small
            .then(|| {
                CumulativeTable::new(&joints, Basis::Bernstein, |_| SegmentForm {
                    base: ctrl[0],
                    factors: (1..=n)
                        .map(|j| (logs[j - 1], (0..=n).map(|l| if l >= j { 1.0 } else { 0.0 }).collect()))
                        .collect(),
                })
            })
            .flatten();
        Ok(CumulativeBezier { ctrl, logs, ln_fact, joints, batch })
    }

    /// The window of row B_{·,m}(u): its terms from the mode outwards while they are at least
    /// [`WINDOW_THRESHOLD`] times the largest, divided by their sum, into `out` (cleared);
    /// returns the index of `out[0]`. Overflow-free (see the module comment).
    fn bernstein_window(&self, m: usize, u: f64, out: &mut Vec<f64>) -> usize {
        out.clear();
        if u <= 0.0 || u >= 1.0 {
            out.push(1.0);
            return if u <= 0.0 { 0 } else { m };
        }
        let k = (((m + 1) as f64 * u).floor() as usize).min(m);
        let f = &self.ln_fact;
        let ln_c = f[m] - f[k] - f[m - k];
        let top = (ln_c + k as f64 * u.ln() + (m - k) as f64 * (-u).ln_1p()).exp();
        let cut = top * WINDOW_THRESHOLD;
        let r = u / (1.0 - u);
        // downwards from the mode (stored reversed, then turned round)
        out.push(top);
        let (mut b, mut lo) = (top, k);
        while lo > 0 {
            b = b * (lo as f64 / (m - lo + 1) as f64) / r;
            if b < cut {
                break;
            }
            out.push(b);
            lo -= 1;
        }
        out.reverse();
        // upwards
        let (mut b, mut i) = (top, k);
        while i < m {
            b = b * ((m - i) as f64 / (i + 1) as f64) * r;
            if b < cut {
                break;
            }
            out.push(b);
            i += 1;
        }
        let sum: f64 = out.iter().sum();
        for x in out.iter_mut() {
            *x /= sum;
        }
        lo
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, _seg: usize, t: f64) -> JQuat<N> {
        SCRATCH.with(|s| self.segment_windowed::<N>(t, &mut s.borrow_mut()))
    }

    /// q(t) as a jet over the Bernstein window (see the module comment).
    fn segment_windowed<const N: usize>(&self, t: f64, s: &mut Scratch) -> JQuat<N> {
        const BINOM: [[f64; 5]; 5] = [
            [1.0, 0.0, 0.0, 0.0, 0.0],
            [1.0, -1.0, 0.0, 0.0, 0.0],
            [1.0, -2.0, 1.0, 0.0, 0.0],
            [1.0, -3.0, 3.0, -1.0, 0.0],
            [1.0, -4.0, 6.0, -4.0, 1.0],
        ];
        let n = self.ctrl.len() - 1;
        let uj = super::local::<N>(t, self.joints[0], self.joints[1]);
        let u = uj.value().clamp(0.0, 1.0);
        // a degree-n polynomial: derivatives above n vanish
        let rows = N.min(MAX_ROWS).min(n + 1);
        let mut lo = [0usize; MAX_ROWS];
        let (mut j0, mut j1) = (usize::MAX, 0usize);
        for r in 0..rows {
            lo[r] = self.bernstein_window(n - r, u, &mut s.rows[r]);
            let hi = lo[r] + s.rows[r].len() - 1;
            // value (r = 0): weight 1 up to lo, varying on lo+1 … hi; derivative r: the terms
            // j − r + k ∈ [lo, hi] for some k < r, i.e. j ∈ [lo + 1, hi + r]
            j0 = j0.min(lo[r] + 1);
            j1 = j1.max(hi + r);
        }
        let (j0, j1) = (j0.max(1), j1.min(n));
        // B̃_j over the value row's window: 1 − Σ_{i<j} B_i up to the mode, Σ_{i≥j} B_i above
        let (row0, lo0) = (&s.rows[0], lo[0]);
        let len = row0.len();
        s.cum.clear();
        s.cum.resize(len, 0.0);
        let mode = row0.iter().enumerate().fold(0, |m, (i, &b)| if b > row0[m] { i } else { m });
        let mut acc = 0.0;
        for i in 0..=mode {
            s.cum[i] = 1.0 - acc;
            acc += row0[i];
        }
        let mut acc = 0.0;
        for i in (mode + 1..len).rev() {
            acc += row0[i];
            s.cum[i] = acc;
        }
        let nf = n as f64;
        let mut scale = [1.0; MAX_ROWS];
        for r in 1..rows {
            scale[r] = scale[r - 1] * (nf - (r - 1) as f64);
        }
        let term = |r: usize, i: isize| -> f64 {
            let i = i - lo[r] as isize;
            if i < 0 || i as usize >= s.rows[r].len() {
                0.0
            } else {
                s.rows[r][i as usize]
            }
        };
        let mut q = JQuat::constant(self.ctrl[j0 - 1]);
        for j in j0..=j1 {
            let mut d = [0.0; N];
            d[0] = if j <= lo0 {
                1.0
            } else if j - lo0 < len {
                s.cum[j - lo0]
            } else {
                0.0
            };
            for r in 1..rows {
                let v: f64 = (0..r).map(|k| BINOM[r - 1][k] * term(r, (j + k) as isize - r as isize)).sum();
                d[r] = scale[r] * v;
            }
            q = q * JQuat::exp_axis(&self.logs[j - 1], uj.compose(d));
        }
        q
    }
}

impl Spline for CumulativeBezier {
    segment_jets!();
    fn name(&self) -> &'static str {
        "cumulative_bezier"
    }
    fn joints(&self) -> &[f64] {
        &self.joints
    }
    fn interpolates(&self) -> bool {
        false
    }
    fn continuity(&self) -> u8 {
        u8::MAX
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Bernstein row B_{·,m}(u) over all i = 0 … m by the mode-and-ratios walk until the
    /// terms underflow (the evaluation before the window), not normalised.
    fn full_row(c: &CumulativeBezier, m: usize, u: f64) -> Vec<f64> {
        let mut out = vec![0.0; m + 1];
        if u <= 0.0 || u >= 1.0 {
            out[if u <= 0.0 { 0 } else { m }] = 1.0;
            return out;
        }
        let k = (((m + 1) as f64 * u).floor() as usize).min(m);
        let f = &c.ln_fact;
        out[k] = (f[m] - f[k] - f[m - k] + k as f64 * u.ln() + (m - k) as f64 * (-u).ln_1p()).exp();
        let r = u / (1.0 - u);
        for i in k..m {
            out[i + 1] = out[i] * ((m - i) as f64 / (i + 1) as f64) * r;
        }
        for i in (1..=k).rev() {
            out[i - 1] = out[i] * (i as f64 / (m - i + 1) as f64) / r;
        }
        out
    }

    /// The O(n) reference: every row in full (divided by its sum, as the window is), B̃_j as
    /// plain suffix sums, the derivatives by the Bernstein identities, and all n factors
    /// multiplied from q₀.
    fn segment_full<const N: usize>(c: &CumulativeBezier, t: f64) -> JQuat<N> {
        let n = c.ctrl.len() - 1;
        let uj = crate::spline::local::<N>(t, c.joints[0], c.joints[1]);
        let u = uj.value().clamp(0.0, 1.0);
        let rows: Vec<Vec<f64>> = (0..N.min(n + 1))
            .map(|r| {
                let row = full_row(c, n - r, u);
                let s: f64 = row.iter().sum();
                row.iter().map(|b| b / s).collect()
            })
            .collect();
        let get = |r: usize, i: isize| if i < 0 || i as usize > n - r { 0.0 } else { rows[r][i as usize] };
        let mut q = JQuat::constant(c.ctrl[0]);
        let mut tail = vec![0.0; n + 2];
        for j in (1..=n).rev() {
            tail[j] = tail[j + 1] + rows[0][j];
        }
        for j in 1..=n {
            let mut d = [0.0; N];
            d[0] = tail[j];
            let j = j as isize;
            for r in 1..rows.len() {
                let v = match r {
                    1 => get(1, j - 1),
                    2 => get(2, j - 2) - get(2, j - 1),
                    3 => get(3, j - 3) - 2.0 * get(3, j - 2) + get(3, j - 1),
                    4 => get(4, j - 4) - 3.0 * get(4, j - 3) + 3.0 * get(4, j - 2) - get(4, j - 1),
                    _ => {
                        get(5, j - 5) - 4.0 * get(5, j - 4) + 6.0 * get(5, j - 3) - 4.0 * get(5, j - 2)
                            + get(5, j - 1)
                    }
                };
                d[r] = (0..r).map(|k| (n - k) as f64).product::<f64>() * v;
            }
            q = q * JQuat::exp_axis(&c.logs[j as usize - 1], uj.compose(d));
        }
        q
    }

    /// A random walk of `n` unit keys with steps of about `step` rad (deterministic).
    fn walk(n: usize, step: f64) -> Vec<Quat> {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut q = vec![Quat::IDENTITY];
        for _ in 1..n {
            let v = [rnd() * step, rnd() * step, rnd() * step];
            let d = Quat::new(0.0, v[0], v[1], v[2]).exp();
            q.push(*q.last().unwrap() * d);
        }
        q
    }

    fn comps<const N: usize>(q: JQuat<N>, k: usize) -> [f64; 4] {
        let d = q.derivative(k);
        [d.w, d.x, d.y, d.z]
    }

    /// The u at which to test: the ends exactly, next to them, and inside.
    const US: [f64; 11] = [0.0, 1e-300, 1e-12, 1e-6, 0.003, 0.27, 0.5, 0.7311, 0.999, 1.0 - 1e-12, 1.0];

    /// The window changes nothing but round-off: values and the first five derivatives equal
    /// the full O(n) evaluation within ulps scaled by the number of factors.
    #[test]
    fn windowed_evaluation_equals_the_full_one() {
        for &n1 in &[17usize, 100, 1000, 4096] {
            let ctrl = walk(n1, 0.6);
            let c = CumulativeBezier::new(&ctrl, (-1.0, 2.0), false).unwrap();
            for &u in &US {
                let t = -1.0 + 3.0 * u;
                let (a, b) = (c.segment::<6>(0, t), segment_full::<6>(&c, t));
                for k in 0..6 {
                    let (x, y) = (comps(a, k), comps(b, k));
                    let size = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                    let tol = 8.0 * n1 as f64 * f64::EPSILON * size;
                    for i in 0..4 {
                        assert!(
                            (x[i] - y[i]).abs() <= tol,
                            "n {n1} u {u} order {k}: {x:?} vs {y:?} (tol {tol:e})"
                        );
                    }
                }
                // the value jet alone starts at the value row's window (the derivative rows
                // may reach a few factors lower): the same value to round-off
                let v = c.segment::<1>(0, t).value();
                assert!(
                    (v - a.value()).norm() <= 16.0 * f64::EPSILON,
                    "n {n1} u {u}: {:e}",
                    (v - a.value()).norm()
                );
            }
        }
    }

    /// The window is wide enough: each row's dropped mass (from the full row) is below
    /// 2⁻⁵⁶, under the round-off of the row's sum; and as narrow as claimed (≤ 19σ + 15 terms: the Gaussian
    /// width, or a Poisson-like tail of at most ~14 terms near the ends).
    #[test]
    fn window_drops_less_than_round_off_and_spans_about_18_sigma() {
        let mut buf = Vec::new();
        for &m in &[1usize, 16, 99, 999, 4095] {
            let c = CumulativeBezier::new(&vec![Quat::IDENTITY; m + 1], (0.0, 1.0), false).unwrap();
            for k in 0..=400 {
                let u = if k == 0 {
                    1e-9
                } else if k == 400 {
                    1.0 - 1e-9
                } else {
                    k as f64 / 400.0
                };
                let full = full_row(&c, m, u);
                let total: f64 = full.iter().sum();
                let lo = c.bernstein_window(m, u, &mut buf);
                let hi = lo + buf.len() - 1;
                let dropped: f64 =
                    full.iter().enumerate().filter(|&(i, _)| i < lo || i > hi).map(|(_, b)| b).sum();
                assert!(dropped / total <= 2f64.powi(-56), "m {m} u {u}: dropped {dropped:e}");
                let sigma = (m as f64 * u * (1.0 - u)).sqrt();
                assert!(
                    buf.len() as f64 <= 19.0 * sigma + 15.0,
                    "m {m} u {u}: {} terms, σ {sigma}",
                    buf.len()
                );
                let s: f64 = buf.iter().sum();
                assert!(
                    (s - 1.0).abs() <= 4.0 * f64::EPSILON * (buf.len() as f64).sqrt(),
                    "m {m} u {u}: sum {s}"
                );
            }
        }
    }

    /// Derivatives (orders 1 … 5, from the six-term jets) against central differences of the
    /// order below, at 1,000 points.
    #[test]
    fn derivatives_match_finite_differences() {
        let c = CumulativeBezier::new(&walk(1000, 0.3), (0.0, 2.0), false).unwrap();
        let h = 1e-5;
        for &t in &[0.01, 0.6, 1.0, 1.5, 1.97] {
            let q = c.segment::<6>(0, t);
            for k in 1..6 {
                let (p, m) = (comps(c.segment::<6>(0, t + h), k - 1), comps(c.segment::<6>(0, t - h), k - 1));
                let want = comps(q, k);
                let size = want.iter().fold(1.0f64, |a, v| a.max(v.abs()));
                for i in 0..4 {
                    let fd = (p[i] - m[i]) / (2.0 * h);
                    assert!((fd - want[i]).abs() <= 1e-5 * size, "t {t} order {k}: {fd} vs {}", want[i]);
                }
            }
        }
    }

    /// Where the window's ends move (between adjacent u found by bisection), the value and
    /// the rate do not jump: the difference is at the level of round-off.
    #[test]
    fn no_jump_where_the_window_moves() {
        let n = 1000;
        let c = CumulativeBezier::new(&walk(n + 1, 0.6), (0.0, 1.0), false).unwrap();
        let mut buf = Vec::new();
        let lo_at = |u: f64, buf: &mut Vec<f64>| {
            let lo = c.bernstein_window(n, u, buf);
            (lo, buf.len())
        };
        let mut events = 0;
        let grid: Vec<f64> = (0..=2000).map(|k| 0.2 + 0.1 * k as f64 / 2000.0).collect();
        for w in grid.windows(2) {
            let (mut a, mut b) = (w[0], w[1]);
            if lo_at(a, &mut buf) == lo_at(b, &mut buf) {
                continue;
            }
            while f64::from_bits(a.to_bits() + 1) < b {
                let mid = 0.5 * (a + b);
                if lo_at(mid, &mut buf) == lo_at(a, &mut buf) {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            events += 1;
            let (qa, qb) = (c.segment::<2>(0, a), c.segment::<2>(0, b));
            for k in 0..2 {
                let (x, y) = (comps(qa, k), comps(qb, k));
                let size = y.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for i in 0..4 {
                    assert!((x[i] - y[i]).abs() <= 1e-13 * size, "u {a} | {b}, order {k}: {x:?} vs {y:?}");
                }
            }
        }
        assert!(events > 20, "{events} window moves");
    }

    /// Regression (issue 2.1 item 5): from 1,024 control points the basis was NaN (C(n, i)
    /// overflowed). The overflow-free rows must equal the exact Bernstein values, which we
    /// get here in log space term by term (an independent formula), at several thousand;
    /// the terms outside the window are below its cut.
    #[test]
    fn bernstein_rows_match_log_space_reference_at_thousands_of_points() {
        for &n in &[3usize, 40, 1023, 1024, 1100, 3000, 4095] {
            let ctrl = vec![Quat::IDENTITY; n + 1];
            let c = CumulativeBezier::new(&ctrl, (0.0, 1.0), false).unwrap();
            let mut win = Vec::new();
            for &u in &[1e-9, 0.001, 0.3, 0.5, 0.77, 0.999, 1.0 - 1e-12] {
                let lo = c.bernstein_window(n, u, &mut win);
                let mut row = vec![0.0; n + 1];
                row[lo..lo + win.len()].copy_from_slice(&win);
                let sum: f64 = row.iter().sum();
                assert!((sum - 1.0).abs() < 1e-12 * (n as f64).sqrt().max(1.0), "n {n} u {u}: sum {sum}");
                for i in (0..=n).step_by((n / 17).max(1)) {
                    let lc = c.ln_fact[n] - c.ln_fact[i] - c.ln_fact[n - i];
                    let want = (lc + i as f64 * u.ln() + (n - i) as f64 * (1.0 - u).ln()).exp();
                    if i < lo || i >= lo + win.len() {
                        // dropped: below the cut, 2⁻⁶⁰ of the largest term
                        assert!(
                            want <= 2f64.powi(-59) * win.iter().fold(0.0f64, |m, &b| m.max(b)),
                            "n {n} u {u} i {i}"
                        );
                        continue;
                    }
                    let tol = 1e-12 * want + 1e-300;
                    assert!(
                        (row[i] - want).abs() <= tol.max(want * 2e-13 * n as f64),
                        "n {n} u {u} i {i}: {} vs {want}",
                        row[i]
                    );
                }
            }
        }
    }

    #[test]
    fn too_many_control_points_name_the_limit_and_the_alternative() {
        let ctrl = vec![Quat::IDENTITY; MAX_CONTROL_POINTS + 1];
        let e = CumulativeBezier::new(&ctrl, (0.0, 1.0), false).unwrap_err().to_string();
        assert!(e.contains("at most 4096") && e.contains("bspline"), "{e}");
    }
}
