"""Cumulative B-spline of poses (SE(3)), uniform or non-uniform knots, exact derivatives
(Rust ``crates/quatspline/src/se3/pose_bspline.rs``; Sommer et al., CVPR 2020; basalt).

``PoseBSpline(control_quats, control_positions, dt=…, t0=…, order=4)`` or ``knots=…`` (the
knot conventions of ``CumulativeBSpline``: n + k knots, domain [u_{k−1}, u_n]):

- ``formulation="se3"`` (default): T(t) = T_{i} Π (T_{j−1}⁻¹ Tⱼ)^{B̃ⱼ(t)} with screw powers —
  the cumulative B-spline on SE(3) itself, rotation and translation coupled;
- ``formulation="split"``: SO(3) cumulative B-spline × Euclidean B-spline of positions, the
  representation basalt uses; positions are linear in the control positions, which is what a
  least-squares pose fit wants (see the 2.4 report).

C^(k−2) for simple knots (C^(k−1−μ) at a knot of multiplicity μ) in rotation and position,
certified by ``quatspline.continuity(s)`` and ``s.continuity_translation()``.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import as_real
from .._util.checks import short
from .knots import knots_from_spacing
from .se3 import PoseCurveSpline, _pose_args

__all__ = ["PoseBSpline"]

_FORMULATIONS = ("se3", "split")


class PoseBSpline(PoseCurveSpline):
    """Cumulative pose B-spline (see the module doc).

    Parameters
    ----------
    control_quats : array_like, shape (n, 4)
        Control rotations.
    control_positions : array_like, shape (n, 3)
        Control positions.
    dt : float or array_like
        Uniform knot spacing, or the n + k − 1 knot spacings.
    t0 : float
        Start of the domain (u_{k−1}).
    order : int
        k (4 = cubic), 2 … 12.
    knots : array_like, optional
        The n + k knots instead of ``dt``/``t0``.
    formulation : {"se3", "split"}
        Coupled screw powers or separate rotation and position B-splines.
    extrapolate : {"raise", "clamp"}

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_rotvec(np.outer(np.arange(5.0), [0, 0, 0.3]))
    >>> p = np.outer(np.arange(5.0), [1.0, 0, 0])
    >>> s = qs.PoseBSpline(q, p, dt=0.5, order=4)
    >>> s.domain, np.round(s.twist(0.25, frame="body")[2], 12)
    ((0.0, 1.0), np.float64(0.6))
    """

    def __init__(
        self,
        control_quats,
        control_positions,
        dt=1.0,
        t0: float = 0.0,
        order: int = 4,
        knots=None,
        formulation: str = "se3",
        extrapolate: str = "raise",
    ):
        if not isinstance(formulation, str):
            raise TypeError(f"formulation: expected a string, got {type(formulation).__name__}")
        if formulation not in _FORMULATIONS:
            raise ValueError(f"formulation: expected one of {_FORMULATIONS}, got {formulation!r}")
        if isinstance(order, bool) or not isinstance(order, (int, np.integer)):
            raise TypeError(f"order: expected an int, got {type(order).__name__}")
        if not 2 <= order <= 12:
            raise ValueError(f"order: expected 2 ≤ order ≤ 12, got {short(order)}")
        q, p = _pose_args(control_quats, control_positions, "control_quats")
        n, k = len(q), int(order)
        if knots is not None:
            if np.ndim(dt) != 0 or dt != 1.0 or t0 != 0.0:
                raise ValueError("knots: give either knots or dt/t0, not both")
            u = as_real(knots, "knots")
            if u.ndim != 1:
                raise ValueError(f"knots: expected a 1-D knot vector, got shape {u.shape}")
        elif np.ndim(dt) == 0:
            step = float(as_real(dt, "dt"))
            if not (np.isfinite(step) and step > 0):
                raise ValueError(f"dt: expected a finite positive spacing, got {step}")
            u = float(t0) + (np.arange(n + k) - (k - 1)) * step
        else:
            u = knots_from_spacing(dt, t0, n, k)
        core = _core.pose_bspline(q, p, np.ascontiguousarray(u, dtype=float), k, formulation)
        super().__init__(core, extrapolate, formulation=formulation, order=k)
        self.knots = np.asarray(u, dtype=float)
