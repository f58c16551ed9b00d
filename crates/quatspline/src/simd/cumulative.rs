//! Batch kernels of the cumulative family: every method whose segment is
//! q(t) = q_s Π_{j=1..J} exp(θ_j(u) n_j), θ_j a polynomial in the local parameter u and n_j a
//! constant unit axis — cumulative B-spline (order k: J = D = k−1), Beta spline and cumulative
//! Bézier (cumulative Bernstein weights), C³ spline (J = 3, D = 7), piecewise slerp (J = D = 1).
//!
//! **Data.** Each segment has two flat records, one per half (u ≤ ½ and u > ½), of
//! 6 + J(D+4) doubles: the time the record's variable is measured from, its rate (1/h on the
//! first half, where x = u; −1/h on the second, where x = 1 − u), the base quaternion, then per
//! factor the axis and the power coefficients of θ_j in x with the log's angle folded in. The
//! second-half record keeps high-degree weights well conditioned (|x| ≤ ½; the C³ weights in
//! powers of u alone lose up to 1e-13 near u = 1) and makes the segment end exact.
//!
//! **Value.** θ_j by Horner, (sin, cos) by the vector fdlibm kernel, J quaternion products.
//!
//! **Rates without jets** (Sommer et al. 2020, generalised to any number of factors): with
//! e_j = exp(θ_j n_j), ω_j = 2θ_j' n_j and R_j(x) = e_j* x e_j,
//!   ω ← R_j(ω) + ω_j,
//!   α ← R_j(α) − ω_j × R_j(ω) + ω_j',
//!   j ← R_j(j) − 2 ω_j × R_j(α) − ω_j' × R_j(ω) + ω_j × (ω_j × R_j(ω)) + ω_j'',
//! (dR_j(x)/dt = R_j(x') − ω_j × R_j(x)) give the body-frame ω, α, jerk; the world frame is
//! one rotation by q (jerk_w = q j q* + ω_w × α_w); q' = ½ q ω, q'' = ½ (q' ω + q α),
//! q''' = ½ (q'' ω + 2 q' α + q j) give the quaternion derivatives.

use super::lanes::Lanes;
use super::{BatchKernel, Isa, Locator};
use crate::jet::Axis;
use crate::quat::Quat;
use crate::spline::Frame;

/// The most factors / the highest degree a table supports (B-spline order 12, Bézier of 12
/// points); beyond, the spline has no batch kernel and the engine uses the jets.
pub const MAX_FACTORS: usize = 11;
/// See [`MAX_FACTORS`].
pub const MAX_DEGREE: usize = 11;

/// How a factor's weight polynomial is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Basis {
    /// Coefficients of 1, u, u², … .
    Power,
    /// Coefficients of the degree-D Bernstein polynomials C(D,l) uˡ (1−u)^(D−l).
    Bernstein,
}

/// One segment for [`CumulativeTable::new`]: base quaternion and, per factor, the log (axis,
/// angle) and the weight polynomial's coefficients (before the angle is folded in).
pub struct SegmentForm {
    pub base: Quat,
    pub factors: Vec<(Axis, Vec<f64>)>,
}

/// Precomputed flat per-segment data of a cumulative-form spline (see the module doc).
#[derive(Debug, Clone)]
pub struct CumulativeTable {
    nj: usize,
    nd: usize,
    stride: usize,
    data: Vec<f64>,
    mid: Vec<f64>,
    locator: Locator,
}

