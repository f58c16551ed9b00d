"""Piecewise slerp (Rust ``spline/piecewise_slerp.rs``; Shoemake 1985): slerp between
consecutive keys, constant angular speed within each segment; interpolating, C⁰.
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _keys, _times

__all__ = ["PiecewiseSlerp"]


class PiecewiseSlerp(Spline):
    """Slerp between consecutive keys: C⁰, constant angular speed within each segment.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
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
    quatspline.slerp : two keys.
    reparameterize : even out the speed across segments.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 90]], degrees=True)
    >>> s = qs.PiecewiseSlerp(keys, [0.0, 1.0, 3.0])
    >>> np.linalg.norm(s.angular_velocity([0.5, 2.0]), axis=1).round(12)  # π/2 rad/s, then 0
    array([1.57079633, 0.        ])
    """

    def __init__(self, quats, times=None, canonicalize: bool = True, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.piecewise_slerp(q, t, bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
        )
