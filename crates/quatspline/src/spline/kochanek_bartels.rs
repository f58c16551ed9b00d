//! Kochanek–Bartels (TCB) splines on the rotation group, and the Catmull–Rom parametrisation
//! by α (Kochanek & Bartels, SIGGRAPH 1984; the `splines` package's rotation notebooks;
//! Yuksel, Schaefer & Keyser 2011 for α; seed 002 and MATH.md §4 for the segment form).
//!
//! Segment i is the cubic spherical Bézier (de Casteljau with slerp) with control points
//! qᵢ, exp(hᵢ vᵢ⁺/3) qᵢ, exp(−hᵢ vᵢ₊₁⁻/3) qᵢ₊₁, qᵢ₊₁ — world-frame key rates v⁺ (outgoing),
//! v⁻ (incoming), half the angular velocity (logs are half rotation vectors) — so q' = v⁺ qᵢ
//! at the start and v⁻ qᵢ₊₁ at the end of each segment (ω = 2v).
//! With Δ⁻ = log(qᵢ qᵢ₋₁*), Δ⁺ = log(qᵢ₊₁ qᵢ*), h⁻ = hᵢ₋₁, h⁺ = hᵢ and the KB weights
//! (tension T, continuity C, bias B at key i; the `splines` package's convention):
//!   outgoing: w⁻ = (1−T)(1+C)(1+B), w⁺ = (1−T)(1−C)(1−B);
//!   incoming: w⁻ = (1−T)(1−C)(1+B), w⁺ = (1−T)(1+C)(1−B);
//! the Euclidean non-uniform KB tangent is v = λ Δ⁻ + μ Δ⁺ with
//!   λ = w⁻ h⁺ / (h⁻ (h⁻ + h⁺)),  μ = w⁺ h⁻ / (h⁺ (h⁻ + h⁺)).
//! On the group we lift it as v = ½(λ + μ) log(qᵢ₊₁ qᵢ₋₁*) + ½(μ − λ)(Δ⁺ − Δ⁻): the symmetric
//! part uses the chord over both segments (Gortler's Catmull–Rom tangent), the antisymmetric
//! part the difference of the two logs. This equals λ Δ⁻ + μ Δ⁺ exactly when Δ⁻ and Δ⁺ share
//! an axis (so it is the `splines` package's curve there), and at (0, 0, 0) with uniform times
//! it is exactly Gortler's Catmull–Rom (`catmull_rom.rs` is this file at T = C = B = 0).
//!
//! Continuity: C¹ in time at every key with C = 0 (v⁻ = v⁺ there, any T and B); at a key
//! with C ≠ 0 the incoming and outgoing rates differ — a corner, C⁰ only. Tension 1 gives a
//! zero rate (a stop). Ends: `Reflect` (phantom mirrored key: end rate = (w⁻ + w⁺)/2 · chord
//! rate; at (0,0,0) two keys give slerp), `Duplicate` (repeated end key: half of that), `Rest`
//! (zero end rates), `Closed` (cyclic neighbours; C¹ across the seam where C = 0 at key 0).
//! α (keys without times): tᵢ₊₁ − tᵢ = θᵢ^α with θᵢ the rotation angle between the keys
//! (α = 0 uniform, ½ centripetal, 1 chordal), as `splines.quaternion.CatmullRom(alpha=…)`.
//! Holds: keys bounding a run of equal keys get zero rates: exactly constant in between.

use super::keyframe::{prepare_loop, same_rotation, KeyLoop};
use super::{check_shape, de_casteljau, local, segment_jets, Spline};
use crate::error::{Error, Result, Short};
use crate::jet::{Axis, JQuat};
use crate::quat::Quat;
use crate::vec3::{self, Vec3};

/// End conditions of Catmull–Rom / Kochanek–Bartels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TcbEnds {
    /// Mirrored phantom key: the end rate is the chord rate (× the end key's weights).
    Reflect,
    /// Repeated end key: half the chord rate.
    Duplicate,
    /// Zero angular velocity at both ends.
    Rest,
    /// A periodic loop.
    Closed,
}

/// Tension, continuity and bias: one value or one per key (as given, before a closing key is
/// dropped).
#[derive(Debug, Clone, Copy)]
pub struct Tcb<'a> {
    pub tension: &'a [f64],
    pub continuity: &'a [f64],
    pub bias: &'a [f64],
}

/// Zero tension, continuity and bias: Catmull–Rom.
pub const CATMULL_ROM: Tcb<'static> = Tcb { tension: &[0.0], continuity: &[0.0], bias: &[0.0] };

fn log_canonical(q: Quat) -> Vec3 {
    q.canonical().log().vec()
}

