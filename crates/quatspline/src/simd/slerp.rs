//! Batch kernels of the slerp family: Squad, the cubic spherical Bézier segments of
//! Catmull–Rom / Kochanek–Bartels, and the spherical Bézier curve (de Casteljau with slerp) of
//! every degree it takes (up to 65 control points: n(n − 1)/2 slerps per sample, vectorised
//! across samples, one lane each).
//!
//! **Data.** One flat record per segment (a multiple of 4 doubles, so that records can be
//! transposed 4 at a time): the segment's start time t₀ and length h, then
//! - de Casteljau of n points: a series flag (field 2, see below), then per control point
//!   j < n−1 the point cⱼ, the log of cⱼ* cⱼ₊₁ as unit axis nⱼ and angle aⱼ, the end of the
//!   first-level slerp eⱼ = cⱼ exp(aⱼ nⱼ) and xⱼ = cos aⱼ − 1 (16 doubles);
//! - Squad: qᵢ, log(qᵢ* qᵢ₊₁) (axis, angle), sᵢ⁺, log(sᵢ⁺* sᵢ₊₁⁻) (axis, angle).
//!
//! **Value** (the formulas of `spline/squad.rs`, `kochanek_bartels.rs`, `spherical_bezier.rs`,
//! evaluated as the jet path does): u = (t − t₀)/h; the first level cⱼ exp(u aⱼ nⱼ) by the
//! vector sin/cos; each slerp(a, b; w) = a exp(w log(a* b)) by [`slerp`] (no quaternion
//! product: c = a·b, r = b − c a, θ = atan2(|r|, c) with the vector atan2 of `lanes.rs`).
//! Where every angle between consecutive control points is at most one of
//! [`SERIES_MAX_ANGLE`] (the record's flag names the tier), de Casteljau instead takes
//! [`slerp_series`] for every slerp, the first level included: a sin((1 − w)θ)/sin θ +
//! b sin(wθ)/sin θ with both ratios as [`SERIES_TERMS`]-term series in cos θ − 1 whose
//! coefficients depend on w = u only, so they are computed once per sample for the whole
//! pyramid: no square root, division or trigonometric function per slerp. Derivatives and
//! rates keep the exact jets (the kernels decline and the engine falls back per run).

use super::lanes::{Lanes, MAX_LANES, P2};
use super::quat_lanes::{slerp, times_exp, Q4};
use super::{Kernel, Locator};
use rayon::prelude::*;

/// Segments per parallel task when a table is filled.
const BUILD_CHUNK: usize = 4096;
use crate::jet::Axis;
use crate::quat::Quat;

/// The most control points a de Casteljau table takes: a cubic segment has 4, a spherical
/// Bézier curve up to 65 (`spline::spherical_bezier::MAX_DEGREE` + 1).
pub const MAX_POINTS: usize = 65;
/// Up to this many points a record is read into stack arrays and the pyramid has 15 rows of
/// room (the common shapes); beyond, the records live on the heap (once per call of the
/// kernel, not per sample) and the pyramid has [`MAX_POINTS`] − 1 rows.
const SMALL_POINTS: usize = 16;
/// Fields per control point of a de Casteljau record: cⱼ, (nⱼ, aⱼ), eⱼ, (xⱼ, 0, 0, 0).
const PER_POINT: usize = 16;
const SMALL_STRIDE: usize = 4 + PER_POINT * (SMALL_POINTS - 1);
const SQUAD_STRIDE: usize = 20;
/// The series slerp below serves a de Casteljau segment when every angle between consecutive
/// control points (half the rotation angle, rad) is at most `SERIES_MAX_ANGLE[i]` for a tier
/// i, with `SERIES_TERMS[i]` terms: the truncation error is below 1.9e-17 (tier 0), 3e-18
/// (tier 1) and 1.4e-17 (tier 2) for every weight in [0, 1] at those angles (mpmath, 40
/// digits), smaller below. Each tier is the first whose bound holds, so dense keys (steps of
/// a few degrees, as animation and capture data have) take the shortest series; the first
/// tier serves single curves (spherical Bézier), the others every de Casteljau table.
pub const SERIES_MAX_ANGLE: [f64; 3] = [0.15, 0.3, 0.5];
/// See [`SERIES_MAX_ANGLE`].
pub const SERIES_TERMS: [usize; 3] = [6, 9, 12];
const MAX_TERMS: usize = 12;
/// Series coefficients βₖ, k = 0…K (entries beyond K unused).
pub(crate) type Coef<V> = [V; MAX_TERMS + 1];

