//! Batch kernels of the rotation-vector splines (natural spline, Hermite keys): segment i,
//! q(τ) = qᵢ e(s), e = exp(v), v(s) = Σₖ aₖ sᵏ (k = 1…5, cubic or quintic), s = τ − τᵢ, with
//! aₖ = cₖ/2 as the segments store them (one flat record of 24 doubles per segment).
//!
//! **Value.** e = (C(x), S(x) v) with x = |v|², C(x) = cos √x, S(x) = sin √x/√x: the vector
//! sin/cos and a square root; S by its series below √x = 1e-3, as the jet path.
//!
//! **Derivatives and rates in closed form** (no jets): v, v', v'', v''' by Horner; x' = 2 v·v',
//! x'' = 2(|v'|² + v·v''), x''' = 2(3 v'·v'' + v·v'''); the x-derivatives of C and S are
//! C⁽ⁿ⁾ = −S⁽ⁿ⁻¹⁾/2 and S⁽ⁿ⁾ = (C⁽ⁿ⁻¹⁾ − (2n−1) S⁽ⁿ⁻¹⁾)/(2x), by their 12-term series below
//! x = 0.5 (the jet path's switch and table), then Faà di Bruno: f' = f₁x',
//! f'' = f₂x'² + f₁x'', f''' = f₃x'³ + 3f₂x'x'' + f₁x'''. Then e⁽ᵏ⁾ = (C⁽ᵏ⁾, Σ binom S⁽ʲ⁾v⁽ᵏ⁻ʲ⁾),
//! q⁽ᵏ⁾ = qᵢ e⁽ᵏ⁾, and the body rates ω = 2 vec(e* e'), α = 2 vec(e* e''),
//! jerk = 2 vec(e'* e'' + e* e''') (qᵢ cancels); world frame by one rotation by q
//! (jerk_w = q jerk q* + ω_w × α_w = q (jerk + ω × α) q*).

use super::lanes::{Lanes, MAX_LANES};
use super::quat_lanes::{cross, dot3, lin3, qmul, rotate, scale3, vec_conj_mul, Q4};
use super::{width, Kernel, Locator, EVAL, WORLD};
use crate::quat::Quat;

const STRIDE: usize = 24;

/// Flat per-segment data of a rotation-vector spline.
#[derive(Debug, Clone)]
pub struct RotvecTable {
    data: Vec<f64>,
    locator: Locator,
}

impl RotvecTable {
    /// From the joints, the base keys qᵢ and per segment and component the coefficients
    /// [a₀ = 0, a₁, …, a₅] of the half rotation vector.
    pub fn new(joints: &[f64], keys: &[Quat], half: &[[[f64; 6]; 3]]) -> Self {
        let mut data = vec![0.0; half.len() * STRIDE];
        for (i, h) in half.iter().enumerate() {
            let r = &mut data[i * STRIDE..(i + 1) * STRIDE];
            r[0] = joints[i];
            r[1..5].copy_from_slice(&keys[i].to_wxyz());
            for c in 0..3 {
                r[5 + 6 * c..11 + 6 * c].copy_from_slice(&h[c]);
            }
        }
        RotvecTable { data, locator: Locator::new(joints) }
    }
}

/// The polynomial with coefficients `c` (lowest first) at x, by Horner.
#[inline(always)]
fn poly<V: Lanes>(x: V, c: &[f64]) -> V {
    let mut acc = V::splat(c[c.len() - 1]);
    for m in (0..c.len() - 1).rev() {
        acc = acc.fma(x, V::splat(c[m]));
    }
    acc
}

