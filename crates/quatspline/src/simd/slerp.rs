//! Batch kernels of the slerp family: Squad, the cubic spherical Bézier segments of
//! Catmull–Rom / Kochanek–Bartels, and the spherical Bézier curve (de Casteljau with slerp).
//!
//! **Data.** One flat record per segment (a multiple of 4 doubles, so that records can be
//! transposed 4 at a time): the segment's start time t₀ and length h, then
//! - de Casteljau of n points: per control point j < n−1 the point cⱼ and the log of
//!   cⱼ* cⱼ₊₁ as unit axis and angle (8 doubles);
//! - Squad: qᵢ, log(qᵢ* qᵢ₊₁) (axis, angle), sᵢ⁺, log(sᵢ⁺* sᵢ₊₁⁻) (axis, angle).
//!
//! **Value** (the formulas of `spline/squad.rs`, `kochanek_bartels.rs`, `spherical_bezier.rs`,
//! evaluated as the jet path does): u = (t − t₀)/h; the first level cⱼ exp(u aⱼ nⱼ) by the
//! vector sin/cos; each slerp(a, b; w) = a exp(w log(a* b)) by [`slerp`] (no quaternion
//! product: c = a·b, r = b − c a, θ = atan2(|r|, c) with the vector atan2 of `lanes.rs`).
//! Derivatives and rates keep the exact jets (the kernels decline and the engine falls back
//! per run).

use super::lanes::{Lanes, LanesExt};
use super::{BatchKernel, Isa, Locator};
use crate::jet::Axis;
use crate::quat::Quat;
use crate::spline::Frame;

/// The most control points a de Casteljau table takes (a cubic segment has 4; spherical
/// Bézier curves beyond this keep the jets).
pub const MAX_POINTS: usize = 16;
const MAX_STRIDE: usize = 4 + 8 * (MAX_POINTS - 1);
const SQUAD_STRIDE: usize = 20;

type Q4<V> = [V; 4];

#[inline(always)]
pub(crate) fn qmul<V: Lanes>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [
        a[3].fnma(b[3], a[2].fnma(b[2], a[1].fnma(b[1], a[0] * b[0]))),
        a[3].fnma(b[2], a[2].fma(b[3], a[1].fma(b[0], a[0] * b[1]))),
        a[3].fma(b[1], a[2].fma(b[0], a[1].fnma(b[3], a[0] * b[2]))),
        a[3].fma(b[0], a[2].fnma(b[1], a[1].fma(b[2], a[0] * b[3]))),
    ]
}

/// c exp(x n) for a constant quaternion c, unit axis n and angle x.
#[inline(always)]
fn times_exp<V: Lanes>(c: Q4<V>, n: [V; 3], x: V) -> Q4<V> {
    let (s, co) = x.sin_cos();
    qmul(c, [co, s * n[0], s * n[1], s * n[2]])
}

/// slerp(a, b; w) = a exp(w log(a* b)), no hemisphere flip (as `JQuat::slerp`), for unit a
/// and b, written without quaternion products: with c = a·b and r = b − c a (= a ⊗ vec(a* b),
/// orthogonal to a, |r| = sin θ), θ = atan2(|r|, c) and the result is
/// a cos wθ + r sin wθ / |r|. Where |r| = 0 exactly: a, or for c < 0 the reference's
/// log(−1) = (π, 0, 0) choice, a ⊗ (cos wπ, sin wπ, 0, 0).
#[inline(always)]
pub(crate) fn slerp<V: LanesExt>(a: Q4<V>, b: Q4<V>, w: V) -> Q4<V> {
    let c = a[3].fma(b[3], a[2].fma(b[2], a[1].fma(b[1], a[0] * b[0])));
    let r = [c.fnma(a[0], b[0]), c.fnma(a[1], b[1]), c.fnma(a[2], b[2]), c.fnma(a[3], b[3])];
    let s = r[3].fma(r[3], r[2].fma(r[2], r[1].fma(r[1], r[0] * r[0]))).sqrt();
    let th = s.atan2(c);
    let (sn, cs) = (w * th).sin_cos();
    let zero = V::splat(0.0);
    let k = zero.lt_select(s, sn / s, zero);
    let o = [r[0].fma(k, a[0] * cs), r[1].fma(k, a[1] * cs), r[2].fma(k, a[2] * cs), r[3].fma(k, a[3] * cs)];
    if !s.any_lt(V::splat(f64::MIN_POSITIVE)) {
        return o;
    }
    // a ⊗ (cs, sn, 0, 0) = a cs + (a ⊗ i) sn, a ⊗ i = (−a_x, a_w, a_z, −a_y)
    let special = [
        a[1].fnma(sn, a[0] * cs),
        a[0].fma(sn, a[1] * cs),
        a[3].fma(sn, a[2] * cs),
        a[2].fnma(sn, a[3] * cs),
    ];
    let tiny = V::splat(f64::MIN_POSITIVE);
    [
        s.lt_select(tiny, special[0], o[0]),
        s.lt_select(tiny, special[1], o[1]),
        s.lt_select(tiny, special[2], o[2]),
        s.lt_select(tiny, special[3], o[3]),
    ]
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Casteljau,
    Squad,
}

