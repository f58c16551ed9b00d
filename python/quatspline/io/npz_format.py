"""NPZ: arrays ``times`` (N,), ``quats`` (N, 4) in (w, x, y, z) order, optional ``positions``.

Each array's ``.npy`` header is read and checked before the array is: real numbers only
(integer or float; complex, datetime, object and the like are refused), a declared size within
:data:`MAX_ARRAY_BYTES` and consistent with the stored member's size, so a small compressed
file cannot make the reader allocate gigabytes.
"""

from __future__ import annotations

import lzma
import struct
import tokenize
import zipfile
import zlib

import numpy as np

from .._util.atomic import atomic_write
from ._common import check_for_writing, open_regular
from .trajectory import Trajectory, TrajectoryError, finish

#: Largest array read (declared size after decompression): 1 GiB, about 33 million keys.
MAX_ARRAY_BYTES = 1 << 30

ARRAYS = ("times", "quats", "positions")


def _read_member(zf: zipfile.ZipFile, name: str, path) -> np.ndarray:
    info = zf.getinfo(name + ".npy")
    if info.file_size > MAX_ARRAY_BYTES + 4096:
        raise TrajectoryError(
            f"{path}: array {name!r} is {info.file_size} bytes uncompressed, more than the "
            f"limit of {MAX_ARRAY_BYTES}"
        )
    with zf.open(info) as f:
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(f)
        elif version == (2, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(f)
        else:
            raise TrajectoryError(f"{path}: array {name!r}: unsupported .npy version {version}")
        if dtype.kind not in "iuf" or dtype.hasobject:
            raise TrajectoryError(
                f"{path}: array {name!r} has dtype {dtype}; expected real numbers "
                "(integer or float)"
            )
        if not all(isinstance(d, int) and d >= 0 for d in shape):
            raise TrajectoryError(
                f"{path}: array {name!r} declares shape {tuple(shape)}; dimensions must be "
                "integers ≥ 0"
            )
        count = 1
        for d in shape:
            count *= d  # Python integers: no overflow
        declared = count * dtype.itemsize
        if declared > MAX_ARRAY_BYTES:
            raise TrajectoryError(
                f"{path}: array {name!r} declares shape {tuple(shape)} ({declared} bytes), "
                f"more than the limit of {MAX_ARRAY_BYTES}"
            )
        if declared > info.file_size:
            raise TrajectoryError(
                f"{path}: array {name!r} declares shape {tuple(shape)} but holds only "
                f"{info.file_size} bytes"
            )
        data = f.read(declared + 1)
    if len(data) != declared:
        raise TrajectoryError(
            f"{path}: array {name!r}: expected {declared} bytes of data, got {len(data)}"
        )
    a = np.frombuffer(data, dtype=dtype, count=count)
    order = "F" if fortran else "C"
    return a.reshape(shape, order=order).astype(float)


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    raw = open_regular(path, "rb")
    try:
        with raw, zipfile.ZipFile(raw) as zf:
            names = {n[:-4] for n in zf.namelist() if n.endswith(".npy")}
            if "times" not in names or "quats" not in names:
                raise TrajectoryError(
                    f"{path}: expected arrays 'times' and 'quats', got {sorted(names)}"
                )
            times = _read_member(zf, "times", path)
            quats = _read_member(zf, "quats", path)
            pos = _read_member(zf, "positions", path) if "positions" in names else None
    except TrajectoryError:
        raise
    except (
        zipfile.BadZipFile,
        zipfile.LargeZipFile,
        zlib.error,
        lzma.LZMAError,
        struct.error,
        RuntimeError,  # zipfile: an encrypted member
        NotImplementedError,
        ValueError,
        EOFError,
        OSError,
        SyntaxError,
        tokenize.TokenError,
    ) as e:
        # a damaged archive or .npy header can raise any of these (found by fuzzing)
        raise TrajectoryError(f"{path}: not a valid .npz file ({type(e).__name__}: {e})") from None
    if times.ndim != 1 or quats.shape != (len(times), 4):
        raise TrajectoryError(
            f"{path}: expected times (N,) and quats (N, 4), got {times.shape} and {quats.shape}"
        )
    if pos is not None and pos.shape != (len(times), 3):
        raise TrajectoryError(f"{path}: expected positions ({len(times)}, 3), got {pos.shape}")
    return finish(path, times, quats, pos, np.arange(len(times)), sort, dedupe)


def write(path, traj: Trajectory) -> None:
    check_for_writing(path, traj, reserved=ARRAYS)
    for name in traj.extra:
        if "/" in name or "\\" in name or name.startswith("."):
            raise ValueError(f"{path}: extra array name {name!r} is not a valid member name")
    arrays = {"times": traj.times, "quats": traj.quats}
    if traj.positions is not None:
        arrays["positions"] = traj.positions
    arrays.update({k: np.asarray(v) for k, v in traj.extra.items()})
    with atomic_write(path, mode="wb") as f:
        np.savez(f, **arrays)
