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

use super::lanes::{Lanes, MAX_LANES, P2};
use super::quat_lanes::{add4, cross, dot3, qmul, qmul_pure, rot_axis, scale3, scale4, Q4, V3};
use super::{width, Kernel, Locator, BODY, EVAL, WORLD};
use crate::jet::Axis;
use crate::quat::Quat;

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
    /// The prefix of a record the value and body-frame kernels read (a multiple of 4): the
    /// world-frame axes come after it.
    vlen: usize,
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

/// The integer weights of the basis changes, tabulated once: `bern[d][k][l]` =
/// C(d,l) C(d−l,k−l) (−1)^(k−l) (the weight of c_l in the coefficient of u^k of a degree-d
/// Bernstein sum) and `binom[k][m]` = C(k,m). Products of small integers, exact: the table
/// holds the very numbers [`binom`] gives in place.
struct Weights {
    bern: [[[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1]; MAX_DEGREE + 1],
    binom: [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1],
}

fn weights() -> &'static Weights {
    static W: std::sync::OnceLock<Weights> = std::sync::OnceLock::new();
    W.get_or_init(|| {
        let mut w = Weights {
            bern: [[[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1]; MAX_DEGREE + 1],
            binom: [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1],
        };
        for d in 0..=MAX_DEGREE {
            for k in 0..=d {
                for l in 0..=k {
                    let sign = if (k - l) % 2 == 0 { 1.0 } else { -1.0 };
                    w.bern[d][k][l] = binom(d, l) * binom(d - l, k - l) * sign;
                }
            }
            for m in 0..=d {
                w.binom[d][m] = binom(d, m);
            }
        }
        w
    })
}

/// Power coefficients in u of Σ c_l C(D,l) uˡ (1−u)^(D−l), c read forwards (`rev` false) or
/// backwards, into `out[..=D]`.
fn bernstein_to_power(c: &[f64], rev: bool, out: &mut [f64]) {
    let d = c.len() - 1;
    let w = &weights().bern[d];
    let at = |l: usize| if rev { c[d - l] } else { c[l] };
    for (k, o) in out[..=d].iter_mut().enumerate() {
        *o = dot2((0..=k).map(|l| (w[k][l], at(l))));
    }
}

/// Power coefficients in v = 1 − u of Σ p_k u^k, into `out[..p.len()]`.
fn reflect_power(p: &[f64], out: &mut [f64]) {
    let b = &weights().binom;
    for (m, o) in out[..p.len()].iter_mut().enumerate() {
        let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
        *o = sign * dot2((m..p.len()).map(|k| (b[k][m], p[k])));
    }
}

/// Segments per parallel task when a table is built.
const BUILD_CHUNK: usize = 2048;

impl CumulativeTable {
    /// Builds the table from the joints and, per segment, its form. None when the form has
    /// more than [`MAX_FACTORS`] factors or degree above [`MAX_DEGREE`] (or none at all).
    pub fn new(joints: &[f64], basis: Basis, mut form: impl FnMut(usize) -> SegmentForm) -> Option<Self> {
        let nseg = joints.len() - 1;
        let forms: Vec<SegmentForm> = (0..nseg).map(&mut form).collect();
        let nj = forms.iter().map(|f| f.factors.len()).max()?;
        let nd = forms.iter().flat_map(|f| f.factors.iter().map(|(_, c)| c.len().saturating_sub(1))).max()?;
        Self::with_shape(joints, basis, nj, nd, |s, out| {
            out.extend(forms[s].factors.iter().map(|(a, c)| (*a, c.as_slice())));
            forms[s].base
        })
    }

