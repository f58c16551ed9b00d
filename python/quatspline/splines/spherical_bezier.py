"""One spherical Bézier curve of degree up to 64: de Casteljau's algorithm with slerp (Rust
``spline/spherical_bezier.rs``; Shoemake 1985). Through its end points; C^∞ (one curve).

The end tangents are ``q'(0) = n b₀ log(b₀* b₁)`` and ``q'(1) = n bₙ log(bₙ₋₁* bₙ)`` (per unit
of the local parameter).
"""

from __future__ import annotations

from .. import _core
from .base import Spline
from .keys import _domain, _keys

__all__ = ["SphericalBezier"]


class SphericalBezier(Spline):
    """One spherical Bézier curve of degree up to 64: de Casteljau's algorithm with slerp.

    Shoemake (1985). The end tangents are ``q'(0) = n b₀ log(b₀* b₁)`` and
    ``q'(1) = n bₙ log(bₙ₋₁* bₙ)`` (per unit of the local parameter).

    Parameters
    ----------
    control_points : array_like, shape (n + 1, 4)
        Control quaternions b₀ … bₙ (or a scipy ``Rotation``), 2 to 65 of them; the curve
        starts at b₀ and ends at bₙ.
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
    CumulativeBezier : the same end points and tangents, another curve.

    Notes
    -----
    A sample costs n(n + 1)/2 slerps (de Casteljau), so the cost grows with the square of the
    degree. Values of every degree run on the batch kernel, the slerps of many samples at
    once: on one idle core of an AVX-512 CPU about 35 ns per sample at 8 control points,
    0.35 µs at 32, 1 µs near 56 and 1.4 µs at 65 (0.8 µs on two cores), about 0.7 ns per
    slerp (``docs/performance.md``). Derivatives and angular rates
    use exact per-sample derivatives and cost more. For many keys use a spline with local
    support (``CumulativeBSpline``).

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> cp = qs.from_euler("xyz", [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0]], degrees=True)
    >>> s = qs.SphericalBezier(cp, domain=(0.0, 2.0))
    >>> bool(np.allclose(s([0.0, 2.0]), cp[[0, -1]]))
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
        super().__init__(_core.spherical_bezier(q, d, bool(canonicalize)), extrapolate)
