"""RepoIMU CSV (as shipped with the ahrs tests): ``;``-separated, two header rows,
``time [s]; Vicon orientation W; X; Y; Z; IMU acc XYZ; gyro XYZ; mag XYZ``. Only time and the
reference orientation are read."""

from __future__ import annotations

from array import array

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write
from ._common import (
    bounded_lines,
    check_for_writing,
    open_regular,
    parse_float,
    read_line,
    refuse_extra,
)
from .trajectory import Trajectory, TrajectoryError, finish

NAMES = ("time", "W", "X", "Y", "Z")


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    rows, lines = array("d"), array("q")  # 8 bytes a value, not a Python float each
    with open_regular(path, encoding="utf-8-sig") as f:
        first = read_line(f, path, 1)
        if not first.startswith("Time (s);Vicon Orientation"):
            raise TrajectoryError(f"{path}:1: bad header: not a RepoIMU file")
        second = read_line(f, path, 2)
        with _progress.reading(path) as bar:
            header = len(first) + len(second)
            for line, text in enumerate(
                _progress.lines(bounded_lines(f, path, 3), bar, header), start=3
            ):
                s = text.strip()
                if not s:
                    continue
                cells = s.split(";")
                if len(cells) < 5:
                    raise TrajectoryError(
                        f"{path}:{line}: expected at least 5 columns, got {len(cells)}"
                    )
                rows.extend([parse_float(path, line, c + 1, NAMES[c], cells[c]) for c in range(5)])
                lines.append(line)
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows, dtype=float).reshape(-1, 5)
    return finish(path, a[:, 0], a[:, 1:5], None, lines, sort, dedupe)


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj)
    refuse_extra(path, traj, "RepoIMU", positions=False)
    with atomic_write(path) as f:
        f.write("Time (s);Vicon Orientation;;;\n;W;X;Y;Z\n")
        for t, q in zip(traj.times, traj.quats):
            f.write(";".join(repr(float(v)) for v in (t, *q)) + "\n")