    /// As [`CumulativeTable::new`] for a caller that knows the shape (at most `nj` factors of
    /// degree at most `nd` in every segment): `form(s, factors)` pushes segment s's factors
    /// (log, weight coefficients) and returns its base. No per-segment allocation; built in
    /// parallel for many segments (the same numbers as one thread).
    pub fn with_shape<'a>(
        joints: &[f64],
        basis: Basis,
        nj: usize,
        nd: usize,
        form: impl Fn(usize, &mut Vec<(Axis, &'a [f64])>) -> Quat + Sync,
    ) -> Option<Self> {
        use rayon::prelude::*;
        let nseg = joints.len() - 1;
        if nseg == 0 || nj == 0 || nj > MAX_FACTORS || nd > MAX_DEGREE {
            return None;
        }
        // multiples of 4, so that records can be read 4 doubles at a time
        let vlen = (6 + nj * (nd + 4)).next_multiple_of(4);
        let stride = (vlen + 3 * nj).next_multiple_of(4);
        let mut data = super::table_buffer(2 * nseg * stride);
        let fill = |factors: &mut Vec<(Axis, &'a [f64])>, s: usize, rec: &mut [f64]| -> bool {
            factors.clear();
            let base = form(s, factors);
            if factors.len() > nj || factors.iter().any(|(_, c)| c.len() > nd + 1) {
                return false;
            }
            let (t0, t1) = (joints[s], joints[s + 1]);
            let h = t1 - t0;
            let (r0, r1) = rec.split_at_mut(stride);
            r0[0] = t0;
            r0[1] = 1.0 / h;
            r1[0] = t1;
            r1[1] = -1.0 / h;
            let b = base.to_wxyz();
            r0[2..6].copy_from_slice(&b);
            r1[2..6].copy_from_slice(&b);
            let (mut lo, mut hi) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
            for (j, (ax, c)) in factors.iter().enumerate() {
                let off = 6 + j * (nd + 4);
                let len = c.len();
                match basis {
                    Basis::Power => {
                        lo[..len].copy_from_slice(c);
                        reflect_power(c, &mut hi);
                    }
                    Basis::Bernstein => {
                        bernstein_to_power(c, false, &mut lo);
                        bernstein_to_power(c, true, &mut hi);
                    }
                }
                // the axis in the world frame, q_s n q_s* (the world-frame rate recursion)
                let mw = base.rotate(ax.n);
                for (r, p) in [(&mut *r0, &lo), (&mut *r1, &hi)] {
                    r[off..off + 3].copy_from_slice(&ax.n);
                    for (m, v) in p[..len].iter().enumerate() {
                        r[off + 3 + m] = v * ax.a;
                    }
                    r[vlen + 3 * j..vlen + 3 * j + 3].copy_from_slice(&mw);
                }
            }
            // factors beyond this segment's count stay zero: exp(0) = 1, exact
            true
        };
        let ok = data
            .par_chunks_mut(2 * stride * BUILD_CHUNK)
            .enumerate()
            .map(|(c, block)| {
                let mut factors = Vec::with_capacity(nj);
                block
                    .chunks_mut(2 * stride)
                    .enumerate()
                    .all(|(i, rec)| fill(&mut factors, c * BUILD_CHUNK + i, rec))
            })
            .collect::<Vec<bool>>()
            .into_iter()
            .all(|b| b);
        if !ok {
            return None;
        }
        let mid = joints.windows(2).map(|w| w[0] + 0.5 * (w[1] - w[0])).collect();
        Some(CumulativeTable { nj, nd, stride, vlen, data, mid, locator: Locator::new(joints) })
    }

    /// (factors, degree).
    pub fn shape(&self) -> (usize, usize) {
        (self.nj, self.nd)
    }
}

// ------------------------------------------------------------------------------- kernel

/// (π/4)², the largest (θ/2)² [`half_angle_sin_cos`] takes (a hair above it is as accurate).
const HALF_ANGLE_Z: f64 = 0.616_850_275_068_084_9;

#[inline(always)]
fn k<V: Lanes>(c: f64) -> V {
    V::splat(c)
}

/// (sin θ, cos θ, (θ/2)²), cheaper than the general vector sin/cos where |θ| ≤ π/2 (every
/// angle of the B-spline and Beta weights, which lie in [0, 1], times a log's half-angle
/// ≤ π/2): fdlibm's kernels at h = θ/2 (|h| ≤ π/4: no reduction, no quadrant), then
/// sin θ = 2 sin h cos h and cos θ = 1 − 2 sin² h (one rounding), within a few ulp or
/// 2⁻⁵² absolutely (where cos θ is small). The caller replaces lanes beyond (θ/2)² ≤ [`HALF_ANGLE_Z`] lane by lane
/// (so each lane's result depends on its angle alone); NaN stays NaN.
#[inline(always)]
fn half_angle_sin_cos<V: Lanes>(x: V) -> (V, V, V) {
    use crate::special::{COS_KERNEL as C, SIN_KERNEL as S};
    let (one, half) = (k::<V>(1.0), k::<V>(0.5));
    let h = x * half;
    let z = h * h;
    let mut ps = z.fma(k(S[5]), k(S[4]));
    ps = z.fma(ps, k(S[3]));
    ps = z.fma(ps, k(S[2]));
    ps = z.fma(ps, k(S[1]));
    ps = z.fma(ps, k(S[0]));
    let sn = (h * z).fma(ps, h);
    let mut pc = z.fma(k(C[5]), k(C[4]));
    pc = z.fma(pc, k(C[3]));
    pc = z.fma(pc, k(C[2]));
    pc = z.fma(pc, k(C[1]));
    pc = z.fma(pc, k(C[0]));
    let hz = half * z;
    let w = one - hz;
    let cs = w + (z * z).fma(pc, (one - w) - hz);
    let s2 = sn + sn;
    (s2 * cs, s2.fnma(sn, one), z)
}

/// `sc` with the lanes whose (θ/2)² exceeds [`HALF_ANGLE_Z`] replaced by the general vector
/// sin/cos of θ.
#[inline(always)]
fn wide_sin_cos<V: Lanes>(x: V, (s, c): (V, V)) -> (V, V) {
    let h = x * k::<V>(0.5);
    let z = h * h;
    let (gs, gc) = Lanes::sin_cos(x);
    let lim = k::<V>(HALF_ANGLE_Z);
    (lim.lt_select(z, gs, s), lim.lt_select(z, gc, c))
}

/// Whether any lane of `x` is above `b`.
#[inline(always)]
fn any_above<V: Lanes>(x: V, b: f64) -> bool {
    V::splat(b).any_lt(x)
}

/// Where the per-segment fields of a block's lanes come from: one record for all of them
/// (broadcast) or one per lane (transposed).
trait Src<A> {
    /// Field `off` of the lanes' records.
    unsafe fn get(&self, off: usize) -> A;
}

struct Bcast(*const f64);
impl<A: Lanes> Src<A> for Bcast {
    #[inline(always)]
    unsafe fn get(&self, off: usize) -> A {
        A::splat(*self.0.add(off))
    }
}

/// Records of the two vectors' lanes transposed into vectors (4×4 transposes of plain
/// loads: cheaper than one AVX2 gather per field).
struct Local2<'a, V>(&'a [V], &'a [V]);
impl<V: Lanes> Src<P2<V>> for Local2<'_, V> {
    #[inline(always)]
    unsafe fn get(&self, off: usize) -> P2<V> {
        P2(*self.0.get_unchecked(off), *self.1.get_unchecked(off))
    }
}

/// The largest record (MAX_FACTORS, MAX_DEGREE), rounded up to a multiple of 4.
const MAX_STRIDE: usize =
    ((6 + MAX_FACTORS * (MAX_DEGREE + 4)).next_multiple_of(4) + 3 * MAX_FACTORS).next_multiple_of(4);

/// The rate scalars of one factor, ω_j = a n, ω_j' = b n, ω_j'' = c n with a = 2θ', b = 2θ'',
/// c = 2θ''' (θ^(m) = m! p_m dvar^m), the orders K needs (the others zero).
#[inline(always)]
fn factor_rates<A: Lanes, const K: usize>(p: [A; 3], dvar: A) -> (A, A, A) {
    let zero = A::splat(0.0);
    let a = A::splat(2.0) * p[0] * dvar;
    let b = if K >= 2 { A::splat(4.0) * p[1] * dvar * dvar } else { zero };
    let c = if K >= 3 { A::splat(12.0) * p[2] * dvar * dvar * dvar } else { zero };
    (a, b, c)
}

/// One step of the rate recursion (module doc) with the factor's rates along its unit axis n,
/// ω_j = a n, ω_j' = b n, ω_j'' = c n, d = n·ω = n·y (the rotation is about n; n·ω is already
/// computed by [`rot_axis`]), and y = R_j(ω), z = R_j(α), v = R_j(j) already rotated;
/// `sg` = −1 for the body frame, +1 for the world frame (the mirrored recursion):
///   ω ← y + a n,  α ← z + sg a (n × y) + b n,
///   j ← v + 2 sg a (n × z) + sg b (n × y) + a² (d n − y) + c n
/// (ω_j × (ω_j × y) = a² n × (n × y) = a² (n (n·y) − y) for |n| = 1): two cross products
/// with the axis instead of four with scaled axes.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn rate_step<A: Lanes, const K: usize>(
    n: V3<A>,
    (a, b, c): (A, A, A),
    sg: f64,
    d: A,
    y: V3<A>,
    z: V3<A>,
    v: V3<A>,
) -> (V3<A>, V3<A>, V3<A>) {
    let w = [n[0].fma(a, y[0]), n[1].fma(a, y[1]), n[2].fma(a, y[2])];
    if K < 2 {
        return (w, z, v);
    }
    let u = cross(n, y);
    let sa = A::splat(sg) * a;
    let al =
        [n[0].fma(b, sa.fma(u[0], z[0])), n[1].fma(b, sa.fma(u[1], z[1])), n[2].fma(b, sa.fma(u[2], z[2]))];
    if K < 3 {
        return (w, al, v);
    }
    let r = cross(n, z);
    let sa2 = sa + sa;
    let sb = A::splat(sg) * b;
    let aa = a * a;
    let g = aa.fma(d, c);
    let mut jk = [A::splat(0.0); 3];
    for i in 0..3 {
        jk[i] = n[i].fma(g, aa.fnma(y[i], sb.fma(u[i], sa2.fma(r[i], v[i]))));
    }
    (w, al, jk)
}