fn binom(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// a·b as an unevaluated sum hi + lo (Dekker's TwoProduct by Veltkamp splitting: exact,
/// no FMA needed).
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let split = |x: f64| {
        let c = 134_217_729.0 * x; // 2^27 + 1
        let hi = c - (c - x);
        (hi, x - hi)
    };
    let p = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// Σ a_i b_i as if in twice the working precision, then rounded (Ogita–Rump–Oishi Dot2): the
/// basis conversions below have integer weights up to 140 with alternating signs, whose
/// cancellation would otherwise cost up to ~10⁻¹³ in the derivative coefficients.
fn dot2(terms: impl Iterator<Item = (f64, f64)>) -> f64 {
    let (mut s, mut err) = (0.0, 0.0);
    for (a, b) in terms {
        let (p, pe) = two_product(a, b);
        let t = s + p;
        let z = t - s;
        err += ((s - (t - z)) + (p - z)) + pe;
        s = t;
    }
    s + err
}

/// Power coefficients in u of Σ c_l C(D,l) uˡ (1−u)^(D−l).
fn bernstein_to_power(c: &[f64]) -> Vec<f64> {
    let d = c.len() - 1;
    (0..=d)
        .map(|k| {
            dot2((0..=k).map(|l| {
                let sign = if (k - l) % 2 == 0 { 1.0 } else { -1.0 };
                (binom(d, l) * binom(d - l, k - l) * sign, c[l])
            }))
        })
        .collect()
}

/// Power coefficients in v = 1 − u of Σ p_k u^k.
fn reflect_power(p: &[f64]) -> Vec<f64> {
    (0..p.len())
        .map(|m| {
            let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
            sign * dot2((m..p.len()).map(|k| (binom(k, m), p[k])))
        })
        .collect()
}

impl CumulativeTable {
    /// Builds the table from the joints and, per segment, its form. None when the form has
    /// more than [`MAX_FACTORS`] factors or degree above [`MAX_DEGREE`] (or none at all).
    pub fn new(joints: &[f64], basis: Basis, mut form: impl FnMut(usize) -> SegmentForm) -> Option<Self> {
        let nseg = joints.len() - 1;
        let forms: Vec<SegmentForm> = (0..nseg).map(&mut form).collect();
        let nj = forms.iter().map(|f| f.factors.len()).max()?;
        let nd = forms.iter().flat_map(|f| f.factors.iter().map(|(_, c)| c.len().saturating_sub(1))).max()?;
        if nj == 0 || nj > MAX_FACTORS || nd > MAX_DEGREE {
            return None;
        }
        // a multiple of 4, so that records can be read 4 doubles at a time
        let stride = (6 + nj * (nd + 4)).next_multiple_of(4);
        let mut data = vec![0.0; 2 * nseg * stride];
        let mut mid = Vec::with_capacity(nseg);
        for (s, f) in forms.iter().enumerate() {
            let (t0, t1) = (joints[s], joints[s + 1]);
            let h = t1 - t0;
            mid.push(t0 + 0.5 * h);
            for half in 0..2 {
                let r = &mut data[(2 * s + half) * stride..(2 * s + half + 1) * stride];
                r[0] = if half == 0 { t0 } else { t1 };
                r[1] = if half == 0 { 1.0 / h } else { -1.0 / h };
                r[2..6].copy_from_slice(&f.base.to_wxyz());
                for (j, (ax, c)) in f.factors.iter().enumerate() {
                    let off = 6 + j * (nd + 4);
                    r[off..off + 3].copy_from_slice(&ax.n);
                    let lo = match basis {
                        Basis::Power => c.clone(),
                        Basis::Bernstein => bernstein_to_power(c),
                    };
                    let p = if half == 0 {
                        lo
                    } else {
                        match basis {
                            Basis::Power => reflect_power(&lo),
                            Basis::Bernstein => {
                                bernstein_to_power(&c.iter().rev().copied().collect::<Vec<_>>())
                            }
                        }
                    };
                    for (m, v) in p.iter().enumerate() {
                        r[off + 3 + m] = v * ax.a;
                    }
                }
                // factors beyond this segment's count stay zero: exp(0) = 1, exact
            }
        }
        Some(CumulativeTable { nj, nd, stride, data, mid, locator: Locator::new(joints) })
    }

    /// (factors, degree).
    pub fn shape(&self) -> (usize, usize) {
        (self.nj, self.nd)
    }
}

// ------------------------------------------------------------------------------- kernel

/// Where a vector's per-segment fields come from: one record for all lanes (broadcast) or
/// one per lane (gather).
trait Src<V: Lanes> {
    /// Field `off` of the lanes' records.
    unsafe fn get(&self, off: usize) -> V;
}

struct Bcast(*const f64);
impl<V: Lanes> Src<V> for Bcast {
    #[inline(always)]
    unsafe fn get(&self, off: usize) -> V {
        V::splat(*self.0.add(off))
    }
}

/// Records of the lanes transposed into vectors (4×4 transposes of plain loads: cheaper than
/// one AVX2 gather per field).
struct Local<'a, V>(&'a [V]);
impl<V: Lanes> Src<V> for Local<'_, V> {
    #[inline(always)]
    unsafe fn get(&self, off: usize) -> V {
        *self.0.get_unchecked(off)
    }
}

