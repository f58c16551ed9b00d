"""Pose trajectories: an orientation spline (any registered method) and a position spline.

``PoseSpline(quats, times, positions, rotation="c3", translation="cubic", **params)``:
orientation and angular rates come from the rotation spline (exact derivatives), positions
from a natural cubic spline (C², zero acceleration at the ends) or piecewise-linear
interpolation (C⁰), with exact velocity and acceleration. Outside the key times both follow
``extrapolate``: "raise", "clamp" (hold the end pose), "linear" (constant angular and linear
velocity from the ends) or "periodic" (repeat).
"""

from __future__ import annotations

import numpy as np

from . import _core
from . import spline as sp
from ._arrays import as_times, pose_key_order, with_width
from .algebra import rotate
from .registry import spline as make_spline

__all__ = ["PoseSpline"]


class PoseSpline:
    """Orientation and position through pose keys."""

    def __init__(
        self,
        quats,
        times,
        positions,
        rotation: str = "c3",
        translation: str = "cubic",
        extrapolate: str = "raise",
        **params,
    ):
        if translation not in ("cubic", "linear"):
            raise ValueError(f"translation: expected 'cubic' or 'linear', got {translation!r}")
        quats, times = pose_key_order(quats, times, "PoseSpline")
        t = as_times(times, "times")
        p = with_width(positions, "positions", 3)
        if p.ndim != 2 or len(p) != len(t):
            raise ValueError(f"positions: expected shape ({len(t)}, 3), got {p.shape}")
        if extrapolate not in sp._EXTRAPOLATE:
            raise ValueError(f"extrapolate: expected one of {sp._EXTRAPOLATE}, got {extrapolate!r}")
        self.rotation = make_spline(rotation, quats, t, **params)
        self.rotation.extrapolate = extrapolate
        self.extrapolate = extrapolate
        self._times = np.ascontiguousarray(t, dtype=float)
        self._points = np.ascontiguousarray(p, dtype=float)
        if not np.all(np.isfinite(self._points)):
            k = int(np.argmax(~np.all(np.isfinite(self._points), axis=1)))
            raise ValueError(f"positions: non-finite value (NaN or inf) at element {k}")
        self._cubic = translation == "cubic"

    @property
    def domain(self) -> tuple[float, float]:
        return float(self._times[0]), float(self._times[-1])

    def _pos(self, t):
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        a, b = self.domain
        if not np.all(np.isfinite(flat)):
            k = int(np.argmax(~np.isfinite(flat)))
            raise ValueError(f"t: non-finite value (NaN or inf) at element {k}")
        outside = (flat < a) | (flat > b)
        if np.any(outside) and self.extrapolate == "raise":
            k = int(np.argmax(outside))
            raise ValueError(f"t: t[{k}] = {flat[k]} is outside the domain [{a}, {b}]")
        if self.extrapolate == "periodic":
            inside = np.clip(a + np.mod(flat - a, b - a), a, b)
            return ta.shape, _core.position_eval(self._times, self._points, self._cubic, inside)
        out = _core.position_eval(self._times, self._points, self._cubic, np.clip(flat, a, b))
        if self.extrapolate == "linear":
            # Constant velocity beyond the ends: p(e) + v(e) (t − e), zero acceleration.
            dt = flat - np.clip(flat, a, b)
            out[outside, 0:3] += out[outside, 3:6] * dt[outside, None]
            out[outside, 6:9] = 0.0
        else:
            out[outside, 3:] = 0.0
        return ta.shape, out

    def orientation(self, t) -> np.ndarray:
        return self.rotation(t)

    def position(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 0:3].reshape((*shape, 3))

    def linear_velocity(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 3:6].reshape((*shape, 3))

    def linear_acceleration(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 6:9].reshape((*shape, 3))

    def angular_velocity(self, t, frame: str = "world") -> np.ndarray:
        return self.rotation.angular_velocity(t, frame)

    def angular_acceleration(self, t, frame: str = "world") -> np.ndarray:
        return self.rotation.angular_acceleration(t, frame)

    def __call__(self, t):
        """(orientations, positions) at t."""
        return self.orientation(t), self.position(t)

    def transform_points(self, t, points) -> np.ndarray:
        """World coordinates R(t) p + x(t) of body points (P, 3) at times (M,): (M, P, 3)."""
        q = np.atleast_2d(self.orientation(np.atleast_1d(t)))
        x = np.atleast_2d(self.position(np.atleast_1d(t)))
        v = with_width(points, "points", 3).reshape(-1, 3)
        return rotate(q[:, None, :], v[None, :, :]) + x[:, None, :]
