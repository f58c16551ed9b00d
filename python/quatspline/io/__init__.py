"""Trajectory files: CSV, JSON, NPZ, TUM, EuRoC, RepoIMU and BVH, read and written.

``read(path, format=None, **options)`` returns a :class:`Trajectory` (times, unit quaternions
in (w, x, y, z) order, optional positions); ``write(path, trajectory, format=None)`` writes
one atomically (temporary file in the target directory, renamed on success). The format is
taken from ``format`` or guessed from the extension and the first line. Every error is a
``ValueError`` naming the file, and where it applies the line and column.
"""

from __future__ import annotations

from pathlib import Path

from . import bvh, csv_format, euroc, json_format, npz_format, repoimu, tum
from ._common import Trajectory, TrajectoryError

__all__ = ["FORMATS", "Trajectory", "TrajectoryError", "detect_format", "read", "write"]

FORMATS = {
    "csv": csv_format,
    "json": json_format,
    "npz": npz_format,
    "tum": tum,
    "euroc": euroc,
    "repoimu": repoimu,
    "bvh": bvh,
}


def detect_format(path) -> str:
    """The format of ``path`` from its extension and, for .csv/.txt, its first line."""
    p = Path(path)
    ext = p.suffix.lower()
    if ext in (".json", ".npz", ".bvh"):
        return ext[1:]
    if ext == ".tum":
        return "tum"
    first = ""
    if p.exists():
        with open(p, encoding="utf-8-sig", errors="replace") as f:
            first = f.readline()
    if first.startswith("#timestamp") and "q_RS_w" in first:
        return "euroc"
    if first.startswith("Time (s);Vicon Orientation"):
        return "repoimu"
    if ext == ".txt":
        return "tum"
    return "csv"


def read(path, format: str | None = None, **options) -> Trajectory:
    """Reads a trajectory. Options depend on the format (see each module)."""
    fmt = format or detect_format(path)
    if fmt not in FORMATS:
        raise ValueError(f"format: unknown format {fmt!r}; valid: {', '.join(FORMATS)}")
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"{path}: no such file")
    try:
        return FORMATS[fmt].read(p, **options)
    except OSError as e:
        raise ValueError(f"{path}: cannot read ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not a text file ({e.reason} at byte {e.start})") from None


def write(path, trajectory: Trajectory, format: str | None = None, **options) -> None:
    """Writes a trajectory atomically; ``format`` defaults to the one of the extension."""
    fmt = format or detect_format_for_writing(path)
    if fmt not in FORMATS:
        raise ValueError(f"format: unknown format {fmt!r}; valid: {', '.join(FORMATS)}")
    FORMATS[fmt].write(Path(path), trajectory, **options)


def detect_format_for_writing(path) -> str:
    ext = Path(path).suffix.lower()
    return {".json": "json", ".npz": "npz", ".bvh": "bvh", ".txt": "tum", ".tum": "tum"}.get(
        ext, "csv"
    )
