"""Integrating angular velocity: exactness, convergence order by step halving, round trips."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation


def _err(a, b):
    """Largest rotation angle between corresponding orientations."""
    rel = qs.multiply(qs.conjugate(a), b)
    return float(np.max(np.linalg.norm(qs.as_rotvec(rel), axis=-1)))


@pytest.mark.parametrize("frame", ["body", "world"])
def test_zoh_is_exact_for_piecewise_constant_rates(frame):
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.05, 0.3, size=50))
    w = rng.normal(scale=3.0, size=(50, 3))
    q0 = qs.normalize(rng.normal(size=4))
    out = qs.integrate(t, w, q0, frame=frame, method="zoh")
    # independent composition with scipy: each interval is one rotation by h·ωₖ
    r = Rotation.from_quat(qs.as_xyzw(q0))
    ref = [r]
    for k in range(49):
        step = Rotation.from_rotvec((t[k + 1] - t[k]) * w[k])
        r = r * step if frame == "body" else step * r
        ref.append(r)
    ref = qs.from_xyzw(np.array([x.as_quat() for x in ref]))
    assert _err(out, ref) < 1e-13


def _reference(f, q0, t_end, frame):
    """Accurate solution of q' = ½ q ω(t) (body) or ½ ω(t) q (world) by DOP853."""

    def rhs(t, q):
        w = np.concatenate([[0.0], f(t)])
        return 0.5 * (qs.multiply(q, w) if frame == "body" else qs.multiply(w, q))

    sol = solve_ivp(rhs, (0.0, t_end), q0, method="DOP853", rtol=1e-13, atol=1e-14)
    return qs.normalize(sol.y[:, -1])


def _orders(errors):
    e = np.asarray(errors)
    return e[:-1] / e[1:]


@pytest.mark.parametrize("frame", ["body", "world"])
def test_linear_method_is_fourth_order_for_linear_rates(frame):
    a, b = np.array([1.0, -2.0, 0.5]), np.array([-3.0, 1.0, 4.0])  # ω(t) = a + b t, a × b ≠ 0
    q0 = qs.normalize([0.3, 0.1, -0.7, 0.2])
    ref = _reference(lambda t: a + b * t, q0, 1.0, frame)
    errors = []
    for n in (10, 20, 40, 80):
        t = np.linspace(0.0, 1.0, n + 1)
        out = qs.integrate(t, a + b * t[:, None], q0, frame=frame, method="linear")
        errors.append(_err(out[-1], ref))
    ratios = _orders(errors)
    assert np.all((ratios > 14) & (ratios < 18)), (errors, ratios)
    # without the commutator term (plain trapezoid) it would be second order: the cross
    # product's sign matters — the wrong frame's sign is only second order
    wrong = "world" if frame == "body" else "body"
    t = np.linspace(0.0, 1.0, 81)
    bad = qs.integrate(t, a + b * t[:, None], q0, frame=frame, method="zoh")
    assert _err(bad[-1], ref) > 100 * errors[-1]
    ref_wrong = _reference(lambda t: a + b * t, q0, 1.0, wrong)
    assert _err(qs.integrate(t, a + b * t[:, None], q0, frame=wrong)[-1], ref_wrong) < 1e-7


def _analytic(t, a, b):
    """q(t) = exp(a t / 2) exp(b t / 2) and its world and body rates (closed form)."""
    ea = qs.from_rotvec(np.outer(t, a))
    eb = qs.from_rotvec(np.outer(t, b))
    q = qs.multiply(ea, eb)
    world = a + qs.rotate(ea, np.broadcast_to(b, (len(t), 3)))
    body = qs.rotate(qs.conjugate(eb), np.broadcast_to(a, (len(t), 3))) + b
    return q, world, body


