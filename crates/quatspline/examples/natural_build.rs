//! Construction time of a natural spline on N uniformly random keys (issue 2.5: 10⁶ keys in
//! ≤ 2 s). `cargo run --release -p quatspline --example natural_build -- 1000000 3`
//! prints the best of the runs.

use quatspline::spline::{NaturalEnds, NaturalSpline};
use quatspline::Quat;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1_000_000);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    // xorshift normals by Box–Muller: uniformly random rotations
    let mut rng = quatspline::testing::XorShift64::new(0x9E37_79B9_7F4A_7C15);
    let mut uni = || ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let mut normal = || (-2.0 * uni().ln()).sqrt() * (2.0 * std::f64::consts::PI * uni()).cos();
    let keys: Vec<Quat> = (0..n).map(|_| Quat::new(normal(), normal(), normal(), normal())).collect();
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let s = NaturalSpline::new(&keys, None, NaturalEnds::Natural, true).expect("natural spline");
        best = best.min(t0.elapsed().as_secs_f64());
        std::hint::black_box(s);
    }
    println!("NaturalSpline::new, {n} random keys: {best:.3} s (best of {reps})");
}
