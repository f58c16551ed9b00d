"""Property: every writer either refuses a trajectory (ValueError naming the file) or writes a
file its own reader reads back to the same trajectory. Hypothesis draws the hostile cases:
empty, repeated or decreasing times, NaN/inf, zero quaternions, huge and tiny values, odd
column and joint names."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import quatspline.io as qio
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

FORMATS = {
    "csv": ".csv",
    "json": ".json",
    "npz": ".npz",
    "tum": ".txt",
    "euroc": ".csv",
    "bvh": ".bvh",
    "repoimu": ".csv",
    "kitti": ".txt",
}

floats = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.floats(-1e3, 1e3),
    st.sampled_from([0.0, -0.0, 1e-300, 1e300, 5e-324]),
)


@st.composite
def trajectories(draw):
    n = draw(st.integers(0, 6))
    if draw(st.booleans()):
        t = np.cumsum(np.abs(draw(st.lists(st.floats(0, 10), min_size=n, max_size=n))))
    else:
        t = np.array(draw(st.lists(floats, min_size=n, max_size=n)), dtype=float)
    q = np.array(draw(st.lists(st.lists(floats, min_size=4, max_size=4), min_size=n, max_size=n)))
    q = q.reshape(n, 4)
    pos = None
    if draw(st.booleans()):
        pos = np.array(
            draw(st.lists(st.lists(floats, min_size=3, max_size=3), min_size=n, max_size=n))
        )
        pos = pos.reshape(n, 3)
    extra = {}
    if draw(st.booleans()):
        name = draw(st.text(min_size=0, max_size=6))
        extra[name] = np.array(draw(st.lists(floats, min_size=n, max_size=n)))
    name = draw(st.text(max_size=8))
    return qio.Trajectory(t, q, pos, extra=extra, name=name)


def _same(a: qio.Trajectory, b: qio.Trajectory) -> None:
    assert len(a) == len(b)
    np.testing.assert_allclose(b.times, a.times, rtol=1e-9, atol=1e-9)
    scale = np.max(np.abs(a.quats), axis=1, keepdims=True)
    qa = a.quats / scale
    qa = qa / np.linalg.norm(qa, axis=1, keepdims=True)
    # as rotations (the BVH writer goes through Euler angles, KITTI through matrices)
    np.testing.assert_allclose(np.abs(np.sum(qa * b.quats, axis=1)), 1.0, atol=1e-6)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(traj=trajectories(), fmt=st.sampled_from(sorted(FORMATS)))
def test_a_writer_refuses_whatever_its_reader_would_reject(traj, fmt):
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"out{FORMATS[fmt]}"
        try:
            qio.write(path, traj, format=fmt)
        except ValueError as e:
            assert str(path) in str(e) and "\n" not in str(e), str(e)
            assert not path.exists()
            return
        back = qio.read(path, format=fmt)  # must not raise: the writer accepted it
        if fmt == "kitti":  # poses only: times are 0, 1, … unless a times file is written
            back.times = traj.times
        if fmt != "bvh":  # BVH stores angles; its times are i × Frame Time
            _same(traj, back)
        else:
            assert len(back) == len(traj)


def test_times_near_the_float_limit_are_compared_without_overflow(tmp_path):
    # hypothesis found it: the checks subtracted times, and 1e300 − (−1.8e308) overflowed
    q = np.array([[1.0, 0.0, 0.0, 0.0]] * 2)
    for fmt, ext in FORMATS.items():
        path = tmp_path / f"down{ext}"
        traj = qio.Trajectory(np.array([1e300, -1.7976931348623157e308]), q, np.zeros((2, 3)))
        try:
            qio.write(path, traj, format=fmt)
        except ValueError as e:
            assert "decreasing time" in str(e) and str(path) in str(e), (fmt, str(e))
        else:
            raise AssertionError(f"{fmt}: decreasing times written")
        assert not path.exists()
    # increasing but spanning more than the largest float: BVH's frame time is not finite
    path = tmp_path / "wide.bvh"
    wide = qio.Trajectory(np.array([-1.7e308, 1.7e308]), q)
    try:
        qio.write(path, wide, format="bvh")
    except ValueError as e:
        assert "uniformly spaced" in str(e) and str(path) in str(e)
    else:
        raise AssertionError("bvh: a non-finite frame time written")
    assert not path.exists()
