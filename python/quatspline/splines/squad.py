"""Squad, spherical quadrangle interpolation (Rust ``spline/squad.rs``; Shoemake 1987):
interpolating, C¹ in time (not C²).
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _keys, _times

__all__ = ["Squad"]


class Squad(Spline):
    """Shoemake's Squad (spherical quadrangle interpolation): interpolating, C¹ in time.

    Shoemake (1987). For non-uniform times each key gets an incoming and an outgoing inner
    point, chosen so that both sides have the same velocity in time; with uniform times
    both are Shoemake's. Squad is C¹, not C².

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
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"open"``: s₀⁺ = q₀, sₙ⁻ = qₙ. ``"rest"``: zero angular velocity at both ends.
        ``"closed"``: a periodic loop, C¹ across the seam (see ``quatspline.splines.keys``).
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still, with zero velocity at both ends
        of the hold.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    CatmullRom : also C¹, Gortler's construction.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [90, 45, 0], [0, 45, 30]], degrees=True)
    >>> s = qs.Squad(keys, [0.0, 1.0, 3.0, 3.5])
    >>> bool(np.allclose(s([0.0, 1.0, 3.0, 3.5]), keys)), [j.order for j in qs.continuity(s)]
    (True, [1, 1])
    """

    def __init__(
        self,
        quats,
        times=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        ends: str = "open",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.squad(q, t, bool(canonicalize), str(ends), bool(holds)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
            ends=ends,
            holds=holds,
        )
