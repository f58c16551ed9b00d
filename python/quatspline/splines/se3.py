"""Pose splines on SE(3) with exact derivatives (Rust ``crates/quatspline/src/se3/``).

:class:`PoseCurveSpline` is the common base of :class:`~quatspline.ScrewSpline` and
:class:`~quatspline.PoseBSpline`: a ``quatspline.Spline`` whose rotation part gives every
rotation feature (``s(t)``… no: ``s.orientation(t)``, angular rates, the continuity
certificate), plus positions and their derivatives, twists in the body and spatial (world)
frame with their derivatives, dual quaternions and point transforms. ``s(t)`` returns
``(orientations, positions)`` like ``PoseSpline``.

Twists: body ξ_b = (ω_b, Rᵀṗ); spatial ξ_s = (ω, ṗ − ω × p); ``order=2, 3`` give dξ/dt and
d²ξ/dt² of the same vector (exact, from the dual-quaternion jets).
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import as_real, with_width
from ..core.algebra import conjugate, rotate
from ..core.dualquat import dq_from_pose
from .base import Spline
from .joints import JointContinuity, continuity

__all__ = ["PoseCurveSpline"]

_FRAMES = ("world", "body")


class PoseCurveSpline(Spline):
    """A pose spline: orientation r(t) (the ``Spline`` part) and position p(t)."""

    def __init__(self, pose_core, extrapolate: str = "raise", **params):
        super().__init__(pose_core.rotation(), extrapolate, **params)
        self._pose = pose_core

    def _flat(self, t):
        ta = as_real(t, "t")
        return ta.shape, np.ascontiguousarray(ta.reshape(-1))

    def orientation(self, t) -> np.ndarray:
        """Orientations (..., 4) at t."""
        return Spline.__call__(self, t)

    def position(self, t, order: int = 0) -> np.ndarray:
        """p(t) (order 0) or its order-th time derivative (1…3), world coordinates, (..., 3)."""
        if order not in (0, 1, 2, 3):
            raise ValueError(f"order: expected 0, 1, 2 or 3, got {order!r}")
        shape, flat = self._flat(t)
        out = self._pose.positions(flat, order, self.extrapolate)
        return out[:, 3 * order :].reshape((*shape, 3))

    def _linear(self, t, order, frame):
        if frame not in _FRAMES:
            raise ValueError(f"frame: expected one of {_FRAMES}, got {frame!r}")
        v = self.position(t, order)
        if frame == "world":
            return v
        return rotate(conjugate(self.orientation(t)), v)

    def linear_velocity(self, t, frame: str = "world") -> np.ndarray:
        """ṗ in world coordinates, or Rᵀṗ (``frame="body"``)."""
        return self._linear(t, 1, frame)

    def linear_acceleration(self, t, frame: str = "world") -> np.ndarray:
        """p̈ in world coordinates, or Rᵀp̈ (``frame="body"``)."""
        return self._linear(t, 2, frame)

    def linear_jerk(self, t, frame: str = "world") -> np.ndarray:
        """d³p/dt³ in world coordinates, or Rᵀ d³p/dt³ (``frame="body"``)."""
        return self._linear(t, 3, frame)

    def twist(self, t, frame: str = "body", order: int = 1) -> np.ndarray:
        """The twist (angular, linear) stacked as (..., 6): body (ω_b, Rᵀṗ) or spatial
        (``frame="world"``: ω, ṗ − ω × p); ``order`` 2 and 3 give its first and second time
        derivative."""
        if frame not in _FRAMES:
            raise ValueError(f"frame: expected one of {_FRAMES}, got {frame!r}")
        if order not in (1, 2, 3):
            raise ValueError(f"order: expected 1, 2 or 3, got {order!r}")
        shape, flat = self._flat(t)
        out = self._pose.twists(flat, order, frame == "body", self.extrapolate)
        return out.reshape((*shape, 6))

    def dual_quaternions(self, t) -> np.ndarray:
        """The pose as unit dual quaternions (..., 8): r + ε ½ p r."""
        return dq_from_pose(self.orientation(t), self.position(t))

    def __call__(self, t):
        """(orientations (..., 4), positions (..., 3)) at t."""
        return self.orientation(t), self.position(t)

    def transform_points(self, t, points) -> np.ndarray:
        """World coordinates R(t) v + p(t) of body points (P, 3) at times (M,): (M, P, 3)."""
        tt = np.atleast_1d(as_real(t, "t"))
        q, x = self.orientation(tt), self.position(tt)
        v = with_width(points, "points", 3).reshape(-1, 3)
        return rotate(q[:, None, :], v[None, :, :]) + x[:, None, :]

    def continuity_translation(self, order: int = 3, tol: float = 1e-9) -> list[JointContinuity]:
        """The certificate of the dual part d(t) = ½ p r at every joint (the rotation's is
        ``quatspline.continuity(s)``); the pose is C^k at a joint when both reach k."""
        return continuity(Spline(self._pose.dual_part()), order, tol)


def _pose_args(quats, positions, qname):
    q = with_width(quats, qname, 4)
    p = with_width(positions, "positions", 3)
    if q.ndim != 2:
        raise ValueError(f"{qname}: expected shape (N, 4), got {q.shape}")
    if p.shape != (len(q), 3):
        raise ValueError(
            f"positions: expected shape ({len(q)}, 3), one per rotation, got {p.shape}"
        )
    return np.ascontiguousarray(q), np.ascontiguousarray(p)


def _check_core(x):  # pragma: no cover - keeps the import used for type checkers
    return isinstance(x, _core.PoseCurve)
