"""Keyframe control: Hermite keys, Kochanek–Bartels, Catmull–Rom α, with cross-checks."""

from __future__ import annotations

import doctest
import warnings

import numpy as np
import pytest
import quatspline as qs
import quatspline.splines.keys as kf
import splines.quaternion as sq

from ..splinekit import random_times, random_walk


def same_rotation(a, b):
    """Max component distance between a and ±b, per row."""
    return np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))


def one_sided(s, seg_left, t_left, seg_right, t_right):
    """|R_m − L_m| / max(1, |L_m|, |R_m|) for m = 0…3 (sign-aligned)."""
    left = s.segment_derivatives(seg_left, t_left)
    right = s.segment_derivatives(seg_right, t_right)
    if np.dot(left[0], right[0]) < 0:
        left = -left
    scale = np.maximum(1.0, np.maximum(np.linalg.norm(left, axis=1), np.linalg.norm(right, axis=1)))
    return np.linalg.norm(left - right, axis=1) / scale


def all_joint_jumps(s):
    """Jumps at every interior joint and (closed curves) the seam."""
    j = s.joints
    out = [one_sided(s, k - 1, j[k], k, j[k]) for k in range(1, len(j) - 1)]
    if s.closed:
        out.append(one_sided(s, len(j) - 2, j[-1], 0, j[0]))
    return np.array(out)


def body_rate(d):
    return 2 * qs.multiply(qs.conjugate(d[0]), d[1])[1:]


def great_circle(times, speed=0.9):
    axis = np.array([0.2, 0.9, -0.4])
    axis /= np.linalg.norm(axis)
    q0 = qs.normalize(np.array([0.3, -0.5, 0.6, 0.2]))
    return lambda t: qs.multiply(q0, qs.from_rotvec(speed * np.asarray(t)[..., None] * axis))


def test_module_doctests():
    assert doctest.testmod(kf).failed == 0


# ---- Hermite ------------------------------------------------------------------------------
@pytest.mark.parametrize("frame", ["world", "body"])
@pytest.mark.parametrize("quintic", [False, True])
def test_hermite_interpolates_keys_and_given_rates(frame, quintic):
    n = 7
    q = random_walk(n, 4)
    t = random_times(n, 4)
    rng = np.random.default_rng(4)
    w = rng.normal(size=(n, 3))
    a = rng.normal(size=(n, 3)) if quintic else None
    s = qs.Hermite(q, t, angular_velocity=w, angular_acceleration=a, frame=frame)
    assert np.all(same_rotation(s(t), q) < 1e-12)
    for k in range(n):
        for seg in {max(k - 1, 0), min(k, n - 2)}:
            d = s.segment_derivatives(seg, t[k])
            got = body_rate(d) if frame == "body" else qs.rotate(d[0], body_rate(d))
            assert np.allclose(got, w[k], atol=1e-12, rtol=0), (k, seg)
            if quintic:
                acc = 2 * qs.multiply(qs.conjugate(d[0]), d[2])[1:]
                if frame == "world":
                    acc = qs.rotate(d[0], acc)
                assert np.allclose(acc, a[k], atol=1e-11, rtol=0), (k, seg)
    order = 2 if quintic else 1
    assert s.continuity == order
    assert all(c.order >= order for c in qs.continuity(s))
    jumps = all_joint_jumps(s)
    assert np.all(jumps[:, : order + 1] < 1e-11)
    assert jumps[:, order + 1].max() > 1e-3  # the next order visibly jumps: the test can fail


def test_hermite_reproduces_a_great_circle_exactly():
    t = np.array([0.0, 0.3, 1.1, 1.5, 2.9])
    f = great_circle(t)
    q = f(t)
    w = np.tile(0.9 * np.array([0.2, 0.9, -0.4]) / np.linalg.norm([0.2, 0.9, -0.4]), (5, 1))
    x = np.linspace(0, 2.9, 301)
    for s in (
        qs.Hermite(q, t, angular_velocity=w, frame="body"),
        qs.Hermite(q, t, angular_velocity=w, angular_acceleration=np.zeros((5, 3)), frame="body"),
    ):
        assert same_rotation(s(x), f(x)).max() < 1e-14
        assert np.allclose(s.angular_acceleration(x), 0, atol=1e-12)


