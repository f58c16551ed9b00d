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

from ..splinekit import random_times, random_walk
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


# ---- details behind the cells -----------------------------------------------------------------
@pytest.mark.parametrize("quintic", [False, True])
def test_hermite_holds_and_rest_override_the_given_rates_only_where_they_must(quintic):
    q = _aabb(9)
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.0, 5.2])
    w, a = 3 * _rates(6), (-2 * _rates(6, 1) if quintic else None)
    for ends, holds, pinned in (
        ("open", True, [0, 1, 2, 3]),
        ("rest", False, [0, 5]),
        ("rest", True, [0, 1, 2, 3, 5]),
    ):
        s = qs.Hermite(q, t, w, a, ends=ends, holds=holds)
        for k in range(6):
            segs = [max(k - 1, 0), min(k, 4)]
            for seg in segs:
                d = s.segment_derivatives(seg, t[k])
                got = s.angular_velocity(t[k]) if seg == segs[-1] else None
                expect_w = np.zeros(3) if k in pinned else w[k]
                rate = qs.rotate(d[0], 2 * qs.multiply(qs.conjugate(d[0]), d[1])[1:])
                assert np.abs(rate - expect_w).max() < 1e-12, (ends, holds, k, seg)
                if got is not None:
                    assert np.abs(got - expect_w).max() < 1e-12
            if quintic:  # (C² by the matrix's jump test, so one side is enough)
                expect_a = np.zeros(3) if k in pinned else a[k]
                assert np.abs(s.angular_acceleration(t[k]) - expect_a).max() < 1e-10, k
        assert _angle(s(t), q).max() < 1e-12


def test_hermite_override_does_not_hide_bad_rows():
    q = _aabb(9)
    w = _rates(6)
    w[0, 1] = np.nan  # at a key whose rate a hold and rest both override
    with pytest.raises(ValueError, match=r"^angular_velocity: non-finite value .* 0$"):
        qs.Hermite(q, angular_velocity=w, ends="rest")
    with pytest.raises(ValueError, match=r"^angular_acceleration: expected shape \(6, 3\)"):
        qs.Hermite(q, angular_velocity=_rates(6), angular_acceleration=np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"^angular_acceleration: expected shape \(\.\.\., 3\)"):
        qs.Hermite(q, angular_velocity=_rates(6), angular_acceleration=np.zeros((6, 4)))


@pytest.mark.parametrize("order", [2, 3, 4, 5, 6])
@pytest.mark.parametrize("closed", [False, True])
def test_bspline_holds_are_exact_for_every_order(order, closed):
    w = random_walk(5, 11, step=0.6)
    q = np.vstack([w[0], w[1], -w[1], w[1], w[2], w[3], w[4], w[4]])  # runs of 3 and 2
    ends = "closed" if closed else "open"
    s = qs.CumulativeBSpline(q, dt=0.5, t0=1.0, order=order, ends=ends, holds=True)
    plain = qs.CumulativeBSpline(q, dt=0.5, t0=1.0, order=order, ends=ends)
    extra = order - 2
    # a run of m becomes m + k − 2 copies: k − 2 more per run (2 runs)
    assert len(s.joints) - len(plain.joints) == 2 * extra
    spans = s.hold_intervals
    lengths = sorted(round((b - a) / 0.5) for a, b in spans)
    assert lengths == [1, 2]  # m − 1 constant segments per run
    for a, b in spans:
        x = np.linspace(a, b, 61)
        assert _angle(s(x), s(x[:1])).max() <= 1e-12
        # order 2 is C⁰: the velocity jumps at the end of the hold (the next segment's)
        inside = x if order > 2 else x[:-1]
        assert np.abs(s.angular_velocity(inside)).max() <= 1e-12
        rates = [s.angular_acceleration, s.jerk][: max(0, order - 3)]
        for r in rates:  # derivatives up to k − 2 vanish at the ends of the hold
            assert np.abs(r(np.array([a, b]))).max() < 1e-11
    assert all(c.order >= min(order - 2, 3) for c in qs.continuity(s))  # certified up to 3


