//! Times arc-length splines per sample on one core against their floor, the original spline's
//! own jet evaluation at the same samples (a quick profile, not a benchmark): value (order 1)
//! and value with first derivative (order 2, what ω needs); the best of 7 runs.
use quatspline::spline::*;
use quatspline::Quat;
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
    let n = 200;
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for k in 1..n {
        let a = 0.3 + 0.05 * (k % 8) as f64;
        let (s, c) = (0.5 * a).sin_cos();
        let ax = [(k as f64).sin(), (1.7 * k as f64).cos(), 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        q.push(q[k - 1] * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
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
        let run = |sp: &dyn Spline, order: usize| {
            best(
                || {
                    let mut acc = 0.0;
                    for &ti in &t {
                        let k = sp.locate(ti);
                        acc += if order == 1 {
                            sp.segment_jet1(k, ti).value().w
                        } else {
                            sp.segment_jet2(k, ti).derivative(1).w
                        };
                    }
                    acc
                },
                m,
            )
        };
        println!(
            "arc_length({}): value {:.1} ns (original {:.1}), first derivative {:.1} ns (original {:.1}); \
             build {:.1} µs/segment, {:.1} table pieces/segment",
            s.name(),
            run(&r, 1),
            run(&*s, 1),
            run(&r, 2),
            run(&*s, 2),
            build,
            r.table_pieces() as f64 / s.segments() as f64
        );
    }
}
