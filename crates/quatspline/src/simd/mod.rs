//! The batch evaluation engine's kernels: per-segment data precomputed flat, samples processed
//! a vector at a time, the instruction set chosen at run time.
//!
//! # Adding a kernel: a table and a body
//! 1. **Table**: a struct of flat per-segment records (multiples of 4 doubles, so that 4
//!    records transpose at once) and a [`Locator`], built by the spline's constructor.
//! 2. **Body**: `unsafe fn body<L: Lanes, const K: usize, const OUT: u8>(&self, seg, t, out)`,
//!    the rows of order K (`EVAL`, or `BODY` / `WORLD` rates) written once over lanes
//!    (`lanes.rs`), with quaternion algebra from `quat_lanes.rs` (never a second `qmul`).
//! 3. **`impl Kernel for Table`**: its name, the orders and rates it covers, and the body. The
//!    dispatch over instruction sets and `impl BatchKernel` come with it (one blanket impl).
//! 4. **Spline**: `Spline::batch` returns the table.
//! 5. **Tests**: the spline joins the lists of `tests/simd_kernels.rs` (shared support in
//!    `tests/common`), which hold it to the per-sample jets on every instruction set.
//!
//! * [`Isa`]: AVX-512 F + DQ (eight lanes) when `is_x86_feature_detected!` finds them (with
//!   AVX2 + FMA), else AVX2 + FMA (four lanes), else the portable scalar kernel (same code,
//!   one lane). One build runs everywhere; nothing needs `target-cpu=native`. Every kernel
//!   that goes through [`dispatch`] runs on all three: the cumulative family, the slerp
//!   family (piecewise slerp, Squad, Catmull–Rom / Kochanek–Bartels, spherical Bézier), the
//!   natural (rotation-vector Hermite) kernel, and the slerp/ScLerp pair kernels. A kernel
//!   may ask for a second AVX2 build compiled where AVX-512 VL exists
//!   (`Kernel::WIDE_REGISTERS`): the same 256-bit instructions (the same bits) with 32 vector
//!   registers.
//! * [`mode`] / [`set_mode`]: `QUATSPLINE_SIMD=auto|avx512|avx2|scalar|reference` (read once)
//!   or [`set_mode`] at run time. `avx512` / `avx2` cap the instruction set (a CPU without it
//!   gets the best one below), `scalar` forces the portable kernels, `reference` the
//!   per-sample jet path that every kernel is tested against.
//! * [`BatchKernel`]: what a spline offers the engine (`Spline::batch`): rows for samples
//!   whose segments the engine has located.
//! * [`Locator`]: segment search for unsorted times in O(1) expected (bucket index), picking
//!   exactly the segment `Spline::locate` picks.
//!
//! Results are a function of each sample alone (never of its neighbours, its position in a
//! vector or a thread's chunk), so they are bit-identical for any thread count and chunking.

pub mod cumulative;
pub(crate) mod lanes;
pub mod natural;
pub mod pairs;
pub(crate) mod quat_lanes;
pub mod slerp;

use crate::frame::Frame;
use lanes::Lanes;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU8, Ordering};

/// The instruction set a kernel runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// Portable scalar code (one sample at a time).
    Scalar,
    /// AVX2 + FMA, four samples per vector (x86-64, detected at run time).
    Avx2,
    /// AVX-512 F + DQ (with AVX2 + FMA), eight samples per vector (x86-64, detected at run
    /// time).
    Avx512,
}

impl Isa {
    /// "avx512", "avx2" or "scalar".
    pub fn name(self) -> &'static str {
        match self {
            Isa::Scalar => "scalar",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    /// Whether this CPU runs the instruction set.
    pub fn available(self) -> bool {
        match self {
            Isa::Scalar => true,
            Isa::Avx2 => avx2_available(),
            Isa::Avx512 => avx512_available(),
        }
    }

    /// The best instruction set this CPU has, at most `cap`.
    pub fn best_up_to(cap: Isa) -> Isa {
        match cap {
            Isa::Avx512 if avx512_available() => Isa::Avx512,
            Isa::Avx512 | Isa::Avx2 if avx2_available() => Isa::Avx2,
            _ => Isa::Scalar,
        }
    }
}

/// The engine's mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The best kernels the CPU supports.
    Auto,
    /// Batch kernels, at most AVX-512 (the same as `Auto` today).
    Avx512,
    /// Batch kernels, at most AVX2 (four lanes).
    Avx2,
    /// Batch kernels, portable scalar instruction set.
    Scalar,
    /// No batch kernels: the per-sample jet path (the reference).
    Reference,
}

impl Mode {
    /// "auto", "avx512", "avx2", "scalar" or "reference".
    pub fn name(self) -> &'static str {
        match self {
            Mode::Auto => "auto",
            Mode::Avx512 => "avx512",
            Mode::Avx2 => "avx2",
            Mode::Scalar => "scalar",
            Mode::Reference => "reference",
        }
    }
}

const UNSET: u8 = 0;
static MODE: AtomicU8 = AtomicU8::new(UNSET);

fn encode(m: Mode) -> u8 {
    match m {
        Mode::Auto => 1,
        Mode::Scalar => 2,
        Mode::Reference => 3,
        Mode::Avx2 => 4,
        Mode::Avx512 => 5,
    }
}

