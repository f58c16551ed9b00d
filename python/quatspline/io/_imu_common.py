"""What the IMU readers and writers share: the checks on what a reader parsed (finite samples,
strictly increasing times, named by file and line) and on a record before it is written."""

from __future__ import annotations

import numpy as np

from .inertial import ImuData
from .trajectory import TrajectoryError

#: The sample groups a text IMU format may leave empty in every row.
OPTIONAL_GROUP = "the {what} columns are empty in some rows and filled in others"


def finish_imu(
    path,
    times,
    gyro,
    accel=None,
    lines=None,
    sort: bool = False,
    dedupe: bool = False,
    *,
    name: str = "",
    stamps_ns=None,
    extra=None,
) -> ImuData:
    """Validates what an IMU reader parsed and builds the record: no rows, NaN or inf
    (naming the file line of the row), times not strictly increasing (or sorted /
    de-duplicated on request, keeping the first of equal times). ``lines`` gives the file
    line of each row; ``extra`` maps names to arrays with one row per sample."""
    times = np.asarray(times, dtype=float)
    n = len(times)
    if n == 0:
        raise TrajectoryError(f"{path}: no data rows")
    lines = np.arange(1, n + 1) if lines is None else np.asarray(lines)
    gyro = np.asarray(gyro, dtype=float).reshape(n, 3)
    accel = None if accel is None else np.asarray(accel, dtype=float).reshape(n, 3)
    extra = {k: np.asarray(v, dtype=float).reshape(n, -1) for k, v in (extra or {}).items()}
    ns = None if stamps_ns is None else np.asarray(stamps_ns, dtype=np.int64)
    bad = ~np.isfinite(times) | ~np.all(np.isfinite(gyro), axis=1)
    for a in [accel, *extra.values()]:
        if a is not None:
            bad |= ~np.all(np.isfinite(a), axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise TrajectoryError(f"{path}:{lines[k]}: NaN or inf in this row")
    keep = None
    if sort:
        keep = np.argsort(times, kind="stable")
    if dedupe:
        t = times if keep is None else times[keep]
        first = np.concatenate([[True], np.diff(t) != 0])
        keep = (np.arange(n) if keep is None else keep)[first]
    if keep is not None:
        times, gyro, lines = times[keep], gyro[keep], lines[keep]
        accel = None if accel is None else accel[keep]
        ns = None if ns is None else ns[keep]
        extra = {k: v[keep] for k, v in extra.items()}
    dt = np.diff(times)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0)) + 1
        if ns is not None and ns[k] > ns[k - 1]:
            res = float(np.spacing(abs(times[k]))) * 1e9
            raise TrajectoryError(
                f"{path}:{lines[k]}: stamps {int(ns[k - 1])} and {int(ns[k])} ns are "
                f"{int(ns[k] - ns[k - 1])} ns apart, closer than float64 seconds resolve at "
                f"this time ({res:.3g} ns); use dedupe=True to drop such rows"
            )
        what = "duplicate" if dt[k - 1] == 0 else "decreasing"
        raise TrajectoryError(
            f"{path}:{lines[k]}: {what} timestamp {float(times[k])!r} after "
            f"{float(times[k - 1])!r} (use sort=True / dedupe=True)"
        )
    return ImuData(times, gyro, accel, stamps_ns=ns, name=name, extra=extra)