def test_bspline_closed_hold_across_the_seam_and_rest_with_a_hold_at_the_end():
    w = random_walk(4, 12, step=0.6)
    q = np.vstack([w[0], w[1], w[2], w[3], w[0]])  # the last equals the first: a hold
    s = qs.CumulativeBSpline(q, dt=0.4, ends="closed", holds=True)
    assert len(s.joints) - 1 == 7  # 5 control rotations + 2 copies, used cyclically
    ((a, b),) = s.hold_intervals
    x = np.linspace(a, b, 31)
    assert _angle(s(x), s(x[:1])).max() <= 1e-12
    # without holds the repeated control rotation is kept as it is (not a closing key)
    assert len(qs.CumulativeBSpline(q, dt=0.4, ends="closed").joints) - 1 == 5
    r = qs.CumulativeBSpline(np.vstack([w, w[-1:]]), dt=0.4, ends="rest", holds=True)
    # 5 given + 2 hold copies at the end (then already k − 1 equal there) + 2 rest copies at
    # the start = 9 control rotations, 9 − 4 + 1 segments
    assert len(r.joints) - 1 == 6
    assert np.abs(r.angular_velocity(np.array(r.domain))).max() < 1e-13


def test_bspline_rest_zeroes_derivatives_up_to_order_minus_two():
    q = random_walk(6, 13, step=0.6)
    for order in (3, 4, 5, 6):
        s = qs.CumulativeBSpline(q, dt=0.3, order=order, ends="rest")
        e = np.array(s.domain)
        assert _angle(s(e), q[[0, -1]]).max() < 1e-12
        rates = [s.angular_velocity, s.angular_acceleration, s.jerk][: order - 2]
        for r in rates:
            assert np.abs(r(e)).max() < 1e-11, (order, r.__name__)
        # the next derivative does not vanish (order k − 1): the test can fail
        nxt = [s.angular_velocity, s.angular_acceleration, s.jerk][order - 2 : order - 1]
        for r in nxt:
            assert np.abs(r(e)).max() > 1e-6


def test_bspline_bad_keyframe_input():
    q = random_walk(5, 14)
    with pytest.raises(ValueError, match=r"^ends: rest needs order ≥ 3"):
        qs.CumulativeBSpline(q, order=2, ends="rest")
    for ends in ("rest", "closed"):
        with pytest.raises(ValueError, match=r"^ends: closed and rest ends and holds need unif"):
            qs.CumulativeBSpline(q, dt=np.full(8, 0.5), ends=ends)
    with pytest.raises(ValueError, match=r"^holds: closed and rest ends and holds need uniform"):
        qs.CumulativeBSpline(q, dt=np.full(8, 0.5), holds=True)
    bad = q.copy()
    bad[3, 2] = np.inf
    with pytest.raises(ValueError, match=r"^control_quats: non-finite value .* element 3$"):
        qs.CumulativeBSpline(bad, holds=True)
    bad[3] = 0
    with pytest.raises(ValueError, match=r"^control_quats: quaternion 3 has zero"):
        qs.CumulativeBSpline(bad, ends="rest")
    with pytest.raises(ValueError, match=r"^ends: CumulativeBSpline does not support 'reflect'"):
        qs.CumulativeBSpline(q, ends="reflect")


def test_c3_speed_matched_alpha_matches_the_mean_chord_speed_at_every_key():
    from quatspline.core.convert import as_rotvec

    rng = np.random.default_rng(15)
    q = qs.canonicalize(qs.from_rotvec(rng.normal(size=(8, 3)) * 0.3))
    t = np.cumsum(np.r_[0.0, rng.uniform(0.5, 1.5, 7)])
    a = qs.splines.c3_speed_matched_alpha(q, t)
    s = qs.C3Spline(q, t, alpha=a, beta=-6 * a)
    speed = np.linalg.norm(s.angular_velocity(t), axis=1)
    c = np.linalg.norm(as_rotvec(qs.multiply(qs.conjugate(q[:-1]), q[1:])), axis=1) / np.diff(t)
    mean = 0.5 * (c[:-1] + c[1:])
    free = (a[1:-1] > 0) & (a[1:-1] < 1)
    assert free.sum() >= 3
    assert np.allclose(speed[1:-1][free], mean[free], rtol=1e-12)
    assert np.all(a[1:-1] >= 0.5 - 1e-15) and a[0] == a[-1] == 0.5
    # closed: one α per distinct key, a repeated closing key dropped
    tc = np.r_[t, t[-1] + 0.7]
    assert len(qs.splines.c3_speed_matched_alpha(np.vstack([q, q[:1]]), tc, closed=True)) == 8


