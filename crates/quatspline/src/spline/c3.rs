//! The C³ parametric quaternion spline with shape parameters α, β (seed 004, patent;
//! MATH.md §8 — the patent's formulas were images, this is the verified reconstruction).
//!
//! Keys Q₁ … Q_N at τ₁ < … < τ_N, padded Q₀ = Q₁, Q_{N+1} = Q_N, ω_k = log(Q_{k−1}* Q_k).
//! Segment i = 1 … N−1, t = (τ − τᵢ)/hᵢ:
//!   qᵢ(t) = Q_{i−1} exp(C̃₁(t) ωᵢ) exp(C̃₂(t) ω_{i+1}) exp(C̃₃(t) ω_{i+2}),
//!   C̃₁ = 1 − C₀, C̃₂ = C₂ + C₃, C̃₃ = C₃, with degree-7 blending functions (b_l = C(7,l) tˡ(1−t)^{7−l}):
//!   C₃(t) = −t⁴(1−t)[α + β(1−t)²] = −((α+β)/35) b₄ − (2α/21) b₅ − (α/7) b₆,  C₀(t) = C₃(1−t),
//!   C₁(t) = b₀ + b₁ + (1 − 8α/21) b₂ + (1 − 8α/7) b₃ + ((41α+β)/35) b₄ + (10α/21) b₅ + (α/7) b₆,
//!   C₂(t) = C₁(1−t).
//! Interpolating, local (a key moves 4 segments). `Patent` variant: parameters per segment,
//! C³ in t for uniform times and shared parameters; only G³ in τ for non-uniform times (speed
//! ratio at a key h_{k−1}/h_k). `Knot` variant: parameters per key; each C_j is the degree-7
//! Hermite interpolant of the τ-derivative weights at its two keys (MATH.md §8), C³ in τ for
//! any spacing and parameters, equal to the patent form for uniform times and constant
//! parameters. α changes q', q'', q''' at keys, β only q'''. Special cases: (5/16, 0) is the
//! quintic C³ scheme; α = β = 0 is slerp with smoothstep-7 timing (zero velocity at keys).

use super::keyframe::{prepare_loop, KeyEnds};
use super::{segment_jets, Spline};
use crate::error::{Error, Result};
use crate::jet::{Axis, JQuat, Jet};
use crate::quat::Quat;
use crate::simd::cumulative::{Basis, CumulativeTable};

/// Where the shape parameters live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum C3Variant {
    /// Parameters per key, C³ in time for any spacing (MATH.md §8, "knot" variant).
    Knot,
    /// Parameters per segment, exactly the patent's blending functions.
    Patent,
}

/// The C³ spline.
#[derive(Debug, Clone)]
pub struct C3Spline {
    base: Vec<Quat>,
    logs: Vec<Axis>,
    times: Vec<f64>,
    /// Per segment, Bernstein coefficients of C̃₁, C̃₂, C̃₃ in the local parameter (evaluated
    /// in Bernstein form: stable, and exact at the ends, so keys are hit to the last bit).
    basis: Vec<[[f64; 8]; 3]>,
    /// Flat per-segment data of the batch kernels (`crate::simd::cumulative`).
    batch: Option<crate::simd::cumulative::CumulativeTable>,
    closed: bool,
}

const BINOM7: [f64; 8] = [1.0, 7.0, 21.0, 35.0, 35.0, 21.0, 7.0, 1.0];

/// BERN_TO_POWER[k][l]: coefficient of tᵏ in b_l(t) = C(7,l) tˡ(1−t)^{7−l} (computed at compile
/// time).
const BERN_TO_POWER: [[f64; 8]; 8] = {
    let mut m = [[0.0; 8]; 8];
    let mut l = 0;
    while l < 8 {
        // b_l(t) = C(7,l) Σ_j C(7−l, j) (−1)^j t^{l+j}
        let mut binom = 1.0;
        let mut j = 0;
        while j <= 7 - l {
            if j > 0 {
                binom = binom * (7 - l - j + 1) as f64 / j as f64;
            }
            let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
            m[l + j][l] = BINOM7[l] * binom * sign;
            j += 1;
        }
        l += 1;
    }
    m
};

/// Power-basis coefficients of Σ c_l b_l(t) (degree-7 Bernstein).
#[inline]
fn bernstein_to_power(c: &[f64; 8]) -> [f64; 8] {
    std::array::from_fn(|k| (0..8).map(|l| BERN_TO_POWER[k][l] * c[l]).sum())
}

fn reversed(c: [f64; 8]) -> [f64; 8] {
    std::array::from_fn(|k| c[7 - k])
}