fn per_key(v: &[f64], given: usize, kept: usize, dropped: bool, arg: &'static str) -> Result<Vec<f64>> {
    check_shape(arg, v)?;
    match v.len() {
        1 => Ok(vec![v[0]; kept]),
        m if m == given => {
            if dropped && v[m - 1] != v[0] {
                return Err(Error::invalid(
                    arg,
                    format!(
                        "{arg}[{}] belongs to the closing key (equal to key 0, dropped) but differs from \
                         {arg}[0]",
                        m - 1
                    ),
                ));
            }
            Ok(v[..kept].to_vec())
        }
        m => Err(Error::invalid(arg, format!("expected 1 or {given} values (one per key), got {m}"))),
    }
}

/// Key times from α: tᵢ₊₁ − tᵢ = θᵢ^α (θ the angle between consecutive keys, the closing
/// segment included for a loop).
pub fn alpha_times(keys: &[Quat], alpha: f64, closed: bool) -> Result<Vec<f64>> {
    if !(alpha.is_finite() && (0.0..=1.0).contains(&alpha)) {
        return Err(Error::invalid("alpha", format!("expected a value in [0, 1], got {}", Short(alpha))));
    }
    let n = keys.len();
    let mut k: Vec<Quat> = keys.iter().map(|q| q.normalize()).collect();
    if closed && n >= 2 && same_rotation(k[0], k[n - 1]) {
        k.pop();
    }
    let m = k.len();
    let segs = if closed { m } else { m.saturating_sub(1) };
    let mut t = vec![0.0];
    for i in 0..segs {
        let (a, b) = (k[i], k[(i + 1) % m]);
        let d = a.conj() * b;
        let theta = 2.0 * vec3::norm_robust(d.vec()).atan2(d.w.abs());
        let dt = theta.powf(alpha);
        if dt == 0.0 || !dt.is_finite() {
            return Err(Error::invalid(
                "quats",
                format!(
                    "keys {i} and {} are the same rotation: alpha = {alpha} gives them no duration; give \
                     times, or use alpha = 0",
                    (i + 1) % m
                ),
            ));
        }
        t.push(t[i] + dt);
    }
    // Closed: one time per kept key plus the one closing the loop (a dropped closing key's).
    Ok(t)
}

/// Kochanek–Bartels spline through keys (Catmull–Rom at T = C = B = 0).
#[derive(Debug, Clone)]
pub struct KochanekBartels {
    times: Vec<f64>,
    ctrl: Vec<[Quat; 4]>,
    logs: Vec<[Axis; 3]>,
    closed: bool,
    order: u8,
    name: &'static str,
    /// Flat per-segment data of the batch kernel (`crate::simd::slerp`).
    batch: Option<crate::simd::slerp::SlerpTable>,
}

impl KochanekBartels {
    /// `times` (n, or n + 1 closing a loop) or, if None, `alpha` (default 0: uniform).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        keys: &[Quat],
        times: Option<&[f64]>,
        alpha: Option<f64>,
        tcb: Tcb<'_>,
        ends: TcbEnds,
        holds: bool,
        canonicalize: bool,
    ) -> Result<Self> {
        Self::build(keys, times, alpha, tcb, ends, holds, canonicalize, "kochanek_bartels")
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn build(
        keys: &[Quat],
        times: Option<&[f64]>,
        alpha: Option<f64>,
        tcb: Tcb<'_>,
        ends: TcbEnds,
        holds: bool,
        canonicalize: bool,
        name: &'static str,
    ) -> Result<Self> {
        let closed = ends == TcbEnds::Closed;
        let grid;
        let times = match (times, alpha) {
            (Some(t), _) => Some(t),
            (None, Some(a)) => {
                // Validate the keys first so a NaN key is reported as such, not as a zero angle.
                super::prepare_keys(keys, "quats", 1, false)?;
                grid = alpha_times(keys, a, closed)?;
                Some(grid.as_slice())
            }
            (None, None) => None,
        };
        let mut kl = prepare_loop(keys, times, closed, if closed { 3 } else { 2 }, name, canonicalize)?;
        if holds {
            kl.align_holds();
        }
        let n = kl.keys.len();
        let (t, c, b) = (
            per_key(tcb.tension, keys.len(), n, kl.dropped_closing_key, "tension")?,
            per_key(tcb.continuity, keys.len(), n, kl.dropped_closing_key, "continuity")?,
            per_key(tcb.bias, keys.len(), n, kl.dropped_closing_key, "bias")?,
        );
        let hold = if holds { kl.hold_keys() } else { vec![false; n] };
        let (incoming, outgoing) = rates(&kl, &t, &c, &b, ends, &hold);
        let segs = kl.segments();
        // segments are independent: built in parallel (the same numbers as one thread)
        let ctrl: Vec<[Quat; 4]> = super::par_map(segs, |i| {
            let h = kl.h(i);
            let (q0, q1) = (kl.key_at_joint(i), kl.key_at_joint(i + 1));
            let d = Quat::pure(vec3::scale(outgoing[i], h / 3.0)).exp() * q0;
            let e = Quat::pure(vec3::scale(incoming[kl.key_index(i + 1)], -h / 3.0)).exp() * q1;
            [q0, d.canonical_to(q0), e.canonical_to(q1), q1]
        });
        let logs: Vec<[Axis; 3]> = super::par_map(segs, |i| {
            let seg = &ctrl[i];
            std::array::from_fn(|j| Axis::from_log((seg[j].conj() * seg[j + 1]).log().vec()))
        });
        // C¹ where the incoming and outgoing rates agree at every joint (C = 0), else C⁰.
        let corner = (0..n).any(|k| {
            let interior = closed || (k > 0 && k < n - 1);
            interior && vec3::norm(vec3::sub(incoming[k], outgoing[k])) > 0.0
        });
        let batch = crate::simd::slerp::SlerpTable::casteljau(
            &kl.times,
            &super::par_map(segs, |i| &ctrl[i][..]),
            &super::par_map(segs, |i| &logs[i][..]),
        );
        let order = if corner { 0 } else { 1 };
        Ok(KochanekBartels { times: kl.times, ctrl, logs, closed, order, name, batch })
    }

    #[inline(always)]
    pub(crate) fn batch_kernel(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch.as_ref().map(|b| b as &dyn crate::simd::BatchKernel)
    }

    #[inline(always)]
    pub(crate) fn segment_jet_n<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        self.segment::<N>(i, t)
    }

    #[inline(always)]
    fn segment<const N: usize>(&self, i: usize, t: f64) -> JQuat<N> {
        let u = local::<N>(t, self.times[i], self.times[i + 1]);
        de_casteljau(&self.ctrl[i], &self.logs[i], u)
    }
}

