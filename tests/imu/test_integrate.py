"""quatspline.imu.integrate: strapdown integration back to the motion that was simulated.

The oracle is the motion itself (its orientation and position at the sample times); the
order of convergence is measured by halving the step.
"""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.imu import ImuData, SensorModel, integrate, simulate, strapdown
from scipy.spatial.transform import Rotation


def _angle(q1, q2) -> np.ndarray:
    """Rotation angle between quaternion rows, by scipy (w, x, y, z in, independent code)."""

    def rot(q):
        return Rotation.from_quat(np.concatenate([q[:, 1:], q[:, :1]], axis=1))

    return (rot(q1).inv() * rot(q2)).magnitude()


def _smooth(rng, t, amp, n=4, fmax=0.3):
    out = np.zeros((t.size, 3))
    for _ in range(n):
        f, ph = rng.uniform(0.02, fmax, 3), rng.uniform(0, 2 * np.pi, 3)
        out += rng.normal(0, amp, 3) * np.sin(2 * np.pi * f * t[:, None] + ph)
    return out


def _errors(motion, rate, sensor=None):
    d = simulate(motion, rate=rate, sensor=sensor)
    t0 = d.times[0]
    q, p = motion.orientation(t0), motion.position(t0)
    v = motion.linear_velocity(t0)
    if sensor is not None:
        w = motion.angular_velocity(t0, frame="world")
        v = v + np.cross(w, qs.rotate(q, sensor.lever_arm))
        q, p = sensor.sensor_pose(q, p)
    tr = integrate(d, (q, p), initial_velocity=v)
    q_true, p_true = motion.orientation(d.times), motion.position(d.times)
    if sensor is not None:
        q_true, p_true = sensor.sensor_pose(q_true, p_true)
    return _angle(tr.quats, q_true).max(), np.abs(tr.positions - p_true).max()


def test_sixty_seconds_at_200_hz_integrate_back_to_the_spline():
    # a smooth pose motion: |ω| up to ~1.7 rad/s, |p̈| up to ~8 m/s², keys every second
    rng = np.random.default_rng(1)
    tk = np.arange(0.0, 61.0, 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(_smooth(rng, tk, 0.5)), tk, _smooth(rng, tk, 2.0), rotation="c3"
    )
    attitude, position = _errors(pose, 200)
    assert attitude < 1e-6  # rad
    assert position < 1e-3  # m


def test_fourth_order_for_a_smooth_motion():
    # C⁴ orientation and position (order-6 B-spline): the scheme's own order shows
    rng = np.random.default_rng(2)
    s = qs.PoseBSpline(
        qs.from_rotvec(rng.normal(0, 0.6, (14, 3))),
        rng.normal(0, 1.0, (14, 3)),
        dt=1.0,
        order=6,
        formulation="split",
    )
    errors = np.array([_errors(s, rate) for rate in (25, 50, 100)])
    order = np.log2(errors[:-1] / errors[1:])
    assert np.all((order > 3.7) & (order < 4.3)), order


def test_c2_positions_limit_the_position_to_second_order():
    # a natural cubic's acceleration has kinks at the keys; no scheme fed point samples can
    # see where they are, so the position converges like h² there (attitude still like h⁴)
    rng = np.random.default_rng(3)
    tk = np.arange(0.0, 11.0, 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(_smooth(rng, tk, 0.5)), tk, _smooth(rng, tk, 2.0), rotation="c3"
    )
    errors = np.array([_errors(pose, rate) for rate in (50, 100, 200)])
    order = np.log2(errors[:-1] / errors[1:])
    assert np.all((order[:, 0] > 3.7) & (order[:, 0] < 4.3)), order
    assert np.all((order[:, 1] > 1.7) & (order[:, 1] < 2.5)), order


def test_the_sensor_frame_is_integrated():
    # a mounted, displaced sensor integrates to its own pose (R R_bs, p + R r)
    rng = np.random.default_rng(4)
    tk = np.arange(0.0, 11.0, 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(_smooth(rng, tk, 0.5)), tk, _smooth(rng, tk, 1.0), rotation="c3"
    )
    sensor = SensorModel(
        rotation=qs.from_euler("xyz", [20, -70, 150], degrees=True), lever_arm=[0.2, 0.1, -0.3]
    )
    attitude, position = _errors(pose, 200, sensor=sensor)
    assert attitude < 1e-8 and position < 1e-4
    # ignoring the lever arm would be wrong by far more
    d = simulate(pose, rate=200, sensor=sensor)
    q, p = sensor.sensor_pose(pose.orientation(0.0), pose.position(0.0))
    tr = integrate(d, (q, p), initial_velocity=pose.linear_velocity(0.0))
    _, p_true = sensor.sensor_pose(pose.orientation(d.times), pose.position(d.times))
    assert np.abs(tr.positions - p_true).max() > 1e-2