/// The largest record (MAX_FACTORS, MAX_DEGREE), rounded up to a multiple of 4.
const MAX_STRIDE: usize = (6 + MAX_FACTORS * (MAX_DEGREE + 4)).next_multiple_of(4);

type V3<V> = [V; 3];
type Q4<V> = [V; 4];

#[inline(always)]
pub(super) fn qmul<V: Lanes>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [
        a[3].fnma(b[3], a[2].fnma(b[2], a[1].fnma(b[1], a[0] * b[0]))),
        a[3].fnma(b[2], a[2].fma(b[3], a[1].fma(b[0], a[0] * b[1]))),
        a[3].fma(b[1], a[2].fma(b[0], a[1].fnma(b[3], a[0] * b[2]))),
        a[3].fma(b[0], a[2].fnma(b[1], a[1].fma(b[2], a[0] * b[3]))),
    ]
}

/// q ⊗ (0, v).
#[inline(always)]
fn qmul_pure<V: Lanes>(a: Q4<V>, v: V3<V>) -> Q4<V> {
    [
        a[3].fnma(v[2], a[2].fnma(v[1], -(a[1] * v[0]))),
        a[3].fnma(v[1], a[2].fma(v[2], a[0] * v[0])),
        a[3].fma(v[0], a[1].fnma(v[2], a[0] * v[1])),
        a[2].fnma(v[0], a[1].fma(v[1], a[0] * v[2])),
    ]
}

#[inline(always)]
pub(super) fn cross<V: Lanes>(a: V3<V>, b: V3<V>) -> V3<V> {
    [a[2].fnma(b[1], a[1] * b[2]), a[0].fnma(b[2], a[2] * b[0]), a[1].fnma(b[0], a[0] * b[1])]
}

#[inline(always)]
fn add3<V: Lanes>(a: V3<V>, b: V3<V>) -> V3<V> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
fn sub3<V: Lanes>(a: V3<V>, b: V3<V>) -> V3<V> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn scale3<V: Lanes>(a: V3<V>, s: V) -> V3<V> {
    [a[0] * s, a[1] * s, a[2] * s]
}

#[inline(always)]
fn add4<V: Lanes>(a: Q4<V>, b: Q4<V>) -> Q4<V> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
}

#[inline(always)]
fn scale4<V: Lanes>(a: Q4<V>, s: V) -> Q4<V> {
    [a[0] * s, a[1] * s, a[2] * s, a[3] * s]
}

/// e* v e for e = (c, s n): v cos 2θ − sin 2θ (n × v) + (1 − cos 2θ)(n·v) n, given
/// s2 = sin 2θ, c2 = cos 2θ, omc = 1 − cos 2θ. (Written as functions, not closures: a closure
/// would not inherit the caller's `target_feature`, and its vector operations would be calls.)
#[inline(always)]
fn rot_axis<V: Lanes>(n: V3<V>, s2: V, c2: V, omc: V, v: V3<V>) -> V3<V> {
    let cr = cross(n, v);
    let k = omc * n[2].fma(v[2], n[1].fma(v[1], n[0] * v[0]));
    [
        k.fma(n[0], s2.fnma(cr[0], c2 * v[0])),
        k.fma(n[1], s2.fnma(cr[1], c2 * v[1])),
        k.fma(n[2], s2.fnma(cr[2], c2 * v[2])),
    ]
}