/// Flat per-segment data of a slerp-family spline (see the module doc).
#[derive(Debug, Clone)]
pub struct SlerpTable {
    kind: Kind,
    points: usize,
    stride: usize,
    data: Vec<f64>,
    locator: Locator,
}

fn put_log(r: &mut [f64], ax: &Axis) {
    r[..3].copy_from_slice(&ax.n);
    r[3] = ax.a;
}

impl SlerpTable {
    /// de Casteljau segments: per segment the control points and the logs of consecutive
    /// ones (as `spline::de_casteljau` takes them). None beyond [`MAX_POINTS`] points or
    /// below 2.
    pub fn casteljau(joints: &[f64], ctrl: &[&[Quat]], logs: &[&[Axis]]) -> Option<Self> {
        let n = ctrl.first()?.len();
        if !(2..=MAX_POINTS).contains(&n) || ctrl.iter().any(|c| c.len() != n) {
            return None;
        }
        let stride = 4 + 8 * (n - 1);
        let mut data = vec![0.0; ctrl.len() * stride];
        for (i, (c, l)) in ctrl.iter().zip(logs).enumerate() {
            let r = &mut data[i * stride..(i + 1) * stride];
            r[0] = joints[i];
            r[1] = joints[i + 1] - joints[i];
            for j in 0..n - 1 {
                r[4 + 8 * j..8 + 8 * j].copy_from_slice(&c[j].to_wxyz());
                put_log(&mut r[8 + 8 * j..12 + 8 * j], &l[j]);
            }
        }
        Some(SlerpTable { kind: Kind::Casteljau, points: n, stride, data, locator: Locator::new(joints) })
    }

    /// Squad segments: keys qᵢ, logs of qᵢ* qᵢ₊₁, outgoing control points sᵢ⁺, logs of
    /// sᵢ⁺* sᵢ₊₁⁻.
    pub fn squad(joints: &[f64], keys: &[Quat], logs: &[Axis], s_out: &[Quat], inner: &[Axis]) -> Self {
        let nseg = joints.len() - 1;
        let mut data = vec![0.0; nseg * SQUAD_STRIDE];
        for i in 0..nseg {
            let r = &mut data[i * SQUAD_STRIDE..(i + 1) * SQUAD_STRIDE];
            r[0] = joints[i];
            r[1] = joints[i + 1] - joints[i];
            r[4..8].copy_from_slice(&keys[i].to_wxyz());
            put_log(&mut r[8..12], &logs[i]);
            r[12..16].copy_from_slice(&s_out[i].to_wxyz());
            put_log(&mut r[16..20], &inner[i]);
        }
        SlerpTable { kind: Kind::Squad, points: 4, stride: SQUAD_STRIDE, data, locator: Locator::new(joints) }
    }
}

#[inline(always)]
fn q4<V: Lanes>(f: &[V], o: usize) -> Q4<V> {
    [f[o], f[o + 1], f[o + 2], f[o + 3]]
}

