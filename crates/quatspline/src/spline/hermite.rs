//! Hermite keys: orientations with given angular velocities (and optionally accelerations).
//!
//! Segment i, s = τ − τᵢ ∈ [0, hᵢ]: q(τ) = qᵢ exp(½ rᵢ(s)) with rᵢ a polynomial in the
//! rotation vector — the segment form of the natural spline (`natural_spline.rs`, scipy's
//! `RotationSpline`; MATH.md §6b) with the key rates given instead of solved:
//! - cubic (rates only): rᵢ(0) = 0, rᵢ'(0) = ωᵢ, rᵢ(hᵢ) = ρᵢ = rotvec(qᵢ* qᵢ₊₁),
//!   rᵢ'(hᵢ) = A(ρᵢ) ωᵢ₊₁ (ω body angular velocity, A the angular-rate → rotation-vector-rate
//!   map I + ½[ρ]× + (1 − (|ρ|/2) cot(|ρ|/2))/|ρ|² [ρ]×²). C¹ in time.
//! - quintic (rates and accelerations αᵢ): additionally rᵢ''(0) = αᵢ and
//!   rᵢ''(hᵢ) = A(ρᵢ)(αᵢ₊₁ − N(ρᵢ, A(ρᵢ) ωᵢ₊₁)), N the quadratic term of the body angular
//!   acceleration in the rotation-vector rate (the same N the natural spline iterates). C² in
//!   time.
//!
//! World-frame inputs are turned into body rates by ω_b = qᵢ* ω qᵢ (and α_b = qᵢ* α qᵢ, since
//! dω/dt = R α_b + ω × ω). The curve passes through every key with exactly the given rates
//! (to rounding). Equal keys (a hold) with zero rates at both give rᵢ ≡ 0: exactly constant.
//! With holds on (`with_keyframes`), the keys bounding a hold get zero rate (and acceleration)
//! whatever was given there — the given rows at those keys are overridden, not checked — so
//! every hold is exactly constant and the curve stays C¹ (C²). `Rest` ends override the rows
//! of the first and last key the same way (zero ω, and zero α for the quintic).
//! Closed loops join key n−1 to key 0 with its rates. Source: the Hermite form of scipy's
//! `RotationSpline` segments (Kim, Kim & Shin's rotation-vector lineage); glTF's CUBICSPLINE
//! keys carry the same data (value and tangents per key).

use super::keyframe::{prepare_loop, KeyEnds};
use super::rotvec_segments::{bases_and_chords, RotvecSegments};
use super::{segment_jets, Frame, Spline};
use crate::error::{Error, Result};
use crate::jet::JQuat;
use crate::quat::Quat;
use crate::vec3::Vec3;

/// Keyframes with angular velocities (cubic, C¹) or velocities and accelerations (quintic,
/// C²); open or closed.
#[derive(Debug, Clone)]
pub struct Hermite {
    seg: RotvecSegments,
    closed: bool,
}

fn check_vectors(v: &[Vec3], n: usize, arg: &'static str) -> Result<()> {
    if v.len() != n {
        return Err(Error::invalid(arg, format!("expected {n} rows (one per key), got {}", v.len())));
    }
    for (i, r) in v.iter().enumerate() {
        if r.iter().any(|c| !c.is_finite()) {
            return Err(Error::NonFinite { arg, index: i });
        }
        if r.iter().any(|c| c.abs() > 1e12) {
            return Err(Error::invalid(arg, format!("row {i} is beyond the supported range |value| ≤ 1e12")));
        }
    }
    Ok(())
}

impl Hermite {
    /// `rates` (and `accels`) one row per key as given (before a closing key is dropped).
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        rates: &[Vec3],
        accels: Option<&[Vec3]>,
        frame: Frame,
        ends: KeyEnds,
        canonicalize: bool,
    ) -> Result<Self> {
        Self::with_keyframes(keys, times, rates, accels, frame, ends, false, canonicalize)
    }

    /// With holds: the keys bounding a hold (consecutive equal keys, see
    /// [`super::keyframe::same_rotation`]) get zero rate and acceleration whatever was given
    /// there, so the hold is exactly constant; `Rest` does the same at the first and last key
    /// (the given rows there are ignored). Both keep the curve C¹ (cubic) / C² (quintic).
    #[allow(clippy::too_many_arguments)]
    pub fn with_keyframes(
        keys: &[Quat],
        times: Option<&[f64]>,
        rates: &[Vec3],
        accels: Option<&[Vec3]>,
        frame: Frame,
        ends: KeyEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        let closed = ends == KeyEnds::Closed;
        check_vectors(rates, keys.len(), "angular_velocity")?;
        if let Some(a) = accels {
            check_vectors(a, keys.len(), "angular_acceleration")?;
        }
        let k = prepare_loop(keys, times, closed, 2, "hermite", canonicalize)?;
        let n = k.keys.len();
        let to_body = |v: &[Vec3], arg: &'static str| -> Result<Vec<Vec3>> {
            let mut out: Vec<Vec3> = (0..n)
                .map(|i| match frame {
                    Frame::Body => v[i],
                    Frame::World => k.keys[i].conj().rotate(v[i]),
                })
                .collect();
            if k.dropped_closing_key {
                // The closing key repeats key 0: its rate must too.
                let last = match frame {
                    Frame::Body => v[n],
                    Frame::World => k.keys[0].conj().rotate(v[n]),
                };
                let diff = (0..3).map(|c| (last[c] - out[0][c]).abs()).fold(0.0, f64::max);
                let scale = (0..3).map(|c| out[0][c].abs()).fold(1.0, f64::max);
                if diff > 1e-9 * scale {
                    return Err(Error::invalid(
                        arg,
                        format!(
                            "row {n} belongs to the closing key (equal to key 0, dropped) but differs \
                             from row 0 by {diff:e}"
                        ),
                    ));
                }
            }
            if closed {
                out.push(out[0]);
            }
            Ok(out)
        };
        let mut w = to_body(rates, "angular_velocity")?;
        let mut acc = accels.map(|a| to_body(a, "angular_acceleration")).transpose()?;
        let mut pinned = if holds { k.hold_keys() } else { vec![false; n] };
        if ends == KeyEnds::Rest {
            pinned[0] = true;
            pinned[n - 1] = true;
        }
        for (key, _) in pinned.iter().enumerate().filter(|(_, &p)| p) {
            // joint n of a closed curve is key 0 again
            let joints: &[usize] = if closed && key == 0 { &[0, n] } else { &[key] };
            for &j in joints {
                w[j] = [0.0; 3];
                if let Some(a) = acc.as_mut() {
                    a[j] = [0.0; 3];
                }
            }
        }
        let (base, rho) = bases_and_chords(&k);
        let seg = RotvecSegments::new(base, &rho, k.times, &w, acc.as_deref());
        Ok(Hermite { seg, closed })
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        self.seg.segment::<N>(i, t)
    }
}

