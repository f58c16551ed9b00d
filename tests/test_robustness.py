"""Robustness rows of docs/robustness.md that are not covered by the per-feature test files."""

from __future__ import annotations

import errno
import os

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from .splinekit import random_walk

ALL = {
    "slerp": lambda q, t: qs.PiecewiseSlerp(q, t),
    "nlerp": lambda q, t: qs.PiecewiseNlerp(q, t),
    "lin_euler": lambda q, t: qs.PiecewiseLinEuler(q, t),
    "lin_mat": lambda q, t: qs.PiecewiseLinMat(q, t),
    "squad": lambda q, t: qs.Squad(q, t),
    "catmull_rom": lambda q, t: qs.CatmullRom(q, t),
    "natural": lambda q, t: qs.NaturalSpline(q, t),
    "c3": lambda q, t: qs.C3Spline(q, t),
    "beta": lambda q, t: qs.BetaSpline(q, times=t[: len(q) - 2]),
    "bspline": lambda q, t: qs.CumulativeBSpline(q),
    "hermite": lambda q, t: qs.Hermite(q, t, np.ones((len(q), 3)), np.ones((len(q), 3))),
    "kochanek_bartels": lambda q, t: qs.KochanekBartels(q, t, tension=0.2, continuity=0.3),
    "catmull_rom_centripetal": lambda q, t: qs.CatmullRom(q, alpha=0.5),
    "squad_rest": lambda q, t: qs.Squad(q, t, ends="rest"),
    "c3_auto_rest": lambda q, t: qs.C3Spline(q, t, alpha="auto", ends="rest"),
    "natural_closed": lambda q, t: qs.NaturalSpline(q, np.r_[t, t[-1] + 1], ends="closed"),
    "c3_closed": lambda q, t: qs.C3Spline(q, np.r_[t, t[-1] + 1], ends="closed"),
    "kb_closed": lambda q, t: qs.KochanekBartels(q, np.r_[t, t[-1] + 1], ends="closed"),
    "squad_closed": lambda q, t: qs.Squad(q, np.r_[t, t[-1] + 1], ends="closed"),
    "bspline_closed": lambda q, t: qs.CumulativeBSpline(q, ends="closed"),
}


def chain(angles, axis=(0.3, -0.5, 0.8)):
    rel = qs.from_axis_angle(np.tile(axis, (len(angles), 1)), angles)
    q = [np.array([1.0, 0, 0, 0])]
    for r in rel:
        q.append(qs.multiply(q[-1], r))
    return np.array(q)


@pytest.mark.parametrize("name", list(ALL))
@pytest.mark.parametrize("step", [1e-12, 1e-8, np.pi - 1e-9])
def test_near_identity_and_near_pi_steps_through_every_method(name, step):
    rng = np.random.default_rng(3)
    q = chain(np.full(6, step))
    q = qs.multiply(q, qs.from_axis_angle(rng.normal(size=3), 1e-3))  # not all on one axis
    t = np.arange(len(q), dtype=float)
    s = ALL[name](q, t)
    x = np.linspace(*s.domain, 301)
    d = s.derivatives(x, 3)
    assert np.all(np.isfinite(d)), name
    np.testing.assert_allclose(np.linalg.norm(d[:, 0], axis=1), 1, atol=2e-15)
    for f in (s.angular_velocity, s.angular_acceleration, s.jerk):
        assert np.all(np.isfinite(f(x, frame="body")))


def test_keys_1e12_apart_work_and_closer_keys_are_rejected():
    q = random_walk(3, 1)
    s = qs.C3Spline(q, [0.0, 1e-12, 1.0])
    x = np.array([0.0, 5e-13, 1e-12, 0.5, 1.0])
    assert np.all(np.isfinite(s.derivatives(x, 3)))
    with pytest.raises(ValueError, match=r"times: keys at index 0 and 1 are .* apart"):
        qs.C3Spline(q, [0.0, 1e-300, 1.0])


def test_a_million_keys_norm_drift():
    k = np.arange(1_000_000)
    rotvec = np.column_stack([3 * np.sin(1e-3 * k), 2 * np.cos(1.3e-3 * k), np.sin(7e-4 * k)])
    q = qs.from_rotvec(rotvec)  # a smooth path, consecutive keys ≲ 0.004 rad apart
    x = np.random.default_rng(0).uniform(0, 999_999, 200_000)
    for s in (qs.PiecewiseSlerp(q), qs.C3Spline(q)):
        assert np.max(np.abs(np.linalg.norm(s(x), axis=1) - 1)) <= 1e-12
    assert abs(np.linalg.norm(qs.PiecewiseSlerp(q)(999_999.0)) - 1) <= 1e-12


def test_evaluation_exactly_on_joints_from_both_sides_is_deterministic():
    q = random_walk(6, 4)
    s = qs.Squad(q, [0.0, 0.5, 1.5, 2.0, 3.5, 4.0])
    j = s.joints
    at = s(j)
    for k in range(1, len(j) - 1):
        left = s.segment_derivatives(k - 1, j[k])
        right = s.segment_derivatives(k, j[k])
        np.testing.assert_allclose(left[0], right[0], atol=1e-15)
        np.testing.assert_array_equal(at[k], right[0])  # a joint belongs to the right segment
    np.testing.assert_array_equal(s(j), s(j))


def test_failed_write_leaves_existing_output_untouched(tmp_path, monkeypatch):
    out = tmp_path / "out.csv"
    out.write_text("precious\n")
    traj = qio.Trajectory([0.0, 1.0], [[1, 0, 0, 0], [0, 1, 0, 0]])

    def disk_full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "replace", disk_full)
    with pytest.raises(OSError, match="No space left"):
        qio.write(out, traj)
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_huge_csv_line_is_an_error(tmp_path):
    p = tmp_path / "huge.csv"
    p.write_text("t" + ",x" * (1 << 20) + "\n0\n")
    with pytest.raises(ValueError, match=r"huge.csv:1: header line longer than"):
        qio.read(p)


extreme = st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True, width=64)


@settings(max_examples=300, deadline=None)
@given(arrays(np.float64, (2, 4), elements=extreme), extreme)
def test_extreme_floats_give_a_valueerror_or_a_unit_quaternion(keys, t):
    try:
        out = qs.slerp(keys[0], keys[1], t)
    except ValueError:
        return
    assert np.all(np.isfinite(out)), (keys, t, out)
    assert abs(np.linalg.norm(out) - 1) < 1e-12 or abs(t) > 1e6


@settings(max_examples=200, deadline=None)
@given(arrays(np.float64, (4, 4), elements=extreme), arrays(np.float64, 3, elements=extreme))
def test_extreme_floats_through_a_spline(keys, ts):
    try:
        s = qs.C3Spline(keys)
    except ValueError:
        return
    try:
        d = s.derivatives(ts, 3)
    except ValueError:
        return
    assert np.all(np.isfinite(d))


def test_huge_interpolation_parameters_are_rejected():
    # found by hypothesis: t = 1.1e308 made t·θ overflow and slerp return NaN
    with pytest.raises(
        ValueError, match=r"t: element 0 is beyond the supported range \|t\| ≤ 1e12"
    ):
        qs.slerp([1.0, 0, 0, 0], [0, 1.0, 0, 0], 1.1444469943028113e308)
    with pytest.raises(ValueError, match=r"^t: element 1 is beyond"):
        qs.power([0.0, 1, 0, 0], [0.5, -1e13])
    assert np.all(np.isfinite(qs.slerp([1.0, 0, 0, 0], [0, 1.0, 0, 0], 1e12)))
