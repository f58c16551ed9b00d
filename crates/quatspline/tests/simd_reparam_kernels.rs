//! The batch path of reparameterised splines (arc length and time stretch): the times mapped
//! first, then the original's kernel on the mapped run, against the per-sample reference path
//! (jets) on every instruction set, sorted and unsorted, with runs of every length and samples
//! at the joints; the engine's rows independent of chunking.

mod common;

use common::{isas, kernel_angular, max_rel, reference_angular, reference_eval, shuffled, times, walk};
use quatspline::spline::{
    evaluate_into, BetaSpline, C3Spline, C3Variant, CatmullRom, CatmullRomEnds, CumulativeBSpline,
    CumulativeBezier, Extrapolate, Frame, KeyEnds, NaturalEnds, NaturalSpline, PiecewiseSlerp,
    Reparameterized, SphericalBezier, Spline, Squad,
};
use std::sync::Arc;

/// Originals of every family with batch kernels (values; rates where the family has them).
fn originals() -> Vec<(&'static str, Arc<dyn Spline>)> {
    let q = walk(24, 11, 0.9);
    let t = times(24, 12);
    vec![
        ("slerp", Arc::new(PiecewiseSlerp::new(&q, Some(&t), true).unwrap())),
        ("squad", Arc::new(Squad::new(&q, Some(&t), true).unwrap())),
        ("squad rest", Arc::new(Squad::with_keyframes(&q, Some(&t), KeyEnds::Rest, false, true).unwrap())),
        ("catmull_rom", Arc::new(CatmullRom::new(&q, Some(&t), CatmullRomEnds::Reflect, true).unwrap())),
        ("natural", Arc::new(NaturalSpline::new(&q, Some(&t), NaturalEnds::Natural, true).unwrap())),
        ("c3", Arc::new(C3Spline::new(&q, Some(&t), &[0.3], &[0.1], C3Variant::Knot, true).unwrap())),
        ("bspline", Arc::new(CumulativeBSpline::new(&q, 0.7, -1.0, 4, true).unwrap())),
        ("beta", Arc::new(BetaSpline::new(&q, &[1.5], &[0.5], Some(&t[..22]), true).unwrap())),
        ("bezier 8", Arc::new(SphericalBezier::new(&q[..8], (0.0, 3.0), true).unwrap())),
        ("bezier 33", Arc::new(SphericalBezier::new(&walk(33, 13, 0.3), (-1.0, 2.0), true).unwrap())),
        ("cumulative_bezier", Arc::new(CumulativeBezier::new(&q[..9], (0.0, 3.0), true).unwrap())),
    ]
}

/// Arc-length and stretched versions of every original.
fn splines() -> Vec<(String, Reparameterized)> {
    let mut v = Vec::new();
    for (name, s) in originals() {
        v.push((format!("arc_length({name})"), Reparameterized::arc_length(s.clone()).unwrap()));
        v.push((format!("scaled({name})"), Reparameterized::scaled(s, 1.7).unwrap()));
    }
    v
}

/// Sorted probe times (joints, around them, ends, 400 random points) and their shuffle.
fn probe(s: &dyn Spline) -> [Vec<f64>; 2] {
    let mut t = common::probe_times(s, 5, 400);
    t.sort_by(f64::total_cmp);
    let u = shuffled(&t, 8);
    [t, u]
}

/// Regression: a reparameterised spline had no batch path (every sample took the jets, with
/// the original evaluated per sample: 48–1,229 ns per sample instead of its kernel's 4–42).
#[test]
fn reparameterised_splines_take_the_batch_path_of_their_original() {
    for (name, r) in splines() {
        assert!(r.batch().is_some(), "{name}");
    }
}

/// Values on every instruction set; first derivatives where the original's kernel has them
/// (and only there: the map declines exactly where the original does).
#[test]
fn values_and_first_derivatives_equal_the_reference() {
    let mut firsts = 0;
    for (name, r) in splines() {
        let s: &dyn Spline = &r;
        for t in probe(s) {
            let seg: Vec<u32> = t.iter().map(|&x| s.locate(x) as u32).collect();
            for isa in isas() {
                for order in 0..=1 {
                    let mut out = vec![f64::NAN; t.len() * 4 * (order + 1)];
                    if !s.batch().unwrap().evaluate(isa, &seg, &t, order, &mut out) {
                        assert!(order > 0 && out.iter().all(|v| v.is_nan()), "{name} declined order {order}");
                        continue;
                    }
                    firsts += order;
                    let e = max_rel(s, &t, &out, &reference_eval(s, &t, order), 4 * (order + 1), 0);
                    assert!(e <= 1.0, "{name} {isa:?} order {order}: {e:e}");
                }
            }
        }
    }
    assert!(firsts > 0);
}

