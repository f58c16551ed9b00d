"""Splines cross-checked against independent code: scipy, numpy-quaternion, splines."""

from __future__ import annotations

import numpy as np
import quaternion
import quatspline as qs
import splines.quaternion as sq
from scipy.spatial.transform import Rotation, RotationSpline, Slerp

from ..splinekit import random_times, random_walk


def same_rotation(a, b, tol):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    assert np.max(d) <= tol, np.max(d)


def to_scipy(q):
    return Rotation.from_quat(qs.as_xyzw(q))


def test_piecewise_slerp_matches_scipy_slerp():
    q, t = random_walk(10, 1), random_times(10, 1)
    x = np.random.default_rng(0).uniform(t[0], t[-1], 3000)
    ref = qs.from_xyzw(Slerp(t, to_scipy(q))(x).as_quat())
    same_rotation(qs.PiecewiseSlerp(q, t)(x), ref, 1e-14)


def test_natural_clamped_matches_scipy_rotation_spline():
    """scipy's RotationSpline = our NaturalSpline(ends="clamped") with the default end rates
    (the end segments' chord rates). scipy stops its fixed-point iteration at 1e-9 relative
    (and uses 1/12604 for a 1/1260 series coefficient), so agreement is to ~1e-8."""
    for seed, times in ((2, None), (3, "nonuniform")):
        q = random_walk(12, seed)
        t = np.arange(12.0) if times is None else random_times(12, seed)
        ref = RotationSpline(t, to_scipy(q))
        ours = qs.NaturalSpline(q, t, ends="clamped")
        x = np.linspace(t[0], t[-1], 2001)
        same_rotation(ours(x), qs.from_xyzw(ref(x).as_quat()), 1e-8)
        # scipy's order-1/2 outputs are body-frame angular velocity and acceleration
        np.testing.assert_allclose(ours.angular_velocity(x, frame="body"), ref(x, 1), atol=1e-7)
        np.testing.assert_allclose(ours.angular_acceleration(x, frame="body"), ref(x, 2), atol=1e-6)


def test_natural_ends_differ_from_scipy_only_near_the_ends():
    q = random_walk(12, 4)
    t = np.arange(12.0)
    ref = RotationSpline(t, to_scipy(q))
    nat = qs.NaturalSpline(q, t)  # zero angular acceleration at the ends
    np.testing.assert_allclose(nat.angular_acceleration([0.0, 11.0]), 0, atol=1e-10)
    assert np.linalg.norm(ref([0.0], 2)) > 1e-3  # scipy's ends are clamped, not natural


def test_squad_matches_numpy_quaternion_on_uniform_keys():
    q = random_walk(10, 5, step=0.3)
    t = np.arange(10.0)
    x = np.linspace(
        1.0, 8.0, 701
    )  # interior segments: numpy-quaternion treats the ends its own way
    ref = quaternion.as_float_array(quaternion.squad(quaternion.as_quat_array(q), t, x))
    same_rotation(qs.Squad(q, t)(x), ref, 1e-13)


def test_squad_is_c1_in_time_for_nonuniform_times():
    from ..splinekit import joint_jumps

    q = random_walk(8, 6, step=0.3)
    t = random_times(8, 6)
    ours = qs.Squad(q, t)
    assert np.max(joint_jumps(ours, 1)[:, 1]) < 1e-12


def test_de_casteljau_matches_splines_package():
    c = random_walk(5, 7)
    curve = sq.DeCasteljau([[sq.UnitQuaternion.from_unit_xyzw(v) for v in qs.as_xyzw(c)]])
    x = np.linspace(0, 1, 51)
    ref = np.array([qs.from_xyzw(curve.evaluate(u).xyzw) for u in x])
    same_rotation(qs.SphericalBezier(c)(x), ref, 1e-14)


def _splines_cr(q):
    curve = sq.CatmullRom([sq.UnitQuaternion.from_unit_xyzw(v) for v in qs.as_xyzw(q)])
    return lambda x: np.array([qs.from_xyzw(curve.evaluate(u).xyzw) for u in x])


def test_catmull_rom_matches_splines_package_where_definitions_coincide():
    """Definitional difference: our key tangent is Gortler's log(c_{i+1} c_{i-1}^-1)/2 (uniform
    times); the splines package averages the two logs, (log(c_i c_{i-1}^-1) +
    log(c_{i+1} c_i^-1))/2. They coincide when consecutive rotations share one axis (then the
    logs add exactly), and their end conditions differ, so interior segments of uniform keys
    about one axis must agree to rounding; on general keys they differ at second order."""
    rng = np.random.default_rng(8)
    axis = rng.normal(size=3)
    angles = np.cumsum(rng.uniform(0.1, 0.8, 8))
    q = qs.from_axis_angle(axis, angles)
    x = np.linspace(1.0, 6.0, 251)
    same_rotation(qs.CatmullRom(q)(x), _splines_cr(q)(x), 1e-13)
    general = random_walk(8, 8, step=0.4)
    a, b = qs.CatmullRom(general)(x), _splines_cr(general)(x)
    d = np.minimum(np.abs(a - b).max(axis=1), np.abs(a + b).max(axis=1))
    assert 1e-6 < d.max() < 1e-2
