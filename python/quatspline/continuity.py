"""Continuity certificates: what is true at every joint of a spline (MATH.md §9).

``continuity(spline)`` returns one :class:`JointContinuity` per interior joint with the jumps
of q, q', q'', q''' (absolute and relative), the parametric order C^k reached, and the fitted
geometric constraints G¹ (R₁ = ξ L₁) and G² (R₂ = ξ² L₂ + δ L₁) with their residuals. For a
``BetaSpline`` it adds the residuals of the paper's own constraints with ξ = β_{i,1},
δ = β_{i,2} (in the local parameter) and of the corrected Theorem-2 condition: the library
reports that the Beta spline is G¹ exactly and not G² in general.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .spline import Spline

__all__ = ["JointContinuity", "continuity"]


@dataclass(frozen=True)
class JointContinuity:
    index: int
    time: float
    jump_abs: np.ndarray
    """``|R_m − L_m|`` for m = 0 … 3 (time derivatives)."""
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
    """The certificate of every interior joint of ``spline`` (orders 0 … ``order`` ≤ 3)."""
    if order not in (0, 1, 2, 3):
        raise ValueError(f"order: expected 0, 1, 2 or 3, got {order!r}")
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol: expected a finite positive tolerance, got {tol!r}")
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