/// One vector of samples on records `f` (24 fields per lane) at local times `s`: up to 16
/// outputs (see the module doc).
#[inline(always)]
fn block<V: Lanes, const K: usize, const OUT: u8>(f: &[V], s: V) -> [V; 16] {
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    let two = V::splat(2.0);
    // v, v', v''/2, v'''/6 by Horner from a₅ down (zero leading coefficients of the cubic are
    // exact)
    let (mut p0, mut p1, mut p2, mut p3) = ([f[10], f[16], f[22]], [zero; 3], [zero; 3], [zero; 3]);
    for k in (0..5).rev() {
        for c in 0..3 {
            if K >= 3 {
                p3[c] = p3[c].fma(s, p2[c]);
            }
            if K >= 2 {
                p2[c] = p2[c].fma(s, p1[c]);
            }
            if K >= 1 {
                p1[c] = p1[c].fma(s, p0[c]);
            }
            p0[c] = p0[c].fma(s, f[5 + 6 * c + k]);
        }
    }
    let r = p0;
    let x = dot3(r, r);
    let th = x.sqrt();
    let (sn, c0) = th.sin_cos();
    // sinc: 1 − x/6 (1 − x/20 (1 − x/42)) below θ = 1e-3 (special::sinc), else sin θ / θ
    let series =
        one - x * V::splat(1.0 / 6.0) * (one - x * V::splat(1.0 / 20.0) * (one - x * V::splat(1.0 / 42.0)));
    let s0 = th.lt_select(V::splat(crate::special::SINC_SWITCH), series, sn / th);
    let e = [c0, s0 * r[0], s0 * r[1], s0 * r[2]];
    let qi: Q4<V> = [f[1], f[2], f[3], f[4]];
    let q = qmul(qi, e);
    let mut o = [zero; 16];
    if K == 0 {
        o[..4].copy_from_slice(&q);
        return o;
    }
    // x-derivatives of C and S: the jet path's series below CS_SERIES, else the recursion
    use crate::jet::{CS_SERIES, CS_TABLE};
    let small = V::splat(CS_SERIES);
    let half = V::splat(0.5);
    let inv2x = half / x;
    let s1 = x.lt_select(small, poly(x, &CS_TABLE.1[0]), (c0 - s0) * inv2x);
    let c1 = -(half * s0);
    let (mut s2, mut c2, mut s3, mut c3) = (zero, zero, zero, zero);
    if K >= 2 {
        c2 = -(half * s1);
        s2 = x.lt_select(small, poly(x, &CS_TABLE.1[1]), V::splat(-3.0).fma(s1, c1) * inv2x);
    }
    if K >= 3 {
        c3 = -(half * s2);
        s3 = x.lt_select(small, poly(x, &CS_TABLE.1[2]), V::splat(-5.0).fma(s2, c2) * inv2x);
    }
    let r1 = p1;
    let r2 = scale3(p2, two);
    let r3 = scale3(p3, V::splat(6.0));
    let x1 = two * dot3(r, r1);
    // e' = (C' , S' v + S v')
    let (cd1, sd1) = (c1 * x1, s1 * x1);
    let e1v = lin3(sd1, r, s0, r1);
    let (mut cd2, mut e2v, mut cd3, mut e3v) = (zero, [zero; 3], zero, [zero; 3]);
    let (mut x2, mut sd2) = (zero, zero);
    let three = V::splat(3.0);
    if K >= 2 {
        x2 = two * (dot3(r1, r1) + dot3(r, r2));
        let x1s = x1 * x1;
        cd2 = c2.fma(x1s, c1 * x2);
        sd2 = s2.fma(x1s, s1 * x2);
        // e'' = S'' v + 2 S' v' + S v''
        let t = lin3(sd2, r, two * sd1, r1);
        e2v = [s0.fma(r2[0], t[0]), s0.fma(r2[1], t[1]), s0.fma(r2[2], t[2])];
    }
    if K >= 3 {
        let x3 = two * three.fma(dot3(r1, r2), dot3(r, r3));
        let x1c = x1 * x1 * x1;
        let m = three * x1 * x2;
        cd3 = c3.fma(x1c, c2.fma(m, c1 * x3));
        let sd3 = s3.fma(x1c, s2.fma(m, s1 * x3));
        // e''' = S''' v + 3 S'' v' + 3 S' v'' + S v'''
        let t = lin3(sd3, r, three * sd2, r1);
        let u = lin3(three * sd1, r2, s0, r3);
        e3v = [t[0] + u[0], t[1] + u[1], t[2] + u[2]];
    }
    let ev = [e[1], e[2], e[3]];
    if OUT == EVAL {
        o[..4].copy_from_slice(&q);
        o[4..8].copy_from_slice(&qmul(qi, [cd1, e1v[0], e1v[1], e1v[2]]));
        if K >= 2 {
            o[8..12].copy_from_slice(&qmul(qi, [cd2, e2v[0], e2v[1], e2v[2]]));
        }
        if K >= 3 {
            o[12..16].copy_from_slice(&qmul(qi, [cd3, e3v[0], e3v[1], e3v[2]]));
        }
        return o;
    }
    let w = scale3(vec_conj_mul(c0, ev, cd1, e1v), two);
    let res = match K {
        1 => {
            if OUT == WORLD {
                rotate(q, w)
            } else {
                w
            }
        }
        2 => {
            let a = scale3(vec_conj_mul(c0, ev, cd2, e2v), two);
            if OUT == WORLD {
                rotate(q, a)
            } else {
                a
            }
        }
        _ => {
            let j1 = vec_conj_mul(cd1, e1v, cd2, e2v);
            let j2 = vec_conj_mul(c0, ev, cd3, e3v);
            let jb = [two * (j1[0] + j2[0]), two * (j1[1] + j2[1]), two * (j1[2] + j2[2])];
            if OUT == WORLD {
                // q j q* + (q ω q*) × (q α q*) = q (j + ω × α) q*: one rotation
                let a = scale3(vec_conj_mul(c0, ev, cd2, e2v), two);
                let c = cross(w, a);
                rotate(q, [jb[0] + c[0], jb[1] + c[1], jb[2] + c[2]])
            } else {
                jb
            }
        }
    };
    o[..3].copy_from_slice(&res);
    o
}