/// One block of samples (a vector, or two in lockstep): the rows (up to 16 components) for
/// lane times `tv`. The angles of every factor first, then their sin/cos, then the products
/// and rate recursions: the serial chains see independent work to overlap.
#[inline(always)]
unsafe fn block<A: Lanes, S: Src<A>, const K: usize, const OUT: u8, const JM: usize>(
    nj: usize,
    nd: usize,
    src: &S,
    tv: A,
) -> [A; 16] {
    let zero = A::splat(0.0);
    let (tref, dvar) = (src.get(0), src.get(1));
    let x = (tv - tref) * dvar;
    // P, P', P''/2, P'''/6 at x by Horner, per factor
    let mut th = [zero; JM];
    let mut dp = [[zero; 3]; JM];
    for j in 0..nj {
        let off = 6 + j * (nd + 4) + 3;
        let mut p0: A = src.get(off + nd);
        let (mut p1, mut p2, mut p3) = (zero, zero, zero);
        // P^(k) is zero before step k, where its first Horner step is a copy (no fma of zeros)
        for i in 0..nd {
            if K >= 3 {
                p3 = if i >= 3 { p3.fma(x, p2) } else { p2 };
            }
            if K >= 2 {
                p2 = if i >= 2 { p2.fma(x, p1) } else { p1 };
            }
            if K >= 1 {
                p1 = if i >= 1 { p1.fma(x, p0) } else { p0 };
            }
            p0 = p0.fma(x, src.get(off + nd - 1 - i));
        }
        th[j] = p0;
        dp[j] = [p1, p2, p3];
    }
    let mut sc = [(zero, zero); JM];
    let mut zmax = zero;
    for j in 0..nj {
        let (s, c, z) = half_angle_sin_cos(th[j]);
        sc[j] = (s, c);
        zmax = zmax.max(z);
    }
    if any_above(zmax, HALF_ANGLE_Z) {
        // rare: some lane beyond ±π/2 (or not finite)
        for j in 0..nj {
            sc[j] = wide_sin_cos(th[j], sc[j]);
        }
    }
    let (one, two) = (A::splat(1.0), A::splat(2.0));
    let mut o = [zero; 16];
    if OUT == WORLD {
        // The world frame without q: with the world axes m_j = q_s n_j q_s* and
        // E_j = exp(θ_j m_j) = q_s e_j q_s*, q = E_1 ⋯ E_J q_s, so
        // ω_w = ω_1 + E_1 (ω_2 + E_2 (…) E_2*) E_1* (ω_j = 2θ_j' m_j): the body recursion
        // mirrored, from the last factor to the first, with d/dt E x E* = E x' E* + ω_j × E x E*.
        let mo = (6 + nj * (nd + 4)).next_multiple_of(4);
        let (mut w, mut a, mut jk) = ([zero; 3], [zero; 3], [zero; 3]);
        for jj in 0..nj {
            let j = nj - 1 - jj;
            let n: V3<A> = [src.get(mo + 3 * j), src.get(mo + 3 * j + 1), src.get(mo + 3 * j + 2)];
            let rt = factor_rates::<A, K>(dp[j], dvar);
            if jj == 0 {
                (w, a, jk) = (scale3(n, rt.0), scale3(n, rt.1), scale3(n, rt.2));
                continue;
            }
            let (s, c) = sc[j];
            // E x E*: rotation by +2θ about m
            let s2 = A::splat(-2.0) * s * c;
            let omc = two * s * s;
            let c2 = one - omc;
            let y = rot_axis(n, s2, c2, omc, w);
            let z = if K >= 2 { rot_axis(n, s2, c2, omc, a) } else { a };
            let v = if K >= 3 { rot_axis(n, s2, c2, omc, jk) } else { jk };
            (w, a, jk) = rate_step::<A, K>(n, rt, 1.0, dot3(n, w), y, z, v);
        }
        let r = match K {
            1 => w,
            2 => a,
            _ => jk,
        };
        o[..3].copy_from_slice(&r);
        return o;
    }
    let mut q: Q4<A> = [src.get(2), src.get(3), src.get(4), src.get(5)];
    let (mut w, mut a, mut jk) = ([zero; 3], [zero; 3], [zero; 3]);
    for j in 0..nj {
        let off = 6 + j * (nd + 4);
        let n: V3<A> = [src.get(off), src.get(off + 1), src.get(off + 2)];
        let (s, c) = sc[j];
        if OUT == EVAL {
            q = qmul(q, [c, s * n[0], s * n[1], s * n[2]]);
        }
        if K == 0 {
            continue;
        }
        let rt = factor_rates::<A, K>(dp[j], dvar);
        if j == 0 {
            (w, a, jk) = (scale3(n, rt.0), scale3(n, rt.1), scale3(n, rt.2));
            continue;
        }
        // R_j(x) = e* x e: rotation by −2θ about n
        let s2 = two * s * c;
        let omc = two * s * s;
        let c2 = one - omc;
        let y = rot_axis(n, s2, c2, omc, w);
        let z = if K >= 2 { rot_axis(n, s2, c2, omc, a) } else { a };
        let v = if K >= 3 { rot_axis(n, s2, c2, omc, jk) } else { jk };
        (w, a, jk) = rate_step::<A, K>(n, rt, -1.0, dot3(n, w), y, z, v);
    }
    if OUT == BODY {
        let r = match K {
            1 => w,
            2 => a,
            _ => jk,
        };
        o[..3].copy_from_slice(&r);
        return o;
    }
    o[..4].copy_from_slice(&q);
    if K >= 1 {
        let half = A::splat(0.5);
        let q1 = scale4(qmul_pure(q, w), half);
        o[4..8].copy_from_slice(&q1);
        if K >= 2 {
            let qa = qmul_pure(q, a);
            let q1w = qmul_pure(q1, w);
            let q2: Q4<A> = scale4(add4(q1w, qa), half);
            o[8..12].copy_from_slice(&q2);
            if K >= 3 {
                let q2w = qmul_pure(q2, w);
                let q1a = qmul_pure(q1, a);
                let qj = qmul_pure(q, jk);
                let q3: Q4<A> = scale4(add4(add4(q2w, add4(q1a, q1a)), qj), half);
                o[12..16].copy_from_slice(&q3);
            }
        }
    }
    o
}