def test_hermite_closed_loop_is_smooth_across_the_seam():
    q = random_walk(5, 6)
    t = np.r_[random_times(5, 6), 0.0]
    t[-1] = t[-2] + 0.8
    w = np.random.default_rng(6).normal(size=(5, 3))
    a = np.random.default_rng(7).normal(size=(5, 3))
    s = qs.Hermite(q, t, angular_velocity=w, angular_acceleration=a, ends="closed")
    assert s.closed and len(s.joints) == 6
    cert = qs.continuity(s)
    assert cert[-1].index == 5 and cert[-1].time == t[-1]  # the seam is in the certificate
    assert all(c.order >= 2 for c in cert)
    assert np.all(all_joint_jumps(s)[:, :3] < 1e-11)
    # the closing key repeated at the end (with its rates) is the same loop
    s2 = qs.Hermite(
        np.vstack([q, -q[:1]]),
        t,
        angular_velocity=np.vstack([w, w[:1]]),
        angular_acceleration=np.vstack([a, a[:1]]),
        ends="closed",
    )
    x = np.linspace(t[0], t[-1], 200)
    assert same_rotation(s(x), s2(x)).max() < 1e-15
    s.extrapolate = "periodic"
    assert same_rotation(s(x + 3 * (t[-1] - t[0])), s(x)).max() < 1e-9


def test_hermite_hold_with_zero_rates_is_exactly_constant():
    q = random_walk(4, 2)
    q = np.vstack([q[:2], -q[1:2], q[2:]])  # keys 1 and 2 equal (as −q)
    t = np.array([0.0, 1.0, 2.5, 3.0, 4.0])
    w = np.random.default_rng(2).normal(size=(5, 3))
    w[1:3] = 0
    s = qs.Hermite(q, t, angular_velocity=w)
    x = np.linspace(1.0, 2.5, 101)
    d = same_rotation(s(x), np.broadcast_to(q[1], (101, 4)))
    assert d.max() == 0.0
    assert np.all(s.angular_velocity(x) == 0)


def test_hermite_bad_input():
    q = random_walk(4, 1)
    w = np.zeros((4, 3))
    with pytest.raises(ValueError, match=r"angular_velocity: expected shape \(4, 3\)"):
        qs.Hermite(q, angular_velocity=np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"angular_velocity: expected shape \(\.\.\., 3\)"):
        qs.Hermite(q, angular_velocity=np.zeros((4, 2)))
    bad = w.copy()
    bad[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"^angular_velocity: non-finite value .* 2$"):
        qs.Hermite(q, angular_velocity=bad)
    with pytest.raises(ValueError, match=r"^angular_acceleration: non-finite value .* 3$"):
        qs.Hermite(
            q, angular_velocity=w, angular_acceleration=np.r_[np.zeros((3, 3)), [[0, np.inf, 0]]]
        )
    with pytest.raises(ValueError, match=r"^angular_velocity: required"):
        qs.Hermite(q)
    with pytest.raises(TypeError, match=r"^angular_velocity: expected real numbers"):
        qs.Hermite(q, angular_velocity="fast")
    with pytest.raises(ValueError, match=r"^frame: expected"):
        qs.Hermite(q, angular_velocity=w, frame="inertial")
    with pytest.raises(
        ValueError, match=r"^ends: hermite does not support .*supported: open, rest, closed$"
    ):
        qs.Hermite(q, angular_velocity=w, ends="natural")
    with pytest.raises(ValueError, match=r"quats: a closed hermite needs at least 2 distinct keys"):
        qs.Hermite(np.vstack([q[:1], q[:1]]), angular_velocity=w[:2], ends="closed")
    w2 = np.vstack([w[:3], [[1.0, 0, 0]]])
    with pytest.raises(ValueError, match=r"angular_velocity: row 3 belongs to the closing key"):
        qs.Hermite(np.vstack([q[:3], q[:1]]), angular_velocity=w2, ends="closed")
    with pytest.raises(ValueError, match=r"times: a closed curve expects 5 times"):
        qs.Hermite(q, [0, 1, 2, 3], angular_velocity=w, ends="closed")


