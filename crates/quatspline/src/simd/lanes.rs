//! The one lane trait: [`Lanes`] is a vector of `N` doubles with the operations every kernel
//! uses. `f64` is the portable scalar lane (N = 1, no FMA, the project's fdlibm `sin_cos`,
//! libm's `atan2`); [`Avx2`] is four lanes of AVX2 + FMA; [`Avx512`] is eight lanes of
//! AVX-512 F/DQ; [`P2`] is two vectors of any of them in lockstep. Kernels are written once, generically, and instantiated inside the
//! `#[target_feature]` functions of `simd::dispatch`, into which every `#[inline(always)]`
//! method here is inlined.

// fdlibm's and Cephes' kernel constants are kept digit for digit as published.
#![allow(clippy::excessive_precision)]

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The most lanes a [`Lanes`] type has (`P2<Avx512>`): the size of [`Lanes::to_array`] and of
/// the kernels' per-lane scratch arrays.
pub(crate) const MAX_LANES: usize = 16;

/// A vector of `N` f64 lanes.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// The number of lanes.
    const N: usize;
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
    /// Lanes from `p[0..N]`.
    ///
    /// # Safety
    /// `p` must be valid for `N` reads.
    unsafe fn load(p: *const f64) -> Self;
    /// Lane l of `out[f]` ← `p[idx[l] + f]` for f < len (records of N lanes, transposed).
    ///
    /// # Safety
    /// `idx` has at least `N` entries; `p[idx[l] .. idx[l] + len.next_multiple_of(4)]` valid
    /// for reads, `out` for `len` writes.
    unsafe fn transpose_records(p: *const f64, idx: &[usize], len: usize, out: *mut Self);
    /// Stores lane l of the 4 vectors at `out + l·stride .. + 4` (rows of 4).
    ///
    /// # Safety
    /// The N rows must be valid for writes.
    unsafe fn store_rows4(v: [Self; 4], out: *mut f64, stride: usize);
    /// The lanes as an array (the first `N` entries).
    fn to_array(self) -> [f64; MAX_LANES];
    /// `self · b + c` (fused where the hardware has it).
    fn fma(self, b: Self, c: Self) -> Self;
    /// `c − self · b` (fused where the hardware has it).
    fn fnma(self, b: Self, c: Self) -> Self;
    /// (sin, cos) of every lane, within one ulp of libm (fdlibm kernels).
    fn sin_cos(self) -> (Self, Self);
    /// √ of every lane.
    fn sqrt(self) -> Self;
    /// Per lane: `if self < b { x } else { y }`.
    fn lt_select(self, b: Self, x: Self, y: Self) -> Self;
    /// atan2(self, x) per lane (self = y), within 2 ulp of libm (the f64 lane is libm).
    fn atan2(self, x: Self) -> Self;
    /// Whether any lane has `self < b`.
    fn any_lt(self, b: Self) -> bool;
    /// The lane-wise larger of `self` and `b` (`self` where either is NaN).
    #[inline(always)]
    fn max(self, b: Self) -> Self {
        self.lt_select(b, b, self)
    }
}

