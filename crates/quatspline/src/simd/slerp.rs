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
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic the slerp-family bodies use: any [`LanesExt`] vector, or [`P2`], two of
/// them in lockstep.
pub(crate) trait Arith:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    fn splat(x: f64) -> Self;
    fn fma(self, b: Self, c: Self) -> Self;
    fn fnma(self, b: Self, c: Self) -> Self;
    fn sin_cos(self) -> (Self, Self);
    fn sqrt(self) -> Self;
    fn lt_select(self, b: Self, x: Self, y: Self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn any_lt(self, b: Self) -> bool;
}

impl<V: LanesExt> Arith for V {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        <V as Lanes>::splat(x)
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        <V as Lanes>::fma(self, b, c)
    }
    #[inline(always)]
    fn fnma(self, b: Self, c: Self) -> Self {
        <V as Lanes>::fnma(self, b, c)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        <V as Lanes>::sin_cos(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        <V as Lanes>::sqrt(self)
    }
    #[inline(always)]
    fn lt_select(self, b: Self, x: Self, y: Self) -> Self {
        <V as Lanes>::lt_select(self, b, x, y)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        <V as LanesExt>::atan2(self, x)
    }
    #[inline(always)]
    fn any_lt(self, b: Self) -> bool {
        <V as LanesExt>::any_lt(self, b)
    }
}

/// Two vectors of samples evaluated in lockstep: every operation is issued for both, so the
/// long dependency chains of a slerp (square root, atan2's divisions, sin/cos, division)
/// of one vector overlap those of the other. Each lane's result is the same as alone.
#[derive(Clone, Copy)]
pub(crate) struct P2<V>(pub(crate) V, pub(crate) V);

macro_rules! p2_op {
    ($tr:ident, $f:ident) => {
        impl<V: Arith> $tr for P2<V> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, b: Self) -> Self {
                P2(self.0.$f(b.0), self.1.$f(b.1))
            }
        }
    };
}
p2_op!(Add, add);
p2_op!(Sub, sub);
p2_op!(Mul, mul);
p2_op!(Div, div);

impl<V: Arith> Neg for P2<V> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        P2(-self.0, -self.1)
    }
}

impl<V: Arith> Arith for P2<V> {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        P2(V::splat(x), V::splat(x))
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        P2(self.0.fma(b.0, c.0), self.1.fma(b.1, c.1))
    }
    #[inline(always)]
    fn fnma(self, b: Self, c: Self) -> Self {
        P2(self.0.fnma(b.0, c.0), self.1.fnma(b.1, c.1))
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let ((s0, c0), (s1, c1)) = (self.0.sin_cos(), self.1.sin_cos());
        (P2(s0, s1), P2(c0, c1))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        P2(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn lt_select(self, b: Self, x: Self, y: Self) -> Self {
        P2(self.0.lt_select(b.0, x.0, y.0), self.1.lt_select(b.1, x.1, y.1))
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        P2(self.0.atan2(x.0), self.1.atan2(x.1))
    }
    #[inline(always)]
    fn any_lt(self, b: Self) -> bool {
        self.0.any_lt(b.0) | self.1.any_lt(b.1)
    }
}

/// The most control points a de Casteljau table takes (a cubic segment has 4; spherical
/// Bézier curves beyond this keep the jets).
pub const MAX_POINTS: usize = 16;
const MAX_STRIDE: usize = 4 + 8 * (MAX_POINTS - 1);
const SQUAD_STRIDE: usize = 20;

type Q4<V> = [V; 4];

#[inline(always)]
pub(crate) fn qmul<V: Arith>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [
        a[3].fnma(b[3], a[2].fnma(b[2], a[1].fnma(b[1], a[0] * b[0]))),
        a[3].fnma(b[2], a[2].fma(b[3], a[1].fma(b[0], a[0] * b[1]))),
        a[3].fma(b[1], a[2].fma(b[0], a[1].fnma(b[3], a[0] * b[2]))),
        a[3].fma(b[0], a[2].fnma(b[1], a[1].fma(b[2], a[0] * b[3]))),
    ]
}

/// c exp(x n) for a constant quaternion c, unit axis n and angle x.
#[inline(always)]
fn times_exp<V: Arith>(c: Q4<V>, n: [V; 3], x: V) -> Q4<V> {
    let (s, co) = x.sin_cos();
    qmul(c, [co, s * n[0], s * n[1], s * n[2]])
}

