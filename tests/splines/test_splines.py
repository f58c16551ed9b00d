"""The spline family: interpolation, exact derivatives, continuity at joints, invariances."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import fd, joint_jumps, random_times, random_walk

N = 8
# method name -> (constructor from keys and times, claimed C^k, interpolates)
METHODS = {
    "slerp": (lambda q, t: qs.PiecewiseSlerp(q, t), 0, True),
    "nlerp": (lambda q, t: qs.PiecewiseNlerp(q, t), 0, True),
    "lin_euler": (lambda q, t: qs.PiecewiseLinEuler(q, t, seq="ZYX"), 0, True),
    "lin_mat": (lambda q, t: qs.PiecewiseLinMat(q, t), 0, True),
    "squad": (lambda q, t: qs.Squad(q, t), 1, True),
    "catmull_rom": (lambda q, t: qs.CatmullRom(q, t), 1, True),
    "catmull_rom_duplicate": (lambda q, t: qs.CatmullRom(q, t, ends="duplicate"), 1, True),
    "natural": (lambda q, t: qs.NaturalSpline(q, t), 2, True),
    "natural_clamped": (lambda q, t: qs.NaturalSpline(q, t, ends="clamped"), 2, True),
    "bspline": (lambda q, t: qs.CumulativeBSpline(q, dt=0.7, t0=t[0]), 2, False),
    "beta": (lambda q, t: qs.BetaSpline(q, beta1=1.7, beta2=0.3, times=t[: len(q) - 2]), 0, False),
    "c3_knot": (
        lambda q, t: qs.C3Spline(q, t, alpha=np.linspace(0.2, 0.4, len(q)), beta=0.3),
        3,
        True,
    ),
    "c3_patent": (
        lambda q, t: qs.C3Spline(q, t, alpha=0.3, beta=0.1, variant="patent"),
        None,
        True,
    ),
    "hermite": (
        lambda q, t: qs.Hermite(q, t, np.sin(np.outer(np.arange(len(q)), [1.0, 2.0, 3.0]))),
        1,
        True,
    ),
    "hermite_quintic": (
        lambda q, t: qs.Hermite(
            q, t, np.cos(np.outer(np.arange(len(q)), [1.0, 2.0, 3.0])), np.ones((len(q), 3))
        ),
        2,
        True,
    ),
    "kochanek_bartels": (lambda q, t: qs.KochanekBartels(q, t, tension=0.3, bias=-0.2), 1, True),
    "catmull_rom_rest": (lambda q, t: qs.CatmullRom(q, t, ends="rest"), 1, True),
    "natural_rest": (lambda q, t: qs.NaturalSpline(q, t, ends="rest"), 2, True),
}
TIMES = ["uniform", "nonuniform"]


def build(name, kind, seed=0):
    q = random_walk(N, seed)
    t = np.arange(N, dtype=float) if kind == "uniform" else random_times(N, seed)
    ctor, order, interp = METHODS[name]
    return ctor(q, t), q, t, order, interp


def same_rotation(a, b, tol):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    return np.all(d <= tol)


@pytest.mark.parametrize("kind", TIMES)
@pytest.mark.parametrize("name", list(METHODS))
def test_interpolates_keys_where_claimed(name, kind):
    s, q, t, _, interp = build(name, kind)
    if interp:
        assert same_rotation(s(t), q, 1e-14)
    else:
        assert not same_rotation(s(s.joints), q[: len(s.joints)], 1e-3)


@pytest.mark.parametrize("kind", TIMES)
@pytest.mark.parametrize("name", list(METHODS))
def test_unit_norm_everywhere(name, kind):
    s, *_ = build(name, kind)
    a, b = s.domain
    q = s(np.linspace(a, b, 2001))
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=2e-15)


@pytest.mark.parametrize("kind", TIMES)
@pytest.mark.parametrize("name", list(METHODS))
def test_derivatives_match_finite_differences(name, kind):
    s, *_ = build(name, kind, seed=3)
    j = s.joints
    # interior points of every segment (finite differences must not straddle a joint)
    u = np.array([0.2, 0.5, 0.8])
    t = (j[:-1, None] + (j[1:] - j[:-1])[:, None] * u).ravel()
    h = 1e-3 * np.min(np.diff(j))
    d = s.derivatives(t, 3)
    for k in (1, 2, 3):
        num = fd(lambda x, k=k: s.derivative(x, k - 1), t, h)
        scale = np.maximum(1.0, np.linalg.norm(d[:, k], axis=1))[:, None]
        assert np.max(np.abs(d[:, k] - num) / scale) < 1e-7, f"order {k}"
    # angular rates are consistent with the quaternion derivatives
    w = s.angular_velocity(t)
    wq = 2 * qs.multiply(d[:, 1], qs.conjugate(d[:, 0]))
    np.testing.assert_allclose(w, wq[:, 1:], atol=1e-12)
    np.testing.assert_allclose(np.abs(wq[:, 0]), 0, atol=1e-12)
    wb = s.angular_velocity(t, frame="body")
    np.testing.assert_allclose(qs.rotate(d[:, 0], wb), w, atol=1e-12)
    for frame in ("world", "body"):
        for lower, higher in (
            (s.angular_velocity, s.angular_acceleration),
            (s.angular_acceleration, s.jerk),
        ):
            g = higher(t, frame=frame)
            num = fd(lambda x, lower=lower, frame=frame: lower(x, frame=frame), t, h)
            scale = np.maximum(1.0, np.linalg.norm(g, axis=1))[:, None]
            assert np.max(np.abs(g - num) / scale) < 1e-7, (higher.__name__, frame)


@pytest.mark.parametrize("kind", TIMES)
@pytest.mark.parametrize("name", list(METHODS))
def test_continuity_at_joints_matches_claim(name, kind):
    s, _, _, order, _ = build(name, kind, seed=5)
    if order is None:  # the patent form: C³ only for uniform times (tests in test_c3.py)
        order = 3 if kind == "uniform" else 0
    jumps = joint_jumps(s, 3)
    assert jumps.shape[0] > 0
    assert np.all(jumps[:, : order + 1] <= 1e-9), jumps
    # the next order visibly jumps, so this test can fail (C⁴ for C³ splines: test_c3.py)
    if order < 3:
        assert np.max(jumps[:, order + 1]) > 1e-4, jumps


@pytest.mark.parametrize("name", ["slerp", "squad", "catmull_rom", "natural", "natural_clamped"])
def test_sign_flipped_input_gives_the_same_curve(name):
    q = random_walk(N, 7)
    t = random_times(N, 7)
    flipped = q.copy()
    flipped[1::2] *= -1
    ctor = METHODS[name][0]
    a, b = ctor(q, t), ctor(flipped, t)
    x = np.linspace(t[0], t[-1], 501)
    assert same_rotation(a(x), b(x), 1e-14)
    np.testing.assert_allclose(a.angular_velocity(x), b.angular_velocity(x), atol=1e-12)


def test_two_keys_give_slerp():
    q = random_walk(2, 9)
    t = np.array([1.0, 3.0])
    x = np.linspace(1, 3, 101)
    ref = qs.slerp(q[0], q[1], (x - 1) / 2)
    for s in (
        qs.PiecewiseSlerp(q, t),
        qs.Squad(q, t),
        qs.CatmullRom(q, t),
        qs.NaturalSpline(q, t),
        qs.NaturalSpline(q, t, ends="clamped"),
    ):
        assert same_rotation(s(x), ref, 1e-14), type(s).__name__


def test_consecutive_antipodal_keys_are_the_same_rotation():
    q = random_walk(4, 11)
    # q1 then −q1: the same rotation twice, handled exactly like a repeated key
    antipodal = np.vstack([q[:2], -q[1:2], q[2:]])
    repeated = np.vstack([q[:2], q[1:2], q[2:]])
    x = np.linspace(0, 4, 101)
    for S in (qs.PiecewiseSlerp, qs.Squad, qs.CatmullRom, qs.NaturalSpline):
        a, b = S(antipodal), S(repeated)
        assert same_rotation(a(x), b(x), 1e-14), S.__name__
        assert np.all(np.isfinite(a.jerk(x)))
    # piecewise slerp holds still on the zero-length segment
    np.testing.assert_allclose(qs.PiecewiseSlerp(antipodal).angular_velocity(1.5), 0, atol=1e-15)


def test_keys_exactly_180_degrees_apart_are_deterministic():
    a = np.array([1.0, 0, 0, 0])
    b = np.array([0.0, 0, 0, 1])  # 180° about z: a·b = 0
    for S in (qs.PiecewiseSlerp, qs.Squad, qs.CatmullRom, qs.NaturalSpline):
        s = S([a, b, a])
        x = np.linspace(0, 2, 41)
        v1, v2 = s(x), S([a, b, a])(x)
        assert np.all(np.isfinite(v1)) and np.array_equal(v1, v2)
        assert np.all(np.isfinite(s.angular_velocity(x)))


def test_bspline_cubic_matches_basis_and_general_order():
    q = random_walk(7, 13)
    s = qs.CumulativeBSpline(q, dt=0.5, t0=2.0)
    assert s.domain == (2.0, 4.0)
    u = 0.3
    b1 = (5 + 3 * u - 3 * u**2 + u**3) / 6
    b2 = (1 + 3 * u + 3 * u**2 - 2 * u**3) / 6
    b3 = u**3 / 6
    w = [qs.log(qs.multiply(qs.conjugate(q[i]), q[i + 1])) for i in range(3)]
    ref = qs.multiply(
        qs.multiply(qs.multiply(q[0], qs.exp(b1 * w[0])), qs.exp(b2 * w[1])), qs.exp(b3 * w[2])
    )
    np.testing.assert_allclose(s(2.0 + 0.5 * u), ref, atol=1e-15)
    for k, c in ((3, 1), (5, 3), (6, 4)):
        sk = qs.CumulativeBSpline(q, order=k)
        assert sk.continuity == c
        jumps = joint_jumps(sk, 3)
        assert np.all(jumps[:, : min(c, 3) + 1] <= 1e-9)
        if c + 1 <= 3:
            assert np.max(jumps[:, c + 1]) > 1e-4


def test_bezier_forms_share_end_tangents_but_differ_inside():
    c = random_walk(4, 17)
    a, b = qs.SphericalBezier(c), qs.CumulativeBezier(c)
    for t in (0.0, 1.0):
        np.testing.assert_allclose(a(t), b(t), atol=1e-15)
        np.testing.assert_allclose(a.derivative(t), b.derivative(t), atol=1e-13)
    assert not np.allclose(a(0.5), b(0.5), atol=1e-4)
    # q'(0) = n q0 log(q0* q1)
    np.testing.assert_allclose(
        a.derivative(0.0),
        3 * qs.multiply(c[0], qs.log(qs.multiply(qs.conjugate(c[0]), c[1]))),
        atol=1e-13,
    )


def test_squad_uniform_matches_shoemake_control_points():
    q = random_walk(5, 19)
    s = qs.Squad(q)

    def ctrl(i):
        a = qs.log(qs.multiply(qs.conjugate(q[i - 1]), q[i]))
        b = qs.log(qs.multiply(qs.conjugate(q[i]), q[i + 1]))
        return qs.multiply(q[i], qs.exp((a - b) / 4))

    u = 0.37
    i = 2
    ref = qs.slerp(
        qs.slerp(q[i], q[i + 1], u, long_path=True),
        qs.slerp(ctrl(i), ctrl(i + 1), u, long_path=True),
        2 * u * (1 - u),
        long_path=True,
    )
    np.testing.assert_allclose(s(i + u), ref, atol=1e-14)


def test_extrapolation_raise_and_clamp():
    q = random_walk(4, 21)
    s = qs.Squad(q)
    with pytest.raises(ValueError, match=r"t\[1\] = 3.5 is outside the spline's domain \[0, 3\]"):
        s([1.0, 3.5])
    c = qs.Squad(q, extrapolate="clamp")
    np.testing.assert_allclose(c([-1.0, 4.0]), c([0.0, 3.0]), atol=0)
    np.testing.assert_array_equal(c.angular_velocity([-1.0, 4.0]), 0.0)


def test_unsorted_times_and_shapes():
    s = qs.CatmullRom(random_walk(5, 23))
    t = np.array([[3.2, 0.1], [2.5, 1.9]])
    out = s(t)
    assert out.shape == (2, 2, 4)
    np.testing.assert_allclose(out[0, 0], s(3.2), atol=0)
    assert s(1.0).shape == (4,)
    assert s.angular_velocity(t).shape == (2, 2, 3)
    big = np.random.default_rng(0).uniform(0, 4, 50_000)  # parallel path
    np.testing.assert_array_equal(s(big)[:100], s(big[:100]))


def test_sample():
    s = qs.PiecewiseSlerp(random_walk(3, 25), times=[0.0, 0.5, 1.0])
    t, q = s.sample(n=11)
    assert t.shape == (11,) and q.shape == (11, 4) and t[-1] == 1.0
    t, _ = s.sample(rate=100)
    assert len(t) == 101 and abs(t[-1] - 1.0) < 1e-12


def test_path_length_and_reparameterize():
    q = random_walk(6, 27)
    t = np.array([0.0, 0.1, 0.2, 3.0, 3.1, 5.0])
    s = qs.PiecewiseSlerp(q, t)
    steps = [2 * np.arccos(min(1.0, abs(np.dot(q[i], q[i + 1])))) for i in range(5)]
    assert abs(qs.path_length(s) - sum(steps)) < 1e-9
    r = qs.reparameterize(s, "angle")
    assert r.domain == s.domain
    speeds = np.linalg.norm(r.angular_velocity(r.joints[:-1] + 1e-6), axis=1)
    np.testing.assert_allclose(speeds, speeds.mean(), rtol=1e-6)
    with pytest.raises(ValueError, match="interpolating"):
        qs.reparameterize(qs.CumulativeBSpline(q), "angle")