/// The coefficients βₖ(w) of sin(wθ)/sin θ = Σₖ βₖ(w) xᵏ, x = cos θ − 1 (k = 0…K):
/// β₀ = w, βₖ = βₖ₋₁ (w² − k²) / (k (2k + 1)) (the hypergeometric series of sin(wθ)/sin θ in
/// cos θ − 1; Eberly, "A fast and accurate algorithm for computing SLERP", J. Graphics, GPU
/// and Game Tools 15 (3), 2011, eq. 11, here to double precision). The terms shrink like
/// sin²(θ/2)ᵏ.
#[inline(always)]
pub(crate) fn series_coefficients<V: Lanes, const K: usize>(w: V) -> Coef<V> {
    let w2 = w * w;
    let mut b = [w; MAX_TERMS + 1];
    for k in 1..=K {
        let kk = (k * k) as f64;
        let inv = 1.0 / (k * (2 * k + 1)) as f64;
        // (w² − k²) / (k(2k + 1)) as w² · inv − k² · inv (both products of exact inputs)
        b[k] = b[k - 1] * w2.fma(V::splat(inv), V::splat(-kk * inv));
    }
    b
}

/// Σₖ βₖ xᵏ (k = 0…K): by Horner's rule, or with `ESTRIN` by Estrin's scheme on the powers
/// x, x², x⁴, x⁸ (`p`, shared by the two series of a slerp): pairs βₖ + βₖ₊₁ x, then pairs of
/// pairs with x², and so on — as many fused multiply-adds but a dependency chain of
/// ⌈log₂(K+1)⌉ instead of K. A tall de Casteljau pyramid waits on its top levels' chains (few
/// independent slerps), so it takes Estrin (8 points, one core: 53.1–53.7 → 49.1–50.1 ns/sample
/// in `benchmarks/engine_bench.py`);
/// a cubic segment (4 points) is throughput-bound — consecutive samples overlap — and keeps
/// Horner, which needs no powers (Estrin made Catmull–Rom 20 % slower: 10.1 → 12.1 ns/sample
/// on both cores, same benchmark).
#[inline(always)]
fn series<V: Lanes, const K: usize, const ESTRIN: bool>(b: &Coef<V>, p: &[V; 4]) -> V {
    if !ESTRIN {
        let mut acc = b[K];
        for k in (0..K).rev() {
            acc = acc.fma(p[0], b[k]);
        }
        return acc;
    }
    let mut c = *b;
    let mut n = K + 1;
    let mut level = 0;
    while n > 1 {
        for i in 0..n / 2 {
            c[i] = c[2 * i + 1].fma(p[level], c[2 * i]);
        }
        if n % 2 == 1 {
            c[n / 2] = c[n - 1];
        }
        n = n.div_ceil(2);
        level += 1;
    }
    c[0]
}

/// x, x², x⁴, x⁸ for Estrin's scheme (series of up to 16 terms); x alone for Horner's.
#[inline(always)]
fn powers<V: Lanes, const ESTRIN: bool>(x: V) -> [V; 4] {
    if !ESTRIN {
        return [x; 4];
    }
    let x2 = x * x;
    let x4 = x2 * x2;
    [x, x2, x4, x4 * x4]
}

/// slerp(a, b; w) = a sin((1 − w)θ)/sin θ + b sin(wθ)/sin θ for unit a, b at an angle θ up to
/// `SERIES_MAX_ANGLE[i]` and K = `SERIES_TERMS[i]`, with `bw` = βₖ(w) and `bv` = βₖ(1 − w)
/// from [`series_coefficients`]:
/// no square root, division or trigonometric function. x = a·b − 1 takes the −1 into its
/// first product (its absolute error is a few ulp of 1, and ∂/∂x of either coefficient is
/// below 0.2); with `ESTRIN` the dot product runs as two chains of two (three operations deep
/// instead of four). Exact at the ends: βₖ(0) = 0 and βₖ(1) = (1, 0, 0, …), so w = 0 gives a
/// and w = 1 gives b (Estrin's pairs then hold 1 or 0 exactly).
#[inline(always)]
pub(crate) fn slerp_series<V: Lanes, const K: usize, const ESTRIN: bool>(
    a: Q4<V>,
    b: Q4<V>,
    bw: &Coef<V>,
    bv: &Coef<V>,
) -> Q4<V> {
    let x = if ESTRIN {
        a[1].fma(b[1], a[0].fma(b[0], V::splat(-1.0))) + a[3].fma(b[3], a[2] * b[2])
    } else {
        a[3].fma(b[3], a[2].fma(b[2], a[1].fma(b[1], a[0].fma(b[0], V::splat(-1.0)))))
    };
    lin_series::<V, K, ESTRIN>(a, b, x, bw, bv)
}

