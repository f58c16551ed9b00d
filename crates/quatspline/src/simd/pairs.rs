//! Independent pairs through the batch machinery: `slerp` of rows q0\[i\], q1\[i\] at t\[i\],
//! four pairs per AVX2 vector (rows transposed in, results transposed out), two vectors in
//! lockstep (`P2`: the square root, atan2, sin/cos and division chains of one overlap the
//! other's), the same lanes, vector sin/cos and atan2 as the spline kernels.
//!
//! Each row equals [`crate::interp::slerp`] of the normalised keys (within the kernels' 1e-14
//! bound; exactly q0 at t = 0 and the shortest-path q1 at t = 1): θ = atan2(|r|, q0·q1) with
//! r = q1 − (q0·q1) q0, result q0 cos tθ + r sin tθ / |r| (q0 where r = 0). A vector with a
//! key whose squared norm lies outside [1e-290, 1e290] (zero, denormal or huge keys: the
//! scalar normalisation scales first, or reports the zero key) or, with `long_path`, a pair
//! on opposite hemispheres (the scalar path's antipodal rules) is done row by row by the
//! scalar function; results are a function of each row alone, so they are bit-identical for
//! any chunking.

use super::lanes::{Lanes, MAX_LANES, P2};
use super::quat_lanes::{add4, conj, dot4, norm2_plain, normalize, qmul, Q4};
use super::{dispatch, Isa, OnLanes};
use crate::dual_quat::DualQuat;
use crate::error::{Error, Result};
use crate::quat::Quat;

/// One row by the scalar path (the reference).
fn scalar_row(q0: &[f64], q1: &[f64], t: &[f64], i: usize, long_path: bool) -> Result<[f64; 4]> {
    let a = Quat::from_wxyz(q0[4 * i..4 * i + 4].try_into().expect("row of 4"))
        .try_normalize()
        .map_err(|_| Error::ZeroNorm { arg: "q0", index: i })?;
    let b = Quat::from_wxyz(q1[4 * i..4 * i + 4].try_into().expect("row of 4"))
        .try_normalize()
        .map_err(|_| Error::ZeroNorm { arg: "q1", index: i })?;
    Ok(crate::interp::slerp(a, b, t[i], long_path).to_wxyz())
}

/// The scalar reference of [`slerp_pairs`]: `interp::slerp` row by row.
pub fn slerp_pairs_reference(
    q0: &[f64],
    q1: &[f64],
    t: &[f64],
    long_path: bool,
    out: &mut [f64],
) -> Result<()> {
    check(q0, q1, t, out);
    for i in 0..t.len() {
        out[4 * i..4 * i + 4].copy_from_slice(&scalar_row(q0, q1, t, i, long_path)?);
    }
    Ok(())
}

fn check(q0: &[f64], q1: &[f64], t: &[f64], out: &[f64]) {
    let n = t.len();
    assert!(q0.len() == 4 * n && q1.len() == 4 * n && out.len() == 4 * n, "slerp_pairs: bad lengths");
}

/// Per lane `if a == b { x } else { y }` (no NaN here).
#[inline(always)]
fn eq_select<V: Lanes>(a: V, b: V, x: V, y: V) -> V {
    a.lt_select(b, y, b.lt_select(a, y, x))
}

