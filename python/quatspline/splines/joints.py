"""Continuity certificates: what is true at every joint of a spline.

``continuity(spline)`` returns one :class:`JointContinuity` per interior joint (and, for a
closed loop, the seam: index = number of segments, the end against the start) with the jumps
of q, q', q'', q''' (absolute and relative; with ``order=4`` or ``5`` also the 4th and 5th
derivatives, so C⁴ splines such as the jerk-penalised fit can be certified), the parametric
order C^k reached, and the fitted
geometric constraints G¹ (R₁ = ξ L₁) and G² (R₂ = ξ² L₂ + δ L₁) with their residuals. For a
``BetaSpline`` it adds the residuals of the paper's own constraints with ξ = β_{i,1},
δ = β_{i,2} (in the local parameter) and of the corrected Theorem-2 condition: the library
reports that the Beta spline is G¹ exactly and not G² in general.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._util.checks import integer, real
from .base import Spline

__all__ = ["JointContinuity", "continuity"]


@dataclass(frozen=True)
class JointContinuity:
    """What is true at one interior joint of a spline (made by :func:`continuity`).

    Parameters
    ----------
    index : int
        Joint number (1 is the joint between segments 0 and 1).
    time : float
        Time of the joint.
    jump_abs, jump_rel : numpy.ndarray, shape (order + 1,)
        Absolute and relative jumps of q, q', … across the joint.
    order : int
        Parametric order C^k reached.
    g1_xi, g1_residual, g2_delta, g2_residual : float
        Fitted G¹/G² constants ξ, δ and the residuals of the fits.
    beta_g1_residual, beta_g2_residual, theorem2_residual, second_derivative : float or None
        For a :class:`BetaSpline` only (else ``None``): the paper's own G¹/G² residuals, the
        corrected Theorem 2 residual and the size of ``s''`` they compare with.

    Examples
    --------
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 90, 90]], degrees=True)
    >>> (j,) = qs.continuity(qs.NaturalSpline(keys))
    >>> j.index, j.time, j.order
    (1, 1.0, 2)
    """

    index: int
    """Joint number (1 is the joint between segments 0 and 1)."""
    time: float
    """Time of the joint."""
    jump_abs: np.ndarray
    """``|R_m − L_m|`` for m = 0 … max(3, order) (time derivatives)."""
    jump_rel: np.ndarray
    """Jumps relative to ``max(|L_m|, |R_m|, 1e-4 × the largest |q^(m)|)`` at joints and
    midpoints."""
    order: int
    """Parametric order C^k reached (−1 if even the positions differ)."""
    g1_xi: float
    g1_residual: float
    g2_delta: float
    g2_residual: float
    beta_g1_residual: float | None = None
    """BetaSpline: ``|sᵢ'(0) − β_{i,1} s_{i−1}'(1)|`` (local parameter)."""
    beta_g2_residual: float | None = None
    """BetaSpline: ``|sᵢ''(0) − β_{i,1}² s_{i−1}''(1) − β_{i,2} s_{i−1}'(1)|``."""
    theorem2_residual: float | None = None
    """BetaSpline: residual of the corrected Theorem-2 condition (G² residual = 6/γᵢ × this)."""
    second_derivative: float | None = None
    """BetaSpline: ``|sᵢ''(0)|``, the size the G² residual compares with."""


def continuity(spline: Spline, order: int = 3, tol: float = 1e-9) -> list[JointContinuity]:
    """The continuity certificate of every interior joint of a spline.

    At each joint q and its first three (with ``order`` 4 or 5: five) time derivatives are
    evaluated from the
    two segments' own formulas (exact, not finite differences) and compared; the geometric
    conditions G¹ (``s_i' = ξ s_{i−1}'``) and G² are fitted, and for a :class:`BetaSpline`
    the Beta paper's own residuals are reported.

    Parameters
    ----------
    spline : Spline
        Any spline.
    order : {0, 1, 2, 3, 4, 5}, default 3
        Highest derivative order to compare (4 and 5 certify C⁴ splines such as the
        jerk-penalised fit and ``MinimumEnergySpline(penalty="jerk")``).
    tol : float, default 1e-9
        A jump counts as zero when its relative size is at most ``tol``.

    Returns
    -------
    list of JointContinuity
        One record per interior joint, in time order (empty for a single open segment); a
        closed loop (``spline.closed``) adds the seam last, its index the number of segments.

    Raises
    ------
    TypeError
        If ``order`` is not an integer or ``tol`` not a real number.
    ValueError
        If ``order`` is not 0–5 or ``tol`` is not a positive finite number.

    Examples
    --------
    >>> import quatspline as qs
    >>> angles = [[0, 0, 0], [0, 0, 90], [0, 90, 90], [90, 90, 0]]
    >>> keys = qs.from_euler("xyz", angles, degrees=True)
    >>> [j.order for j in qs.continuity(qs.Squad(keys))]
    [1, 1]
    >>> [j.order for j in qs.continuity(qs.C3Spline(keys))]
    [3, 3]
    >>> j = qs.continuity(qs.PiecewiseSlerp(keys))[0]
    >>> j.time, j.order, bool(j.jump_rel[1] > 0.1)  # slerp: the velocity jumps
    (1.0, 0, True)
    """
    order = integer(order, "order", 0, 5)
    tol = real(tol, "tol", positive=True)
    beta = spline._core.beta_residuals()
    by_joint = {b[0]: b for b in beta} if beta is not None else {}
    out = []
    for idx, time, ja, jr, k, xi, g1, delta, g2 in spline._core.continuity_report(order, tol):
        extra = {}
        # Beta joints are numbered like the paper's segments: report joint idx ↔ paper idx + 1
        b = by_joint.get(idx + 1)
        if b is not None:
            _, bg1, bg2, th2, _gamma, s2 = b
            extra = dict(
                beta_g1_residual=float(np.linalg.norm(bg1)),
                beta_g2_residual=float(np.linalg.norm(bg2)),
                theorem2_residual=float(np.linalg.norm(th2)),
                second_derivative=float(s2),
            )
        out.append(
            JointContinuity(idx, time, np.array(ja), np.array(jr), k, xi, g1, delta, g2, **extra)
        )
    return out