/// The vector rotated by the unit quaternion q: x + 2w (v × x) + 2 v × (v × x).
#[inline(always)]
pub(super) fn rotate<V: Lanes>(q: Q4<V>, x: V3<V>) -> V3<V> {
    let v = [q[1], q[2], q[3]];
    let c1 = cross(v, x);
    let c1 = add3(c1, c1);
    let c2 = cross(v, c1);
    [q[0].fma(c1[0], x[0]) + c2[0], q[0].fma(c1[1], x[1]) + c2[1], q[0].fma(c1[2], x[2]) + c2[2]]
}

/// Output kinds.
pub(super) const EVAL: u8 = 0;
pub(super) const BODY: u8 = 1;
pub(super) const WORLD: u8 = 2;

pub(super) const fn width(k: usize, out: u8) -> usize {
    if out == EVAL {
        4 * (k + 1)
    } else {
        3
    }
}

/// One vector of samples: the rows (up to 16 components) for lane times `tv`.
#[inline(always)]
unsafe fn block<V: Lanes, S: Src<V>, const K: usize, const OUT: u8>(
    nj: usize,
    nd: usize,
    src: &S,
    tv: V,
) -> [V; 16] {
    let zero = V::splat(0.0);
    let (tref, dvar) = (src.get(0), src.get(1));
    let x = (tv - tref) * dvar;
    let mut q: Q4<V> = [src.get(2), src.get(3), src.get(4), src.get(5)];
    let (mut w, mut a, mut jk) = ([zero; 3], [zero; 3], [zero; 3]);
    let (two, four, twelve) = (V::splat(2.0), V::splat(4.0), V::splat(12.0));
    for j in 0..nj {
        let off = 6 + j * (nd + 4);
        let n: V3<V> = [src.get(off), src.get(off + 1), src.get(off + 2)];
        // P, P', P''/2, P'''/6 at x by Horner
        let mut p0: V = src.get(off + 3 + nd);
        let (mut p1, mut p2, mut p3) = (zero, zero, zero);
        for m in (0..nd).rev() {
            if K >= 3 {
                p3 = p3.fma(x, p2);
            }
            if K >= 2 {
                p2 = p2.fma(x, p1);
            }
            if K >= 1 {
                p1 = p1.fma(x, p0);
            }
            p0 = p0.fma(x, src.get(off + 3 + m));
        }
        let (s, c) = p0.sin_cos();
        q = qmul(q, [c, s * n[0], s * n[1], s * n[2]]);
        if K == 0 {
            continue;
        }
        // ω_j = 2 θ' n, ω_j' = 2 θ'' n, ω_j'' = 2 θ''' n (θ^(m) = m! p_m dvar^m)
        let d1 = two * p1 * dvar;
        let om = scale3(n, d1);
        let omd = if K >= 2 { scale3(n, four * p2 * dvar * dvar) } else { [zero; 3] };
        let omdd = if K >= 3 { scale3(n, twelve * p3 * dvar * dvar * dvar) } else { [zero; 3] };
        if j == 0 {
            (w, a, jk) = (om, omd, omdd);
            continue;
        }
        // R_j(x) = e* x e: rotation by −2θ about n
        let s2 = two * s * c;
        let omc = two * s * s;
        let c2 = V::splat(1.0) - omc;
        let y = rot_axis(n, s2, c2, omc, w);
        if K >= 2 {
            let z = rot_axis(n, s2, c2, omc, a);
            let oy = cross(om, y);
            if K >= 3 {
                let v = rot_axis(n, s2, c2, omc, jk);
                let oz = cross(om, z);
                jk = add3(sub3(sub3(v, add3(oz, oz)), cross(omd, y)), add3(cross(om, oy), omdd));
            }
            a = add3(sub3(z, oy), omd);
        }
        w = add3(y, om);
    }
    let mut o = [zero; 16];
    match OUT {
        EVAL => {
            o[..4].copy_from_slice(&q);
            if K >= 1 {
                let half = V::splat(0.5);
                let q1 = scale4(qmul_pure(q, w), half);
                o[4..8].copy_from_slice(&q1);
                if K >= 2 {
                    let qa = qmul_pure(q, a);
                    let q1w = qmul_pure(q1, w);
                    let q2: Q4<V> = scale4(add4(q1w, qa), half);
                    o[8..12].copy_from_slice(&q2);
                    if K >= 3 {
                        let q2w = qmul_pure(q2, w);
                        let q1a = qmul_pure(q1, a);
                        let qj = qmul_pure(q, jk);
                        let q3: Q4<V> = scale4(add4(add4(q2w, add4(q1a, q1a)), qj), half);
                        o[12..16].copy_from_slice(&q3);
                    }
                }
            }
        }
        BODY => {
            let r = match K {
                1 => w,
                2 => a,
                _ => jk,
            };
            o[..3].copy_from_slice(&r);
        }
        _ => {
            let r = match K {
                1 => rotate(q, w),
                2 => rotate(q, a),
                // q j q* + (q ω q*) × (q α q*) = q (j + ω × α) q*: one rotation
                _ => rotate(q, add3(jk, cross(w, a))),
            };
            o[..3].copy_from_slice(&r);
        }
    }
    o
}

