"""JSON: ``{"times": [...], "quats": [[w, x, y, z], ...], "positions": [[x, y, z], ...]}``
(``positions`` optional; ``"layout": "xyzw"`` for scalar-last quaternions)."""

from __future__ import annotations

import json
import math

import numpy as np

from .._util.atomic import atomic_write
from ._common import check_for_writing, open_regular
from .trajectory import Trajectory, TrajectoryError, finish


def _parse_int(s: str) -> float:
    # JSON integers become floats here: a 401-digit integer is out of range, not an OverflowError
    x = float(s)
    if not math.isfinite(x):
        raise ValueError(f"integer of {len(s.lstrip('-'))} digits is out of range")
    return x


def _parse_float(s: str) -> float:
    x = float(s)
    if not math.isfinite(x):
        raise ValueError(f"number {s[:40]!r} is out of range")
    return x


def _numbers(path, key: str, value) -> np.ndarray:
    """``value`` (numbers in nested lists) as a float array. Anything else where a number
    belongs — a string such as ``"1"``, ``true``, ``null``, an object — is refused naming the
    key, rather than converted by numpy (``"1"`` → 1.0, ``true`` → 1.0, ``null`` → NaN)."""
    stack = [value]
    while stack:
        v = stack.pop()
        if isinstance(v, list):
            stack.extend(v)
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            kind = {bool: "a boolean", str: "a string", dict: "an object"}.get(type(v), "null")
            shown = json.dumps(v)[:40] if not isinstance(v, dict) else "{…}"
            raise TrajectoryError(f'{path}: "{key}" holds {kind} ({shown}) where numbers belong')
    return np.array(value, dtype=float)


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    with open_regular(path, encoding="utf-8-sig") as f:
        text = f.read()
    try:
        doc = json.loads(text, parse_int=_parse_int, parse_float=_parse_float)
    except json.JSONDecodeError as e:
        raise TrajectoryError(
            f"{path}:{e.lineno}: column {e.colno}: invalid JSON ({e.msg})"
        ) from None
    except ValueError as e:  # out-of-range numbers from the hooks above
        raise TrajectoryError(f"{path}: {e}") from None
    except RecursionError:  # the parser's guard against deep nesting
        raise TrajectoryError(f"{path}: JSON nested too deeply") from None
    if not isinstance(doc, dict) or "times" not in doc or "quats" not in doc:
        raise TrajectoryError(f'{path}: expected an object with "times" and "quats"')
    try:
        times = _numbers(path, "times", doc["times"])
        quats = _numbers(path, "quats", doc["quats"])
        pos = (
            _numbers(path, "positions", doc["positions"])
            if doc.get("positions") is not None
            else None
        )
    except TrajectoryError:
        raise
    except (TypeError, ValueError, RecursionError) as e:
        raise TrajectoryError(f"{path}: non-numeric or ragged values ({e})") from None
    if times.ndim != 1 or quats.shape != (len(times), 4):
        raise TrajectoryError(
            f"{path}: expected times (N,) and quats (N, 4), got {times.shape} and {quats.shape}"
        )
    if pos is not None and pos.shape != (len(times), 3):
        raise TrajectoryError(f"{path}: expected positions ({len(times)}, 3), got {pos.shape}")
    layout = doc.get("layout", "wxyz")
    if layout == "xyzw":
        quats = quats[:, [3, 0, 1, 2]]
    elif layout != "wxyz":
        raise TrajectoryError(f'{path}: "layout" must be "wxyz" or "xyzw", got {layout!r}')
    lines = np.arange(len(times))  # entry index, not a line
    return finish(path, times, quats, pos, lines, sort, dedupe)


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj, reserved=("layout", "times", "quats", "positions"))
    doc = {"layout": "wxyz", "times": traj.times.tolist(), "quats": traj.quats.tolist()}
    if traj.positions is not None:
        doc["positions"] = traj.positions.tolist()
    for k, v in traj.extra.items():
        doc[k] = np.asarray(v).tolist()
    if not all(
        np.all(np.isfinite(np.asarray(v, dtype=float))) for k, v in doc.items() if k != "layout"
    ):
        raise ValueError(f"{path}: refusing to write NaN or inf")
    with atomic_write(path) as f:
        json.dump(doc, f)
