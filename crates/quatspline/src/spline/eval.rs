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

/// q, q', …, q^(order) at time t (order ≤ 3), located in its segment. None outside with clamp
/// means "held": the caller writes the end value with zero derivatives.
#[inline]
pub fn derivatives_at(s: &dyn Spline, t: f64, order: usize) -> [Quat; 4] {
    let seg = s.locate(t);
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

/// Writes q, q', …, q^(order) (4·(order+1) numbers) for each t into `out`.
pub fn evaluate_into(
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
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(w)).enumerate() {
        let (tc, held) = resolve(s, first + k, ti, ex)?;
        let d = derivatives_at(s, tc, if held { 0 } else { order });
        for (m, q) in d.iter().take(order + 1).enumerate() {
            row[4 * m..4 * m + 4].copy_from_slice(&q.to_wxyz());
        }
    }
    Ok(())
}

/// Writes the angular velocity (order 1), acceleration (2) or jerk (3) for each t into `out`
/// (3 numbers per sample) in the chosen frame.
pub fn angular_into(
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
    for (k, (&ti, row)) in t.iter().zip(out.chunks_exact_mut(3)).enumerate() {
        let (tc, held) = resolve(s, first + k, ti, ex)?;
        if held {
            row.copy_from_slice(&[0.0; 3]);
            continue;
        }
        let d = derivatives_at(s, tc, order);
        row.copy_from_slice(&angular(&d, order, frame == Frame::Body));
    }
    Ok(())
}
