"""Trajectory files: CSV, JSON, NPZ, TUM, EuRoC, RepoIMU, BVH, KITTI, glTF/GLB and ROS bags
(ROS 1, ROS 2, MCAP), read and written; inertial measurements (EuRoC ``imu0/data.csv``,
RepoIMU, ``sensor_msgs/Imu`` in bags) and Kalibr ``imu.yaml`` noise parameters likewise.

``read(path, format=None, **options)`` returns a :class:`Trajectory` (times, unit quaternions
in (w, x, y, z) order, optional positions); ``write(path, trajectory, format=None)`` writes
one atomically (temporary file in the target directory, renamed on success). The format is
taken from ``format`` or guessed from the extension and the first line. Every error is a
``ValueError`` naming the file, and where it applies the line and column.

``read_imu(path, format=None, **options)`` returns an :class:`ImuData` (times, gyroscope,
accelerometer); ``write_imu(path, data, format=None)`` writes one by the same rules;
``read_imu_noise`` / ``write_imu_noise`` read and write Kalibr's ``imu.yaml``.
"""

from __future__ import annotations

import inspect
import lzma
import os
import struct
import zlib
from pathlib import Path

from . import (
    bvh,
    csv_format,
    euroc,
    euroc_imu,
    gltf,
    json_format,
    kalibr_yaml,
    kitti,
    npz_format,
    repoimu,
    repoimu_imu,
    rosbag,
    rosbag_imu,
    tum,
)
from ._common import MAX_SNIFF_LINE, check_regular_input, open_regular
from .evo_bridge import from_evo, to_evo
from .inertial import ImuData, ImuNoise
from .trajectory import Trajectory, TrajectoryError, from_dataframe, to_dataframe