# ---- Kochanek–Bartels and Catmull–Rom --------------------------------------------------------
def _slerp_np(a, b, u):
    return qs.slerp(a, b, u)


def _gortler_uniform(q):
    """Independent Gortler Catmull–Rom (uniform keys, reflected ends) by de Casteljau."""
    q = qs.canonicalize(q)
    n = len(q)

    def tangent_half(i):  # log(c_{i+1} c_{i-1}^{-1})/2 per unit time
        if i == 0:
            return qs.log(qs.canonicalize(np.array([qs.multiply(q[1], qs.conjugate(q[0]))])))[0]
        if i == n - 1:
            return qs.log(qs.canonicalize(np.array([qs.multiply(q[-1], qs.conjugate(q[-2]))])))[0]
        r = qs.multiply(q[i + 1], qs.conjugate(q[i - 1]))
        return 0.5 * qs.log(qs.canonicalize(np.array([r])))[0]

    def curve(x):
        out = []
        for xi in x:
            i = min(int(np.floor(xi)), n - 2)
            u = xi - i
            d = qs.multiply(qs.exp(tangent_half(i) / 3), q[i])
            e = qs.multiply(qs.exp(-tangent_half(i + 1) / 3), q[i + 1])
            c = [q[i], d, e, q[i + 1]]
            while len(c) > 1:
                c = [_slerp_np(a, b, u) for a, b in zip(c[:-1], c[1:])]
            out.append(c[0])
        return np.array(out)

    return curve


def test_kb_at_zero_is_catmull_rom_and_gortler():
    q = random_walk(7, 12, step=0.5)
    x = np.linspace(0, 6, 241)
    kb = qs.KochanekBartels(q, tension=0, continuity=0, bias=0)
    assert same_rotation(kb(x), qs.CatmullRom(q)(x)).max() == 0.0
    assert same_rotation(kb(x), _gortler_uniform(q)(x)).max() < 1e-13
    t = random_times(7, 12)
    y = np.linspace(t[0], t[-1], 241)
    assert same_rotation(qs.KochanekBartels(q, t)(y), qs.CatmullRom(q, t)(y)).max() == 0.0


