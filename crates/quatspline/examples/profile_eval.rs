//! Times the value path of a few splines on one core, and the angular rates (ω, α, jerk) of
//! the natural spline and the cubic B-spline (a quick profile, not a benchmark).
use quatspline::spline::*;
use quatspline::Quat;
use std::time::Instant;

fn main() {
    let q = quatspline::testing::profile_keys(1000);
    let t: Vec<f64> = (0..1_000_000).map(|i| i as f64 * 996.0 / 1e6).collect();
    let splines: Vec<Box<dyn Spline>> = vec![
        Box::new(PiecewiseSlerp::new(&q, None, true).unwrap()),
        Box::new(CumulativeBSpline::new(&q, 1.0, 0.0, 4, true).unwrap()),
        Box::new(C3Spline::new(&q, None, &[0.3125], &[0.0], C3Variant::Knot, true).unwrap()),
    ];
    pieces(&t);
    let mut out = vec![0.0; 4 * t.len()];
    for s in &splines {
        evaluate_into(&**s, &t, 0, 0, Extrapolate::Raise, &mut out).unwrap();
        let start = Instant::now();
        evaluate_into(&**s, &t, 0, 0, Extrapolate::Raise, &mut out).unwrap();
        println!("{}: {:.1} ns/sample", s.name(), start.elapsed().as_nanos() as f64 / t.len() as f64);
        let start = Instant::now();
        let mut acc = 0.0;
        for &ti in &t {
            acc += s.segment_jet1(s.locate(ti), ti).value().w;
        }
        println!("  raw loop {:.1} ns/sample ({acc:.3})", start.elapsed().as_nanos() as f64 / t.len() as f64);
    }
    rates(&q, &t);
    let start = Instant::now();
    let mut acc = 0.0;
    for &ti in &t {
        acc += quatspline::special::sin_cos(ti * 1e-3).0;
    }
    println!("sin_cos: {:.1} ns ({acc:.3})", start.elapsed().as_nanos() as f64 / t.len() as f64);
    let start = Instant::now();
    let mut acc = 0.0;
    for &ti in &t {
        acc += (ti * 1e-3).sin_cos().0;
    }
    println!("libm sin_cos: {:.1} ns ({acc:.3})", start.elapsed().as_nanos() as f64 / t.len() as f64);
}

#[allow(dead_code)]
pub fn pieces(t: &[f64]) {
    use quatspline::jet::{Axis, JQuat, Jet};
    let ax = Axis { n: [0.6, 0.0, 0.8], a: 0.7 };
    let start = Instant::now();
    let mut acc = JQuat::<1>::constant(Quat::IDENTITY);
    for &ti in t {
        let u = Jet::<1>::variable(ti * 1e-3, 1.0);
        acc = JQuat::constant(Quat::new(0.5, 0.5, 0.5, 0.5)) * JQuat::exp_axis(&ax, u);
    }
    println!(
        "exp_axis+mul: {:.1} ns ({:?})",
        start.elapsed().as_nanos() as f64 / t.len() as f64,
        acc.value().w
    );
    let start = Instant::now();
    let mut a2 = Quat::IDENTITY;
    for &ti in t {
        let (s, c) = quatspline::special::sin_cos(ti * 1e-3 * 0.7);
        a2 = Quat::new(0.5, 0.5, 0.5, 0.5) * Quat::new(c, s * 0.6, 0.0, s * 0.8);
    }
    println!("plain quat: {:.1} ns ({:?})", start.elapsed().as_nanos() as f64 / t.len() as f64, a2.w);
}

/// ω, α and jerk (world frame) of the natural spline and the cubic B-spline, best of 10.
pub fn rates(q: &[Quat], t: &[f64]) {
    let splines: Vec<Box<dyn Spline>> = vec![
        Box::new(NaturalSpline::new(q, None, NaturalEnds::Natural, true).unwrap()),
        Box::new(CumulativeBSpline::new(q, 1.0, 0.0, 4, true).unwrap()),
    ];
    let mut out = vec![0.0; 3 * t.len()];
    for s in &splines {
        let mut row = Vec::new();
        for order in 1..=3 {
            let mut best = f64::MAX;
            for _ in 0..10 {
                let start = Instant::now();
                angular_into(&**s, t, 0, order, Frame::World, Extrapolate::Raise, &mut out).unwrap();
                best = best.min(start.elapsed().as_secs_f64());
            }
            row.push(best * 1e9 / t.len() as f64);
        }
        println!("{}: ω {:.2}  α {:.2}  jerk {:.2} ns/sample", s.name(), row[0], row[1], row[2]);
    }
}
