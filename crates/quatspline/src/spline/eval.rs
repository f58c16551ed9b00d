//! Batch evaluation of any [`Spline`]: orientations with derivatives, angular rates.

use super::Spline;
use crate::error::{Error, Result};
use crate::jet::angular;
use crate::quat::Quat;

/// What to do with t outside the domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Extrapolate {
    /// An error naming the first offending index.
    Raise,
    /// Hold the end orientation: the value at the nearest end, zero derivatives.
    Clamp,
}

/// The frame of angular rates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// ω = 2 q' q* (vector part), in world coordinates.
    World,
    /// ω_b = 2 q* q', in body coordinates.
    Body,
}

/// A segment cursor for runs of sorted times: the segment of the previous sample is tried
/// first, then its successor, and only then a binary search — so sorted input costs O(1) per
/// sample and unsorted input O(log n). It picks exactly the segment [`Spline::locate`] picks.
pub struct Cursor<'a> {
    joints: &'a [f64],
    seg: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(s: &'a dyn Spline) -> Self {
        Cursor { joints: s.joints(), seg: 0 }
    }

    #[inline(always)]
    fn fits(&self, k: usize, t: f64) -> bool {
        let j = self.joints;
        let last = j.len() - 2;
        j[k] <= t && (t < j[k + 1] || k == last) || (k == 0 && t < j[0])
    }

    /// The segment containing t (same rule as `Spline::locate`).
    #[inline(always)]
    pub fn locate(&mut self, t: f64) -> usize {
        let last = self.joints.len() - 2;
        if self.fits(self.seg, t) {
            return self.seg;
        }
        if self.seg < last && self.fits(self.seg + 1, t) {
            self.seg += 1;
            return self.seg;
        }
        let k = self.joints.partition_point(|&x| x <= t);
        self.seg = k.saturating_sub(1).min(last);
        self.seg
    }
}

/// q, q', …, q^(order) at time t (order ≤ 3) on segment `seg`.
#[inline]
pub fn derivatives_on(s: &dyn Spline, seg: usize, t: f64, order: usize) -> [Quat; 4] {
    let mut d = [Quat::default(); 4];
    match order {
        0 => d[0] = s.segment_jet1(seg, t).value(),
        1 => d[..2].copy_from_slice(&s.segment_jet2(seg, t).derivatives()),
        2 => d[..3].copy_from_slice(&s.segment_jet3(seg, t).derivatives()),
        _ => d.copy_from_slice(&s.segment_jet4(seg, t).derivatives()),
    }
    d
}

/// Resolves t against the domain: Ok(Some(t)) inside, Ok(None) when clamped to an end
/// (the returned end time in `end`), Err with raise.
#[inline]
fn resolve(s: &dyn Spline, i: usize, t: f64, ex: Extrapolate) -> Result<(f64, bool)> {
    if !t.is_finite() {
        return Err(Error::NonFinite { arg: "t", index: i });
    }
    let (a, b) = s.domain();
    if t >= a && t <= b {
        return Ok((t, false));
    }
    match ex {
        Extrapolate::Raise => Err(Error::OutOfDomain { index: i, t, start: a, end: b }),
        Extrapolate::Clamp => Ok((t.clamp(a, b), true)),
    }
}

/// Writes q, q', …, q^(order) (4·(order+1) numbers) for each t into `out`: through the
/// spline's batch kernels where it has them (`crate::simd`), else per sample.
pub fn evaluate_into(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    if order <= 3 {
        let reference = |tc: &[f64], f: usize, o: &mut [f64]| evaluate_reference_into(s, tc, f, order, ex, o);
        if let Some(r) = crate::simd::engine::evaluate(s, t, first, order, reference, out) {
            return r;
        }
    }
    evaluate_reference_into(s, t, first, order, ex, out)
}

/// The per-sample reference path of [`evaluate_into`]: cursor, one `segment_jetN` call per
/// sample. Every batch kernel is tested against it.
pub fn evaluate_reference_into(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    if order > 3 {
        return Err(Error::invalid("order", format!("expected 0, 1, 2 or 3, got {order}")));
    }
    let w = 4 * (order + 1);
    let mut cursor = Cursor::new(s);
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(w)).enumerate() {
        let (tc, held) = resolve(s, first + k, ti, ex)?;
        let seg = cursor.locate(tc);
        let d = derivatives_on(s, seg, tc, if held { 0 } else { order });
        for (m, q) in d.iter().take(order + 1).enumerate() {
            row[4 * m..4 * m + 4].copy_from_slice(&q.to_wxyz());
        }
    }
    Ok(())
}

/// Writes the angular velocity (order 1), acceleration (2) or jerk (3) for each t into `out`
/// (3 numbers per sample) in the chosen frame: closed-form batch kernels where the spline has
/// them (`crate::simd`), else exact jets per sample.
pub fn angular_into(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    frame: Frame,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    if (1..=3).contains(&order) {
        let reference =
            |tc: &[f64], f: usize, o: &mut [f64]| angular_reference_into(s, tc, f, order, frame, ex, o);
        if let Some(r) = crate::simd::engine::angular(s, t, first, order, frame, reference, out) {
            return r;
        }
    }
    angular_reference_into(s, t, first, order, frame, ex, out)
}

/// The per-sample reference path of [`angular_into`] (jets, then `jet::angular`).
pub fn angular_reference_into(
    s: &dyn Spline,
    t: &[f64],
    first: usize,
    order: usize,
    frame: Frame,
    ex: Extrapolate,
    out: &mut [f64],
) -> Result<()> {
    if !(1..=3).contains(&order) {
        return Err(Error::invalid("order", format!("expected 1, 2 or 3, got {order}")));
    }
    let mut cursor = Cursor::new(s);
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(3)).enumerate() {
        let (tc, held) = resolve(s, first + k, ti, ex)?;
        if held {
            row.copy_from_slice(&[0.0; 3]);
            continue;
        }
        let seg = cursor.locate(tc);
        let d = derivatives_on(s, seg, tc, order);
        row.copy_from_slice(&angular(&d, order, frame == Frame::Body));
    }
    Ok(())
}