def check_imu_for_writing(path, data, fmt_name: str, extra=()) -> None:
    """Refuses, before anything is written, a record the format's reader would reject or
    whose content the format cannot hold: not an :class:`ImuData`, no rows, NaN or inf,
    times not strictly increasing, true biases (no IMU file format has columns for them) or
    ``extra`` entries other than the format's own ``extra`` names (each of shape (N, k))."""
    if not isinstance(data, ImuData):
        raise TypeError(f"data: expected a quatspline.io.ImuData, got {type(data).__name__}")
    n = len(data)
    if n == 0:
        raise ValueError(f"{path}: refusing to write an IMU record with no rows")
    biases = [b for b in ("gyro_bias", "accel_bias") if getattr(data, b) is not None]
    if biases:
        raise ValueError(
            f"{path}: the {fmt_name} format has no columns for {' and '.join(biases)}; set "
            "them to None to write the measurements only"
        )
    unknown = [k for k in data.extra if k not in extra]
    if unknown:
        has = f" (it holds {', '.join(extra)})" if extra else ""
        raise ValueError(
            f"{path}: the {fmt_name} format has no columns for extra "
            f"{', '.join(map(repr, unknown))}{has}"
        )
    arrays = [("times", data.times), ("gyro", data.gyro)]
    if data.accel is not None:
        arrays.append(("accel", data.accel))
    for k in extra:
        if k in data.extra:
            a = np.asarray(data.extra[k], dtype=float)
            if a.shape[:1] != (n,):
                raise ValueError(f"{path}: extra {k!r} has shape {a.shape}, expected ({n}, …)")
            arrays.append((k, a))
    for name, a in arrays:
        a = np.asarray(a, dtype=float)
        if a.shape[:1] != (n,):
            raise ValueError(f"{path}: {name} has shape {a.shape}, expected ({n}, …)")
        finite = np.isfinite(a).reshape(n, -1).all(axis=1)
        if not finite.all():
            k = int(np.argmax(~finite))
            raise ValueError(f"{path}: refusing to write NaN or inf ({name}, row {k})")
    t = np.asarray(data.times, dtype=float)
    bad = t[1:] <= t[:-1]
    if np.any(bad):
        k = int(np.argmax(bad)) + 1
        raise ValueError(
            f"{path}: refusing to write times not strictly increasing at row {k} "
            "(the reader needs strictly increasing times)"
        )


def integer_stamps(path, data, fmt_name: str) -> np.ndarray:
    """The record's integer nanosecond stamps: ``stamps_ns`` when it kept them (checked
    against ``times``), else the times rounded to the nanosecond; stamps that round to the
    same nanosecond are refused (the reader needs strictly increasing times)."""
    t = np.asarray(data.times, dtype=float)
    if np.max(np.abs(t)) > 9.2e9:
        raise ValueError(
            f"{path}: times beyond ±9.2e9 s cannot be written as 64-bit integer nanoseconds"
        )
    if data.stamps_ns is not None:
        ns = np.asarray(data.stamps_ns, dtype=np.int64)
        off = np.abs(ns * 1e-9 - t) > 1e-6 * np.maximum(1.0, np.abs(t))
        if np.any(off):  # stamps kept from a file but times changed since
            k = int(np.argmax(off))
            raise ValueError(
                f"{path}: stamps_ns[{k}] = {int(ns[k])} disagrees with times[{k}] = "
                f"{float(t[k])!r}; set stamps_ns=None to write the times"
            )
    else:
        ns = np.round(t * 1e9).astype(np.int64)
    dup = np.diff(ns) <= 0
    if np.any(dup):
        k = int(np.argmax(dup)) + 1
        raise ValueError(
            f"{path}: times at rows {k - 1} and {k} round to the same nanosecond; the "
            f"{fmt_name} format stores integer nanoseconds"
        )
    return ns


def group(path, line: int, cells, first: int, names, groups_seen: dict, what: str, parse):
    """The numbers of the columns ``first … first + len(names) - 1`` (1-based column numbers
    in messages), or None when they are all empty. A group is filled in every row or empty
    in every row (``groups_seen`` remembers which); a mix is a one-line error."""
    part = cells[first - 1 : first - 1 + len(names)]
    empty = all(not c.strip() for c in part)
    seen = groups_seen.setdefault(what, empty)
    if seen != empty:
        raise TrajectoryError(f"{path}:{line}: " + OPTIONAL_GROUP.format(what=what))
    if empty:
        return None
    return [parse(path, line, first + i, names[i], c) for i, c in enumerate(part)]
