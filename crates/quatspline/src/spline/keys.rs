//! Validation of keyframes and key times, shared by every spline constructor.

use crate::error::{Error, Result, Short};
use crate::jet::Axis;
use crate::quat::Quat;

/// Checks keys (finite, non-zero), normalises them and, unless `canonicalize` is false, flips
/// signs so consecutive keys lie in the same hemisphere (shortest path between each pair).
/// `min` is the fewest keys the method accepts.
pub fn prepare_keys(keys: &[Quat], arg: &'static str, min: usize, canonicalize: bool) -> Result<Vec<Quat>> {
    if keys.len() < min {
        return Err(Error::invalid(arg, format!("needs at least {min} keys, got {}", keys.len())));
    }
    let mut out = Vec::with_capacity(keys.len());
    for (i, q) in keys.iter().enumerate() {
        if !q.is_finite() {
            return Err(Error::NonFinite { arg, index: i });
        }
        out.push(q.try_normalize().map_err(|_| Error::ZeroNorm { arg, index: i })?);
    }
    if canonicalize {
        canonicalize_chain(&mut out);
    }
    Ok(out)
}

/// q_k ← −q_k whenever q_{k−1}·q_k < 0 (MATH.md §1): q and −q are the same rotation, so this
/// changes no orientation, only which way round the sphere each segment goes.
pub fn canonicalize_chain(q: &mut [Quat]) {
    for k in 1..q.len() {
        if q[k - 1].dot(q[k]) < 0.0 {
            q[k] = -q[k];
        }
    }
}

/// Key times: `None` gives 0, 1, …, n−1; otherwise n finite, strictly increasing values.
pub fn prepare_times(times: Option<&[f64]>, n: usize) -> Result<Vec<f64>> {
    let Some(t) = times else {
        return Ok((0..n).map(|i| i as f64).collect());
    };
    if t.len() != n {
        return Err(Error::invalid("times", format!("expected {n} times (one per key), got {}", t.len())));
    }
    check_increasing("times", t, true)?;
    Ok(t.to_vec())
}

/// Checks that `v` is finite and strictly increasing, naming `arg` and the first bad index;
/// with `spans`, also that each step is wide enough ([`check_span`]), in index order.
pub fn check_increasing(arg: &'static str, v: &[f64], spans: bool) -> Result<()> {
    for (i, &x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFinite { arg, index: i });
        }
        if i > 0 && x <= v[i - 1] {
            return Err(Error::invalid(
                arg,
                format!("not strictly increasing at index {i} ({} after {})", Short(x), Short(v[i - 1])),
            ));
        }
        if spans && i > 0 {
            check_span(arg, v[i - 1], x, i)?;
        }
    }
    Ok(())
}

/// The smallest key spacing accepted, relative to the times' magnitude: closer keys leave
/// too few significant bits in t − tᵢ for the local parameter and its derivatives (1/h³).
pub const MIN_RELATIVE_SPACING: f64 = 1e-14;

/// The largest |time| accepted: beyond it, rates × spans overflow in the derivative series.
pub const MAX_TIME: f64 = 1e30;

/// Checks that the span [a, b] is finite and wide enough (see [`MIN_RELATIVE_SPACING`]).
pub fn check_span(arg: &'static str, a: f64, b: f64, index: usize) -> Result<()> {
    if a.abs() > MAX_TIME || b.abs() > MAX_TIME {
        return Err(Error::invalid(
            arg,
            format!(
                "time {} at index {index} is beyond the supported range |t| ≤ 1e30",
                Short(if a.abs() > MAX_TIME { a } else { b })
            ),
        ));
    }
    let h = b - a;
    let scale = 1f64.max(a.abs()).max(b.abs());
    if !h.is_finite() {
        return Err(Error::invalid(
            arg,
            format!("span {} … {} at index {index} overflows", Short(a), Short(b)),
        ));
    }
    if h < MIN_RELATIVE_SPACING * scale {
        return Err(Error::invalid(
            arg,
            format!("keys at index {} and {index} are {h:e} apart: below 1e-14 × max(1, |t|)", index - 1),
        ));
    }
    Ok(())
}

/// Checks a shape parameter list: finite and |value| ≤ 1e6 (beyond that derivatives overflow).
pub fn check_shape(arg: &'static str, v: &[f64]) -> Result<()> {
    for (i, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFinite { arg, index: i });
        }
        if x.abs() > 1e6 {
            return Err(Error::invalid(
                arg,
                format!("{arg}[{i}] = {} is beyond the supported range |{arg}| ≤ 1e6", Short(*x)),
            ));
        }
    }
    Ok(())
}

/// The logarithms log(q_{k−1}* q_k) of consecutive keys, as axis × angle.
pub fn chain_logs(q: &[Quat]) -> Vec<Axis> {
    q.windows(2).map(|w| Axis::from_log((w[0].conj() * w[1]).log().vec())).collect()
}

/// A single curve's time domain (t₀, t₁): finite, increasing, wide enough.
pub fn check_domain(domain: (f64, f64)) -> Result<[f64; 2]> {
    if !(domain.0.is_finite() && domain.1.is_finite() && domain.1 > domain.0) {
        return Err(Error::invalid(
            "domain",
            format!("expected finite t0 < t1, got ({}, {})", Short(domain.0), Short(domain.1)),
        ));
    }
    check_span("domain", domain.0, domain.1, 1)?;
    Ok([domain.0, domain.1])
}