/// Parses a mode name: `auto`/`on`, `avx512`, `avx2`, `scalar`/`off`, `reference`.
pub fn parse_mode(s: &str) -> Option<Mode> {
    match s.trim().to_ascii_lowercase().as_str() {
        "" | "auto" | "on" | "1" => Some(Mode::Auto),
        "avx512" => Some(Mode::Avx512),
        "avx2" => Some(Mode::Avx2),
        "scalar" | "off" | "0" => Some(Mode::Scalar),
        "reference" | "ref" => Some(Mode::Reference),
        _ => None,
    }
}

/// A zeroed table of `n` doubles for per-segment data. Large tables are allocated untouched
/// (calloc's fresh pages) and, on Linux, advised as transparent huge pages before they are
/// filled: a table of 10⁶ segments is hundreds of megabytes, and with 4 KiB pages its page
/// faults (and their release) cost more than computing its contents. The advice changes no
/// value; where the kernel declines it the table is the same, in small pages.
pub(crate) fn table_buffer(n: usize) -> Vec<f64> {
    let mut v = vec![0.0; n];
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        const MADV_HUGEPAGE: i32 = 14;
        extern "C" {
            fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
        }
        let bytes = n * std::mem::size_of::<f64>();
        if bytes >= 4 * HUGE {
            let start = v.as_mut_ptr() as usize;
            let a = start.next_multiple_of(HUGE);
            let e = (start + bytes) / HUGE * HUGE;
            if e > a {
                // SAFETY: [a, e) lies inside the vector's allocation and is page aligned;
                // MADV_HUGEPAGE only advises how the range is backed (no data changes) and
                // its failure is harmless.
                unsafe {
                    madvise(a as *mut std::ffi::c_void, e - a, MADV_HUGEPAGE);
                }
            }
        }
    }
    v
}

/// The current mode (first call reads `QUATSPLINE_SIMD`; an unknown value means `auto`).
pub fn mode() -> Mode {
    match MODE.load(Ordering::Relaxed) {
        1 => Mode::Auto,
        2 => Mode::Scalar,
        3 => Mode::Reference,
        4 => Mode::Avx2,
        5 => Mode::Avx512,
        _ => {
            let m = std::env::var("QUATSPLINE_SIMD").ok().and_then(|v| parse_mode(&v)).unwrap_or(Mode::Auto);
            MODE.store(encode(m), Ordering::Relaxed);
            m
        }
    }
}

/// Sets the mode for the whole process (tests, benchmarks, `quatspline.set_simd`).
pub fn set_mode(m: Mode) {
    MODE.store(encode(m), Ordering::Relaxed);
}

/// Whether this CPU has AVX2 and FMA.
pub fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether this CPU has AVX-512 F and DQ (and AVX2 + FMA, which the 8-lane kernels also use).
pub fn avx512_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        avx2_available()
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512dq")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// The instruction set batch kernels use now; None in reference mode.
pub fn isa() -> Option<Isa> {
    match mode() {
        Mode::Reference => None,
        Mode::Scalar => Some(Isa::Scalar),
        Mode::Avx2 => Some(Isa::best_up_to(Isa::Avx2)),
        Mode::Auto | Mode::Avx512 => Some(Isa::best_up_to(Isa::Avx512)),
    }
}

/// A call of a kernel over lanes: what [`dispatch`] runs on the lanes of the instruction set
/// it picks.
pub(crate) trait OnLanes {
    /// The call's result.
    type Out;
    /// The call on lanes `L`.
    ///
    /// # Safety
    /// The preconditions of the kernel called (checked lengths and indices).
    unsafe fn run<L: Lanes>(self) -> Self::Out;
}

/// Runs `f` on the lanes of `isa`: inside a `#[target_feature(enable = "avx512f,avx512dq")]`
/// function on eight lanes when `isa` is AVX-512 and the CPU has it; inside a
/// `#[target_feature(enable = "avx2,fma")]` function (with `wide_registers`, where AVX-512
/// VL exists, one also compiled with `avx512f,avx512vl`: the same instructions, 32 vector
/// registers) when `isa` is AVX2 (or AVX-512 on a CPU without it) and the CPU has AVX2;
/// else on the portable `f64` lane. The one dispatch of every kernel.
///
/// # Safety
/// The preconditions of `f`'s kernel.
#[inline(always)]
pub(crate) unsafe fn dispatch<F: OnLanes>(isa: Isa, wide_registers: bool, f: F) -> F::Out {
    #[cfg(target_arch = "x86_64")]
    if isa == Isa::Avx512 && avx512_available() {
        // SAFETY: AVX2, FMA, AVX-512 F and DQ detected.
        return on_avx512(f);
    }
    #[cfg(target_arch = "x86_64")]
    if matches!(isa, Isa::Avx2 | Isa::Avx512) && avx2_available() {
        if wide_registers
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
        {
            // SAFETY: AVX2, FMA, AVX-512 F and VL detected.
            return on_avx2_32regs(f);
        }
        // SAFETY: AVX2 and FMA detected.
        return on_avx2(f);
    }
    let _ = (isa, wide_registers);
    f.run::<f64>()
}