/// Every sample of the run: records by lane, broadcast when the lanes share one.
#[inline(always)]
unsafe fn run<V: Lanes, const K: usize, const OUT: u8>(
    tab: &CumulativeTable,
    nj: usize,
    nd: usize,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    let w = width(K, OUT);
    let n = t.len();
    let base = tab.data.as_ptr();
    let mut local = [V::splat(0.0); MAX_STRIDE];
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        // a full vector loads its times directly (4 scalar stores then a vector load would
        // miss store forwarding); the tail repeats its last sample
        let tv = if m == V::N {
            V::load(t.as_ptr().add(i))
        } else {
            let mut tl = [0.0; 4];
            for (l, x) in tl.iter_mut().enumerate().take(V::N) {
                *x = t[i + l.min(m - 1)];
            }
            V::load(tl.as_ptr())
        };
        // the common case first: every lane in the first lane's segment and half (no gather
        // of the midpoints)
        let s0 = seg[i] as usize;
        let mid0 = tab.mid[s0];
        let h0 = t[i] > mid0;
        let uniform = (1..V::N).all(|l| {
            let k = i + l.min(m - 1);
            seg[k] as usize == s0 && (t[k] > mid0) == h0
        });
        let o = if uniform {
            block::<V, _, K, OUT>(nj, nd, &Bcast(base.add((2 * s0 + h0 as usize) * tab.stride)), tv)
        } else {
            let mut rec = [0usize; 4];
            for (l, r) in rec.iter_mut().enumerate().take(V::N) {
                let k = i + l.min(m - 1);
                let s = seg[k] as usize;
                *r = 2 * s + (t[k] > tab.mid[s]) as usize;
            }
            let idx = [rec[0] * tab.stride, rec[1] * tab.stride, rec[2] * tab.stride, rec[3] * tab.stride];
            V::transpose_records(base, &idx, tab.stride, local.as_mut_ptr());
            block::<V, _, K, OUT>(nj, nd, &Local(&local[..tab.stride]), tv)
        };
        let rows = &mut out[i * w..(i + m) * w];
        if m == V::N && OUT == EVAL {
            for b in 0..=K {
                V::store_rows4(
                    [o[4 * b], o[4 * b + 1], o[4 * b + 2], o[4 * b + 3]],
                    rows.as_mut_ptr().add(4 * b),
                    w,
                );
            }
        } else {
            for (c, v) in o.iter().take(w).enumerate() {
                let a = v.to_array();
                for l in 0..m {
                    rows[l * w + c] = a[l];
                }
            }
        }
        i += m;
    }
}

