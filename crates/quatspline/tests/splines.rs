//! Every spline through the core API: continuity certificates and the Beta paper's Example 1.

use quatspline::analysis::continuity;
use quatspline::spline::*;
use quatspline::Quat;

fn walk(n: usize) -> Vec<Quat> {
    // deterministic, non-commuting relative rotations of 0.3–0.7 rad
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for k in 1..n {
        let a = 0.3 + 0.05 * (k % 8) as f64;
        let axis = [(k as f64).sin(), (1.7 * k as f64).cos(), 0.5];
        let norm = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let s = (0.5 * a).sin() / norm;
        let r = Quat::new((0.5 * a).cos(), s * axis[0], s * axis[1], s * axis[2]);
        q.push(q[k - 1] * r);
    }
    q
}

fn times(n: usize) -> Vec<f64> {
    (0..n).map(|k| k as f64 + 0.3 * ((k * k) % 3) as f64).collect()
}

#[test]
fn every_method_reaches_its_claimed_order() {
    let q = walk(8);
    let t = times(8);
    let splines: Vec<(Box<dyn Spline>, i32)> = vec![
        (Box::new(PiecewiseSlerp::new(&q, Some(&t), true).unwrap()), 0),
        (Box::new(Squad::new(&q, Some(&t), true).unwrap()), 1),
        (Box::new(CatmullRom::new(&q, Some(&t), CatmullRomEnds::Reflect, true).unwrap()), 1),
        (Box::new(NaturalSpline::new(&q, Some(&t), NaturalEnds::Natural, true).unwrap()), 2),
        (Box::new(CumulativeBSpline::new(&q, 0.5, 0.0, 4, true).unwrap()), 2),
        (Box::new(C3Spline::new(&q, Some(&t), &[0.3], &[0.1], C3Variant::Knot, true).unwrap()), 3),
    ];
    let mut splines = splines;
    let w: Vec<[f64; 3]> = (0..8).map(|k| [(k as f64).sin(), 0.3, -(k as f64).cos()]).collect();
    let a: Vec<[f64; 3]> = (0..8).map(|k| [0.2, (k as f64).cos(), 0.1]).collect();
    let tc = times(9);
    let ends = KeyEnds::Open;
    splines.extend([
        (
            Box::new(Hermite::new(&q, Some(&t), &w, None, Frame::World, ends, true).unwrap())
                as Box<dyn Spline>,
            1,
        ),
        (Box::new(Hermite::new(&q, Some(&t), &w, Some(&a), Frame::Body, ends, true).unwrap()), 2),
        (Box::new(Hermite::new(&q, Some(&tc), &w, Some(&a), Frame::Body, KeyEnds::Closed, true).unwrap()), 2),
        (
            Box::new(
                KochanekBartels::new(&q, Some(&tc), None, CATMULL_ROM, TcbEnds::Closed, true, true).unwrap(),
            ),
            1,
        ),
        (Box::new(NaturalSpline::with_keyframes(&q, Some(&tc), NaturalEnds::Closed, true, true).unwrap()), 2),
        (Box::new(Squad::with_keyframes(&q, Some(&tc), KeyEnds::Closed, true, true).unwrap()), 1),
        (
            Box::new(
                C3Spline::with_keyframes(
                    &q,
                    Some(&tc),
                    &[0.3],
                    &[0.1],
                    C3Variant::Knot,
                    KeyEnds::Closed,
                    true,
                    true,
                )
                .unwrap(),
            ),
            3,
        ),
        (Box::new(CumulativeBSpline::with_closed(&q, 0.5, 0.0, 4, true, true).unwrap()), 2),
    ]);
    for (s, claimed) in splines {
        assert_eq!(s.continuity() as i32, claimed, "{}", s.name());
        // a closed curve's certificate includes the seam: one report per joint
        let joints = s.joints().len();
        assert_eq!(continuity(&*s, 3, 1e-9).len(), if s.closed() { joints - 1 } else { joints - 2 });
        for j in continuity(&*s, 3, 1e-9) {
            assert_eq!(j.order, claimed, "{} joint {}: {:?}", s.name(), j.index, j.jump_rel);
        }
    }
}

#[test]
fn beta_example1_control_points() {
    let raw = [
        [-0.2011, -0.7478, 0.0791, 0.6278],
        [-0.1603, 0.6073, 0.3653, 0.6871],
        [-0.4696, 0.0554, -0.8480, -0.2394],
        [-0.5268, -0.5665, -0.4194, -0.4751],
        [0.6921, -0.2551, 0.1314, 0.6623],
    ];
    let p: Vec<Quat> = raw.iter().map(|&a| Quat::from_wxyz(a)).collect();
    let s = BetaSpline::new(&p, &[1.0], &[0.5], None, false).unwrap();
    let cp = s.bezier_points();
    let expect_q10 = [-0.3796, 0.4589, 0.1106, 0.7956];
    let expect_q23 = [-0.3509, -0.7065, -0.5548, -0.2642];
    for k in 0..4 {
        assert!((cp[0][0].to_wxyz()[k] - expect_q10[k]).abs() < 5e-5);
        assert!((cp[1][3].to_wxyz()[k] - expect_q23[k]).abs() < 5e-5);
    }
    let r = s.joint_residuals();
    assert!(r[0].g1.norm() < 1e-14);
    assert!((r[0].g2.norm() - 0.066).abs() < 5e-4);
}