/// The slerp rows of the lanes (keys as loaded): the results, q0·q1 of the normalised keys
/// (before the hemisphere flip) and the keys' squared norms, for the caller's checks.
#[inline(always)]
fn slerp_lanes<V: Lanes>(a: Q4<V>, b: Q4<V>, tv: V, long_path: bool) -> (Q4<V>, V, V, V) {
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    let (na, nb) = (norm2_plain(a), norm2_plain(b));
    let a = normalize(a, na);
    let mut b = normalize(b, nb);
    // q0·q1 as `Quat::dot` sums it: the hemisphere test sees the scalar path's sign
    let mut d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    let d_in = d;
    if !long_path {
        let neg = d.lt_select(zero, -one, one);
        b = [b[0] * neg, b[1] * neg, b[2] * neg, b[3] * neg];
        d = d * neg;
    }
    let r: Q4<V> = [d.fnma(a[0], b[0]), d.fnma(a[1], b[1]), d.fnma(a[2], b[2]), d.fnma(a[3], b[3])];
    let s = dot4(r, r).sqrt();
    let th = s.atan2(d);
    let (st, ct) = (tv * th).sin_cos();
    let w = zero.lt_select(s, st / s, tv);
    let mut o: Q4<V> =
        [r[0].fma(w, a[0] * ct), r[1].fma(w, a[1] * ct), r[2].fma(w, a[2] * ct), r[3].fma(w, a[3] * ct)];
    for c in 0..4 {
        // exact ends: q0 at t = 0, the (flipped) q1 at t = 1
        o[c] = eq_select(tv, zero, a[c], eq_select(tv, one, b[c], o[c]));
    }
    (o, d_in, na, nb)
}

#[inline(always)]
unsafe fn run<V: Lanes>(q0: &[f64], q1: &[f64], t: &[f64], long_path: bool, out: &mut [f64]) -> Result<()> {
    let n = t.len();
    let w = 2 * V::N;
    let (lo, hi) = (<V as Lanes>::splat(1e-290), <V as Lanes>::splat(1e290));
    let zero = <V as Lanes>::splat(0.0);
    let mut i = 0;
    while i < n {
        // two vectors in lockstep; full blocks read the rows in place, a tail is padded with
        // copies of its last row
        let m = (n - i).min(w);
        let (mut pa, mut pb, mut pt) = ([0.0; 4 * MAX_LANES], [0.0; 4 * MAX_LANES], [0.0; MAX_LANES]);
        let (ap, bp, tp) = if m == w {
            (q0.as_ptr().add(4 * i), q1.as_ptr().add(4 * i), t.as_ptr().add(i))
        } else {
            for l in 0..w {
                let k = i + l.min(m - 1);
                pa[4 * l..4 * l + 4].copy_from_slice(&q0[4 * k..4 * k + 4]);
                pb[4 * l..4 * l + 4].copy_from_slice(&q1[4 * k..4 * k + 4]);
                pt[l] = t[k];
            }
            (pa.as_ptr(), pb.as_ptr(), pt.as_ptr())
        };
        let idx: [usize; MAX_LANES / 2] = std::array::from_fn(|l| 4 * l);
        let mut f = [[zero; 4]; 4];
        for (h, fh) in f.iter_mut().enumerate() {
            let src = if h < 2 { ap } else { bp };
            V::transpose_records(src.add(4 * V::N * (h % 2)), &idx, 4, fh.as_mut_ptr());
        }
        let p = |x: [V; 4], y: [V; 4]| [P2(x[0], y[0]), P2(x[1], y[1]), P2(x[2], y[2]), P2(x[3], y[3])];
        let tv = P2(V::load(tp), V::load(tp.add(V::N)));
        let (o, d_in, na, nb) = slerp_lanes(p(f[0], f[1]), p(f[2], f[3]), tv, long_path);
        let rows = &mut out[4 * i..4 * (i + m)];
        let halves = [[o[0].0, o[1].0, o[2].0, o[3].0], [o[0].1, o[1].1, o[2].1, o[3].1]];
        if m == w {
            V::store_rows4(halves[0], rows.as_mut_ptr(), 4);
            V::store_rows4(halves[1], rows.as_mut_ptr().add(4 * V::N), 4);
        } else {
            for (h, half) in halves.iter().enumerate() {
                for (c, v) in half.iter().enumerate() {
                    let x = v.to_array();
                    for l in 0..V::N.min(m.saturating_sub(h * V::N)) {
                        rows[4 * (h * V::N + l) + c] = x[l];
                    }
                }
            }
        }
        // lanes the vector formula does not cover go through the scalar path, lane by lane
        // (so that no row depends on its neighbours)
        for (h, (na, nb, d)) in [(na.0, nb.0, d_in.0), (na.1, nb.1, d_in.1)].into_iter().enumerate() {
            let rare = <V as Lanes>::any_lt(na, lo)
                || <V as Lanes>::any_lt(hi, na)
                || <V as Lanes>::any_lt(nb, lo)
                || <V as Lanes>::any_lt(hi, nb)
                || (long_path && <V as Lanes>::any_lt(d, zero));
            if !rare {
                continue;
            }
            let (na, nb, dd) = (na.to_array(), nb.to_array(), d.to_array());
            for l in 0..V::N.min(m.saturating_sub(h * V::N)) {
                let ok = |x: f64| (1e-290..=1e290).contains(&x);
                if !ok(na[l]) || !ok(nb[l]) || (long_path && dd[l] < 0.0) {
                    let k = h * V::N + l;
                    rows[4 * k..4 * k + 4].copy_from_slice(&scalar_row(q0, q1, t, i + k, long_path)?);
                }
            }
        }
        i += m;
    }
    Ok(())
}

