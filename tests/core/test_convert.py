"""Conversions against scipy (all 24 Euler sequences, matrices, rotation vectors)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline._core import __version__  # noqa: F401  (the extension imports)
from scipy.spatial.transform import Rotation

from ..conftest import HARD_CASES, random_quats

SEQS = [a + b + c for a in "xyz" for b in "xyz" for c in "xyz" if a != b and b != c]
ALL_SEQS = SEQS + [s.upper() for s in SEQS]


def same_rotation(a, b, tol):
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    return np.all(d <= tol)


def test_twelve_sequences_of_each_kind():
    assert len(SEQS) == 12 and len(ALL_SEQS) == 24


@pytest.mark.parametrize("seq", ALL_SEQS)
def test_euler_matches_scipy(seq):
    rng = np.random.default_rng(7)
    angles = rng.uniform(-np.pi, np.pi, size=(500, 3))
    angles[:, 1] = (
        rng.uniform(0.05, np.pi - 0.05, 500)
        if seq[0] == seq[2].lower() or seq[0] == seq[2]
        else rng.uniform(-1.5, 1.5, 500)
    )
    ours = qs.from_euler(seq, angles)
    ref = qs.from_scipy(Rotation.from_euler(seq, angles))
    np.testing.assert_allclose(ours, ref, atol=2e-15)
    q = random_quats(500, seed=3)
    np.testing.assert_allclose(
        qs.as_euler(q, seq), Rotation.from_quat(qs.as_xyzw(q)).as_euler(seq), atol=1e-12
    )


@pytest.mark.parametrize("seq", ["xyz", "ZYX", "zxz", "YXY"])
def test_euler_degrees_and_gimbal_lock(seq):
    a = (
        np.array([30.0, 0.0, 45.0])
        if seq[0].lower() == seq[2].lower()
        else np.array([30.0, 90.0, 45.0])
    )
    q = qs.from_euler(seq, a, degrees=True)
    np.testing.assert_allclose(q, qs.from_euler(seq, np.deg2rad(a)), atol=1e-16)
    back = qs.as_euler(q, seq, degrees=True)
    with pytest.warns(UserWarning, match="Gimbal"):
        ref = Rotation.from_euler(seq, a, degrees=True).as_euler(seq, degrees=True)
    np.testing.assert_allclose(back, ref, atol=1e-9)
    assert same_rotation(qs.from_euler(seq, back, degrees=True), q, 1e-12)


def test_matrix_matches_scipy_and_round_trips():
    q = random_quats(1000, seed=1)
    m = qs.as_matrix(q)
    np.testing.assert_allclose(m, Rotation.from_quat(qs.as_xyzw(q)).as_matrix(), atol=1e-15)
    assert same_rotation(qs.from_matrix(m), q, 1e-15)


def test_matrix_hard_cases(hard_quat):
    q = qs.normalize(hard_quat)
    assert same_rotation(qs.from_matrix(qs.as_matrix(q)), q, 1e-15)


def test_from_matrix_projects_non_orthogonal_like_scipy():
    rng = np.random.default_rng(2)
    m = qs.as_matrix(random_quats(50, seed=4)) + 1e-3 * rng.normal(size=(50, 3, 3))
    ref = Rotation.from_matrix(m).as_quat()
    assert same_rotation(qs.from_matrix(m), qs.from_xyzw(ref), 1e-12)


def test_rotvec_matches_scipy():
    q = random_quats(1000, seed=5)
    r = qs.as_rotvec(q)
    np.testing.assert_allclose(r, Rotation.from_quat(qs.as_xyzw(q)).as_rotvec(), atol=2e-15)
    assert same_rotation(qs.from_rotvec(r), q, 1e-15)


def test_rotvec_hard_cases(hard_quat):
    q = qs.normalize(hard_quat)
    assert same_rotation(qs.from_rotvec(qs.as_rotvec(q)), q, 1e-15)
    tiny = qs.as_rotvec(HARD_CASES["1e-12 rad"])
    assert abs(np.linalg.norm(tiny) - 1e-12) < 1e-27


def test_axis_angle():
    q = qs.from_axis_angle([[0, 0, 2.0]], [np.pi / 2])
    np.testing.assert_allclose(q, [[np.sqrt(0.5), 0, 0, np.sqrt(0.5)]], atol=1e-16)
    np.testing.assert_allclose(qs.rotate(q[0], [1.0, 0, 0]), [0, 1, 0], atol=1e-15)


def test_layouts_and_scipy_interop():
    q = random_quats(10, seed=6)
    np.testing.assert_array_equal(qs.from_xyzw(qs.as_xyzw(q)), q)
    r = qs.to_scipy(q)
    np.testing.assert_allclose(qs.from_scipy(r), q, atol=0)
