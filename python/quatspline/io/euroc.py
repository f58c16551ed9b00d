"""EuRoC MAV ground truth (``state_groundtruth_estimate0/data.csv``) and TUM-VI mocap CSV:
``#timestamp [ns], p_RS_R_x, p_RS_R_y, p_RS_R_z, q_RS_w, q_RS_x, q_RS_y, q_RS_z, …``.
Times are returned in seconds (ns / 1e9); extra columns are ignored."""

from __future__ import annotations

import numpy as np

from .._atomic import atomic_write
from ._common import Trajectory, TrajectoryError, finish, parse_float

NAMES = ("timestamp", "p_x", "p_y", "p_z", "q_w", "q_x", "q_y", "q_z")


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    rows, times, lines = [], [], []
    with open(path, encoding="utf-8-sig") as f:
        header = f.readline()
        if not header.startswith("#"):
            raise TrajectoryError(f"{path}:1: bad header: expected '#timestamp [ns], p_RS_R_x …'")
        for line, text in enumerate(f, start=2):
            s = text.strip()
            if not s:
                continue
            cells = s.split(",")
            if len(cells) < 8:
                raise TrajectoryError(
                    f"{path}:{line}: expected at least 8 columns, got {len(cells)}"
                )
            try:
                ns = int(cells[0])
            except ValueError:
                raise TrajectoryError(
                    f"{path}:{line}: column 1 ('timestamp'): not an integer: "
                    f"{cells[0].strip()[:40]!r}"
                ) from None
            if abs(ns) > 10**30:
                raise TrajectoryError(
                    f"{path}:{line}: column 1 ('timestamp'): {len(str(abs(ns)))}-digit integer "
                    "out of range (|t| ≤ 1e30 ns)"
                )
            times.append(ns * 1e-9)
            rows.append([parse_float(path, line, c + 1, NAMES[c], cells[c]) for c in range(1, 8)])
            lines.append(line)
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows)
    return finish(path, times, a[:, 3:7], a[:, 0:3], lines, sort, dedupe)


def write(path, traj: Trajectory) -> None:
    pos = traj.positions if traj.positions is not None else np.zeros((len(traj), 3))
    with atomic_write(path) as f:
        f.write(
            "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],"
            "q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
        )
        for t, p, q in zip(traj.times, pos, traj.quats):
            vals = [repr(float(v)) for v in (*p, *q)]
            f.write(f"{int(round(t * 1e9))}," + ",".join(vals) + "\n")