/// `f` on AVX2 lanes. Caller checked AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn on_avx2<F: OnLanes>(f: F) -> F::Out {
    f.run::<lanes::Avx2>()
}

/// `f` on AVX-512 lanes (eight). Caller checked AVX2, FMA, AVX-512 F and DQ.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512dq")]
pub(crate) unsafe fn on_avx512<F: OnLanes>(f: F) -> F::Out {
    f.run::<lanes::Avx512>()
}

/// `f` on AVX2 lanes, compiled with AVX-512 VL's 32 vector registers. Caller checked AVX2,
/// FMA, AVX-512 F and VL.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl")]
pub(crate) unsafe fn on_avx2_32regs<F: OnLanes>(f: F) -> F::Out {
    f.run::<lanes::Avx2>()
}

/// `f(v)` for every vector `v` of `x`, in order (a tail padded with `pad`): the accuracy
/// tests' view of a lane function. Results `out[0]`, `out[1]` per element.
struct Elementwise<'a, F> {
    x: &'a [f64],
    y: &'a [f64],
    pad: (f64, f64),
    out: (&'a mut [f64], Option<&'a mut [f64]>),
    f: F,
}

/// A lane function for [`Elementwise`] (a trait, not a closure: it is generic over lanes).
trait LaneFn {
    fn apply<L: Lanes>(&self, x: L, y: L) -> (L, L);
}

impl<F: LaneFn> OnLanes for Elementwise<'_, F> {
    type Out = ();
    #[inline(always)]
    unsafe fn run<L: Lanes>(self) {
        let (o0, mut o1) = self.out;
        for (k, xc) in self.x.chunks(L::N).enumerate() {
            let (mut bx, mut by) = ([self.pad.0; lanes::MAX_LANES], [self.pad.1; lanes::MAX_LANES]);
            bx[..xc.len()].copy_from_slice(xc);
            if !self.y.is_empty() {
                by[..xc.len()].copy_from_slice(&self.y[k * L::N..k * L::N + xc.len()]);
            }
            let (a, b) = self.f.apply(L::load(bx.as_ptr()), L::load(by.as_ptr()));
            let r = k * L::N..k * L::N + xc.len();
            o0[r.clone()].copy_from_slice(&a.to_array()[..xc.len()]);
            if let Some(o1) = o1.as_deref_mut() {
                o1[r].copy_from_slice(&b.to_array()[..xc.len()]);
            }
        }
    }
}

struct SinCos;
impl LaneFn for SinCos {
    #[inline(always)]
    fn apply<L: Lanes>(&self, x: L, _: L) -> (L, L) {
        x.sin_cos()
    }
}

struct Atan2;
impl LaneFn for Atan2 {
    #[inline(always)]
    fn apply<L: Lanes>(&self, x: L, y: L) -> (L, L) {
        (y.atan2(x), x)
    }
}

/// (sin x, cos x) elementwise with the kernel `isa` would use (for accuracy tests).
pub fn sin_cos_slice(isa: Isa, x: &[f64], s: &mut [f64], c: &mut [f64]) {
    assert!(s.len() == x.len() && c.len() == x.len(), "sin_cos_slice: length mismatch");
    let f = Elementwise { x, y: &[], pad: (0.0, 0.0), out: (s, Some(c)), f: SinCos };
    // SAFETY: lengths checked above.
    unsafe { dispatch(isa, false, f) }
}

/// atan2(y\[i\], x\[i\]) with the kernel `isa` would use (for accuracy tests).
pub fn atan2_slice(isa: Isa, y: &[f64], x: &[f64], out: &mut [f64]) {
    assert!(x.len() == y.len() && out.len() == y.len(), "atan2_slice: length mismatch");
    let f = Elementwise { x, y, pad: (1.0, 0.0), out: (out, None), f: Atan2 };
    // SAFETY: lengths checked above.
    unsafe { dispatch(isa, false, f) }
}

