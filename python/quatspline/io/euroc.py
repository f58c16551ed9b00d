"""EuRoC MAV ground truth (``state_groundtruth_estimate0/data.csv``) and TUM-VI mocap CSV:
``#timestamp [ns], p_RS_R_x, p_RS_R_y, p_RS_R_z, q_RS_w, q_RS_x, q_RS_y, q_RS_z, …``.
Times are returned in seconds (ns / 1e9) and kept exactly as int64 nanoseconds in
``Trajectory.stamps_ns``, which the writer uses; extra columns are ignored."""

from __future__ import annotations

from array import array

import numpy as np

from .._util.atomic import atomic_write
from ._common import (
    check_for_writing,
    nanosecond_rows,
    open_regular,
    parse_float,
    read_line,
    refuse_extra,
)
from ._fast import table as fast_table
from .trajectory import Trajectory, TrajectoryError, finish

NAMES = ("timestamp", "p_x", "p_y", "p_z", "q_w", "q_x", "q_y", "q_z")


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    # 8 bytes a value, not a Python object each (a bad last row is found after the rest)
    rows, times, lines, stamps = array("d"), array("d"), array("q"), array("q")
    exact = True  # every stamp fits int64 and is kept exactly
    with open_regular(path, encoding="utf-8-sig") as f:
        header = read_line(f, path, 1)
        if not header.startswith("#"):
            raise TrajectoryError(f"{path}:1: bad header: expected '#timestamp [ns], p_RS_R_x …'")
        fast = fast_table(path, ",", None, skip=1, int_first=True, min_cols=8)
        if fast is not None:
            ns, a = fast
            try:
                return finish(
                    path, ns * 1e-9, a[:, 3:7], a[:, 0:3], None, sort, dedupe, stamps_ns=ns
                )
            except TrajectoryError:
                pass  # the careful parser below gives the message with the file's line numbers
        for line, ns, cells in nanosecond_rows(
            f, path, header, 8, False, 10**30 + 1, "|t| ≤ 1e30 ns"
        ):
            times.append(ns * 1e-9)
            if exact and -(2**63) <= ns < 2**63:
                stamps.append(ns)
            else:
                exact = False
            rows.extend([parse_float(path, line, c + 1, NAMES[c], cells[c]) for c in range(1, 8)])
            lines.append(line)
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows, dtype=float).reshape(-1, 7)
    return finish(
        path,
        np.array(times, dtype=float),
        a[:, 3:7],
        a[:, 0:3],
        np.asarray(lines),
        sort,
        dedupe,
        stamps_ns=np.asarray(stamps) if exact else None,
    )


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj, needs_positions="EuRoC")
    refuse_extra(path, traj, "EuRoC")
    if np.max(np.abs(traj.times)) > 1e21:
        raise ValueError(f"{path}: times beyond ±1e21 s cannot be written as integer nanoseconds")
    # exact integer stamps when the trajectory kept them (read from EuRoC or a bag)
    ns = traj.stamps_ns if traj.stamps_ns is not None else np.round(traj.times * 1e9)
    off = np.abs(ns * 1e-9 - traj.times) > 1e-6 * np.maximum(1.0, np.abs(traj.times))
    if np.any(off):  # stamps_ns kept from a file but times changed since
        k = int(np.argmax(off))
        raise ValueError(
            f"{path}: stamps_ns[{k}] = {int(ns[k])} disagrees with times[{k}] = "
            f"{float(traj.times[k])!r}; set stamps_ns=None to write the times"
        )
    if np.any(np.diff(ns) <= 0):
        k = int(np.argmax(np.diff(ns) <= 0)) + 1
        raise ValueError(
            f"{path}: times at rows {k - 1} and {k} round to the same nanosecond; the EuRoC "
            "format stores integer nanoseconds (resample or write csv)"
        )
    pos = traj.positions
    with atomic_write(path) as f:
        f.write(
            "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],"
            "q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
        )
        for t, p, q in zip(ns, pos, traj.quats):
            vals = [repr(float(v)) for v in (*p, *q)]
            f.write(f"{int(t)}," + ",".join(vals) + "\n")
