//! Keyframe control shared by the interpolating methods: closed loops, holds, rest ends.
//!
//! - **Closed loops** (`ends = "closed"`): n keys at n + 1 times; the last time closes the loop
//!   (the segment from key n−1 back to key 0). If the last key given equals the first (q or −q,
//!   see [`same_rotation`]) it is taken as the closing key: it is dropped and its time closes
//!   the loop, so `A B C A` at 0 1 2 3 and `A B C` at 0 1 2 3 are the same loop. Without times
//!   the keys are at 0, 1, …, n and the loop closes at n.
//! - **Holds**: consecutive keys that are the same rotation; the methods make the curve exactly
//!   constant between them with zero velocity at both ends of the hold.
//! - **Rest ends** (`ends = "rest"`): zero angular velocity (and higher derivatives as far as
//!   the method's order allows) at the first and last key.

use super::{canonicalize_chain, prepare_keys, prepare_times};
use crate::error::{Error, Result};
use crate::quat::Quat;

/// The end conditions of a keyframe spline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyEnds {
    /// The method's own open ends.
    Open,
    /// Zero angular velocity (acceleration, jerk as far as the method allows) at both ends.
    Rest,
    /// A periodic loop: the last key joins the first.
    Closed,
}

impl KeyEnds {
    /// The name used by the bindings.
    pub fn name(self) -> &'static str {
        match self {
            KeyEnds::Open => "open",
            KeyEnds::Rest => "rest",
            KeyEnds::Closed => "closed",
        }
    }
}

/// Two rotations are "the same" (a hold, or a closing key) when the angle between them is at
/// most 1e-12 rad: q and −q count as equal.
pub fn same_rotation(a: Quat, b: Quat) -> bool {
    let d = a.conj() * b;
    let v = crate::vec3::norm_robust(d.vec());
    2.0 * v.atan2(d.w.abs()) <= 1e-12
}

/// Keys and joint times of a spline, open or closed (the result of [`prepare_loop`]).
#[derive(Debug, Clone)]
pub struct KeyLoop {
    /// Normalised keys, consecutive ones in the same hemisphere (unless not canonicalised).
    pub keys: Vec<Quat>,
    /// Joint times: n for an open curve, n + 1 for a closed one (the last closes the loop).
    pub times: Vec<f64>,
    pub closed: bool,
    /// Whether a closing key equal to the first was dropped.
    pub dropped_closing_key: bool,
}

impl KeyLoop {
    /// The number of segments (n − 1 open, n closed).
    pub fn segments(&self) -> usize {
        self.times.len() - 1
    }

    /// Key at joint j (j = n is key 0 again, on the sign sheet nearest key n−1 when closed).
    pub fn key_at_joint(&self, j: usize) -> Quat {
        let n = self.keys.len();
        if j < n {
            self.keys[j]
        } else {
            self.keys[0].canonical_to(self.keys[n - 1])
        }
    }

    /// Key index of joint j (joint n of a closed curve is key 0).
    pub fn key_index(&self, j: usize) -> usize {
        j % self.keys.len()
    }

    /// Step h of segment i.
    pub fn h(&self, i: usize) -> f64 {
        self.times[i + 1] - self.times[i]
    }

    /// Whether segment i joins two equal keys (a hold).
    pub fn is_hold(&self, i: usize) -> bool {
        same_rotation(self.key_at_joint(i), self.key_at_joint(i + 1))
    }

    /// Makes the two keys of every hold the same quaternion sign (negating all the keys after
    /// a hold given as q, −q): a hold joins equal rotations without moving, whatever
    /// `canonicalize` says; the keys after it keep their relative signs, so no other segment
    /// changes its way round the sphere.
    pub fn align_holds(&mut self) {
        let n = self.keys.len();
        for i in 0..n.saturating_sub(1) {
            if self.keys[i].dot(self.keys[i + 1]) < 0.0 && same_rotation(self.keys[i], self.keys[i + 1]) {
                for q in &mut self.keys[i + 1..] {
                    *q = -*q;
                }
            }
        }
    }

    /// Per key: whether it starts or ends a hold (so its velocity must vanish).
    pub fn hold_keys(&self) -> Vec<bool> {
        let mut h = vec![false; self.keys.len()];
        for i in 0..self.segments() {
            if self.is_hold(i) {
                h[self.key_index(i)] = true;
                h[self.key_index(i + 1)] = true;
            }
        }
        h
    }
}

/// Validates keys and times for open or closed curves. `min` is the fewest keys the method
/// needs (after a closing key is dropped), `method` names it in the error.
pub fn prepare_loop(
    keys: &[Quat],
    times: Option<&[f64]>,
    closed: bool,
    min: usize,
    method: &str,
    canonicalize: bool,
) -> Result<KeyLoop> {
    if !closed {
        let keys = prepare_keys(keys, "quats", min, canonicalize)?;
        let times = prepare_times(times, keys.len())?;
        return Ok(KeyLoop { keys, times, closed, dropped_closing_key: false });
    }
    let mut k = prepare_keys(keys, "quats", 1, false)?;
    let n0 = k.len();
    let dropped = n0 >= 2 && same_rotation(k[0], k[n0 - 1]);
    if dropped {
        k.pop();
    }
    if k.len() < min {
        return Err(Error::invalid(
            "quats",
            format!(
                "a closed {method} needs at least {min} distinct keys, got {}{}",
                k.len(),
                if dropped {
                    " (the last key equals the first and is dropped as the closing key)"
                } else {
                    ""
                }
            ),
        ));
    }
    if canonicalize {
        canonicalize_chain(&mut k);
    }
    let n = k.len();
    let times = match times {
        None => (0..=n).map(|i| i as f64).collect(),
        Some(t) => {
            if t.len() != n + 1 {
                let why = if dropped {
                    format!("{n} distinct keys plus the closing key")
                } else {
                    format!(
                        "{n} keys plus one time closing the loop (or repeat the first key at the end \
                         with its time)"
                    )
                };
                return Err(Error::invalid(
                    "times",
                    format!("a closed curve expects {} times ({why}), got {}", n + 1, t.len()),
                ));
            }
            prepare_times(Some(t), n + 1)?
        }
    };
    Ok(KeyLoop { keys: k, times, closed, dropped_closing_key: dropped })
}
