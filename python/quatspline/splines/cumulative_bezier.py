"""One cumulative spherical Bézier curve (Rust ``spline/cumulative_bezier.rs``; Kim, Kim &
Shin 1995). Through its end points; C^∞ (one curve).

``q(t) = b₀ Π_j (b_{j−1}* b_j)^{B̃_j(t)}`` with the cumulative Bernstein polynomials ``B̃_j``:
the end points and end tangents of the spherical Bézier curve with the same control points, a
different curve in between.
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _domain, _keys

__all__ = ["CumulativeBezier"]


class CumulativeBezier(Spline):
    """One cumulative spherical Bézier curve (Kim, Kim & Shin 1995).

    ``q(t) = b₀ Π_j (b_{j−1}* b_j)^{B̃_j(t)}`` with the cumulative Bernstein polynomials
    ``B̃_j``. It has the end points and end tangents of :class:`SphericalBezier` with the
    same control points, and is a different curve in between.

    Parameters
    ----------
    control_points : array_like, shape (n + 1, 4)
        Control quaternions b₀ … bₙ (or a scipy ``Rotation``).
    domain : tuple of float, default (0.0, 1.0)
        The time interval the curve is mapped to.
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
    SphericalBezier

    Notes
    -----
    At most 4,096 control points (degree 4,095). A sample costs one exponential and one
    product per factor in the window of the Bernstein basis that matters, the terms at least
    2⁻⁶⁰ times the largest: about 9√(n u(1−u)) factors for degree n at ``u`` (below the window
    the factors combine to a control point, above it they are the identity), so the cost
    grows as √n, not n. For many keys, :class:`CumulativeBSpline` costs the same per sample at
    any size.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> cp = qs.from_euler("xyz", [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0]], degrees=True)
    >>> s, b = qs.CumulativeBezier(cp), qs.SphericalBezier(cp)
    >>> bool(np.allclose(s.derivative(0.0), b.derivative(0.0)))  # same end tangent
    True
    """

    def __init__(
        self,
        control_points,
        domain=(0.0, 1.0),
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(control_points, "control_points")
        d = _domain(domain)
        super().__init__(_core.cumulative_bezier(q, d, bool(canonicalize)), extrapolate)
