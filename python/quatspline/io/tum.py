"""TUM RGB-D trajectory files: ``timestamp tx ty tz qx qy qz qw`` (quaternion scalar last),
whitespace separated, ``#`` comment lines."""

from __future__ import annotations

from array import array

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write
from ._common import bounded_lines, check_for_writing, fmt, open_regular, parse_float, refuse_extra
from ._fast import table as fast_table
from .trajectory import Trajectory, TrajectoryError, finish

NAMES = ("timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw")


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    fast = fast_table(path, "ws", 8)
    if fast is not None:
        try:
            return finish(path, fast[:, 0], fast[:, [7, 4, 5, 6]], fast[:, 1:4], None, sort, dedupe)
        except TrajectoryError:
            pass  # the careful parser below gives the message with the file's line numbers
    rows, lines = array("d"), array("q")  # 8 bytes a value, not a Python float each
    with open_regular(path, encoding="utf-8-sig") as f, _progress.reading(path) as bar:
        for line, text in enumerate(_progress.lines(bounded_lines(f, path), bar), start=1):
            s = text.strip()
            if not s or s.startswith("#"):
                continue
            cells = s.split()
            if len(cells) != 8:
                raise TrajectoryError(
                    f"{path}:{line}: expected 8 columns (timestamp tx ty tz qx qy qz qw), "
                    f"got {len(cells)}"
                )
            rows.extend([parse_float(path, line, c + 1, NAMES[c], v) for c, v in enumerate(cells)])
            lines.append(line)
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows, dtype=float).reshape(-1, 8)
    quats = a[:, [7, 4, 5, 6]]
    return finish(path, a[:, 0], quats, a[:, 1:4], lines, sort, dedupe)


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj, needs_positions="TUM")
    refuse_extra(path, traj, "TUM")
    pos = traj.positions
    with atomic_write(path) as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for t, p, q in zip(traj.times, pos, traj.quats):
            vals = [t, *p, q[1], q[2], q[3], q[0]]
            f.write(" ".join(fmt(v) for v in vals) + "\n")
