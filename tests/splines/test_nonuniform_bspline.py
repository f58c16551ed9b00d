"""Non-uniform cumulative B-splines: uniform knots = the uniform spline, scipy BSpline about a
fixed axis, finite differences, continuity by knot multiplicity, clamping, bad knots."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.interpolate import BSpline

from ..splinekit import fd, random_walk


def _dense(s, n=301):
    a, b = s.domain
    return np.concatenate([np.linspace(a, b, n), s.joints])


@pytest.mark.parametrize("order", [2, 3, 4, 5, 6, 8])
def test_uniform_knots_equal_the_uniform_spline(order):
    q = random_walk(12, seed=order)
    dt, t0 = 0.37, -1.3
    knots = t0 + (np.arange(12 + order) - (order - 1)) * dt
    a = qs.CumulativeBSpline(q, knots=knots, order=order)
    b = qs.CumulativeBSpline(q, dt=dt, t0=t0, order=order)
    assert np.allclose(a.joints, b.joints, rtol=0, atol=1e-15)
    t = np.linspace(*b.domain, 997)[1:-1]
    # derivatives compared in the local parameter u = (t − tᵢ)/Δt: q^(m) × Δt^m
    unit = (dt ** np.arange(4))[:, None]
    da, db = a.derivatives(t, 3) * unit, b.derivatives(t, 3) * unit
    assert np.max(np.abs(da - db)) <= 1e-14
    assert a.continuity == b.continuity == order - 2


@pytest.mark.parametrize("order", [2, 3, 4, 6])
def test_fixed_axis_equals_scipy_bspline(order):
    """About one axis the rotations commute: q(t) = exp(θ(t) n / 2) with θ = Σ Bₗ θₗ, the
    Euclidean B-spline of the control angles (scipy), and ω = θ'(t) n."""
    rng = np.random.default_rng(order)
    n = 9
    theta = np.cumsum(rng.uniform(-0.8, 0.8, n))
    axis = np.array([0.48, -0.6, 0.64])
    q = qs.from_rotvec(theta[:, None] * axis)
    knots = np.sort(rng.uniform(0, 5, n + order))
    s = qs.CumulativeBSpline(q, knots=knots, order=order)
    ref = BSpline(knots, theta, order - 1)
    t = _dense(s)
    got = qs.as_rotvec(s(t)) @ axis
    assert np.max(np.abs(got - ref(t))) < 1e-13
    w = s.angular_velocity(t) @ axis
    assert np.max(np.abs(w - ref.derivative(1)(t))) < 1e-11 * max(1, np.abs(w).max())
    if order >= 3:
        acc = s.angular_acceleration(t[: -len(s.joints)]) @ axis  # away from C¹ joints
        ref2 = ref.derivative(2)(t[: -len(s.joints)])
        assert np.max(np.abs(acc - ref2)) < 1e-10 * max(1, np.abs(ref2).max())


@pytest.mark.parametrize(
    "knots",
    [
        [0, 0, 0, 0, 0.4, 1.7, 1.9, 3.0, 3.0, 3.0, 3.0],  # clamped, uneven
        [-1, -0.5, 0, 0.1, 0.3, 0.3, 1.2, 2.0, 2.7, 3.5, 4.0],  # a double knot inside
    ],
)
def test_derivatives_match_finite_differences(knots):
    q = random_walk(7, seed=5)
    s = qs.CumulativeBSpline(q, knots=knots, order=4)
    h = 1e-4
    for seg in range(len(s.joints) - 1):
        a, b = s.joints[seg], s.joints[seg + 1]
        for u in (0.2, 0.5, 0.8):
            t = a + u * (b - a)
            d = s.segment_derivatives(seg, t)
            for m in range(1, 4):
                num = fd(lambda x, m=m, seg=seg: s.segment_derivatives(seg, x)[m - 1], t, h)
                assert np.linalg.norm(num - d[m]) <= 2e-7 * max(1.0, np.linalg.norm(d[m]))


def test_continuity_follows_knot_multiplicity():
    q = random_walk(11, seed=2)
    knots = [0, 1, 2, 3, 4, 4, 5, 6, 6, 6, 7, 8, 9, 10, 11]  # domain [3, 8]; 4 double, 6 triple
    s = qs.CumulativeBSpline(q, knots=knots, order=4)
    assert s.continuity == 0
    by_time = {round(j.time, 9): j.order for j in qs.continuity(s)}
    assert by_time[4.0] == 1 and by_time[6.0] == 0
    assert by_time[5.0] == 2 and by_time[7.0] == 2
    # simple knots everywhere: C² at every joint, certified
    s2 = qs.CumulativeBSpline(q, knots=np.cumsum(np.r_[0, np.linspace(0.5, 1.5, 14)]), order=4)
    assert s2.continuity == 2 and all(j.order == 2 for j in qs.continuity(s2))


