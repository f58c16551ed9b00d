"""NPZ: arrays ``times`` (N,), ``quats`` (N, 4) in (w, x, y, z) order, optional ``positions``."""

from __future__ import annotations

import tokenize
import zipfile

import numpy as np

from .._atomic import atomic_write
from ._common import Trajectory, TrajectoryError, finish


def read(path, sort: bool = False, dedupe: bool = False) -> Trajectory:
    try:
        with np.load(path, allow_pickle=False) as z:
            if "times" not in z or "quats" not in z:
                raise TrajectoryError(f"{path}: expected arrays 'times' and 'quats', got {list(z)}")
            times, quats = z["times"], z["quats"]
            pos = z["positions"] if "positions" in z else None
    except TrajectoryError:
        raise
    except (
        zipfile.BadZipFile,
        ValueError,
        EOFError,
        OSError,
        SyntaxError,
        tokenize.TokenError,
    ) as e:
        # numpy's loader can raise any of these on a damaged file (found by fuzzing)
        raise TrajectoryError(f"{path}: not a valid .npz file ({type(e).__name__}: {e})") from None
    if times.ndim != 1 or quats.shape != (len(times), 4):
        raise TrajectoryError(
            f"{path}: expected times (N,) and quats (N, 4), got {times.shape} and {quats.shape}"
        )
    return finish(path, times, quats, pos, np.arange(len(times)), sort, dedupe)


def write(path, traj: Trajectory) -> None:
    arrays = {"times": traj.times, "quats": traj.quats}
    if traj.positions is not None:
        arrays["positions"] = traj.positions
    arrays.update({k: np.asarray(v) for k, v in traj.extra.items()})
    with atomic_write(path, mode="wb") as f:
        np.savez(f, **arrays)
