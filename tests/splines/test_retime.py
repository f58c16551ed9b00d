"""Arc-length reparameterisation of any spline and rate-limited retiming."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.integrate import quad

from ..splinekit import fd, random_times, random_walk

KEYS = random_walk(6, seed=11, step=0.7)
TIMES = random_times(6, seed=11)


def _splines():
    yield "slerp", qs.PiecewiseSlerp(KEYS, TIMES)
    yield "squad", qs.Squad(KEYS, TIMES)
    yield "catmull_rom", qs.CatmullRom(KEYS, TIMES)
    yield "natural", qs.NaturalSpline(KEYS, TIMES)
    yield "c3", qs.C3Spline(KEYS, TIMES)
    yield "bspline", qs.CumulativeBSpline(KEYS, dt=0.8)
    yield "nonuniform", qs.spline("nonuniform_bspline", KEYS, TIMES)
    yield "beta", qs.spline("beta", KEYS, TIMES, beta1=1.5, beta2=2.0)
    yield "bezier", qs.SphericalBezier(KEYS, domain=(0.0, 2.0))


SPLINES = dict(_splines())


def _angle(a, b):
    """Rotation angle between unit quaternions (either sign)."""
    sg = np.where(np.sum(a * b, axis=-1) < 0, -1.0, 1.0)[..., None]
    return 2 * np.arctan2(np.linalg.norm(a - sg * b, axis=-1), np.linalg.norm(a + sg * b, axis=-1))


def _inside(s, n):
    """n times strictly inside each segment plus both one-sided joint limits."""
    j = s.joints
    return np.concatenate([np.linspace(a, b, n)[1:-1] for a, b in zip(j[:-1], j[1:])])


@pytest.mark.parametrize("name", list(SPLINES))
def test_arc_length_has_constant_speed(name):
    s = SPLINES[name]
    r = qs.reparameterize(s, "arc_length")
    assert r.domain == s.domain and r.method == "arc_length"
    t = np.concatenate([np.linspace(*r.domain, 4001), r.joints])
    speed = np.linalg.norm(r.angular_velocity(t), axis=1)
    c = r.length / r.duration
    assert np.max(np.abs(speed - c)) <= 1e-6 * c
    # one-sided limits at the joints as well
    for k in range(len(r.joints) - 1):
        for x in r.joints[k : k + 2]:
            d = r.segment_derivatives(k, x)
            assert abs(2 * np.linalg.norm(d[1]) - c) <= 1e-6 * c
    # the length agrees with an independent quadrature of the original speed
    ref = sum(
        quad(lambda x: np.linalg.norm(s.angular_velocity(x)), a, b, epsabs=1e-13, limit=200)[0]
        for a, b in zip(s.joints[:-1], s.joints[1:])
    )
    assert r.length == pytest.approx(ref, rel=1e-10)


@pytest.mark.parametrize("name", list(SPLINES))
def test_arc_length_traces_the_same_path(name):
    s = SPLINES[name]
    r = qs.arc_length(s)
    dense = np.linspace(*s.domain, 20001)
    orig = s(dense)
    t = np.linspace(*r.domain, 151)
    worst = 0.0
    for q in r(t):
        # nearest sample, then Newton on ⟨s(x) − q, s'(x)⟩ = 0 with the original's exact
        # derivatives (the squared chordal distance is smooth and has no cancellation)
        i = int(np.argmin(_angle(orig, q[None, :])))
        x, lo, hi = dense[i], dense[max(i - 1, 0)], dense[min(i + 1, len(dense) - 1)]
        q = q * (1.0 if np.dot(orig[i], q) >= 0 else -1.0)
        for _ in range(12):
            k = min(int(np.searchsorted(s.joints, x, side="right")) - 1, len(s.joints) - 2)
            d = s.segment_derivatives(k, x)
            e = d[0] - q
            g, h = np.dot(e, d[1]), np.dot(d[1], d[1]) + np.dot(e, d[2])
            x = float(np.clip(x - g / h, lo, hi)) if h > 0 else x
        worst = max(worst, float(_angle(s(x), q)))
    assert worst <= 1e-9
    # where the original reaches its joints, the arc length up to there is c·(t − a)
    c = r.length / r.duration
    for k, sj in enumerate(s.joints[1:-1], start=1):
        phi = sum(
            quad(lambda x: np.linalg.norm(s.angular_velocity(x)), a, b, epsabs=1e-13)[0]
            for a, b in zip(s.joints[:k], s.joints[1 : k + 1])
        )
        tj = r.domain[0] + phi / c
        assert _angle(r(tj), s(sj)) < 1e-9


@pytest.mark.parametrize("name", list(SPLINES))
def test_arc_length_reaches_the_arc_length_of_its_clock(name):
    # the tabulated inverse of the arc-length map: at t, the original's arc length up to the
    # traced point (scipy's adaptive quadrature from the start) is c·(t − a), within 1e-12 of
    # the segment's arc length (the stated bound) plus the quadrature's own tolerance
    s = SPLINES[name]
    r = qs.arc_length(s)
    c, a = r.length / r.duration, r.domain[0]
    j = s.joints

    def speed(x):
        return np.linalg.norm(s.angular_velocity(x))

    seg_len = [quad(speed, lo, hi, epsabs=1e-14, limit=200)[0] for lo, hi in zip(j[:-1], j[1:])]
    rng = np.random.default_rng(5)
    for t in rng.uniform(*r.domain, 12):
        i = min(int(np.searchsorted(r.joints, t, side="right")) - 1, len(r.joints) - 2)
        d = r.segment_derivatives(i, t)
        # the inner parameter: Newton on ⟨s(x) − q, s'(x)⟩ = 0 from the inner segment whose
        # arc length reaches c·(t − a)
        phi = c * (t - a)
        k = min(int(np.searchsorted(np.cumsum(seg_len), phi)), len(j) - 2)
        base = sum(seg_len[:k])
        x = j[k] + (j[k + 1] - j[k]) * (phi - base) / seg_len[k]
        q = d[0]
        for _ in range(30):
            e = s.segment_derivatives(k, x)
            q = q * (1.0 if np.dot(e[0], q) >= 0 else -1.0)
            g, h = np.dot(e[0] - q, e[1]), np.dot(e[1], e[1]) + np.dot(e[0] - q, e[2])
            x = float(np.clip(x - g / h, j[k], j[k + 1]))
        got = base + quad(speed, j[k], x, epsabs=1e-14, limit=200)[0]
        assert abs(got - phi) <= 1e-12 * seg_len[k] + 1e-11 * r.length, (t, got - phi)


@pytest.mark.parametrize("name", ["squad", "natural", "c3", "nonuniform", "beta"])
def test_arc_length_derivatives_match_finite_differences(name):
    r = qs.arc_length(SPLINES[name])
    h = 1e-4
    for t in _inside(r, 5):
        k = int(np.searchsorted(r.joints, t, side="right") - 1)
        d = r.segment_derivatives(k, t)
        for m in range(1, 4):
            num = fd(lambda x, m=m, k=k: r.segment_derivatives(k, x)[m - 1], t, h)
            assert np.linalg.norm(num - d[m]) <= 1e-6 * max(1.0, np.linalg.norm(d[m])), (m, t)


@pytest.mark.parametrize("name", ["squad", "natural", "c3", "nonuniform"])
def test_arc_length_keeps_the_continuity(name):
    s = SPLINES[name]
    r = qs.arc_length(s)
    assert r.continuity == s.continuity
    orders = [j.order for j in qs.continuity(r, tol=1e-7)]
    assert min(orders) >= s.continuity


def test_interpolating_keys_are_kept_in_order():
    s = SPLINES["natural"]
    r = qs.arc_length(s)
    assert len(r.joints) == len(s.joints)
    got, want = r(r.joints), s(s.joints)
    assert np.max(_angle(got, want)) < 1e-12


def test_holds_take_no_time():
    keys = np.vstack([KEYS[:2], KEYS[1:2], KEYS[2:4]])  # key 1 repeated: slerp holds still
    s = qs.PiecewiseSlerp(keys, [0.0, 1.0, 2.0, 3.0, 4.0])
    r = qs.arc_length(s)
    assert len(r.joints) == len(s.joints) - 1
    t = np.linspace(*r.domain, 1001)
    speed = np.linalg.norm(r.angular_velocity(t), axis=1)
    assert np.ptp(speed) <= 1e-9 * speed.mean()


def test_bad_input_for_arc_length():
    with pytest.raises(TypeError, match="spline: expected a quatspline.Spline"):
        qs.arc_length(KEYS)
    still = qs.PiecewiseSlerp(np.tile(KEYS[:1], (3, 1)))
    with pytest.raises(ValueError, match="does not rotate"):
        qs.reparameterize(still, "arc_length")
    with pytest.raises(ValueError, match="kind: expected 'angle' or 'arc_length'"):
        qs.reparameterize(SPLINES["squad"], "speed")


# ---- retime -------------------------------------------------------------------------------


def _dense_max(s, order, n=20001):
    t = np.concatenate([np.linspace(*s.domain, n), s.joints])
    f = s.angular_velocity if order == 1 else s.angular_acceleration
    return float(np.max(np.linalg.norm(f(t), axis=1)))


@pytest.mark.parametrize("name", ["squad", "natural", "c3", "nonuniform", "bezier"])
@pytest.mark.parametrize(("w_max", "a_max"), [(0.3, None), (None, 0.2), (0.5, 0.4), (5.0, 50.0)])
def test_retime_respects_the_bounds_and_is_tight(name, w_max, a_max):
    s = SPLINES[name]
    r = qs.retime(s, max_angular_velocity=w_max, max_angular_acceleration=a_max)
    lam = r.time_scale
    assert r.duration == pytest.approx(lam * (s.domain[1] - s.domain[0]), rel=1e-15)
    wv, av = _dense_max(r, 1), _dense_max(r, 2)
    if w_max is not None:
        assert wv <= w_max and qs.max_angular_rate(r, 1)[0] <= w_max
    if a_max is not None:
        assert av <= a_max and qs.max_angular_rate(r, 2)[0] <= a_max
    # tight: either the binding bound is reached, or nothing needed stretching (λ = 1)
    reached = []
    if w_max is not None:
        reached.append(qs.max_angular_rate(r, 1)[0] / w_max)
    if a_max is not None:
        reached.append(qs.max_angular_rate(r, 2)[0] / a_max)
    if lam > 1:
        assert max(reached) >= 1 - 1e-9
    else:
        assert lam == 1.0 and max(reached) <= 1
    # a shorter uniform stretch would break a bound: least duration among uniform stretches
    if lam > 1:
        x = lam * (1 - 1e-6)
        over = []
        if w_max is not None:
            over.append(qs.max_angular_rate(s, 1)[0] / x > w_max)
        if a_max is not None:
            over.append(qs.max_angular_rate(s, 2)[0] / x**2 > a_max)
        assert any(over)


def test_retime_scales_the_derivatives_exactly():
    s = SPLINES["c3"]
    r = qs.retime(s, max_angular_velocity=0.1)
    lam, a = r.time_scale, s.domain[0]
    t = np.linspace(*s.domain, 257)
    tr = a + lam * (t - a)
    assert np.max(np.abs(r(tr) - s(t))) < 1e-15
    for k, f in enumerate(("angular_velocity", "angular_acceleration", "jerk"), start=1):
        want = getattr(s, f)(t, frame="body") / lam**k
        got = getattr(r, f)(tr, frame="body")
        assert np.max(np.abs(got - want)) <= 1e-13 * max(1.0, np.abs(want).max())
    assert [j.order for j in qs.continuity(r)] == [j.order for j in qs.continuity(s)]


def test_shrink_speeds_up_a_slow_spline():
    s = SPLINES["natural"]
    slow = qs.retime(s, max_angular_velocity=100.0)
    assert slow.time_scale == 1.0 and slow.duration == s.domain[1] - s.domain[0]
    fast = qs.retime(s, max_angular_velocity=100.0, shrink=True)
    assert fast.time_scale < 1
    assert qs.max_angular_rate(fast)[0] == pytest.approx(100.0, rel=1e-9)
    assert _dense_max(fast, 1) <= 100.0


@pytest.mark.parametrize(
    ("kwargs", "err", "msg"),
    [
        (dict(max_angular_velocity=0.0), ValueError, "max_angular_velocity: expected a finite"),
        (dict(max_angular_velocity=-1.0), ValueError, "max_angular_velocity"),
        (dict(max_angular_velocity=np.nan), ValueError, "max_angular_velocity"),
        (dict(max_angular_velocity=np.inf), ValueError, "max_angular_velocity"),
        (dict(max_angular_acceleration=0.0), ValueError, "max_angular_acceleration"),
        (dict(max_angular_acceleration=-np.inf), ValueError, "max_angular_acceleration"),
        (dict(max_angular_velocity="1"), TypeError, "max_angular_velocity: expected a number"),
        (dict(max_angular_acceleration=[1.0]), TypeError, "max_angular_acceleration"),
        (dict(), ValueError, "give max_angular_velocity and/or max_angular_acceleration"),
    ],
)
def test_bad_bounds(kwargs, err, msg):
    with pytest.raises(err, match=msg):
        qs.retime(SPLINES["squad"], **kwargs)
    with pytest.raises(TypeError, match="spline"):
        qs.retime("squad", max_angular_velocity=1.0)


def test_arc_length_keeps_the_extrapolation_rule():
    s = qs.NaturalSpline(KEYS, TIMES, extrapolate="linear")
    r = qs.arc_length(s)
    assert r.extrapolate == "linear"
    c = r.length / r.duration
    a, b = r.domain
    speed = np.linalg.norm(r.angular_velocity([a - 1.0, b + 0.5, b + 3.0]), axis=1)
    assert np.allclose(speed, c, rtol=1e-12)  # the constant speed carries on past the ends
    p = qs.arc_length(qs.NaturalSpline(KEYS, TIMES, extrapolate="periodic"))
    t = np.linspace(a, b, 9)[1:-1]
    assert np.allclose(p(t + (b - a)), p(t), atol=1e-13)