/// Every sample of the run, a group of lanes at a time: the record broadcast when all lanes
/// share one segment and half, transposed per lane otherwise.
#[inline(always)]
unsafe fn run<V: Lanes, const K: usize, const OUT: u8, const JM: usize>(
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
    let stride = tab.stride;
    // the world-frame axes follow the fields the other kernels read
    let len = if OUT == WORLD { stride } else { tab.vlen };
    let zero = P2::<V>::splat(0.0);
    // transposed records (written before they are read: no 13 KB memset per call)
    let mut la = std::mem::MaybeUninit::<[V; MAX_STRIDE]>::uninit();
    let mut lb = std::mem::MaybeUninit::<[V; MAX_STRIDE]>::uninit();
    let (pa, pb) = (la.as_mut_ptr() as *mut V, lb.as_mut_ptr() as *mut V);
    let step = P2::<V>::N;
    let tp = t.as_ptr();
    let sp = seg.as_ptr();
    let op = out.as_mut_ptr();
    let mut i = 0;
    while i < n {
        let m = (n - i).min(step);
        let full = m == step;
        // a full group loads its times directly (scalar stores then a vector load would miss
        // store forwarding); a tail repeats its last sample
        let lane = |l: usize| i + l.min(m - 1);
        let tv = if full {
            P2::<V>::load(tp.add(i))
        } else {
            let mut tl = [0.0; MAX_LANES];
            for (l, x) in tl.iter_mut().enumerate().take(step) {
                *x = *tp.add(lane(l));
            }
            P2::<V>::load(tl.as_ptr())
        };
        // the common case first: every lane in the first lane's segment and half
        let s0 = *sp.add(i);
        let mid0 = *tab.mid.get_unchecked(s0 as usize);
        let h0 = *tp.add(i) > mid0;
        let mut odd = 0u32;
        if full {
            // a fixed trip count: compiled to a few vector compares
            for l in 1..step {
                odd |= (*sp.add(i + l) ^ s0) | ((*tp.add(i + l) > mid0) != h0) as u32;
            }
        } else {
            for l in 1..m {
                odd |= (*sp.add(i + l) ^ s0) | ((*tp.add(i + l) > mid0) != h0) as u32;
            }
        }
        let o = if odd == 0 {
            let rec = base.add((2 * s0 as usize + h0 as usize) * stride);
            block::<P2<V>, _, K, OUT, JM>(nj, nd, &Bcast(rec), tv)
        } else {
            let mut idx = [[0usize; MAX_LANES / 2]; 2];
            for l in 0..step {
                let k = lane(l);
                let s = *sp.add(k) as usize;
                idx[l / V::N][l % V::N] =
                    (2 * s + (*tp.add(k) > *tab.mid.get_unchecked(s)) as usize) * stride;
            }
            // `len` is a multiple of 4: the transposes initialise exactly the slices read
            V::transpose_records(base, &idx[0], len, pa);
            if step > V::N {
                V::transpose_records(base, &idx[1], len, pb);
            }
            let (fa, fb) = (std::slice::from_raw_parts(pa, len), std::slice::from_raw_parts(pb, len));
            block::<P2<V>, _, K, OUT, JM>(nj, nd, &Local2(fa, fb), tv)
        };
        let rows = op.add(i * w);
        if full && OUT == EVAL {
            for b in 0..=K {
                let c = 4 * b;
                P2::<V>::store_rows4([o[c], o[c + 1], o[c + 2], o[c + 3]], rows.add(c), w);
            }
        } else if full && OUT != EVAL && i + m < n {
            // rows of 3 written as rows of 4 in order, each spilling one number into the
            // next row (rewritten right after); not for the last group
            P2::<V>::store_rows4([o[0], o[1], o[2], zero], rows, 3);
        } else {
            for (c, v) in o.iter().take(w).enumerate() {
                let a = v.to_array();
                for (l, x) in a.iter().enumerate().take(m) {
                    *rows.add(l * w + c) = *x;
                }
            }
        }
        i += m;
    }
}

