"""The global interpolating C² spline (Rust ``spline/natural_spline.rs``), the construction
of scipy's ``RotationSpline``.

Every key moves every segment (global support). Segment i is ``qᵢ exp(½ rᵢ(τ − τᵢ))`` with a
cubic rotation vector ``rᵢ``; the key rates follow from continuity of angular velocity and
acceleration, a non-linear system solved by iterating a block-tridiagonal solve.
"""

from __future__ import annotations

from .. import _core
from .._util.arrays import as_real
from .base import Spline
from .keys import _keys, _times

__all__ = ["NaturalSpline"]


class NaturalSpline(Spline):
    """The global interpolating C² spline (the construction of scipy's ``RotationSpline``).

    Every key moves every segment (global support). Segment i is
    ``qᵢ exp(½ rᵢ(τ − τᵢ))`` with a cubic rotation vector ``rᵢ``; the key rates follow from
    continuity of angular velocity and acceleration, a non-linear system solved by
    iterating a block-tridiagonal solve.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    ends : {"natural", "clamped", "rest", "closed"}, default "natural"
        ``"natural"``: zero angular acceleration at both ends. ``"clamped"``: the body
        angular velocities ``start_rate`` and ``end_rate`` at the ends. ``"rest"``: zero
        angular velocity at both ends. ``"closed"``: a periodic loop, C² across the seam
        (see ``quatspline.splines.keys``).
    start_rate, end_rate : array_like, shape (3,), optional
        Body-frame end rates for ``ends="clamped"`` (rad per time unit); by default the end
        segments' chord rates, which is exactly what scipy's ``RotationSpline`` does.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still: the rates at the keys bounding
        a hold are pinned to zero, so the curve is C¹ (not C²) there — a cubic cannot also
        zero the acceleration (``continuity`` then reports 1).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    C3Spline : local support, C³.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation, RotationSpline
    >>> import quatspline as qs
    >>> keys, times = Rotation.random(5, random_state=0), [0.0, 1.0, 1.5, 3.0, 4.0]
    >>> s = qs.NaturalSpline(keys, times, ends="clamped")
    >>> t = np.linspace(0, 4, 9)
    >>> bool(np.allclose(s.angular_velocity(t, frame="body"), RotationSpline(times, keys)(t, 1),
    ...                  rtol=1e-5, atol=1e-6))
    True
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "natural",
        start_rate=None,
        end_rate=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        if not isinstance(ends, str):
            raise TypeError(f"ends: expected a string, got {type(ends).__name__}")
        if ends == "natural":
            for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
                if r is not None:
                    raise ValueError(
                        f"{name}: only used with ends='clamped' (natural ends have zero angular "
                        "acceleration, not a given rate)"
                    )
        rates = []
        for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
            if r is None:
                rates.append(None)
                continue
            v = as_real(r, name)
            if v.shape != (3,):
                raise ValueError(f"{name}: expected shape (3,), got {v.shape}")
            rates.append(tuple(float(x) for x in v))
        super().__init__(
            _core.natural_spline(
                q, t, str(ends), rates[0], rates[1], bool(canonicalize), bool(holds)
            ),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            start_rate=start_rate,
            end_rate=end_rate,
            canonicalize=canonicalize,
            holds=holds,
        )