/// The patent's Bernstein coefficients of C₀ … C₃ for one (α, β).
pub fn patent_blending(alpha: f64, beta: f64) -> [[f64; 8]; 4] {
    let c3 = [0.0, 0.0, 0.0, 0.0, -(alpha + beta) / 35.0, -2.0 * alpha / 21.0, -alpha / 7.0, 0.0];
    let c1 = [
        1.0,
        1.0,
        1.0 - 8.0 * alpha / 21.0,
        1.0 - 8.0 * alpha / 7.0,
        (41.0 * alpha + beta) / 35.0,
        10.0 * alpha / 21.0,
        alpha / 7.0,
        0.0,
    ];
    [reversed(c3), c1, reversed(c1), c3]
}

/// Degree-7 Hermite interpolant in Bernstein form from value and first three derivatives
/// (in the local parameter) at t = 0 and t = 1.
fn hermite7(f0: [f64; 4], f1: [f64; 4]) -> [f64; 8] {
    let mut c = [0.0; 8];
    c[0] = f0[0];
    c[1] = c[0] + f0[1] / 7.0;
    c[2] = 2.0 * c[1] - c[0] + f0[2] / 42.0;
    c[3] = 3.0 * c[2] - 3.0 * c[1] + c[0] + f0[3] / 210.0;
    c[7] = f1[0];
    c[6] = c[7] - f1[1] / 7.0;
    c[5] = 2.0 * c[6] - c[7] + f1[2] / 42.0;
    c[4] = 3.0 * c[5] - 3.0 * c[6] + c[7] - f1[3] / 210.0;
    c
}

fn per(v: &[f64], n: usize, arg: &'static str, what: &str) -> Result<Vec<f64>> {
    let out = match v.len() {
        1 => vec![v[0]; n],
        m if m == n => v.to_vec(),
        m => return Err(Error::invalid(arg, format!("expected 1 or {n} values ({what}), got {m}"))),
    };
    super::check_shape(arg, &out)?;
    Ok(out)
}

