//! Times arc-length splines per sample on one core against their floor, the original spline's
//! own evaluation at the same samples (a quick profile, not a benchmark): values through the
//! engine (the batch path: times mapped through the tabulated inverse, then the original's
//! kernel) and per sample (`segment_jet1`, the reference path), ω through the engine; the best
//! of 7 runs. Keys: `quatspline::testing::profile_keys` (as `profile_eval` and the criterion
//! benchmarks).
use quatspline::spline::*;
use std::sync::Arc;
use std::time::Instant;

fn best(mut f: impl FnMut() -> f64, n: usize) -> f64 {
    let mut b = f64::INFINITY;
    let mut acc = 0.0;
    for _ in 0..7 {
        let s = Instant::now();
        acc += f();
        b = b.min(s.elapsed().as_nanos() as f64 / n as f64);
    }
    std::hint::black_box(acc);
    b
}

fn main() {
    let q = quatspline::testing::profile_keys(200);
    let splines: Vec<Arc<dyn Spline>> = vec![
        Arc::new(PiecewiseSlerp::new(&q, None, true).unwrap()),
        Arc::new(Squad::new(&q, None, true).unwrap()),
        Arc::new(CatmullRom::new(&q, None, CatmullRomEnds::Reflect, true).unwrap()),
        Arc::new(NaturalSpline::new(&q, None, NaturalEnds::Natural, true).unwrap()),
        Arc::new(C3Spline::new(&q, None, &[0.3125], &[0.0], C3Variant::Knot, true).unwrap()),
        Arc::new(CumulativeBSpline::new(&q, 1.0, 0.0, 4, true).unwrap()),
        Arc::new(BetaSpline::new(&q, &[1.5], &[0.5], None, true).unwrap()),
        Arc::new(SphericalBezier::new(&q[..8], (0.0, 199.0), true).unwrap()),
    ];
    let m = 200_000;
    for s in splines {
        let build = Instant::now();
        let r = Reparameterized::arc_length(s.clone()).unwrap();
        let build = build.elapsed().as_secs_f64() * 1e6 / s.segments() as f64;
        let (a, b) = r.domain();
        let t: Vec<f64> = (0..m).map(|i| a + (b - a) * i as f64 / m as f64).collect();
        let mut out = vec![0.0; 4 * m];
        let mut engine = |sp: &dyn Spline, omega: bool| {
            best(
                || {
                    if omega {
                        angular_into(sp, &t, 0, 1, Frame::World, Extrapolate::Raise, &mut out[..3 * m])
                            .unwrap();
                    } else {
                        evaluate_into(sp, &t, 0, 0, Extrapolate::Raise, &mut out).unwrap();
                    }
                    out[0]
                },
                m,
            )
        };
        let (val, orig, om, orig_om) =
            (engine(&r, false), engine(&*s, false), engine(&r, true), engine(&*s, true));
        let per_sample = |sp: &dyn Spline| {
            best(|| t.iter().map(|&ti| sp.segment_jet1(sp.locate(ti), ti).value().w).sum(), m)
        };
        println!(
            "arc_length({}): values {val:.1} ns (original {orig:.1}), ω {om:.1} ns (original {orig_om:.1}), \
             per sample {:.1} ns; build {build:.1} µs/segment, {:.1} table pieces/segment",
            s.name(),
            per_sample(&r),
            r.table_pieces() as f64 / s.segments() as f64
        );
    }
}
