"""MinimumEnergySpline(mode="exact"): the Riemannian cubic spline, the continuous minimiser of
∫|ω̇|² through the keys (MATH.md §13), checked against its Euler–Lagrange equation by finite
differences and by an independent scipy integration, and as the limit of the discrete form."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

EL_BOUND = 1e-8  # the stated bound on |ω⃛ + ω × ω̈| / (1 + |ω| |ω̈|) inside key intervals


def angle(a, b):
    r = qs.multiply(qs.conjugate(qs.normalize(a)), qs.normalize(b))
    return 2 * np.arctan2(np.linalg.norm(r[..., 1:], axis=-1), np.abs(r[..., 0]))


def keys(n=12, seed=0, spread=0.8):
    rng = np.random.default_rng(seed)
    t = np.cumsum(np.r_[0.0, rng.uniform(0.5, 1.5, n - 1)])
    return t, qs.from_rotvec(rng.normal(size=(n, 3)) * spread)


def energy(s, sub=8):
    """∫|ω̇|² by 10-point Gauss–Legendre on `sub` pieces of every key interval."""
    x, w = np.polynomial.legendre.leggauss(10)
    j = s.joints
    e = np.r_[
        np.concatenate([np.linspace(a, b, sub + 1)[:-1] for a, b in zip(j[:-1], j[1:])]), j[-1]
    ]
    lo, hi = e[:-1, None], e[1:, None]
    t = (0.5 * (hi - lo) * x + 0.5 * (lo + hi)).ravel()
    v = np.sum(s.angular_acceleration(t, "body") ** 2, axis=1).reshape(lo.shape[0], -1)
    return float(np.sum(0.5 * (hi - lo) * v * w))


def el_residual(s, t):
    """max |ω⃛ + ω × ω̈| / (1 + |ω| |ω̈|) inside every key interval, ω⃛ by the 7-point central
    difference of the spline's own jerk (truncation O(h⁶), h = 2e-3 of the interval)."""
    worst = 0.0
    for a, b in zip(t[:-1], t[1:]):
        tt = np.linspace(a, b, 9)[1:-1]
        h = 2e-3 * (b - a)
        j = [s.jerk(tt + k * h, "body") for k in (-3, -2, -1, 1, 2, 3)]
        w3 = (-j[0] + 9 * j[1] - 45 * j[2] + 45 * j[3] - 9 * j[4] + j[5]) / (60 * h)
        w, w2 = s.angular_velocity(tt, "body"), s.jerk(tt, "body")
        r = np.linalg.norm(w3 + np.cross(w, w2), axis=1)
        scale = 1 + np.linalg.norm(w, axis=1) * np.linalg.norm(w2, axis=1)
        worst = max(worst, float(np.max(r / scale)))
    return worst


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_satisfies_the_euler_lagrange_equation_between_keys(seed):
    t, q = keys(seed=seed)
    s = qs.MinimumEnergySpline(q, t, mode="exact")
    assert el_residual(s, t) <= EL_BOUND
    # the natural spline and the default discrete form do not satisfy it to this level
    assert el_residual(qs.NaturalSpline(q, t), t) > 1e-3
    assert el_residual(qs.MinimumEnergySpline(q, t), t) > 100 * EL_BOUND


def _ode(_, y):
    q, w, a, j = y[:4], y[4:7], y[7:10], y[10:13]
    qd = 0.5 * qs.multiply(q, np.r_[0.0, w])
    return np.r_[qd, a, j, -np.cross(w, j)]


@pytest.mark.parametrize("ends", ["natural", "rest"])
def test_an_independent_integration_from_each_key_reaches_the_next_key(ends):
    # scipy's DOP853 from the spline's own state (q, ω, ω̇, ω̈ at tᵢ⁺) integrates the
    # Euler–Lagrange system q̇ = ½ q ω, ω⃛ = −ω × ω̈: it must follow the spline and land on qᵢ₊₁.
    t, q = keys(8, seed=4)
    s = qs.MinimumEnergySpline(q, t, ends=ends, mode="exact")
    for i in range(len(t) - 1):
        y0 = np.r_[
            s(t[i]),
            s.angular_velocity(t[i], "body"),
            s.angular_acceleration(t[i], "body"),
            s.jerk(t[i], "body"),
        ]
        inside = np.linspace(t[i], t[i + 1], 7)[1:]
        sol = solve_ivp(_ode, (t[i], t[i + 1]), y0, "DOP853", inside, rtol=1e-13, atol=1e-13)
        assert sol.success
        assert np.max(angle(sol.y[:4].T, s(inside - 1e-12 * (inside == t[i + 1])))) < 1e-9
        assert angle(sol.y[:4, -1], q[i + 1]) < 1e-9
        w = s.angular_velocity(inside[:-1], "body")
        assert np.max(np.abs(sol.y[4:7, :-1].T - w)) < 1e-9 * (1 + np.max(np.abs(w)))


