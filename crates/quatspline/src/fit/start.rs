//! Start values: control points through a running medoid of the samples (or the samples
//! themselves when interpolating).

use super::layout;
use super::so3;
use super::types::Data;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::vec3;
use rayon::prelude::*;

/// Initial control rotations: the data slerped at each control point's Greville time.
pub(super) fn initial_controls(data: &Data, t0: f64, dt: f64, segs: usize, k: usize) -> Vec<Quat> {
    initial_controls_from(data, &data.y, &layout::Layout::uniform(t0, dt, segs, k))
}

/// Half-width of the window of [`medoid_filter`].
pub(super) const MEDOID_HALF: usize = 2;

/// Half-width of the window of the robust fits' start ([`medoid_filter_half`]): a burst of up
/// to this many consecutive bad frames is a minority of every window that holds it
/// (2·20 + 1 = 41 samples), so the start does not follow it.
pub(super) const ROBUST_MEDOID_HALF: usize = 20;

/// Each sample replaced by the medoid of the samples of positive weight within ±2 of it: the
/// one closest to the others in Σ (1 − |⟨qₐ, q_b⟩|) (monotone in the angle, bounded, blind to
/// sign), ties to the nearer one. An isolated glitch — or two in five, far from each other —
/// is never a medoid, so a smoothing fit starts from a curve near the good frames instead of
/// one through the glitches (through 170° glitches Gauss–Newton wandered for hundreds of
/// iterations). Only the starting point changes, not the objective.
pub(super) fn medoid_filter(data: &Data) -> Vec<Quat> {
    let n = data.y.len();
    (0..n)
        .into_par_iter()
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(MEDOID_HALF), (i + MEDOID_HALF + 1).min(n));
            let mut best = (f64::INFINITY, usize::MAX, i);
            for a in lo..hi {
                if data.w[a] <= 0.0 {
                    continue;
                }
                let cost: f64 =
                    (lo..hi).filter(|&b| data.w[b] > 0.0).map(|b| 1.0 - data.y[a].dot(data.y[b]).abs()).sum();
                let key = (cost, a.abs_diff(i));
                if key.0 < best.0 || (key.0 == best.0 && key.1 < best.1) {
                    best = (key.0, key.1, a);
                }
            }
            data.y[best.2]
        })
        .collect()
}

/// The window of sample `i` in [`medoid_filter_half`]: ±`half` samples, shifted inwards at
/// the ends so that it always holds 2·`half` + 1 samples (a one-sided window of `half` + 1
/// samples at the first frame would be a majority for a burst of `half`/2 there).
fn robust_window(i: usize, half: usize, n: usize) -> (usize, usize) {
    let lo = i.saturating_sub(half).min(n.saturating_sub(2 * half + 1));
    (lo, (lo + 2 * half + 1).min(n))
}

/// Windows of [`medoid_filter_half`] per parallel chunk (fixed, so the result does not depend
/// on the number of threads).
const MEDOID_CHUNK: usize = 1024;

/// The start of a robust fit: each sample replaced by the medoid of the samples of positive
/// weight within ±`half` of it in the cost 1 − ⟨qₐ, q_b⟩² = sin²(θ/2) (θ the angle between
/// them; blind to sign; the chordal distance of rotation matrices, ‖Rₐ − R_b‖²_F / 8), ties to
/// the nearer one. The cost is θ²/4 near 0 and flat at the half turn (slope ½ sin θ), so the
/// medoid of a window is the good sample nearest to the good samples' centre as long as the
/// bad ones do not agree with each other more than the good ones do: glitches about random
/// axes never form a majority however many there are, and a burst of consecutive frames turned
/// by one rotation (which agree with each other) is outvoted while it holds fewer than half of
/// the window (≤ `half` frames; the window is shifted inwards at the ends to keep its
/// length). (The cost of [`medoid_filter`], 1 − cos(θ/2), has slope ½
/// at the half turn: with 30 % of glitches near 175° in a window of 41 their pull moved the
/// medoid 15 samples from the centre.)
/// (The windows slide: [`running_medoid`].)
pub(super) fn medoid_filter_half(data: &Data, half: usize) -> Vec<Quat> {
    let (y, w) = (&data.y, &data.w);
    let d = |a: usize, b: usize| 1.0 - y[a].dot(y[b]).powi(2);
    running_medoid(w, half, d).into_iter().map(|i| y[i]).collect()
}

