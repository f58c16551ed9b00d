"""The uniform cumulative B-spline of order k (Rust ``spline/cumulative_bspline.rs``; Kim,
Kim & Shin 1995; Sommer et al. 2020): approximating, C^(k−2) (C² for the cubic).

Non-uniform knots (``knots=`` or ``dt=[…]``): :mod:`quatspline.splines.knots`. Holds and rest
ends: :func:`quatspline.splines.keys.bspline_controls`.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.checks import integer, real, short
from .base import Spline
from .keys import _keys, bspline_controls, bspline_hold_intervals
from .knots import _core_spline

__all__ = ["CumulativeBSpline"]


class CumulativeBSpline(Spline):
    """Uniform cumulative B-spline of order k (cubic by default): C^(k−2), approximating.

    Kim, Kim & Shin (1995); the form used in visual-inertial estimation (Sommer et al.
    2020). Segment i spans ``[t0 + i·dt, t0 + (i+1)·dt]`` and uses control rotations
    i … i+k−1, so the domain is ``[t0, t0 + (n − k + 1)·dt]``. Non-uniform: ``knots=``
    (n + k non-decreasing knots, domain ``[u_{k−1}, u_n]``) or ``dt=[…]`` (the n + k − 1 knot
    spacings, ``u_{k−1} = t0``) give the non-uniform cumulative B-spline (De Boor basis, see
    ``quatspline.splines.knots``).

    Parameters
    ----------
    control_quats : array_like, shape (n, 4)
        Control rotations (or a scipy ``Rotation``); at least ``order`` of them. The curve
        does not pass through them.
    dt : float or array_like, default 1.0
        Knot spacing (time per segment), > 0; or the n + k − 1 knot spacings.
    t0 : float, default 0.0
        Start time.
    order : int, default 4
        B-spline order k (degree k − 1), 2 … 8.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"closed"``: the control rotations are used cyclically — n segments over
        ``[t0, t0 + n·dt]``, C^(k−2) across the seam (uniform knots only); a last control
        rotation equal to the first is kept (a hold across the seam with ``holds=True``),
        not dropped as the interpolating methods' closing key is. ``"rest"``
        (order ≥ 3, uniform knots): k − 2 copies of the first and last control rotation are
        added (fewer if a hold is there already), so the curve starts and ends on them with
        zero angular velocity (and acceleration, … up to derivative k − 2); the domain grows
        by 2(k − 2)·dt.
    holds : bool, default False
        Runs of consecutive equal control rotations (q or −q) become exact holds: a run of
        m is repeated to m + k − 2 copies, so the curve is exactly constant on m − 1 whole
        segments (listed in ``hold_intervals``) with derivatives up to k − 2 zero at their
        ends; each added copy lengthens the domain by ``dt`` (see
        ``quatspline.splines.bspline_controls``). Off by default because control rotations
        are not keys: the construction moves the domain. Uniform knots only.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    BetaSpline : shape parameters, G¹.

    Examples
    --------
    >>> import quatspline as qs
    >>> angles = [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0], [60, 0, 0]]
    >>> cp = qs.from_euler("xyz", angles, degrees=True)
    >>> s = qs.CumulativeBSpline(cp, dt=0.5)
    >>> s.domain, s.continuity, s.interpolates
    ((0.0, 1.0), 2, False)
    """

    def __init__(
        self,
        control_quats,
        dt: float = 1.0,
        t0: float = 0.0,
        order: int = 4,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        knots=None,
        ends: str = "open",
        holds: bool = False,
    ):
        if ends not in ("open", "rest", "closed"):
            raise ValueError(
                f"ends: CumulativeBSpline does not support {ends!r}; supported: open, rest, closed"
            )
        q = _keys(control_quats, "control_quats")
        order = integer(order, "order")
        if not 2 <= order <= 12:  # the core's rule and message (-1 overflowed its usize before)
            raise ValueError(f"order: expected 2 ≤ order ≤ 12, got {short(order)}")
        self.hold_intervals: list[tuple[float, float]] = []
        if (ends != "open" or holds) and (knots is not None or np.ndim(dt) != 0):
            raise ValueError(
                f"{'ends' if ends != 'open' else 'holds'}: closed and rest ends and holds need "
                "uniform knots (a scalar dt, no knots=)"
            )
        if ends == "rest" or holds:
            q = bspline_controls(q, order, ends, bool(holds))
        if knots is not None or np.ndim(dt) != 0:
            # Non-uniform knots (explicit, or per-interval spacings): see knots.py.
            core = _core_spline(q, dt, t0, order, bool(canonicalize), knots)
            super().__init__(core, extrapolate)
            return
        dt, t0 = real(dt, "dt", positive=True), real(t0, "t0")
        super().__init__(
            _core.cumulative_bspline(
                q, float(dt), float(t0), int(order), bool(canonicalize), ends == "closed"
            ),
            extrapolate,
        )
        if holds:
            self.hold_intervals = bspline_hold_intervals(q, order, ends == "closed", dt, t0)