/// A spline's batch evaluation, offered to the engine by `Spline::batch`.
///
/// The engine validates every time (finite, inside the domain), locates its segment
/// (`seg[i]`, the same rule as `Spline::locate`) and hands over runs of samples; kernels
/// broadcast per-segment data while consecutive samples share a segment and gather it
/// otherwise.
pub trait BatchKernel: Send + Sync {
    /// The segment search for times in any order.
    fn locator(&self) -> &Locator;
    /// Rows q, q', …, q^(order) (4·(order+1) numbers) for sample t\[i\] on segment seg\[i\].
    /// Returns false (writing nothing) for orders the kernel does not cover: the engine then
    /// uses the jets.
    fn evaluate(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool;
    /// Rows of angular velocity (order 1), acceleration (2) or jerk (3), 3 numbers each.
    /// Returns false (writing nothing) where the method has no closed form: the engine then
    /// uses the jets.
    fn angular(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, frame: Frame, out: &mut [f64]) -> bool;
}

/// Output kinds of a kernel body: rows q, q', … ([`EVAL`]), angular rates in the body frame
/// ([`BODY`]) or the world frame ([`WORLD`]).
pub(crate) const EVAL: u8 = 0;
/// See [`EVAL`].
pub(crate) const BODY: u8 = 1;
/// See [`EVAL`].
pub(crate) const WORLD: u8 = 2;

/// Numbers per row: 4 (K + 1) for [`EVAL`] up to order K, 3 for rates.
pub(crate) const fn width(k: usize, out: u8) -> usize {
    if out == EVAL {
        4 * (k + 1)
    } else {
        3
    }
}

/// A kernel: a table of flat per-segment records and its body over lanes (the recipe at the
/// top of this module). Every `Kernel` is a [`BatchKernel`].
pub(crate) trait Kernel: Send + Sync {
    /// Names the kernel in its panics ("natural kernel: bad lengths").
    const NAME: &'static str;
    /// The highest derivative order the body evaluates (higher orders keep the jets).
    const ORDERS: usize;
    /// Whether the body has closed-form angular rates ([`BODY`], [`WORLD`]).
    const RATES: bool;
    /// Whether the AVX2 build is also compiled with AVX-512 VL's 32 vector registers (where
    /// the CPU has them), for a body whose working set spills with 16.
    const WIDE_REGISTERS: bool;
    /// The segment search over the table's joints.
    fn locator(&self) -> &Locator;
    /// The number of segments (records).
    fn segments(&self) -> usize;
    /// Rows of kind `OUT` up to order `K` (`width(K, OUT)` numbers each) for sample `t[i]` on
    /// segment `seg[i]`.
    ///
    /// # Safety
    /// `seg.len() == t.len()`, `out.len() == width(K, OUT) · t.len()`, every `seg[i]` below
    /// `segments()`.
    unsafe fn body<L: Lanes, const K: usize, const OUT: u8>(&self, seg: &[u32], t: &[f64], out: &mut [f64]);
}

/// One call of a kernel's body, for [`dispatch`].
struct Body<'a, T, const K: usize, const OUT: u8> {
    tab: &'a T,
    seg: &'a [u32],
    t: &'a [f64],
    out: &'a mut [f64],
}

impl<T: Kernel, const K: usize, const OUT: u8> OnLanes for Body<'_, T, K, OUT> {
    type Out = ();
    #[inline(always)]
    unsafe fn run<L: Lanes>(self) {
        self.tab.body::<L, K, OUT>(self.seg, self.t, self.out)
    }
}

/// The body of order `K`, kind `OUT` on the lanes of `isa`, after checking its preconditions.
fn run_kernel<T: Kernel, const K: usize, const OUT: u8>(
    tab: &T,
    isa: Isa,
    seg: &[u32],
    t: &[f64],
    out: &mut [f64],
) {
    assert!(seg.len() == t.len() && out.len() == t.len() * width(K, OUT), "{} kernel: bad lengths", T::NAME);
    assert!(
        seg.is_empty() || (seg.iter().fold(0, |m, &s| m.max(s)) as usize) < tab.segments(),
        "{} kernel: segment out of range",
        T::NAME
    );
    // SAFETY: lengths and segment indices checked above.
    unsafe { dispatch(isa, T::WIDE_REGISTERS, Body::<T, K, OUT> { tab, seg, t, out }) }
}

impl<T: Kernel> BatchKernel for T {
    fn locator(&self) -> &Locator {
        Kernel::locator(self)
    }

    fn evaluate(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, out: &mut [f64]) -> bool {
        let k = order.min(3);
        if k > T::ORDERS {
            return false;
        }
        match k {
            0 => run_kernel::<T, 0, EVAL>(self, isa, seg, t, out),
            1 => run_kernel::<T, 1, EVAL>(self, isa, seg, t, out),
            2 => run_kernel::<T, 2, EVAL>(self, isa, seg, t, out),
            _ => run_kernel::<T, 3, EVAL>(self, isa, seg, t, out),
        }
        true
    }

    fn angular(&self, isa: Isa, seg: &[u32], t: &[f64], order: usize, frame: Frame, out: &mut [f64]) -> bool {
        if !T::RATES {
            return false;
        }
        match (order, frame) {
            (1, Frame::Body) => run_kernel::<T, 1, BODY>(self, isa, seg, t, out),
            (2, Frame::Body) => run_kernel::<T, 2, BODY>(self, isa, seg, t, out),
            (_, Frame::Body) => run_kernel::<T, 3, BODY>(self, isa, seg, t, out),
            (1, Frame::World) => run_kernel::<T, 1, WORLD>(self, isa, seg, t, out),
            (2, Frame::World) => run_kernel::<T, 2, WORLD>(self, isa, seg, t, out),
            (_, Frame::World) => run_kernel::<T, 3, WORLD>(self, isa, seg, t, out),
        }
        true
    }
}

/// Flag bit of `Locator::start`: the bucket holds more than one joint.
const MULTI: u32 = 1 << 31;

/// Segment search by a bucket index over the domain: bucket b holds the segment of its left
/// edge, then a short walk fixes the answer, so it returns exactly
/// `partition_point(x ≤ t) − 1` clamped to the segments, for any joint spacing.
#[derive(Debug, Clone)]
pub struct Locator {
    joints: Vec<f64>,
    t0: f64,
    inv_w: f64,
    /// The bucket width w: bucket b is [t₀ + b·w, t₀ + (b + 1)·w), edges computed by this
    /// expression (the same rounding at construction and at search).
    w: f64,
    /// The segment of bucket b's left edge, with [`MULTI`] set when more than one joint lies
    /// inside the bucket (then the bucket's segment and the next do not cover it).
    start: Vec<u32>,
    /// The right end of bucket b's first segment (+∞ for the last segment), so that the
    /// first step of an unsorted search does not wait for `start[b]`.
    split: Vec<f64>,
}

