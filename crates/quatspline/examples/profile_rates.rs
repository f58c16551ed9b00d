//! ω, α and jerk of the natural spline and the cubic B-spline on one core (best of 10).
use quatspline::spline::*;
use quatspline::Quat;
use std::time::Instant;

fn main() {
    let n = 1000;
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for k in 1..n {
        let a = 0.3 + 0.05 * (k % 8) as f64;
        let (s, c) = (0.5 * a).sin_cos();
        let ax = [(k as f64).sin(), (1.7 * k as f64).cos(), 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        q.push(q[k - 1] * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
    let t: Vec<f64> = (0..1_000_000).map(|i| i as f64 * 996.0 / 1e6).collect();
    let splines: Vec<Box<dyn Spline>> = vec![
        Box::new(NaturalSpline::new(&q, None, NaturalEnds::Natural, true).unwrap()),
        Box::new(CumulativeBSpline::new(&q, 1.0, 0.0, 4, true).unwrap()),
    ];
    let mut out = vec![0.0; 3 * t.len()];
    for s in &splines {
        let mut row = Vec::new();
        for order in 1..=3 {
            let mut best = f64::MAX;
            for _ in 0..10 {
                let start = Instant::now();
                angular_into(&**s, &t, 0, order, Frame::World, Extrapolate::Raise, &mut out).unwrap();
                best = best.min(start.elapsed().as_secs_f64());
            }
            row.push(best * 1e9 / t.len() as f64);
        }
        println!("{}: ω {:.2}  α {:.2}  jerk {:.2} ns/sample", s.name(), row[0], row[1], row[2]);
    }
}