impl Lanes for f64 {
    const N: usize = 1;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    unsafe fn load(p: *const f64) -> Self {
        *p
    }
    #[inline(always)]
    unsafe fn transpose_records(p: *const f64, idx: &[usize], len: usize, out: *mut Self) {
        std::ptr::copy_nonoverlapping(p.add(idx[0]), out, len);
    }
    #[inline(always)]
    unsafe fn store_rows4(v: [Self; 4], out: *mut f64, _stride: usize) {
        std::ptr::copy_nonoverlapping(v.as_ptr(), out, 4);
    }
    #[inline(always)]
    fn to_array(self) -> [f64; MAX_LANES] {
        let mut a = [0.0; MAX_LANES];
        a[0] = self;
        a
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        self * b + c
    }
    #[inline(always)]
    fn fnma(self, b: Self, c: Self) -> Self {
        c - self * b
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        crate::special::sin_cos(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn lt_select(self, b: Self, x: Self, y: Self) -> Self {
        if self < b {
            x
        } else {
            y
        }
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline(always)]
    fn any_lt(self, b: Self) -> bool {
        self < b
    }
}

/// Two vectors of samples evaluated in lockstep: every operation is issued for both, so the
/// long dependency chains of one vector (square root, divisions, sin/cos) overlap those of
/// the other. Each lane's result is the same as alone.
#[derive(Clone, Copy)]
pub(crate) struct P2<V>(pub(crate) V, pub(crate) V);

macro_rules! p2_op {
    ($tr:ident, $f:ident) => {
        impl<V: Lanes> $tr for P2<V> {
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

impl<V: Lanes> Neg for P2<V> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        P2(-self.0, -self.1)
    }
}

impl<V: Lanes> Lanes for P2<V> {
    const N: usize = 2 * V::N;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        P2(V::splat(x), V::splat(x))
    }
    #[inline(always)]
    unsafe fn load(p: *const f64) -> Self {
        P2(V::load(p), V::load(p.add(V::N)))
    }
    #[inline(always)]
    unsafe fn transpose_records(p: *const f64, idx: &[usize], len: usize, out: *mut Self) {
        // four fields at a time per half (the halves' transposes read whole blocks of 4)
        let z = V::splat(0.0);
        let mut f = 0;
        while f < len {
            let (mut a, mut b) = ([z; 4], [z; 4]);
            let m = (len - f).min(4);
            V::transpose_records(p.add(f), &idx[..V::N], m, a.as_mut_ptr());
            V::transpose_records(p.add(f), &idx[V::N..2 * V::N], m, b.as_mut_ptr());
            for k in 0..m {
                *out.add(f + k) = P2(a[k], b[k]);
            }
            f += 4;
        }
    }
    #[inline(always)]
    unsafe fn store_rows4(v: [Self; 4], out: *mut f64, stride: usize) {
        V::store_rows4([v[0].0, v[1].0, v[2].0, v[3].0], out, stride);
        V::store_rows4([v[0].1, v[1].1, v[2].1, v[3].1], out.add(V::N * stride), stride);
    }
    #[inline(always)]
    fn to_array(self) -> [f64; MAX_LANES] {
        let (a, b) = (self.0.to_array(), self.1.to_array());
        let mut o = [0.0; MAX_LANES];
        o[..V::N].copy_from_slice(&a[..V::N]);
        o[V::N..2 * V::N].copy_from_slice(&b[..V::N]);
        o
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

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2;

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::{Lanes, MAX_LANES};
    use std::arch::x86_64::*;
    use std::ops::{Add, Div, Mul, Neg, Sub};

    /// Four f64 lanes in an AVX2 register. Only constructed inside functions compiled with
    /// `#[target_feature(enable = "avx2,fma")]` after `is_x86_feature_detected!` said yes.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx2(pub(crate) __m256d);

    impl Add for Avx2 {
        type Output = Self;
        #[inline(always)]
        fn add(self, b: Self) -> Self {
            // SAFETY (all methods): an Avx2 value exists only where AVX2+FMA were detected.
            Avx2(unsafe { _mm256_add_pd(self.0, b.0) })
        }
    }
    impl Sub for Avx2 {
        type Output = Self;
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            Avx2(unsafe { _mm256_sub_pd(self.0, b.0) })
        }
    }
    impl Mul for Avx2 {
        type Output = Self;
        #[inline(always)]
        fn mul(self, b: Self) -> Self {
            Avx2(unsafe { _mm256_mul_pd(self.0, b.0) })
        }
    }
    impl Div for Avx2 {
        type Output = Self;
        #[inline(always)]
        fn div(self, b: Self) -> Self {
            Avx2(unsafe { _mm256_div_pd(self.0, b.0) })
        }
    }
    impl Neg for Avx2 {
        type Output = Self;
        #[inline(always)]
        fn neg(self) -> Self {
            Avx2(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
        }
    }

    pub(super) const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    pub(super) const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
    pub(super) const PIO2_2T: f64 = 2.022_266_248_795_950_631_54e-21;
    pub(super) const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
    pub(super) const MAGIC: f64 = 6_755_399_441_055_744.0;
    /// Beyond this |x| the 3-part reduction loses bits (same limit as `special::sin_cos`).
    pub(super) const REDUCE_LIMIT: f64 = 823_549.6;
    pub(super) const S: [f64; 6] = [
        -1.666_666_666_666_663_243_48e-1,
        8.333_333_333_322_489_461_24e-3,
        -1.984_126_982_985_794_931_34e-4,
        2.755_731_370_707_006_767_89e-6,
        -2.505_076_025_340_686_341_95e-8,
        1.589_690_995_211_550_102_21e-10,
    ];
    pub(super) const C: [f64; 6] = [
        4.166_666_666_666_660_190_37e-2,
        -1.388_888_888_887_410_957_49e-3,
        2.480_158_728_947_672_941_78e-5,
        -2.755_731_435_139_066_330_35e-7,
        2.087_572_321_298_174_827_90e-9,
        -1.135_964_755_778_819_482_65e-11,
    ];

    /// 4×4 transpose: rows r0…r3 in, columns out.
    #[inline(always)]
    pub(super) unsafe fn transpose4(
        r0: __m256d,
        r1: __m256d,
        r2: __m256d,
        r3: __m256d,
    ) -> (__m256d, __m256d, __m256d, __m256d) {
        let t0 = _mm256_unpacklo_pd(r0, r1);
        let t1 = _mm256_unpackhi_pd(r0, r1);
        let t2 = _mm256_unpacklo_pd(r2, r3);
        let t3 = _mm256_unpackhi_pd(r2, r3);
        (
            _mm256_permute2f128_pd::<0x20>(t0, t2),
            _mm256_permute2f128_pd::<0x20>(t1, t3),
            _mm256_permute2f128_pd::<0x31>(t0, t2),
            _mm256_permute2f128_pd::<0x31>(t1, t3),
        )
    }

    /// A constant in every lane (a function, not a closure: closures do not inherit the
    /// caller's `target_feature`, so the intrinsic would not be inlined into them).
    #[inline(always)]
    unsafe fn s1(v: f64) -> __m256d {
        _mm256_set1_pd(v)
    }

    /// (sin x, cos x) for four lanes: fdlibm's kernels after a 3-part Cody–Waite reduction by
    /// π/2, quadrant by blend and sign flips (no branch). Lanes with |x| ≥ 823549.6 or NaN
    /// are redone by libm (rare: a branch on a movemask).
    #[inline(always)]
    unsafe fn sin_cos4(x: __m256d) -> (__m256d, __m256d) {
        let big = _mm256_fmadd_pd(x, s1(INV_PIO2), s1(MAGIC));
        let k = _mm256_sub_pd(big, s1(MAGIC));
        let r = _mm256_fnmadd_pd(k, s1(PIO2_1), x);
        let r = _mm256_fnmadd_pd(k, s1(PIO2_2), r);
        let r = _mm256_fnmadd_pd(k, s1(PIO2_2T), r);
        let z = _mm256_mul_pd(r, r);
        // __kernel_sin: r + r z (S1 + z (S2 + … + z S6))
        let mut ps = _mm256_fmadd_pd(z, s1(S[5]), s1(S[4]));
        ps = _mm256_fmadd_pd(z, ps, s1(S[3]));
        ps = _mm256_fmadd_pd(z, ps, s1(S[2]));
        ps = _mm256_fmadd_pd(z, ps, s1(S[1]));
        ps = _mm256_fmadd_pd(z, ps, s1(S[0]));
        let sn = _mm256_fmadd_pd(_mm256_mul_pd(r, z), ps, r);
        // __kernel_cos: w + (((1 − w) − z/2) + z² P(z)), w = 1 − z/2
        let mut pc = _mm256_fmadd_pd(z, s1(C[5]), s1(C[4]));
        pc = _mm256_fmadd_pd(z, pc, s1(C[3]));
        pc = _mm256_fmadd_pd(z, pc, s1(C[2]));
        pc = _mm256_fmadd_pd(z, pc, s1(C[1]));
        pc = _mm256_fmadd_pd(z, pc, s1(C[0]));
        let hz = _mm256_mul_pd(s1(0.5), z);
        let w = _mm256_sub_pd(s1(1.0), hz);
        let tail = _mm256_sub_pd(_mm256_sub_pd(s1(1.0), w), hz);
        let cs = _mm256_add_pd(w, _mm256_fmadd_pd(_mm256_mul_pd(z, z), pc, tail));
        // quadrant k mod 4 from the low bits of `big`
        let qi = _mm256_castpd_si256(big);
        let one = _mm256_set1_epi64x(1);
        let two = _mm256_set1_epi64x(2);
        let swap = _mm256_castsi256_pd(_mm256_cmpeq_epi64(_mm256_and_si256(qi, one), one));
        let s_ = _mm256_blendv_pd(sn, cs, swap);
        let c_ = _mm256_blendv_pd(cs, sn, swap);
        let sgn_s = _mm256_slli_epi64::<62>(_mm256_and_si256(qi, two));
        let sgn_c = _mm256_slli_epi64::<62>(_mm256_and_si256(_mm256_add_epi64(qi, one), two));
        let mut s_out = _mm256_xor_pd(s_, _mm256_castsi256_pd(sgn_s));
        let mut c_out = _mm256_xor_pd(c_, _mm256_castsi256_pd(sgn_c));
        // |x| < limit is false for NaN too
        let ax = _mm256_andnot_pd(s1(-0.0), x);
        let ok = _mm256_cmp_pd::<_CMP_LT_OQ>(ax, s1(REDUCE_LIMIT));
        if _mm256_movemask_pd(ok) != 0xF {
            let (mut xa, mut sa, mut ca) = ([0.0; 4], [0.0; 4], [0.0; 4]);
            _mm256_storeu_pd(xa.as_mut_ptr(), x);
            _mm256_storeu_pd(sa.as_mut_ptr(), s_out);
            _mm256_storeu_pd(ca.as_mut_ptr(), c_out);
            for l in 0..4 {
                if xa[l].is_nan() || xa[l].abs() >= REDUCE_LIMIT {
                    (sa[l], ca[l]) = xa[l].sin_cos();
                }
            }
            s_out = _mm256_loadu_pd(sa.as_ptr());
            c_out = _mm256_loadu_pd(ca.as_ptr());
        }
        (s_out, c_out)
    }

    /// Cephes `atan`: atan(x) = x + x³ P(x²)/Q(x²) on |x| ≤ 0.66 (Moshier, Cephes Math Library
    /// 2.8, atan.c; peak relative error 2.6e-18 of the rational form), with the reductions
    /// x > tan(3π/8): π/2 − atan(1/x) and 0.66 < x ≤ tan(3π/8): π/4 + atan((x−1)/(x+1)).
    pub(super) const ATAN_P: [f64; 5] = [
        -8.750_608_600_031_904_122_785e-1,
        -1.615_753_718_733_365_076_637e1,
        -7.500_855_792_314_704_667_340e1,
        -1.228_866_684_490_136_173_410e2,
        -6.485_021_904_942_025_371_773e1,
    ];
    pub(super) const ATAN_Q: [f64; 5] = [
        2.485_846_490_142_306_297_962e1,
        1.650_270_098_316_988_542_046e2,
        4.328_810_604_912_902_668_951e2,
        4.853_903_996_359_136_964_868e2,
        1.945_506_571_482_613_964_425e2,
    ];
    /// π/2 − fl(π/2) (Cephes MOREBITS).
    pub(super) const MOREBITS: f64 = 6.123_233_995_736_765_886_130e-17;
    pub(super) const T3P8: f64 = 2.414_213_562_373_095_048_80;

    /// Four-lane atan2: the Cephes reduction chosen per lane by comparisons of |y| against
    /// multiples of |x| (no division to pick the branch), one division for the reduced
    /// argument, one for the rational form; the quadrant by the sign bits of x and y.
    #[inline(always)]
    unsafe fn atan2_4(y: __m256d, x: __m256d) -> __m256d {
        let sign = s1(-0.0);
        let ay = _mm256_andnot_pd(sign, y);
        let ax = _mm256_andnot_pd(sign, x);
        let small = _mm256_cmp_pd::<_CMP_LE_OQ>(ay, _mm256_mul_pd(s1(0.66), ax));
        let big = _mm256_cmp_pd::<_CMP_GT_OQ>(ay, _mm256_mul_pd(s1(T3P8), ax));
        // middle: ((|y| − |x|) / (|y| + |x|), π/4); big: (−|x| / |y|, π/2); small: (|y| / |x|, 0)
        let mut num = _mm256_sub_pd(ay, ax);
        let mut den = _mm256_add_pd(ay, ax);
        let mut base = s1(std::f64::consts::FRAC_PI_4);
        let mut more = s1(0.5 * MOREBITS);
        num = _mm256_blendv_pd(num, _mm256_xor_pd(ax, sign), big);
        den = _mm256_blendv_pd(den, ay, big);
        base = _mm256_blendv_pd(base, s1(std::f64::consts::FRAC_PI_2), big);
        more = _mm256_blendv_pd(more, s1(MOREBITS), big);
        num = _mm256_blendv_pd(num, ay, small);
        den = _mm256_blendv_pd(den, ax, small);
        base = _mm256_blendv_pd(base, _mm256_setzero_pd(), small);
        more = _mm256_blendv_pd(more, _mm256_setzero_pd(), small);
        // 0/0 (y = x = 0): the reduced argument 0
        let zero_den = _mm256_cmp_pd::<_CMP_EQ_OQ>(den, _mm256_setzero_pd());
        den = _mm256_blendv_pd(den, s1(1.0), zero_den);
        let z = _mm256_div_pd(num, den);
        let zz = _mm256_mul_pd(z, z);
        let mut p = _mm256_fmadd_pd(zz, s1(ATAN_P[0]), s1(ATAN_P[1]));
        p = _mm256_fmadd_pd(zz, p, s1(ATAN_P[2]));
        p = _mm256_fmadd_pd(zz, p, s1(ATAN_P[3]));
        p = _mm256_fmadd_pd(zz, p, s1(ATAN_P[4]));
        let mut q = _mm256_add_pd(zz, s1(ATAN_Q[0]));
        q = _mm256_fmadd_pd(zz, q, s1(ATAN_Q[1]));
        q = _mm256_fmadd_pd(zz, q, s1(ATAN_Q[2]));
        q = _mm256_fmadd_pd(zz, q, s1(ATAN_Q[3]));
        q = _mm256_fmadd_pd(zz, q, s1(ATAN_Q[4]));
        let r = _mm256_fmadd_pd(_mm256_mul_pd(z, zz), _mm256_div_pd(p, q), z);
        let a = _mm256_add_pd(base, _mm256_add_pd(r, more));
        // x < 0 (sign bit, so −0 too): π − a, with π's low part 2·MOREBITS
        let pi_hi = s1(std::f64::consts::PI);
        let flipped = _mm256_add_pd(_mm256_sub_pd(pi_hi, a), s1(2.0 * MOREBITS));
        let a = _mm256_blendv_pd(a, flipped, x);
        // the sign of y
        _mm256_or_pd(a, _mm256_and_pd(y, sign))
    }

    impl Lanes for Avx2 {
        const N: usize = 4;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            Avx2(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        unsafe fn load(p: *const f64) -> Self {
            Avx2(_mm256_loadu_pd(p))
        }
        #[inline(always)]
        unsafe fn transpose_records(p: *const f64, idx: &[usize], len: usize, out: *mut Self) {
            let mut f = 0;
            while f < len {
                let (a, b, c, d) = transpose4(
                    _mm256_loadu_pd(p.add(idx[0] + f)),
                    _mm256_loadu_pd(p.add(idx[1] + f)),
                    _mm256_loadu_pd(p.add(idx[2] + f)),
                    _mm256_loadu_pd(p.add(idx[3] + f)),
                );
                *out.add(f) = Avx2(a);
                *out.add(f + 1) = Avx2(b);
                *out.add(f + 2) = Avx2(c);
                *out.add(f + 3) = Avx2(d);
                f += 4;
            }
        }
        #[inline(always)]
        unsafe fn store_rows4(v: [Self; 4], out: *mut f64, stride: usize) {
            let (a, b, c, d) = transpose4(v[0].0, v[1].0, v[2].0, v[3].0);
            _mm256_storeu_pd(out, a);
            _mm256_storeu_pd(out.add(stride), b);
            _mm256_storeu_pd(out.add(2 * stride), c);
            _mm256_storeu_pd(out.add(3 * stride), d);
        }
        #[inline(always)]
        fn to_array(self) -> [f64; MAX_LANES] {
            let mut a = [0.0; MAX_LANES];
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn fma(self, b: Self, c: Self) -> Self {
            Avx2(unsafe { _mm256_fmadd_pd(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn fnma(self, b: Self, c: Self) -> Self {
            Avx2(unsafe { _mm256_fnmadd_pd(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn sin_cos(self) -> (Self, Self) {
            let (s, c) = unsafe { sin_cos4(self.0) };
            (Avx2(s), Avx2(c))
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx2(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn lt_select(self, b: Self, x: Self, y: Self) -> Self {
            unsafe { Avx2(_mm256_blendv_pd(y.0, x.0, _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0))) }
        }
        #[inline(always)]
        fn atan2(self, x: Self) -> Self {
            Avx2(unsafe { atan2_4(self.0, x.0) })
        }
        #[inline(always)]
        fn any_lt(self, b: Self) -> bool {
            unsafe { _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0)) != 0 }
        }
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx512::Avx512;

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::avx2::{
        transpose4, ATAN_P, ATAN_Q, C, INV_PIO2, MAGIC, MOREBITS, PIO2_1, PIO2_2, PIO2_2T, REDUCE_LIMIT, S,
        T3P8,
    };
    use super::{Lanes, MAX_LANES};
    use std::arch::x86_64::*;
    use std::ops::{Add, Div, Mul, Neg, Sub};

    /// Eight f64 lanes in an AVX-512 register. Only constructed inside functions compiled with
    /// `#[target_feature(enable = "avx512f,avx512dq")]` (and AVX2 + FMA) after
    /// `is_x86_feature_detected!` said yes. The operations are the AVX2 lanes' one for one
    /// (the same fused and unfused steps), so each lane's result equals the AVX2 kernel's.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx512(pub(crate) __m512d);

    impl Add for Avx512 {
        type Output = Self;
        #[inline(always)]
        fn add(self, b: Self) -> Self {
            // SAFETY (all methods): an Avx512 value exists only where AVX-512 F/DQ were detected.
            Avx512(unsafe { _mm512_add_pd(self.0, b.0) })
        }
    }
    impl Sub for Avx512 {
        type Output = Self;
        #[inline(always)]
        fn sub(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_sub_pd(self.0, b.0) })
        }
    }
    impl Mul for Avx512 {
        type Output = Self;
        #[inline(always)]
        fn mul(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_mul_pd(self.0, b.0) })
        }
    }
    impl Div for Avx512 {
        type Output = Self;
        #[inline(always)]
        fn div(self, b: Self) -> Self {
            Avx512(unsafe { _mm512_div_pd(self.0, b.0) })
        }
    }
    impl Neg for Avx512 {
        type Output = Self;
        #[inline(always)]
        fn neg(self) -> Self {
            Avx512(unsafe { _mm512_xor_pd(self.0, _mm512_set1_pd(-0.0)) })
        }
    }

    /// A constant in every lane (a function, not a closure: see the AVX2 lanes).
    #[inline(always)]
    unsafe fn s1(v: f64) -> __m512d {
        _mm512_set1_pd(v)
    }

    /// Lanes 0–3 from `lo`, 4–7 from `hi`.
    #[inline(always)]
    unsafe fn join(lo: __m256d, hi: __m256d) -> __m512d {
        _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(lo), hi)
    }

    /// (sin x, cos x) for eight lanes: the AVX2 lanes' fdlibm kernels step for step (mask
    /// registers for the blends), lanes with |x| ≥ 823549.6 or NaN redone by libm.
    #[inline(always)]
    unsafe fn sin_cos8(x: __m512d) -> (__m512d, __m512d) {
        let big = _mm512_fmadd_pd(x, s1(INV_PIO2), s1(MAGIC));
        let k = _mm512_sub_pd(big, s1(MAGIC));
        let r = _mm512_fnmadd_pd(k, s1(PIO2_1), x);
        let r = _mm512_fnmadd_pd(k, s1(PIO2_2), r);
        let r = _mm512_fnmadd_pd(k, s1(PIO2_2T), r);
        let z = _mm512_mul_pd(r, r);
        let mut ps = _mm512_fmadd_pd(z, s1(S[5]), s1(S[4]));
        ps = _mm512_fmadd_pd(z, ps, s1(S[3]));
        ps = _mm512_fmadd_pd(z, ps, s1(S[2]));
        ps = _mm512_fmadd_pd(z, ps, s1(S[1]));
        ps = _mm512_fmadd_pd(z, ps, s1(S[0]));
        let sn = _mm512_fmadd_pd(_mm512_mul_pd(r, z), ps, r);
        let mut pc = _mm512_fmadd_pd(z, s1(C[5]), s1(C[4]));
        pc = _mm512_fmadd_pd(z, pc, s1(C[3]));
        pc = _mm512_fmadd_pd(z, pc, s1(C[2]));
        pc = _mm512_fmadd_pd(z, pc, s1(C[1]));
        pc = _mm512_fmadd_pd(z, pc, s1(C[0]));
        let hz = _mm512_mul_pd(s1(0.5), z);
        let w = _mm512_sub_pd(s1(1.0), hz);
        let tail = _mm512_sub_pd(_mm512_sub_pd(s1(1.0), w), hz);
        let cs = _mm512_add_pd(w, _mm512_fmadd_pd(_mm512_mul_pd(z, z), pc, tail));
        let qi = _mm512_castpd_si512(big);
        let one = _mm512_set1_epi64(1);
        let two = _mm512_set1_epi64(2);
        let swap = _mm512_cmpeq_epi64_mask(_mm512_and_si512(qi, one), one);
        let s_ = _mm512_mask_blend_pd(swap, sn, cs);
        let c_ = _mm512_mask_blend_pd(swap, cs, sn);
        let sgn_s = _mm512_slli_epi64::<62>(_mm512_and_si512(qi, two));
        let sgn_c = _mm512_slli_epi64::<62>(_mm512_and_si512(_mm512_add_epi64(qi, one), two));
        let mut s_out = _mm512_xor_pd(s_, _mm512_castsi512_pd(sgn_s));
        let mut c_out = _mm512_xor_pd(c_, _mm512_castsi512_pd(sgn_c));
        let ax = _mm512_andnot_pd(s1(-0.0), x);
        let ok = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(ax, s1(REDUCE_LIMIT));
        if ok != 0xFF {
            let (mut xa, mut sa, mut ca) = ([0.0; 8], [0.0; 8], [0.0; 8]);
            _mm512_storeu_pd(xa.as_mut_ptr(), x);
            _mm512_storeu_pd(sa.as_mut_ptr(), s_out);
            _mm512_storeu_pd(ca.as_mut_ptr(), c_out);
            for l in 0..8 {
                if xa[l].is_nan() || xa[l].abs() >= REDUCE_LIMIT {
                    (sa[l], ca[l]) = xa[l].sin_cos();
                }
            }
            s_out = _mm512_loadu_pd(sa.as_ptr());
            c_out = _mm512_loadu_pd(ca.as_ptr());
        }
        (s_out, c_out)
    }

    /// Eight-lane atan2: the AVX2 lanes' Cephes reduction step for step.
    #[inline(always)]
    unsafe fn atan2_8(y: __m512d, x: __m512d) -> __m512d {
        let sign = s1(-0.0);
        let ay = _mm512_andnot_pd(sign, y);
        let ax = _mm512_andnot_pd(sign, x);
        let small = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(ay, _mm512_mul_pd(s1(0.66), ax));
        let big = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(ay, _mm512_mul_pd(s1(T3P8), ax));
        let mut num = _mm512_sub_pd(ay, ax);
        let mut den = _mm512_add_pd(ay, ax);
        let mut base = s1(std::f64::consts::FRAC_PI_4);
        let mut more = s1(0.5 * MOREBITS);
        num = _mm512_mask_blend_pd(big, num, _mm512_xor_pd(ax, sign));
        den = _mm512_mask_blend_pd(big, den, ay);
        base = _mm512_mask_blend_pd(big, base, s1(std::f64::consts::FRAC_PI_2));
        more = _mm512_mask_blend_pd(big, more, s1(MOREBITS));
        num = _mm512_mask_blend_pd(small, num, ay);
        den = _mm512_mask_blend_pd(small, den, ax);
        base = _mm512_mask_blend_pd(small, base, _mm512_setzero_pd());
        more = _mm512_mask_blend_pd(small, more, _mm512_setzero_pd());
        let zero_den = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(den, _mm512_setzero_pd());
        den = _mm512_mask_blend_pd(zero_den, den, s1(1.0));
        let z = _mm512_div_pd(num, den);
        let zz = _mm512_mul_pd(z, z);
        let mut p = _mm512_fmadd_pd(zz, s1(ATAN_P[0]), s1(ATAN_P[1]));
        p = _mm512_fmadd_pd(zz, p, s1(ATAN_P[2]));
        p = _mm512_fmadd_pd(zz, p, s1(ATAN_P[3]));
        p = _mm512_fmadd_pd(zz, p, s1(ATAN_P[4]));
        let mut q = _mm512_add_pd(zz, s1(ATAN_Q[0]));
        q = _mm512_fmadd_pd(zz, q, s1(ATAN_Q[1]));
        q = _mm512_fmadd_pd(zz, q, s1(ATAN_Q[2]));
        q = _mm512_fmadd_pd(zz, q, s1(ATAN_Q[3]));
        q = _mm512_fmadd_pd(zz, q, s1(ATAN_Q[4]));
        let r = _mm512_fmadd_pd(_mm512_mul_pd(z, zz), _mm512_div_pd(p, q), z);
        let a = _mm512_add_pd(base, _mm512_add_pd(r, more));
        let pi_hi = s1(std::f64::consts::PI);
        let flipped = _mm512_add_pd(_mm512_sub_pd(pi_hi, a), s1(2.0 * MOREBITS));
        // x's sign bit (−0 too), as AVX2's blendv reads it
        let neg_x = _mm512_movepi64_mask(_mm512_castpd_si512(x));
        let a = _mm512_mask_blend_pd(neg_x, a, flipped);
        _mm512_or_pd(a, _mm512_and_pd(y, sign))
    }

    impl Lanes for Avx512 {
        const N: usize = 8;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            Avx512(unsafe { _mm512_set1_pd(x) })
        }
        #[inline(always)]
        unsafe fn load(p: *const f64) -> Self {
            Avx512(_mm512_loadu_pd(p))
        }
        #[inline(always)]
        unsafe fn transpose_records(p: *const f64, idx: &[usize], len: usize, out: *mut Self) {
            // per block of 4 fields: two 4×4 transposes (records 0–3, 4–7) joined
            let mut f = 0;
            while f < len {
                // (no closures: they would not inherit the caller's target features)
                let (a0, b0, c0, d0) = transpose4(
                    _mm256_loadu_pd(p.add(idx[0] + f)),
                    _mm256_loadu_pd(p.add(idx[1] + f)),
                    _mm256_loadu_pd(p.add(idx[2] + f)),
                    _mm256_loadu_pd(p.add(idx[3] + f)),
                );
                let (a1, b1, c1, d1) = transpose4(
                    _mm256_loadu_pd(p.add(idx[4] + f)),
                    _mm256_loadu_pd(p.add(idx[5] + f)),
                    _mm256_loadu_pd(p.add(idx[6] + f)),
                    _mm256_loadu_pd(p.add(idx[7] + f)),
                );
                *out.add(f) = Avx512(join(a0, a1));
                *out.add(f + 1) = Avx512(join(b0, b1));
                *out.add(f + 2) = Avx512(join(c0, c1));
                *out.add(f + 3) = Avx512(join(d0, d1));
                f += 4;
            }
        }
        #[inline(always)]
        unsafe fn store_rows4(v: [Self; 4], out: *mut f64, stride: usize) {
            let (a, b, c, d) = transpose4(
                _mm512_castpd512_pd256(v[0].0),
                _mm512_castpd512_pd256(v[1].0),
                _mm512_castpd512_pd256(v[2].0),
                _mm512_castpd512_pd256(v[3].0),
            );
            _mm256_storeu_pd(out, a);
            _mm256_storeu_pd(out.add(stride), b);
            _mm256_storeu_pd(out.add(2 * stride), c);
            _mm256_storeu_pd(out.add(3 * stride), d);
            let (a, b, c, d) = transpose4(
                _mm512_extractf64x4_pd::<1>(v[0].0),
                _mm512_extractf64x4_pd::<1>(v[1].0),
                _mm512_extractf64x4_pd::<1>(v[2].0),
                _mm512_extractf64x4_pd::<1>(v[3].0),
            );
            let out = out.add(4 * stride);
            _mm256_storeu_pd(out, a);
            _mm256_storeu_pd(out.add(stride), b);
            _mm256_storeu_pd(out.add(2 * stride), c);
            _mm256_storeu_pd(out.add(3 * stride), d);
        }
        #[inline(always)]
        fn to_array(self) -> [f64; MAX_LANES] {
            let mut a = [0.0; MAX_LANES];
            unsafe { _mm512_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn fma(self, b: Self, c: Self) -> Self {
            Avx512(unsafe { _mm512_fmadd_pd(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn fnma(self, b: Self, c: Self) -> Self {
            Avx512(unsafe { _mm512_fnmadd_pd(self.0, b.0, c.0) })
        }
        #[inline(always)]
        fn sin_cos(self) -> (Self, Self) {
            let (s, c) = unsafe { sin_cos8(self.0) };
            (Avx512(s), Avx512(c))
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx512(unsafe { _mm512_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn lt_select(self, b: Self, x: Self, y: Self) -> Self {
            unsafe { Avx512(_mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, b.0), y.0, x.0)) }
        }
        #[inline(always)]
        fn atan2(self, x: Self) -> Self {
            Avx512(unsafe { atan2_8(self.0, x.0) })
        }
        #[inline(always)]
        fn any_lt(self, b: Self) -> bool {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, b.0) != 0 }
        }
    }
}
