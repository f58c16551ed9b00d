"""KITTI odometry poses: round trips, a cross-read against evo's KITTI reader and scipy's
matrices, times files, and malformed rows."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from scipy.spatial.transform import Rotation

from ..splinekit import random_walk


def traj(n=30, seed=0):
    q = random_walk(n, seed)
    p = np.random.default_rng(seed).normal(size=(n, 3)) * 10
    return qio.Trajectory(np.arange(n) * 0.1, q, p)


def same_rotation(a, b, tol):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    assert np.max(d) <= tol


def test_round_trip_with_times(tmp_path):
    tr = traj()
    qio.write(tmp_path / "00.txt", tr, format="kitti", times_path=tmp_path / "times.txt")
    assert qio.detect_format(tmp_path / "00.txt") == "kitti"
    back = qio.read(tmp_path / "00.txt", times=tmp_path / "times.txt")
    np.testing.assert_array_equal(back.times, tr.times)
    same_rotation(back.quats, tr.quats, 1e-15)
    np.testing.assert_array_equal(back.positions, tr.positions)
    # without a times file: frame numbers
    np.testing.assert_array_equal(qio.read(tmp_path / "00.txt").times, np.arange(30.0))


def test_matrices_match_scipy(tmp_path):
    """Cross-read: a file written from scipy's matrices (the KITTI layout) reads as them."""
    rng = np.random.default_rng(7)
    r = Rotation.random(50, random_state=7)
    t = rng.normal(size=(50, 3))
    rows = np.concatenate([r.as_matrix(), t[:, :, None]], axis=2).reshape(50, 12)
    np.savetxt(tmp_path / "p.txt", rows, fmt="%.17e")
    tr = qio.read(tmp_path / "p.txt")
    same_rotation(tr.quats, r.as_quat()[:, [3, 0, 1, 2]], 1e-14)
    np.testing.assert_array_equal(tr.positions, t)


def test_cross_read_with_evo(tmp_path):
    file_interface = pytest.importorskip("evo.tools.file_interface")
    tr = traj(seed=2)
    qio.write(tmp_path / "k.txt", tr, format="kitti", times_path=tmp_path / "t.txt")
    ev = file_interface.read_kitti_poses_file(str(tmp_path / "k.txt"))
    np.testing.assert_allclose(ev.positions_xyz, tr.positions, atol=1e-12)
    same_rotation(ev.orientations_quat_wxyz, tr.quats, 1e-12)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (
            "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n",
            r"k.txt:2: expected 12 values .*got 11",
        ),
        ("1 0 0 0 0 1 0 0 0 0 1 x\n", r"k.txt:1: column 12 \('tz'\): not a number: 'x'"),
        ("1 0 0 0 0 1 0 0 0 0 1 nan\n", r"k.txt:1: NaN or inf in this row"),
        ("1 0 0 0 0 1 0 0 0 0 -1 0\n", r"k.txt:1: the 3×3 block is not a rotation"),
        ("# only a comment\n", r"k.txt: no data rows"),
    ],
)
def test_bad_rows(tmp_path, text, match):
    (tmp_path / "k.txt").write_text(text)
    with pytest.raises(ValueError, match=match):
        qio.read(tmp_path / "k.txt", format="kitti")


def test_times_file_mismatch(tmp_path):
    qio.write(tmp_path / "k.txt", traj(5), format="kitti", times_path=tmp_path / "t0.txt")
    (tmp_path / "t.txt").write_text("0\n1\n2\n")
    with pytest.raises(ValueError, match=r"t.txt: 3 times for 5 poses in .*k.txt"):
        qio.read(tmp_path / "k.txt", times=tmp_path / "t.txt")
    (tmp_path / "t.txt").write_text("0\n1 2\n")
    with pytest.raises(ValueError, match=r"t.txt:2: expected one time, got 2 values"):
        qio.read(tmp_path / "k.txt", times=tmp_path / "t.txt")


def test_writer_needs_positions(tmp_path):
    tr = qio.Trajectory(np.arange(3.0), qs.normalize(np.ones((3, 4))))
    with pytest.raises(ValueError, match=r"KITTI poses need positions"):
        qio.write(tmp_path / "k.txt", tr, format="kitti")
    assert not (tmp_path / "k.txt").exists()
