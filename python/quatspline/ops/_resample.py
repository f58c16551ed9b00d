"""Resampling a trajectory onto other times, e.g. an estimate onto ground-truth stamps.

``resample(traj, times, method="natural", extrapolate="raise")`` is :func:`quatspline.ops.sample`
with ``times``: ``method`` through the trajectory's keys (a cubic position spline when it has
positions), evaluated at ``times`` — an array, or another :class:`~quatspline.io.Trajectory`
whose times (and exact ``stamps_ns``) are used. Times are absolute, in the trajectory's unit;
the spline itself runs on times relative to the first key (precision with Unix stamps), and
every message gives absolute times as in the input.
"""

from __future__ import annotations

from .._util.options import DEFAULT_METHOD
from ._ops import _check_trajectory
from ._sample import sample

__all__ = ["resample"]


def resample(traj, times, method: str = DEFAULT_METHOD, extrapolate: str = "raise", **params):
    """``traj``'s spline sampled at ``times`` (:func:`quatspline.ops.sample` with ``times``).

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
    ValueError: times: times[0] = 999999999.0 is before the trajectory's first time 1000000000.0 (range [1000000000.0, 1000000002.0]; use extrapolate="clamp" to hold the end pose)
    """  # noqa: E501
    _check_trajectory(traj)
    return sample(traj, method, times=times, params=params, extrapolate=extrapolate)