#[inline(always)]
unsafe fn run<V: Lanes, const K: usize, const OUT: u8>(
    tab: &RotvecTable,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    let w = width(K, OUT);
    let n = t.len();
    let base = tab.data.as_ptr();
    let mut local = [V::splat(0.0); STRIDE];
    let mut cur = usize::MAX;
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        // a full vector loads its times directly (no store-forwarding stall); the tail
        // repeats its last sample
        let tv = if m == V::N {
            V::load(t.as_ptr().add(i))
        } else {
            let mut tl = [0.0; MAX_LANES];
            for (l, x) in tl.iter_mut().enumerate().take(V::N) {
                *x = t[i + l.min(m - 1)];
            }
            V::load(tl.as_ptr())
        };
        let mut idx = [0usize; MAX_LANES];
        for (l, x) in idx.iter_mut().enumerate().take(V::N) {
            *x = seg[i + l.min(m - 1)] as usize * STRIDE;
        }
        if idx[..V::N].iter().all(|&x| x == idx[0]) {
            // broadcast: splat the record once per run of vectors in one segment
            if cur != idx[0] {
                for (o, v) in local.iter_mut().zip(&tab.data[idx[0]..idx[0] + STRIDE]) {
                    *o = V::splat(*v);
                }
                cur = idx[0];
            }
        } else {
            V::transpose_records(base, &idx, STRIDE, local.as_mut_ptr());
            cur = usize::MAX;
        }
        let s = tv - local[0];
        let o = block::<V, K, OUT>(&local, s);
        let rows = &mut out[w * i..w * (i + m)];
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
                    rows[w * l + c] = a[l];
                }
            }
        }
        i += m;
    }
}

impl Kernel for RotvecTable {
    const NAME: &'static str = "natural";
    const ORDERS: usize = 3;
    const RATES: bool = true;
    const WIDE_REGISTERS: bool = false;
    fn locator(&self) -> &Locator {
        &self.locator
    }
    fn segments(&self) -> usize {
        self.data.len() / STRIDE
    }
    #[inline(always)]
    unsafe fn body<L: Lanes, const K: usize, const OUT: u8>(&self, seg: &[u32], t: &[f64], out: &mut [f64]) {
        run::<L, K, OUT>(self, seg, t, out)
    }
}
