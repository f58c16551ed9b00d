"""KITTI odometry poses: one pose per line, the 12 values of the 3×4 matrix [R | t] in row
order, whitespace separated (``poses/00.txt``). KITTI has no time column: times come from a
separate file with one time per line (``sequences/00/times.txt``) given as ``times=``, or are
the frame numbers 0, 1, 2, … when it is left out.

The 3×3 blocks must be rotations: orthonormal within :data:`ORTHONORMAL_TOL` (the largest
entry of |RᵀR − I|; a file printed with 4 significant digits is within about 1e-4) and with a
positive determinant, else the reader names the file and line. The writer writes poses and
times as a pair (both old or both new after a kill, see
:func:`quatspline._util.atomic.atomic_write_pair`), and refuses what the format cannot hold: times
other than 0, 1, 2, … without a times file, and extra columns."""

from __future__ import annotations

import os
from array import array
from pathlib import Path

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write, atomic_write_pair, committed_pair
from ..core.convert import as_matrix, from_matrix
from ._common import bounded_lines, check_for_writing, fmt, open_regular, parse_float, refuse_extra
from ._fast import table as fast_table
from .trajectory import Trajectory, TrajectoryError, finish

#: Largest entry of |RᵀR − I| accepted in a 3×3 block: real KITTI files print 6–9
#: significant digits (|RᵀR − I| ≲ 1e-6); 1e-3 also admits files printed with 4 digits and
#: refuses shears, scalings and other non-rotations.
ORTHONORMAL_TOL = 1e-3

NAMES = ("r11", "r12", "r13", "tx", "r21", "r22", "r23", "ty", "r31", "r32", "r33", "tz")


def _matrices_to_quats(path, mats: np.ndarray, lines) -> np.ndarray:
    eye = np.eye(3)
    off = np.max(np.abs(np.einsum("nji,njk->nik", mats, mats) - eye), axis=(1, 2))
    det = np.linalg.det(mats)
    bad = ~(off <= ORTHONORMAL_TOL) | ~(det > 0)
    if np.any(bad):
        k = int(np.argmax(bad))
        why = (
            f"|RᵀR − I| reaches {off[k]:.3g} > {ORTHONORMAL_TOL:g}"
            if not off[k] <= ORTHONORMAL_TOL
            else f"determinant {det[k]:.6g}: a reflection"
        )
        raise TrajectoryError(f"{path}:{lines[k]}: the 3×3 block is not a rotation ({why})")
    return from_matrix(mats)


def read_times(path) -> np.ndarray:
    """One time per line (``#`` comments and blank lines skipped)."""
    out = array("d")
    with open_regular(path, encoding="utf-8-sig") as f:
        for line, text in enumerate(bounded_lines(f, path), start=1):
            s = text.strip()
            if not s or s.startswith("#"):
                continue
            cells = s.split()
            if len(cells) != 1:
                raise TrajectoryError(f"{path}:{line}: expected one time, got {len(cells)} values")
            out.append(parse_float(path, line, 1, "time", cells[0]))
    return np.array(out, dtype=float)


def parse_rows(path, f, first_line: int = 1):
    """The careful parser: (values (N·12,) as an ``array("d")``, lines): 8 bytes a value, not
    a Python float each (a file with a bad last row is parsed whole before it is refused)."""
    rows, lines = array("d"), array("q")
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
        rows.extend([parse_float(path, line, c + 1, NAMES[c], v) for c, v in enumerate(cells)])
        lines.append(line)
    return rows, lines


def read(path, times=None, sort: bool = False, dedupe: bool = False) -> Trajectory:
    pending = committed_pair(path)  # a pair write interrupted after its commit point
    if pending:  # read the new pair it committed (both new), not a mix
        if isinstance(times, (str, Path)):
            times = pending.get(Path(os.path.realpath(times)), times)
        path = pending.get(Path(os.path.realpath(path)), path)
    fast = fast_table(path, "ws", 12)
    if fast is not None:
        try:
            return from_rows(path, fast, np.arange(1, len(fast) + 1), times, sort, dedupe)
        except TrajectoryError:
            pass  # the careful parser below gives the message with the file's line numbers
    with open_regular(path, encoding="utf-8-sig") as f, _progress.reading(path) as bar:
        rows, lines = parse_rows(path, _progress.lines(bounded_lines(f, path), bar))
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows, dtype=float).reshape(-1, 12)
    return from_rows(path, a, np.asarray(lines), times, sort, dedupe)


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
    """Writes the poses (positions are required) and, with ``times_path``, the times file.

    The two files are replaced as a pair (both old or both new after a kill at any point,
    as :func:`quatspline._util.atomic.atomic_write_pair` states). Without ``times_path`` the times
    must be the frame numbers 0, 1, 2, … that the reader assumes without a times file;
    other times, and extra columns, are refused (one line) rather than lost."""

    if traj.positions is None:
        raise ValueError(f"{path}: KITTI poses need positions; this trajectory has none")
    check_for_writing(path, traj)  # NaN, no rows, repeated times: what the reader rejects
    refuse_extra(path, traj, "KITTI")
    if times_path is None and not np.array_equal(traj.times, np.arange(len(traj))):
        raise ValueError(
            f"{path}: KITTI poses hold no times and these are not the frame numbers 0, 1, 2, … "
            "read without a times file; give times_path= to write them (or write tum or csv)"
        )
    m = np.concatenate([as_matrix(traj.quats), traj.positions[:, :, None]], axis=2)
    data = m.reshape(-1, 12)
    if times_path is None:
        with atomic_write(path) as f:
            _write_rows(f, data)
        return
    with atomic_write_pair(path, times_path) as (f, g):
        _write_rows(f, data)
        for t in traj.times:
            g.write(fmt(t) + "\n")


def _write_rows(f, data: np.ndarray) -> None:
    for row in data:
        f.write(" ".join(fmt(v) for v in row) + "\n")