impl Locator {
    /// From strictly increasing joints (at least two). Segment indices are `u32` with the top
    /// bit as [`MULTI`]: fewer than 2³⁰ segments (every kernel table is tens of bytes per
    /// segment, so memory ends far sooner).
    pub fn new(joints: &[f64]) -> Self {
        let nseg = joints.len() - 1;
        debug_assert!(nseg < 1 << 30, "Locator: {nseg} segments");
        let nb = 2 * nseg;
        let (t0, t1) = (joints[0], joints[nseg]);
        let w = (t1 - t0) / nb as f64;
        let inv_w = if w > 0.0 && (1.0 / w).is_finite() { 1.0 / w } else { 0.0 };
        // start[b]: the last segment k (< nseg) with joints[k] ≤ the bucket's left edge (k = 0
        // at least) — found by a merge of edges and joints, in parallel blocks of buckets, each
        // block's first by binary search (the same numbers as one merge over all)
        const BLOCK: usize = 8192;
        let first_at = |edge: f64| -> usize { joints[1..nseg].partition_point(|&x| x <= edge) };
        let mut start = vec![0u32; nb + 1];
        let fill = |(c, blk): (usize, &mut [u32])| {
            let b0 = c * BLOCK;
            let mut k = first_at(t0 + b0 as f64 * w);
            for (i, st) in blk.iter_mut().enumerate() {
                let edge = t0 + (b0 + i) as f64 * w;
                while k + 1 < nseg && joints[k + 1] <= edge {
                    k += 1;
                }
                *st = k as u32;
            }
        };
        if nb < 4 * BLOCK {
            start.chunks_mut(BLOCK).enumerate().for_each(fill);
        } else {
            start.par_chunks_mut(BLOCK).enumerate().for_each(fill);
        }
        let split = start[..nb]
            .par_iter()
            .with_min_len(BLOCK)
            .map(|&k| if (k as usize) < nseg - 1 { joints[k as usize + 1] } else { f64::INFINITY })
            .collect();
        // bucket b holds the joints start[b] + 1 … start[b + 1]: at most one, and a time in
        // the bucket lies in segment start[b] or the next, told apart by split[b]
        let multi: Vec<bool> = start.windows(2).map(|p| p[1] - p[0] > 1).collect();
        for (st, m) in start.iter_mut().zip(multi) {
            if m {
                *st |= MULTI;
            }
        }
        start.truncate(nb);
        Locator { joints: crate::spline::par_copy(joints), t0, inv_w, w, start, split }
    }

    /// The segment containing t (the right one at an interior joint, the last at the end).
    ///
    /// For times in any order: the bucket's segment, one step right without a branch (a
    /// bucket is half a mean segment wide, so this settles nearly every time), then a check
    /// that is almost always true (a predictable branch) before the rare longer walk.
    #[inline(always)]
    pub fn locate(&self, t: f64) -> usize {
        let j = &self.joints;
        let last = j.len() - 2;
        // `as usize` saturates: negative and NaN give bucket 0
        let b = (((t - self.t0) * self.inv_w) as usize).min(self.start.len() - 1);
        let k = (self.start[b] & !MULTI) as usize;
        // k ≤ last, so j[k + 1] exists
        let k = k + ((j[k + 1] <= t) & (k < last)) as usize;
        if self.fits(k, t) {
            return k;
        }
        self.walk(k, t)
    }

    #[cold]
    #[inline(never)]
    fn walk(&self, mut k: usize, t: f64) -> usize {
        let j = &self.joints;
        let last = j.len() - 2;
        while k < last && j[k + 1] <= t {
            k += 1;
        }
        while k > 0 && j[k] > t {
            k -= 1;
        }
        k
    }

    /// (a, b) with `fits(k, t)` ⇔ a ≤ t < b for every t (−∞ and +∞ at the ends).
    #[inline(always)]
    pub fn bounds(&self, k: usize) -> (f64, f64) {
        let j = &self.joints;
        let last = j.len() - 2;
        (if k == 0 { f64::NEG_INFINITY } else { j[k] }, if k == last { f64::INFINITY } else { j[k + 1] })
    }

