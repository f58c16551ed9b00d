"""Pose trajectories (PoseSpline), screw-motion splines (ScrewSpline) and the registry."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import fd, random_times, random_walk


def keys(n=7, seed=0):
    q = random_walk(n, seed)
    t = random_times(n, seed)
    p = np.cumsum(np.random.default_rng(seed).normal(size=(n, 3)), axis=0)
    return t, q, p


@pytest.mark.parametrize("translation", ["cubic", "linear"])
@pytest.mark.parametrize("rotation", ["c3", "squad", "natural"])
def test_pose_spline_derivatives_match_finite_differences(rotation, translation):
    t, q, p = keys()
    s = qs.PoseSpline(q, t, p, rotation=rotation, translation=translation)
    np.testing.assert_allclose(s.position(t), p, atol=1e-12)
    mids = 0.5 * (t[1:] + t[:-1]) + 0.1 * np.diff(t)
    h = 1e-4
    np.testing.assert_allclose(
        s.linear_velocity(mids), fd(s.position, mids, h), rtol=1e-7, atol=1e-7
    )
    np.testing.assert_allclose(
        s.linear_acceleration(mids), fd(s.linear_velocity, mids, h), rtol=1e-6, atol=1e-6
    )
    np.testing.assert_allclose(
        s.angular_acceleration(mids), fd(s.angular_velocity, mids, h), rtol=1e-6, atol=1e-6
    )
    if translation == "cubic":  # natural cubic: C², zero acceleration at the ends
        np.testing.assert_allclose(s.linear_acceleration([t[0], t[-1]]), 0, atol=1e-10)
        left = s.linear_acceleration(t[1:-1] - 1e-9)
        right = s.linear_acceleration(t[1:-1] + 1e-9)
        np.testing.assert_allclose(left, right, atol=1e-6)


def test_pose_transform_points():
    t, q, p = keys()
    s = qs.PoseSpline(q, t, p)
    body = np.array([[0.1, 0.0, 0.0], [0.0, 0.2, 0.3]])
    w = s.transform_points(t[:3], body)
    assert w.shape == (3, 2, 3)
    np.testing.assert_allclose(w[:, 1], qs.rotate(q[:3], body[1]) + p[:3], atol=1e-12)


def test_pose_bad_input():
    t, q, p = keys()
    with pytest.raises(ValueError, match=r"positions: expected shape \(7, 3\)"):
        qs.PoseSpline(q, t, p[:5])
    with pytest.raises(ValueError, match=r"translation: expected"):
        qs.PoseSpline(q, t, p, translation="bezier")
    with pytest.raises(ValueError, match=r"outside the domain"):
        qs.PoseSpline(q, t, p).position(t[-1] + 1)


def test_screw_spline_equals_sclerp_on_two_keys():
    t, q, p = keys(2, 3)
    s = qs.ScrewSpline(q, t, p)
    x = np.linspace(t[0], t[1], 21)
    a = qs.dq_from_pose(q[0], p[0])
    b = qs.dq_from_pose(q[1], p[1])
    ref = qs.sclerp(a, b, (x - t[0]) / (t[1] - t[0]))
    got = s.dual_quaternions(x)
    d = np.minimum(np.abs(got - ref).max(axis=1), np.abs(got + ref).max(axis=1))
    assert d.max() < 1e-13


def one_sided_slopes(f, tk, h):
    right = (-3 * f(tk) + 4 * f(tk + h) - f(tk + 2 * h)) / (2 * h)
    left = (3 * f(tk) - 4 * f(tk - h) + f(tk - 2 * h)) / (2 * h)
    return left, right


@pytest.mark.parametrize("smooth", [False, True])
def test_screw_spline_interpolates_and_its_continuity(smooth):
    t, q, p = keys(6, 4)
    s = qs.ScrewSpline(q, t, p, smooth=smooth)
    qq, pp = s(t)
    np.testing.assert_allclose(pp, p, atol=1e-12)
    assert np.all(np.abs(np.abs(np.sum(qq * q, axis=1)) - 1) < 1e-12)
    pos = lambda x: s(np.atleast_1d(x))[1]  # noqa: E731
    jumps = []
    for tk in t[1:-1]:
        left, right = one_sided_slopes(pos, tk, 1e-5)
        jumps.append(np.abs(left - right).max())
    if smooth:
        assert max(jumps) < 1e-4  # C¹ (and C³ by construction) in time
    else:
        assert max(jumps) > 1e-2  # piecewise ScLerp: velocity jumps at keys


def test_registry_builds_every_method_and_rejects_unknowns():
    t, q, _ = keys(8, 5)
    for name, m in qs.METHODS.items():
        s = qs.spline(name, q, t)
        assert s.domain[0] == t[0] and abs(s.domain[1] - t[-1]) < 1e-9, name
        if m.interpolating:
            d = np.minimum(np.abs(s(t) - q).max(axis=1), np.abs(s(t) + q).max(axis=1))
            assert d.max() < 1e-12, name
    with pytest.raises(ValueError, match=r"method: unknown method 'foo'; valid: slerp, nlerp"):
        qs.spline("foo", q, t)
    with pytest.raises(
        ValueError, match=r"gamma: unknown parameter of c3; valid: alpha, beta, variant"
    ):
        qs.spline("c3", q, t, gamma=1.0)
    with pytest.raises(ValueError, match=r"alpha: expected a number or .auto., got .big."):
        qs.spline("c3", q, t, alpha="big")
    s = qs.spline("c3", q, t, alpha="0.5", variant="patent")
    assert s.method == "c3"