impl Spline for Hermite {
    segment_jets!();
    fn name(&self) -> &'static str {
        "hermite"
    }
    fn joints(&self) -> &[f64] {
        self.seg.joints()
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        if self.seg.degree == 5 {
            2
        } else {
            1
        }
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        Some(&self.seg.batch)
    }
    fn closed(&self) -> bool {
        self.closed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::angular;

    #[test]
    fn passes_through_keys_with_the_given_rates() {
        let keys = [
            Quat::new(1.0, 0.0, 0.0, 0.0),
            Quat::new(0.9, 0.3, -0.2, 0.1).normalize(),
            Quat::new(0.5, -0.5, 0.5, 0.5),
        ];
        let w = [[0.1, 0.2, -0.3], [1.0, -0.5, 0.2], [0.0, 0.3, 0.4]];
        let a = [[0.5, 0.0, 0.1], [-0.2, 0.3, 0.0], [0.1, 0.1, -0.7]];
        for (frame, body) in [(Frame::Body, true), (Frame::World, false)] {
            let h = Hermite::new(&keys, Some(&[0.0, 0.7, 2.0]), &w, Some(&a), frame, KeyEnds::Open, true)
                .unwrap();
            for (j, &t) in [0.0, 0.7, 2.0].iter().enumerate() {
                for seg in [j.saturating_sub(1), j.min(1)] {
                    let d = h.segment_jet4(seg, t).derivatives();
                    assert!((d[0].dot(keys[j]).abs() - 1.0).abs() < 1e-14);
                    let got = angular(&d, 1, body);
                    let acc = angular(&d, 2, body);
                    for c in 0..3 {
                        assert!((got[c] - w[j][c]).abs() < 1e-12, "ω {seg} {j}: {got:?}");
                        assert!((acc[c] - a[j][c]).abs() < 1e-11, "α {seg} {j}: {acc:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn holds_and_rest_override_the_given_rates_and_accelerations() {
        let a = Quat::new(0.9, 0.3, -0.2, 0.1).normalize();
        let b = Quat::new(0.5, -0.5, 0.5, 0.5);
        let keys = [a, -a, b, Quat::new(0.2, 0.9, 0.1, -0.3).normalize()];
        let t = [0.0, 1.0, 1.8, 3.0];
        let w = [[1.0, 0.5, -0.3], [0.7, -0.2, 0.4], [0.3, 0.3, 0.3], [-0.5, 0.1, 0.2]];
        let acc = [[0.2, 0.1, 0.0], [0.0, -0.4, 0.3], [0.5, 0.5, -0.1], [0.1, 0.0, 0.6]];
        let h =
            Hermite::with_keyframes(&keys, Some(&t), &w, Some(&acc), Frame::Body, KeyEnds::Rest, true, true)
                .unwrap();
        // the hold between keys 0 and 1 is exactly still
        for s in [0.0, 0.25, 0.5, 0.99, 1.0] {
            let d = h.segment_jet4(0, s).derivatives();
            assert!((d[0].dot(a).abs() - 1.0).abs() < 1e-15);
            for m in 1..4 {
                assert!(d[m].dot(d[m]).sqrt() < 1e-14, "derivative {m} at {s}");
            }
        }
        // keys 0, 1 (hold) and 3 (rest end) pinned; key 2 keeps its given rate and acceleration
        for (j, seg) in [(1usize, 1usize), (2, 1), (2, 2), (3, 2)] {
            let d = h.segment_jet4(seg, t[j]).derivatives();
            let (got_w, got_a) = (angular(&d, 1, true), angular(&d, 2, true));
            let (ew, ea) = if j == 2 { (w[2], acc[2]) } else { ([0.0; 3], [0.0; 3]) };
            for c in 0..3 {
                assert!((got_w[c] - ew[c]).abs() < 1e-12, "ω key {j} seg {seg}: {got_w:?}");
                assert!((got_a[c] - ea[c]).abs() < 1e-11, "α key {j} seg {seg}: {got_a:?}");
            }
        }
    }
}