/// `run` on two vectors in lockstep ([`P2`]; measured in the release build: faster than one
/// vector for values and rates alike), with the table's shape folded into constants for the
/// common shapes.
#[inline(always)]
unsafe fn shaped<V: Lanes, const K: usize, const OUT: u8>(
    tab: &CumulativeTable,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    match (tab.nj, tab.nd) {
        // (the per-factor arrays sized to the shape: no memset of unused ones per block)
        (1, 1) => run::<V, K, OUT, 1>(tab, 1, 1, seg, t, out),
        (3, 3) => run::<V, K, OUT, 3>(tab, 3, 3, seg, t, out),
        (3, 7) => run::<V, K, OUT, 3>(tab, 3, 7, seg, t, out),
        (7, 7) => run::<V, K, OUT, 7>(tab, 7, 7, seg, t, out),
        (nj, nd) => run::<V, K, OUT, MAX_FACTORS>(tab, nj, nd, seg, t, out),
    }
}

impl Kernel for CumulativeTable {
    const NAME: &'static str = "cumulative";
    const ORDERS: usize = 3;
    const RATES: bool = true;
    const WIDE_REGISTERS: bool = false;
    fn locator(&self) -> &Locator {
        &self.locator
    }
    fn segments(&self) -> usize {
        self.mid.len()
    }
    #[inline(always)]
    unsafe fn body<L: Lanes, const K: usize, const OUT: u8>(&self, seg: &[u32], t: &[f64], out: &mut [f64]) {
        shaped::<L, K, OUT>(self, seg, t, out)
    }
}