/// slerp of independent pairs: rows of 4 in `q0`, `q1` (any nonzero norm; normalised as
/// `Quat::try_normalize` does), parameters `t` (finite, validated by the caller), rows of 4
/// out. Errors name the first zero key (`q0`/`q1` and its row).
pub fn slerp_pairs(
    isa: Isa,
    q0: &[f64],
    q1: &[f64],
    t: &[f64],
    long_path: bool,
    out: &mut [f64],
) -> Result<()> {
    check(q0, q1, t, out);
    // SAFETY: lengths checked above.
    unsafe { dispatch(isa, false, SlerpPairs { q0, q1, t, long_path, out }) }
}

struct SlerpPairs<'a> {
    q0: &'a [f64],
    q1: &'a [f64],
    t: &'a [f64],
    long_path: bool,
    out: &'a mut [f64],
}

impl OnLanes for SlerpPairs<'_> {
    type Out = Result<()>;
    #[inline(always)]
    unsafe fn run<L: Lanes>(self) -> Result<()> {
        run::<L>(self.q0, self.q1, self.t, self.long_path, self.out)
    }
}

// ------------------------------------------------------------------------------- sclerp

fn unit_dq(rows: &[f64], i: usize, arg: &'static str) -> Result<DualQuat> {
    DualQuat::from_array(rows[8 * i..8 * i + 8].try_into().expect("row of 8"))
        .try_normalize()
        .map_err(|_| Error::ZeroNorm { arg, index: i })
}

fn sclerp_row(a: &[f64], b: &[f64], t: &[f64], i: usize) -> Result<[f64; 8]> {
    Ok(crate::interp::sclerp(unit_dq(a, i, "dq0")?, unit_dq(b, i, "dq1")?, t[i]).to_array())
}

/// The scalar reference of [`sclerp_pairs`]: `interp::sclerp` row by row.
pub fn sclerp_pairs_reference(a: &[f64], b: &[f64], t: &[f64], out: &mut [f64]) -> Result<()> {
    check8(a, b, t, out);
    for i in 0..t.len() {
        out[8 * i..8 * i + 8].copy_from_slice(&sclerp_row(a, b, t, i)?);
    }
    Ok(())
}

fn check8(a: &[f64], b: &[f64], t: &[f64], out: &[f64]) {
    let n = t.len();
    assert!(a.len() == 8 * n && b.len() == 8 * n && out.len() == 8 * n, "sclerp_pairs: bad lengths");
}

