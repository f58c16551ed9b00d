"""The keyframe support matrix: every method of issue 2.3 × closed / rest / holds / every
extrapolation rule, each cell checked the same way (docs/choosing.rst lists the matrix).

Cells: closed seams continuous by the certificate and by one-sided differences; rest ends with
zero rates by the exact derivatives (as many orders as the method allows); holds exactly
constant to 1e-12 rad; extrapolation linear (the end's ω exactly), periodic, clamp, raise.
"""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from .splinekit import random_times, random_walk
from .test_keyframe import all_joint_jumps

N = 6


def _rates(n, seed=0):
    return np.sin(np.outer(np.arange(1, n + 1) + seed, [0.7, -1.3, 0.4]))


def _bspline(q, t, ends, holds):
    m = len(q) if ends == "closed" else len(q) - 1
    return qs.CumulativeBSpline(q, dt=(t[-1] - t[0]) / m, t0=t[0], ends=ends, holds=holds)


# name -> (builder(q, t, ends, holds), open ends name, C^k claimed (open, closed),
#          derivative orders zero at rest ends, C^k claimed with holds, uniform times only)
METHODS = {
    "catmull_rom": (
        lambda q, t, e, h: qs.CatmullRom(q, t, ends=e, holds=h),
        "reflect",
        1,
        1,
        1,
        False,
    ),
    "kochanek_bartels": (
        lambda q, t, e, h: qs.KochanekBartels(q, t, tension=0.3, bias=-0.2, ends=e, holds=h),
        "reflect",
        1,
        1,
        1,
        False,
    ),
    "squad": (lambda q, t, e, h: qs.Squad(q, t, ends=e, holds=h), "open", 1, 1, 1, False),
    "natural": (
        lambda q, t, e, h: qs.NaturalSpline(q, t, ends=e, holds=h),
        "natural",
        2,
        1,
        1,
        False,
    ),
    "c3_knot": (
        lambda q, t, e, h: qs.C3Spline(q, t, alpha=0.3, beta=0.1, ends=e, holds=h),
        "open",
        3,
        3,
        3,
        False,
    ),
    # the patent variant is C³ in time only for uniform times (G³ otherwise, documented)
    "c3_patent": (
        lambda q, t, e, h: qs.C3Spline(q, t, variant="patent", ends=e, holds=h),
        "open",
        3,
        3,
        3,
        True,
    ),
    "bspline": (_bspline, "open", 2, 2, 2, False),
    "hermite": (
        lambda q, t, e, h: qs.Hermite(q, t, _rates(len(q)), ends=e, holds=h),
        "open",
        1,
        1,
        1,
        False,
    ),
    "hermite_quintic": (
        lambda q, t, e, h: qs.Hermite(q, t, _rates(len(q)), -_rates(len(q), 2), ends=e, holds=h),
        "open",
        2,
        2,
        2,
        False,
    ),
}


def _times(n, seed, uniform):
    return np.arange(n, dtype=float) * 0.8 + 0.3 if uniform else random_times(n, seed)


def _build(name, ends, holds=True, keys=None, seed=1):
    ctor, open_name, *_, uniform = METHODS[name]
    q = random_walk(N, seed, step=0.5) if keys is None else keys
    n = len(q)
    t = _times(n + 1 if ends == "closed" else n, seed, uniform)
    e = open_name if ends == "open" else ends
    return ctor(q, t, e, holds), q, t


def _angle(a, b):
    return qs.angle_between(a, np.broadcast_to(b, a.shape))


# ---- closed ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(METHODS))
def test_closed_seam_is_continuous_by_certificate_and_one_sided_differences(name):
    s, q, t = _build(name, "closed")
    order = METHODS[name][2]
    assert s.closed
    cert = qs.continuity(s)
    assert len(cert) == len(s.joints) - 1 and cert[-1].index == len(s.joints) - 1
    assert min(c.order for c in cert) >= order, [c.order for c in cert]
    jumps = all_joint_jumps(s)
    assert jumps[-1, : order + 1].max() < 1e-10, jumps[-1]  # the seam
    assert jumps[:, : order + 1].max() < 1e-10
    if s.interpolates:
        assert _angle(s(t[:-1]), q).max() < 1e-12
        assert _angle(s(t[-1:]), q[0]).max() < 1e-12