/// One vector of samples on the lanes' records `f`.
#[inline(always)]
fn body<V: LanesExt, const SQUAD: bool>(f: &[V], points: usize, tv: V) -> Q4<V> {
    let u = (tv - f[0]) / f[1];
    if SQUAD {
        let a = times_exp(q4(f, 4), [f[8], f[9], f[10]], u * f[11]);
        let b = times_exp(q4(f, 12), [f[16], f[17], f[18]], u * f[19]);
        let w = (u - u * u) * V::splat(2.0);
        return slerp(a, b, w);
    }
    let mut b = [[V::splat(0.0); 4]; MAX_POINTS - 1];
    let m = points - 1;
    for (j, bj) in b.iter_mut().enumerate().take(m) {
        let o = 4 + 8 * j;
        *bj = times_exp(q4(f, o), [f[o + 4], f[o + 5], f[o + 6]], u * f[o + 7]);
    }
    for level in (1..m).rev() {
        for j in 0..level {
            b[j] = slerp(b[j], b[j + 1], u);
        }
    }
    b[0]
}

#[inline(always)]
unsafe fn run<V: LanesExt, const SQUAD: bool>(
    tab: &SlerpTable,
    points: usize,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    let n = t.len();
    let stride = tab.stride;
    let base = tab.data.as_ptr();
    let mut local = [V::splat(0.0); MAX_STRIDE];
    let mut cached = usize::MAX;
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        let mut tl = [0.0; 4];
        let mut idx = [0usize; 4];
        for l in 0..V::N {
            let k = i + l.min(m - 1);
            tl[l] = t[k];
            idx[l] = seg[k] as usize * stride;
        }
        if idx[..V::N].iter().all(|&x| x == idx[0]) {
            // runs of one segment keep its broadcast record
            if cached != idx[0] {
                for (o, v) in local.iter_mut().zip(&tab.data[idx[0]..idx[0] + stride]) {
                    *o = V::splat(*v);
                }
                cached = idx[0];
            }
        } else {
            V::transpose_records(base, &idx, stride, local.as_mut_ptr());
            cached = usize::MAX;
        }
        let o = body::<V, SQUAD>(&local[..stride], points, V::load(tl.as_ptr()));
        let rows = &mut out[4 * i..4 * (i + m)];
        if m == V::N {
            V::store_rows4(o, rows.as_mut_ptr(), 4);
        } else {
            for (c, v) in o.iter().enumerate() {
                let a = v.to_array();
                for l in 0..m {
                    rows[4 * l + c] = a[l];
                }
            }
        }
        i += m;
    }
}

/// `run` with the common point counts folded into constants.
#[inline(always)]
unsafe fn shaped<V: LanesExt>(tab: &SlerpTable, seg: &[u32], t: &[f64], out: &mut [f64]) {
    match (tab.kind, tab.points) {
        (Kind::Squad, _) => run::<V, true>(tab, 4, seg, t, out),
        (_, 4) => run::<V, false>(tab, 4, seg, t, out),
        (_, 8) => run::<V, false>(tab, 8, seg, t, out),
        (_, p) => run::<V, false>(tab, p, seg, t, out),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn shaped_avx2(tab: &SlerpTable, seg: &[u32], t: &[f64], out: &mut [f64]) {
    shaped::<super::lanes::Avx2>(tab, seg, t, out)
}

impl BatchKernel for SlerpTable {
    fn locator(&self) -> &Locator {
        &self.locator
    }

    fn evaluate(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool {
        if order > 0 {
            return false;
        }
        let nseg = self.data.len() / self.stride;
        assert!(seg.len() == t.len() && out.len() == 4 * t.len(), "slerp kernel: bad lengths");
        assert!(seg.iter().all(|&s| (s as usize) < nseg), "slerp kernel: segment out of range");
        #[cfg(target_arch = "x86_64")]
        if isa == Isa::Avx2 && super::avx2_available() {
            // SAFETY: AVX2 and FMA detected; lengths and segment indices checked above.
            unsafe { shaped_avx2(self, seg, t, out) };
            return true;
        }
        let _ = isa;
        // SAFETY: lengths and segment indices checked above.
        unsafe { shaped::<f64>(self, seg, t, out) };
        true
    }

    fn angular(&self, _: Isa, _: &[u32], _: &[f64], _: usize, _: Frame, _: &mut [f64]) -> bool {
        false
    }
}
