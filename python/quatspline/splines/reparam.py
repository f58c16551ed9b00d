"""Path length and re-timing of a spline for an even angular speed.

:func:`path_length` is ``∫|ω| dt`` by Gauss–Legendre quadrature between the joints;
:func:`reparameterize` re-times an interpolating spline's keys by their angles
(``kind="angle"``) or traces any spline at constant angular speed (``kind="arc_length"``,
:func:`quatspline.splines.timing.arc_length`, Rust ``spline/reparam.rs``).
"""

from __future__ import annotations

import numpy as np

from .base import Spline
from .timing import arc_length

__all__ = ["path_length", "reparameterize"]


def path_length(spline: Spline, per_segment: int = 8) -> float:
    """Total rotation angle ``∫|ω| dt`` over the domain, in radians.

    Computed by Gauss–Legendre quadrature with 8 nodes on each of ``per_segment`` pieces of
    every segment.

    Parameters
    ----------
    spline : Spline
        Any spline.
    per_segment : int, default 8
        Pieces per segment.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 0]], degrees=True)
    >>> s = qs.PiecewiseSlerp(keys)
    >>> round(float(np.degrees(qs.path_length(s))), 9)
    180.0
    """
    j = spline.joints
    edges = np.concatenate(
        [np.linspace(a, b, per_segment + 1)[:-1] for a, b in zip(j[:-1], j[1:])] + [j[-1:]]
    )
    return gauss_legendre(edges, lambda t: np.linalg.norm(spline.angular_velocity(t), axis=-1))


def gauss_legendre(edges: np.ndarray, f) -> float:
    """∫ f(t) dt from ``edges[0]`` to ``edges[-1]``, by 8-point Gauss–Legendre on every interval
    between consecutive ``edges`` (place them where ``f`` is not smooth: spline joints).
    ``f`` maps an array of times (n_intervals, 8) to values of the same shape."""
    x, w = np.polynomial.legendre.leggauss(8)
    a, b = edges[:-1, None], edges[1:, None]
    return float(np.sum(0.5 * (b - a) * w * f(0.5 * (b - a) * x + 0.5 * (a + b))))


def reparameterize(spline: Spline, kind: str = "angle") -> Spline:
    """The same method through the same keys, re-timed for an even angular speed.

    ``kind="angle"``: each segment's duration becomes proportional to its rotation angle,
    keeping the start and end times, so the angular speed is (near) constant across
    segments (interpolating methods made from keys and times). ``kind="arc_length"`` works
    for ANY spline: the same path at exactly constant angular speed over the same domain,
    with exact derivatives (``quatspline.splines.timing.arc_length``).

    Parameters
    ----------
    spline : Spline
        An interpolating spline made from keys and times (``PiecewiseSlerp``, ``Squad``,
        ``CatmullRom``, ``NaturalSpline``, ``C3Spline``, the baselines).
    kind : {"angle", "arc_length"}, default "angle"
        Re-timing rule.

    Returns
    -------
    Spline
        A new spline of the same class (the input itself if every key is the same).

    Raises
    ------
    ValueError
        If ``kind`` is unknown or the spline is not built from keys at times.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 10], [0, 0, 100]], degrees=True)
    >>> s = qs.reparameterize(qs.PiecewiseSlerp(keys, [0.0, 1.0, 2.0]))
    >>> s.joints.round(6)
    array([0. , 0.2, 2. ])
    """
    if kind == "arc_length":
        return arc_length(spline)
    if kind != "angle":
        raise ValueError(f"kind: expected 'angle' or 'arc_length', got {kind!r}")
    if "quats" not in spline.params:
        raise ValueError(
            f"reparameterize: {type(spline).__name__} is not built from keys at times; "
            "angle reparameterisation needs an interpolating spline"
        )
    q = spline.params["quats"]
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    ang = 2 * np.arctan2(
        np.linalg.norm(q[1:] - q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
        np.linalg.norm(q[1:] + q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
    )
    a, b = spline.domain
    total = ang.sum()
    if total == 0:
        return spline
    share = np.maximum(ang, 1e-9 * total)
    times = a + (b - a) * np.concatenate([[0.0], np.cumsum(share) / share.sum()])
    times[-1] = b
    params = dict(spline.params, times=times)
    return type(spline)(**params, extrapolate=spline.extrapolate)
