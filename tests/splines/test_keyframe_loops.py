"""Closed loops, holds and rest-to-rest ends for every method that offers them."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import fd, random_times, random_walk
from .test_keyframe import all_joint_jumps, great_circle, same_rotation

N = 6


def _rates(n):
    return np.sin(np.outer(np.arange(1, n + 1), [0.7, -1.3, 0.4]))


# method -> (constructor of a closed loop from n keys and n + 1 times, claimed order,
# interpolates)
CLOSED = {
    "catmull_rom": (lambda q, t: qs.CatmullRom(q, t, ends="closed"), 1, True),
    "kochanek_bartels": (
        lambda q, t: qs.KochanekBartels(q, t, tension=0.3, bias=-0.4, ends="closed"),
        1,
        True,
    ),
    "hermite": (lambda q, t: qs.Hermite(q, t, _rates(len(q)), ends="closed"), 1, True),
    "hermite_quintic": (
        lambda q, t: qs.Hermite(q, t, _rates(len(q)), -_rates(len(q)), ends="closed"),
        2,
        True,
    ),
    "squad": (lambda q, t: qs.Squad(q, t, ends="closed"), 1, True),
    "natural": (lambda q, t: qs.NaturalSpline(q, t, ends="closed"), 2, True),
    "c3": (lambda q, t: qs.C3Spline(q, t, alpha=0.3, beta=0.1, ends="closed"), 3, True),
    "bspline": (
        lambda q, t: qs.CumulativeBSpline(q, dt=0.8, t0=t[0], ends="closed"),
        2,
        False,
    ),
}


def _loop(seed=0):
    q = random_walk(N, seed, step=0.5)
    t = np.r_[random_times(N, seed), 0.0]
    t[-1] = t[-2] + 0.9
    return q, t


@pytest.mark.parametrize("name", list(CLOSED))
def test_closed_loop_is_as_smooth_across_the_seam_as_inside(name):
    q, t = _loop(1)
    ctor, order, interp = CLOSED[name]
    s = ctor(q, t)
    assert s.closed
    j = s.joints
    if interp:
        assert np.array_equal(j, t)
        assert same_rotation(s(t[:-1]), q).max() < 1e-14
        assert same_rotation(s(t[-1])[None], q[:1]).max() < 1e-14  # the loop closes on key 0
    cert = qs.continuity(s)
    assert len(cert) == len(j) - 1 and cert[-1].index == len(j) - 1  # the seam is certified
    assert all(c.order >= order for c in cert), [c.order for c in cert]
    jumps = all_joint_jumps(s)
    assert np.all(jumps[:, : order + 1] < 1e-10), jumps
    if order < 3:
        assert jumps[:, order + 1].max() > 1e-4  # the next order visibly jumps: can fail
    # periodic extrapolation repeats the loop, smoothly across every period boundary
    s.extrapolate = "periodic"
    p = j[-1] - j[0]
    x = np.linspace(j[0], j[-1], 97)
    assert same_rotation(s(x + 2 * p), s(x)).max() < 1e-9
    rates = [s.angular_velocity, s.angular_acceleration, s.jerk][:order]
    for b in (j[0] - p, j[0], j[0] + 3 * p):
        for r in rates:
            assert np.allclose(r(b - 1e-9), r(b + 1e-9), atol=1e-5), (b, r.__name__)
    # inside a period the reported rate is the derivative of the reported curve
    y = j[0] + 2.3 * p + 0.37 * (j[1] - j[0])
    assert np.allclose(s.derivative(y), fd(lambda z: s(z), y, 1e-4), atol=1e-8)


def test_open_methods_certify_no_seam():
    q, t = _loop(2)
    s = qs.CatmullRom(q, t[:-1])
    assert not s.closed and len(qs.continuity(s)) == N - 2


def test_closed_great_circle_is_reproduced_by_hermite():
    speed = 0.9
    period = 2 * np.pi / speed
    t = np.r_[0.0, 0.7, 2.2, 3.0, 4.1, 5.9, period]
    f = great_circle(t, speed)
    q = f(t[:-1])
    axis = np.array([0.2, 0.9, -0.4]) / np.linalg.norm([0.2, 0.9, -0.4])
    s = qs.Hermite(q, t, np.tile(speed * axis, (6, 1)), frame="body", ends="closed")
    x = np.linspace(0, period, 301)
    assert same_rotation(s(x), f(x)).max() < 1e-14


@pytest.mark.parametrize(
    "name, ctor, min_keys",
    [
        ("catmull_rom", lambda q: qs.CatmullRom(q, ends="closed"), 3),
        ("kochanek_bartels", lambda q: qs.KochanekBartels(q, ends="closed"), 3),
        (
            "hermite",
            lambda q: qs.Hermite(q, angular_velocity=np.zeros((len(q), 3)), ends="closed"),
            2,
        ),
        ("squad", lambda q: qs.Squad(q, ends="closed"), 3),
        ("natural spline", lambda q: qs.NaturalSpline(q, ends="closed"), 3),
        ("c3 spline", lambda q: qs.C3Spline(q, ends="closed"), 3),
    ],
)
def test_closed_curves_with_too_few_keys(name, ctor, min_keys):
    q = random_walk(min_keys, 3)
    ctor(q)  # enough
    few = q[: min_keys - 1]
    with pytest.raises(ValueError, match=rf"^quats: a closed {name} needs at least {min_keys}"):
        ctor(few)
    # a repeated first key at the end is the closing key: dropped, so it does not count
    with pytest.raises(ValueError, match=r"the last key equals the first and is dropped"):
        ctor(np.vstack([few, -few[:1]]))
    with pytest.raises(ValueError, match=r"control_quats: needs at least 4 keys, got 3"):
        qs.CumulativeBSpline(random_walk(3, 3), ends="closed")


def test_unsupported_ends_list_the_supported_ones():
    q = random_walk(5, 4)
    cases = [
        (lambda: qs.Squad(q, ends="reflect"), "squad", "open, rest, closed"),
        (lambda: qs.C3Spline(q, ends="natural"), "c3", "open, rest, closed"),
        (
            lambda: qs.Hermite(q, angular_velocity=np.zeros((5, 3)), ends="reflect"),
            "hermite",
            "open, rest, closed$",
        ),
        (
            lambda: qs.CumulativeBSpline(q, ends="natural"),
            "CumulativeBSpline",
            "open, rest, closed$",
        ),
        (lambda: qs.spline("bspline", q, ends="clamped"), "bspline", "open, rest, closed"),
    ]
    for f, method, supported in cases:
        with pytest.raises(ValueError, match=rf"^ends: {method} does not support .*{supported}"):
            f()
    with pytest.raises(ValueError, match=r"^ends: rest needs order ≥ 3"):
        qs.CumulativeBSpline(q, order=2, ends="rest")


# ---- holds --------------------------------------------------------------------------------
HOLDS = {
    "catmull_rom": (lambda q, t, h: qs.CatmullRom(q, t, holds=h), 1),
    "kochanek_bartels": (lambda q, t, h: qs.KochanekBartels(q, t, tension=0.2, holds=h), 1),
    "squad": (lambda q, t, h: qs.Squad(q, t, holds=h), 1),
    "natural": (lambda q, t, h: qs.NaturalSpline(q, t, holds=h), 1),
    "c3": (lambda q, t, h: qs.C3Spline(q, t, holds=h), 3),
}


def _aabb(seed=5):
    """Keys A, A, B, B (the issue's example; the second A given as −A) plus two more."""
    w = random_walk(4, seed, step=0.7)
    q = np.vstack([w[0], -w[0], w[1], w[1], w[2], w[3]])
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.0, 5.2])
    return q, t


