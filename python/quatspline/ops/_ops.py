"""What every operation of :mod:`quatspline.ops` shares: the option error, argument checks and
the spline of a method through a recording's keys."""

from __future__ import annotations

import numbers

import numpy as np

from .._util.checks import short
from .._util.errors import ParameterError
from ..io import Trajectory
from ..registry import spline as make_spline
from ..splines import DEFAULT_MAX_SAMPLES

__all__ = ["DEFAULT_MAX_SAMPLES", "ParameterError", "build_spline"]

# DEFAULT_MAX_SAMPLES bounds the number of samples one call may produce. Measured peak memory
# of ``quatspline sample --derivatives`` on a recording with positions: 0.27 GB (NPZ) and
# 0.37 GB (CSV) for 1,000,000 samples, i.e. about 300 bytes a sample: about 3 GB at this bound.


def _check_trajectory(traj, name: str = "traj") -> None:
    if not isinstance(traj, Trajectory):
        raise TypeError(f"{name}: expected a quatspline.io.Trajectory, got {type(traj).__name__}")


def _int_arg(value, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    value = int(value)
    if value < minimum:
        raise ParameterError(f"{name}: expected an integer ≥ {minimum}, got {short(value)}")
    return value


def build_spline(method: str, traj: Trajectory, params: dict | None = None):
    """The spline of ``method`` through the keys of ``traj``, on times relative to the first
    key (``traj.times - traj.times[0]``, for accuracy with large timestamps).

    Parameters
    ----------
    method : str
        Registry method name.
    traj : quatspline.io.Trajectory
        The keys.
    params : dict, optional
        The method's parameters.

    Returns
    -------
    Spline

    Raises
    ------
    ParameterError
        Unknown method or parameter.
    ValueError
        Keys the method cannot use.

    Examples
    --------
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import build_spline
    >>> s = build_spline("slerp", Trajectory([5.0, 6.0], [[1, 0, 0, 0], [0, 0, 0, 1]]))
    >>> s.domain
    (0.0, 1.0)
    """
    _check_trajectory(traj)
    if params is not None and not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    return _build(method, traj, traj.times - traj.times[0], dict(params or {}))


def _build(method: str, traj: Trajectory, times: np.ndarray, params: dict):
    # the registry raises ParameterError itself for an unknown method or a bad parameter
    return make_spline(method, traj.quats, times, **params)
