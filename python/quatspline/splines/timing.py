"""Retiming: the same path on a new clock, with exact derivatives (Rust ``spline/reparam.rs``).

- :func:`arc_length` (also ``reparameterize(s, "arc_length")``): any spline traced at
  constant angular speed over the same domain. The arc-length map ``φ(s) = ∫|ω|`` is tabulated
  by adaptive Gauss–Legendre quadrature and its inverse ``s(φ)`` by strictly increasing
  degree-7 Hermite pieces (slopes 1/|ω| and their first two derivatives at both ends), halved until
  ``|φ(s_tab(φ)) − φ|`` is within 1e-12 of the segment's arc length at three check points of
  every piece, so a sample costs one evaluation of the original spline; the derivatives
  of the composed curve q(s(t)) follow from the chain rule with s' = c/|ω(s)| solved in Taylor
  mode, so velocity, acceleration and jerk are exact, not differenced.
- :func:`retime`: the spline slowed down (or, with ``shrink=True``, sped up) uniformly so
  that the angular velocity and acceleration stay within bounds. The stretch is **global**
  (t ↦ a + λ(t − a)): ω scales by 1/λ and dω/dt by 1/λ², so
  ``λ = max(max|ω|/ω_max, √(max|dω/dt|/α_max))`` is the least uniform stretch and the binding
  bound is met with equality where its maximum is reached. A per-segment stretch could save
  time on slow segments but makes ω jump at every joint where λ changes (the retimed curve
  would only be C⁰), so it is not offered: a global stretch keeps the spline's continuity.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .base import Spline
from .se3 import PoseCurveSpline

__all__ = ["Reparameterized", "arc_length", "max_angular_rate", "retime"]


class Reparameterized(Spline):
    """A spline on a new clock: ``arc_length`` (constant angular speed) or ``retimed``
    (uniform time stretch), made by :func:`arc_length`, :func:`retime` or
    ``reparameterize(s, "arc_length")``; a :class:`Spline` with exact derivatives of the
    composition.

    Attributes
    ----------
    inner : Spline
        The original spline.
    time_scale : float
        λ of a retimed spline (new duration / old duration).
    length : float
        Path length (rad) of an arc-length spline.

    See Also
    --------
    arc_length, retime, max_angular_rate

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> s = qs.C3Spline(qs.from_rotvec([[0, 0, 0], [0, 0, 0.2], [0, 0, 1.5]]), [0, 1, 2])
    >>> r = qs.arc_length(s)
    >>> w = np.linalg.norm(r.angular_velocity(np.linspace(0, 2, 9)), axis=1)
    >>> bool(np.ptp(w) < 1e-9), round(r.length, 12)
    (True, 1.5)
    """

    inner: Spline
    time_scale: float
    length: float

    @property
    def duration(self) -> float:
        """t_end − t_start."""
        a, b = self.domain
        return b - a


def _check_spline(spline) -> Spline:
    if not isinstance(spline, Spline):
        raise TypeError(f"spline: expected a quatspline.Spline, got {type(spline).__name__}")
    if isinstance(spline, PoseCurveSpline):
        raise TypeError(
            f"spline: {type(spline).__name__} is a pose spline; retiming would keep only its "
            "rotation (pose retiming is not supported yet)"
        )
    return spline


def arc_length(spline: Spline) -> Reparameterized:
    """The same path at constant angular speed over the same time domain.

    Parameters
    ----------
    spline : Spline
        Any spline.

    Returns
    -------
    Reparameterized
        ``r(t) = spline(s(t))`` with ``|ω| = r.length / r.duration`` wherever the original
        moves; same continuity order as ``spline``; segments where it holds still are skipped.

    Raises
    ------
    TypeError
        ``spline`` is not a quatspline.Spline.
    ValueError
        The spline does not rotate (zero path length).

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> s = qs.Squad(qs.from_rotvec([[0, 0, 0], [0, 0, 0.2], [0, 0.5, 1.0]]), [0, 1, 3])
    >>> r = qs.reparameterize(s, "arc_length")
    >>> speed = np.linalg.norm(r.angular_velocity(np.linspace(0, 3, 7)), axis=1)
    >>> bool(np.ptp(speed) < 1e-12 * speed[0]), round(r.length, 6)
    (True, 1.14676)
    """
    _check_spline(spline)
    core, length = _core.arc_length_spline(spline._core)
    r = Reparameterized(core, spline.extrapolate, kind="arc_length")
    r.inner, r.time_scale, r.length = spline, float("nan"), float(length)
    return r


def max_angular_rate(spline: Spline, order: int = 1) -> tuple[float, float]:
    """(largest ``|ω|`` (order 1), ``|dω/dt|`` (2) or ``|d²ω/dt²|`` (3) over the domain, a
    time where it is reached), found by sampling every segment and refining each local maximum by
    golden-section search; the same in the world and body frames.

    Parameters
    ----------
    spline : Spline
        Any spline.
    order : {1, 2, 3}, default 1
        Angular velocity, acceleration or jerk.

    Returns
    -------
    (float, float)
        The largest norm (rad per time unit to the power ``order``) and a time where it occurs.

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.PiecewiseSlerp(qs.from_rotvec([[0, 0, 0], [0, 0, 0.5], [0, 0, 2.5]]), [0, 1, 2])
    >>> round(qs.max_angular_rate(s)[0], 12)
    2.0
    """
    _check_spline(spline)
    if order not in (1, 2, 3):
        raise ValueError(f"order: expected 1, 2 or 3, got {order!r}")
    v, t = _core.max_rate(spline._core, int(order))
    return float(v), float(t)


def _bound(v, name):
    if v is None:
        return None
    if isinstance(v, (bool, str, bytes)) or not isinstance(
        v, (int, float, np.integer, np.floating)
    ):
        raise TypeError(f"{name}: expected a number, got {type(v).__name__}")
    v = float(v)
    if not (np.isfinite(v) and v > 0):
        raise ValueError(f"{name}: expected a finite positive bound, got {v}")
    return v


#: Relative margin added to the stretch so rounding in the retimed evaluation cannot push a
#: bound over by an ulp; the bound is still met to within this factor (tight).
MARGIN = 1e-12


def retime(
    spline: Spline,
    max_angular_velocity: float | None = None,
    max_angular_acceleration: float | None = None,
    *,
    shrink: bool = False,
) -> Reparameterized:
    """Stretch time uniformly so ``|ω|`` ≤ ``max_angular_velocity`` and ``|dω/dt|`` ≤
    ``max_angular_acceleration`` everywhere (global stretch, see the module doc).

    Parameters
    ----------
    spline : Spline
        Any spline.
    max_angular_velocity, max_angular_acceleration : float, optional
        Bounds (rad/s, rad/s²), finite and positive; at least one.
    shrink : bool
        Also speed up a spline that is slower than the bounds allow (λ < 1), so the binding
        bound is met with equality; by default time is only ever stretched (λ ≥ 1).

    Returns
    -------
    Reparameterized
        ``r(t) = spline(a + (t − a)/λ)``, domain [a, a + λ(b − a)]; ``r.time_scale`` is λ
        and ``r.duration`` the new duration.

    Raises
    ------
    TypeError
        ``spline`` is not a quatspline.Spline or a bound is not a number.
    ValueError
        A bound ≤ 0 or non-finite, or no bound given.

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.NaturalSpline(qs.from_rotvec([[0, 0, 0], [0, 0, 1], [0, 1, 1]]), [0, 1, 2])
    >>> r = qs.retime(s, max_angular_velocity=0.5, max_angular_acceleration=1.0)
    >>> round(r.duration, 4), r.time_scale > 1
    (5.0278, True)
    """
    _check_spline(spline)
    w_max = _bound(max_angular_velocity, "max_angular_velocity")
    a_max = _bound(max_angular_acceleration, "max_angular_acceleration")
    if w_max is None and a_max is None:
        raise ValueError(
            "max_angular_velocity: give max_angular_velocity and/or max_angular_acceleration"
        )
    need = []
    if w_max is not None:
        need.append(max_angular_rate(spline, 1)[0] / w_max)
    if a_max is not None:
        need.append(np.sqrt(max_angular_rate(spline, 2)[0] / a_max))
    lam = max(need) * (1 + MARGIN)
    if not shrink:
        lam = max(lam, 1.0)
    if lam == 0.0:
        lam = 1.0  # a spline that does not move meets every bound at any speed
    r = Reparameterized(_core.time_scaled_spline(spline._core, float(lam)), spline.extrapolate)
    r.inner, r.time_scale, r.length = spline, float(lam), float("nan")
    return r
