"""Dual quaternions: poses, screw form, ScLerp (against pytransform3d) and DLB."""

from __future__ import annotations

import numpy as np
import pytransform3d.transformations as pt
import quatspline as qs
from hypothesis import given, settings
from hypothesis import strategies as st

from ..conftest import random_quats


def random_poses(n, seed):
    q = random_quats(n, seed)
    t = np.random.default_rng(seed + 100).uniform(-3, 3, size=(n, 3))
    return q, t


def test_pose_round_trip_and_pytransform3d_layout():
    q, t = random_poses(50, 1)
    dq = qs.dq_from_pose(q, t)
    for i in range(5):
        ref = pt.dual_quaternion_from_pq(np.r_[t[i], q[i]])
        np.testing.assert_allclose(dq[i], ref, atol=1e-15)
    q2, t2 = qs.dq_to_pose(dq)
    np.testing.assert_allclose(q2, q, atol=1e-15)
    np.testing.assert_allclose(t2, t, atol=1e-14)


def test_transform_point_and_product():
    q, t = random_poses(20, 2)
    a, b = qs.dq_from_pose(q[:10], t[:10]), qs.dq_from_pose(q[10:], t[10:])
    p = np.array([0.3, -1.2, 2.0])
    ab = qs.dq_multiply(a, b)
    np.testing.assert_allclose(
        qs.dq_transform_point(ab, p),
        qs.dq_transform_point(a, qs.dq_transform_point(b, p)),
        atol=1e-13,
    )
    np.testing.assert_allclose(
        qs.dq_transform_point(a, p), qs.rotate(q[:10], p) + t[:10], atol=1e-14
    )
    inv = qs.dq_conjugate(a)
    np.testing.assert_allclose(
        qs.dq_multiply(a, inv), np.tile([1, 0, 0, 0, 0, 0, 0, 0.0], (10, 1)), atol=1e-14
    )


def test_sclerp_matches_pytransform3d():
    q, t = random_poses(40, 3)
    a, b = qs.dq_from_pose(q[:20], t[:20]), qs.dq_from_pose(q[20:], t[20:])
    for i in range(20):
        if np.dot(a[i, :4], b[i, :4]) < 0:  # pytransform3d takes the path as given
            b[i] = -b[i]
        for s in (0.0, 0.3, 0.77, 1.0):
            ref = pt.dual_quaternion_sclerp(a[i], b[i], s)
            got = qs.sclerp(a[i], b[i], s)
            assert min(np.abs(got - ref).max(), np.abs(got + ref).max()) < 1e-12


def test_sclerp_equal_rotations_and_pure_translation():
    q = qs.from_axis_angle([1.0, 2.0, 0.5], 0.9)
    a = qs.dq_from_pose(q, [0.0, 0.0, 0.0])
    b = qs.dq_from_pose(q, [2.0, -4.0, 6.0])
    for s in (0.25, 0.5):
        r, tr = qs.dq_to_pose(qs.sclerp(a, b, s))
        np.testing.assert_allclose(r, q, atol=1e-15)
        np.testing.assert_allclose(tr, s * np.array([2.0, -4.0, 6.0]), atol=1e-14)
    same = qs.sclerp(b, b, 0.4)
    np.testing.assert_allclose(same, b, atol=1e-15)


def test_screw_parameters():
    # 90° about z through the point (1, 0, 0), advancing 0.5 along z
    r = qs.from_axis_angle([0, 0, 1.0], np.pi / 2)
    c = np.array([1.0, 0.0, 0.0])
    t = c - qs.rotate(r, c) + [0, 0, 0.5]
    s = qs.dq_screw(qs.dq_from_pose(r, t))
    np.testing.assert_allclose(s["axis"], [0, 0, 1], atol=1e-15)
    assert abs(s["angle"] - np.pi / 2) < 1e-15
    assert abs(s["displacement"] - 0.5) < 1e-15
    # a point on the screw axis is axis × moment
    np.testing.assert_allclose(np.cross(s["axis"], s["moment"]), c, atol=1e-15)


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 10_000), st.floats(0.0, 1.0))
def test_sclerp_constant_screw_and_dlb_axis(seed, s):
    q, t = random_poses(2, seed)
    a, b = qs.dq_from_pose(q[0], t[0]), qs.dq_from_pose(q[1], t[1])
    x = qs.sclerp(a, b, s)
    assert abs(np.linalg.norm(x[:4]) - 1) < 1e-14 and abs(np.dot(x[:4], x[4:])) < 1e-13
    # two-key DLB is NLerp of dual quaternions: unit, same endpoints
    d0 = qs.dlb(np.stack([a, b]), [1.0, 0.0])
    assert min(np.abs(d0 - a).max(), np.abs(d0 + a).max()) < 1e-14


def test_dlb_keeps_axis_but_not_angle():
    a = qs.dq_from_pose([1.0, 0, 0, 0], [0, 0, 0.0])
    b = qs.dq_from_pose(qs.from_axis_angle([0, 0, 1.0], np.deg2rad(162)), [1.0, 2.0, 0])
    ts = np.linspace(0, 1, 401)
    sc = qs.sclerp(a, b, ts)
    bl = np.stack([qs.dlb(np.stack([a, b]), [1 - s, s]) for s in ts])
    err = np.rad2deg(np.abs(2 * np.arccos(np.clip(sc[:, 0], -1, 1)) - 2 * np.arccos(bl[:, 0])))
    # MATH.md §3: max angle error ≈ 5.8° at 162°, none at the ends or the middle; axis kept
    assert 5.6 < err.max() < 6.0
    assert err[0] < 1e-6 and err[200] < 1e-6 and err[-1] < 1e-6
    np.testing.assert_allclose(bl[1:, 1:3], 0, atol=1e-15)
    np.testing.assert_allclose(sc[1:, 1:3], 0, atol=1e-15)


def test_dlb_sign_alignment():
    q, t = random_poses(3, 9)
    dq = qs.dq_from_pose(q, t)
    flipped = dq.copy()
    flipped[1] *= -1
    w = [0.2, 0.5, 0.3]
    np.testing.assert_allclose(qs.dlb(dq, w), qs.dlb(flipped, w), atol=1e-15)


def test_dq_power_halves_compose():
    q, t = random_poses(10, 11)
    dq = qs.dq_from_pose(q, t)
    h = qs.dq_power(dq, 0.5)
    two = qs.dq_multiply(h, h)
    ok = np.minimum(np.abs(two - dq).max(axis=1), np.abs(two + dq).max(axis=1))
    assert np.all(ok < 1e-13)
