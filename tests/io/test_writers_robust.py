"""Regression tests for the writers and outputs of issue 2.1: a writer refuses whatever its
reader would reject; outputs are regular files only, symlinks are followed, a replaced file
keeps its mode and owner, and SIGTERM leaves no temporary file. Each failed on main."""

from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.cli import main

from ..conftest import random_quats

FORMATS = ["csv", "json", "npz", "tum", "euroc", "bvh", "repoimu"]
EXT = {
    "csv": ".csv",
    "json": ".json",
    "npz": ".npz",
    "tum": ".txt",
    "euroc": ".csv",
    "bvh": ".bvh",
    "repoimu": ".csv",
}


def _traj(n=5, positions=True, **kw):
    t = np.arange(n) * 0.5
    pos = np.column_stack([t, -t, 2 * t]) if positions else None
    return qio.Trajectory(t, random_quats(n, seed=9), pos, **kw)


def _write(tmp_path, fmt, traj):
    p = tmp_path / f"out{EXT[fmt]}"
    qio.write(p, traj, format=fmt)
    return p


@pytest.mark.parametrize("fmt", FORMATS)
def test_every_writer_round_trips_what_its_reader_accepts(tmp_path, fmt):
    traj = _traj(positions=fmt != "repoimu")
    back = qio.read(_write(tmp_path, fmt, traj), format=fmt)
    np.testing.assert_allclose(back.times, traj.times, atol=1e-9)
    np.testing.assert_allclose(np.abs(np.sum(back.quats * traj.quats, axis=1)), 1.0, atol=1e-9)
    if traj.positions is not None:
        np.testing.assert_allclose(back.positions, traj.positions, atol=1e-9)


@pytest.mark.parametrize(
    ("fmt", "where"),
    [
        (f, w)
        for f in FORMATS
        for w in ("times", "quats", "positions")
        if not (f == "repoimu" and w == "positions")  # the format has no positions
    ],
)
def test_writers_refuse_nan(tmp_path, fmt, where):
    traj = _traj(positions=fmt != "repoimu")
    getattr(traj, where)[2] = np.nan
    with pytest.raises(ValueError, match=rf"refusing to write NaN or inf \({where}, row 2\)"):
        _write(tmp_path, fmt, traj)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("fmt", FORMATS)
def test_writers_refuse_zero_rows(tmp_path, fmt):
    traj = qio.Trajectory(
        np.zeros(0), np.zeros((0, 4)), None if fmt == "repoimu" else np.zeros((0, 3))
    )
    with pytest.raises(ValueError, match="refusing to write a trajectory with no rows"):
        _write(tmp_path, fmt, traj)


@pytest.mark.parametrize("fmt", FORMATS)
def test_writers_refuse_duplicate_times(tmp_path, fmt):
    traj = _traj(positions=fmt != "repoimu")
    traj.times[3] = traj.times[2]
    with pytest.raises(ValueError, match="refusing to write duplicate time 1.0 at row 3"):
        _write(tmp_path, fmt, traj)


def test_euroc_refuses_times_that_round_to_the_same_nanosecond(tmp_path):
    traj = _traj()
    traj.times[1] = traj.times[0] + 1e-10
    with pytest.raises(ValueError, match="round to the same nanosecond"):
        _write(tmp_path, "euroc", traj)


@pytest.mark.parametrize(
    "name", ["a,b", "a;b", "tab\there", 'q"', "line\nbreak", "unit[s]", " x", "#c"]
)
def test_csv_refuses_column_names_its_reader_would_misread(tmp_path, name):
    traj = _traj(extra={name: np.arange(5.0)})
    with pytest.raises(ValueError, match="cannot be written to CSV"):
        _write(tmp_path, "csv", traj)


@pytest.mark.parametrize("name", ["x", "qw", "time", "roll"])
def test_csv_refuses_column_names_read_as_data(tmp_path, name):
    traj = _traj(positions=False, extra={name: np.arange(5.0)})
    with pytest.raises(ValueError, match="would be read as"):
        _write(tmp_path, "csv", traj)


@pytest.mark.parametrize(("fmt", "name"), [("json", "times"), ("json", "layout"), ("npz", "quats")])
def test_json_and_npz_refuse_extra_names_that_overwrite_the_data(tmp_path, fmt, name):
    with pytest.raises(ValueError, match=f"extra column '{name}' would collide"):
        _write(tmp_path, fmt, _traj(extra={name: np.arange(5.0)}))


@pytest.mark.parametrize("name", ["Left\nArm", "Arm\r", "two  spaces", " ", "{"])
def test_bvh_refuses_joint_names_its_reader_would_misread(tmp_path, name):
    with pytest.raises(ValueError, match="cannot be written to BVH"):
        _write(tmp_path, "bvh", _traj(name=name))


def test_bvh_without_positions_writes_no_position_channels(tmp_path):
    back = qio.read(_write(tmp_path, "bvh", _traj(positions=False)))
    assert back.positions is None


@pytest.mark.parametrize("fmt", ["tum", "euroc", "bvh"])
def test_formats_without_extra_columns_refuse_them_rather_than_drop(tmp_path, fmt):
    with pytest.raises(ValueError, match="has no columns for omega"):
        _write(tmp_path, fmt, _traj(extra={"omega": np.zeros((5, 3))}))
    # a column name with a line break (found by hypothesis) stays a one-line message
    with pytest.raises(ValueError, match=r"has no columns for '\\n', omega \(write") as e:
        _write(tmp_path, fmt, _traj(extra={"\n": np.zeros(5), "omega": np.zeros((5, 3))}))
    assert "\n" not in str(e.value)