/// `DualQuat::try_normalize` (r with the bits of `Quat::try_normalize`, d/|r| made
/// orthogonal to r) for squared norms of r in [1e-290, 1e290].
#[inline(always)]
fn unit_dual<V: Lanes>(r: Q4<V>, d: Q4<V>, n2: V) -> (Q4<V>, Q4<V>) {
    let ru = normalize(r, n2);
    let k = V::splat(1.0) / n2.sqrt();
    let d = [d[0] * k, d[1] * k, d[2] * k, d[3] * k];
    let p = dot4(ru, d);
    (ru, [p.fnma(ru[0], d[0]), p.fnma(ru[1], d[1]), p.fnma(ru[2], d[2]), p.fnma(ru[3], d[3])])
}

/// `DualQuat::powf` of a unit dual quaternion with r_w ≥ 0: the screw power by its
/// parameters (half angle h = atan2(|v|, w), axis u = v/|v|, translation t = 2 vec(d r*)):
/// real part (cos sh, sin sh · u), dual part (−½ s (u·t) sin sh, m + ½ s (u·t) cos sh · u)
/// with m = ½ (sin sh (t × u) + (t − (u·t) u) sin(sh)/sin(h) cos h); at |v| = 0 the pure
/// translation (1, 0) + ε (0, ½ s t).
#[inline(always)]
fn screw_power<V: Lanes>(r: Q4<V>, d: Q4<V>, s: V) -> (Q4<V>, Q4<V>) {
    let zero = V::splat(0.0);
    let (half, one) = (V::splat(0.5), V::splat(1.0));
    let dr = qmul(d, conj(r));
    let t = [dr[1] + dr[1], dr[2] + dr[2], dr[3] + dr[3]];
    let sn = r[3].fma(r[3], r[2].fma(r[2], r[1] * r[1])).sqrt();
    let h = sn.atan2(r[0]);
    let pos = |x: V, y: V| zero.lt_select(sn, x, y);
    let inv = pos(one / sn, zero);
    let u = [pos(r[1] * inv, one), r[2] * inv, r[3] * inv];
    let ut = u[2].fma(t[2], u[1].fma(t[1], u[0] * t[0]));
    let (sh, ch) = (s * h).sin_cos();
    // sin(sh)/sin(h) · cos h = sin(sh) w / |v| (|r| = 1); s at |v| = 0
    let ratio = pos(sh * r[0] * inv, s);
    let cr = [t[1] * u[2] - t[2] * u[1], t[2] * u[0] - t[0] * u[2], t[0] * u[1] - t[1] * u[0]];
    let hd = half * s * ut;
    let hdc = hd * ch;
    let mut dv = [zero; 3];
    for c in 0..3 {
        let m = half * cr[c].fma(sh, ratio * ut.fnma(u[c], t[c]));
        // pure translation (|v| = 0): ½ s t exactly
        dv[c] = pos(hdc.fma(u[c], m), half * s * t[c]);
    }
    ([ch, sh * u[0], sh * u[1], sh * u[2]], [-(hd * sh), dv[0], dv[1], dv[2]])
}

