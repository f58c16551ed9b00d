//! Batch evaluation of any [`Spline`]: orientations with derivatives, angular rates.
//!
//! Outside the domain [a, b] every spline follows one [`Extrapolate`] rule, so all methods
//! (and the pose spline, which uses these for its orientation) behave alike:
//! - `Linear`: constant angular velocity from the nearest end, q(t) = q_e exp(½ ω_e (t − e))
//!   with q_e, ω_e the end orientation and its body angular velocity (one-sided, from the end
//!   segment). ω is then constant in both frames, α and jerk are zero; the curve is C¹ at the
//!   ends (C² only where the end acceleration happens to vanish). The rule of evo's and
//!   scipy's slerp-based extrapolation; scipy's `RotationSpline` instead continues its end
//!   cubic, which agrees with this to first order (and exactly when its end segment turns at
//!   constant speed, which the tests use).
//! - `Periodic`: t ↦ a + ((t − a) mod (b − a)): repeats the curve; for a closed spline
//!   (`ends="closed"`) this is as smooth across the seam as inside, for an open one the
//!   repetition jumps at every period boundary.

use super::Spline;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::jet::{angular, JQuat, Jet};
use crate::quat::Quat;

/// What to do with t outside the domain (parsed from "raise", "clamp", "linear" or
/// "periodic" by its `FromStr`, `names.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Extrapolate {
    /// An error naming the first offending index.
    Raise,
    /// Hold the end orientation: the value at the nearest end, zero derivatives.
    Clamp,
    /// Constant angular velocity beyond the ends (the end's one-sided body rate).
    Linear,
    /// Repeat the domain: t ↦ a + ((t − a) mod (b − a)).
    Periodic,
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

/// Where a time lands after the extrapolation rule.
#[derive(Debug, Clone, Copy)]
enum Resolved {
    /// Inside the domain (or wrapped into it): evaluate the segment formula at this time.
    At(f64),
    /// Clamped to this end time: the end value, zero derivatives.
    Held(f64),
    /// Beyond the end at time `end` (the first or last joint) by `dt` = t − end.
    Linear { end: f64, dt: f64 },
}

/// Resolves t against the domain, or the error with `raise`.
#[inline]
fn resolve(s: &dyn Spline, i: usize, t: f64, ex: Extrapolate) -> Result<Resolved> {
    if !t.is_finite() {
        return Err(Error::NonFinite { arg: "t", index: i });
    }
    let (a, b) = s.domain();
    if t >= a && t <= b {
        return Ok(Resolved::At(t));
    }
    Ok(match ex {
        Extrapolate::Raise => return Err(Error::OutOfDomain { index: i, t, start: a, end: b }),
        Extrapolate::Clamp => Resolved::Held(t.clamp(a, b)),
        Extrapolate::Linear => {
            let end = if t < a { a } else { b };
            Resolved::Linear { end, dt: t - end }
        }
        Extrapolate::Periodic => {
            let w = a + (t - a).rem_euclid(b - a);
            // rem_euclid may round up to b − a exactly; both ends are in the domain.
            Resolved::At(w.clamp(a, b))
        }
    })
}

/// q, q', q'', q''' of the constant-angular-velocity continuation from the end at `end`:
/// q(end + dt) = q_e exp(½ ω_b dt), ω_b the one-sided body rate at the end.
#[inline]
pub fn linear_extrapolation(s: &dyn Spline, end: f64, dt: f64) -> [Quat; 4] {
    let (a, _) = s.domain();
    let seg = if end <= a { 0 } else { s.segments() - 1 };
    let d = s.segment_jet2(seg, end).derivatives();
    let w = angular(&d, 1, true);
    let x = Jet::<4>::variable(dt, 1.0);
    let r: [Jet<4>; 3] = std::array::from_fn(|c| x * (0.5 * w[c]));
    (JQuat::constant(d[0]) * JQuat::exp_pure(r)).derivatives()
}

/// q, q', …, q^(order) after the extrapolation rule.
#[inline]
fn resolved_derivatives(s: &dyn Spline, cursor: &mut Cursor<'_>, r: Resolved, order: usize) -> [Quat; 4] {
    match r {
        Resolved::At(t) => derivatives_on(s, cursor.locate(t), t, order),
        Resolved::Held(t) => derivatives_on(s, cursor.locate(t), t, 0),
        Resolved::Linear { end, dt } => linear_extrapolation(s, end, dt),
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
        if let Some(r) = super::engine::evaluate(s, t, first, order, reference, out) {
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
        let r = resolve(s, first + k, ti, ex)?;
        let d = resolved_derivatives(s, &mut cursor, r, order);
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
        if let Some(r) = super::engine::angular(s, t, first, order, frame, reference, out) {
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
        let r = resolve(s, first + k, ti, ex)?;
        if let Resolved::Held(_) = r {
            row.copy_from_slice(&[0.0; 3]);
            continue;
        }
        let d = resolved_derivatives(s, &mut cursor, r, order);
        row.copy_from_slice(&angular(&d, order, frame == Frame::Body));
    }
    Ok(())
}