def _quiet(ctor, *args, **kw):
    """The splines package's closed curves use numpy's deprecated row_stack."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return ctor(*args, **kw)


def _sq(q):
    return [sq.UnitQuaternion.from_unit_xyzw(v) for v in qs.as_xyzw(q)]


def _sq_eval(curve, x):
    return np.array([qs.from_xyzw(curve.evaluate(u).xyzw) for u in x])


def _coaxial(n, seed):
    rng = np.random.default_rng(seed)
    axis = rng.normal(size=3)
    angles = np.cumsum(rng.uniform(-0.3, 0.9, n))
    return qs.from_axis_angle(axis, angles)


def test_kb_matches_the_splines_package_where_both_define_the_same_curve():
    """Coaxial keys (the two neighbouring logs of every key share an axis), non-uniform grid,
    per-key TCB: the closed loops are the same curve everywhere (the package's closed TCB
    applies at every key), to 1e-12; on general keys they differ at second order."""
    n = 6
    q = _coaxial(n, 21)
    rng = np.random.default_rng(21)
    tcb = rng.uniform(-0.6, 0.6, size=(n, 3))
    grid = np.r_[0.0, np.cumsum(rng.uniform(0.4, 1.6, n))]  # n + 1: the loop closes at the end
    ref = _quiet(
        sq.KochanekBartels, _sq(q), grid.tolist(), tcb=tcb.tolist(), endconditions="closed"
    )
    ours = qs.KochanekBartels(
        q, grid, tension=tcb[:, 0], continuity=tcb[:, 1], bias=tcb[:, 2], ends="closed"
    )
    x = np.linspace(grid[0], grid[-1], 301)[:-1]
    assert same_rotation(ours(x), _sq_eval(ref, x)).max() < 1e-12
    # open curves: interior segments (the package's "natural" ends differ from ours)
    ref_open = sq.KochanekBartels(_sq(q), grid[:-1].tolist(), tcb=tcb[1:-1].tolist())
    ours_open = qs.KochanekBartels(
        q, grid[:-1], tension=tcb[:, 0], continuity=tcb[:, 1], bias=tcb[:, 2]
    )
    y = np.linspace(grid[1], grid[n - 2], 201)
    assert same_rotation(ours_open(y), _sq_eval(ref_open, y)).max() < 1e-12
    general = random_walk(n, 22, step=0.4)
    ref_g = _quiet(
        sq.KochanekBartels, _sq(general), grid.tolist(), tcb=tcb.tolist(), endconditions="closed"
    )
    ours_g = qs.KochanekBartels(
        general, grid, tension=tcb[:, 0], continuity=tcb[:, 1], bias=tcb[:, 2], ends="closed"
    )
    d = same_rotation(ours_g(x), _sq_eval(ref_g, x))
    assert 1e-6 < d.max() < 2e-2


@pytest.mark.parametrize("alpha", [0.0, 0.5, 1.0])
def test_catmull_rom_alpha_matches_the_splines_package(alpha):
    q = _coaxial(7, 30 + int(10 * alpha))
    ref = sq.CatmullRom(_sq(q), alpha=alpha)
    ours = qs.CatmullRom(q, alpha=alpha)
    theta = 2 * np.arccos(np.clip(np.abs(np.sum(q[1:] * q[:-1], axis=1)), 0, 1))
    assert np.allclose(ours.joints, np.r_[0, np.cumsum(theta**alpha)], rtol=1e-9)
    assert np.allclose(ours.joints, ref.grid, rtol=1e-9)
    j = ours.joints
    y = np.linspace(j[1], j[-2], 201)  # interior segments: the end conditions differ
    assert same_rotation(ours(y), _sq_eval(ref, y)).max() < 1e-12
    closed_ref = _quiet(sq.CatmullRom, _sq(q), alpha=alpha, endconditions="closed")
    closed = qs.CatmullRom(q, alpha=alpha, ends="closed")
    assert np.allclose(closed.joints, closed_ref.grid, rtol=1e-9)
    x = np.linspace(closed.joints[0], closed.joints[-1], 301)[:-1]
    assert same_rotation(closed(x), _sq_eval(closed_ref, x)).max() < 1e-12


def test_times_take_precedence_over_alpha():
    q = random_walk(5, 3)
    t = random_times(5, 3)
    x = np.linspace(t[0], t[-1], 50)
    a = qs.CatmullRom(q, t, alpha=0.5)
    assert np.array_equal(a.joints, t)
    assert np.array_equal(a(x), qs.CatmullRom(q, t)(x))


@pytest.mark.parametrize("closed", [False, True])
def test_great_circle_reproduced_exactly_by_catmull_rom_and_kb(closed):
    if closed:
        # one full turn at constant speed, keys at non-uniform times, the loop closing at 2π/ω
        speed = 0.9
        period = 2 * np.pi / speed
        t = np.r_[0.0, 0.9, 2.0, 3.1, 4.5, 5.2, period]
        f = great_circle(t, speed)
        q = f(t[:-1])
    else:
        t = np.array([0.0, 0.3, 1.1, 1.5, 2.9, 3.0, 4.4])
        f = great_circle(t)
        q = f(t)
    x = np.linspace(t[0], t[-1], 401)
    ends = "closed" if closed else "reflect"
    for s in (
        qs.CatmullRom(q, t, ends=ends),
        qs.KochanekBartels(q, t, ends=ends),
        qs.KochanekBartels(q, t, tension=0.0, continuity=0.0, bias=0.0, ends=ends),
    ):
        assert same_rotation(s(x), f(x)).max() < 1e-14
        assert np.allclose(np.linalg.norm(s.angular_velocity(x), axis=1), 0.9, atol=1e-13)


def _kb_rate_numpy(q, t, k, tcb, incoming):
    """The documented KB key rate, from the formula in kochanek_bartels.rs."""
    T, C, B = tcb
    if incoming:
        wm, wp = (1 - T) * (1 - C) * (1 + B), (1 - T) * (1 + C) * (1 - B)
    else:
        wm, wp = (1 - T) * (1 + C) * (1 + B), (1 - T) * (1 - C) * (1 - B)
    hm, hp = t[k] - t[k - 1], t[k + 1] - t[k]

    def lg(a, b):
        return qs.log(qs.canonicalize(np.array([qs.multiply(a, qs.conjugate(b))])))[0, 1:]

    dm, dp, chord = lg(q[k], q[k - 1]), lg(q[k + 1], q[k]), lg(q[k + 1], q[k - 1])
    lam = wm * hp / (hm * (hm + hp))
    mu = wp * hm / (hp * (hm + hp))
    # logs are half rotation vectors: ω = 2 v
    return (lam + mu) * chord + (mu - lam) * (dp - dm)


def test_kb_continuity_parameter_gives_the_documented_corner():
    n = 6
    q = random_walk(n, 40)
    t = random_times(n, 40)
    tcb = np.zeros((n, 3))
    tcb[2] = [0.2, 0.5, -0.3]
    tcb[4] = [-0.1, 0.0, 0.4]  # tension and bias only: still C¹
    s = qs.KochanekBartels(q, t, tension=tcb[:, 0], continuity=tcb[:, 1], bias=tcb[:, 2])
    assert s.continuity == 0
    cert = {c.index: c.order for c in qs.continuity(s)}
    assert cert[2] == 0 and all(cert[k] >= 1 for k in (1, 3, 4))
    for k in (2, 4):
        left = s.segment_derivatives(k - 1, t[k])
        right = s.segment_derivatives(k, t[k])
        w_in = 2 * qs.multiply(left[1], qs.conjugate(left[0]))[1:]
        w_out = 2 * qs.multiply(right[1], qs.conjugate(right[0]))[1:]
        assert np.allclose(w_in, _kb_rate_numpy(q, t, k, tcb[k], True), atol=1e-12)
        assert np.allclose(w_out, _kb_rate_numpy(q, t, k, tcb[k], False), atol=1e-12)
    assert np.linalg.norm(all_joint_jumps(s)[1, 1]) > 1e-2  # the corner is real
    # tension 1 stops at the key
    stop = qs.KochanekBartels(q, t, tension=np.r_[0, 0, 1.0, 0, 0, 0])
    assert np.allclose(stop.angular_velocity(t[2]), 0, atol=1e-13)
    assert qs.KochanekBartels(q, t, tension=0.3, bias=-0.2).continuity == 1


@pytest.mark.parametrize("ends", ["reflect", "duplicate", "rest", "closed"])
def test_kb_continuity_at_every_joint_and_the_seam(ends):
    q = random_walk(6, 50)
    t = random_times(6, 50)
    if ends == "closed":
        t = np.r_[t, t[-1] + 0.7]
    s = qs.KochanekBartels(q, t, tension=0.2, bias=0.3, ends=ends)
    jumps = all_joint_jumps(s)
    assert np.all(jumps[:, :2] < 1e-12)
    assert jumps[:, 2].max() > 1e-4
    assert all(c.order >= 1 for c in qs.continuity(s))
    assert len(qs.continuity(s)) == len(s.joints) - (1 if ends == "closed" else 2)


def test_kb_and_cr_bad_input():
    q = random_walk(5, 1)
    with pytest.raises(ValueError, match=r"^tension: non-finite value \(NaN or inf\) at element 3"):
        qs.KochanekBartels(q, tension=[0, 0, 0, np.nan, 0])
    with pytest.raises(ValueError, match=r"^bias: expected 1 or 5 values \(one per key\), got 3"):
        qs.KochanekBartels(q, bias=[0, 0, 0])
    with pytest.raises(ValueError, match=r"^continuity: non-finite value .* element 0"):
        qs.KochanekBartels(q, continuity=np.inf)
    with pytest.raises(ValueError, match=r"^continuity: expected a scalar or a 1-D array"):
        qs.KochanekBartels(q, continuity=np.zeros((5, 1)))
    for a in (-0.1, 1.5, np.nan):
        with pytest.raises(ValueError, match=r"^alpha: expected a value in \[0, 1\]"):
            qs.CatmullRom(q, alpha=a)
        with pytest.raises(ValueError, match=r"^alpha: expected a value in \[0, 1\]"):
            qs.KochanekBartels(q, alpha=a)
    rep = np.vstack([q[:2], q[1:2], q[2:]])
    with pytest.raises(ValueError, match=r"quats: keys 1 and 2 are the same rotation: alpha"):
        qs.CatmullRom(rep, alpha=0.5)
    with pytest.raises(ValueError, match=r"closed kochanek_bartels needs at least 3 distinct keys"):
        qs.KochanekBartels(q[:2], ends="closed")
    with pytest.raises(ValueError, match=r"needs at least 3 distinct keys, got 2 \(the last key"):
        qs.CatmullRom(np.vstack([q[:2], -q[:1]]), ends="closed")
    with pytest.raises(ValueError, match=r"^ends: .*supported: reflect, duplicate, rest, closed"):
        qs.KochanekBartels(q, ends="natural")
    with pytest.raises(ValueError, match=r"tension\[4\] belongs to the closing key"):
        qs.KochanekBartels(np.vstack([q[:4], q[:1]]), tension=[0, 0, 0, 0, 0.5], ends="closed")


def test_closed_loop_first_key_repeated_is_dropped_and_its_time_closes_the_loop():
    q = random_walk(5, 60)
    t = random_times(6, 60)
    loop = qs.CatmullRom(q, t, ends="closed")
    repeated = qs.CatmullRom(np.vstack([q, -q[:1]]), t, ends="closed")
    x = np.linspace(t[0], t[-1], 120)
    assert np.array_equal(loop.joints, repeated.joints)
    assert same_rotation(loop(x), repeated(x)).max() == 0.0
    assert same_rotation(loop(t[-1])[None], q[:1]).max() < 1e-15


def test_registry_and_cli_reach_the_new_methods(tmp_path):
    from quatspline.cli import main

    q = random_walk(6, 70)
    t = random_times(6, 70)
    s = qs.spline("kochanek_bartels", q, t, tension="0.3", ends="closed", holds="false")
    assert s.closed and s.method == "kochanek_bartels"
    # the registry closes a loop of N keys at N times after the mean key spacing
    assert np.allclose(s.joints, np.r_[t, t[-1] + (t[-1] - t[0]) / 5])
    h = qs.spline("hermite", q, t)
    assert np.allclose(h.angular_velocity(t, "body"), kf.bessel_rates(q, t), atol=1e-12)
    rates = tmp_path / "w.txt"
    np.savetxt(rates, np.ones((6, 3)))
    h2 = qs.spline("hermite", q, t, rates=str(rates), frame="world")
    assert np.allclose(h2.angular_velocity(t), 1.0, atol=1e-12)
    c = qs.spline("catmull_rom", q, None, alpha="0.5")
    assert not np.allclose(np.diff(c.joints), 1.0)
    src = tmp_path / "keys.npz"
    np.savez(src, times=t, quats=q)
    out = tmp_path / "out.csv"
    at = tmp_path / "at.txt"
    np.savetxt(at, np.r_[t[0] - 0.5, t, t[-1] + 1.0])
    for method, params in (
        ("kochanek_bartels", ["--param", "tension=0.2", "--param", "continuity=0.1"]),
        ("hermite", ["--param", f"rates={rates}", "--param", "frame=world"]),
        ("catmull_rom", ["--param", "ends=rest"]),
    ):
        argv = ["sample", str(src), "-o", str(out), "--method", method, "--at", str(at)]
        assert main([*argv, *params, "--extrapolate", "linear"]) == 0
        assert main([*argv, *params]) == 1  # raise: outside the keys
    with pytest.raises(SystemExit) as e:
        main(["sample", str(src), "-o", str(out), "--count", "5", "--extrapolate", "x"])
    assert e.value.code == 2


# ---- the C³ spline's alpha="auto" ---------------------------------------------------------
@pytest.mark.parametrize("uniform", [True, False])
def test_c3_auto_removes_the_ripple_on_a_constant_speed_great_circle(uniform):
    t = np.arange(10.0) if uniform else np.r_[0.0, np.cumsum(np.linspace(0.5, 1.6, 9))]
    f = great_circle(t)
    q = f(t)
    x = np.linspace(t[2], t[-3], 1501)  # interior segments (the padded ends differ)
    auto = qs.C3Spline(q, t, alpha="auto")
    speed = np.linalg.norm(auto.angular_velocity(x), axis=1)
    assert np.allclose(speed, 0.9, rtol=0, atol=1e-12)
    assert same_rotation(auto(x), f(x)).max() < 1e-14
    default = qs.C3Spline(q, t)
    w = np.linalg.norm(default.angular_velocity(x), axis=1)
    # the default dips to 5/8 of the chord speed at every key
    assert np.allclose(np.linalg.norm(default.angular_velocity(t[2:-2]), axis=1), 0.9 * 5 / 8)
    assert w.max() / w.min() > 2.1
    assert qs.spline("c3", q, t, alpha="auto").params["alpha"] == "auto"
    explicit = qs.C3Spline(q, t, alpha=0.5, beta=-3.0)
    assert np.array_equal(explicit(x), auto(x))


def test_c3_alpha_bad_values():
    q = random_walk(4, 1)
    with pytest.raises(ValueError, match=r"^alpha: expected a number, numbers or 'auto'"):
        qs.C3Spline(q, alpha="fast")
    with pytest.raises(ValueError, match=r"^alpha: expected a number or 'auto', got 'fast'"):
        qs.spline("c3", q, alpha="fast")
    with pytest.raises(ValueError, match=r"^alpha: non-finite value .* element 2"):
        qs.C3Spline(q, alpha=[0.3, 0.3, np.nan, 0.3])


def test_registry_closed_hermite_takes_loop_bessel_rates():
    """``ends="closed"`` with the default rates: Bessel's rule around the loop (the closing
    chord runs from the last key back to the first). A constant-speed great circle is exact:
    keys at angles 0 … 5 about z, the closing chord 2π − 5, times equal to the angles."""
    ang = np.arange(6.0)
    q = qs.from_rotvec(np.c_[0 * ang, 0 * ang, ang])
    t = np.r_[ang, 2 * np.pi]
    tt = np.linspace(0, 2 * np.pi, 97)
    for keys, times in ((q, t), (np.vstack([q, q[:1]]), t)):  # closing time, closing key
        s = qs.spline("hermite", keys, times, ends="closed")
        assert s.closed and s.domain == (0.0, 2 * np.pi)
        assert np.abs(s.angular_velocity(tt) - [0, 0, 1]).max() < 1e-13
    # N keys at N times: the registry closes the loop after the mean spacing
    s = qs.spline("hermite", q, ang, ends="closed")
    loop = np.r_[ang, 6.0]
    w = kf.bessel_rates(q, loop, closed=True)
    assert np.allclose(s.angular_velocity(loop[:-1], "body"), w, atol=1e-12)
    # every key is interior: the first key's rate averages the closing chord and the first
    closing = 2 * np.pi - 5.0  # the rotation from key 5 on to key 0, in one time unit
    assert np.allclose(w[0], [0, 0, (1.0 + closing) / 2], atol=1e-12)
    assert np.allclose(w[-1], [0, 0, (1.0 + closing) / 2], atol=1e-12)


def test_closed_bessel_rates_check_the_loop_times():
    q = random_walk(5, 3)
    with pytest.raises(ValueError, match=r"times: expected shape \(6,\)"):
        kf.bessel_rates(q, np.arange(5.0), closed=True)
    with pytest.raises(ValueError, match=r"times: expected shape \(5,\)"):
        kf.bessel_rates(q, np.arange(6.0))