impl C3Spline {
    /// Keys at times (default 0, 1, …), `alpha`/`beta` one value or one per segment (patent)
    /// or per key (knot). Needs two keys.
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        alpha: &[f64],
        beta: &[f64],
        variant: C3Variant,
        canonicalize: bool,
    ) -> Result<Self> {
        Self::with_keyframes(keys, times, alpha, beta, variant, KeyEnds::Open, false, canonicalize)
    }

    /// With keyframe control (`keyframe.rs`). Knot variant: `Rest` sets α = β = 0 at the end
    /// keys (zero angular velocity, acceleration and jerk there, C³ kept); holds set α = β = 0
    /// at the keys bounding a hold (the hold is exactly constant, all derivatives vanish at its
    /// ends, C³ kept). Patent variant: at such a pinned key each neighbouring segment's
    /// blending functions get their four Bernstein coefficients next to that key equal (the
    /// degree-7 blend then has zero first three derivatives there, its other end unchanged):
    /// the same zero ω, α, jerk at rest ends and hold ends, a hold segment blends to exactly
    /// constant, and continuity elsewhere is the patent's. `Closed` pads the keys cyclically
    /// (Q₀ = Q_{n−1}, Q_{n+1} = Q₁, …) with cyclic spacings: C³ across the seam (at least 3 keys).
    #[allow(clippy::too_many_arguments)]
    pub fn with_keyframes(
        keys: &[Quat],
        times: Option<&[f64]>,
        alpha: &[f64],
        beta: &[f64],
        variant: C3Variant,
        ends: KeyEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        let closed = ends == KeyEnds::Closed;
        let mut kl =
            prepare_loop(keys, times, closed, if closed { 3 } else { 2 }, "c3 spline", canonicalize)?;
        if holds {
            kl.align_holds();
        }
        let k = &kl.keys;
        let n = k.len();
        let segs = kl.segments();
        let times = kl.times.clone();
        let h: Vec<f64> = (0..segs).map(|i| kl.h(i)).collect();
        let mut padded = Vec::with_capacity(n + 3);
        if closed {
            // Q_{n−1}, Q_0 … Q_{n−1}, Q_0, Q_1 on one sign sheet.
            padded.push(k[n - 1].canonical_to(k[0]));
            padded.extend_from_slice(k);
            padded.push(k[0]);
            padded.push(k[1]);
            for j in n + 1..n + 3 {
                padded[j] = padded[j].canonical_to(padded[j - 1]);
            }
        } else {
            padded.push(k[0]);
            padded.extend_from_slice(k);
            padded.push(k[n - 1]);
        }
        let logs: Vec<Axis> = super::par_map(padded.len(), |i| {
            if i == 0 {
                Axis::default()
            } else {
                Axis::from_log((padded[i - 1].conj() * padded[i]).log().vec())
            }
        });
        let hold = if holds { kl.hold_keys() } else { vec![false; n] };
        let pinned = |key: usize| hold[key] || (ends == KeyEnds::Rest && (key == 0 || key == n - 1));
        // Per segment, the blending functions C₀ … C₃ as the cumulative C̃₁, C̃₂, C̃₃.
        let cumulative = |c: [[f64; 8]; 4]| -> [[f64; 8]; 3] {
            let c1t: [f64; 8] = std::array::from_fn(|k| 1.0 - c[0][k]);
            let c2t: [f64; 8] = std::array::from_fn(|k| c[2][k] + c[3][k]);
            [c1t, c2t, c[3]]
        };
        let basis: Vec<[[f64; 8]; 3]> = match variant {
            C3Variant::Patent => {
                let (a, b) = (
                    per(alpha, segs, "alpha", "one per segment")?,
                    per(beta, segs, "beta", "one per segment")?,
                );
                super::par_map(segs, |s| {
                    let mut c = patent_blending(a[s], b[s]);
                    // A pinned key (rest end, hold end): the first (last) four Bernstein
                    // coefficients of every blending function made equal, so its first
                    // three derivatives vanish there; the other end is the patent's.
                    for cj in c.iter_mut() {
                        if pinned(s % n) {
                            let v = cj[0];
                            cj[1..4].fill(v);
                        }
                        if pinned((s + 1) % n) {
                            let v = cj[7];
                            cj[4..7].fill(v);
                        }
                    }
                    cumulative(c)
                })
            }
            C3Variant::Knot => {
                let (mut a, mut b) =
                    (per(alpha, n, "alpha", "one per key")?, per(beta, n, "beta", "one per key")?);
                for key in 0..n {
                    if pinned(key) {
                        a[key] = 0.0;
                        b[key] = 0.0;
                    }
                }
                // τ-derivative weights (a_m, b_m, c_m), m = 1..3, of (p_{k−1}, p_k, p_{k+1}) at key k,
                // already multiplied by h_s^m for a segment of length h_s: written with ratios
                // of spacings so that nothing overflows or underflows for any time scale.
                let spacing = |key: usize| -> (f64, f64) {
                    if closed {
                        let key = key % n;
                        return (h[(key + segs - 1) % segs], h[key % segs]);
                    }
                    let hl = if key == 0 { h[0] } else { h[key - 1] };
                    let hr = if key == n - 1 { h[n - 2] } else { h[key] };
                    (hl, hr)
                };
                let scaled = |key: usize, hs: f64| -> [[f64; 3]; 3] {
                    let (hl, hr) = spacing(key);
                    let key = key % n;
                    let hb = 0.5 * hl + 0.5 * hr;
                    let (a1, a2, a3) = (a[key], 8.0 * a[key], 36.0 * a[key] + 6.0 * b[key]);
                    let (l, r, m) = (hs / hl, hs / hr, hs / hb);
                    let am = [-a1 * l, a2 * l * m, -a3 * l * m * m];
                    let cm = [a1 * r, a2 * r * m, a3 * r * m * m];
                    std::array::from_fn(|k| [am[k], -(am[k] + cm[k]), cm[k]])
                };
                super::par_map(segs, |s| {
                    let hs = h[s];
                    let w0 = scaled(s, hs);
                    let w1 = scaled(s + 1, hs);
                    let at0 = |j: usize| -> [f64; 4] {
                        // C0 ↔ a, C1 ↔ b, C2 ↔ c at key s; C3 not involved
                        if j == 3 {
                            return [0.0; 4];
                        }
                        let v = if j == 1 { 1.0 } else { 0.0 };
                        [v, w0[0][j], w0[1][j], w0[2][j]]
                    };
                    let at1 = |j: usize| -> [f64; 4] {
                        // C1 ↔ a, C2 ↔ b, C3 ↔ c at key s+1; C0 not involved
                        if j == 0 {
                            return [0.0; 4];
                        }
                        let v = if j == 2 { 1.0 } else { 0.0 };
                        [v, w1[0][j - 1], w1[1][j - 1], w1[2][j - 1]]
                    };
                    cumulative(std::array::from_fn(|j| hermite7(at0(j), at1(j))))
                })
            }
        };
        let batch = CumulativeTable::with_shape(&times, Basis::Bernstein, 3, 7, |s, factors| {
            factors.extend((0..3).map(|j| (logs[s + 1 + j], &basis[s][j][..])));
            padded[s]
        });
        Ok(C3Spline { base: padded, logs, times, basis, batch, closed })
    }

    /// Per segment, the power-basis coefficients of the cumulative weights C̃₁, C̃₂, C̃₃ in the
    /// local parameter (reused by the dual-quaternion screw spline).
    pub fn cumulative_weights(&self) -> Vec<[[f64; 8]; 3]> {
        self.basis.iter().map(|b| b.map(|c| bernstein_to_power(&c))).collect()
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, s: usize, t: f64) -> JQuat<N> {
        let (t0, t1) = (self.times[s], self.times[s + 1]);
        let u = Jet::<N>::variable((t - t0) / (t1 - t0), 1.0 / (t1 - t0));
        let v = Jet::<N>::constant(1.0) - u;
        let mut up = [Jet::<N>::constant(1.0); 8];
        let mut vp = [Jet::<N>::constant(1.0); 8];
        for k in 1..8 {
            up[k] = up[k - 1] * u;
            vp[k] = vp[k - 1] * v;
        }
        let b: [Jet<N>; 8] = std::array::from_fn(|l| up[l] * vp[7 - l] * BINOM7[l]);
        let mut q = JQuat::constant(self.base[s]);
        for j in 0..3 {
            let c = &self.basis[s][j];
            let mut w = Jet::<N>::constant(0.0);
            for l in 0..8 {
                w = w + b[l] * c[l];
            }
            q = q * JQuat::exp_axis(&self.logs[s + 1 + j], w);
        }
        q
    }
}