# ---- outputs: regular files only, symlinks followed, mode and owner kept ---------------------
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs")
def test_fifo_output_is_refused_not_replaced(tmp_path, capsys):
    src = _write(tmp_path, "csv", _traj())
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    assert main(["sample", str(src), "-o", str(fifo), "--count", "5"]) == 1
    assert "is a FIFO (named pipe); refusing to replace it" in capsys.readouterr().err
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    with pytest.raises(ValueError, match="refusing to replace it"):
        qio.write(fifo, _traj())


@pytest.mark.skipif(os.geteuid() != 0, reason="creating a device node needs root")
def test_device_output_is_refused_not_replaced(tmp_path, capsys):
    """A private copy of /dev/null in tmp_path: main replaced it by a regular file (as root,
    ``-o /dev/null`` replaced the system's)."""
    src = _write(tmp_path, "csv", _traj())
    dev = tmp_path / "null.csv"
    os.mknod(dev, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    assert main(["sample", str(src), "-o", str(dev), "--count", "5"]) == 1
    assert "is a device; refusing to replace it" in capsys.readouterr().err
    assert stat.S_ISCHR(os.lstat(dev).st_mode)


def test_directory_output_is_refused(tmp_path):
    d = tmp_path / "d.csv"
    d.mkdir()
    with pytest.raises(ValueError, match="is a directory; refusing to replace it"):
        qio.write(d, _traj())


def test_output_symlink_writes_its_target_and_stays_a_link(tmp_path):
    target = tmp_path / "real" / "target.csv"
    target.parent.mkdir()
    target.write_text("old\n")
    link = tmp_path / "link.csv"
    os.symlink(target, link)
    qio.write(link, _traj())
    assert link.is_symlink()
    assert len(qio.read(target)) == 5
    assert not [p for p in target.parent.iterdir() if p.name.startswith(".")]


def test_dash_output_means_standard_output(tmp_path, capsys):
    src = _write(tmp_path, "csv", _traj())
    assert main(["sample", str(src), "-o", "-", "--count", "3"]) == 0
    cap = capsys.readouterr()
    assert cap.out.splitlines()[0] == "t,qw,qx,qy,qz,x,y,z"
    assert len(cap.out.splitlines()) == 4
    assert "wrote standard output" in cap.err
    assert not (tmp_path / "-").exists()


def test_replaced_output_keeps_its_mode_and_owner(tmp_path):
    p = tmp_path / "keep.csv"
    p.write_text("old\n")
    os.chmod(p, 0o600)
    owner = None
    if os.geteuid() == 0:
        owner = (4321, 4322)
        os.chown(p, *owner)
    qio.write(p, _traj())
    st = os.stat(p)
    assert stat.S_IMODE(st.st_mode) == 0o600
    if owner:
        assert (st.st_uid, st.st_gid) == owner
    os.chmod(p, 0o640)
    qio.write(p, _traj())
    assert stat.S_IMODE(os.stat(p).st_mode) == 0o640


def test_sigterm_during_a_write_leaves_no_temporary_file(tmp_path):
    """A child writes a large CSV; SIGTERM arrives once the temporary file exists. Main left
    the hidden ``.big.csv.*.tmp`` behind."""
    out = tmp_path / "big.csv"
    code = textwrap.dedent(
        f"""
        import numpy as np, quatspline.io as qio
        n = 3_000_000
        q = np.tile([1.0, 0, 0, 0], (n, 1))
        qio.write({str(out)!r}, qio.Trajectory(np.arange(n, dtype=float), q))
        """
    )
    child = subprocess.Popen([sys.executable, "-c", code])
    try:
        deadline = time.monotonic() + 120
        while not any(p.name.endswith(".tmp") for p in tmp_path.iterdir()):
            assert child.poll() is None, "the child finished before it could be interrupted"
            assert time.monotonic() < deadline
            time.sleep(0.02)
        child.send_signal(signal.SIGTERM)
        rc = child.wait(timeout=120)
    finally:
        if child.poll() is None:
            child.kill()
    assert rc == 128 + signal.SIGTERM
    assert list(tmp_path.iterdir()) == []


def test_dash_output_into_a_closed_pipe_exits_quietly(tmp_path):
    """``sample … -o - | head -c 100``: main printed ``[Errno 32] Broken pipe`` and exit 1."""
    src = _write(tmp_path, "csv", _traj(n=50))
    child = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "quatspline.cli",
            "sample",
            str(src),
            "-o",
            "-",
            "--count",
            "300000",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    with child.stderr:
        assert child.stdout.read(100)
        child.stdout.close()
        err = child.stderr.read().decode()
    assert child.wait(timeout=300) == 141
    assert err == ""


def test_euroc_round_trip_keeps_integer_nanosecond_stamps(tmp_path):
    """Stamps of 1.4e18 ns do not survive seconds in float64 (±128 ns): the writer uses the
    integer stamps the reader kept."""
    p = tmp_path / "in.csv"
    stamps = [1403715273262142976, 1403715273267142912, 1403715273272142848]
    header = (
        "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],"
        "q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
    )
    p.write_text(header + "".join(f"{s},0,0,0,1,0,0,0\n" for s in stamps))
    out = tmp_path / "out.csv"
    qio.write(out, qio.read(p), format="euroc")
    assert [int(line.split(",")[0]) for line in out.read_text().splitlines()[1:]] == stamps
