"""Resampling onto another trajectory's times; the evo and pandas bridges."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline.ops._resample import resample

from ..splinekit import random_walk

T0 = 1_305_031_102.0  # a Unix time as in TUM RGB-D


def est(n=40, seed=0, positions=True):
    q = random_walk(n, seed, step=0.2)
    t = T0 + np.cumsum(np.r_[0.0, np.random.default_rng(seed).uniform(0.02, 0.05, n - 1)])
    p = np.random.default_rng(seed + 1).normal(size=(n, 3)) if positions else None
    return qio.Trajectory(t, q, p, name="est")


def test_resample_onto_another_trajectory():
    e = est()
    gt = qio.Trajectory(np.linspace(e.times[0], e.times[-1], 57), random_walk(57, 9))
    out = e.resample(gt, method="natural")
    s = qs.NaturalSpline(e.quats, e.times - e.times[0])
    np.testing.assert_allclose(out.quats, s(gt.times - e.times[0]), atol=1e-15)
    ps = qs.PoseSpline(e.quats, e.times - e.times[0], e.positions, rotation="natural")
    np.testing.assert_allclose(out.positions, ps.position(gt.times - e.times[0]), atol=1e-12)
    np.testing.assert_array_equal(out.times, gt.times)


def test_resample_keeps_stamps_ns():
    e = est()
    ns = np.round(e.times[5:10] * 1e9).astype(np.int64) + 7
    gt = qio.Trajectory(ns * 1e-9, random_walk(5, 1), stamps_ns=ns)
    np.testing.assert_array_equal(e.resample(gt).stamps_ns, ns)


def test_outside_stamps_name_the_first_in_input_time():
    e = est(positions=False)
    t = np.array([e.times[0] + 0.01, e.times[-1] + 0.25, e.times[-1] + 1])
    with pytest.raises(
        ValueError, match=r"times\[1\] = 1305031103\.\d+ is after the trajectory's last time"
    ):  # noqa: E501
        e.resample(t)
    allout = e.times[0] - np.array([3.0, 2.0])
    with pytest.raises(
        ValueError, match=r"times\[0\] = 1305031099\.0 is before .*\(all of them are outside\)"
    ):
        e.resample(allout)
    c = e.resample(t, extrapolate="clamp")
    np.testing.assert_allclose(c.quats[1:], np.tile(e.quats[-1], (2, 1)), atol=1e-12)
    with pytest.raises(ValueError, match=r"extrapolate: expected one of"):
        e.resample(t, extrapolate="wrap")


def test_resample_bad_times():
    e = est()
    with pytest.raises(ValueError, match=r"times: times\[1\] is nan"):
        e.resample([T0, np.nan])
    with pytest.raises(TypeError, match=r"times: expected an array of times or a Trajectory"):
        e.resample("gt.tum")
    with pytest.raises(ValueError, match=r"times: no times"):
        e.resample([])
    with pytest.raises(TypeError, match=r"traj: expected a quatspline.io.Trajectory"):
        resample(e.quats, [T0])


def test_pandas_round_trip():
    pytest.importorskip("pandas")
    e = est()
    e.stamps_ns = np.round(e.times * 1e9).astype(np.int64)
    e.extra = {"omega": np.ones((len(e), 3))}
    df = e.to_dataframe()
    assert list(df.columns)[:9] == ["t", "qw", "qx", "qy", "qz", "x", "y", "z", "t_ns"]
    assert df["t_ns"].dtype == np.int64
    back = qio.Trajectory.from_dataframe(df)
    np.testing.assert_array_equal(back.times, e.times)
    np.testing.assert_array_equal(back.stamps_ns, e.stamps_ns)
    np.testing.assert_allclose(back.quats, e.quats, atol=1e-15)
    np.testing.assert_array_equal(back.positions, e.positions)


def test_pandas_scalar_last_columns_and_errors():
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(
        {"time": [0.0, 1.0], "qx": [0.0, 0.0], "qy": [0.0, 0.0], "qz": [0.0, 1.0], "qw": [1.0, 0.0]}
    )
    tr = qio.from_dataframe(df)
    np.testing.assert_array_equal(tr.quats, [[1, 0, 0, 0], [0, 0, 0, 1]])
    assert tr.positions is None
    df.loc[1, "qz"] = np.nan
    with pytest.raises(ValueError, match=r"df row:1: NaN or inf in this row"):
        qio.from_dataframe(df)
    with pytest.raises(ValueError, match=r"df: no quaternion columns"):
        qio.from_dataframe(df[["time", "qx"]])
    with pytest.raises(TypeError, match=r"df: expected a pandas DataFrame"):
        qio.from_dataframe({"t": [0]})


def test_evo_round_trip_and_cross_read(tmp_path):
    pytest.importorskip("evo")
    from evo.core.trajectory import PoseTrajectory3D
    from evo.tools import file_interface

    e = est()
    pt = qio.to_evo(e)
    assert isinstance(pt, PoseTrajectory3D)
    np.testing.assert_array_equal(pt.timestamps, e.times)
    back = qio.from_evo(pt)
    np.testing.assert_allclose(back.quats, e.quats, atol=1e-15)
    np.testing.assert_array_equal(back.positions, e.positions)
    # cross-read: our TUM writer, evo's TUM reader (and the other way round)
    qio.write(tmp_path / "e.tum", e)
    ev = file_interface.read_tum_trajectory_file(str(tmp_path / "e.tum"))
    np.testing.assert_array_equal(ev.timestamps, e.times)
    np.testing.assert_allclose(
        np.abs(np.sum(ev.orientations_quat_wxyz * e.quats, 1)), 1, atol=1e-12
    )
    file_interface.write_tum_trajectory_file(str(tmp_path / "evo.tum"), pt)
    mine = qio.read(tmp_path / "evo.tum")
    np.testing.assert_allclose(mine.positions, e.positions, atol=1e-9)
    with pytest.raises(TypeError, match=r"pose_trajectory: expected an evo PoseTrajectory3D"):
        qio.from_evo(e)


def test_linear_extrapolation_continues_at_the_end_rate():
    e = est()
    t_end = e.times[-1]
    out = e.resample(np.array([t_end + 0.1, t_end + 0.2]), extrapolate="linear", method="natural")
    s = qs.NaturalSpline(e.quats, e.times - e.times[0], extrapolate="linear")
    np.testing.assert_allclose(out.quats, s(np.array([0.1, 0.2]) + t_end - e.times[0]), atol=1e-14)
    # constant angular velocity beyond the end: equal steps (to the 2.4e-7 s resolution of
    # float64 Unix times at 1.3e9 s, i.e. 2.4e-6 of a 0.1 s step)
    w = qs.angle_between(out.quats[0], out.quats[1])
    w0 = qs.angle_between(s(t_end - e.times[0]), out.quats[0])
    assert w == pytest.approx(w0, rel=5e-6)
    # positions continue linearly too
    ps = qs.PoseSpline(e.quats, e.times - e.times[0], e.positions, rotation="natural")
    v = ps.linear_velocity(t_end - e.times[0])
    dt = (out.times[1] - e.times[0]) - (out.times[0] - e.times[0])  # the step as computed
    np.testing.assert_allclose(out.positions[1] - out.positions[0], dt * v, atol=1e-12)


def test_trajectory_resample_is_the_ops_sampling_route():
    """``Trajectory.resample`` imported the operation inside the method (io reaching up to
    ops); it now calls the route ops registers, with the same answers."""
    e = est()
    gt = qio.Trajectory(np.linspace(e.times[0] - 0.1, e.times[-1], 33), random_walk(33, 2))
    for method, params in (("c3", {}), ("squad", {}), ("kochanek_bartels", {"tension": 0.3})):
        got = e.resample(gt, method=method, extrapolate="clamp", **params)
        want = resample(e, gt, method=method, extrapolate="clamp", **params)
        np.testing.assert_array_equal(got.times, want.times)
        np.testing.assert_array_equal(got.quats, want.quats)
        np.testing.assert_array_equal(got.positions, want.positions)


def test_trajectory_resample_without_a_registered_sampler_says_so(monkeypatch):
    monkeypatch.setattr(qio.trajectory, "_sampler", [])
    with pytest.raises(RuntimeError, match=r"^Trajectory\.resample: no sampler is registered"):
        est().resample([T0])
    with pytest.raises(TypeError, match=r"^fn: expected a function, got int"):
        qio.trajectory.set_sampler(5)


def test_dataframe_bridge_without_pandas_names_the_extra(monkeypatch):
    """The one hint of a missing optional package (``need``), naming the pip extra."""
    monkeypatch.setitem(__import__("sys").modules, "pandas", None)
    with pytest.raises(ImportError, match=r'needs pandas: pip install "quatspline\[pandas\]"'):
        est().to_dataframe()
    with pytest.raises(ImportError, match=r'needs pandas: pip install "quatspline\[pandas\]"'):
        qio.from_dataframe(None)