/// slerp(a, b; w) = a exp(w log(a* b)), no hemisphere flip (as `JQuat::slerp`), for unit a
/// and b, written without quaternion products: with c = a·b and r = b − c a (= a ⊗ vec(a* b),
/// orthogonal to a, |r| = sin θ), θ = atan2(|r|, c) and the result is
/// a cos wθ + r sin wθ / |r|. Where |r| = 0 exactly: a, or for c < 0 the reference's
/// log(−1) = (π, 0, 0) choice, a ⊗ (cos wπ, sin wπ, 0, 0).
#[inline(always)]
pub(crate) fn slerp<V: Arith>(a: Q4<V>, b: Q4<V>, w: V) -> Q4<V> {
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

/// Field `o` of the two vectors' records.
#[inline(always)]
fn g<V: Copy>(f: &[V], h: &[V], o: usize) -> P2<V> {
    P2(f[o], h[o])
}

#[inline(always)]
fn q4<V: Copy>(f: &[V], h: &[V], o: usize) -> Q4<P2<V>> {
    [g(f, h, o), g(f, h, o + 1), g(f, h, o + 2), g(f, h, o + 3)]
}

/// Two vectors of samples on the lanes' records `f` (first vector) and `h` (second).
#[inline(always)]
fn body<V: LanesExt, const SQUAD: bool>(f: &[V], h: &[V], points: usize, tv: P2<V>) -> Q4<P2<V>> {
    let u = (tv - g(f, h, 0)) / g(f, h, 1);
    let axis = |o: usize| [g(f, h, o), g(f, h, o + 1), g(f, h, o + 2)];
    if SQUAD {
        let a = times_exp(q4(f, h, 4), axis(8), u * g(f, h, 11));
        let b = times_exp(q4(f, h, 12), axis(16), u * g(f, h, 19));
        let w = (u - u * u) * <P2<V> as Arith>::splat(2.0);
        return slerp(a, b, w);
    }
    let zero = <P2<V> as Arith>::splat(0.0);
    let mut b = [[zero; 4]; MAX_POINTS - 1];
    let m = points - 1;
    for (j, bj) in b.iter_mut().enumerate().take(m) {
        let o = 4 + 8 * j;
        *bj = times_exp(q4(f, h, o), axis(o + 4), u * g(f, h, o + 7));
    }
    for level in (1..m).rev() {
        for j in 0..level {
            b[j] = slerp(b[j], b[j + 1], u);
        }
    }
    b[0]
}

/// Loads the records of lanes `idx` into `local` (broadcast when they share one; `cached`
/// remembers a broadcast record).
#[inline(always)]
unsafe fn fetch<V: LanesExt>(tab: &SlerpTable, idx: &[usize; 4], local: &mut [V], cached: &mut usize) {
    let stride = tab.stride;
    if idx[..V::N].iter().all(|&x| x == idx[0]) {
        // runs of one segment keep its broadcast record
        if *cached != idx[0] {
            for (o, v) in local.iter_mut().zip(&tab.data[idx[0]..idx[0] + stride]) {
                *o = <V as Lanes>::splat(*v);
            }
            *cached = idx[0];
        }
    } else {
        V::transpose_records(tab.data.as_ptr(), idx, stride, local.as_mut_ptr());
        *cached = usize::MAX;
    }
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
    let z = <V as Lanes>::splat(0.0);
    let (mut la, mut lb) = ([z; MAX_STRIDE], [z; MAX_STRIDE]);
    let (mut ca, mut cb) = (usize::MAX, usize::MAX);
    let w = 2 * V::N;
    let mut i = 0;
    while i < n {
        // two vectors of lanes; a tail is padded with copies of its last sample
        let m = (n - i).min(w);
        let mut tl = [0.0; 8];
        let mut idx = [[0usize; 4]; 2];
        for l in 0..w {
            let k = i + l.min(m - 1);
            tl[l] = t[k];
            idx[l / V::N][l % V::N] = seg[k] as usize * stride;
        }
        fetch(tab, &idx[0], &mut la, &mut ca);
        fetch(tab, &idx[1], &mut lb, &mut cb);
        let tv = P2(V::load(tl.as_ptr()), V::load(tl.as_ptr().add(V::N)));
        let o = body::<V, SQUAD>(&la[..stride], &lb[..stride], points, tv);
        let rows = &mut out[4 * i..4 * (i + m)];
        if m == w {
            V::store_rows4([o[0].0, o[1].0, o[2].0, o[3].0], rows.as_mut_ptr(), 4);
            V::store_rows4([o[0].1, o[1].1, o[2].1, o[3].1], rows.as_mut_ptr().add(4 * V::N), 4);
        } else {
            for (c, v) in o.iter().enumerate() {
                let (a, b) = (v.0.to_array(), v.1.to_array());
                for l in 0..m {
                    rows[4 * l + c] = if l < V::N { a[l] } else { b[l - V::N] };
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