__all__ = [
    "FORMATS",
    "IMU_FORMATS",
    "ImuData",
    "ImuNoise",
    "Trajectory",
    "TrajectoryError",
    "detect_format",
    "detect_imu_format",
    "from_dataframe",
    "from_evo",
    "read",
    "read_imu",
    "read_imu_noise",
    "to_dataframe",
    "to_evo",
    "write",
    "write_imu",
    "write_imu_noise",
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
    valid = [n for n in inspect.signature(fn).parameters if n not in ("path", "traj", "data")]
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
    return _run_reader(path, fmt, FORMATS[fmt].read, p, options)


def _run_reader(path, fmt: str, fn, p: Path, options: dict):
    """``fn(p, **options)``, with what goes wrong reading a file as one-line errors naming
    it (a third-party parser's own errors included)."""
    try:
        return fn(p, **options)
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


#: IMU formats: name → module with ``read(path, …) -> ImuData`` and ``write(path, data, …)``.
IMU_FORMATS = {
    "euroc": euroc_imu,
    "repoimu": repoimu_imu,
    "rosbag": rosbag_imu,
}

#: IMU output extensions and their formats.
IMU_WRITE_EXTENSIONS = {".csv": "euroc", ".bag": "rosbag", ".mcap": "rosbag"}


def detect_imu_format(path: str | Path) -> str:
    """The format of an IMU file: a bag by its extension (or a ROS 2 bag directory), EuRoC
    and RepoIMU by their first line.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (or ROS 2 bag directory).

    Returns
    -------
    str
        A key of :data:`IMU_FORMATS`.

    Raises
    ------
    ValueError
        If the file is not regular or its format cannot be told (the message lists the
        formats to pass as ``format=``).

    Examples
    --------
    >>> from quatspline.io import detect_imu_format
    >>> detect_imu_format("flight.mcap"), detect_imu_format("flight.bag")
    ('rosbag', 'rosbag')
    """
    p = Path(path)
    if rosbag.is_bag(p):
        return "rosbag"
    first = ""
    if p.exists():
        with open_regular(p, encoding="utf-8-sig", errors="replace") as f:
            first = f.readline(MAX_SNIFF_LINE)
    if first.startswith("#timestamp") and "w_RS_S_x" in first:
        return "euroc"
    if first.startswith("Time (s);Vicon Orientation"):
        return "repoimu"
    raise TrajectoryError(
        f"{path}: cannot tell the IMU format (neither an EuRoC imu0/data.csv header, a RepoIMU "
        f"header nor a bag); choose one with format= ({', '.join(IMU_FORMATS)})"
    )


def read_imu(path: str | Path, format: str | None = None, **options: object) -> ImuData:
    """Reads inertial measurements: EuRoC ``imu0/data.csv``, RepoIMU CSV or
    ``sensor_msgs/Imu`` messages in a ROS 1 / ROS 2 / MCAP bag.

    Only regular files are read (a FIFO, device or directory is refused before it is
    opened); the same rules as :func:`read`.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (a ROS 2 bag may be a directory).
    format : str, optional
        A key of :data:`IMU_FORMATS`; by default guessed by :func:`detect_imu_format`.
    **options
        Format options: ``sort=True`` / ``dedupe=True`` for unordered or repeated times
        (every format); ``topic=`` and ``stamp="header"|"bag"`` for bags.

    Returns
    -------
    ImuData
        Times in seconds (as in the file: EuRoC and bag stamps are absolute), gyroscope
        [rad/s], accelerometer [m/s²] or None, the integer stamps in ``stamps_ns`` where the
        file has them; RepoIMU's Vicon orientation and magnetometer in ``extra``.

    Raises
    ------
    ValueError
        If the file is missing or not regular, the format or an option is unknown, or the
        content is invalid (the message names the file, and the line and column where it
        applies).

    See Also
    --------
    write_imu, read_imu_noise

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "data.csv"
    >>> _ = path.write_text(
    ...     "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    ...     "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\\n"
    ...     "1403636579758555392,0.1,0.2,0.3,0,0,9.81\\n"
    ...     "1403636579763555392,0.1,0.2,0.3,0,0,9.81\\n"
    ... )
    >>> imu = io.read_imu(path)
    >>> int(imu.stamps_ns[1] - imu.stamps_ns[0]), imu.gyro[0], imu.accel[0]
    (5000000, array([0.1, 0.2, 0.3]), array([0.  , 0.  , 9.81]))
    """
    if format is not None and format not in IMU_FORMATS:
        raise ValueError(f"format: unknown IMU format {format!r}; valid: {', '.join(IMU_FORMATS)}")
    p = Path(path)
    if not (p.is_dir() and rosbag.is_bag(p)):  # a ROS 2 bag is a directory
        check_regular_input(p)
    fmt = format or detect_imu_format(path)
    _check_options(fmt, IMU_FORMATS[fmt].read, options)
    return _run_reader(path, fmt, IMU_FORMATS[fmt].read, p, options)


def write_imu(
    path: str | Path, data: ImuData, format: str | None = None, **options: object
) -> None:
    """Writes inertial measurements atomically (temporary file beside the target, renamed on
    success), by the rules of :func:`write`: only a regular file (or, for a ROS 2 bag, a
    directory that provably is one) is replaced, a symbolic link is followed, a replaced
    file keeps its mode.

    Parameters
    ----------
    path : str or pathlib.Path
        The output: ``.csv`` → EuRoC ``imu0/data.csv``, ``.bag`` → ROS 1, ``.mcap`` → ROS 2
        MCAP; give ``format=`` for RepoIMU or a ROS 2 bag directory.
    data : ImuData
        What to write. A format refuses what it has no place for (true biases; ``extra``
        entries other than RepoIMU's ``orientation`` and ``mag``, a bag's ``orientation``)
        rather than drop it.
    format : str, optional
        A key of :data:`IMU_FORMATS`; by default taken from the extension.
    **options
        Format options: ``topic=``, ``frame_id=``, ``ros=1|2`` for bags.

    Raises
    ------
    TypeError
        If ``data`` is not an :class:`ImuData`.
    ValueError
        If the format or an option is unknown, the target is not a regular file, or the
        record cannot be written faithfully (NaN, times that round to the same nanosecond,
        content the format has no columns for).

    See Also
    --------
    read_imu

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import numpy as np
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "imu.csv"
    >>> data = io.ImuData([0.0, 0.005], [[0.1, 0, 0]] * 2, accel=[[0, 0, 9.81]] * 2)
    >>> io.write_imu(path, data)
    >>> print(path.read_text().splitlines()[1])
    0,0.1,0.0,0.0,0.0,0.0,9.81
    """
    if not isinstance(data, ImuData):
        raise TypeError(f"data: expected a quatspline.io.ImuData, got {type(data).__name__}")
    if format is not None and format not in IMU_FORMATS:
        raise ValueError(f"format: unknown IMU format {format!r}; valid: {', '.join(IMU_FORMATS)}")
    if format is None:
        ext = Path(path).suffix.lower()
        if ext not in IMU_WRITE_EXTENSIONS:
            known = ", ".join(f"{e} ({f})" for e, f in IMU_WRITE_EXTENSIONS.items())
            raise ValueError(
                f"{path}: unknown IMU output extension {ext or '(none)'!r}; known: {known}; "
                f"or choose a format ({', '.join(IMU_FORMATS)})"
            )
        format = IMU_WRITE_EXTENSIONS[ext]
    _check_options(format, IMU_FORMATS[format].write, options)
    IMU_FORMATS[format].write(Path(path), data, **options)


def read_imu_noise(path: str | Path, imu: str | None = None) -> dict:
    """Reads IMU noise parameters from a Kalibr ``imu.yaml`` (needs PyYAML:
    ``pip install 'quatspline[imu]'``).

    Parameters
    ----------
    path : str or pathlib.Path
        The file: the parameters at the top level, or under ``imu0`` … (an IMU chain file).
    imu : str, optional
        Which IMU of a chain file holding several (``"imu1"``).

    Returns
    -------
    dict
        ``accelerometer_noise_density`` [m/s²/√Hz], ``accelerometer_random_walk``
        [m/s³/√Hz], ``gyroscope_noise_density`` [rad/s/√Hz], ``gyroscope_random_walk``
        [rad/s²/√Hz] (continuous-time, each ≥ 0), ``update_rate`` [Hz], and ``rostopic``
        when the file names one.

    Raises
    ------
    ValueError
        If the file is missing, not YAML, lacks a parameter (named), or holds a negative,
        non-finite or non-numeric one (named with its line and column).

    See Also
    --------
    write_imu_noise

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "imu.yaml"
    >>> io.write_imu_noise(path, {
    ...     "accelerometer_noise_density": 1.86e-3, "accelerometer_random_walk": 4.33e-4,
    ...     "gyroscope_noise_density": 1.87e-4, "gyroscope_random_walk": 2.66e-5,
    ...     "update_rate": 200.0})
    >>> noise = io.read_imu_noise(path)
    >>> noise["gyroscope_noise_density"], noise["rostopic"]
    (0.000187, '/imu0')
    """
    check_regular_input(path)
    return _run_reader(path, "imu.yaml", kalibr_yaml.read, Path(path), {"imu": imu})


def write_imu_noise(
    path: str | Path, noise, rostopic: str | None = None, update_rate: float | None = None
) -> None:
    """Writes IMU noise parameters as a Kalibr ``imu.yaml``, atomically (the rules of
    :func:`write`).

    Parameters
    ----------
    path : str or pathlib.Path
        The output file.
    noise : mapping or object
        The four densities as keys or attributes (what :func:`read_imu_noise` returns, or a
        noise-model object), and ``update_rate`` unless it is given here.
    rostopic : str, optional
        The topic written; by default ``noise``'s own, else ``/imu0``.
    update_rate : float, optional
        The sample rate, Hz, the densities are given for; by default ``noise``'s own.

    Raises
    ------
    TypeError
        If an object lacks a density, or a parameter is not a number.
    ValueError
        If a mapping lacks a parameter, a density is negative or not finite, the update
        rate is missing or not > 0.

    See Also
    --------
    read_imu_noise

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "imu.yaml"
    >>> io.write_imu_noise(path, {
    ...     "accelerometer_noise_density": 2e-3, "accelerometer_random_walk": 3e-3,
    ...     "gyroscope_noise_density": 1.7e-4, "gyroscope_random_walk": 2e-5},
    ...     update_rate=400)
    >>> print(path.read_text().splitlines()[3])
    gyroscope_noise_density: 0.00017  # [rad/s/sqrt(Hz)]
    """
    kalibr_yaml.write(Path(path), noise, rostopic=rostopic, update_rate=update_rate)
