"""Output paths that cannot be created: a parent that is a regular file, a FIFO or a dangling
symbolic link. Every writer and the batch command name the component, in one line."""

from __future__ import annotations

import os

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.cli import main

TRAJ = qio.Trajectory(
    np.arange(4.0), [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], np.zeros((4, 3))
)

#: (output name, format) for every writer
OUTPUTS = [
    ("out.csv", None),
    ("out.json", None),
    ("out.npz", None),
    ("out.bvh", None),
    ("out.tum", None),
    ("out.glb", None),
    ("out.bag", None),
    ("out.mcap", None),
    ("bagdir", "rosbag"),
    ("out.txt", "euroc"),
    ("out.txt", "kitti"),
]


def _blockers(tmp_path):
    plain = tmp_path / "plain.csv"
    plain.write_text("precious\n")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    dangling = tmp_path / "dangling"
    os.symlink(tmp_path / "nowhere" / "deeper", dangling)
    return [
        (plain, "plain.csv is a regular file, not a directory"),
        (fifo, "fifo is a FIFO (named pipe), not a directory"),
        (dangling, "dangling is a symbolic link to a missing target"),
    ]


@pytest.mark.parametrize("name, fmt", OUTPUTS, ids=[f"{n}-{f}" for n, f in OUTPUTS])
def test_writers_name_a_parent_that_is_not_a_directory(tmp_path, name, fmt):
    """`io.write("plain.csv/out.csv", …)` raised `NotADirectoryError: [Errno 20] Not a
    directory` (an OSError, not the ValueError the writers promise, and not saying which
    component); a dangling link created directories where it pointed."""
    for blocker, why in _blockers(tmp_path):
        for out in (blocker / name, blocker / "sub" / name):
            with pytest.raises(ValueError) as err:
                qio.write(out, TRAJ, format=fmt)
            msg = str(err.value)
            assert msg.startswith(f"{out}: ") and msg.endswith(why), msg
    assert (tmp_path / "plain.csv").read_text() == "precious\n"
    assert not (tmp_path / "nowhere").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dangling", "fifo", "plain.csv"]


def test_kitti_pair_names_a_times_parent_that_is_not_a_directory(tmp_path):
    plain = tmp_path / "plain"
    plain.write_text("x")
    t = qio.Trajectory(TRAJ.times + 0.5, TRAJ.quats, TRAJ.positions)
    with pytest.raises(ValueError, match=r"times.txt: .*plain is a regular file, not a directory$"):
        qio.write(tmp_path / "poses.txt", t, format="kitti", times_path=plain / "times.txt")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plain"]


@pytest.mark.parametrize("command", ["sample", "batch"])
def test_commands_name_an_output_parent_that_is_not_a_directory(tmp_path, capsys, command):
    """`quatspline sample in.csv -o fifo/out.csv` and `quatspline batch sample in.csv -o
    file/out` printed `error: [Errno 20] Not a directory: '…/.quatspline-batch'`."""
    src = tmp_path / "in.csv"
    qio.write(src, TRAJ)
    for blocker, why in _blockers(tmp_path):
        out = blocker / "out.csv"
        argv = ["sample", str(src), "-o", str(out), "--count", "5"]
        if command == "batch":
            argv = ["batch", "sample", str(src), "-o", str(out), "--count", "5", "--workers", "1"]
        capsys.readouterr()
        assert main(argv) != 0
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and err.endswith(why), err
        assert str(out) in err
    assert (tmp_path / "plain.csv").read_text() == "precious\n"
    assert not (tmp_path / "nowhere").exists()
