//! Times the 8-point spherical Bézier value kernel on one core (best of 10; a quick profile,
//! not a benchmark): control points 0.05–0.3 rad apart (halved), the benchmark's curve.
use quatspline::spline::*;
use quatspline::Quat;
use std::time::Instant;

fn main() {
    let mut rng = quatspline::testing::XorShift64::new(4);
    let mut next = || rng.uniform();
    for (label, lo, hi) in [("half-angles 0.05–0.3", 0.05, 0.3), ("half-angles 0.02–0.15", 0.02, 0.15)] {
        let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
        for _ in 1..8 {
            let a = lo + (hi - lo) * next();
            let ax = [next() - 0.5, next() - 0.5, next() - 0.5];
            let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
            let (s, c) = a.sin_cos();
            let last = *q.last().unwrap();
            q.push(last * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
        }
        let s = SphericalBezier::new(&q, (0.0, 999.0), true).unwrap();
        let t: Vec<f64> = (0..1_000_000).map(|i| i as f64 * 999.0 / 1e6).collect();
        let mut out = vec![0.0; 4 * t.len()];
        let mut best = f64::MAX;
        for _ in 0..10 {
            let start = Instant::now();
            evaluate_into(&s, &t, 0, 0, Extrapolate::Raise, &mut out).unwrap();
            best = best.min(start.elapsed().as_secs_f64());
        }
        let sum: f64 = out.iter().sum();
        println!(
            "spherical Bézier 8 points, {label}: {:.2} ns/sample ({sum:.6})",
            best * 1e9 / t.len() as f64
        );
    }
}
