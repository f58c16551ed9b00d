"""scipy-friendly conventions (issue 2.6): Rotation inputs, pandas/datetime times, the
``s(t, 1)`` hint, and the pose classes' argument order with its deprecation path."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
import quatspline as qs
from scipy.spatial.transform import Rotation, RotationSpline

RNG = np.random.default_rng(7)
ROT = Rotation.random(6, random_state=3)
Q = qs.from_scipy(ROT)
T = np.array([0.0, 0.4, 1.1, 1.5, 2.6, 3.0])


def test_rotation_is_converted_like_from_xyzw():
    xyzw = ROT.as_quat()
    np.testing.assert_array_equal(Q, qs.from_xyzw(xyzw))
    np.testing.assert_array_equal(qs.normalize(ROT), qs.normalize(Q))


@pytest.mark.parametrize(
    "call",
    [
        lambda r: qs.C3Spline(r, T)(T),
        lambda r: qs.NaturalSpline(r, T)(T),
        lambda r: qs.PiecewiseSlerp(r, T)(T),
        lambda r: qs.Squad(r, T)(T),
        lambda r: qs.CatmullRom(r, T)(T),
        lambda r: qs.spline("c3", r, T)(T),
        lambda r: qs.slerp(r[0], r[1], [0.0, 0.3, 1.0]),
        lambda r: qs.rotate(r, [1.0, 2.0, 3.0]),
        lambda r: qs.multiply(r, r[::-1]),
        lambda r: qs.log(r),
        lambda r: qs.as_matrix(r),
        lambda r: qs.rotate_points(r, [[1.0, 0.0, 0.0]]),
        lambda r: qs.dq_from_pose(r, np.zeros(3)),
        lambda r: qs.PoseSpline(r, T, np.zeros((6, 3)))(T)[0],
        lambda r: qs.ScrewSpline(r, T, np.zeros((6, 3)))(T)[0],
    ],
)
def test_every_rotation_argument_accepts_a_scipy_rotation(call):
    np.testing.assert_array_equal(call(ROT), call(Q))


def test_single_rotation_is_one_quaternion():
    r = Rotation.from_euler("z", 90, degrees=True)
    q = qs.slerp(r, [1.0, 0.0, 0.0, 0.0], 0.5)
    assert q.shape == (4,)
    np.testing.assert_allclose(qs.as_rotvec(q)[2], np.pi / 4, atol=1e-15)


def test_natural_spline_matches_rotation_spline_rates_in_body_frame():
    s = qs.NaturalSpline(ROT, T, ends="clamped")
    t = np.linspace(0, 3, 31)
    np.testing.assert_allclose(
        s.angular_velocity(t, frame="body"), RotationSpline(T, ROT)(t, 1), rtol=1e-5, atol=1e-6
    )


def test_scipy_order_argument_points_to_angular_velocity():
    s = qs.C3Spline(Q, T)
    for order in (1, 2, np.int64(1)):
        with pytest.raises(TypeError, match=r"angular_velocity\(t, frame='body'\)"):
            s(0.5, order)
    with pytest.raises(ValueError, match="out:"):
        s(0.5, np.zeros(4, dtype=np.float32))


def test_datetime_index_times_are_seconds():
    idx = pd.date_range("2024-03-01 12:00", periods=6, freq="250ms")
    s = qs.NaturalSpline(Q, idx)
    epoch = idx[0].value / 1e9
    assert s.domain == (pytest.approx(epoch), pytest.approx(epoch + 1.25))
    np.testing.assert_allclose(
        s(idx), qs.NaturalSpline(Q, 0.25 * np.arange(6))(0.25 * np.arange(6)), atol=1e-6
    )
    np.testing.assert_allclose(s(idx[3]), s(pd.Timestamp(idx[3])), atol=0)
    np.testing.assert_allclose(s(idx.values), s(idx), atol=0)


def test_timezone_aware_times_are_utc():
    naive = pd.date_range("2024-03-01 12:00", periods=6, freq="1s")
    aware = naive.tz_localize("Europe/Berlin")
    assert qs.C3Spline(Q, aware).domain[0] == qs.C3Spline(Q, naive).domain[0] - 3600
    series = pd.Series(aware)
    assert qs.C3Spline(Q, series).domain == qs.C3Spline(Q, aware).domain


def test_timedelta_times_are_seconds():
    td = pd.to_timedelta(T, unit="s")
    s = qs.C3Spline(Q, td)
    assert s.domain == (0.0, 3.0)
    np.testing.assert_array_equal(s(td), qs.C3Spline(Q, T)(T))
    np.testing.assert_array_equal(
        s(np.array([400, 1100], dtype="timedelta64[ms]")), qs.C3Spline(Q, T)([0.4, 1.1])
    )
    assert qs.C3Spline(Q, T)(pd.Timedelta(seconds=1.5)).shape == (4,)


def test_nat_is_rejected_with_its_index():
    idx = pd.DatetimeIndex(
        ["2024-01-01", "NaT", "2024-01-03", "2024-01-04", "2024-01-05", "2024-01-06"]
    )
    with pytest.raises(ValueError, match=r"times: NaT .* index \(1,\)"):
        qs.C3Spline(Q, idx)


def test_pose_classes_take_quats_then_times():
    p = RNG.normal(size=(6, 3))
    new = qs.PoseSpline(Q, T, p)
    with pytest.warns(DeprecationWarning, match=r"write PoseSpline\(quats, times, positions\)"):
        old = qs.PoseSpline(T, Q, p)
    np.testing.assert_array_equal(new.position(T), old.position(T))
    np.testing.assert_array_equal(new.orientation(T), old.orientation(T))
    with pytest.warns(DeprecationWarning, match="ScrewSpline"):
        old_screw = qs.ScrewSpline(list(T), Q, p)
    np.testing.assert_array_equal(old_screw(T)[1], qs.ScrewSpline(Q, T, p)(T)[1])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        qs.PoseSpline(ROT, pd.to_timedelta(T, unit="s"), p)