/// A stretch maps every order (q⁽ᵏ⁾ scaled by λ⁻ᵏ) where the original's kernel has it; an
/// arc-length map declines orders above 1 (the jets: s'' needs the original's second
/// derivative, which its values kernel does not give).
#[test]
fn higher_orders_scaled_or_declined() {
    for (name, r) in splines() {
        let s: &dyn Spline = &r;
        let [t, _] = probe(s);
        let seg: Vec<u32> = t.iter().map(|&x| s.locate(x) as u32).collect();
        for isa in isas() {
            for order in 2..=3 {
                let mut out = vec![f64::NAN; t.len() * 4 * (order + 1)];
                let took = s.batch().unwrap().evaluate(isa, &seg, &t, order, &mut out);
                if name.starts_with("arc_length") {
                    assert!(!took && out.iter().all(|v| v.is_nan()), "{name}");
                } else if took {
                    let e = max_rel(s, &t, &out, &reference_eval(s, &t, order), 4 * (order + 1), 0);
                    assert!(e <= 1.0, "{name} {isa:?} order {order}: {e:e}");
                }
            }
        }
    }
}

#[test]
fn rates_equal_the_reference_where_the_original_has_closed_forms() {
    let mut covered = 0;
    for (name, r) in splines() {
        let s: &dyn Spline = &r;
        let orders = if name.starts_with("arc_length") { 1..=1 } else { 1..=3 };
        for t in probe(s) {
            for isa in isas() {
                for order in orders.clone() {
                    for frame in [Frame::World, Frame::Body] {
                        let seg: Vec<u32> = t.iter().map(|&x| s.locate(x) as u32).collect();
                        let mut out = vec![0.0; 3 * t.len()];
                        if !s.batch().unwrap().angular(isa, &seg, &t, order, frame, &mut out) {
                            continue;
                        }
                        covered += 1;
                        let got = kernel_angular(s, isa, &t, order, frame);
                        let want = reference_angular(s, &t, order, frame);
                        let e = max_rel(s, &t, &got, &want, 3, order);
                        assert!(e <= 1.0, "{name} {isa:?} order {order} {frame:?}: {e:e}");
                    }
                }
            }
        }
    }
    assert!(covered > 0);
}

/// |ω| of an arc-length spline is its constant speed c wherever the original moves.
#[test]
fn arc_length_speed_is_constant_on_the_batch_path() {
    for (name, r) in splines().into_iter().filter(|(n, _)| n.starts_with("arc_length(natural")) {
        let s: &dyn Spline = &r;
        let [t, _] = probe(s);
        let c = r.length() / (s.domain().1 - s.domain().0);
        for isa in isas() {
            let w = kernel_angular(s, isa, &t, 1, Frame::Body);
            for v in w.chunks(3) {
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                assert!((n - c).abs() <= 1e-13 * c, "{name}: |ω| = {n}, c = {c}");
            }
        }
    }
}

/// Runs of every length, starting anywhere: each row is a function of its own time only.
#[test]
fn rows_do_not_depend_on_chunking() {
    for (name, r) in splines() {
        let s: &dyn Spline = &r;
        let [_, t] = probe(s);
        let mut whole = vec![0.0; 4 * t.len()];
        evaluate_into(s, &t, 0, 0, Extrapolate::Raise, &mut whole).unwrap();
        for len in [1, 3, 7, 16, 33] {
            for (k, part) in t.chunks(len).enumerate() {
                let mut o = vec![0.0; 4 * part.len()];
                evaluate_into(s, part, 0, 0, Extrapolate::Raise, &mut o).unwrap();
                assert_eq!(o, whole[4 * k * len..4 * (k * len + part.len())], "{name} runs of {len}");
            }
        }
    }
}
