"""What every reader and writer shares: opening only regular files, bounded lines, numbers as
files write them, and the checks before a trajectory is written. The record itself is
:mod:`quatspline.io.trajectory`."""

from __future__ import annotations

import os
import stat

import numpy as np

from .._util import progress_bars as _progress
from .._util.atomic import file_kind
from .trajectory import MIN_QUAT_NORM, Trajectory, TrajectoryError, quat_norms

#: Longest first line read while guessing a format.
MAX_SNIFF_LINE = 1 << 16

#: Longest line the text readers accept (characters, line end excluded). A trajectory row is
#: well under 1 KB; a longer line is refused as soon as this much of it has been read, before
#: it is split into cells (a 2 GB line of ``0 0 0 …`` would otherwise cost tens of GB).
MAX_LINE = 1 << 20


def _require_regular(path, mode: int) -> None:
    if not stat.S_ISREG(mode):
        raise TrajectoryError(f"{path}: is {file_kind(mode)}; only regular files are read")


def check_regular_input(path) -> None:
    """Refuses anything but a regular file (symbolic links are followed): a FIFO would block
    forever, a device such as /dev/zero would never end. The one check every input goes
    through: readers open their files with :func:`open_regular`, which makes it again on the
    opened descriptor; files a third-party library opens itself (bag storage files) are
    checked here just before."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise TrajectoryError(f"{path}: no such file") from None
    except OSError as e:
        raise TrajectoryError(f"{path}: cannot read ({e.strerror or e})") from None
    _require_regular(path, st.st_mode)


_OPEN_FLAGS = (
    os.O_RDONLY
    | getattr(os, "O_NONBLOCK", 0)
    | getattr(os, "O_NOCTTY", 0)
    | getattr(os, "O_CLOEXEC", 0)
    | getattr(os, "O_BINARY", 0)
)


def open_regular(path, mode: str = "r", **kwargs):
    """Opens ``path`` for reading if it is a regular file, else a one-line
    :class:`TrajectoryError` naming it.

    The path is checked before it is opened (a device is never opened), then opened without
    blocking (``O_NONBLOCK``: a FIFO put in its place in between cannot block the open) and
    checked again on the descriptor (``fstat``), which is what is read: a race cannot make
    the reader block on a FIFO or read a device. ``mode`` and ``kwargs`` as for
    :func:`open` (read modes only)."""
    if any(c in mode for c in "wax+"):
        raise ValueError(f"mode: open_regular reads only, got {mode!r}")
    check_regular_input(path)
    try:
        fd = os.open(path, _OPEN_FLAGS)
    except OSError as e:
        raise TrajectoryError(f"{path}: cannot read ({e.strerror or e})") from None
    try:
        _require_regular(path, os.fstat(fd).st_mode)
        if _OPEN_FLAGS & getattr(os, "O_NONBLOCK", 0):
            os.set_blocking(fd, True)
        return os.fdopen(fd, mode, **kwargs)
    except BaseException:
        os.close(fd)
        raise


def bounded_lines(f, path, first_line: int = 1):
    """The lines of the text file ``f`` (line ends kept), never reading more than
    :data:`MAX_LINE` characters of one line: a longer line is a one-line
    :class:`TrajectoryError` naming ``path`` and the line (``first_line`` is the number of the
    first line ``f`` yields)."""
    line = first_line
    while True:
        text = f.readline(MAX_LINE + 2)
        if not text:
            return
        check_line_length(path, line, text)
        yield text
        line += 1


def check_line_length(path, line: int, text: str, what: str = "line") -> None:
    """Refuses ``text``, read with ``readline(MAX_LINE + 2)``, when the line is longer than
    :data:`MAX_LINE` characters (then ``text`` is only its start)."""
    if len(text) > MAX_LINE and len(text.rstrip("\r\n")) > MAX_LINE:
        raise TrajectoryError(f"{path}:{line}: {what} longer than {MAX_LINE} characters")


def read_line(f, path, line: int) -> str:
    """One header line of ``f``, refused like :func:`bounded_lines` when too long."""
    text = f.readline(MAX_LINE + 2)
    check_line_length(path, line, text, "header line")
    return text


def plain_number(text: str) -> str:
    """``text`` unchanged if it may be a number as files write them; a ``ValueError`` for
    what Python's ``float``/``int`` accept beyond that: digit-group underscores (``1_0`` is
    10) and non-ASCII digits (Arabic-Indic ``١٢`` is 12, full-width ``１`` is 1)."""
    if "_" in text or not text.isascii():
        raise ValueError(f"not a plain number: {text[:40]!r}")
    return text


def parse_float(path, line: int, col: int, name: str, cell: str) -> float:
    try:
        return float(plain_number(cell))
    except ValueError:
        raise TrajectoryError(
            f"{path}:{line}: column {col} ({name!r}): not a number: {cell.strip()[:40]!r}"
        ) from None


def nanosecond_rows(f, path, header: str, columns: int, exact: bool, max_ns: int, limit: str):
    """The data rows of an EuRoC-style file (``#timestamp [ns],…`` header already read from
    ``f``): yields ``(line number, integer stamp, cells)`` for every non-blank line, with a
    progress bar. ``columns`` is the exact count if ``exact`` else the least; a stamp must be
    a plain integer with ``-max_ns ≤ ns < max_ns`` (``limit`` words it). Errors name the
    file, the line and the column."""
    with _progress.reading(path) as bar:
        for line, text in enumerate(
            _progress.lines(bounded_lines(f, path, 2), bar, len(header)), start=2
        ):
            s = text.strip()
            if not s:
                continue
            cells = s.split(",")
            if len(cells) < columns or (exact and len(cells) != columns):
                least = "" if exact else "at least "
                raise TrajectoryError(
                    f"{path}:{line}: expected {least}{columns} columns, got {len(cells)}"
                )
            try:
                ns = int(plain_number(cells[0]))
            except ValueError:
                raise TrajectoryError(
                    f"{path}:{line}: column 1 ('timestamp'): not an integer: "
                    f"{cells[0].strip()[:40]!r}"
                ) from None
            if not -max_ns <= ns < max_ns:
                raise TrajectoryError(
                    f"{path}:{line}: column 1 ('timestamp'): {len(str(abs(ns)))}-digit integer "
                    f"out of range ({limit})"
                )
            yield line, ns, cells


def check_for_writing(
    path, traj: Trajectory, *, needs_positions: str | None = None, reserved=()
) -> None:
    """Refuses, before anything is written, a trajectory the format's reader would reject:
    no rows, NaN or inf anywhere (times, quaternions, positions, extra columns), a quaternion
    of zero norm, times not strictly increasing; for ``needs_positions`` (the format's name),
    a trajectory without positions; extra columns named like ``reserved`` names or of the
    wrong length. Every message is one line naming the file."""
    if not isinstance(traj, Trajectory):
        raise TypeError(
            f"trajectory: expected a quatspline.io.Trajectory, got {type(traj).__name__}"
        )
    n = len(traj)
    if n == 0:
        raise ValueError(f"{path}: refusing to write a trajectory with no rows")
    if needs_positions and traj.positions is None:
        raise ValueError(
            f"{path}: the {needs_positions} format needs positions and this trajectory has none "
            "(write csv, json or npz instead)"
        )
    arrays = [("times", traj.times), ("quats", traj.quats)]
    if traj.positions is not None:
        arrays.append(("positions", traj.positions))
    for name, v in traj.extra.items():
        if not isinstance(name, str) or not name:
            raise ValueError(f"{path}: extra column name {name!r} is not a non-empty string")
        if name in reserved:
            raise ValueError(
                f"{path}: extra column {name!r} would collide with the format's own "
                f"{name!r}; rename it"
            )
        try:
            a = np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{path}: extra column {name!r} is not numeric") from None
        if a.ndim == 0 or len(a) != n:
            raise ValueError(
                f"{path}: extra column {name!r} has shape {a.shape}, expected ({n}, …)"
            )
        arrays.append((name, a))
    for name, a in arrays:
        finite = np.isfinite(a).reshape(n, -1).all(axis=1)
        if not finite.all():
            k = int(np.argmax(~finite))
            raise ValueError(f"{path}: refusing to write NaN or inf ({name}, row {k})")
    norm, _ = quat_norms(traj.quats)
    if np.any(norm < MIN_QUAT_NORM):
        k = int(np.argmax(norm < MIN_QUAT_NORM))
        raise ValueError(
            f"{path}: refusing to write a quaternion of (nearly) zero norm "
            f"{float(norm[k]):.3g} < {MIN_QUAT_NORM:g} at row {k} (the reader rejects it)"
        )
    t = np.asarray(traj.times, dtype=float)
    bad = t[1:] <= t[:-1]  # compared, not subtracted: no overflow for times near ±1.8e308
    if np.any(bad):
        k = int(np.argmax(bad)) + 1
        what = "duplicate" if t[k] == t[k - 1] else "decreasing"
        raise ValueError(
            f"{path}: refusing to write {what} time {float(traj.times[k])!r} at row {k} "
            "(the reader needs strictly increasing times)"
        )


def _name(key) -> str:
    """A column name as written in a one-line message (quoted when it holds odd characters)."""
    k = str(key)
    return k if k.isidentifier() else repr(k)


def refuse_extra(path, traj: Trajectory, fmt_name: str, positions: bool = True) -> None:
    """A format without columns for extra data (or positions) refuses it rather than
    dropping it silently."""
    if traj.extra:
        raise ValueError(
            f"{path}: the {fmt_name} format has no columns for {', '.join(map(_name, traj.extra))} "
            "(write csv, json or npz)"
        )
    if not positions and traj.positions is not None:
        raise ValueError(
            f"{path}: the {fmt_name} format has no columns for positions (write csv, json or npz)"
        )


def fmt(x: float) -> str:
    """Shortest round-trip representation."""
    return repr(float(x))
