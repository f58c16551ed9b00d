"""Knot vectors for the cumulative B-spline: ``CumulativeBSpline(knots=…)`` or ``dt=[…]``.

The non-uniform cumulative B-spline of order k (De Boor's basis on the rotation group, Rust
``spline/nonuniform_bspline.rs``) takes n control rotations and n + k non-decreasing knots
u₀ … u_{n+k−1}; its domain is [u_{k−1}, u_n]. A knot may repeat up to k times at the ends
(k clamps the curve to the end control rotations) and up to k − 1 times inside the domain; a
joint whose knot repeats μ times is C^(k−1−μ). ``dt=[…]`` gives the n + k − 1 knot spacings
instead, with u_{k−1} = t0. A scalar ``dt`` keeps the uniform fast path.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import as_real
from .._util.checks import short

__all__ = ["clamped_knots", "knots_from_spacing"]


def knots_from_spacing(dt, t0: float, n: int, order: int) -> np.ndarray:
    """Knots u₀ … u_{n+k−1} from the n + k − 1 spacings ``dt`` with u_{k−1} = ``t0``.

    Examples
    --------
    >>> from quatspline.splines.knots import knots_from_spacing
    >>> knots_from_spacing([1, 1, 1, 2, 0.5, 1, 1, 1], 0.0, 5, 4).tolist()
    [-3.0, -2.0, -1.0, 0.0, 2.0, 2.5, 3.5, 4.5, 5.5]
    """
    d = as_real(dt, "dt")
    if d.ndim != 1 or len(d) != n + order - 1:
        raise ValueError(
            f"dt: expected a scalar or n + k − 1 = {n + order - 1} knot spacings "
            f"for {n} control rotations of order {order}, got shape {d.shape}"
        )
    if not np.all(np.isfinite(d)):
        raise ValueError(f"dt: non-finite value at element {int(np.argmax(~np.isfinite(d)))}")
    if np.any(d < 0):
        raise ValueError(f"dt: negative spacing at element {int(np.argmax(d < 0))}")
    u = np.concatenate([[0.0], np.cumsum(d)])
    return u - u[order - 1] + float(t0)


def clamped_knots(times, order: int = 4) -> np.ndarray:
    """An open (clamped) knot vector whose joints are ``times``: the ends repeated k times,
    so the curve starts and ends at the first and last control rotation; it needs
    len(times) + k − 2 control rotations.

    Examples
    --------
    >>> from quatspline.splines.knots import clamped_knots
    >>> clamped_knots([0.0, 1.0, 3.0], order=3).tolist()
    [0.0, 0.0, 0.0, 1.0, 3.0, 3.0, 3.0]
    """
    t = as_real(times, "times")
    if t.ndim != 1 or len(t) < 2:
        raise ValueError(f"times: expected at least 2 joint times, got shape {t.shape}")
    return np.concatenate([np.full(order - 1, t[0]), t, np.full(order - 1, t[-1])])


def _core_spline(q, dt, t0, order, canonicalize, knots):
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
        raise TypeError(f"order: expected an int, got {type(order).__name__}")
    if not 2 <= order <= 12:
        raise ValueError(f"order: expected 2 ≤ order ≤ 12, got {short(order)}")
    if knots is None:
        u = knots_from_spacing(dt, t0, len(q), int(order))
    else:
        if np.ndim(dt) != 0 or dt != 1.0 or t0 != 0.0:
            raise ValueError("knots: give either knots or dt/t0, not both")
        u = as_real(knots, "knots")
        if u.ndim != 1:
            raise ValueError(f"knots: expected a 1-D knot vector, got shape {u.shape}")
    return _core.nonuniform_bspline(
        q, np.ascontiguousarray(u, dtype=float), int(order), canonicalize
    )
