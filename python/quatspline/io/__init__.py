"""Trajectory files: CSV, JSON, NPZ, TUM, EuRoC, RepoIMU, BVH, KITTI, glTF/GLB and ROS bags
(ROS 1, ROS 2, MCAP), read and written.

``read(path, format=None, **options)`` returns a :class:`Trajectory` (times, unit quaternions
in (w, x, y, z) order, optional positions); ``write(path, trajectory, format=None)`` writes
one atomically (temporary file in the target directory, renamed on success). The format is
taken from ``format`` or guessed from the extension and the first line. Every error is a
``ValueError`` naming the file, and where it applies the line and column.
"""

from __future__ import annotations

import inspect
import lzma
import os
import struct
import zlib
from pathlib import Path

from . import bvh, csv_format, euroc, gltf, json_format, kitti, npz_format, repoimu, rosbag, tum
from ._common import MAX_SNIFF_LINE, check_regular_input, open_regular
from .evo_bridge import from_evo, to_evo
from .inertial import ImuData, ImuNoise
from .trajectory import Trajectory, TrajectoryError, from_dataframe, to_dataframe

__all__ = [
    "FORMATS",
    "ImuData",
    "ImuNoise",
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


def detect_format(path: str | Path) -> str:
    """The format of a trajectory file, from its extension and, for .csv/.txt, its first line.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (or ROS 2 bag directory).

    Returns
    -------
    str
        A key of :data:`FORMATS`; ``"csv"`` when nothing else matches.

    Raises
    ------
    ValueError
        If ``path`` exists but is not a regular file (a FIFO or device).

    Examples
    --------
    >>> from quatspline.io import detect_format
    >>> detect_format("walk.bvh"), detect_format("poses.json"), detect_format("track.glb")
    ('bvh', 'json', 'gltf')
    """
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
        # a FIFO would block, /dev/zero would never end a line
        with open_regular(p, encoding="utf-8-sig", errors="replace") as f:
            first = f.readline(MAX_SNIFF_LINE)
    if first.startswith("#timestamp") and "q_RS_w" in first:
        return "euroc"
    if first.startswith("Time (s);Vicon Orientation"):
        return "repoimu"
    if ext == ".txt":
        return "kitti" if _kitti_like(p) else "tum"
    return "csv"


def _check_options(fmt: str, fn, options: dict) -> None:
    valid = [n for n in inspect.signature(fn).parameters if n != "path" and n != "traj"]
    for name in options:
        if name not in valid:
            raise ValueError(
                f"{name}: unknown option for format {fmt}; valid: {', '.join(valid) or 'none'}"
            )


def read(path: str | Path, format: str | None = None, **options: object) -> Trajectory:
    """Reads a trajectory file.

    Only regular files are read (a FIFO, device or directory is refused before it is
    opened).

    Parameters
    ----------
    path : str or pathlib.Path
        The file (a ROS 2 bag may be a directory).
    format : str, optional
        A key of :data:`FORMATS`; by default guessed by :func:`detect_format`.
    **options
        Format options, e.g. ``euler="xyz"`` and ``degrees=True`` for a CSV of Euler
        angles, ``joint="LeftElbow"`` and ``world=True`` for BVH, ``sort=True`` /
        ``dedupe=True`` for unordered or repeated times (see each format's module).

    Returns
    -------
    Trajectory
        Times in seconds, unit quaternions (w, x, y, z), positions when the file has them.

    Raises
    ------
    ValueError
        If the file is missing or not regular, the format or an option is unknown, or the
        content is invalid (the message names the file, and the line and column where it
        applies).

    See Also
    --------
    write, quatspline.examples.load_recording

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "keys.csv"
    >>> _ = path.write_text("t,qw,qx,qy,qz\\n0,1,0,0,0\\n1,0,0,0,1\\n")
    >>> traj = io.read(path)
    >>> traj.times, traj.quats[1]
    (array([0., 1.]), array([0., 0., 0., 1.]))
    """
    if format is not None and format not in FORMATS:
        raise ValueError(f"format: unknown format {format!r}; valid: {', '.join(FORMATS)}")
    p = Path(path)
    if not p.exists():
        raise ValueError(f"{path}: no such file")
    if not (p.is_dir() and rosbag.is_bag(p)):  # a ROS 2 bag is a directory
        check_regular_input(p)
    fmt = format or detect_format(path)
    _check_options(fmt, FORMATS[fmt].read, options)
    try:
        return FORMATS[fmt].read(p, **options)
    except OSError as e:
        raise ValueError(f"{path}: cannot read ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not a text file ({e.reason} at byte {e.start})") from None
    except TrajectoryError:
        raise
    except _BUILTIN_PARSER_ERRORS as e:
        if not _raised_by_a_parser(e):
            raise  # ours: a wrong option is a TypeError or a ValueError naming the option
        raise _parser_error(path, fmt, e) from None
    except Exception as e:
        if not isinstance(e, _third_party_errors()):
            raise
        raise _parser_error(path, fmt, e) from None


#: What a third-party parser (rosbags, pygltflib, numpy, zipfile …) raises on bad bytes.
_BUILTIN_PARSER_ERRORS = (
    ValueError,
    TypeError,
    KeyError,
    IndexError,
    AttributeError,
    AssertionError,
    EOFError,
    OverflowError,
    ZeroDivisionError,
    RecursionError,
    NotImplementedError,
    struct.error,
    zlib.error,
    lzma.LZMAError,
)

_PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _raised_by_a_parser(e: BaseException) -> bool:
    """Whether ``e`` was raised in code outside this package (the innermost frame of its
    traceback), i.e. by a third-party parser on a file's content."""
    tb = e.__traceback__
    if tb is None:
        return False
    while tb.tb_next is not None:
        tb = tb.tb_next
    filename = os.path.abspath(tb.tb_frame.f_code.co_filename)
    return not filename.startswith(_PACKAGE_DIR + os.sep)


def _third_party_errors() -> tuple[type[BaseException], ...]:
    """The error classes of the optional parsers that are installed (rosbags' own)."""
    found: list[type[BaseException]] = []
    for module, names in (
        ("rosbags.highlevel", ("AnyReaderError",)),
        ("rosbags.rosbag1", ("ReaderError",)),
        ("rosbags.rosbag2", ("ReaderError",)),
        ("rosbags.serde", ("SerdeError",)),
        ("rosbags.typesys", ("TypesysError",)),
    ):
        try:
            mod = __import__(module, fromlist=list(names))
        except ImportError:
            continue
        found += [getattr(mod, n) for n in names if hasattr(mod, n)]
    return tuple(found)


def _parser_error(path, fmt: str, e: BaseException) -> TrajectoryError:
    text = " ".join(str(e).split())
    if len(text) > 200:
        text = text[:200] + "…"
    return TrajectoryError(f"{path}: not a readable {fmt} file ({type(e).__name__}: {text})")


def write(
    path: str | Path, trajectory: Trajectory, format: str | None = None, **options: object
) -> None:
    """Writes a trajectory atomically (temporary file beside the target, renamed on success).

    An extension that names no format (``.xlsx``, ``.parquet``) is refused with the list of
    formats rather than written as CSV. The target must be a regular file or not exist (a
    symbolic link is followed and its target replaced); a replaced file keeps its mode.

    Parameters
    ----------
    path : str or pathlib.Path
        The output file.
    trajectory : Trajectory
        What to write.
    format : str, optional
        A key of :data:`FORMATS`; by default taken from the extension.
    **options
        Format options (see each format's module).

    Raises
    ------
    TypeError
        If ``trajectory`` is not a :class:`Trajectory`.
    ValueError
        If the format or an option is unknown, or the target is not a regular file.

    See Also
    --------
    read

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "out.json"
    >>> io.write(path, io.Trajectory([0.0, 1.0], [[1, 0, 0, 0], [0, 1, 0, 0]]))
    >>> io.read(path).quats[1]
    array([0., 1., 0., 0.])
    """
    if not isinstance(trajectory, Trajectory):
        raise TypeError(
            f"trajectory: expected a quatspline.io.Trajectory, got {type(trajectory).__name__}"
        )
    if format is not None and format not in FORMATS:
        raise ValueError(f"format: unknown format {format!r}; valid: {', '.join(FORMATS)}")
    fmt = format or detect_format_for_writing(path)
    _check_options(fmt, FORMATS[fmt].write, options)
    FORMATS[fmt].write(Path(path), trajectory, **options)


#: Output extensions and their formats.
WRITE_EXTENSIONS = {
    ".csv": "csv",
    ".json": "json",
    ".npz": "npz",
    ".bvh": "bvh",
    ".txt": "tum",
    ".tum": "tum",
    ".glb": "gltf",
    ".gltf": "gltf",
    ".bag": "rosbag",
    ".mcap": "rosbag",
}


def detect_format_for_writing(path) -> str:
    """The format of an output path from its extension; an unknown extension is an error
    listing the extensions and formats (give ``format=`` to write euroc or repoimu)."""
    ext = Path(path).suffix.lower()
    if ext not in WRITE_EXTENSIONS:
        known = ", ".join(f"{e} ({f})" for e, f in WRITE_EXTENSIONS.items())
        raise ValueError(
            f"{path}: unknown output extension {ext or '(none)'!r}; known: {known}; "
            f"or choose a format ({', '.join(FORMATS)})"
        )
    return WRITE_EXTENSIONS[ext]


def _kitti_like(p: Path) -> bool:
    """A .txt whose first data line has 12 numbers (KITTI) rather than 8 (TUM)."""
    try:
        with open_regular(p, encoding="utf-8-sig", errors="replace") as f:
            for _ in range(64):
                line = f.readline(1 << 16)
                if not line:
                    return False
                s = line.strip()
                if s and not s.startswith("#"):
                    return len(s.split()) == 12
    except (OSError, ValueError):
        return False
    return False
