"""Piecewise LinMat (Rust ``spline/lin_mat.rs``): rotation matrices interpolated entrywise,
projected back to rotations; interpolating, C⁰. A baseline.
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _keys, _times

__all__ = ["PiecewiseLinMat"]


class PiecewiseLinMat(Spline):
    """Baseline: rotation matrices interpolated entrywise, projected back to rotations (C⁰).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    PiecewiseSlerp

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.PiecewiseLinMat(qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0]], degrees=True))
    >>> s(0.5).shape
    (4,)
    """

    def __init__(self, quats, times=None, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(_core.lin_mat_spline(q, t), extrapolate, quats=q, times=t)