/// a sin((1 − w)θ)/sin θ + b sin(wθ)/sin θ for a given x = cos θ − 1.
#[inline(always)]
fn lin_series<V: Lanes, const K: usize, const ESTRIN: bool>(
    a: Q4<V>,
    b: Q4<V>,
    x: V,
    bw: &Coef<V>,
    bv: &Coef<V>,
) -> Q4<V> {
    let p = powers::<V, ESTRIN>(x);
    let (fa, fb) = (series::<V, K, ESTRIN>(bv, &p), series::<V, K, ESTRIN>(bw, &p));
    [b[0].fma(fb, a[0] * fa), b[1].fma(fb, a[1] * fa), b[2].fma(fb, a[2] * fa), b[3].fma(fb, a[3] * fa)]
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
        let stride = 4 + PER_POINT * (n - 1);
        let mut data = super::table_buffer(ctrl.len() * stride);
        // records are independent: filled in parallel blocks (the same numbers as one thread)
        data.par_chunks_mut(stride * BUILD_CHUNK).enumerate().for_each(|(b, block)| {
            for (k, r) in block.chunks_mut(stride).enumerate() {
                let i = b * BUILD_CHUNK + k;
                let (c, l) = (ctrl[i], logs[i]);
                r[0] = joints[i];
                r[1] = joints[i + 1] - joints[i];
                // field 2: 1 + the series tier where one applies, else 0 (see `body`). The
                // shortest tier only for a single curve: segments of a spline sharing a vector
                // (unsorted times) cost one pyramid per tier present, and a third tier among
                // Catmull–Rom segments made unsorted input slower than it saves on sorted input
                let first = if ctrl.len() == 1 { 0 } else { 1 };
                r[2] = match SERIES_MAX_ANGLE[first..]
                    .iter()
                    .position(|&m| l[..n - 1].iter().all(|ax| ax.a <= m))
                {
                    Some(tier) => (first + tier + 1) as f64,
                    None => 0.0,
                };
                for j in 0..n - 1 {
                    let o = 4 + PER_POINT * j;
                    r[o..o + 4].copy_from_slice(&c[j].to_wxyz());
                    put_log(&mut r[o + 4..o + 8], &l[j]);
                    // eⱼ = cⱼ exp(aⱼ nⱼ) (the end of the first-level slerp) and xⱼ = cos aⱼ − 1
                    let (sa, ca) = crate::special::sin_cos(l[j].a);
                    let e = c[j] * Quat::new(ca, sa * l[j].n[0], sa * l[j].n[1], sa * l[j].n[2]);
                    r[o + 8..o + 12].copy_from_slice(&e.to_wxyz());
                    let h = (0.5 * l[j].a).sin();
                    r[o + 12] = -2.0 * h * h;
                }
            }
        });
        Some(SlerpTable { kind: Kind::Casteljau, points: n, stride, data, locator: Locator::new(joints) })
    }

    /// Squad segments: keys qᵢ, logs of qᵢ* qᵢ₊₁, outgoing control points sᵢ⁺, logs of
    /// sᵢ⁺* sᵢ₊₁⁻.
    pub fn squad(joints: &[f64], keys: &[Quat], logs: &[Axis], s_out: &[Quat], inner: &[Axis]) -> Self {
        let nseg = joints.len() - 1;
        let mut data = super::table_buffer(nseg * SQUAD_STRIDE);
        data.par_chunks_mut(SQUAD_STRIDE * BUILD_CHUNK).enumerate().for_each(|(b, block)| {
            for (k, r) in block.chunks_mut(SQUAD_STRIDE).enumerate() {
                let i = b * BUILD_CHUNK + k;
                r[0] = joints[i];
                r[1] = joints[i + 1] - joints[i];
                r[4..8].copy_from_slice(&keys[i].to_wxyz());
                put_log(&mut r[8..12], &logs[i]);
                r[12..16].copy_from_slice(&s_out[i].to_wxyz());
                put_log(&mut r[16..20], &inner[i]);
            }
        });
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
///
/// With `TIER` t > 0 (every lane's record is flagged t: all control-point angles at most
/// `SERIES_MAX_ANGLE[t − 1]`, hence every angle of the pyramid too, since on the sphere
/// d(slerp(P, Q; u), slerp(Q, R; u)) ≤ (1 − u) d(P, Q) + u d(Q, R)), every slerp of the
/// pyramid, the first level included (from cⱼ to eⱼ), is [`slerp_series`] with the same
/// coefficients βₖ(u), βₖ(1 − u) for all of them.
#[inline(always)]
fn body<V: Lanes, const SQUAD: bool, const TIER: usize, const CAP: usize>(
    f: &[V],
    h: &[V],
    points: usize,
    tv: P2<V>,
) -> Q4<P2<V>> {
    let u = (tv - g(f, h, 0)) / g(f, h, 1);
    if !SQUAD {
        match TIER {
            1 => return series_pyramid::<V, { SERIES_TERMS[0] }, CAP>(f, h, points, u),
            2 => return series_pyramid::<V, { SERIES_TERMS[1] }, CAP>(f, h, points, u),
            3 => return series_pyramid::<V, { SERIES_TERMS[2] }, CAP>(f, h, points, u),
            _ => {}
        }
    }
    let axis = |o: usize| [g(f, h, o), g(f, h, o + 1), g(f, h, o + 2)];
    if SQUAD {
        let a = times_exp(q4(f, h, 4), axis(8), u * g(f, h, 11));
        let b = times_exp(q4(f, h, 12), axis(16), u * g(f, h, 19));
        let w = (u - u * u) * P2::<V>::splat(2.0);
        return slerp(a, b, w);
    }
    let zero = P2::<V>::splat(0.0);
    let mut b = [[zero; 4]; CAP];
    let m = points - 1;
    for (j, bj) in b.iter_mut().enumerate().take(m) {
        let o = 4 + PER_POINT * j;
        *bj = times_exp(q4(f, h, o), axis(o + 4), u * g(f, h, o + 7));
    }
    for level in (1..m).rev() {
        for j in 0..level {
            b[j] = slerp(b[j], b[j + 1], u);
        }
    }
    b[0]
}

/// The de Casteljau pyramid by [`slerp_series`] with K terms (see [`body`]): Estrin's scheme
/// beyond 4 points, Horner's up to 4 (see [`series`]; `points` is a constant in the common
/// shapes, so the choice folds away).
#[inline(always)]
fn series_pyramid<V: Lanes, const K: usize, const CAP: usize>(
    f: &[V],
    h: &[V],
    points: usize,
    u: P2<V>,
) -> Q4<P2<V>> {
    if points > 4 {
        pyramid::<V, K, true, CAP>(f, h, points, u)
    } else {
        pyramid::<V, K, false, CAP>(f, h, points, u)
    }
}

#[inline(always)]
fn pyramid<V: Lanes, const K: usize, const ESTRIN: bool, const CAP: usize>(
    f: &[V],
    h: &[V],
    points: usize,
    u: P2<V>,
) -> Q4<P2<V>> {
    let one = P2::<V>::splat(1.0);
    let (bw, bv) = (series_coefficients::<_, K>(u), series_coefficients::<_, K>(one - u));
    let zero = P2::<V>::splat(0.0);
    let mut b = [[zero; 4]; CAP];
    let m = points - 1;
    for (j, bj) in b.iter_mut().enumerate().take(m) {
        let o = 4 + PER_POINT * j;
        *bj = lin_series::<_, K, ESTRIN>(q4(f, h, o), q4(f, h, o + 8), g(f, h, o + 12), &bw, &bv);
    }
    for level in (1..m).rev() {
        for j in 0..level {
            b[j] = slerp_series::<_, K, ESTRIN>(b[j], b[j + 1], &bw, &bv);
        }
    }
    b[0]
}

/// 1 in the lanes whose flag is `k`, else 0.
#[inline(always)]
fn tier_indicator<V: Lanes>(flag: V, k: f64) -> V {
    let (zero, one) = (V::splat(0.0), V::splat(1.0));
    V::splat(k - 0.5).lt_select(flag, flag.lt_select(V::splat(k + 0.5), one, zero), zero)
}

/// Loads the records of lanes `idx` into `local` (broadcast when they share one; `cached`
/// remembers a broadcast record).
#[inline(always)]
unsafe fn fetch<V: Lanes>(
    tab: &SlerpTable,
    idx: &[usize; MAX_LANES / 2],
    local: &mut [V],
    cached: &mut usize,
) {
    let stride = tab.stride;
    if idx[..V::N].iter().all(|&x| x == idx[0]) {
        // runs of one segment keep its broadcast record
        if *cached != idx[0] {
            for (o, v) in local.iter_mut().zip(&tab.data[idx[0]..idx[0] + stride]) {
                *o = V::splat(*v);
            }
            *cached = idx[0];
        }
    } else {
        V::transpose_records(tab.data.as_ptr(), idx, stride, local.as_mut_ptr());
        *cached = usize::MAX;
    }
}

#[inline(always)]
unsafe fn run<V: Lanes, const SQUAD: bool, const CAP: usize>(
    tab: &SlerpTable,
    points: usize,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
    la: &mut [V],
    lb: &mut [V],
) {
    let n = t.len();
    let stride = tab.stride;
    let (mut ca, mut cb) = (usize::MAX, usize::MAX);
    let w = 2 * V::N;
    let mut i = 0;
    while i < n {
        // two vectors of lanes; a tail is padded with copies of its last sample
        let m = (n - i).min(w);
        let mut tl = [0.0; MAX_LANES];
        let mut idx = [[0usize; MAX_LANES / 2]; 2];
        for l in 0..w {
            let k = i + l.min(m - 1);
            tl[l] = t[k];
            idx[l / V::N][l % V::N] = seg[k] as usize * stride;
        }
        fetch(tab, &idx[0], la, &mut ca);
        fetch(tab, &idx[1], lb, &mut cb);
        let tv = P2(V::load(tl.as_ptr()), V::load(tl.as_ptr().add(V::N)));
        let o = if SQUAD {
            body::<V, true, 0, CAP>(&la[..stride], &lb[..stride], points, tv)
        } else {
            // each lane's path is chosen by its own record's flag (field 2: 0 general, else
            // 1 + series tier), so that no row depends on its neighbours: a vector mixing
            // paths computes each and blends
            // (no closures here: they would not inherit the caller's target features)
            let flag = P2(la[2], lb[2]);
            let half = P2::<V>::splat(0.5);
            let ind = [
                tier_indicator(flag, 0.0),
                tier_indicator(flag, 1.0),
                tier_indicator(flag, 2.0),
                tier_indicator(flag, 3.0),
            ];
            let present =
                [half.any_lt(ind[0]), half.any_lt(ind[1]), half.any_lt(ind[2]), half.any_lt(ind[3])];
            let (f, h) = (&la[..stride], &lb[..stride]);
            let mut o: Option<Q4<P2<V>>> = None;
            for k in 0..ind.len() {
                if !present[k] {
                    continue;
                }
                let r = match k {
                    1 => body::<V, false, 1, CAP>(f, h, points, tv),
                    2 => body::<V, false, 2, CAP>(f, h, points, tv),
                    3 => body::<V, false, 3, CAP>(f, h, points, tv),
                    _ => body::<V, false, 0, CAP>(f, h, points, tv),
                };
                o = Some(match o {
                    None => r,
                    Some(p) => [
                        ind[k].lt_select(half, p[0], r[0]),
                        ind[k].lt_select(half, p[1], r[1]),
                        ind[k].lt_select(half, p[2], r[2]),
                        ind[k].lt_select(half, p[3], r[3]),
                    ],
                });
            }
            o.expect("every lane has a flag of 0 to 3")
        };
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

/// `run` with the common point counts folded into constants; records of up to
/// [`SMALL_POINTS`] points in stack arrays, larger ones in two heap buffers per call (a
/// spherical Bézier curve is one record, broadcast once per call).
#[inline(always)]
unsafe fn shaped<V: Lanes>(tab: &SlerpTable, seg: &[u32], t: &[f64], out: &mut [f64]) {
    const SMALL: usize = SMALL_POINTS - 1;
    let z = V::splat(0.0);
    if tab.stride > SMALL_STRIDE {
        let (mut la, mut lb) = (vec![z; tab.stride], vec![z; tab.stride]);
        return run::<V, false, { MAX_POINTS - 1 }>(tab, tab.points, seg, t, out, &mut la, &mut lb);
    }
    let (mut la, mut lb) = ([z; SMALL_STRIDE], [z; SMALL_STRIDE]);
    let (la, lb) = (&mut la[..], &mut lb[..]);
    match (tab.kind, tab.points) {
        (Kind::Squad, _) => run::<V, true, SMALL>(tab, 4, seg, t, out, la, lb),
        (_, 4) => run::<V, false, SMALL>(tab, 4, seg, t, out, la, lb),
        (_, 8) => run::<V, false, SMALL>(tab, 8, seg, t, out, la, lb),
        (_, p) => run::<V, false, SMALL>(tab, p, seg, t, out, la, lb),
    }
}

impl Kernel for SlerpTable {
    const NAME: &'static str = "slerp";
    // values only: derivatives and rates keep the exact jets
    const ORDERS: usize = 0;
    const RATES: bool = false;
    // the pyramid's working set needs the 32 vector registers of AVX-512 VL (fewer spills;
    // the same 256-bit instructions, so the same bits)
    const WIDE_REGISTERS: bool = true;
    fn locator(&self) -> &Locator {
        &self.locator
    }
    fn segments(&self) -> usize {
        self.data.len() / self.stride
    }
    #[inline(always)]
    unsafe fn body<L: Lanes, const K: usize, const OUT: u8>(&self, seg: &[u32], t: &[f64], out: &mut [f64]) {
        shaped::<L>(self, seg, t, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(q: [f64; 4]) -> [f64; 4] {
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        q.map(|v| v / n)
    }

    /// The series slerp against the trigonometric one (f64 lanes) for angles from 0 to each
    /// tier's [`SERIES_MAX_ANGLE`] and weights across [0, 1], ends exact.
    #[test]
    fn series_slerp_equals_the_trigonometric_slerp() {
        let mut rng = crate::testing::XorShift64::new(5);
        let mut next = || rng.uniform();
        // both evaluation schemes (Horner, Estrin)
        fn tier<const K: usize>(a: [f64; 4], b: [f64; 4], w: f64, estrin: bool) -> [f64; 4] {
            let (bw, bv) = (series_coefficients::<_, K>(w), series_coefficients::<_, K>(1.0 - w));
            if estrin {
                slerp_series::<_, K, true>(a, b, &bw, &bv)
            } else {
                slerp_series::<_, K, false>(a, b, &bw, &bv)
            }
        }
        let mut worst = [0.0f64; 3];
        for i in 0..4000 {
            let a = unit([next() - 0.5, next() - 0.5, next() - 0.5, next() - 0.5]);
            // b at angle th from a: a cos th + p sin th, p ⟂ a unit
            let r = [next() - 0.5, next() - 0.5, next() - 0.5, next() - 0.5];
            let d: f64 = (0..4).map(|c| r[c] * a[c]).sum();
            let p = unit([0, 1, 2, 3].map(|c| r[c] - d * a[c]));
            let frac = match i % 4 {
                0 => 1.0,
                1 => next(),
                2 => 1e-9 * next(),
                _ => 0.0,
            };
            for (k, max) in SERIES_MAX_ANGLE.iter().enumerate() {
                let (s, c) = f64::sin_cos(frac * max);
                let b = [0, 1, 2, 3].map(|j| a[j] * c + p[j] * s);
                for (w, estrin) in [0.0, 1.0, next(), 0.5, 1e-3 * next(), 1.0 - 1e-3 * next()]
                    .into_iter()
                    .flat_map(|w| [(w, false), (w, true)])
                {
                    let got = match k {
                        0 => tier::<{ SERIES_TERMS[0] }>(a, b, w, estrin),
                        1 => tier::<{ SERIES_TERMS[1] }>(a, b, w, estrin),
                        _ => tier::<{ SERIES_TERMS[2] }>(a, b, w, estrin),
                    };
                    let want = slerp(a, b, w);
                    for j in 0..4 {
                        worst[k] = worst[k].max((got[j] - want[j]).abs());
                    }
                    if w == 0.0 {
                        assert_eq!(got, a);
                    }
                    if w == 1.0 {
                        assert_eq!(got, b);
                    }
                }
            }
        }
        assert!(worst.iter().all(|&w| w <= 1e-15), "worst by tier {worst:?}");
    }

    /// The table flags a curve with the first series tier whose angle bounds every neighbour
    /// angle, or 0 (the trigonometric path).
    #[test]
    fn series_flag_follows_the_largest_angle() {
        for (half, want) in [
            (0.1, 1.0),
            (0.1499, 1.0),
            (0.1501, 2.0),
            (0.2999, 2.0),
            (0.3001, 3.0),
            (0.4999, 3.0),
            (0.5001, 0.0),
            (3.0, 0.0),
        ] {
            let (s, c) = f64::sin_cos(half);
            let ctrl = [Quat::IDENTITY, Quat::new(c, s, 0.0, 0.0), Quat::new(c * c, s * c, s * c, s * s)];
            let logs: Vec<Axis> =
                ctrl.windows(2).map(|w| Axis::from_log((w[0].conj() * w[1]).log().vec())).collect();
            let tab = SlerpTable::casteljau(&[0.0, 1.0], &[&ctrl[..]], &[&logs[..]]).unwrap();
            assert_eq!(tab.data[2], want, "half-angle {half}");
            // segments of a spline (more than one) start at the second tier
            let two =
                SlerpTable::casteljau(&[0.0, 1.0, 2.0], &[&ctrl[..], &ctrl[..]], &[&logs[..], &logs[..]])
                    .unwrap();
            let want_many = if want == 1.0 { 2.0 } else { want };
            assert_eq!((two.data[2], two.data[two.stride + 2]), (want_many, want_many), "half-angle {half}");
        }
    }

    /// The AVX2 kernel compiled with 32 vector registers (chosen where AVX-512 VL exists) and
    /// the one with 16 give the same bits, on segments of both paths mixed within vectors.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_kernels_with_16_and_32_registers_agree_bitwise() {
        if !(crate::simd::avx2_available()
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl"))
        {
            return;
        }
        let mut rng = crate::testing::XorShift64::new(9);
        let mut next = || rng.uniform();
        let nseg = 12;
        let joints: Vec<f64> = (0..=nseg).map(|i| i as f64 * 0.7).collect();
        let mut ctrl: Vec<Vec<Quat>> = Vec::new();
        for i in 0..nseg {
            // even segments within the series' angle, odd ones beyond it
            let half = if i % 2 == 0 { 0.05 + 0.4 * next() } else { 0.55 + 2.0 * next() };
            let mut c = vec![Quat::new(next() - 0.5, next() - 0.5, next() - 0.5, next() - 0.5).normalize()];
            for _ in 0..3 {
                let ax = [next() - 0.5, next() - 0.5, next() - 0.5];
                let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
                let (s, co) = f64::sin_cos(half);
                let q = *c.last().unwrap() * Quat::new(co, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m);
                c.push(q);
            }
            ctrl.push(c);
        }
        let logs: Vec<Vec<Axis>> = ctrl
            .iter()
            .map(|c| c.windows(2).map(|w| Axis::from_log((w[0].conj() * w[1]).log().vec())).collect())
            .collect();
        let cr: Vec<&[Quat]> = ctrl.iter().map(|c| &c[..]).collect();
        let lr: Vec<&[Axis]> = logs.iter().map(|l| &l[..]).collect();
        let tab = SlerpTable::casteljau(&joints, &cr, &lr).unwrap();
        assert!((0..nseg).any(|i| tab.data[i * tab.stride + 2] > 0.0));
        assert!((0..nseg).any(|i| tab.data[i * tab.stride + 2] == 0.0));
        let t: Vec<f64> = (0..999).map(|_| joints[nseg] * next()).collect();
        let seg: Vec<u32> = t.iter().map(|&v| tab.locator.locate(v) as u32).collect();
        let (mut a, mut b) = (vec![0.0; 4 * t.len()], vec![0.0; 4 * t.len()]);
        use crate::simd::{on_avx2, on_avx2_32regs, Body, EVAL};
        // SAFETY: features checked above; lengths and segments valid
        unsafe {
            on_avx2(Body::<_, 0, EVAL> { tab: &tab, seg: &seg, t: &t, out: &mut a });
            on_avx2_32regs(Body::<_, 0, EVAL> { tab: &tab, seg: &seg, t: &t, out: &mut b });
        }
        assert!(a.iter().zip(&b).all(|(p, q)| p.to_bits() == q.to_bits()));
        assert!(a.iter().all(|v| v.is_finite()));
    }
}