    /// `seg[i]` ← the segment of `t[i]` for a chunk of finite times inside the domain, with
    /// `cur` the segment of the previous sample (updated).
    ///
    /// A chunk in increasing order (`sorted`, which only picks the path: the result is the
    /// same either way) keeps the cursor (its test is predictable there). Any other
    /// chunk takes the bucket search for every sample, whose only data-dependent branch (the
    /// rare long walk) is predictable: a cursor test on times in random order would be a coin
    /// toss per sample (a mispredicted branch costs more than the whole search). With
    /// `isa` AVX2 the bucket search takes four times a step (two gathers); the result is the
    /// same on either instruction set.
    #[inline(always)]
    pub fn locate_run(&self, isa: Isa, t: &[f64], seg: &mut [u32], cur: &mut usize, sorted: bool) {
        let j = &self.joints[..];
        let start = &self.start[..];
        let last = j.len() - 2;
        if last == 0 {
            // one segment (a Bézier curve): nothing to search
            seg.fill(0);
            return;
        }
        if sorted {
            // per segment: locate its first sample, then the run of samples in it by two
            // comparisons a sample (four per branch) and one fill
            let mut c = (*cur).min(last);
            let mut i = 0;
            while i < t.len() {
                let x = t[i];
                // short-circuit tests: predictable on sorted times
                let fits = |k: usize| (j[k] <= x || k == 0) && (x < j[k + 1] || k == last);
                if !fits(c) {
                    c = if c < last && fits(c + 1) { c + 1 } else { self.locate(x) };
                }
                let (ge, lt) = self.bounds(c);
                let fit = |v: f64| (v >= ge) & (v < lt);
                let first = i;
                i += 1;
                while i + 4 <= t.len() && (fit(t[i]) & fit(t[i + 1]) & fit(t[i + 2]) & fit(t[i + 3])) {
                    i += 4;
                }
                while i < t.len() && fit(t[i]) {
                    i += 1;
                }
                seg[first..i].fill(c as u32);
            }
            *cur = c;
            return;
        }
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        // (bucket indices as i32 lanes: below 2³¹ buckets, i.e. 2³⁰ segments)
        if matches!(isa, Isa::Avx2 | Isa::Avx512) && avx2_available() && start.len() < i32::MAX as usize {
            // SAFETY: AVX2 and FMA detected; t and seg have the same length; every bucket
            // index fits an i32 lane
            done = unsafe { self.locate_unsorted_avx2(t, seg) };
        }
        let _ = isa;
        let (t0, inv_w, w, nb) = (self.t0, self.inv_w, self.w, start.len() - 1);
        let split = &self.split[..nb + 1];
        for (s, &x) in seg[done..].iter_mut().zip(&t[done..]) {
            let y = (x - t0) * inv_w;
            debug_assert!((0.0..=(nb + 2) as f64).contains(&y), "locate_run: time outside the domain");
            // SAFETY: t0 ≤ x ≤ the last joint (the caller's domain check), so y is finite and
            // in [0, nb + 1]
            let b = (unsafe { y.to_int_unchecked::<i64>() } as usize).min(nb);
            // start[b] and split[b] load side by side (no dependent load before the step)
            let st = start[b];
            let k = (st & !MULTI) as usize + (split[b] <= x) as usize;
            // x inside bucket b by the construction's own edges (recomputed, not loaded) and
            // at most one joint inside: k is exact without reading the joints. Else (a time
            // that rounding put in a neighbouring bucket, a crowded bucket) the joints decide.
            let (lo, hi) = (t0 + b as f64 * w, t0 + (b + 1) as f64 * w);
            // (`||`: the joints are read only where the bucket test fails)
            let sure = (st & MULTI == 0) & (lo <= x) & (x < hi);
            *s = if sure || self.fits(k, x) { k } else { self.walk(k, x) } as u32;
        }
        *cur = seg.last().map_or(*cur, |&k| k as usize);
    }

