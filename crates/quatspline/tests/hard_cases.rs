//! The hard-case corpus through the core: identity, 1e-12 and 1e-8 rad, π − 1e-9, q vs −q,
//! unnormalised input. References are closed forms that hold exactly for these inputs.

use quatspline::convert::{from_rotvec, to_rotvec};
use quatspline::interp::slerp;
use quatspline::Quat;

fn axis_angle(axis: [f64; 3], angle: f64) -> Quat {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let (s, c) = (0.5 * angle).sin_cos();
    Quat::new(c, s * axis[0] / n, s * axis[1] / n, s * axis[2] / n)
}

fn corpus() -> Vec<(&'static str, Quat, f64)> {
    vec![
        ("identity", Quat::IDENTITY, 0.0),
        ("1e-12 rad", axis_angle([0.3, -0.5, 0.8], 1e-12), 1e-12),
        ("1e-8 rad", axis_angle([1.0, 2.0, 3.0], 1e-8), 1e-8),
        ("pi - 1e-9", axis_angle([-0.2, 0.9, 0.1], std::f64::consts::PI - 1e-9), std::f64::consts::PI - 1e-9),
        ("negated", -axis_angle([0.5, 0.5, -0.7], 1.1), 1.1),
    ]
}

fn close(a: Quat, b: Quat, tol: f64) -> bool {
    (a - b).to_wxyz().iter().all(|c| c.abs() <= tol)
}

#[test]
fn log_exp_round_trip_and_angle() {
    for (name, q, angle) in corpus() {
        let l = q.log();
        assert!(close(l.exp(), q, 1e-15), "{name}");
        // |log q| = θ/2 for the w ≥ 0 representative
        let half = q.canonical().log();
        let len = (half.x * half.x + half.y * half.y + half.z * half.z).sqrt();
        assert!((len - angle / 2.0).abs() <= 1e-15 * (1.0 + angle), "{name}: {len}");
    }
}

#[test]
fn rotvec_round_trip() {
    for (name, q, angle) in corpus() {
        let r = to_rotvec(q);
        let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        assert!((n - angle).abs() <= 1e-15 * (1.0 + angle), "{name}");
        assert!(close(from_rotvec(r), q.canonical(), 1e-15), "{name}");
    }
}

#[test]
fn slerp_endpoints_and_midpoint() {
    for (name, q, angle) in corpus() {
        let p = Quat::IDENTITY;
        assert_eq!(slerp(p, q, 0.0, false), p, "{name}");
        assert!(close(slerp(p, q, 1.0, false), q.canonical_to(p), 0.0), "{name}");
        let mid = slerp(p, q, 0.5, false);
        assert!(((mid.w) - (angle / 4.0).cos()).abs() <= 1e-15, "{name}");
    }
}

#[test]
fn unnormalised_input_normalises() {
    let q = axis_angle([0.0, 1.0, 1.0], 0.4).scale(3.7);
    let n = q.try_normalize().unwrap();
    assert!((n.norm() - 1.0).abs() < 1e-15);
    assert!(close(n.scale(3.7), q, 1e-15));
}
