//! Shared support of the batch-kernel tests (`simd_kernels.rs`, `simd_slerp_kernels.rs`):
//! deterministic numbers and keys, probe times, the kernel and reference rows, and the one
//! error measure with its documented bound.

// Each test file uses its own part of this module.
#![allow(dead_code)]

use quatspline::simd::{self, Isa};
use quatspline::spline::{angular_reference_into, evaluate_reference_into, Extrapolate, Frame, Spline};
use quatspline::Quat;

/// Deterministic xorshift numbers in [0, 1).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A random unit quaternion (components uniform, norm above 0.1 before normalising).
    pub fn quat(&mut self) -> Quat {
        loop {
            let q = Quat::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5, self.next() - 0.5);
            if q.norm() > 0.1 {
                return q.normalize();
            }
        }
    }
}

/// Keys of a random walk: each step a rotation by step · (0.2 … 1.2) rad about a random axis.
pub fn walk(n: usize, seed: u64, step: f64) -> Vec<Quat> {
    let mut r = Rng(seed);
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for _ in 1..n {
        let a = step * (0.2 + r.next());
        let ax = [r.next() - 0.5, r.next() - 0.5, r.next() - 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let (s, c) = (0.5 * a).sin_cos();
        let next = *q.last().unwrap() * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m);
        q.push(next);
    }
    q
}

/// Increasing key times from −3 with steps 0.05 … 2.05.
pub fn times(n: usize, seed: u64) -> Vec<f64> {
    let mut r = Rng(seed);
    let mut t = vec![-3.0];
    for _ in 1..n {
        t.push(t.last().unwrap() + 0.05 + 2.0 * r.next());
    }
    t
}

/// Times that exercise the kernels: joints, just around them, midpoints (the cumulative
/// kernels' half switch) and just above, ends, and `random` interior points.
pub fn probe_times(s: &dyn Spline, seed: u64, random: usize) -> Vec<f64> {
    let j = s.joints();
    let (a, b) = s.domain();
    let mut t = Vec::new();
    for w in j.windows(2) {
        let (l, r) = (w[0], w[1]);
        let mid = l + 0.5 * (r - l);
        t.extend([
            l,
            f64::from_bits(l.to_bits() + 1),
            mid,
            f64::from_bits(mid.to_bits() + 1),
            l + 0.3 * (r - l),
        ]);
        t.push(f64::from_bits(r.to_bits() - 1));
    }
    t.push(b);
    let mut r = Rng(seed);
    t.extend((0..random).map(|_| a + (b - a) * r.next()));
    t.retain(|&x| x >= a && x <= b);
    t
}

/// `t` in a random order.
pub fn shuffled(t: &[f64], seed: u64) -> Vec<f64> {
    let mut u = t.to_vec();
    let mut r = Rng(seed);
    for i in (1..u.len()).rev() {
        u.swap(i, (r.next() * (i + 1) as f64) as usize);
    }
    u
}

/// The instruction sets this machine runs.
pub fn isas() -> Vec<Isa> {
    let mut v = vec![Isa::Scalar];
    if simd::avx2_available() {
        v.push(Isa::Avx2);
    }
    if simd::avx512_available() {
        v.push(Isa::Avx512);
    }
    v
}

/// The documented bound by derivative order k (see [`max_rel`] for the scale): 1e-14 for q,
/// q' and ω; 5e-14 for k = 2 and 1e-13 for k = 3, where two roundings of the same formula
/// (the AVX2 and scalar kernels) already differ by 2e-14 on the C³ spline's degree-7 weights.
pub const TOL: [f64; 4] = [1e-14, 1e-14, 5e-14, 1e-13];

/// Worst |a − b| / (scale · TOL\[k\]) over the rows (≤ 1 passes), per quantity (one
/// quaternion of 4 numbers or one rate vector of 3): scale = max(1, |b's quantity|, h⁻ᵏ) for a
/// k-th derivative on a segment of length h — the bound is relative in the local parameter u,
/// where every derivative is of order one; in time the k-th derivative carries h⁻ᵏ and so does
/// its rounding error. `ang` is the order of angular rows (width 3). Every number of `a` must
/// be finite.
pub fn max_rel(s: &dyn Spline, t: &[f64], a: &[f64], b: &[f64], width: usize, ang: usize) -> f64 {
    assert_eq!(a.len(), b.len());
    let block = if width.is_multiple_of(4) { 4 } else { 3 };
    let j = s.joints();
    let mut worst: f64 = 0.0;
    for (i, (ra, rb)) in a.chunks(width).zip(b.chunks(width)).enumerate() {
        let seg = s.locate(t[i]);
        let h = j[seg + 1] - j[seg];
        for (m, (qa, qb)) in ra.chunks(block).zip(rb.chunks(block)).enumerate() {
            let k = if block == 4 { m } else { ang };
            let size = qb.iter().map(|v| v * v).sum::<f64>().sqrt();
            let scale = size.max(1.0).max(h.powi(-(k as i32)));
            for (x, y) in qa.iter().zip(qb) {
                assert!(x.is_finite(), "non-finite row {i}");
                worst = worst.max((x - y).abs() / scale / TOL[k]);
            }
        }
    }
    worst
}

/// The spline's batch kernel rows of order `order` for `t`, segments by `Spline::locate`.
pub fn kernel_eval(s: &dyn Spline, isa: Isa, t: &[f64], order: usize) -> Vec<f64> {
    let seg: Vec<u32> = t.iter().map(|&x| s.locate(x) as u32).collect();
    let mut out = vec![f64::NAN; t.len() * 4 * (order + 1)];
    assert!(
        s.batch().expect("batch kernel").evaluate(isa, &seg, t, order, &mut out),
        "{}: the kernel declined order {order}",
        s.name()
    );
    out
}

/// The spline's batch kernel rates (closed form expected).
pub fn kernel_angular(s: &dyn Spline, isa: Isa, t: &[f64], order: usize, frame: Frame) -> Vec<f64> {
    let seg: Vec<u32> = t.iter().map(|&x| s.locate(x) as u32).collect();
    let mut out = vec![f64::NAN; t.len() * 3];
    assert!(
        s.batch().expect("batch kernel").angular(isa, &seg, t, order, frame, &mut out),
        "{}: closed-form rates expected",
        s.name()
    );
    out
}

/// The per-sample reference rows (jets).
pub fn reference_eval(s: &dyn Spline, t: &[f64], order: usize) -> Vec<f64> {
    let mut out = vec![0.0; t.len() * 4 * (order + 1)];
    evaluate_reference_into(s, t, 0, order, Extrapolate::Raise, &mut out).unwrap();
    out
}

/// The per-sample reference rates (jets).
pub fn reference_angular(s: &dyn Spline, t: &[f64], order: usize, frame: Frame) -> Vec<f64> {
    let mut out = vec![0.0; t.len() * 3];
    angular_reference_into(s, t, 0, order, frame, Extrapolate::Raise, &mut out).unwrap();
    out
}
