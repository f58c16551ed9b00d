"""Trajectory files: CSV, JSON, NPZ, TUM, EuRoC, RepoIMU, BVH, KITTI, glTF/GLB and ROS bags
(ROS 1, ROS 2, MCAP), read and written.

``read(path, format=None, **options)`` returns a :class:`Trajectory` (times, unit quaternions
in (w, x, y, z) order, optional positions); ``write(path, trajectory, format=None)`` writes
one atomically (temporary file in the target directory, renamed on success). The format is
taken from ``format`` or guessed from the extension and the first line. Every error is a
``ValueError`` naming the file, and where it applies the line and column.
"""

from __future__ import annotations

from pathlib import Path

from . import bvh, csv_format, euroc, gltf, json_format, kitti, npz_format, repoimu, rosbag, tum
from ._common import Trajectory, TrajectoryError
from .evo_bridge import from_evo, to_evo
from .pandas_bridge import from_dataframe, to_dataframe

__all__ = [
    "FORMATS",
    "Trajectory",
    "TrajectoryError",
    "detect_format",
    "from_dataframe",
    "from_evo",
    "read",
    "to_dataframe",
    "to_evo",
    "write",
]

FORMATS = {
    "csv": csv_format,
    "json": json_format,
    "npz": npz_format,
    "tum": tum,
    "euroc": euroc,
    "repoimu": repoimu,
    "bvh": bvh,
    "kitti": kitti,
    "gltf": gltf,
    "rosbag": rosbag,
}


def detect_format(path) -> str:
    """The format of ``path`` from its extension and, for .csv/.txt, its first line."""
    p = Path(path)
    ext = p.suffix.lower()
    if rosbag.is_bag(p):
        return "rosbag"
    if ext in (".gltf", ".glb"):
        return "gltf"
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
        return "kitti" if _kitti_like(p) else "tum"
    return "csv"


def read(path, format: str | None = None, **options) -> Trajectory:
    """Reads a trajectory. Options depend on the format (see each module)."""
    fmt = format or detect_format(path)
    if fmt not in FORMATS:
        raise ValueError(f"format: unknown format {fmt!r}; valid: {', '.join(FORMATS)}")
    p = Path(path)
    if not (p.is_file() or (fmt == "rosbag" and p.is_dir())):
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
    more = {".glb": "gltf", ".gltf": "gltf", ".bag": "rosbag", ".mcap": "rosbag"}
    if ext in more:
        return more[ext]
    return {".json": "json", ".npz": "npz", ".bvh": "bvh", ".txt": "tum", ".tum": "tum"}.get(
        ext, "csv"
    )


def _kitti_like(p: Path) -> bool:
    """A .txt whose first data line has 12 numbers (KITTI) rather than 8 (TUM)."""
    try:
        with open(p, encoding="utf-8-sig", errors="replace") as f:
            for _ in range(64):
                line = f.readline(1 << 16)
                if not line:
                    return False
                s = line.strip()
                if s and not s.startswith("#"):
                    return len(s.split()) == 12
    except OSError:
        return False
    return False