/// For each of the `w.len()` samples, the index of the sample of positive weight in its window
/// ([`robust_window`]) whose summed cost `d` to the window's samples of positive weight is
/// least, ties to the nearer one. Within a chunk of [`MEDOID_CHUNK`] samples the windows
/// slide: each candidate's cost gains the sample entering and loses the one leaving (O(n ·
/// half) work; the first window of a chunk is summed in full).
fn running_medoid(w: &[f64], half: usize, d: impl Fn(usize, usize) -> f64 + Sync) -> Vec<usize> {
    let n = w.len();
    let d = |a: usize, b: usize| if w[b] > 0.0 { d(a, b) } else { 0.0 };
    let chunks: Vec<Vec<usize>> = (0..n.div_ceil(MEDOID_CHUNK))
        .into_par_iter()
        .map(|c| {
            let (i0, i1) = (c * MEDOID_CHUNK, ((c + 1) * MEDOID_CHUNK).min(n));
            let base = i0.saturating_sub(half);
            let mut cost = vec![0.0; (i1 + half).min(n) - base];
            let mut out = Vec::with_capacity(i1 - i0);
            let (mut lo, mut hi) = (base, base);
            for i in i0..i1 {
                let (nlo, nhi) = robust_window(i, half, n);
                for a in nlo..hi.min(nhi) {
                    let mut c = cost[a - base];
                    for b in lo..nlo {
                        c -= d(a, b);
                    }
                    for b in hi..nhi {
                        c += d(a, b);
                    }
                    cost[a - base] = c;
                }
                for a in hi.max(nlo)..nhi {
                    cost[a - base] = (nlo..nhi).map(|b| d(a, b)).sum();
                }
                (lo, hi) = (nlo, nhi);
                let mut best = (f64::INFINITY, usize::MAX, i);
                for a in lo..hi {
                    if w[a] <= 0.0 {
                        continue;
                    }
                    let key = (cost[a - base], a.abs_diff(i));
                    if key.0 < best.0 || (key.0 == best.0 && key.1 < best.1) {
                        best = (key.0, key.1, a);
                    }
                }
                out.push(best.2);
            }
            out
        })
        .collect();
    chunks.concat()
}

/// The least angle (radians) between consecutive samples that [`consensus_mask`] reads as a
/// jump rather than motion: 30°. A curve that turns that far between two samples is not
/// resolved by any fit of them (and 8 × the median step raises it for data sampled that
/// coarsely); tracker flips (170°–180°) and random rotations (median 126°) lie far above it.
const JUMP_MIN: f64 = std::f64::consts::PI / 6.0;

/// Runs of [`consensus_mask`] a chain may skip at once (the look-back of its dynamic
/// programme, which is O(runs × this)).
const CHAIN_LOOKBACK: usize = 64;