@pytest.mark.parametrize("name", list(HOLDS))
def test_holds_are_exactly_constant(name):
    q, t = _aabb()
    ctor, order = HOLDS[name]
    s = ctor(q, t, True)
    for a, b, key in ((0.0, 1.0, q[0]), (2.0, 3.5, q[2])):
        x = np.linspace(a, b, 201)
        dev = same_rotation(s(x), np.broadcast_to(key, (201, 4))).max()
        # constant up to the rounding of the result's components (a few ulp of 1): the slerp
        # kernels form a·f_a + b·f_b with f_a + f_b = 1 in exact arithmetic (Catmull–Rom's
        # series slerp measured 3.3e-16, the jet path ≤ 2e-16)
        assert dev <= 4 * np.finfo(float).eps, dev
        assert np.abs(s.angular_velocity(x)).max() <= 1e-14
    assert s.continuity == order  # the natural spline says it drops to C¹ at the hold ends
    cert = qs.continuity(s)
    assert all(c.order >= order for c in cert)
    jumps = all_joint_jumps(s)
    assert np.all(jumps[:, : order + 1] < 1e-10)
    # without holds the "hold" drifts (the 2.3° for C³ and 11.5° for natural)
    drift = ctor(q, t, False)
    x = np.linspace(2.0, 3.5, 201)
    ang = qs.angle_between(drift(x), np.broadcast_to(q[2], (201, 4)))
    assert np.degrees(ang.max()) > 0.5


# ---- rest-to-rest ends --------------------------------------------------------------------
REST = {
    "catmull_rom": (lambda q, t: qs.CatmullRom(q, t, ends="rest"), 1),
    "kochanek_bartels": (lambda q, t: qs.KochanekBartels(q, t, bias=0.3, ends="rest"), 1),
    "squad": (lambda q, t: qs.Squad(q, t, ends="rest"), 1),
    "natural": (lambda q, t: qs.NaturalSpline(q, t, ends="rest"), 1),
    "c3": (lambda q, t: qs.C3Spline(q, t, ends="rest"), 3),
    "bspline": (lambda q, t: qs.spline("bspline", q, t, ends="rest"), 2),
}


@pytest.mark.parametrize("name", list(REST))
def test_rest_ends_have_zero_rates(name):
    q = random_walk(N, 8)
    t = random_times(N, 8)
    ctor, zero_up_to = REST[name]
    s = ctor(q, t)
    ends = np.array(s.domain)
    assert np.abs(s.angular_velocity(ends)).max() < 1e-13
    if zero_up_to >= 2:
        assert np.abs(s.angular_acceleration(ends)).max() < 1e-12
    if zero_up_to >= 3:
        assert np.abs(s.jerk(ends)).max() < 1e-11
    # and the rates really are not zero just inside (so the test can fail)
    inside = ends + np.array([1e-2, -1e-2]) * (t[-1] - t[0])
    assert np.abs(s.angular_velocity(inside)).max() > 1e-6
    if name not in ("bspline",):
        assert same_rotation(s(t), q).max() < 1e-14
