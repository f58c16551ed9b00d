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
    let one = |(i, q): (usize, &Quat)| -> Result<Quat> {
        if !q.is_finite() {
            return Err(Error::NonFinite { arg, index: i });
        }
        q.try_normalize().map_err(|_| Error::ZeroNorm { arg, index: i })
    };
    let serial = || keys.iter().enumerate().map(one).collect::<Result<Vec<Quat>>>();
    let mut out = if keys.len() < 2 * PAR_MIN {
        serial()?
    } else {
        // in parallel, straight into place; on failure the serial pass names the first bad
        // key, as one thread would
        let bad = std::sync::atomic::AtomicBool::new(false);
        let v = par_map(keys.len(), |i| {
            one((i, &keys[i])).unwrap_or_else(|_| {
                bad.store(true, std::sync::atomic::Ordering::Relaxed);
                Quat::default()
            })
        });
        if bad.into_inner() {
            serial()?
        } else {
            v
        }
    };
    if canonicalize {
        canonicalize_chain(&mut out);
    }
    Ok(out)
}

/// Below twice this many items the key preparation runs on the calling thread (the pool's
/// hand-off costs more); above, in parallel blocks of at least this many.
pub const PAR_MIN: usize = 16_384;

/// q_k ← −q_k whenever q_{k−1}·q_k < 0 (MATH.md §1): q and −q are the same rotation, so this
/// changes no orientation, only which way round the sphere each segment goes.
///
/// In parallel for long chains, with the same result: negation is exact, so the test on the
/// flipped q_{k−1} is the test on the given one times q_{k−1}'s sign s_{k−1}. Key k keeps
/// s_k = +1 where the given dot product is ±0 (never flipped), else s_k = s_{k−1} ·
/// sign(q_{k−1}·q_k). A block's signs follow from its first key's sign by this rule: the
/// blocks' first signs are resolved one after another from per-block summaries (a prefix over
/// blocks), then every block is flipped in parallel.
pub fn canonicalize_chain(q: &mut [Quat]) {
    use rayon::prelude::*;
    if q.len() < 2 * PAR_MIN {
        for k in 1..q.len() {
            if q[k - 1].dot(q[k]) < 0.0 {
                q[k] = -q[k];
            }
        }
        return;
    }
    // key k against key k−1, on the given keys: 0 = reset to +1, 1 = same sign, −1 = flip
    let rel = |q: &[Quat], k: usize| -> i8 {
        let d = q[k - 1].dot(q[k]);
        if d < 0.0 {
            -1
        } else if d > 0.0 {
            1
        } else {
            0
        }
    };
    let step = |s: i8, r: i8| if r == 0 { 1 } else { s * r };
    let starts: Vec<usize> = (0..q.len()).step_by(PAR_MIN).collect();
    let qs: &[Quat] = q;
    // per block, its last sign as a function of its first: (true, c) constant c after a
    // reset, (false, p) the first sign times p
    let summary: Vec<(bool, i8)> = starts
        .par_iter()
        .map(|&a| {
            let b = (a + PAR_MIN).min(qs.len());
            let (mut fixed, mut s) = (false, 1i8);
            for k in a + 1..b {
                let r = rel(qs, k);
                fixed |= r == 0;
                s = step(s, r);
            }
            (fixed, s)
        })
        .collect();
    let mut first = Vec::with_capacity(starts.len());
    let mut last = 1i8;
    for (&a, &(fixed, p)) in starts.iter().zip(&summary) {
        let s0 = if a == 0 { 1 } else { step(last, rel(qs, a)) };
        first.push(s0);
        last = if fixed { p } else { s0 * p };
    }
    // the relations are read before any key changes: collect the flips, then apply them
    let flips: Vec<Vec<bool>> = starts
        .par_iter()
        .zip(first.par_iter())
        .map(|(&a, &s0)| {
            let b = (a + PAR_MIN).min(qs.len());
            let mut s = s0;
            let mut f = Vec::with_capacity(b - a);
            f.push(s < 0);
            for k in a + 1..b {
                s = step(s, rel(qs, k));
                f.push(s < 0);
            }
            f
        })
        .collect();
    q.par_chunks_mut(PAR_MIN).zip(flips.par_iter()).for_each(|(c, f)| {
        for (x, &neg) in c.iter_mut().zip(f) {
            if neg {
                *x = -*x;
            }
        }
    });
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
    Ok(par_copy(t))
}