/// Incoming and outgoing world-frame rates at each key.
fn rates(
    kl: &KeyLoop,
    t: &[f64],
    c: &[f64],
    b: &[f64],
    ends: TcbEnds,
    hold: &[bool],
) -> (Vec<Vec3>, Vec<Vec3>) {
    let q = &kl.keys;
    let n = q.len();
    let segs = kl.segments();
    let h = |i: usize| kl.h(i);
    // the chord logs log(q_{k+1} q_k*) (cyclic), each shared by the keys at its two ends
    let chord_log = super::par_map(n, |k| log_canonical(q[(k + 1) % n] * q[k].conj()));
    // each key's rates read only its neighbours: in parallel (the same numbers as one thread)
    let both = super::par_map(n, |k| -> (Vec3, Vec3) {
        if hold[k] {
            return ([0.0; 3], [0.0; 3]);
        }
        let (tt, cc, bb) = (t[k], c[k], b[k]);
        // (w⁻, w⁺) of the outgoing and of the incoming rate.
        let w_out = ((1.0 - tt) * (1.0 + cc) * (1.0 + bb), (1.0 - tt) * (1.0 - cc) * (1.0 - bb));
        let w_in = ((1.0 - tt) * (1.0 - cc) * (1.0 + bb), (1.0 - tt) * (1.0 + cc) * (1.0 - bb));
        let interior = kl.closed || (k > 0 && k < n - 1);
        if interior {
            let (p, nx) = ((k + n - 1) % n, (k + 1) % n);
            let (hm, hp) = (h(if k == 0 { segs - 1 } else { k - 1 }), h(k));
            let (dm, dp) = (chord_log[p], chord_log[k]);
            let l = log_canonical(q[nx] * q[p].conj());
            let diff = vec3::sub(dp, dm);
            let tangent = |(wm, wp): (f64, f64)| -> Vec3 {
                let lam = wm * hp / (hm * (hm + hp));
                let mu = wp * hm / (hp * (hm + hp));
                vec3::add(vec3::scale(l, 0.5 * (lam + mu)), vec3::scale(diff, 0.5 * (mu - lam)))
            };
            return (tangent(w_in), tangent(w_out));
        }
        // Open ends: the chord rate of the end segment, weighted by the phantom-key rule.
        let first = k == 0;
        let seg = if first { 0 } else { n - 2 };
        let chord = vec3::scale(chord_log[seg], 1.0 / h(seg));
        let (w, phantom_weight) = if first { (w_out, w_out.1) } else { (w_in, w_in.0) };
        let f = match ends {
            TcbEnds::Reflect => 0.5 * (w.0 + w.1),
            TcbEnds::Duplicate => 0.5 * phantom_weight,
            TcbEnds::Rest | TcbEnds::Closed => 0.0,
        };
        let v = vec3::scale(chord, f);
        (v, v)
    });
    (super::par_map(n, |k| both[k].0), super::par_map(n, |k| both[k].1))
}

impl Spline for KochanekBartels {
    segment_jets!();
    fn name(&self) -> &'static str {
        self.name
    }
    fn joints(&self) -> &[f64] {
        &self.times
    }
    fn interpolates(&self) -> bool {
        true
    }
    fn continuity(&self) -> u8 {
        self.order
    }
    fn closed(&self) -> bool {
        self.closed
    }
    fn batch(&self) -> Option<&dyn crate::simd::BatchKernel> {
        self.batch_kernel()
    }
}
