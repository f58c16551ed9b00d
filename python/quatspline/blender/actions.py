"""Blender's animation data ↔ quatspline, without Blender: what the add-on's operators
translate, in plain arrays (so it is tested outside Blender too).

Blender keys a frame number; quatspline keys a time in seconds: ``time = (frame − frame_start)
/ fps`` on the way in and ``frame = frame_start + time × fps`` on the way out. Rotations stay
in Blender's own frame (``rotation_quaternion`` is w, x, y, z, world from object, Z up), so
reading an object's F-curves and writing them back changes nothing but the keys. An Euler
rotation mode (``'XYZ'`` … ``'ZYX'``: Blender's letters are the order the axes apply, about
fixed axes) is the extrinsic sequence of :func:`quatspline.from_euler` in lower case.
"""

from __future__ import annotations

import numpy as np

from ..core.convert import from_euler
from ..io.trajectory import Trajectory
from ..registry import METHODS

__all__ = [
    "EULER_MODES",
    "curve_frames",
    "frames_to_times",
    "method_items",
    "parse_params",
    "quats_from_rotation",
    "times_to_frames",
    "trajectory_from_samples",
]

#: Blender's Euler rotation modes (F-curve ``rotation_euler``).
EULER_MODES = ("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX")


def frames_to_times(frames, fps: float, frame_start: float = 0.0) -> np.ndarray:
    """Seconds from ``frame_start`` at ``fps`` frames per second.

    Examples
    --------
    >>> frames_to_times([1, 25, 49], 24, 1).tolist()
    [0.0, 1.0, 2.0]
    """
    fps = _fps(fps)
    return (np.asarray(frames, dtype=float) - float(frame_start)) / fps


def times_to_frames(times, fps: float, frame_start: float = 0.0) -> np.ndarray:
    """Frames for times in seconds (the inverse of :func:`frames_to_times`).

    Examples
    --------
    >>> times_to_frames([0.0, 0.5], 24, 1).tolist()
    [1.0, 13.0]
    """
    fps = _fps(fps)
    return float(frame_start) + np.asarray(times, dtype=float) * fps


def _fps(fps) -> float:
    if isinstance(fps, bool) or not isinstance(fps, (int, float, np.integer, np.floating)):
        raise TypeError(f"fps: expected a number, got {type(fps).__name__}")
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"fps: expected a positive frame rate, got {fps}")
    return float(fps)


def quats_from_rotation(mode: str, values) -> np.ndarray:
    """Quaternions (w, x, y, z) from the values of an object's rotation channels.

    Parameters
    ----------
    mode : str
        ``"QUATERNION"`` (values (N, 4), w x y z) or an Euler mode of :data:`EULER_MODES`
        (values (N, 3), radians).
    values : array_like

    Examples
    --------
    >>> np.round(quats_from_rotation("XYZ", [[0.0, 0.0, np.pi / 2]]), 6).tolist()
    [[0.707107, 0.0, 0.0, 0.707107]]
    """
    v = np.asarray(values, dtype=float)
    if mode == "QUATERNION":
        if v.ndim != 2 or v.shape[1] != 4:
            raise ValueError(f"values: expected shape (N, 4) for QUATERNION, got {v.shape}")
        n = np.linalg.norm(v, axis=1)
        if not np.all(n > 0):
            raise ValueError("values: a zero quaternion (all four rotation curves at 0)")
        return v / n[:, None]
    if mode in EULER_MODES:
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"values: expected shape (N, 3) for {mode}, got {v.shape}")
        return from_euler(mode.lower(), v)
    raise ValueError(
        f"mode: expected QUATERNION or an Euler mode ({', '.join(EULER_MODES)}), got {mode!r} "
        "(axis-angle rotations are not read)"
    )


def curve_frames(key_frames) -> np.ndarray:
    """The frames where any of an object's rotation or location curves has a key: the
    samples a resampling starts from (sorted, without repeats).

    Examples
    --------
    >>> curve_frames([[1, 10, 20], [1, 15], []]).tolist()
    [1.0, 10.0, 15.0, 20.0]
    """
    parts = [np.asarray(k, dtype=float).ravel() for k in key_frames]
    out = np.unique(np.concatenate(parts)) if parts else np.zeros(0)
    if len(out) < 2:
        raise ValueError(
            "keys: the object's rotation and location curves have fewer than two keyframes"
        )
    return out


def trajectory_from_samples(
    frames, fps: float, frame_start: float, mode: str, rotation, location=None, name: str = ""
) -> Trajectory:
    """The motion an object's curves play at ``frames`` (values as Blender evaluates them)
    as a :class:`quatspline.io.Trajectory` on seconds from ``frame_start``.

    Examples
    --------
    >>> tr = trajectory_from_samples([1, 25], 24, 1, "XYZ", [[0, 0, 0], [0, 0, 1.0]])
    >>> tr.times.tolist(), tr.positions is None
    ([0.0, 1.0], True)
    """
    t = frames_to_times(frames, fps, frame_start)
    q = quats_from_rotation(mode, rotation)
    p = None if location is None else np.asarray(location, dtype=float)
    return Trajectory(t, q, p, name=name)


def method_items() -> list[tuple[str, str, str]]:
    """(identifier, name, description) of every registry method, for a Blender enum.

    Examples
    --------
    >>> ("fit", "fit", METHODS["fit"].summary) in method_items()
    True
    """
    return [(m.name, m.name, m.summary) for m in METHODS.values()]


def parse_params(method: str, text: str) -> dict:
    """``"alpha=0.5, ends=rest"`` → ``{"alpha": "0.5", "ends": "rest"}``: a method's
    parameters as typed in the add-on (the registry converts and checks each value, and
    names an unknown one).

    Examples
    --------
    >>> parse_params("c3", "alpha=0.5, beta = 0.2")
    {'alpha': '0.5', 'beta': '0.2'}
    >>> parse_params("c3", "alpha")
    Traceback (most recent call last):
    ...
    ValueError: parameters: expected name=value, got 'alpha'
    """
    out = {}
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        name, eq, value = part.partition("=")
        if not eq or not name.strip():
            raise ValueError(f"parameters: expected name=value, got {part!r}")
        out[name.strip()] = value.strip()
    METHODS[method].resolve(out)  # names an unknown or bad parameter now
    return out
