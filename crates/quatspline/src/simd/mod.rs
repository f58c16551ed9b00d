//! The batch evaluation engine's kernels: per-segment data precomputed flat, samples processed
//! a vector at a time, the instruction set chosen at run time.
//!
//! * [`Isa`]: AVX2 + FMA when `is_x86_feature_detected!` finds both, else the portable scalar
//!   kernel (same code, one lane). One build runs everywhere; nothing needs
//!   `target-cpu=native`.
//! * [`mode`] / [`set_mode`]: `QUATSPLINE_SIMD=auto|scalar|reference` (read once) or
//!   [`set_mode`] at run time. `scalar` forces the portable kernels, `reference` the per-sample
//!   jet path that every kernel is tested against.
//! * [`BatchKernel`]: what a spline offers the engine (`Spline::batch`): rows for samples
//!   whose segments the engine has located.
//! * [`Locator`]: segment search for unsorted times in O(1) expected (bucket index), picking
//!   exactly the segment `Spline::locate` picks.
//!
//! Results are a function of each sample alone (never of its neighbours, its position in a
//! vector or a thread's chunk), so they are bit-identical for any thread count and chunking.

pub mod cumulative;
pub mod engine;
pub(crate) mod lanes;
pub mod natural;
pub mod pairs;
pub mod slerp;

use crate::spline::Frame;
use std::sync::atomic::{AtomicU8, Ordering};

/// The instruction set a kernel runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// Portable scalar code (one sample at a time).
    Scalar,
    /// AVX2 + FMA, four samples per vector (x86-64, detected at run time).
    Avx2,
}

impl Isa {
    /// "avx2" or "scalar".
    pub fn name(self) -> &'static str {
        match self {
            Isa::Scalar => "scalar",
            Isa::Avx2 => "avx2",
        }
    }
}

/// The engine's mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The best kernels the CPU supports.
    Auto,
    /// Batch kernels, portable scalar instruction set.
    Scalar,
    /// No batch kernels: the per-sample jet path (the reference).
    Reference,
}

const UNSET: u8 = 0;
static MODE: AtomicU8 = AtomicU8::new(UNSET);

fn encode(m: Mode) -> u8 {
    match m {
        Mode::Auto => 1,
        Mode::Scalar => 2,
        Mode::Reference => 3,
    }
}

/// Parses a mode name: `auto`/`on`, `scalar`/`off`, `reference`.
pub fn parse_mode(s: &str) -> Option<Mode> {
    match s.trim().to_ascii_lowercase().as_str() {
        "" | "auto" | "on" | "1" => Some(Mode::Auto),
        "scalar" | "off" | "0" => Some(Mode::Scalar),
        "reference" | "ref" => Some(Mode::Reference),
        _ => None,
    }
}

/// The current mode (first call reads `QUATSPLINE_SIMD`; an unknown value means `auto`).
pub fn mode() -> Mode {
    match MODE.load(Ordering::Relaxed) {
        1 => Mode::Auto,
        2 => Mode::Scalar,
        3 => Mode::Reference,
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

/// The instruction set batch kernels use now; None in reference mode.
pub fn isa() -> Option<Isa> {
    match mode() {
        Mode::Reference => None,
        Mode::Scalar => Some(Isa::Scalar),
        Mode::Auto => Some(if avx2_available() { Isa::Avx2 } else { Isa::Scalar }),
    }
}

/// (sin x, cos x) elementwise with the kernel `isa` would use (for accuracy tests).
pub fn sin_cos_slice(isa: Isa, x: &[f64], s: &mut [f64], c: &mut [f64]) {
    assert!(s.len() == x.len() && c.len() == x.len(), "sin_cos_slice: length mismatch");
    #[cfg(target_arch = "x86_64")]
    if isa == Isa::Avx2 && avx2_available() {
        // SAFETY: AVX2 and FMA detected.
        unsafe { lanes::avx2_sin_cos_slice(x, s, c) };
        return;
    }
    let _ = isa;
    for i in 0..x.len() {
        (s[i], c[i]) = crate::special::sin_cos(x[i]);
    }
}

/// atan2(y\[i\], x\[i\]) with the kernel `isa` would use (for accuracy tests).
pub fn atan2_slice(isa: Isa, y: &[f64], x: &[f64], out: &mut [f64]) {
    assert!(x.len() == y.len() && out.len() == y.len(), "atan2_slice: length mismatch");
    lanes::atan2_slice(isa == Isa::Avx2 && avx2_available(), y, x, out);
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

/// Segment search by a bucket index over the domain: bucket b holds the segment of its left
/// edge, then a short walk fixes the answer, so it returns exactly
/// `partition_point(x ≤ t) − 1` clamped to the segments, for any joint spacing.
#[derive(Debug, Clone)]
pub struct Locator {
    joints: Vec<f64>,
    t0: f64,
    inv_w: f64,
    start: Vec<u32>,
}

impl Locator {
    /// From strictly increasing joints (at least two).
    pub fn new(joints: &[f64]) -> Self {
        let nseg = joints.len() - 1;
        let nb = 2 * nseg;
        let (t0, t1) = (joints[0], joints[nseg]);
        let w = (t1 - t0) / nb as f64;
        let inv_w = if w > 0.0 && (1.0 / w).is_finite() { 1.0 / w } else { 0.0 };
        let mut start = Vec::with_capacity(nb);
        let mut k = 0usize;
        for b in 0..nb {
            let edge = t0 + b as f64 * w;
            while k + 1 < nseg && joints[k + 1] <= edge {
                k += 1;
            }
            start.push(k as u32);
        }
        Locator { joints: joints.to_vec(), t0, inv_w, start }
    }

    /// The segment containing t (the right one at an interior joint, the last at the end).
    #[inline(always)]
    pub fn locate(&self, t: f64) -> usize {
        let j = &self.joints;
        let last = j.len() - 2;
        let x = (t - self.t0) * self.inv_w;
        let b = if x > 0.0 { (x as usize).min(self.start.len() - 1) } else { 0 };
        let mut k = self.start[b] as usize;
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

    /// Whether t lies in segment k by the `locate` rule.
    #[inline(always)]
    pub fn fits(&self, k: usize, t: f64) -> bool {
        let j = &self.joints;
        let last = j.len() - 2;
        (j[k] <= t || k == 0) && (t < j[k + 1] || k == last)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locator_equals_partition_point() {
        let mut joints = vec![0.0];
        let mut x: u64 = 7;
        for _ in 0..300 {
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

    #[test]
    fn mode_names() {
        assert_eq!(parse_mode("off"), Some(Mode::Scalar));
        assert_eq!(parse_mode("Reference"), Some(Mode::Reference));
        assert_eq!(parse_mode("auto"), Some(Mode::Auto));
        assert_eq!(parse_mode("bogus"), None);
    }

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (b.abs().max(f64::MIN_POSITIVE) * f64::EPSILON)
    }

    /// The vector sin/cos against libm over the ranges the kernels meet (angles up to a few π,
    /// shape-parameter-scaled angles up to 1e5) and the fallback range beyond 823549.6.
    #[test]
    fn vector_sin_cos_within_two_ulp_of_libm() {
        for isa in [Isa::Scalar, Isa::Avx2] {
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
