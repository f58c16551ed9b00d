"""EuRoC MAV / TUM-VI IMU files (``mav0/imu0/data.csv``):
``#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y,w_RS_S_z,a_RS_S_x [m s^-2],a_RS_S_y,a_RS_S_z``.

Exactly seven columns: the integer nanosecond stamp, the angular rate (rad/s) and the specific
force (m/s²) in the sensor frame S. Times are returned in seconds as in the file (ns / 1e9,
absolute, like the EuRoC pose reader) and kept exactly as int64 nanoseconds in
``ImuData.stamps_ns``, which the writer uses. A gyroscope-only record is written with the
three accelerometer cells of every row empty, and read back as such (a row with some of
them empty among rows with all of them filled is an error)."""

from __future__ import annotations

from array import array
from pathlib import Path

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import atomic_write
from ._common import bounded_lines, open_regular, parse_float, plain_number, read_line
from ._fast import table as fast_table
from ._imu_common import check_imu_for_writing, finish_imu, group, integer_stamps
from .inertial import ImuData
from .trajectory import TrajectoryError

NAMES = ("timestamp", "w_RS_S_x", "w_RS_S_y", "w_RS_S_z", "a_RS_S_x", "a_RS_S_y", "a_RS_S_z")
HEADER = (
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
)


def _check_header(path, header: str) -> None:
    if not header.startswith("#"):
        raise TrajectoryError(
            f"{path}:1: bad header: expected '#timestamp [ns],w_RS_S_x [rad s^-1],…'"
        )
    names = [c.split("[")[0].strip().lstrip("#").strip() for c in header.strip().split(",")]
    if len(names) != 7:
        raise TrajectoryError(
            f"{path}:1: the header names {len(names)} columns; an EuRoC IMU file has 7 "
            "(timestamp, w_RS_S_x y z, a_RS_S_x y z)"
        )
    for col, expected in ((2, "w_RS_S_x"), (5, "a_RS_S_x")):
        other = "a_RS_S_x" if expected == "w_RS_S_x" else "w_RS_S_x"
        if names[col - 1] == other:
            raise TrajectoryError(
                f"{path}:1: column {col} is {other!r}; the EuRoC IMU order is timestamp, "
                "w_RS_S_x y z (rad/s), a_RS_S_x y z (m/s²)"
            )


def read(path, sort: bool = False, dedupe: bool = False) -> ImuData:
    """Reads an EuRoC ``imu0/data.csv``; see the module."""
    rows, lines, stamps = array("d"), array("q"), []
    groups: dict = {}
    with open_regular(path, encoding="utf-8-sig") as f:
        header = read_line(f, path, 1)
        _check_header(path, header)
        fast = fast_table(path, ",", 7, skip=1, int_first=True)
        if fast is not None:
            ns, a = fast
            try:
                return finish_imu(
                    path,
                    ns * 1e-9,
                    a[:, 0:3],
                    a[:, 3:6],
                    None,
                    sort,
                    dedupe,
                    stamps_ns=ns,
                    name=Path(path).name,
                )
            except TrajectoryError:
                pass  # the careful parser below gives the message with the file's line numbers
        with _progress.reading(path) as bar:
            for line, text in enumerate(
                _progress.lines(bounded_lines(f, path, 2), bar, len(header)), start=2
            ):
                s = text.strip()
                if not s:
                    continue
                cells = s.split(",")
                if len(cells) != 7:
                    raise TrajectoryError(f"{path}:{line}: expected 7 columns, got {len(cells)}")
                try:
                    ns = int(plain_number(cells[0]))
                except ValueError:
                    raise TrajectoryError(
                        f"{path}:{line}: column 1 ('timestamp'): not an integer: "
                        f"{cells[0].strip()[:40]!r}"
                    ) from None
                if not -(2**63) <= ns < 2**63:
                    raise TrajectoryError(
                        f"{path}:{line}: column 1 ('timestamp'): {len(str(abs(ns)))}-digit "
                        "integer beyond 64-bit nanoseconds"
                    )
                gyro = [parse_float(path, line, c + 1, NAMES[c], cells[c]) for c in range(1, 4)]
                acc = group(path, line, cells, 5, NAMES[4:], groups, "accelerometer", parse_float)
                stamps.append(ns)
                rows.extend(gyro + (acc or [0.0, 0.0, 0.0]))
                lines.append(line)
    if not stamps:
        raise TrajectoryError(f"{path}: no data rows")
    ns = np.array(stamps, dtype=np.int64)
    a = np.array(rows, dtype=float).reshape(-1, 6)
    accel = None if groups.get("accelerometer") else a[:, 3:6]
    return finish_imu(
        path,
        ns * 1e-9,
        a[:, 0:3],
        accel,
        np.asarray(lines),
        sort,
        dedupe,
        stamps_ns=ns,
        name=Path(path).name,
    )


def write(path, data: ImuData) -> None:
    """Writes an EuRoC ``imu0/data.csv`` atomically; see the module."""
    check_imu_for_writing(path, data, "EuRoC IMU")
    ns = integer_stamps(path, data, "EuRoC IMU")
    accel = data.accel
    with atomic_write(path) as f:
        f.write(HEADER)
        for k, t in enumerate(ns):
            acc = ",,," if accel is None else "," + ",".join(map(_num, accel[k]))
            f.write(f"{int(t)}," + ",".join(map(_num, data.gyro[k])) + acc + "\n")


def _num(x) -> str:
    return repr(float(x))