/// `run` with the table's shape folded into constants for the common shapes.
#[inline(always)]
unsafe fn shaped<V: Lanes, const K: usize, const OUT: u8>(
    tab: &CumulativeTable,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    match (tab.nj, tab.nd) {
        (1, 1) => run::<V, K, OUT>(tab, 1, 1, seg, t, out),
        (3, 3) => run::<V, K, OUT>(tab, 3, 3, seg, t, out),
        (3, 7) => run::<V, K, OUT>(tab, 3, 7, seg, t, out),
        (7, 7) => run::<V, K, OUT>(tab, 7, 7, seg, t, out),
        (nj, nd) => run::<V, K, OUT>(tab, nj, nd, seg, t, out),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn shaped_avx2<const K: usize, const OUT: u8>(
    tab: &CumulativeTable,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    shaped::<super::lanes::Avx2, K, OUT>(tab, seg, t, out)
}

fn dispatch<const K: usize, const OUT: u8>(
    isa: Isa,
    tab: &CumulativeTable,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    assert!(seg.len() == t.len() && out.len() == t.len() * width(K, OUT), "cumulative kernel: bad lengths");
    assert!(seg.iter().all(|&s| (s as usize) < tab.mid.len()), "cumulative kernel: segment out of range");
    #[cfg(target_arch = "x86_64")]
    if isa == Isa::Avx2 && super::avx2_available() {
        // SAFETY: AVX2 and FMA detected; lengths and segment indices checked above.
        unsafe { shaped_avx2::<K, OUT>(tab, seg, t, out) };
        return;
    }
    let _ = isa;
    // SAFETY: lengths and segment indices checked above.
    unsafe { shaped::<f64, K, OUT>(tab, seg, t, out) }
}

impl BatchKernel for CumulativeTable {
    fn locator(&self) -> &Locator {
        &self.locator
    }

    fn evaluate(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool {
        match order {
            0 => dispatch::<0, EVAL>(isa, self, seg, t, out),
            1 => dispatch::<1, EVAL>(isa, self, seg, t, out),
            2 => dispatch::<2, EVAL>(isa, self, seg, t, out),
            _ => dispatch::<3, EVAL>(isa, self, seg, t, out),
        }
        true
    }

    fn angular(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, frame: Frame, out: &mut [f64]) -> bool {
        match (order, frame) {
            (1, Frame::Body) => dispatch::<1, BODY>(isa, self, seg, t, out),
            (2, Frame::Body) => dispatch::<2, BODY>(isa, self, seg, t, out),
            (_, Frame::Body) => dispatch::<3, BODY>(isa, self, seg, t, out),
            (1, Frame::World) => dispatch::<1, WORLD>(isa, self, seg, t, out),
            (2, Frame::World) => dispatch::<2, WORLD>(isa, self, seg, t, out),
            (_, Frame::World) => dispatch::<3, WORLD>(isa, self, seg, t, out),
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bernstein_and_reflection_round_trip() {
        // cumulative cubic Bernstein weight 1 − (1−u)³ = 3u − 3u² + u³
        assert_eq!(bernstein_to_power(&[0.0, 1.0, 1.0, 1.0]), vec![0.0, 3.0, -3.0, 1.0]);
        // in v = 1 − u: 1 − v³
        assert_eq!(reflect_power(&[0.0, 3.0, -3.0, 1.0]), vec![1.0, 0.0, 0.0, -1.0]);
    }
}