/// The factors' (sin θ, cos θ) as the kernels compute them ([`half_angle_sin_cos`], then
/// [`wide_sin_cos`] when a lane is beyond ±π/2), vectors of `x` in order (for the accuracy
/// tests).
#[cfg(test)]
fn factor_sin_cos_slice(isa: super::Isa, x: &[f64], s: &mut [f64], c: &mut [f64]) {
    struct Factor;
    impl super::LaneFn for Factor {
        #[inline(always)]
        fn apply<A: Lanes>(&self, x: A, _: A) -> (A, A) {
            let (s, c, z) = half_angle_sin_cos(x);
            if any_above(z, HALF_ANGLE_Z) {
                wide_sin_cos(x, (s, c))
            } else {
                (s, c)
            }
        }
    }
    let f = super::Elementwise { x, y: &[], pad: (0.0, 0.0), out: (s, Some(c)), f: Factor };
    // SAFETY: the lengths are the caller's (equal).
    unsafe { super::dispatch(isa, false, f) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::Isa;

    /// The half-angle sin/cos against libm over the angles the factors meet (and beyond ±π/2,
    /// where lanes take the general kernel), lane by lane: each lane's result is the same
    /// whatever its neighbours are.
    #[test]
    fn factor_sin_cos_accurate_and_lane_independent() {
        let mut x: Vec<f64> = (0..200_001).map(|i| -4.0 + 8.0 * i as f64 / 200_000.0).collect();
        let h = std::f64::consts::FRAC_PI_2;
        x.extend([h, -h, h.next_up(), (-h).next_down(), h.next_down(), 0.0, -0.0, 1e-300, 30.0, -1e6]);
        for isa in [Isa::Scalar, Isa::Avx2, Isa::Avx512].into_iter().filter(|i| i.available()) {
            let (mut s, mut c) = (vec![0.0; x.len()], vec![0.0; x.len()]);
            factor_sin_cos_slice(isa, &x, &mut s, &mut c);
            for i in 0..x.len() {
                let (rs, rc) = x[i].sin_cos();
                // a few ulp, or 2⁻⁵² absolutely where cos θ = 1 − 2 sin² h cancels
                for (a, b) in [(s[i], rs), (c[i], rc)] {
                    let tol = 4.0 * f64::EPSILON * b.abs() + 2.0 * f64::EPSILON;
                    assert!((a - b).abs() <= tol.max(f64::EPSILON), "{isa:?} {}: {a} vs {b}", x[i]);
                }
                // alone (all lanes equal) the same bits
                let (mut s1, mut c1) = ([0.0; 4], [0.0; 4]);
                factor_sin_cos_slice(isa, &[x[i]; 4], &mut s1, &mut c1);
                assert!(
                    s1[0].to_bits() == s[i].to_bits() && c1[0].to_bits() == c[i].to_bits(),
                    "{isa:?} {}",
                    x[i]
                );
            }
            let (mut s, mut c) = ([0.0; 4], [0.0; 4]);
            factor_sin_cos_slice(isa, &[f64::NAN, f64::INFINITY, 0.5, 3.0], &mut s, &mut c);
            assert!(s[0].is_nan() && c[0].is_nan() && s[1].is_nan() && c[1].is_nan());
            assert!(
                (s[3] - 3f64.sin()).abs() <= 1e-16 && (c[2] - 0.5f64.cos()).abs() <= 2e-16,
                "{s:?} {c:?}"
            );
        }
    }

    #[test]
    fn bernstein_and_reflection_round_trip() {
        // cumulative cubic Bernstein weight 1 − (1−u)³ = 3u − 3u² + u³
        let mut p = [0.0; 4];
        bernstein_to_power(&[0.0, 1.0, 1.0, 1.0], false, &mut p);
        assert_eq!(p, [0.0, 3.0, -3.0, 1.0]);
        // read backwards: 1 − u³, the weight's reflection
        bernstein_to_power(&[0.0, 1.0, 1.0, 1.0], true, &mut p);
        assert_eq!(p, [1.0, 0.0, 0.0, -1.0]);
        // in v = 1 − u: 1 − v³
        reflect_power(&[0.0, 3.0, -3.0, 1.0], &mut p);
        assert_eq!(p, [1.0, 0.0, 0.0, -1.0]);
    }

    #[test]
    fn tabulated_weights_are_the_binomials_computed_in_place() {
        let w = weights();
        for d in 0..=MAX_DEGREE {
            for k in 0..=d {
                assert_eq!(w.binom[d][k], binom(d, k));
                for l in 0..=k {
                    let sign = if (k - l) % 2 == 0 { 1.0 } else { -1.0 };
                    assert_eq!(w.bern[d][k][l], binom(d, l) * binom(d - l, k - l) * sign);
                }
            }
        }
    }
}
