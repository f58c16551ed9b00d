//! Independent pairs through the batch machinery: `slerp` of rows q0\[i\], q1\[i\] at t\[i\],
//! four pairs per AVX2 vector (rows transposed in, results transposed out), the same lanes,
//! vector sin/cos and atan2 as the spline kernels.
//!
//! Each row equals [`crate::interp::slerp`] of the normalised keys (within the kernels' 1e-14
//! bound; exactly q0 at t = 0 and the shortest-path q1 at t = 1): θ = atan2(|r|, q0·q1) with
//! r = q1 − (q0·q1) q0, result q0 cos tθ + r sin tθ / |r| (q0 where r = 0). A vector with a
//! key whose squared norm lies outside [1e-290, 1e290] (zero, denormal or huge keys: the
//! scalar normalisation scales first, or reports the zero key) or, with `long_path`, a pair
//! on opposite hemispheres (the scalar path's antipodal rules) is done row by row by the
//! scalar function; results are a function of each row alone, so they are bit-identical for
//! any chunking.

use super::lanes::{Lanes, LanesExt};
use super::Isa;
use crate::error::{Error, Result};
use crate::quat::Quat;

type Q4<V> = [V; 4];

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

#[inline(always)]
fn dot<V: Lanes>(a: Q4<V>, b: Q4<V>) -> V {
    a[3].fma(b[3], a[2].fma(b[2], a[1].fma(b[1], a[0] * b[0])))
}

/// q·q summed as `Quat::norm_squared` does (no FMA), so that the unit test below keeps the
/// same keys' bits as the scalar path.
#[inline(always)]
fn norm2_plain<V: Lanes>(q: Q4<V>) -> V {
    q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]
}

/// `Quat::try_normalize` of a key with a squared norm in [1e-290, 1e290]: the key as given
/// when |q·q − 1| ≤ 4ε, else (q/m)/|q/m| with m the largest |component| — the same
/// operations, so the same bits.
#[inline(always)]
fn unit<V: LanesExt>(q: Q4<V>, n2: V) -> Q4<V> {
    let one = V::splat(1.0);
    let dev = n2 - one;
    let tol = V::splat(4.0 * f64::EPSILON);
    // |dev| ≤ tol  ⇔  not (dev < −tol or tol < dev)
    if !(dev.any_lt(-tol) || tol.any_lt(dev)) {
        return q;
    }
    let zero = V::splat(0.0);
    let abs = |x: V| x.lt_select(zero, -x, x);
    let max = |a: V, b: V| a.lt_select(b, b, a);
    let m = max(max(max(abs(q[0]), abs(q[1])), abs(q[2])), abs(q[3]));
    let s = [q[0] / m, q[1] / m, q[2] / m, q[3] / m];
    let k = one / norm2_plain(s).sqrt();
    let keep = |c: usize| dev.lt_select(-tol, s[c] * k, tol.lt_select(dev, s[c] * k, q[c]));
    [keep(0), keep(1), keep(2), keep(3)]
}

/// Per lane `if a == b { x } else { y }` (no NaN here).
#[inline(always)]
fn eq_select<V: Lanes>(a: V, b: V, x: V, y: V) -> V {
    a.lt_select(b, y, b.lt_select(a, y, x))
}

#[inline(always)]
unsafe fn run<V: LanesExt>(
    q0: &[f64],
    q1: &[f64],
    t: &[f64],
    long_path: bool,
    out: &mut [f64],
) -> Result<()> {
    let n = t.len();
    let (lo, hi) = (V::splat(1e-290), V::splat(1e290));
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        // full vectors read the rows in place; a tail is padded with copies of its last row
        let (mut pa, mut pb, mut pt) = ([0.0; 16], [0.0; 16], [0.0; 4]);
        let (ap, bp, tp) = if m == V::N {
            (q0.as_ptr().add(4 * i), q1.as_ptr().add(4 * i), t.as_ptr().add(i))
        } else {
            for l in 0..4 {
                let k = i + l.min(m - 1);
                pa[4 * l..4 * l + 4].copy_from_slice(&q0[4 * k..4 * k + 4]);
                pb[4 * l..4 * l + 4].copy_from_slice(&q1[4 * k..4 * k + 4]);
                pt[l] = t[k];
            }
            (pa.as_ptr(), pb.as_ptr(), pt.as_ptr())
        };
        let idx = [0, 4, 8, 12];
        let mut a = [zero; 4];
        let mut b = [zero; 4];
        V::transpose_records(ap, &idx, 4, a.as_mut_ptr());
        V::transpose_records(bp, &idx, 4, b.as_mut_ptr());
        let tv = V::load(tp);
        let (na, nb) = (norm2_plain(a), norm2_plain(b));
        let a = unit(a, na);
        let mut b = unit(b, nb);
        // q0·q1 as `Quat::dot` sums it: the hemisphere test sees the scalar path's sign
        let mut d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
        let d_in = d;
        if !long_path {
            let neg = d.lt_select(zero, -one, one);
            b = [b[0] * neg, b[1] * neg, b[2] * neg, b[3] * neg];
            d = d * neg;
        }
        let rows = &mut out[4 * i..4 * (i + m)];
        let r: Q4<V> = [d.fnma(a[0], b[0]), d.fnma(a[1], b[1]), d.fnma(a[2], b[2]), d.fnma(a[3], b[3])];
        let s = dot(r, r).sqrt();
        let th = s.atan2(d);
        let (st, ct) = (tv * th).sin_cos();
        let w = zero.lt_select(s, st / s, tv);
        let mut o: Q4<V> =
            [r[0].fma(w, a[0] * ct), r[1].fma(w, a[1] * ct), r[2].fma(w, a[2] * ct), r[3].fma(w, a[3] * ct)];
        for c in 0..4 {
            // exact ends: q0 at t = 0, the (flipped) q1 at t = 1
            o[c] = eq_select(tv, zero, a[c], eq_select(tv, one, b[c], o[c]));
        }
        if m == V::N {
            V::store_rows4(o, rows.as_mut_ptr(), 4);
        } else {
            for (c, v) in o.iter().enumerate() {
                let x = v.to_array();
                for l in 0..m {
                    rows[4 * l + c] = x[l];
                }
            }
        }
        // lanes the vector formula does not cover go through the scalar path, lane by lane
        // (so that no row depends on its neighbours)
        let rare = na.any_lt(lo)
            || hi.any_lt(na)
            || nb.any_lt(lo)
            || hi.any_lt(nb)
            || (long_path && d_in.any_lt(zero));
        if rare {
            let (na, nb, dd) = (na.to_array(), nb.to_array(), d_in.to_array());
            for l in 0..m {
                let ok = |x: f64| (1e-290..=1e290).contains(&x);
                if !ok(na[l]) || !ok(nb[l]) || (long_path && dd[l] < 0.0) {
                    rows[4 * l..4 * l + 4].copy_from_slice(&scalar_row(q0, q1, t, i + l, long_path)?);
                }
            }
        }
        i += m;
    }
    Ok(())
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2(q0: &[f64], q1: &[f64], t: &[f64], long_path: bool, out: &mut [f64]) -> Result<()> {
    run::<super::lanes::Avx2>(q0, q1, t, long_path, out)
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
    #[cfg(target_arch = "x86_64")]
    if isa == Isa::Avx2 && super::avx2_available() {
        // SAFETY: AVX2 and FMA detected; lengths checked above.
        return unsafe { run_avx2(q0, q1, t, long_path, out) };
    }
    let _ = isa;
    // SAFETY: lengths checked above.
    unsafe { run::<f64>(q0, q1, t, long_path, out) }
}