/// The angle between two rotations (sign-blind), radians.
fn angle(a: Quat, b: Quat) -> f64 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// Which samples the start of a robust fit may use: false for each sample of a run of
/// consecutive samples that the consensus of the recording rejects; an error where that
/// consensus is contested for a run longer than [`ROBUST_MEDOID_HALF`] (shorter ones the
/// running medoid of the kept samples outvotes in any case).
///
/// The samples of positive weight are cut into runs at jumps: consecutive samples farther
/// apart than J = max(30°, 8 × the median step) ([`JUMP_MIN`]). A run is internally smooth; a
/// burst of flipped frames is a run bounded by two jumps. (J reads the median step: when more
/// than half of the steps are jumps — scattered glitches beyond about 30 % — J exceeds them
/// all, there is one run, and the running medoid alone is the start.) Run q may follow run p in a chain
/// when its first sample lies within J + v·Δt of p's last (Δt the time between them, v the
/// 99th percentile of the angular rate over the steps that are not jumps: the motion cannot
/// carry the curve farther), skipping at most [`CHAIN_LOOKBACK`] runs. The consensus is the
/// chain holding the most samples (dynamic programming forwards, F, and backwards, B: the best
/// chain through run r holds F(r) + B(r) − |r| samples).
///
/// Breakdown: a rejected run r of |r| samples loses to the consensus by the margin
/// best − through(r), the samples it contradicts less its own. The run is rejected cleanly when
/// that margin is at least |r| — the samples it contradicts outnumber it two to one; below, no
/// choice is supported by the data (a burst as long as the motion that surrounds it, or motion
/// fast enough that a flip is reachable within the burst's duration) and the fit is an error
/// naming the run's time range, not a curve through it or half-way to it.
pub(super) fn consensus_mask(data: &Data) -> Result<Vec<bool>> {
    let (t, y) = (&data.t, &data.y);
    let n = y.len();
    let mut mask = vec![true; n];
    let idx: Vec<usize> = (0..n).filter(|&i| data.w[i] > 0.0).collect();
    if idx.len() < 3 {
        return Ok(mask);
    }
    let steps: Vec<f64> = idx.windows(2).map(|p| angle(y[p[0]], y[p[1]])).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let jump = JUMP_MIN.max(8.0 * sorted[sorted.len() / 2]);
    // runs: [start, end] positions in `idx`
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    for (j, &s) in steps.iter().enumerate() {
        if s > jump {
            runs.push((start, j));
            start = j + 1;
        }
    }
    runs.push((start, idx.len() - 1));
    if runs.len() == 1 {
        return Ok(mask);
    }
    let mut rates: Vec<f64> = steps
        .iter()
        .enumerate()
        .filter(|(_, &s)| s <= jump)
        .map(|(j, &s)| s / (t[idx[j + 1]] - t[idx[j]]))
        .collect();
    rates.sort_by(f64::total_cmp);
    let v = if rates.is_empty() { 0.0 } else { rates[(rates.len() * 99 / 100).min(rates.len() - 1)] };
    let m = runs.len();
    let len = |r: usize| (runs[r].1 - runs[r].0 + 1) as f64;
    let fits = |p: usize, q: usize| {
        let (a, b) = (idx[runs[p].1], idx[runs[q].0]);
        angle(y[a], y[b]) <= jump + v * (t[b] - t[a])
    };
    let mut fwd = vec![0.0; m];
    let mut pred = vec![usize::MAX; m];
    for q in 0..m {
        let mut best = (0.0, usize::MAX);
        for p in q.saturating_sub(CHAIN_LOOKBACK)..q {
            if fwd[p] > best.0 && fits(p, q) {
                best = (fwd[p], p);
            }
        }
        fwd[q] = len(q) + best.0;
        pred[q] = best.1;
    }
    let mut bwd = vec![0.0; m];
    for p in (0..m).rev() {
        let mut best = 0.0;
        for q in p + 1..(p + 1 + CHAIN_LOOKBACK).min(m) {
            if bwd[q] > best && fits(p, q) {
                best = bwd[q];
            }
        }
        bwd[p] = len(p) + best;
    }
    let mut last = 0;
    for r in 1..m {
        if fwd[r] > fwd[last] {
            last = r;
        }
    }
    let best = fwd[last];
    let mut chosen = vec![false; m];
    let mut r = last;
    while r != usize::MAX {
        chosen[r] = true;
        r = pred[r];
    }
    for r in (0..m).filter(|&r| !chosen[r]) {
        let through = fwd[r] + bwd[r] - len(r);
        let (a, b) = (idx[runs[r].0], idx[runs[r].1]);
        if len(r) > ROBUST_MEDOID_HALF as f64 && best - through < len(r) {
            let before = if runs[r].0 > 0 { steps[runs[r].0 - 1] } else { steps[runs[r].1] };
            return Err(Error::invalid(
                "quats",
                format!(
                    "the {} consecutive samples at t = {} … {} jump {:.0}° from their neighbours, \
                     and the samples around them do not outnumber them two to one: the robust fit \
                     cannot tell which are glitches (give the bad ones weight 0)",
                    len(r),
                    t[a],
                    t[b],
                    before.to_degrees()
                ),
            ));
        }
        for &i in &idx[runs[r].0..=runs[r].1] {
            mask[i] = false;
        }
    }
    Ok(mask)
}

