//! Knot layouts: uniform spacing or given breakpoints spanning the data exactly, and the
//! Schoenberg–Whitney check for interpolation.

use super::layout;
use super::types::{Data, Knots};
use crate::error::{Error, Result, Short};

/// (t₀, Δt, segments) from the knot option, with t₀ + segments·Δt ≥ the last sample time in
/// floating point (see [`cover`]).
pub(super) fn knot_layout(knots: &Knots, t: &[f64]) -> Result<(f64, f64, usize)> {
    let b = t[t.len() - 1];
    let (a, h, s) = knot_layout_raw(knots, t)?;
    Ok((a, cover(a, h, s, b), s))
}

/// The smallest Δt ≥ h with a + s·Δt ≥ b as the spline computes its last joint: span/s
/// can round so that a + s·(span/s) falls an ulp short of b, which would leave the last
/// sample outside the fitted spline's domain. A few ulps at most.
pub(super) fn cover(a: f64, h: f64, s: usize, b: f64) -> f64 {
    let mut h = h;
    while a + s as f64 * h < b {
        h = h.next_up();
    }
    h
}

pub(super) fn knot_layout_raw(knots: &Knots, t: &[f64]) -> Result<(f64, f64, usize)> {
    let (a, b) = (t[0], t[t.len() - 1]);
    let span = b - a;
    let segs_for = |h: f64| -> Result<usize> {
        let s = (span / h).round().max(1.0);
        if s > 5e7 {
            return Err(Error::invalid(
                "knots",
                format!("spacing {} gives {s:e} knot intervals (limit 5e7)", Short(h)),
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
                return Err(Error::invalid(
                    "knots",
                    format!("expected a finite positive spacing, got {}", Short(*h)),
                ));
            }
            if *h > span {
                return Err(Error::invalid(
                    "knots",
                    format!("spacing {} exceeds the data's time span {}", Short(*h), Short(span)),
                ));
            }
            let s = segs_for(*h)?;
            Ok((a, span / s as f64, s))
        }
        Knots::Array(k) => {
            check_knot_array(k, t)?;
            let s = k.len() - 1;
            let h = span / s as f64;
            for (i, &v) in k.iter().enumerate() {
                if (v - (a + i as f64 * h)).abs() > 1e-6 * h {
                    return Err(Error::invalid(
                        "knots",
                        format!("the fitted spline uses uniform knots; knot {i} = {} is off the uniform grid (spacing {})", Short(v), Short(h)),
                    ));
                }
            }
            Ok((a, h, s))
        }
    }
}

/// An explicit knot array: at least 2 knots, finite, strictly increasing, first and last at
/// the first and last sample times (to 1e-9 of the span).
pub(super) fn check_knot_array(k: &[f64], t: &[f64]) -> Result<()> {
    let (a, b) = (t[0], t[t.len() - 1]);
    let span = b - a;
    if k.len() < 2 {
        return Err(Error::invalid("knots", format!("expected at least 2 knots, got {}", k.len())));
    }
    crate::spline::check_increasing("knots", k, false)?;
    let tol = 1e-9 * span.max(1e-300);
    if (k[0] - a).abs() > tol || (k[k.len() - 1] - b).abs() > tol {
        return Err(Error::invalid(
            "knots",
            format!(
                "knots must span the data's time range exactly: [{}, {}] given, data [{}, {}]",
                Short(k[0]),
                Short(k[k.len() - 1]),
                Short(a),
                Short(b)
            ),
        ));
    }
    if k.len() - 1 > 50_000_000 {
        return Err(Error::invalid("knots", format!("{} knot intervals (limit 5e7)", k.len() - 1)));
    }
    Ok(())
}

/// The layout of a fit: uniform for the default, a spacing or a uniform array (to 1e-6 of the
/// spacing), otherwise the given breakpoints with their ends set to the first and last sample
/// times exactly (so every sample lies in the domain).
pub(super) fn fit_layout(knots: &Knots, t: &[f64], k: usize) -> Result<layout::Layout> {
    if let Knots::Array(arr) = knots {
        check_knot_array(arr, t)?;
        let (a, b) = (t[0], t[t.len() - 1]);
        let s = arr.len() - 1;
        let h = (b - a) / s as f64;
        if arr.iter().enumerate().any(|(i, &v)| (v - (a + i as f64 * h)).abs() > 1e-6 * h) {
            let mut br = arr.clone();
            br[0] = a;
            br[s] = b;
            if s >= 2 && (br[1] <= a || br[s - 1] >= b) {
                return Err(Error::invalid(
                    "knots",
                    format!(
                        "an interior knot coincides with the first or last sample time ({}, {})",
                        Short(a),
                        Short(b)
                    ),
                ));
            }
            return Ok(layout::Layout::nonuniform(br, k));
        }
    }
    let (t0, dt, segs) = knot_layout(knots, t)?;
    Ok(layout::Layout::uniform(t0, dt, segs, k))
}

/// Refuses `smoothing=0` when the knots cannot interpolate the samples (Schoenberg–Whitney).
///
/// Interpolation needs the collocation matrix of the weighted samples to have full row rank,
/// and a run of segments a … b is reached by only (b − a + 1) + k − 1 control points: more
/// samples in it than that is a rank deficiency (Hall's condition on the intervals). Samples
/// are counted in the segment `locate` gives them, whose k basis functions include all that
/// are non-zero there, so the test is necessary — it never refuses knots that can interpolate.
/// The worst run is the maximum-sum run of (count − 1) (Kadane, O(segments)).
pub(super) fn schoenberg_whitney(data: &Data, lay: &layout::Layout) -> Result<()> {
    let k = lay.order;
    let mut count = vec![0usize; lay.segs];
    for (t, w) in data.t.iter().zip(&data.w) {
        if *w > 0.0 {
            count[lay.locate(*t).0] += 1;
        }
    }
    let (mut best, mut best_range) = (i64::MIN, (0, 0));
    let (mut run, mut start) = (0i64, 0usize);
    for (s, &c) in count.iter().enumerate() {
        if run <= 0 {
            run = 0;
            start = s;
        }
        run += c as i64 - 1;
        if run > best {
            best = run;
            best_range = (start, s);
        }
    }
    if best < k as i64 {
        return Ok(());
    }
    let (a, b) = best_range;
    let knot = |s: usize| lay.breaks.as_ref().map_or(lay.t0 + s as f64 * lay.dt, |v| v[s]);
    let (lo, hi) = (knot(a), knot(b + 1));
    let inside: Vec<usize> = (0..data.t.len())
        .filter(|&i| data.w[i] > 0.0 && (a..=b).contains(&lay.locate(data.t[i]).0))
        .collect();
    Err(Error::invalid(
        "smoothing",
        format!(
            "smoothing=0 cannot interpolate with these knots: the {} samples {} … {} lie between \
             knots {} and {}, which only {} control points reach (Schoenberg–Whitney \
             condition); add knots there or use smoothing > 0",
            inside.len(),
            inside[0],
            inside[inside.len() - 1],
            Short(lo),
            Short(hi),
            b - a + k
        ),
    ))
}