#[test]
fn bad_parameters_are_errors_not_panics() {
    let q = walk(5);
    assert!(BetaSpline::new(&q, &[0.0], &[0.0], None, true).is_err());
    assert!(BetaSpline::new(&q, &[1.0], &[-4.0], None, true).is_err());
    assert!(C3Spline::new(&q, None, &[0.1, 0.2], &[0.0], C3Variant::Knot, true).is_err());
    assert!(Squad::new(&q[..1], None, true).is_err());
    assert!(PiecewiseSlerp::new(&q, Some(&[0.0, 1.0, 1.0, 2.0, 3.0]), true).is_err());
}

// ---- regressions found by fuzzing (fuzz/fuzz_targets/splines.rs) --------------------------

#[test]
fn c3_huge_shape_parameters_are_rejected_not_nan() {
    let q = walk(4);
    assert!(C3Spline::new(&q, None, &[1e300], &[0.0], C3Variant::Knot, true).is_err());
    assert!(C3Spline::new(&q, None, &[0.3], &[-1e7], C3Variant::Patent, true).is_err());
}

#[test]
fn c3_knot_weights_do_not_overflow_at_huge_time_scales() {
    let q = walk(4);
    let t = [-6e29, -5e29, -4.5e29, -2e29];
    let s = C3Spline::new(&q, Some(&t), &[0.3], &[0.1], C3Variant::Knot, true).unwrap();
    for k in 0..3 {
        for u in [0.0, 0.3, 1.0] {
            let x = t[k] + u * (t[k + 1] - t[k]);
            for d in s.segment_jet4(k, x).derivatives() {
                assert!(d.is_finite(), "segment {k} at u = {u}: {d:?}");
            }
        }
    }
}

#[test]
fn beta_tiny_beta1_and_vanishing_denominator_are_rejected() {
    let q = walk(5);
    assert!(BetaSpline::new(&q, &[1e-300], &[0.0], None, true).is_err());
    assert!(BetaSpline::new(&q, &[1.0], &[-4.0 + 1e-12], None, true).is_err());
}

#[test]
fn keys_closer_than_the_time_resolution_are_rejected() {
    let q = walk(3);
    assert!(PiecewiseSlerp::new(&q, Some(&[0.0, 1e-300, 1.0]), true).is_err());
    assert!(PiecewiseSlerp::new(&q, Some(&[1e9, 1e9 + 1e-3, 1e9 + 1.0]), true).is_ok());
    assert!(PiecewiseSlerp::new(&q, Some(&[1e9, 1e9 + 1e-6, 1e9 + 1.0]), true).is_err());
    assert!(PiecewiseSlerp::new(&q, Some(&[-1.7e308, 1.7e308, f64::MAX]), true).is_err());
    // found by fuzzing: spacings 1e91 and 1e-11 overflowed the natural spline's jerk
    assert!(
        NaturalSpline::new(&q, Some(&[-9.586e90, -4.7e-224, 3.2e-11]), NaturalEnds::Natural, true).is_err()
    );
    assert!(
        C3Spline::new(&q, Some(&[-6e306, -5e306, -4e306]), &[0.3], &[0.0], C3Variant::Knot, true).is_err()
    );
}

/// Regression (issue 2.1 item 5): with 1,024 or more control points the cumulative Bézier
/// curve was NaN everywhere (its binomial coefficients overflowed). Values and all three
/// derivatives must be finite and unit across the domain at 1,100 and 4,096 control points.
#[test]
fn cumulative_bezier_with_thousands_of_control_points_is_finite() {
    for &n in &[1024usize, 1100, 4096] {
        let keys: Vec<Quat> = (0..n)
            .map(|i| {
                let a = 0.01 * i as f64;
                Quat::new(1.0 + a.cos(), (0.7 * a).sin(), (1.3 * a).cos(), 0.2).normalize()
            })
            .collect();
        let s = CumulativeBezier::new(&keys, (0.0, 10.0), true).unwrap();
        for k in 0..=20 {
            let t = 10.0 * k as f64 / 20.0;
            let d = derivatives_on(&s, 0, t, 3);
            assert!(d.iter().all(|q| q.is_finite()), "n {n} t {t}: {d:?}");
            assert!((d[0].norm() - 1.0).abs() < 1e-12);
        }
    }
}
