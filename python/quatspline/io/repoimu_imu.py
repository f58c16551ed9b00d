"""RepoIMU CSV, IMU columns: ``;``-separated, two header rows, 14 columns per row —
time [s]; Vicon orientation W X Y Z; IMU accelerometer X Y Z [m/s²]; gyroscope X Y Z [rad/s];
magnetometer X Y Z (units as recorded).

The reader returns the gyroscope and accelerometer as an :class:`ImuData`, with the Vicon
orientation (scalar first, as recorded) in ``extra["orientation"]`` and the magnetometer in
``extra["mag"]``; the writer writes them back from there. The orientation, accelerometer
and magnetometer groups may each be empty in every row (the writer leaves the cells of what
the record does not hold empty; the pose reader, :mod:`quatspline.io.repoimu`, needs the
orientation); a group filled in some rows and empty in others is an error."""

from __future__ import annotations

from array import array
from pathlib import Path

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write
from ._common import bounded_lines, open_regular, parse_float, read_line
from ._fast import table as fast_table
from ._imu_common import check_imu_for_writing, finish_imu, group
from .inertial import ImuData
from .trajectory import TrajectoryError

#: column names (1-based column = index + 1)
NAMES = (
    "time",
    *("W", "X", "Y", "Z"),
    *("acc X", "acc Y", "acc Z"),
    *("gyro X", "gyro Y", "gyro Z"),
    *("mag X", "mag Y", "mag Z"),
)
HEADER = (
    "Time (s);Vicon Orientation;;;;IMU Acceleration;;;IMU Gyroscope;;;IMU Magnetometer;;;\n"
    ";W;X;Y;Z;X;Y;Z;X;Y;Z;X;Y;Z;\n"
)
#: the optional groups: extra name (or "accel"), first column, width, name in messages
GROUPS = (("orientation", 2, 4, "orientation"), ("accel", 6, 3, "accelerometer"),
          ("mag", 12, 3, "magnetometer"))  # fmt: skip


def read(path, sort: bool = False, dedupe: bool = False) -> ImuData:
    """Reads the IMU columns of a RepoIMU CSV; see the module."""
    rows, lines = array("d"), array("q")
    seen: dict = {}
    with open_regular(path, encoding="utf-8-sig") as f:
        first = read_line(f, path, 1)
        if not first.startswith("Time (s);Vicon Orientation"):
            raise TrajectoryError(f"{path}:1: bad header: not a RepoIMU file")
        second = read_line(f, path, 2)
        fast = fast_table(path, ";", 14, skip=2)
        if fast is not None:
            try:
                return _finish(path, fast, None, sort, dedupe, {})
            except TrajectoryError:
                pass  # the careful parser below gives the message with the file's line numbers
        with _progress.reading(path) as bar:
            header = len(first) + len(second)
            for line, text in enumerate(
                _progress.lines(bounded_lines(f, path, 3), bar, header), start=3
            ):
                s = text.strip()
                if not s:
                    continue
                cells = s.split(";")
                if len(cells) == 15 and not cells[14].strip():
                    cells = cells[:14]  # a trailing separator, as on the header rows
                if len(cells) != 14:
                    raise TrajectoryError(
                        f"{path}:{line}: expected 14 columns (time; Vicon W X Y Z; acc X Y Z; "
                        f"gyro X Y Z; mag X Y Z), got {len(cells)}"
                    )
                row = [parse_float(path, line, 1, "time", cells[0])]
                row += [parse_float(path, line, c, NAMES[c - 1], cells[c - 1]) for c in (9, 10, 11)]
                for _, col, width, what in GROUPS:
                    names = NAMES[col - 1 : col - 1 + width]
                    vals = group(path, line, cells, col, names, seen, what, parse_float)
                    row += vals if vals is not None else [0.0] * width
                rows.extend(row)
                lines.append(line)
    if not lines:
        raise TrajectoryError(f"{path}: no data rows")
    a = np.array(rows, dtype=float).reshape(-1, 14)
    # back to the file's column order: time, W X Y Z, acc, gyro, mag
    table = np.concatenate([a[:, 0:1], a[:, 4:8], a[:, 8:11], a[:, 1:4], a[:, 11:14]], axis=1)
    return _finish(path, table, np.asarray(lines), sort, dedupe, seen)


def _finish(path, a, lines, sort, dedupe, empty) -> ImuData:
    """The record from the 14 columns ``a`` (``empty``: group → whether it was empty)."""
    extra = {}
    if not empty.get("orientation"):
        extra["orientation"] = a[:, 1:5]
    if not empty.get("magnetometer"):
        extra["mag"] = a[:, 11:14]
    accel = None if empty.get("accelerometer") else a[:, 5:8]
    return finish_imu(
        path, a[:, 0], a[:, 8:11], accel, lines, sort, dedupe, name=Path(path).name, extra=extra
    )


def write(path, data: ImuData) -> None:
    """Writes a RepoIMU CSV atomically; see the module."""
    check_imu_for_writing(path, data, "RepoIMU", extra=("orientation", "mag"))
    n = len(data)
    parts = {"orientation": 4, "mag": 3}
    cols = {}
    for name, width in parts.items():
        if name in data.extra:
            a = np.asarray(data.extra[name], dtype=float)
            if a.shape != (n, width):
                raise ValueError(
                    f"{path}: extra {name!r} has shape {a.shape}, expected ({n}, {width})"
                )
            cols[name] = a
    with atomic_write(path) as f:
        f.write(HEADER)
        for k in range(n):
            cells = [_num(data.times[k])]
            cells += _cells(cols.get("orientation"), k, 4)
            cells += _cells(data.accel, k, 3)
            cells += _cells(data.gyro, k, 3)
            cells += _cells(cols.get("mag"), k, 3)
            f.write(";".join(cells) + "\n")


def _cells(a, k: int, width: int) -> list[str]:
    return [""] * width if a is None else [_num(v) for v in a[k]]


def _num(x) -> str:
    return repr(float(x))
