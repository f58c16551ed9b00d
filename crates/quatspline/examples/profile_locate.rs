//! Unsorted segment search alone, scalar and AVX2 (`cargo run --release --example profile_locate`):
//! 1,000 uniform keys, 10⁶ random times, best of 20 passes.
use quatspline::simd::{Isa, Locator};
use std::time::Instant;
fn main() {
    let joints: Vec<f64> = (0..=999).map(|i| i as f64).collect();
    let loc = Locator::new(&joints);
    let n = 1_000_000;
    let mut rng = quatspline::testing::XorShift64::new(3);
    let t: Vec<f64> = (0..n).map(|_| 999.0 * rng.uniform()).collect();
    let mut seg = vec![0u32; n];
    for isa in [Isa::Scalar, Isa::Avx2] {
        let mut best = f64::MAX;
        for _ in 0..20 {
            let s = Instant::now();
            let mut cur = 0;
            for (tc, sc) in t.chunks(256).zip(seg.chunks_mut(256)) {
                loc.locate_run(isa, tc, sc, &mut cur, false);
            }
            best = best.min(s.elapsed().as_secs_f64());
        }
        println!(
            "{isa:?} unsorted locate_run: {:.2} ns/sample (checksum {})",
            best / n as f64 * 1e9,
            seg.iter().map(|&v| v as u64).sum::<u64>()
        );
    }
}