# ---- rest -----------------------------------------------------------------------------------
@pytest.mark.parametrize("name", list(METHODS))
def test_rest_ends_have_zero_rates_by_the_exact_derivatives(name):
    s, q, t = _build(name, "rest", seed=4)
    zero = METHODS[name][3]
    ends = np.array(s.domain)
    rates = [s.angular_velocity, s.angular_acceleration, s.jerk][:zero]
    for r in rates:
        assert np.abs(r(ends)).max() < 1e-11, r.__name__
    inside = ends + np.array([0.05, -0.05]) * (ends[1] - ends[0])
    assert np.linalg.norm(s.angular_velocity(inside), axis=1).min() > 1e-4  # so it can fail
    if s.interpolates:
        assert _angle(s(t), q).max() < 1e-12
    else:  # the B-spline starts and ends on its end control rotations
        assert _angle(s(ends), q[[0, -1]]).max() < 1e-12
    cert = qs.continuity(s)
    assert min(c.order for c in cert) >= METHODS[name][2]


# ---- holds ----------------------------------------------------------------------------------
def _aabb(seed=5):
    w = random_walk(4, seed, step=0.7)
    return np.vstack([w[0], -w[0], w[1], w[1], w[2], w[3]])  # A, −A, B, B, C, D


def _hold_intervals(s, t, name):
    if name == "bspline":
        return s.hold_intervals
    return [(t[0], t[1]), (t[2], t[3])]


@pytest.mark.parametrize("ends", ["open", "closed"])
@pytest.mark.parametrize("name", list(METHODS))
def test_holds_are_exactly_constant(name, ends):
    q = _aabb()
    s, _, t = _build(name, ends, keys=q)
    spans = _hold_intervals(s, t, name)
    assert len(spans) == 2
    for a, b in spans:
        x = np.linspace(a, b, 101)
        held = s(x)
        assert _angle(held, held[0]).max() <= 1e-12
        assert np.abs(s.angular_velocity(x)).max() <= 1e-12
        if s.interpolates:
            assert _angle(held[:1], q[int(np.searchsorted(t, a))]).max() <= 1e-12
    cert = qs.continuity(s)
    assert min(c.order for c in cert) >= METHODS[name][4], [c.order for c in cert]
    jumps = all_joint_jumps(s)
    assert jumps[:, : METHODS[name][4] + 1].max() < 1e-10
    # and without holds the same keys drift (the test can fail)
    d, _, _ = _build(name, ends, holds=False, keys=q)
    a, b = (t[2], t[3]) if name != "bspline" else (d.domain[0], d.domain[1])
    x = np.linspace(a, b, 101)
    assert _angle(d(x), d(x[:1])).max() > 1e-4


# ---- extrapolation --------------------------------------------------------------------------
def _body_rate(q, dq):
    return 2 * qs.multiply(qs.conjugate(q), dq)[..., 1:]


@pytest.mark.parametrize("rule", ["linear", "periodic", "clamp", "raise"])
@pytest.mark.parametrize("ends", ["open", "rest", "closed"])
@pytest.mark.parametrize("name", list(METHODS))
def test_extrapolation_rules(name, ends, rule):
    s, _, _ = _build(name, ends, seed=7)
    s.extrapolate = rule
    a, b = s.domain
    p = b - a
    nseg = len(s.joints) - 1
    for end, seg, sign in ((a, 0, -1.0), (b, nseg - 1, 1.0)):
        x = end + sign * np.array([1e-3, 0.4, 2.7]) * p
        if rule == "raise":
            with pytest.raises(ValueError):
                s(x)
            continue
        d = s.segment_derivatives(seg, end)
        if rule == "linear":
            wb = _body_rate(d[0], d[1])
            expect = qs.multiply(d[0], qs.exp(np.c_[np.zeros(3), 0.5 * (x - end)[:, None] * wb]))
            assert np.abs(s(x) - expect).max() < 1e-13
            assert np.abs(s.angular_velocity(x, "body") - wb).max() < 1e-12
            assert np.abs(s.angular_velocity(x) - qs.rotate(d[0], wb)).max() < 1e-12
            assert np.abs(s.angular_acceleration(x)).max() < 1e-12
        elif rule == "clamp":
            assert _angle(s(x), d[0]).max() < 1e-15
            assert np.abs(s.angular_velocity(x)).max() == 0.0
        else:  # periodic
            y = x - sign * np.ceil(np.abs(x - end) / p) * p
            assert np.all((y >= a) & (y <= b))
            assert _angle(s(x), s(y)).max() < 1e-12
            assert np.abs(s.angular_velocity(x) - s.angular_velocity(y)).max() < 1e-9
    if rule == "periodic" and ends == "closed":  # smooth across every period boundary
        for r in (s.angular_velocity, s.angular_acceleration)[: METHODS[name][2]]:
            for c in (a, b, b + p):
                assert np.allclose(r(c - 1e-8), r(c + 1e-8), atol=1e-5), r.__name__