/// Controls at the knots' Greville-like abscissae, slerped between the neighbouring `anchors`
/// (one per sample).
pub(super) fn initial_controls_from(data: &Data, anchors: &[Quat], lay: &layout::Layout) -> Vec<Quat> {
    let n = lay.segs + lay.order - 1;
    let xs = lay.abscissae();
    let t = &data.t;
    let mut out = Vec::with_capacity(n);
    let mut j = 0usize;
    for m in 0..n {
        let tau = xs[m].clamp(t[0], t[t.len() - 1]);
        while j + 2 < t.len() && t[j + 1] <= tau {
            j += 1;
        }
        let (a, b) = (t[j], t[(j + 1).min(t.len() - 1)]);
        let u = if b > a { ((tau - a) / (b - a)).clamp(0.0, 1.0) } else { 0.0 };
        let qa = anchors[j];
        let qb = anchors[(j + 1).min(t.len() - 1)].canonical_to(qa);
        let r = so3::log(qa.conj() * qb);
        let q = (qa * so3::exp(vec3::scale(r, u))).normalize();
        out.push(match out.last() {
            Some(&p) => q.canonical_to(p),
            None => q,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::XorShift64;

    /// The medoid of each window by its definition: every candidate's cost summed in full.
    fn direct(data: &Data, half: usize) -> Vec<Quat> {
        let n = data.y.len();
        (0..n)
            .map(|i| {
                let (lo, hi) = robust_window(i, half, n);
                let mut best = (f64::INFINITY, usize::MAX, i);
                for a in (lo..hi).filter(|&a| data.w[a] > 0.0) {
                    let cost: f64 = (lo..hi)
                        .filter(|&b| data.w[b] > 0.0)
                        .map(|b| 1.0 - data.y[a].dot(data.y[b]).powi(2))
                        .sum();
                    let key = (cost, a.abs_diff(i));
                    if key.0 < best.0 || (key.0 == best.0 && key.1 < best.1) {
                        best = (key.0, key.1, a);
                    }
                }
                data.y[best.2]
            })
            .collect()
    }

    /// The sliding windows pick the same medoids as the direct sums, across chunk boundaries
    /// and the ends, with zero weights and random signs, for several half-widths.
    #[test]
    fn sliding_medoid_matches_the_direct_definition() {
        let mut rng = XorShift64::new(11);
        let n = 2 * MEDOID_CHUNK + 300;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let y: Vec<Quat> = t
            .iter()
            .map(|&s| {
                let e = [rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5];
                let big = if rng.uniform() < 0.2 { 3.0 } else { 0.02 };
                let q = so3::exp([0.5 * s.sin() + big * e[0], 0.3 * s + big * e[1], big * e[2]]);
                if rng.uniform() < 0.5 {
                    -q
                } else {
                    q
                }
            })
            .collect();
        let w: Vec<f64> = (0..n).map(|_| if rng.uniform() < 0.05 { 0.0 } else { 1.0 }).collect();
        let data = Data { t, y, w };
        for half in [1, 2, 7, ROBUST_MEDOID_HALF] {
            let (got, want) = (medoid_filter_half(&data, half), direct(&data, half));
            let mut same = 0;
            for i in 0..n {
                // the sums differ in their last bits: a different choice must be a tie
                let cost = |q: Quat| -> f64 {
                    let (lo, hi) = robust_window(i, half, n);
                    (lo..hi).filter(|&b| data.w[b] > 0.0).map(|b| 1.0 - q.dot(data.y[b]).powi(2)).sum()
                };
                let (a, b) = (cost(got[i]), cost(want[i]));
                assert!((a - b).abs() <= 1e-12 * (1.0 + b), "half {half} sample {i}: {a} vs {b}");
                same += usize::from(got[i] == want[i]);
            }
            assert!(same >= n - 5, "half {half}: {same} of {n} identical");
        }
    }

    /// A burst of up to `ROBUST_MEDOID_HALF` consecutive frames turned by one rotation (they
    /// agree with each other) is outvoted, in the middle and at the first frame; 30 % of single
    /// glitches about random axes too:
    /// every medoid is a good sample.
    #[test]
    fn robust_medoid_outvotes_bursts_and_scattered_glitches() {
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let clean: Vec<Quat> = t.iter().map(|&s| so3::exp([0.6 * s.sin(), 0.3 * s, 0.1])).collect();
        let mut y = clean.clone();
        for i in (0..ROBUST_MEDOID_HALF).chain(100..100 + ROBUST_MEDOID_HALF) {
            y[i] = y[i] * so3::exp([0.0, 2.97, 0.0]);
        }
        let mut rng = XorShift64::new(5);
        for q in y.iter_mut().skip(200) {
            if rng.uniform() < 0.3 {
                let a = [rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5];
                let s = 3.05 / vec3::norm(a);
                *q = *q * so3::exp(vec3::scale(a, s));
            }
        }
        let out = medoid_filter_half(&Data { t, y, w: vec![1.0; n] }, ROBUST_MEDOID_HALF);
        let ang = |a: Quat, b: Quat| 2.0 * a.dot(b).abs().min(1.0).acos();
        for i in 0..n {
            // a good sample near in time (the bad ones are ≥ 170° away): within 0.3 rad, 45
            // samples of this motion (inside a burst the nearest good ones are 10 samples
            // away; for the one at the first frame the window is [0, 41), whose good samples'
            // centre is 30 samples in)
            assert!(ang(out[i], clean[i]) < 0.3, "sample {i}: {}", ang(out[i], clean[i]));
        }
    }

    /// The consensus of runs drops a burst of 50 frames turned by one rotation (longer than
    /// the medoid's window, which followed it) and keeps every other sample; a burst of 140
    /// between runs of 130 (they outnumber it, but not two to one) is an error naming it.
    #[test]
    fn consensus_drops_long_bursts_and_names_contested_ones() {
        let n = 400;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let clean: Vec<Quat> = t.iter().map(|&s| so3::exp([0.6 * s.sin(), 0.3 * s, 0.1])).collect();
        let burst = |lo: usize, hi: usize| {
            let mut y = clean.clone();
            for q in &mut y[lo..hi] {
                *q = *q * so3::exp([0.0, 2.97, 0.0]);
            }
            Data { t: t.clone(), y, w: vec![1.0; n] }
        };
        let mask = consensus_mask(&burst(100, 150)).unwrap();
        for (i, k) in mask.iter().enumerate() {
            assert_eq!(*k, !(100..150).contains(&i), "sample {i}");
        }
        assert!(consensus_mask(&Data { t: t.clone(), y: clean.clone(), w: vec![1.0; n] })
            .unwrap()
            .iter()
            .all(|k| *k));
        let e = consensus_mask(&burst(130, 270)).unwrap_err();
        assert!(matches!(e, Error::Invalid { arg: "quats", .. }), "{e}");
        assert!(e.to_string().contains("the 140 consecutive samples at t = 1.3 … "), "{e}");
    }
}
