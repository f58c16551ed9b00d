//! Batch kernel of the rotation-vector splines' value (natural spline, Hermite keys): segment
//! i, q(τ) = qᵢ exp(r(s)), r(s) = Σₖ aₖ sᵏ (k = 1…5, cubic or quintic), s = τ − τᵢ, with
//! aₖ = cₖ/2 as the segments store them (one flat record of 24 doubles per segment). exp of the
//! pure quaternion by the vector sin/cos and a square root; sin θ/θ by its series below
//! θ = 1e-3, as the jet path. Derivatives and rates keep the exact jets (the kernel declines
//! and the engine falls back).

use super::lanes::Lanes;
use super::{BatchKernel, Isa, Locator};
use crate::quat::Quat;
use crate::spline::Frame;

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

#[inline(always)]
unsafe fn run<V: Lanes>(tab: &RotvecTable, seg: &[u32], t: &[f64], out: &mut [f64]) {
    let n = t.len();
    let base = tab.data.as_ptr();
    let mut local = [V::splat(0.0); STRIDE];
    let mut i = 0;
    while i < n {
        let m = (n - i).min(V::N);
        let mut tl = [0.0; 4];
        let mut idx = [0usize; 4];
        for l in 0..V::N {
            let k = i + l.min(m - 1);
            tl[l] = t[k];
            idx[l] = seg[k] as usize * STRIDE;
        }
        let f: &[V] = if idx[..V::N].iter().all(|&x| x == idx[0]) {
            for (o, v) in local.iter_mut().zip(&tab.data[idx[0]..idx[0] + STRIDE]) {
                *o = V::splat(*v);
            }
            &local
        } else {
            V::transpose_records(base, &idx, STRIDE, local.as_mut_ptr());
            &local
        };
        let s = V::load(tl.as_ptr()) - f[0];
        // Horner from a₅ down to a₀ (zero leading coefficients of the cubic are exact)
        let mut r = [f[10], f[16], f[22]];
        for k in (0..5).rev() {
            for c in 0..3 {
                r[c] = r[c].fma(s, f[5 + 6 * c + k]);
            }
        }
        let x = r[2].fma(r[2], r[1].fma(r[1], r[0] * r[0]));
        let th = x.sqrt();
        let (sn, cs) = th.sin_cos();
        // sinc: 1 − x/6 (1 − x/20 (1 − x/42)) below θ = 1e-3 (special::sinc), else sin θ / θ
        let one = V::splat(1.0);
        let series = one
            - x * V::splat(1.0 / 6.0) * (one - x * V::splat(1.0 / 20.0) * (one - x * V::splat(1.0 / 42.0)));
        let sinc = th.lt_select(V::splat(crate::special::SINC_SWITCH), series, sn / th);
        let e = [cs, sinc * r[0], sinc * r[1], sinc * r[2]];
        let q = [f[1], f[2], f[3], f[4]];
        let o = [
            q[3].fnma(e[3], q[2].fnma(e[2], q[1].fnma(e[1], q[0] * e[0]))),
            q[3].fnma(e[2], q[2].fma(e[3], q[1].fma(e[0], q[0] * e[1]))),
            q[3].fma(e[1], q[2].fma(e[0], q[1].fnma(e[3], q[0] * e[2]))),
            q[3].fma(e[0], q[2].fnma(e[1], q[1].fma(e[2], q[0] * e[3]))),
        ];
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

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2(tab: &RotvecTable, seg: &[u32], t: &[f64], out: &mut [f64]) {
    run::<super::lanes::Avx2>(tab, seg, t, out)
}

impl BatchKernel for RotvecTable {
    fn locator(&self) -> &Locator {
        &self.locator
    }

    fn evaluate(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool {
        if order > 0 {
            return false;
        }
        let nseg = self.data.len() / STRIDE;
        assert!(seg.len() == t.len() && out.len() == 4 * t.len(), "natural kernel: bad lengths");
        assert!(seg.iter().all(|&s| (s as usize) < nseg), "natural kernel: segment out of range");
        #[cfg(target_arch = "x86_64")]
        if isa == Isa::Avx2 && super::avx2_available() {
            // SAFETY: AVX2 and FMA detected; lengths and segment indices checked above.
            unsafe { run_avx2(self, seg, t, out) };
            return true;
        }
        let _ = isa;
        // SAFETY: lengths and segment indices checked above.
        unsafe { run::<f64>(self, seg, t, out) };
        true
    }

    fn angular(&self, _: Isa, _: &[u32], _: &[f64], _: usize, _: Frame, _: &mut [f64]) -> bool {
        false
    }
}
