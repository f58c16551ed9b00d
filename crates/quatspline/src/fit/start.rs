//! Start values: control points through a running medoid of the samples (or the samples
//! themselves when interpolating).

use super::layout;
use super::so3;
use super::types::Data;
use crate::quat::Quat;
use crate::vec3;
use rayon::prelude::*;

/// Initial control rotations: the data slerped at each control point's Greville time.
pub(super) fn initial_controls(data: &Data, t0: f64, dt: f64, segs: usize, k: usize) -> Vec<Quat> {
    initial_controls_from(data, &data.y, &layout::Layout::uniform(t0, dt, segs, k))
}

/// Half-width of the window of [`medoid_filter`].
pub(super) const MEDOID_HALF: usize = 2;

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
