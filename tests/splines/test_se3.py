"""SE(3) splines: ScrewSpline (both variants) and PoseBSpline (both formulations, uniform and
non-uniform knots) — exact derivatives against finite differences, twists against their
definitions, certificates against one-sided differences, cross-checks with scipy."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.interpolate import BSpline

from ..splinekit import fd, random_times, random_walk

N = 6
Q = random_walk(N, seed=21, step=0.8)
T = random_times(N, seed=21)
P = np.random.default_rng(21).normal(scale=2.0, size=(N, 3))


def _make(kind):
    if kind == "screw":
        return qs.ScrewSpline(Q, T, P)
    if kind == "screw_smooth":
        return qs.ScrewSpline(Q, T, P, smooth=True, alpha=0.4, beta=0.1)
    if kind == "pose_bspline":
        return qs.PoseBSpline(Q, P, dt=0.7, t0=0.3)
    if kind == "pose_bspline_knots":
        return qs.PoseBSpline(Q, P, knots=[0, 0.2, 0.9, 1.0, 1.6, 2.9, 3.0, 3.4, 4.1, 5.0])
    if kind == "split":
        return qs.PoseBSpline(
            Q, P, knots=[0, 0.2, 0.9, 1.0, 1.6, 2.9, 3.0, 3.4, 4.1, 5.0], formulation="split"
        )
    raise AssertionError(kind)


KINDS = ["screw", "screw_smooth", "pose_bspline", "pose_bspline_knots", "split"]


def _interior(s, n=4):
    j = s.joints
    out = []
    for k in range(len(j) - 1):
        for u in np.linspace(0, 1, n + 2)[1:-1]:
            out.append((k, j[k] + u * (j[k + 1] - j[k])))
    return out


@pytest.mark.parametrize("kind", KINDS)
def test_position_and_rotation_derivatives_match_finite_differences(kind):
    s = _make(kind)
    h = 1e-4
    for _, t in _interior(s, 3):
        for m in range(1, 4):
            exact = s.position(t, m)
            num = fd(lambda x, m=m: s.position(x, m - 1), t, h)
            assert np.linalg.norm(num - exact) <= 1e-6 * max(1.0, np.linalg.norm(exact)), (m, t)
            qe = s.derivative(t, m)
            qn = fd(lambda x, m=m: s.derivative(x, m - 1), t, h)
            assert np.linalg.norm(qn - qe) <= 1e-6 * max(1.0, np.linalg.norm(qe)), (m, t)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("frame", ["body", "world"])
def test_twists_match_their_definitions_and_derivatives(kind, frame):
    s = _make(kind)
    h = 1e-4
    for _, t in _interior(s, 3):
        tw = s.twist(t, frame)
        q, p, v = s.orientation(t), s.position(t), s.linear_velocity(t)
        if frame == "body":
            want = np.r_[s.angular_velocity(t, "body"), qs.rotate(qs.conjugate(q), v)]
            assert np.allclose(s.linear_velocity(t, "body"), want[3:], atol=1e-12)
        else:
            w = s.angular_velocity(t)
            want = np.r_[w, v - np.cross(w, p)]
        assert np.allclose(tw, want, rtol=0, atol=1e-12 * max(1, np.abs(want).max()))
        for order in (2, 3):
            exact = s.twist(t, frame, order)
            num = fd(lambda x, o=order: s.twist(x, frame, o - 1), t, h)
            assert np.linalg.norm(num - exact) <= 1e-6 * max(1.0, np.linalg.norm(exact))
    # angular parts equal the rotation spline's own rates
    t = np.array([x for _, x in _interior(s, 2)])
    assert np.allclose(s.twist(t, frame, 2)[:, :3], s.angular_acceleration(t, frame), atol=1e-11)


@pytest.mark.parametrize("kind", KINDS)
def test_certificates_against_one_sided_differences(kind):
    s = _make(kind)
    h = 1e-5
    rot, tra = qs.continuity(s), s.continuity_translation()
    j = s.joints

    def dual(x):
        return s.dual_quaternions(x)[4:]

    for jr, jt, tk in zip(rot, tra, j[1:-1]):
        # one-sided slopes of the dual part (3-point, O(h²)) vs the certificate's jump
        right = (-3 * dual(tk) + 4 * dual(tk + h) - dual(tk + 2 * h)) / (2 * h)
        left = (3 * dual(tk) - 4 * dual(tk - h) + dual(tk - 2 * h)) / (2 * h)
        assert abs(np.linalg.norm(right - left) - jt.jump_abs[1]) < 1e-5
        assert jt.jump_abs[0] < 1e-13 and jr.jump_abs[0] < 1e-13  # continuous pose
    want = {"screw": 0, "screw_smooth": 3, "pose_bspline": 2, "pose_bspline_knots": 2, "split": 2}
    assert s.continuity == want[kind]
    assert min(x.order for x in rot) == min(x.order for x in tra) == want[kind]
    if kind == "screw":  # velocity really jumps: the certificate sees it
        assert max(x.jump_abs[1] for x in tra) > 1e-2


def test_piecewise_screw_has_constant_body_twist_per_segment():
    s = _make("screw")
    for k in range(N - 1):
        t = np.linspace(T[k], T[k + 1], 7)[1:-1]
        tw = s.twist(t, "body")
        assert np.ptp(tw, axis=0).max() < 1e-12
        rel = qs.multiply(qs.conjugate(Q[k]), Q[k + 1])
        assert np.allclose(tw[0, :3], qs.as_rotvec(rel) / (T[k + 1] - T[k]), atol=1e-12)


def test_screw_spline_on_two_keys_is_sclerp_and_interpolates():
    s = qs.ScrewSpline(Q[:2], T[:2], P[:2])
    x = np.linspace(T[0], T[1], 11)
    ref = qs.sclerp(
        qs.dq_from_pose(Q[0], P[0]), qs.dq_from_pose(Q[1], P[1]), (x - T[0]) / (T[1] - T[0])
    )
    got = s.dual_quaternions(x)
    assert np.minimum(np.abs(got - ref).max(1), np.abs(got + ref).max(1)).max() < 1e-13
    for smooth in (False, True):
        q, p = qs.ScrewSpline(Q, T, P, smooth=smooth)(T)
        assert np.abs(p - P).max() < 1e-12


def test_transform_points_and_clamp():
    s = qs.ScrewSpline(Q, T, P, smooth=True, extrapolate="clamp")
    pts = np.array([[1.0, 0, 0], [0, 2.0, -1]])
    x = np.array([T[0] - 1, 0.5 * (T[1] + T[2]), T[-1] + 3])
    got = s.transform_points(x, pts)
    q, p = s(x)
    want = qs.rotate(q[:, None, :], pts[None]) + p[:, None, :]
    assert np.allclose(got, want, atol=1e-13)
    assert np.allclose(got[0], qs.rotate(Q[0], pts) + P[0], atol=1e-12)
    assert np.all(s.linear_velocity(x[[0, 2]]) == 0) and np.all(s.twist(x[[0, 2]]) == 0)
    with pytest.raises(ValueError, match="outside the spline's domain"):
        qs.ScrewSpline(Q, T, P).position(T[-1] + 1)


@pytest.mark.parametrize("formulation", ["se3", "split"])
def test_pose_bspline_rotation_is_the_so3_bspline(formulation):
    knots = [0, 0.2, 0.9, 1.0, 1.6, 2.9, 3.0, 3.4, 4.1, 5.0]
    s = qs.PoseBSpline(Q, P, knots=knots, formulation=formulation)
    r = qs.CumulativeBSpline(Q, knots=knots)
    t = np.linspace(*s.domain, 301)
    assert np.abs(s.derivatives(t, 3) - r.derivatives(t, 3)).max() < 1e-13 * max(
        1, np.abs(r.derivatives(t, 3)).max()
    )
    u = qs.PoseBSpline(Q, P, dt=0.5, t0=1.0, formulation=formulation)
    ru = qs.CumulativeBSpline(Q, dt=0.5, t0=1.0)
    tu = np.linspace(*u.domain, 301)
    assert np.abs(u(tu)[0] - ru(tu)).max() < 1e-14


def test_pose_bspline_positions_against_scipy():
    knots = np.array([0, 0.2, 0.9, 1.0, 1.6, 2.9, 3.0, 3.4, 4.1, 5.0])
    ref = BSpline(knots, P, 3)
    split = qs.PoseBSpline(Q, P, knots=knots, formulation="split")
    t = np.linspace(*split.domain, 201)
    for m in range(3):
        want = ref(t) if m == 0 else ref.derivative(m)(t)
        assert np.abs(split.position(t, m) - want).max() < 1e-12 * max(1, np.abs(want).max())
    # SE(3) form with pure translations is the Euclidean B-spline too
    ident = np.tile([1.0, 0, 0, 0], (N, 1))
    se3 = qs.PoseBSpline(ident, P, knots=knots)
    assert np.abs(se3.position(t) - ref(t)).max() < 1e-12
    # with rotations the coupled SE(3) form differs from the split one (screw motion)
    assert np.abs(qs.PoseBSpline(Q, P, knots=knots).position(t) - ref(t)).max() > 1e-3


def test_pose_bspline_uniform_fast_path_equals_de_boor():
    # knots uniform to rounding but not bit-equal take the De Boor path
    k1 = 0.3 + 0.7 * (np.arange(N + 4) - 3.0)
    k2 = k1 + np.r_[0.0, 1e-15, 0, 0, 0, 0, 0, 0, 0, 0]
    a = qs.PoseBSpline(Q, P, knots=k1)
    b = qs.PoseBSpline(Q, P, knots=k2)
    t = np.linspace(*a.domain, 101)
    assert np.abs(a.position(t, 2) - b.position(t, 2)).max() < 1e-12
    assert np.abs(a.twist(t, order=3) - b.twist(t, order=3)).max() < 1e-11


def test_pose_registry():
    for name in qs.registry.POSE_METHODS:
        s = qs.registry.pose_spline(name, Q, T, P)
        assert s.domain == (T[0], T[-1]) and isinstance(s, qs.Spline)
        if qs.registry.POSE_METHODS[name].interpolating:
            assert np.abs(s.position(T) - P).max() < 1e-12
    s = qs.registry.pose_spline("pose_bspline", Q, T, P, formulation="split")
    assert s.method == "pose_bspline_split" and s.continuity == 2
    with pytest.raises(ValueError, match="method: unknown pose method 'spline'"):
        qs.registry.pose_spline("spline", Q, T, P)
    with pytest.raises(ValueError, match="order: unknown parameter of screw"):
        qs.registry.pose_spline("screw", Q, T, P, order=3)


@pytest.mark.parametrize(
    ("make", "err", "msg"),
    [
        (lambda: qs.ScrewSpline(Q, T, P[:3]), ValueError, "times/quats/positions"),
        (lambda: qs.ScrewSpline(Q, T[::-1], P), ValueError, "times: not strictly increasing"),
        (lambda: qs.ScrewSpline(Q[:1], T[:1], P[:1]), ValueError, "quats: needs at least 2"),
        (lambda: qs.ScrewSpline(Q, T, P + np.nan), ValueError, "positions: non-finite"),
        (lambda: qs.ScrewSpline(Q * 0, T, P), ValueError, "quats: quaternion 0 has zero"),
        (lambda: qs.PoseBSpline(Q, P[:4]), ValueError, "positions: expected shape \\(6, 3\\)"),
        (lambda: qs.PoseBSpline(Q, P, knots=[0, 1, 2]), ValueError, "at least 2·k = 8 knots"),
        (
            lambda: qs.PoseBSpline(Q, P, knots=np.arange(10.0)[::-1]),
            ValueError,
            "not non-decreasing",
        ),
        (lambda: qs.PoseBSpline(Q, P, dt=0.0), ValueError, "dt: expected a finite positive"),
        (lambda: qs.PoseBSpline(Q, P, formulation="lie"), ValueError, "formulation"),
        (lambda: qs.PoseBSpline(Q, P, formulation=1), TypeError, "formulation"),
        (lambda: qs.PoseBSpline(Q, P, order=7), ValueError, "control_quats: needs at least 7"),
        (lambda: qs.PoseBSpline(Q, P, order="4"), TypeError, "order"),
        (lambda: _make("screw").twist(T[1], order=4), ValueError, "order"),
        (lambda: _make("screw").twist(T[1], frame="local"), ValueError, "frame"),
        (lambda: _make("screw").position(T[1], order=5), ValueError, "order"),
    ],
)
def test_bad_input(make, err, msg):
    with pytest.raises(err, match=msg):
        make()


@pytest.mark.parametrize("kind", ["screw_smooth", "pose_bspline_knots"])
def test_linear_and_periodic_extrapolation(kind):
    s = _make(kind)
    a, b = s.domain
    lin = type(s).__new__(type(s))
    lin.__dict__.update(s.__dict__)
    lin.extrapolate = "linear"
    for end, x in ((b, b + np.array([0.1, 0.7, 2.0])), (a, a - np.array([0.3, 1.5]))):
        p_e, v_e = s.position(end), s.linear_velocity(end)
        w_e = s.angular_velocity(end, "body")
        assert np.allclose(lin.position(x), p_e + np.outer(x - end, v_e), atol=1e-12)
        assert np.allclose(lin.linear_velocity(x), np.tile(v_e, (len(x), 1)), atol=1e-12)
        assert np.allclose(lin.twist(x, "body")[:, :3], np.tile(w_e, (len(x), 1)), atol=1e-12)
        assert np.allclose(lin.linear_acceleration(x), 0, atol=1e-12)
        h = 1e-4
        for xi in x:
            num = fd(lambda y: lin.position(y), xi, h)
            assert np.allclose(num, lin.linear_velocity(xi), atol=1e-7)
    per = type(s).__new__(type(s))
    per.__dict__.update(s.__dict__)
    per.extrapolate = "periodic"
    t = np.linspace(a, b, 13)[1:-1]
    for k in (1, -2):
        assert np.allclose(per.position(t + k * (b - a)), s.position(t), atol=1e-10)
        assert np.allclose(per.twist(t + k * (b - a), order=2), s.twist(t, order=2), atol=1e-8)
    with pytest.raises(ValueError, match="extrapolate"):
        type(s)(*([Q, T, P] if "screw" in kind else [Q, P]), extrapolate="mirror")


def test_retiming_a_pose_spline_is_refused_not_silently_rotation_only():
    for f in (qs.arc_length, lambda s: qs.retime(s, max_angular_velocity=1.0)):
        with pytest.raises(TypeError, match="pose spline"):
            f(_make("screw"))