/// Checks that `v` is finite and strictly increasing, naming `arg` and the first bad index;
/// with `spans`, also that each step is wide enough ([`check_span`]), in index order.
pub fn check_increasing(arg: &'static str, v: &[f64], spans: bool) -> Result<()> {
    use rayon::prelude::*;
    let one = |i: usize| -> Result<()> {
        let x = v[i];
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
        Ok(())
    };
    // each index's checks read only v[i − 1] and v[i]: in parallel blocks, and on failure the
    // serial pass names the first bad index, as one thread would
    if v.len() >= 2 * PAR_MIN && (0..v.len()).into_par_iter().with_min_len(PAR_MIN).try_for_each(one).is_ok()
    {
        return Ok(());
    }
    (0..v.len()).try_for_each(one)
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
    par_map(q.len().saturating_sub(1), |i| Axis::from_log((q[i].conj() * q[i + 1]).log().vec()))
}

/// (0..n).map(f) collected, in parallel blocks for large n (the same values as one thread).
pub fn par_map<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    use rayon::prelude::*;
    if n < 2 * PAR_MIN {
        return (0..n).map(f).collect();
    }
    (0..n).into_par_iter().with_min_len(PAR_MIN).map(f).collect()
}

/// A copy of `v`, in parallel blocks for long slices.
pub fn par_copy<T: Copy + Send + Sync>(v: &[T]) -> Vec<T> {
    par_map(v.len(), |i| v[i])
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A long chain (several parallel blocks) with random signs, exact ±0 dot products and
    /// runs of antipodal keys: the parallel sign pass equals the one-thread recurrence.
    #[test]
    fn parallel_canonicalize_matches_the_serial_recurrence() {
        let n = 5 * PAR_MIN + 123;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut q: Vec<Quat> = (0..n)
            .map(|_| Quat::new(next() - 0.5, next() - 0.5, next() - 0.5, next() - 0.5).normalize())
            .collect();
        // exact zeros of q_{k−1}·q_k, some at block boundaries
        for &k in &[1, 77, PAR_MIN, PAR_MIN + 1, 3 * PAR_MIN, n - 1] {
            let p = q[k - 1];
            q[k] = Quat::new(-p.x, p.w, -p.z, p.y);
            assert_eq!(q[k - 1].dot(q[k]), 0.0);
        }
        let mut serial = q.clone();
        for k in 1..n {
            if serial[k - 1].dot(serial[k]) < 0.0 {
                serial[k] = -serial[k];
            }
        }
        let mut par = q.clone();
        canonicalize_chain(&mut par);
        assert_eq!(par, serial);
        assert!(serial.iter().zip(&q).any(|(a, b)| a != b), "the chain had no flips to make");
    }

    /// Errors in long inputs name the first bad element, as one pass in order does.
    #[test]
    fn parallel_checks_name_the_first_bad_index() {
        let n = 6 * PAR_MIN;
        let mut keys = vec![Quat::new(1.0, 0.0, 0.0, 0.0); n];
        keys[5 * PAR_MIN + 3] = Quat::new(f64::NAN, 0.0, 0.0, 0.0);
        keys[2 * PAR_MIN + 9] = Quat::new(0.0, 0.0, 0.0, 0.0);
        keys[4 * PAR_MIN] = Quat::new(0.0, f64::INFINITY, 0.0, 0.0);
        match prepare_keys(&keys, "quats", 2, true) {
            Err(Error::ZeroNorm { index, .. }) => assert_eq!(index, 2 * PAR_MIN + 9),
            other => panic!("{other:?}"),
        }
        let mut t: Vec<f64> = (0..n).map(|i| i as f64).collect();
        t[4 * PAR_MIN + 1] = f64::NAN;
        t[3 * PAR_MIN] = t[3 * PAR_MIN - 1];
        let e = prepare_times(Some(&t), n).unwrap_err().to_string();
        assert!(e.contains(&format!("at index {}", 3 * PAR_MIN)), "{e}");
        t[3 * PAR_MIN] = 3.0 * PAR_MIN as f64;
        match prepare_times(Some(&t), n) {
            Err(Error::NonFinite { index, .. }) => assert_eq!(index, 4 * PAR_MIN + 1),
            other => panic!("{other:?}"),
        }
        t[4 * PAR_MIN + 1] = (4 * PAR_MIN + 1) as f64;
        assert_eq!(prepare_times(Some(&t), n).unwrap(), t);
    }
}