def test_registry_and_cli_reach_the_new_cells(tmp_path):
    from quatspline.cli import main

    q = _aabb(16)
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.0, 5.2])
    h = qs.spline("hermite", q, t, ends="rest")  # Bessel rates, overridden at holds and ends
    assert np.abs(h.angular_velocity(t[[0, 1, 2, 3, 5]])).max() < 1e-12
    assert np.abs(h.angular_velocity(t[4:5])).max() > 1e-3
    x = np.linspace(2.0, 3.5, 51)
    assert _angle(h(x), q[2]).max() <= 1e-12
    drift = qs.spline("hermite", q, t, holds="false")
    assert _angle(drift(x), q[2]).max() > 1e-3
    c = qs.spline("c3", q, t, variant="patent", ends="rest")
    assert np.abs(c.jerk(t[[0, -1]])).max() < 1e-11 and _angle(c(x), q[2]).max() <= 1e-12
    src = tmp_path / "keys.npz"
    np.savez(src, times=t, quats=q)
    out = tmp_path / "out.csv"
    for method, params in (
        ("hermite", ["--param", "ends=rest"]),
        ("c3", ["--param", "variant=patent", "--param", "ends=rest"]),
    ):
        argv = ["sample", str(src), "-o", str(out), "--method", method, "--count", "7"]
        assert main([*argv, *params]) == 0
        assert out.stat().st_size > 0


@pytest.mark.parametrize(
    "ctor",
    [
        lambda q, t: qs.CatmullRom(q, t, canonicalize=False),
        lambda q, t: qs.KochanekBartels(q, t, tension=0.2, canonicalize=False),
        lambda q, t: qs.Squad(q, t, canonicalize=False),
        lambda q, t: qs.NaturalSpline(q, t, canonicalize=False),
        lambda q, t: qs.C3Spline(q, t, canonicalize=False),
        lambda q, t: qs.C3Spline(q, t, variant="patent", canonicalize=False),
        lambda q, t: qs.Hermite(q, t, _rates(6), _rates(6, 1), canonicalize=False),
    ],
    ids=["catmull_rom", "kb", "squad", "natural", "c3_knot", "c3_patent", "hermite"],
)
def test_a_hold_given_as_q_then_minus_q_holds_without_canonicalize(ctor):
    q = _aabb(3)  # A, −A, B, B, C, D
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.0, 5.2])
    s = ctor(q, t)
    x = np.linspace(0.0, 1.0, 41)
    assert _angle(s(x), q[0]).max() <= 1e-12  # not a full turn from A to −A
    assert _angle(s(t), q).max() < 1e-12


@pytest.mark.parametrize("ends", ["open", "rest", "closed"])
def test_registry_bspline_holds(ends):
    q = _aabb(17)
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.0, 5.2])
    s = qs.spline("bspline", q, t, ends=ends, holds="true")
    plain = qs.spline("bspline", q, t, ends=ends)
    assert s.domain[0] == plain.domain[0] and np.isclose(s.domain[1], plain.domain[1])
    assert len(s.hold_intervals) == 2 and plain.hold_intervals == []
    for a, b in s.hold_intervals:
        x = np.linspace(a, b, 31)
        assert _angle(s(x), s(x[:1])).max() <= 1e-12
        assert np.abs(s.angular_velocity(x)).max() <= 1e-12
    if ends == "rest":
        assert np.abs(s.angular_velocity(np.array(s.domain))).max() < 1e-13


@pytest.mark.parametrize("name", [m for m in METHODS if m != "bspline"])
def test_a_hold_across_the_seam_of_a_closed_loop(name):
    w = random_walk(3, 21, step=0.6)
    # A B C A, then A again: the last key equals the first, so it is the closing key (dropped)
    # and the segment from the fourth key (A) back to the first is a hold across the seam
    q = np.vstack([w[0], w[1], w[2], -w[0], w[0]])
    t = np.arange(5.0) * 0.8
    if name.startswith("hermite"):  # the closing key's rows must repeat row 0
        r, a = _rates(5), -_rates(5, 2)
        r[4], a[4] = r[0], a[0]
        s = qs.Hermite(q, t, r, a if name == "hermite_quintic" else None, ends="closed")
    else:
        s = METHODS[name][0](q, t, "closed", True)
    assert len(s.joints) == 5 and s.closed
    x = np.linspace(t[3], t[4], 41)
    assert _angle(s(x), w[0]).max() <= 1e-12
    assert np.abs(s.angular_velocity(x)).max() <= 1e-12
    order = METHODS[name][4]
    assert all_joint_jumps(s)[:, : order + 1].max() < 1e-10
    assert min(c.order for c in qs.continuity(s)) >= order
