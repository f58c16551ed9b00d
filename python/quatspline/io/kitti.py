"""KITTI odometry poses: one pose per line, the 12 values of the 3×4 matrix [R | t] in row
order, whitespace separated (``poses/00.txt``). KITTI has no time column: times come from a
separate file with one time per line (``sequences/00/times.txt``) given as ``times=``, or are
the frame numbers 0, 1, 2, … when it is left out."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import _progress
from .._atomic import atomic_write
from . import _fast
from ._common import Trajectory, TrajectoryError, finish, fmt, parse_float

NAMES = ("r11", "r12", "r13", "tx", "r21", "r22", "r23", "ty", "r31", "r32", "r33", "tz")


def _matrices_to_quats(path, mats: np.ndarray, lines) -> np.ndarray:
    from ..convert import from_matrix

    det = np.linalg.det(mats)
    bad = ~(det > 0.5)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise TrajectoryError(
            f"{path}:{lines[k]}: the 3×3 block is not a rotation (determinant {det[k]:.6g})"
        )
    return from_matrix(mats)


def read_times(path) -> np.ndarray:
    """One time per line (``#`` comments and blank lines skipped)."""
    out = []
    with open(path, encoding="utf-8-sig") as f:
        for line, text in enumerate(f, start=1):
            s = text.strip()
            if not s or s.startswith("#"):
                continue
            cells = s.split()
            if len(cells) != 1:
                raise TrajectoryError(f"{path}:{line}: expected one time, got {len(cells)} values")
            out.append(parse_float(path, line, 1, "time", cells[0]))
    return np.array(out)


def parse_rows(path, f, first_line: int = 1):
    """The careful parser: (values (N, 12), lines)."""
    rows, lines = [], []
    for line, text in enumerate(f, start=first_line):
        s = text.strip()
        if not s or s.startswith("#"):
            continue
        cells = s.split()
        if len(cells) != 12:
            raise TrajectoryError(
                f"{path}:{line}: expected 12 values (the 3×4 matrix [R | t] row by row), "
                f"got {len(cells)}"
            )
        rows.append([parse_float(path, line, c + 1, NAMES[c], v) for c, v in enumerate(cells)])
        lines.append(line)
    return rows, lines


def read(path, times=None, sort: bool = False, dedupe: bool = False) -> Trajectory:
    fast = _fast.table(path, "ws", 12)
    if fast is not None:
        try:
            return from_rows(path, fast, np.arange(1, len(fast) + 1), times, sort, dedupe)
        except TrajectoryError:
            pass  # the careful parser below gives the message with the file's line numbers
    with open(path, encoding="utf-8-sig") as f, _progress.reading(path) as bar:
        rows, lines = parse_rows(path, _progress.lines(f, bar))
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    return from_rows(path, np.array(rows), np.array(lines), times, sort, dedupe)


def from_rows(path, a: np.ndarray, lines, times, sort, dedupe) -> Trajectory:
    if not np.all(np.isfinite(a)):
        k = int(np.argmax(~np.all(np.isfinite(a), axis=1)))
        raise TrajectoryError(f"{path}:{lines[k]}: NaN or inf in this row")
    m = a.reshape(-1, 3, 4)
    quats = _matrices_to_quats(path, m[:, :, :3], lines)
    if times is None:
        t = np.arange(len(a), dtype=float)
    elif isinstance(times, (str, Path)):
        t = read_times(times)
        if len(t) != len(a):
            raise TrajectoryError(f"{times}: {len(t)} times for {len(a)} poses in {path}")
    else:
        t = np.asarray(times, dtype=float).reshape(-1)
        if len(t) != len(a):
            raise ValueError(f"times: expected {len(a)} times (one per pose), got {len(t)}")
    return finish(path, t, quats, m[:, :, 3], lines, sort, dedupe)


def write(path, traj: Trajectory, times_path=None) -> None:
    """Writes the poses (positions are required); ``times_path`` also writes the times."""
    from ..convert import as_matrix
    from ._common import check_for_writing

    if traj.positions is None:
        raise ValueError(f"{path}: KITTI poses need positions; this trajectory has none")
    check_for_writing(path, traj)  # NaN, no rows, repeated times: what the reader rejects
    m = np.concatenate([as_matrix(traj.quats), traj.positions[:, :, None]], axis=2)
    data = m.reshape(-1, 12)
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{path}: refusing to write NaN or inf")
    with atomic_write(path) as f:
        for row in data:
            f.write(" ".join(fmt(v) for v in row) + "\n")
    if times_path is not None:
        with atomic_write(times_path) as f:
            for t in traj.times:
                f.write(fmt(t) + "\n")
