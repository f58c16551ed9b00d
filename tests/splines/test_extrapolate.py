"""Extrapolation beyond the domain: raise, clamp, linear (constant ω), periodic — every method,
and the pose spline; linear against scipy's RotationSpline outside its range."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.spatial.transform import Rotation, RotationSpline

from ..splinekit import fd, random_times, random_walk

METHODS = list(qs.METHODS)


def _built(name, extrapolate):
    q = random_walk(6, seed=3)
    t = random_times(6, seed=3)
    s = qs.spline(name, q, t)
    s.extrapolate = extrapolate
    return s


def _body_rate(q, dq):
    return 2 * qs.multiply(qs.conjugate(q), dq)[..., 1:]


@pytest.mark.parametrize("name", METHODS)
def test_linear_continues_at_the_end_rate_exactly(name):
    s = _built(name, "linear")
    a, b = s.domain
    nseg = len(s.joints) - 1
    for end, seg, sign in ((a, 0, -1.0), (b, nseg - 1, 1.0)):
        d = s.segment_derivatives(seg, end)
        wb = _body_rate(d[0], d[1])
        dt = sign * np.array([0.01, 0.7, 3.0])
        t = end + dt
        # The closed form q_e exp(½ ω_b dt), computed independently here.
        expect = qs.multiply(d[0], qs.exp(np.c_[np.zeros(3), 0.5 * dt[:, None] * wb]))
        got = s(t)
        assert np.allclose(got, expect, atol=1e-13), name
        # Constant angular velocity in the body frame (and so in the world frame), zero α, jerk.
        assert np.allclose(s.angular_velocity(t, "body"), wb, atol=1e-12)
        w_world = qs.rotate(d[0], wb)
        assert np.allclose(s.angular_velocity(t), w_world, atol=1e-12)
        assert np.allclose(s.angular_acceleration(t), 0, atol=1e-12)
        assert np.allclose(s.jerk(t, "body"), 0, atol=1e-12)
        # The reported derivative is the derivative of the reported curve.
        for ti in t:
            num = fd(lambda x: s(x), ti, 1e-4)
            assert np.allclose(s.derivative(ti), num, atol=1e-9)
        # Continuous in value and rate at the end (C¹).
        eps = 1e-9 * sign
        assert np.allclose(s(end + eps), s(end), atol=1e-8)
        assert np.allclose(s.angular_velocity(end + eps), s.angular_velocity(end - eps), atol=1e-6)


def _great_circle(times, speed=0.8):
    axis = np.array([0.3, -0.4, 0.866])
    axis /= np.linalg.norm(axis)
    q0 = qs.normalize(np.array([0.9, 0.1, 0.3, -0.2]))
    return qs.multiply(q0, qs.from_rotvec(speed * times[:, None] * axis)), q0, axis, speed


def test_linear_matches_scipy_rotationspline_outside_its_range_on_a_great_circle():
    # A constant-speed great circle: scipy's end cubic turns at constant speed, so its
    # polynomial continuation and our constant-ω continuation are the same curve.
    times = np.array([0.0, 0.4, 1.5, 2.1, 3.0, 4.6])
    q, q0, axis, speed = _great_circle(times)
    ref = RotationSpline(times, Rotation.from_quat(qs.as_xyzw(q)))
    s = qs.NaturalSpline(q, times, ends="clamped", extrapolate="linear")
    t = np.array([-2.0, -0.3, 4.9, 6.0, 9.5])
    got = s(t)
    want = qs.from_xyzw(ref(t).as_quat())
    dot = np.abs(np.sum(got * want, axis=1))
    assert np.all(1 - dot < 1e-14)
    exact = qs.multiply(q0, qs.from_rotvec(speed * t[:, None] * axis))
    assert np.allclose(np.abs(np.sum(got * exact, axis=1)), 1, atol=1e-14)
    assert np.allclose(s.angular_velocity(t, "body"), ref(t, 1), atol=1e-10)


def test_linear_agrees_with_scipy_to_first_order_on_general_keys():
    # scipy continues its end cubic (not constant ω): same value and rate at the end, a gap
    # that grows like dt² beyond it.
    q = random_walk(7, seed=11)
    times = random_times(7, seed=11)
    ref = RotationSpline(times, Rotation.from_quat(qs.as_xyzw(q)))
    s = qs.NaturalSpline(q, times, ends="clamped", extrapolate="linear")
    b = times[-1]
    assert np.allclose(s.angular_velocity(b, "body"), ref(b, 1), atol=1e-7)
    gaps = []
    for dt in (1e-2, 5e-3, 2.5e-3):
        ours = Rotation.from_quat(qs.as_xyzw(s(b + dt)))
        gaps.append((ours.inv() * ref(b + dt)).magnitude())
    ratios = np.array(gaps[:-1]) / np.array(gaps[1:])
    assert np.all((ratios > 3.5) & (ratios < 4.5)), ratios


@pytest.mark.parametrize("name", METHODS)
def test_periodic_repeats_the_domain(name):
    s = _built(name, "periodic")
    a, b = s.domain
    p = b - a
    t = np.linspace(a, b, 37)[1:-1]
    for k in (-3, -1, 1, 2):
        assert np.allclose(s(t + k * p), s(t), atol=1e-9)
        assert np.allclose(s.angular_velocity(t + k * p), s.angular_velocity(t), atol=1e-7)


@pytest.mark.parametrize("rule", ["raise", "clamp", "linear", "periodic"])
def test_rules_inside_the_domain_change_nothing(rule):
    s = _built("c3", "raise")
    s2 = _built("c3", rule)
    t = np.linspace(*s.domain, 50)
    assert np.array_equal(s(t), s2(t))
    assert np.array_equal(s.jerk(t), s2.jerk(t))


def test_clamp_and_raise_unchanged():
    s = _built("squad", "clamp")
    a, b = s.domain
    assert np.allclose(s(b + 5), s(b))
    assert np.all(s.angular_velocity(np.array([a - 1, b + 1])) == 0)
    s.extrapolate = "raise"
    with pytest.raises(ValueError, match=r"t\[1\]"):
        s(np.array([a, b + 1]))


def test_bad_extrapolate_value():
    with pytest.raises(ValueError, match="extrapolate: expected one of"):
        qs.Squad(random_walk(3, 0), extrapolate="cubic")
    with pytest.raises(ValueError, match="extrapolate: expected one of"):
        qs.PoseSpline(random_walk(3, 0), [0, 1, 2], np.zeros((3, 3)), extrapolate="mirror")
    s = qs.Squad(random_walk(3, 0))
    s.extrapolate = "bogus"  # set after construction: the core names the argument
    with pytest.raises(ValueError, match="extrapolate"):
        s(5.0)


def test_pose_spline_extrapolates_positions_linearly_and_periodically():
    t = np.array([0.0, 1.0, 2.5, 3.0])
    q = random_walk(4, seed=5)
    p = np.array([[0, 0, 0], [1, 2, 0], [2, 2, 1], [4, 0, 1.0]])
    for translation in ("cubic", "linear"):
        ps = qs.PoseSpline(
            q, t, p, rotation="natural", translation=translation, extrapolate="linear"
        )
        v_end = ps.linear_velocity(3.0)
        v_start = ps.linear_velocity(0.0)
        assert np.allclose(ps.position(5.0), p[-1] + 2.0 * v_end)
        assert np.allclose(ps.position(-1.5), p[0] - 1.5 * v_start)
        assert np.allclose(ps.linear_velocity(np.array([4.0, 7.0])), v_end)
        assert np.allclose(ps.linear_acceleration(7.0), 0)
        w = ps.angular_velocity(np.array([3.5, 8.0]))
        assert np.allclose(w[0], w[1], atol=1e-12)
        per = qs.PoseSpline(q, t, p, translation=translation, extrapolate="periodic")
        tt = np.array([0.3, 1.7, 2.9])
        assert np.allclose(per.position(tt + 3.0), per.position(tt))
        assert np.allclose(per.orientation(tt - 6.0), per.orientation(tt), atol=1e-12)
