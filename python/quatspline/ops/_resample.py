"""Resampling a trajectory onto other times, e.g. an estimate onto ground-truth stamps.

``resample(traj, times, method="c3", extrapolate="raise")`` builds ``method`` through the
trajectory's keys (a cubic position spline when it has positions) and evaluates it at
``times`` — an array, or another :class:`~quatspline.io.Trajectory` whose times (and exact
``stamps_ns``) are used. Times are absolute, in the trajectory's unit; the spline itself runs
on times relative to the first key (precision with Unix stamps), and every message gives
absolute times as in the input.
"""

from __future__ import annotations

import numpy as np

from .._util.progress_bars import progress

__all__ = ["resample"]

CHUNK = 200_000


def _as_times(times):
    from ..io import Trajectory

    if isinstance(times, Trajectory):
        return np.asarray(times.times, dtype=float), times.stamps_ns
    if isinstance(times, (str, bytes)) or not hasattr(times, "__len__"):
        raise TypeError(
            f"times: expected an array of times or a Trajectory, got {type(times).__name__}"
        )
    t = np.asarray(times)
    if t.dtype.kind not in "iuf" or t.ndim != 1:
        raise ValueError(f"times: expected a 1-D array of real numbers, got {t.dtype} {t.shape}")
    t = t.astype(float)
    if len(t) == 0:
        raise ValueError("times: no times to sample at")
    if not np.all(np.isfinite(t)):
        k = int(np.argmax(~np.isfinite(t)))
        raise ValueError(f"times: times[{k}] is {float(t[k])} (NaN or inf)")
    return t, None


def resample(traj, times, method: str = "c3", extrapolate: str = "raise", **params):
    """``traj``'s spline sampled at ``times``.

    Parameters
    ----------
    traj : io.Trajectory
        The keys (times, quaternions, optional positions).
    times : array_like or io.Trajectory
        Absolute times; a Trajectory gives its times (and its exact ``stamps_ns``).
    method : str
        Any registry method (``quatspline.METHODS``), ``params`` its parameters.
    extrapolate : {"raise", "clamp", "linear", "periodic"}
        Times outside the keys' range: ``"raise"`` names the first one (index and time, as in
        the input), ``"clamp"`` holds the end pose, ``"linear"`` continues at the end's
        angular (and linear) velocity, ``"periodic"`` repeats the motion.

    Returns
    -------
    io.Trajectory
        Orientations (and positions) at ``times``.

    Raises
    ------
    ValueError
        Times outside the range with ``extrapolate="raise"``, NaN times, an unknown method,
        parameter or mode.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> q = qs.from_axis_angle([0, 0, 1], [0.0, 1.0, 2.0])
    >>> tr = qs.io.Trajectory(1e9 + np.arange(3.0), q)
    >>> out = resample(tr, 1e9 + np.array([0.5, 1.5]), method="slerp")
    >>> np.round(qs.as_rotvec(out.quats)[:, 2], 12)
    array([0.5, 1.5])
    >>> resample(tr, [1e9 - 1, 1e9 + 1], method="slerp")
    Traceback (most recent call last):
    ...
    ValueError: times: times[0] = 999999999.0 is before the trajectory's first time 1000000000.0 (range [1000000000.0, 1000000002.0]; use extrapolate="clamp" or "linear")
    """  # noqa: E501
    from ..io import Trajectory
    from ..poses.pose_spline import PoseSpline
    from ..registry import spline as make_spline

    if not isinstance(traj, Trajectory):
        raise TypeError(f"traj: expected a quatspline.io.Trajectory, got {type(traj).__name__}")
    from ..splines import EXTRAPOLATE as modes

    if extrapolate not in modes:
        raise ValueError(f"extrapolate: expected one of {', '.join(modes)}, got {extrapolate!r}")
    t, ns = _as_times(times)
    a, b = float(traj.times[0]), float(traj.times[-1])
    if extrapolate == "raise":
        before, after = t < a, t > b
        out = before | after
        if np.any(out):
            k = int(np.argmax(out))
            where = (
                f"before the trajectory's first time {a!r}"
                if before[k]
                else f"after the trajectory's last time {b!r}"
            )
            allout = " (all of them are outside)" if np.all(out) else ""
            raise ValueError(
                f"times: times[{k}] = {float(t[k])!r} is {where}{allout} (range [{a!r}, {b!r}]; "
                'use extrapolate="clamp" or "linear")'
            )
    t0 = a
    rel = t - t0
    if traj.positions is not None:
        motion = PoseSpline(
            traj.quats,
            traj.times - t0,
            traj.positions,
            rotation=method,
            extrapolate=extrapolate,
            **params,
        )
        rot = motion.rotation
    else:
        motion = None
        rot = make_spline(method, traj.quats, traj.times - t0, **params)
    rot.extrapolate = extrapolate
    q = np.empty((len(t), 4))
    p = None if motion is None else np.empty((len(t), 3))
    lo, hi = rot.domain
    with progress(total=len(t), desc="sampling", unit="sample") as bar:
        for s in range(0, len(t), CHUNK):
            part = rel[s : s + CHUNK]
            if extrapolate == "clamp":
                part = np.clip(part, lo, hi)
            q[s : s + CHUNK] = rot(part)
            if motion is not None:
                p[s : s + CHUNK] = motion.position(part)
            bar.update(len(part))
    return Trajectory(t, q, p, name=traj.name, stamps_ns=ns)