def test_clamped_knots_interpolate_the_end_rotations():
    q = random_walk(6, seed=3)
    knots = qs.splines.knots.clamped_knots([0.0, 0.5, 2.0, 2.2], order=4)
    s = qs.CumulativeBSpline(q, knots=knots, order=4)
    assert np.allclose(s.joints, [0.0, 0.5, 2.0, 2.2])
    qn = qs.canonicalize(q / np.linalg.norm(q, axis=1, keepdims=True), q[:1])
    for got, want in ((s(0.0), qn[0]), (s(2.2), qn[-1])):
        assert min(np.abs(got - want).max(), np.abs(got + want).max()) < 1e-14


def test_spacings_give_the_same_spline_as_knots():
    q = random_walk(6, seed=4)
    dt = [0.5, 1.0, 0.2, 0.7, 0.0, 1.3, 0.4, 0.9, 1.1]
    a = qs.CumulativeBSpline(q, dt=dt, t0=2.0, order=4)
    u = qs.splines.knots.knots_from_spacing(dt, 2.0, 6, 4)
    b = qs.CumulativeBSpline(q, knots=u, order=4)
    t = _dense(a)
    assert a.domain[0] == 2.0 and np.array_equal(a(t), b(t))


def test_in_the_registry():
    q = random_walk(6, seed=6)
    t = [0.0, 0.2, 1.0, 1.1, 2.5, 4.0]
    s = qs.spline("nonuniform_bspline", q, t)
    assert s.domain == (0.0, 4.0) and np.allclose(s.joints, t)
    assert s.method == "nonuniform_bspline" and s.continuity == 2


@pytest.mark.parametrize(
    ("kwargs", "err", "msg"),
    [
        (dict(knots=[0, 1, 2, 3, 4, 5, 6]), ValueError, r"at least 2·k = 8 knots"),
        (dict(knots=np.arange(10.0)), ValueError, "expected n \\+ k = 9 knots"),
        (dict(knots=[0, 1, 2, 3, 2.5, 5, 6, 7, 8]), ValueError, "not non-decreasing at index 4"),
        (dict(knots=[0, 1, 2, 3, 3, 3, 3, 7, 8]), ValueError, r"domain \[u_3, u_5\] = \[3, 3\]"),
        (dict(knots=[0, 0, 0, 0, 0, 1, 2, 3, 4]), ValueError, "repeats 5 times"),
        (dict(knots=[0, 1, 2, 3, np.nan, 5, 6, 7, 8]), ValueError, "knots: non-finite"),
        (dict(knots=[[0, 1, 2, 3, 4, 5, 6, 7, 8]]), ValueError, "knots: expected a 1-D"),
        (dict(knots=[0, 1, 2, 3, 3, 3, 6, 7, 8], order=3), ValueError, "expected n \\+ k = 8"),
        (dict(dt=[1.0] * 7), ValueError, "dt: expected a scalar or n \\+ k − 1 = 8"),
        (dict(dt=[1.0, -1, 1, 1, 1, 1, 1, 1]), ValueError, "dt: negative spacing at element 1"),
        (dict(dt=[1.0, 1, 1, np.inf, 1, 1, 1, 1]), ValueError, "dt: non-finite"),
        (dict(dt=[1.0] * 8, knots=np.arange(9.0)), ValueError, "either knots or dt"),
        (dict(knots=np.arange(9.0), order=2.0), TypeError, "order"),
        (dict(knots=np.arange(9.0), order=1), ValueError, "order"),
    ],
)
def test_bad_knots(kwargs, err, msg):
    q = random_walk(5, seed=1)
    with pytest.raises(err, match=msg):
        qs.CumulativeBSpline(q, **kwargs)


def test_interior_knot_repeated_k_times_is_rejected():
    with pytest.raises(
        ValueError, match="knots: knot 4 \\(index 4\\) repeats 4 times; at most 3 inside"
    ):
        qs.CumulativeBSpline(random_walk(8, 1), knots=[0, 1, 2, 3, 4, 4, 4, 4, 5, 6, 7, 8])


def test_cli_samples_the_nonuniform_bspline(tmp_path):
    from quatspline.cli import main
    from quatspline.io import Trajectory, read, write

    q = random_walk(6, seed=7)
    t = np.array([0.0, 0.2, 1.0, 1.1, 2.5, 4.0])
    write(tmp_path / "in.csv", Trajectory(t, q))
    out = tmp_path / "out.csv"
    assert (
        main(
            [
                "sample",
                str(tmp_path / "in.csv"),
                "-o",
                str(out),
                "--method",
                "nonuniform_bspline",
                "--count",
                "9",
            ]
        )
        == 0
    )
    got = read(out)
    want = qs.spline("nonuniform_bspline", q, t)(np.linspace(0.0, 4.0, 9))
    d = np.minimum(np.abs(got.quats - want).max(1), np.abs(got.quats + want).max(1))
    assert d.max() < 1e-9