def test_gyroscope_only_and_the_forms_of_the_initial_pose():
    keys = qs.from_rotvec([[0, 0, 0], [0.4, 0.1, 0], [0.5, 0.7, 0.2], [0.1, 0.9, 0.6]])
    s = qs.C3Spline(keys, [0.0, 1.0, 2.0, 3.0])
    d = simulate(s, rate=400)
    q0 = s(0.0)
    tr = integrate(d, q0)
    assert tr.positions is None and "velocity" not in tr.extra
    assert _angle(tr.quats, s(d.times)).max() < 1e-9
    from_scipy = integrate(d, Rotation.from_quat(np.r_[q0[1:], q0[:1]]))
    np.testing.assert_allclose(from_scipy.quats, tr.quats, atol=1e-15)


def test_defaults_start_at_rest_at_the_origin():
    # an accelerometer at rest, upright, reads +g: the integral stays at the origin
    n = 201
    data = ImuData(np.linspace(0, 1, n), np.zeros((n, 3)), accel=[[0, 0, 9.80665]] * n)
    tr = integrate(data, [1.0, 0, 0, 0])
    np.testing.assert_allclose(tr.positions, 0.0, atol=1e-12)
    np.testing.assert_allclose(tr.extra["velocity"], 0.0, atol=1e-12)
    # with no gravity, a constant specific force integrates to p = f t² / 2 exactly
    data = ImuData(
        np.sort(np.random.default_rng(0).uniform(0, 2, 50)),
        np.zeros((50, 3)),
        accel=[[1.0, -2.0, 0.5]] * 50,
    )
    tr = integrate(data, ([1.0, 0, 0, 0], [1, 2, 3]), gravity=[0, 0, 0], initial_velocity=[0, 0, 1])
    dt = data.times - data.times[0]
    expected = [1, 2, 3] + np.outer(dt, [0, 0, 1]) + 0.5 * np.outer(dt**2, [1.0, -2.0, 0.5])
    np.testing.assert_allclose(tr.positions, expected, atol=1e-12)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_few_samples(n):
    data = ImuData(np.arange(n) * 0.1, np.tile([0, 0, 1.0], (n, 1)), accel=np.ones((n, 3)))
    tr = integrate(data, [1.0, 0, 0, 0], gravity=[0, 0, 0])
    assert tr.positions.shape == (n, 3)
    np.testing.assert_allclose(qs.as_rotvec(tr.quats)[:, 2], data.times, atol=1e-14)


@pytest.mark.parametrize(
    ("args", "kwargs", "exc", "match"),
    [
        (("imu", [1.0, 0, 0, 0]), {}, TypeError, "data"),
        ((None, [1.0, 0, 0]), {}, ValueError, "initial_pose"),
        ((None, [2.0, 0, 0, 0]), {}, ValueError, "initial_pose: .*not a rotation"),
        ((None, ([1.0, 0, 0, 0], [0, 0])), {}, ValueError, "initial_pose"),
        ((None, ([1.0, 0, 0, 0], [0, 0, np.nan])), {}, ValueError, "initial_pose"),
        ((None, "up"), {}, TypeError, "initial_pose"),
        ((None, [1.0, 0, 0, 0]), dict(initial_velocity=[0, 0]), ValueError, "initial_velocity"),
        ((None, [1.0, 0, 0, 0], [0, 0]), {}, ValueError, "gravity"),
    ],
)
def test_bad_input(args, kwargs, exc, match):
    data = ImuData(np.arange(5) * 0.1, np.zeros((5, 3)), accel=np.zeros((5, 3)))
    args = (data if args[0] is None else args[0], *args[1:])
    with pytest.raises(exc, match=match):
        integrate(*args, **kwargs)


def test_blocks_do_not_change_the_result(monkeypatch):
    # the quadrature runs in blocks of intervals; a block boundary is invisible
    rng = np.random.default_rng(5)
    n = 203
    t = np.cumsum(rng.uniform(0.004, 0.006, n))
    data = ImuData(t, rng.normal(0, 1, (n, 3)), accel=rng.normal(0, 5, (n, 3)))
    whole = integrate(data, [1.0, 0, 0, 0])
    monkeypatch.setattr(strapdown, "_BLOCK", 7)
    blocks = integrate(data, [1.0, 0, 0, 0])
    np.testing.assert_array_equal(blocks.positions, whole.positions)
    np.testing.assert_array_equal(blocks.extra["velocity"], whole.extra["velocity"])


def test_a_time_offset_shifts_the_trajectory_by_it():
    rng = np.random.default_rng(6)
    tk = np.arange(0.0, 11.0, 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(_smooth(rng, tk, 0.5)), tk, _smooth(rng, tk, 1.0), rotation="c3"
    )
    delta = 0.0123
    d = simulate(pose, rate=200, sensor=SensorModel(time_offset=delta))
    t0 = d.times[0] + delta
    tr = integrate(
        d, (pose.orientation(t0), pose.position(t0)), initial_velocity=pose.linear_velocity(t0)
    )
    assert _angle(tr.quats, pose.orientation(d.times + delta)).max() < 1e-8
    assert np.abs(tr.positions - pose.position(d.times + delta)).max() < 1e-4