impl Spline for C3Spline {
    segment_jets!();
    fn name(&self) -> &'static str {
        "c3"
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        3
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }
    fn closed(&self) -> bool {
        self.closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blending_functions_sum_to_one_and_match_the_closed_form_c3() {
        let (a, b) = (0.3, -0.2);
        let c = patent_blending(a, b);
        for &t in &[0.0, 0.13, 0.5, 0.77, 1.0] {
            let ev = |cf: &[f64; 8]| -> f64 {
                (0..8)
                    .map(|l| cf[l] * BINOM7[l] * f64::powi(t, l as i32) * f64::powi(1.0 - t, 7 - l as i32))
                    .sum()
            };
            let sum: f64 = c.iter().map(ev).sum();
            assert!((sum - 1.0).abs() < 1e-15);
            let closed = -t.powi(4) * (1.0 - t) * (a + b * (1.0 - t).powi(2));
            assert!((ev(&c[3]) - closed).abs() < 1e-15);
        }
    }

    #[test]
    fn patent_rest_and_holds_zero_the_first_three_derivatives_and_hold_exactly() {
        let a = Quat::new(0.9, 0.3, -0.2, 0.1).normalize();
        let b = Quat::new(0.5, -0.5, 0.5, 0.5);
        let c = Quat::new(0.2, 0.9, 0.1, -0.3).normalize();
        let keys = [Quat::new(1.0, 0.0, 0.0, 0.0), a, -a, b, c];
        let s = C3Spline::with_keyframes(
            &keys,
            None,
            &[0.3],
            &[0.2],
            C3Variant::Patent,
            KeyEnds::Rest,
            true,
            true,
        )
        .unwrap();
        let zero_upto3 = |seg: usize, t: f64| {
            let d = s.segment_jet4(seg, t).derivatives();
            (1..4).all(|m| d[m].dot(d[m]).sqrt() < 1e-13)
        };
        // rest ends (keys 0 and 4), both ends of the hold (keys 1 and 2), from both sides
        for (seg, t) in [(0, 0.0), (0, 1.0), (1, 1.0), (1, 2.0), (2, 2.0), (3, 4.0)] {
            assert!(zero_upto3(seg, t), "segment {seg} at {t}");
        }
        for u in [1.0, 1.3, 1.5, 1.9, 2.0] {
            let q = s.segment_jet1(1, u).value();
            assert!((q.dot(a).abs() - 1.0).abs() < 1e-15, "hold at {u}");
        }
        // key 3 is not pinned: the patent's non-zero key velocity, same from both sides
        let (l, r) = (s.segment_jet4(2, 3.0).derivatives(), s.segment_jet4(3, 3.0).derivatives());
        assert!(l[1].dot(l[1]).sqrt() > 1e-3);
        for m in 0..4 {
            let diff = l[m] - r[m];
            assert!(diff.dot(diff).sqrt() < 1e-12, "derivative {m} at key 3");
        }
    }
}