@pytest.mark.parametrize("frame", ["body", "world"])
def test_against_an_analytic_rotation(frame):
    a, b = np.array([0.0, 0.0, 2.0]), np.array([1.5, 0.0, 0.3])  # coning-like motion
    errors = {"linear": [], "cubic": [], "zoh": []}
    for n in (20, 40, 80, 160):
        t = np.linspace(0.0, 2.0, n + 1)
        q, world, body = _analytic(t, a, b)
        w = body if frame == "body" else world
        for m in errors:
            errors[m].append(_err(qs.integrate(t, w, q[0], frame=frame, method=m), q))
    assert np.all(np.abs(_orders(errors["cubic"]) - 16) < 2.5), errors["cubic"]
    assert np.all(np.abs(_orders(errors["linear"]) - 4) < 0.6), errors["linear"]
    assert np.all(np.abs(_orders(errors["zoh"]) - 2) < 0.3), errors["zoh"]
    assert errors["cubic"][-1] < 5e-8


def test_round_trip_spline_rates_integrate_back():
    keys = qs.from_rotvec(
        [[0, 0, 0], [0.5, 0.2, 0], [0.9, -0.4, 0.6], [1.2, 0.3, 1.5], [0.4, 1, 2]]
    )
    s = qs.C3Spline(keys, times=[0.0, 0.7, 1.5, 2.1, 3.0])
    errors = []
    for n in (30, 60, 120, 240):
        t = np.linspace(0.0, 3.0, n + 1)
        out = qs.integrate(t, s.angular_velocity(t, frame="body"), s(0.0), method="cubic")
        errors.append(_err(out, s(t)))
        world = qs.integrate(t, s.angular_velocity(t), s(0.0), frame="world", method="cubic")
        assert _err(world, s(t)) < 10 * errors[-1]
    ratios = _orders(errors)
    assert np.all(ratios > 12), (errors, ratios)  # fourth order: 2⁴ = 16 per halving
    assert errors[-1] < 1e-6


def test_single_sample_and_normalisation():
    out = qs.integrate([0.0], [[1.0, 2.0, 3.0]], [1.0 + 1e-9, 0, 0, 0])
    assert out.shape == (1, 4) and np.allclose(out, [[1, 0, 0, 0]], atol=0, rtol=0)
    assert abs(np.linalg.norm(out[0]) - 1.0) < 1e-15


@pytest.mark.parametrize(
    ("kwargs", "err", "msg"),
    [
        (dict(angular_velocity=np.zeros((3, 4))), ValueError, "angular_velocity: expected shape"),
        (dict(angular_velocity=np.zeros((2, 3))), ValueError, "angular_velocity: expected shape"),
        (dict(angular_velocity=np.zeros(3)), ValueError, "angular_velocity: expected shape"),
        (dict(angular_velocity=[[0, 0, np.nan]] * 3), ValueError, "angular_velocity: non-finite"),
        (dict(times=[0.0, 2.0, 1.0]), ValueError, "times: not strictly increasing at index 2"),
        (dict(times=[0.0, 1.0, 1.0]), ValueError, "times: not strictly increasing"),
        (dict(times=[0.0, np.inf, 3.0]), ValueError, "times: non-finite"),
        (dict(times=[[0.0, 1.0, 2.0]]), ValueError, "times: expected shape"),
        (dict(times=[]), ValueError, "angular_velocity: expected shape"),
        (dict(q0=[2.0, 0, 0, 0]), ValueError, "q0: not a rotation"),
        (dict(q0=[0.0, 0, 0, 0]), ValueError, "q0: not a rotation"),
        (dict(q0=[1.0, 0, 0]), ValueError, "q0: expected shape"),
        (dict(q0=[np.nan, 0, 0, 0]), ValueError, "q0: non-finite"),
        (dict(frame="inertial"), ValueError, "frame"),
        (dict(frame=None), TypeError, "frame"),
        (dict(method="rk4"), ValueError, "method"),
        (dict(method=1), TypeError, "method"),
    ],
)
def test_bad_input(kwargs, err, msg):
    args = dict(times=[0.0, 1.0, 2.0], angular_velocity=np.zeros((3, 3)), q0=[1.0, 0, 0, 0])
    args.update(kwargs)
    with pytest.raises(err, match=msg):
        qs.integrate(**args)
