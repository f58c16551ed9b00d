//! `cargo bench -p quatspline`: the core's evaluation engine on one thread (criterion).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use quatspline::spline::*;
use quatspline::Quat;
use std::hint::black_box;

fn keys(n: usize) -> Vec<Quat> {
    quatspline::testing::profile_keys(n)
}

fn evaluation(c: &mut Criterion) {
    let q = keys(1000);
    let m = 100_000;
    let t: Vec<f64> = (0..m).map(|i| i as f64 * 996.0 / m as f64).collect();
    let splines: Vec<Box<dyn Spline>> = vec![
        Box::new(PiecewiseSlerp::new(&q, None, true).unwrap()),
        Box::new(Squad::new(&q, None, true).unwrap()),
        Box::new(CatmullRom::new(&q, None, CatmullRomEnds::Reflect, true).unwrap()),
        Box::new(NaturalSpline::new(&q, None, NaturalEnds::Natural, true).unwrap()),
        Box::new(CumulativeBSpline::new(&q, 1.0, 0.0, 4, true).unwrap()),
        Box::new(BetaSpline::new(&q, &[1.5], &[0.5], None, true).unwrap()),
        Box::new(C3Spline::new(&q, None, &[0.3125], &[0.0], C3Variant::Knot, true).unwrap()),
    ];
    let mut g = c.benchmark_group("evaluate 1000 keys, 100k sorted samples");
    g.throughput(Throughput::Elements(m as u64));
    let mut out = vec![0.0; 16 * m];
    for s in &splines {
        for order in [0usize, 1] {
            g.bench_with_input(BenchmarkId::new(s.name(), format!("order {order}")), &order, |b, &order| {
                b.iter(|| evaluate_into(&**s, black_box(&t), 0, order, Extrapolate::Raise, &mut out).unwrap())
            });
        }
    }
    g.finish();
}

fn construction(c: &mut Criterion) {
    let q = keys(100_000);
    let mut g = c.benchmark_group("construct 100k keys");
    g.sample_size(10);
    g.bench_function("c3", |b| {
        b.iter(|| C3Spline::new(black_box(&q), None, &[0.3125], &[0.0], C3Variant::Knot, true).unwrap())
    });
    g.bench_function("natural", |b| {
        b.iter(|| NaturalSpline::new(black_box(&q), None, NaturalEnds::Natural, true).unwrap())
    });
    g.finish();
}

criterion_group!(benches, evaluation, construction);
criterion_main!(benches);
