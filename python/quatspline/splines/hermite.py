"""Hermite keys (Rust ``spline/hermite.rs``): orientations with given angular velocities (C¹
cubic) and optionally accelerations (C² quintic); interpolating.

Segment i is qᵢ exp(½ rᵢ(s)), s = t − tᵢ, with rᵢ a cubic (quintic) rotation-vector polynomial
— the segment form of scipy's ``RotationSpline`` with the rates given instead of solved.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import with_width
from .base import Spline
from .keys import _keys, _times

__all__ = ["Hermite"]


def _rows3(v, name: str, n: int) -> np.ndarray:
    a = with_width(v, name, 3)
    if a.ndim != 2 or a.shape[0] != n:
        raise ValueError(f"{name}: expected shape ({n}, 3) (one row per key), got {a.shape}")
    return np.ascontiguousarray(a, dtype=np.float64)


class Hermite(Spline):
    """Keys with angular velocities (C¹ cubic) and optionally accelerations (C² quintic).

    Segment i is qᵢ exp(½ rᵢ(s)), s = t − tᵢ, with rᵢ a cubic (quintic) rotation-vector
    polynomial matching the key orientations and the given rates (accelerations) at both ends
    — the segment form of scipy's ``RotationSpline`` with the rates given instead of solved.

    Holds and rest ends override the given rates: with ``holds=True`` (default) the keys
    bounding a hold (consecutive equal keys, q or −q) get zero angular velocity (and zero
    acceleration for the quintic) whatever rows were given there, so the hold is exactly
    constant and the curve stays C¹ (C²); ``ends="rest"`` does the same at the first and
    last key. The given rows at those keys are ignored, not checked (``holds=False`` and
    ``ends="open"`` use every given row).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Key orientations (w, x, y, z); normalised, and made shortest-path unless
        ``canonicalize=False``.
    times : array_like, shape (N,) or (N + 1,), optional
        Key times (default 0, 1, …); a closed curve takes one more, closing the loop.
    angular_velocity : array_like, shape (N, 3)
        Angular velocity at each key, rad per time unit, in ``frame``.
    angular_acceleration : array_like, shape (N, 3), optional
        Angular acceleration at each key; gives the C² quintic.
    frame : {"world", "body"}
        Frame of the given rates.
    ends : {"open", "rest", "closed"}
        ``"rest"``: zero angular velocity (and acceleration) at the first and last key,
        overriding the given rows there; ``"closed"``: the last key joins the first (see the
        module doc).
    canonicalize : bool
        Flip keys so consecutive ones are in the same hemisphere.
    extrapolate : {"raise", "clamp", "linear", "periodic"}
        Rule outside the domain.
    holds : bool
        Consecutive equal keys hold exactly still: zero rate (and acceleration) at both ends
        of every hold, overriding the given rows there (default True).

    Raises
    ------
    ValueError
        Rates of the wrong shape or non-finite (named with the row), bad times or keys,
        an unsupported ``ends``.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> q = qs.from_rotvec([[0, 0, 0], [0, 0, 0.5], [0, 0, 1.0]])
    >>> s = qs.Hermite(q, [0, 1, 2], angular_velocity=[[0, 0, 0.5]] * 3)
    >>> bool(np.allclose(s.angular_velocity(0.7), [0, 0, 0.5]))
    True
    >>> s.continuity
    1
    """

    def __init__(
        self,
        quats,
        times=None,
        angular_velocity=None,
        angular_acceleration=None,
        frame: str = "world",
        ends: str = "open",
        canonicalize: bool = True,
        extrapolate: str = "raise",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        if angular_velocity is None:
            raise ValueError("angular_velocity: required (one row of 3 per key)")
        w = _rows3(angular_velocity, "angular_velocity", len(q))
        a = None
        if angular_acceleration is not None:
            a = _rows3(angular_acceleration, "angular_acceleration", len(q))
        super().__init__(
            _core.hermite(q, t, w, a, str(frame), str(ends), bool(canonicalize), bool(holds)),
            extrapolate,
            quats=q,
            times=t,
            angular_velocity=w,
            angular_acceleration=a,
            frame=frame,
            ends=ends,
            canonicalize=canonicalize,
            holds=holds,
        )
