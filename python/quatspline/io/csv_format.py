"""CSV with a header row: a time column and quaternion (or Euler angle) columns, optional
positions. Column names are matched case-insensitively, with '#', spaces and units in
brackets ignored:

- time: ``t``, ``time``, ``timestamp``, ``times``, ``sec``, ``seconds``;
- quaternion: ``qw qx qy qz`` or ``w x y z`` (any column order: scalar-last files such as
  ``t,qx,qy,qz,qw`` are read correctly);
- Euler angles (with ``euler="xyz"`` etc., ``degrees=True`` for degrees): ``roll pitch yaw``,
  ``rx ry rz``, ``e1 e2 e3`` or ``a1 a2 a3``;
- positions (optional): ``x y z`` (when the quaternion is ``qw…``), ``tx ty tz``, ``px py pz``.

Delimiter: ``,``, ``;`` or tab, from the header. A UTF-8 BOM and CRLF line ends are fine.
"""

from __future__ import annotations

import csv
from array import array

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write
from ..core.convert import from_euler
from ._columns import EULER, POSITIONS, QUATS, TIME, clean, find, positions_for
from ._common import bounded_lines, check_for_writing, fmt, open_regular, parse_float, read_line
from ._fast import table as fast_table
from .trajectory import Trajectory, TrajectoryError, finish


def read(
    path,
    euler: str | None = None,
    degrees: bool = False,
    sort: bool = False,
    dedupe: bool = False,
) -> Trajectory:
    with open_regular(path, encoding="utf-8-sig", newline="") as f:
        header_line = read_line(f, path, 1)
        if not header_line.strip():
            raise TrajectoryError(f"{path}:1: empty file or empty header")
        delim = max((",", ";", "\t"), key=header_line.count)
        header = next(csv.reader([header_line], delimiter=delim))
        names = [clean(h) for h in header]
        ti = next((names.index(n) for n in TIME if n in names), None)
        if ti is None:
            raise TrajectoryError(
                f"{path}:1: bad header: no time column (expected one of {', '.join(TIME)}); "
                f"got {', '.join(header)}"
            )
        if euler is not None:
            qi = find(names, EULER)
            if qi is None:
                raise TrajectoryError(
                    f"{path}:1: bad header: --euler needs angle columns "
                    f"({'; '.join(' '.join(g) for g in EULER)})"
                )
        else:
            qi = find(names, QUATS)
            if qi is None:
                raise TrajectoryError(
                    f"{path}:1: bad header: no quaternion columns (qw qx qy qz or w x y z), "
                    "and no --euler SEQ given for angle columns"
                )
        pi = find(names, positions_for(names, qi))
        ncol = len(header)
        fast = fast_table(path, delim, ncol, skip=1)
        if fast is not None:
            out = _from_fast(path, fast, ti, qi, pi, euler, degrees, sort, dedupe)
            if out is not None:
                return out
        # 8 bytes a value, not a Python float each (a bad last row is found after the rest)
        times, rows, pos, lines = array("d"), array("d"), array("d"), array("q")
        with _progress.reading(path) as bar:
            rows_in = bounded_lines(f, path, first_line=2)
            reader = csv.reader(_progress.lines(rows_in, bar, len(header_line)), delimiter=delim)
            try:
                for row in reader:
                    line = reader.line_num + 1
                    if not row or all(not c.strip() for c in row):
                        continue
                    if len(row) != ncol:
                        raise TrajectoryError(
                            f"{path}:{line}: expected {ncol} columns (as the header), "
                            f"got {len(row)}"
                        )
                    times.append(parse_float(path, line, ti + 1, header[ti], row[ti]))
                    rows.extend([parse_float(path, line, c + 1, header[c], row[c]) for c in qi])
                    if pi is not None:
                        pos.extend([parse_float(path, line, c + 1, header[c], row[c]) for c in pi])
                    lines.append(line)
            except csv.Error as e:
                raise TrajectoryError(f"{path}:{reader.line_num + 1}: {e}") from None
    if not rows:
        raise TrajectoryError(f"{path}: no data rows")
    values = np.array(rows, dtype=float).reshape(-1, len(qi))
    if euler is not None:
        try:
            quats = from_euler(euler, values, degrees=degrees)
        except ValueError as e:
            bad = ~np.all(np.isfinite(values), axis=1)
            if np.any(bad):
                raise TrajectoryError(f"{path}:{lines[int(np.argmax(bad))]}: NaN or inf") from None
            raise TrajectoryError(f"{path}: {e}") from None
    else:
        quats = values
    positions = np.array(pos, dtype=float).reshape(-1, 3) if pi is not None else None
    times = np.array(times, dtype=float)
    return finish(path, times, quats, positions, np.asarray(lines), sort, dedupe)


#: Characters a written column name may not hold (delimiters, quotes, line ends, the unit
#: brackets and comment mark the reader strips).
BAD_NAME_CHARS = set(',;\t"\r\n[]#')
RESERVED = {
    n for g in (TIME, *QUATS, *EULER, *POSITIONS) for n in ((g,) if isinstance(g, str) else g)
}


def _column_names(path, name: str, width: int) -> list[str]:
    bad = sorted(set(name) & BAD_NAME_CHARS)
    if bad or name != name.strip() or not name.isprintable():
        raise ValueError(
            f"{path}: extra column name {name!r} cannot be written to CSV "
            f"(no {', '.join(map(repr, bad)) or 'control characters or surrounding spaces'})"
        )
    if width == 1:
        return [name]
    return [f"{name}_{k}" for k in "xyz"] if width == 3 else [f"{name}_{k}" for k in range(width)]


def _from_fast(path, a, ti, qi, pi, euler, degrees, sort, dedupe):
    """The fast path's table through the same checks; None sends the caller to the careful
    parser (for its messages with line numbers)."""
    try:
        if euler is not None:
            quats = from_euler(euler, a[:, list(qi)], degrees=degrees)
        else:
            quats = a[:, list(qi)]
        pos = a[:, list(pi)] if pi is not None else None
        return finish(path, a[:, ti], quats, pos, None, sort, dedupe)
    except ValueError:
        return None


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj)
    cols = ["t", "qw", "qx", "qy", "qz"]
    blocks = [traj.times[:, None], traj.quats]
    if traj.positions is not None:
        cols += ["x", "y", "z"]
        blocks.append(traj.positions)
    for name, arr in traj.extra.items():
        a = np.asarray(arr, dtype=float).reshape(len(traj), -1)
        cols += _column_names(path, name, a.shape[1])
        blocks.append(a)
    seen = set()
    for c in cols[5 + 3 * (traj.positions is not None) :]:
        key = clean(c)
        if key in RESERVED or key in seen:
            raise ValueError(
                f"{path}: extra column {c!r} would be read as (or collide with) a time, "
                "quaternion, angle or position column; rename it"
            )
        seen.add(key)
    data = np.hstack(blocks)
    with atomic_write(path, newline="") as f:
        f.write(",".join(cols) + "\n")
        for row in data:
            f.write(",".join(fmt(v) for v in row) + "\n")