#[inline(always)]
unsafe fn run_sclerp<V: Lanes>(a8: &[f64], b8: &[f64], t: &[f64], out: &mut [f64]) -> Result<()> {
    let n = t.len();
    let (lo, hi) = (V::splat(1e-290), V::splat(1e290));
    let zero = V::splat(0.0);
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        let (mut pa, mut pb, mut pt) = ([0.0; 4 * MAX_LANES], [0.0; 4 * MAX_LANES], [0.0; MAX_LANES / 2]);
        let (ap, bp, tp) = if m == V::N {
            (a8.as_ptr().add(8 * i), b8.as_ptr().add(8 * i), t.as_ptr().add(i))
        } else {
            for l in 0..V::N {
                let k = i + l.min(m - 1);
                pa[8 * l..8 * l + 8].copy_from_slice(&a8[8 * k..8 * k + 8]);
                pb[8 * l..8 * l + 8].copy_from_slice(&b8[8 * k..8 * k + 8]);
                pt[l] = t[k];
            }
            (pa.as_ptr(), pb.as_ptr(), pt.as_ptr())
        };
        let idx: [usize; MAX_LANES / 2] = std::array::from_fn(|l| 8 * l);
        let (mut fa, mut fb) = ([zero; 8], [zero; 8]);
        V::transpose_records(ap, &idx, 8, fa.as_mut_ptr());
        V::transpose_records(bp, &idx, 8, fb.as_mut_ptr());
        let tv = V::load(tp);
        let (ar, ad) = ([fa[0], fa[1], fa[2], fa[3]], [fa[4], fa[5], fa[6], fa[7]]);
        let (br, bd) = ([fb[0], fb[1], fb[2], fb[3]], [fb[4], fb[5], fb[6], fb[7]]);
        let (na, nb) = (norm2_plain(ar), norm2_plain(br));
        let (ar, ad) = unit_dual(ar, ad, na);
        let (br, bd) = unit_dual(br, bd, nb);
        // rel = a* b, negated when its real w < 0 (w summed as the scalar product does, so the
        // shortest-screw choice is the scalar path's)
        let w = ar[0] * br[0] + ar[1] * br[1] + ar[2] * br[2] + ar[3] * br[3];
        let sg = w.lt_select(zero, V::splat(-1.0), V::splat(1.0));
        let rr = qmul(conj(ar), br);
        let rd = add4(qmul(conj(ar), bd), qmul(conj(ad), br));
        let rr = [w * sg, rr[1] * sg, rr[2] * sg, rr[3] * sg];
        let rd = [rd[0] * sg, rd[1] * sg, rd[2] * sg, rd[3] * sg];
        let (pr, pd) = screw_power(rr, rd, tv);
        let or = qmul(ar, pr);
        let od = add4(qmul(ar, pd), qmul(ad, pr));
        let rows = &mut out[8 * i..8 * (i + m)];
        if m == V::N {
            V::store_rows4(or, rows.as_mut_ptr(), 8);
            V::store_rows4(od, rows.as_mut_ptr().add(4), 8);
        } else {
            for (c, v) in or.iter().chain(od.iter()).enumerate() {
                let x = v.to_array();
                for l in 0..m {
                    rows[8 * l + c] = x[l];
                }
            }
        }
        if na.any_lt(lo) || hi.any_lt(na) || nb.any_lt(lo) || hi.any_lt(nb) {
            let (na, nb) = (na.to_array(), nb.to_array());
            for l in 0..m {
                let ok = |x: f64| (1e-290..=1e290).contains(&x);
                if !ok(na[l]) || !ok(nb[l]) {
                    rows[8 * l..8 * l + 8].copy_from_slice(&sclerp_row(a8, b8, t, i + l)?);
                }
            }
        }
        i += m;
    }
    Ok(())
}

/// ScLerp of independent pose pairs: rows of 8 (dual quaternions, normalised as
/// `DualQuat::try_normalize` does) in `a`, `b`, parameters `t`, rows of 8 out; equals
/// [`crate::interp::sclerp`] row by row within the kernels' bound. Errors name the first
/// zero rotation part (`dq0`/`dq1` and its row).
pub fn sclerp_pairs(isa: Isa, a: &[f64], b: &[f64], t: &[f64], out: &mut [f64]) -> Result<()> {
    check8(a, b, t, out);
    // SAFETY: lengths checked above.
    unsafe { dispatch(isa, false, SclerpPairs { a, b, t, out }) }
}

struct SclerpPairs<'a> {
    a: &'a [f64],
    b: &'a [f64],
    t: &'a [f64],
    out: &'a mut [f64],
}

impl OnLanes for SclerpPairs<'_> {
    type Out = Result<()>;
    #[inline(always)]
    unsafe fn run<L: Lanes>(self) -> Result<()> {
        run_sclerp::<L>(self.a, self.b, self.t, self.out)
    }
}