@pytest.mark.parametrize("ends", ["natural", "rest", "clamped", "closed"])
def test_interpolates_is_c2_at_the_keys_and_jerk_jumps(ends):
    t, q = keys(9, seed=5)
    kw = {}
    if ends == "closed":
        t = np.r_[t, t[-1] + 1.1]
    if ends == "clamped":
        kw = dict(start_rate=[0.3, -0.2, 0.5], end_rate=[0.0, 0.4, -0.1])
    s = qs.MinimumEnergySpline(q, t, ends=ends, mode="exact", **kw)
    assert np.max(angle(s(t[: len(q)]), q)) < 1e-12
    cert = qs.continuity(s, order=3)
    assert cert and all(j.order == 2 for j in cert)
    # the jump of ω̈ at a key is the Lagrange multiplier of its interpolation constraint
    assert all(j.jump_rel[3] > 1e-6 for j in cert)
    assert s.residual <= 1e-12
    assert el_residual(s, t) <= EL_BOUND
    d = qs.MinimumEnergySpline(q, t, ends=ends, resolution=4, **kw)
    assert energy(s) <= energy(d) * (1 + 1e-12)
    if ends == "natural":  # the optimum's natural boundary condition ω̇ = 0
        assert np.max(np.abs(s.angular_acceleration(t[[0, -1]], "body"))) < 1e-9
    if ends == "rest":
        assert np.max(np.abs(s.angular_velocity(t[[0, -1]], "body"))) < 1e-12
    if ends == "clamped":
        np.testing.assert_allclose(s.angular_velocity(t[0], "body"), kw["start_rate"], atol=1e-12)
        np.testing.assert_allclose(s.angular_velocity(t[-1], "body"), kw["end_rate"], atol=1e-12)


def test_one_axis_is_the_natural_cubic_spline_of_the_angle():
    t = np.array([0.0, 0.7, 2.0, 2.6, 4.0, 5.5, 6.0, 7.2])
    ang = np.array([0.0, 0.4, 1.1, 1.3, 0.9, 1.5, 2.4, 2.6])
    axis = [0.3, -0.4, 0.866]
    s = qs.MinimumEnergySpline(qs.from_axis_angle(axis, ang), t, mode="exact")
    cs = CubicSpline(t, ang, bc_type="natural")
    d = np.linspace(0, 7.2, 577)
    assert np.max(angle(s(d), qs.from_axis_angle(axis, cs(d)))) < 1e-12


def test_the_discrete_form_converges_to_it_as_its_resolution_grows():
    # Nested discrete spaces (resolution = bubble polynomials per key interval): the energy
    # gap to the exact optimum is positive, falls monotonically and faster than geometrically
    # (spectral convergence: observed gaps 1e-2, 8e-3, 1e-3, 2e-5, 3e-10 of the energy ~ 10²
    # for resolution 0, 1, 2, 4, 8), and the curves approach the exact one.
    t, q = keys(10, seed=6)
    s = qs.MinimumEnergySpline(q, t, mode="exact")
    e = energy(s)
    assert abs(e - s.energy) <= 1e-10 * e  # its exact energy integral agrees with quadrature
    grid = np.linspace(t[0], t[-1], 2001)
    gaps, dist = [], []
    for r in (0, 1, 2, 4, 8):
        d = qs.MinimumEnergySpline(q, t, resolution=r)
        gaps.append(energy(d) - e)
        dist.append(np.max(angle(d(grid), s(grid))))
    gaps, dist = np.array(gaps), np.array(dist)
    assert np.all(gaps > -1e-11 * e)
    assert np.all(np.diff(gaps) < 0) and np.all(np.diff(dist) < 0)
    assert gaps[-1] < 1e-6 * gaps[0] and dist[-1] < 1e-3 * dist[0]
    # faster than geometric: each doubling of the resolution cuts the gap by a growing factor
    assert gaps[3] / gaps[4] > gaps[2] / gaps[3] > 1


def test_energy_is_the_least_among_the_interpolants():
    t, q = keys(15, seed=7, spread=1.2)
    s = qs.MinimumEnergySpline(q, t, mode="exact")
    assert s.energy < s.natural_energy
    assert energy(s) < energy(qs.NaturalSpline(q, t))
    assert energy(s) <= energy(qs.MinimumEnergySpline(q, t, resolution=8)) * (1 + 1e-12)


def test_holds_still_between_equal_keys():
    rng = np.random.default_rng(11)
    q = qs.from_rotvec(rng.normal(size=(7, 3)) * 0.7)
    q[3] = q[2]
    t = np.cumsum(np.r_[0.0, rng.uniform(0.5, 1.5, 6)])
    s = qs.MinimumEnergySpline(q, t, mode="exact")
    tt = np.linspace(t[2], t[3], 33)
    np.testing.assert_array_less(np.abs(np.abs(s(tt) @ q[2]) - 1.0), 4e-16)
    assert np.all(s.angular_velocity(tt[1:-1]) == 0.0)
    assert s.continuity == 1
    np.testing.assert_array_less(angle(s(t), q), 1e-12)
    assert el_residual(s, t[:3]) <= EL_BOUND and el_residual(s, t[3:]) <= EL_BOUND


def test_registry_and_params():
    t, q = keys(6)
    s = qs.spline("min_energy", q, t, mode="exact")
    assert s.method == "min_energy" and s.mode == "exact" and s.params["mode"] == "exact"
    assert qs.MinimumEnergySpline(q, t).mode == "discrete"


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        (dict(mode="analytic"), ValueError, "mode: unknown"),
        (dict(mode=1), TypeError, "mode"),
        (dict(mode="exact", penalty="jerk"), ValueError, "mode: 'exact' is for penalty"),
        (dict(mode="exact", resolution=4), ValueError, "resolution: only with mode='discrete'"),
    ],
)
def test_bad_input(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        qs.MinimumEnergySpline(qs.from_rotvec(np.arange(12.0).reshape(4, 3) / 10), **kwargs)