    /// The bucket search of `locate_run` four samples at a time, for the first multiple of 4
    /// of `t`; returns how many it located. Per lane as the scalar loop: bucket b by
    /// truncation (clamped to the buckets), start[b] and split[b] by gathers, k = start[b] +
    /// (split[b] ≤ x), accepted when x lies in [t₀ + b·w, t₀ + (b + 1)·w) (the same products
    /// and sums as the construction, no fused multiply-add) and the bucket is single; other
    /// lanes are settled by the joints as in the scalar loop.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn locate_unsorted_avx2(&self, t: &[f64], seg: &mut [u32]) -> usize {
        use std::arch::x86_64::*;
        let n4 = t.len().min(seg.len()) / 4 * 4;
        let nb = self.start.len() - 1;
        debug_assert_eq!(self.split.len(), self.start.len());
        let (t0, inv_w, w) = (_mm256_set1_pd(self.t0), _mm256_set1_pd(self.inv_w), _mm256_set1_pd(self.w));
        let one = _mm256_set1_pd(1.0);
        let (zero, top) = (_mm_setzero_si128(), _mm_set1_epi32(nb as i32));
        let low_bits = _mm_set1_epi32(!MULTI as i32);
        let even = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
        let (sp, pp) = (self.start.as_ptr() as *const i32, self.split.as_ptr());
        let mut i = 0;
        while i < n4 {
            let x = _mm256_loadu_pd(t.as_ptr().add(i));
            let y = _mm256_mul_pd(_mm256_sub_pd(x, t0), inv_w);
            // NaN and out-of-range give i32::MIN: clamped into [0, nb] (then rejected below)
            let b = _mm_min_epi32(_mm_max_epi32(_mm256_cvttpd_epi32(y), zero), top);
            let st = _mm_i32gather_epi32::<4>(sp, b);
            let split = _mm256_i32gather_pd::<8>(pp, b);
            let le = _mm256_castpd_si256(_mm256_cmp_pd::<_CMP_LE_OQ>(split, x));
            // the 64-bit masks' low halves: −1 where split[b] ≤ x
            let le = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(le, even));
            let k = _mm_sub_epi32(_mm_and_si128(st, low_bits), le);
            let bf = _mm256_cvtepi32_pd(b);
            let lo = _mm256_add_pd(t0, _mm256_mul_pd(bf, w));
            let hi = _mm256_add_pd(t0, _mm256_mul_pd(_mm256_add_pd(bf, one), w));
            let inside =
                _mm256_and_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(lo, x), _mm256_cmp_pd::<_CMP_LT_OQ>(x, hi));
            // MULTI is the sign bit of start[b]
            let ok = _mm256_movemask_pd(inside) & !_mm_movemask_ps(_mm_castsi128_ps(st)) & 0xF;
            _mm_storeu_si128(seg.as_mut_ptr().add(i) as *mut __m128i, k);
            if ok != 0xF {
                for l in 0..4 {
                    if ok & (1 << l) == 0 {
                        let (x, k) = (*t.get_unchecked(i + l), *seg.get_unchecked(i + l) as usize);
                        *seg.get_unchecked_mut(i + l) =
                            if self.fits(k, x) { k } else { self.walk(k, x) } as u32;
                    }
                }
            }
            i += 4;
        }
        n4
    }

    /// Whether t lies in segment k by the `locate` rule (no branch: the comparisons are
    /// combined as booleans, so a caller's test on the result is the only branch).
    #[inline(always)]
    pub fn fits(&self, k: usize, t: f64) -> bool {
        let j = &self.joints;
        let last = j.len() - 2;
        ((j[k] <= t) | (k == 0)) & ((t < j[k + 1]) | (k == last))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locator_equals_partition_point() {
        // 300 joints: the one-thread table; 40 000: the table built in parallel blocks
        for n in [300, 40_000] {
            locator_equals_partition_point_at(n);
        }
    }

    fn locator_equals_partition_point_at(n: usize) {
        let mut joints = vec![0.0];
        let mut x: u64 = 7;
        for _ in 0..n {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let h = if (x >> 60) < 3 { 1e-6 } else { ((x >> 11) as f64 / (1u64 << 53) as f64) * 5.0 + 1e-3 };
            joints.push(joints.last().unwrap() + h);
        }
        let loc = Locator::new(&joints);
        let last = joints.len() - 2;
        let reference = |t: f64| joints.partition_point(|&v| v <= t).saturating_sub(1).min(last);
        let mut probes: Vec<f64> = joints.clone();
        for w in joints.windows(2) {
            probes.push(0.5 * (w[0] + w[1]));
            probes.push(f64::from_bits(w[1].to_bits() - 1));
        }
        probes.extend([-1.0, joints[0] - 1e-300, joints[last + 1] + 1.0]);
        for t in probes {
            assert_eq!(loc.locate(t), reference(t), "t = {t}");
            // the engine's run test: fits(k, t) ⇔ a ≤ t < b
            for k in [0, 1, reference(t).saturating_sub(1), reference(t), (reference(t) + 1).min(last), last]
            {
                let (a, b) = loc.bounds(k);
                assert_eq!(loc.fits(k, t), a <= t && t < b, "k = {k}, t = {t}");
            }
        }
    }

    /// `locate_run` on both of its paths (the cursor for sorted chunks, the bucket search for
    /// others) equals `partition_point`, for chunks of every length 0–9 and a long one,
    /// sorted and shuffled, with joints, just-below-joint times and both domain ends.
    #[test]
    fn locate_run_equals_partition_point_on_both_paths() {
        let mut x: u64 = 11;
        let mut next = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        // crowded buckets (1e-7 steps) among wide ones
        let mut joints = vec![-2.0];
        for _ in 0..120 {
            let h = if next() < 0.15 { 1e-7 } else { 0.01 + 3.0 * next() };
            joints.push(joints.last().unwrap() + h);
        }
        let mut sets = vec![joints];
        // uniform keys: every joint on a bucket edge; the same at a Unix-epoch offset (edges
        // and joints rounded to 2.4e-7) and at a large negative one
        sets.push((0..=200).map(f64::from).collect());
        sets.push((0..=300).map(|i| 1.7e9 + 0.01 * i as f64).collect());
        sets.push((0..=97).map(|i| -3.3e7 + 0.3 * i as f64).collect());
        // jittered keys, no crowding: bucket search without the joints nearly everywhere
        let mut jit = vec![5.0];
        for _ in 0..150 {
            jit.push(jit.last().unwrap() + 0.8 + 0.4 * next());
        }
        sets.push(jit);
        // both kinds of bucket occur: crowded ones (the joints decide) and single ones
        assert!(Locator::new(&sets[0]).start.iter().any(|&k| k & MULTI != 0));
        assert!(Locator::new(&sets[1]).start.iter().all(|&k| k & MULTI == 0));
        for joints in &sets {
            check_locate_run(joints, &mut next);
        }
        // one segment (Bézier curves): every time on segment 0, ends included
        let one = Locator::new(&[-2.0, 5.0]);
        let c = [5.0, -2.0, 0.3, 4.999, -1.0];
        for sorted in [false, true] {
            let t = if sorted { &c[2..4] } else { &c[..] };
            let mut seg = vec![7u32; t.len()];
            let mut cur = 0;
            one.locate_run(Isa::Avx2, t, &mut seg, &mut cur, sorted);
            assert!(seg.iter().all(|&k| k == 0) && cur == 0, "{seg:?}");
        }
    }

    fn check_locate_run(joints: &[f64], next: &mut impl FnMut() -> f64) {
        let loc = Locator::new(joints);
        let last = joints.len() - 2;
        let reference = |t: f64| joints.partition_point(|&v| v <= t).saturating_sub(1).min(last);
        let (a, b) = (joints[0], joints[last + 1]);
        let mut t: Vec<f64> = joints.to_vec();
        for w in joints.windows(2) {
            t.push(f64::from_bits(w[1].to_bits() - 1));
            t.push(f64::from_bits(w[0].to_bits() + 1));
            t.push(w[0] + 0.37 * (w[1] - w[0]));
        }
        // bucket edges as the locator computes them, and the times either side
        for e in (0..=loc.start.len()).map(|k| loc.t0 + k as f64 * loc.w) {
            t.extend([e.next_down(), e, e.next_up()]);
        }
        t.retain(|&v| (a..=b).contains(&v));
        t.extend((0..500).map(|_| a + (b - a) * next()));
        t.sort_by(f64::total_cmp);
        let mut u = t.clone();
        for i in (1..u.len()).rev() {
            u.swap(i, (next() * (i + 1) as f64) as usize);
        }
        for times in [&t, &u] {
            let mut cases: Vec<&[f64]> = (0..=9).map(|n| &times[40..40 + n]).collect();
            cases.push(&times[..]);
            for c in cases {
                for sorted in [true, false] {
                    if sorted && !c.windows(2).all(|w| w[0] <= w[1]) {
                        continue;
                    }
                    for (start_cur, isa) in [
                        (0, Isa::Scalar),
                        (last / 2, Isa::Avx2),
                        (last, Isa::Scalar),
                        (0, Isa::Avx2),
                        (last / 3, Isa::Avx512),
                    ] {
                        let mut seg = vec![u32::MAX; c.len()];
                        let mut cur = start_cur;
                        loc.locate_run(isa, c, &mut seg, &mut cur, sorted);
                        for (k, &x) in c.iter().enumerate() {
                            assert_eq!(
                                seg[k] as usize,
                                reference(x),
                                "t = {x}, sorted path {sorted}, {isa:?}"
                            );
                        }
                        if let Some(&x) = c.last() {
                            assert_eq!(cur, reference(x));
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn mode_names() {
        assert_eq!(parse_mode("off"), Some(Mode::Scalar));
        assert_eq!(parse_mode("Reference"), Some(Mode::Reference));
        assert_eq!(parse_mode("auto"), Some(Mode::Auto));
        assert_eq!(parse_mode("AVX512"), Some(Mode::Avx512));
        assert_eq!(parse_mode("avx2"), Some(Mode::Avx2));
        assert_eq!(parse_mode("bogus"), None);
    }

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (b.abs().max(f64::MIN_POSITIVE) * f64::EPSILON)
    }

    /// The vector sin/cos against libm over the ranges the kernels meet (angles up to a few π,
    /// shape-parameter-scaled angles up to 1e5) and the fallback range beyond 823549.6.
    #[test]
    fn vector_sin_cos_within_two_ulp_of_libm() {
        for isa in [Isa::Scalar, Isa::Avx2, Isa::Avx512].into_iter().filter(|i| i.available()) {
            let mut x: Vec<f64> = (0..400_001).map(|i| -20.0 + 40.0 * i as f64 / 400_000.0).collect();
            x.extend((0..20_000).map(|i| 1e5 * (i as f64 / 20_000.0).powi(3)));
            x.extend([0.0, -0.0, 1e-300, 5e-324, 1e-8, 823_549.5, 823_549.7, 1e7, -3e9, 1e300]);
            x.extend((1..200).map(|k| k as f64 * std::f64::consts::FRAC_PI_2));
            let (mut s, mut c) = (vec![0.0; x.len()], vec![0.0; x.len()]);
            sin_cos_slice(isa, &x, &mut s, &mut c);
            let mut worst: f64 = 0.0;
            for i in 0..x.len() {
                let (rs, rc) = x[i].sin_cos();
                for (a, b) in [(s[i], rs), (c[i], rc)] {
                    if b.abs() > 1e-3 {
                        worst = worst.max(ulps(a, b));
                    } else {
                        // near a zero of sin/cos: ulps of the result, plus the reduction's
                        // absolute error (≈ |x| · 2⁻¹⁰⁰ from the 3-part π/2)
                        let tol = 2.0 * f64::EPSILON * b.abs() + 1e-28 * x[i].abs().max(1.0);
                        assert!((a - b).abs() <= tol, "{isa:?} {}: {a} vs {b}", x[i]);
                    }
                }
            }
            assert!(worst <= 2.0, "{isa:?}: worst {worst} ulp");
            let (mut s, mut c) = ([0.0; 3], [0.0; 3]);
            sin_cos_slice(isa, &[f64::NAN, f64::INFINITY, 1.0], &mut s, &mut c);
            assert!(s[0].is_nan() && c[0].is_nan() && s[1].is_nan() && c[1].is_nan());
            assert!(ulps(s[2], 1f64.sin()) <= 1.0 && ulps(c[2], 1f64.cos()) <= 1.0);
        }
    }
}
