"""Regression tests for issue 2.1's numerics and API items (each failed on main before its fix).

Item numbers refer to issue 2.1 (docs/robustness.md has one row per input).
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest
import quatspline as qs
from scipy.spatial.transform import Rotation

SEQS = [
    "".join(p)
    for axes in ("xyz", "XYZ")
    for p in itertools.product(axes, repeat=3)
    if p[0] != p[1] and p[1] != p[2]
]


def test_all_24_sequences_listed():
    assert len(SEQS) == 24


# ---- item 2: slerp(q, -q, t, long_path=True) -------------------------------------------------
@pytest.mark.parametrize(
    "q",
    [
        np.array([0, 0, 1, 1]) / np.sqrt(2),  # the example: norm 0 at t = 0.75 on main
        np.array([1.0, 0, 0, 0]),
        np.array([0.5, 0.5, 0.5, 0.5]),
        np.array([0.1, -0.7, 0.3, 0.2]) / np.linalg.norm([0.1, -0.7, 0.3, 0.2]),
    ],
)
def test_slerp_long_path_to_minus_q_is_a_unit_full_turn_about_body_x(q):
    t = np.linspace(-0.5, 1.5, 81)
    m = qs.slerp(q, -q, t, long_path=True)
    np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1.0, atol=1e-15)
    # The documented axis: q ⊗ (cos πt, sin πt, 0, 0), a 2πt turn about the body x axis.
    want = qs.multiply(q, np.stack([np.cos(np.pi * t), np.sin(np.pi * t), 0 * t, 0 * t], -1))
    np.testing.assert_allclose(m, want, atol=1e-15)
    # The rotation angle is 2πt (mod 2π) — a full turn over [0, 1].
    ang = Rotation.from_quat(qs.as_xyzw(m)).inv() * Rotation.from_quat(qs.as_xyzw(q))
    wrapped = np.abs((2 * np.pi * t + np.pi) % (2 * np.pi) - np.pi)
    np.testing.assert_allclose(ang.magnitude(), wrapped, atol=1e-7)


def test_slerp_long_path_nearly_opposite_keys_stay_unit():
    rng = np.random.default_rng(2)
    q = rng.normal(size=(500, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    for eps in (1e-15, 1e-12, 1e-9, 1e-6):
        q1 = -q + eps * rng.normal(size=q.shape)
        m = qs.slerp(q, q1, rng.uniform(0, 1, 500), long_path=True)
        np.testing.assert_allclose(np.linalg.norm(m, axis=-1), 1.0, atol=1e-14)


# ---- item 3: as_euler ranges exactly scipy's -------------------------------------------------
def _hard_rotations():
    rng = np.random.default_rng(3)
    out = [rng.normal(size=(300, 4))]
    grid = np.deg2rad(np.arange(-180, 181, 45.0))
    angles = np.array(list(itertools.product(grid, grid, grid)))
    for seq in SEQS:  # gimbal lock (middle 0 / ±90 / 180) and exactly 180° for every sequence
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out.append(Rotation.from_euler(seq, angles).as_quat(scalar_first=True))
    half_turns = np.array(
        [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 1, 1, 0], [0, 1, 0, 1], [0, 0, 1, 1]],
        dtype=float,
    )
    out.append(half_turns)
    out.append(-half_turns)
    q = np.concatenate(out)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


@pytest.mark.parametrize("seq", SEQS)
def test_as_euler_matches_scipy_ranges_exactly_incl_gimbal_lock_and_180(seq):
    q = _hard_rotations()
    ours = qs.as_euler(q, seq)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = Rotation.from_quat(qs.as_xyzw(q)).as_euler(seq)
    # Same ranges: no 2π jumps allowed (on main a middle angle of π came out as −π).
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-9)
    assert np.all(np.abs(ours) <= np.pi)
    mid = ours[:, 1]
    if seq[0].lower() == seq[2].lower():
        assert np.all((mid >= 0) & (mid <= np.pi))
    else:
        assert np.all(np.abs(mid) <= np.pi / 2 + 1e-15)


# ---- item 7: from_euler 1- and 2-axis sequences; dq_power sign invariance ---------------------
@pytest.mark.parametrize("seq", ["x", "Y", "z", "zx", "XY", "yz", "ZX", "xyz", "ZYZ"])
def test_from_euler_accepts_one_and_two_axis_sequences_like_scipy(seq):
    rng = np.random.default_rng(7)
    a = rng.uniform(-4, 4, size=(20, len(seq)))
    ref = Rotation.from_euler(seq, a).as_quat(scalar_first=True)
    ours = qs.from_euler(seq, a)
    np.testing.assert_allclose(np.abs(np.sum(ours * ref, axis=-1)), 1.0, atol=1e-14)
    if len(seq) == 1:  # a scalar or a flat array of angles, like scipy
        np.testing.assert_allclose(np.abs(qs.from_euler(seq, a[:, 0]) @ ref.T).diagonal(), 1.0)
        assert qs.from_euler(seq, 0.3).shape == (4,)


@pytest.mark.parametrize("seq", ["", "xx", "xY", "xyzx", "w", "XYY"])
def test_from_euler_bad_sequences_name_seq(seq):
    with pytest.raises(ValueError, match="seq: unknown rotation sequence"):
        qs.from_euler(seq, np.zeros(max(len(seq), 1)))


def test_from_euler_wrong_width_names_angles():
    with pytest.raises(ValueError, match=r"angles: expected shape \(\.\.\., 2\)"):
        qs.from_euler("zx", [1.0, 2.0, 3.0])


def test_dq_power_is_sign_invariant_with_long_path_opt_out():
    rng = np.random.default_rng(8)
    q = rng.normal(size=(200, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    d = qs.dq_from_pose(q, rng.normal(size=(200, 3)))
    t = rng.uniform(-2, 2, size=200)
    a, b = qs.dq_power(d, t), qs.dq_power(-d, t)
    same = np.minimum(np.abs(a - b).max(-1), np.abs(a + b).max(-1))
    assert same.max() < 1e-12
    # The shortest screw: the rotation part of q̂^½ turns by half the (≤ π) angle.
    ra = qs.dq_to_pose(qs.dq_power(d, 0.5))[0]
    full = Rotation.from_quat(qs.as_xyzw(q)).magnitude()
    half = Rotation.from_quat(qs.as_xyzw(ra)).magnitude()
    np.testing.assert_allclose(half, full / 2, atol=1e-12)
    # Opt-out: the sign as given; −q̂ then goes the long way round.
    la, lb = qs.dq_power(d, t, long_path=True), qs.dq_power(-d, t, long_path=True)
    flipped = q[:, 0] < 0
    np.testing.assert_allclose(la[~flipped], a[~flipped], atol=1e-12)
    diff = np.minimum(np.abs(la - lb).max(-1), np.abs(la + lb).max(-1))
    assert np.all(diff[np.abs(t - np.round(t)) > 0.05] > 1e-6)


# ---- item 15: from_rotvec above |v| ≈ 1.3e154 -------------------------------------------------
def test_from_rotvec_huge_vectors_are_finite_unit_rotations():
    v = np.array([[1e154, 0, 0], [1.3e154, 1.3e154, 0], [1e200, -1e200, 1e200], [1e308, 0, 0]])
    q = qs.from_rotvec(v)
    assert np.all(np.isfinite(q))
    np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-15)
    # The axis is the direction of v (the angle |v| mod 2π carries no information here).
    d = v / np.max(np.abs(v), axis=-1, keepdims=True)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    axis = q[:, 1:] / np.linalg.norm(q[:, 1:], axis=-1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.sum(axis * d, -1)), 1.0, atol=1e-15)
    # Where scipy is finite it agrees (same rotation), on both sides of the |v| = 1 branch.
    w = np.array(
        [[0.3, -0.2, 0.5], [1.0, 0, 0], [1 + 1e-15, 0, 0], [3.0, 4.0, 12.0], [1e10, 2e10, 0]]
    )
    ref = Rotation.from_rotvec(w).as_quat(scalar_first=True)
    np.testing.assert_allclose(np.abs(np.sum(qs.from_rotvec(w) * ref, -1)), 1.0, atol=1e-15)


# ---- item 9: no panic reaches Python when numpy cannot allocate --------------------------------
def test_output_allocation_failure_is_memory_error_naming_the_size_not_a_panic():
    s = qs.PiecewiseSlerp(qs.from_euler("z", [0.0, 1.0, 2.0]), [0.0, 1.0, 2.0])
    huge = np.broadcast_to(0.5, (2 * 10**9,))  # no memory behind it: stride 0
    # The binding allocates the (2e9, 16) output first: 238 GiB, refused by numpy → MemoryError.
    with pytest.raises(MemoryError, match=r"Spline\.evaluate: cannot allocate .*238\.4 GiB"):
        s._core.evaluate(huge, 3, "raise")
    # Through the public API: broadcasting keys against 10^12 parameters (a 0-stride view).
    t = np.broadcast_to(0.5, (10**12,))
    with pytest.raises(MemoryError, match=r"slerp: cannot allocate the \(1000000000000, 4\)"):
        qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], t)
    # An exabyte-sized request is refused the same way.
    t = np.broadcast_to(0.5, (2**57,))
    with pytest.raises(MemoryError, match=r"slerp: cannot allocate .*4\.0 EiB"):
        qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], t)
    assert qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], 0.5).shape == (4,)  # still works
