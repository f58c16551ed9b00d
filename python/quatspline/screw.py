"""Screw-motion trajectories on dual quaternions (seed 001; MATH.md §3).

``ScrewSpline(quats, times, positions)`` interpolates pose keys as unit dual quaternions
Q̂ₖ = rₖ + ε ½ (0, tₖ) rₖ (consecutive keys sign-aligned):

- ``smooth=False`` (default): piecewise ScLerp, Q̂ᵢ (Q̂ᵢ* Q̂ᵢ₊₁)^u, u = (τ − τᵢ)/hᵢ — each
  segment is one constant screw motion; C⁰ at keys (velocity jumps), interpolating; with two
  keys it *is* ScLerp.
- ``smooth=True``: the C³ spline's cumulative form on dual quaternions,
  Q̂(τ) = P̂ᵢ₋₁ Ŵᵢ^{C̃₁} Ŵᵢ₊₁^{C̃₂} Ŵᵢ₊₂^{C̃₃} with Ŵₖ = P̂ₖ₋₁* P̂ₖ (P̂ the keys with the ends
  doubled) and the knot-variant weights C̃ⱼ of ``C3Spline`` (α, β per key): interpolating
  and C³ in time for position and orientation together by construction (the powers are smooth
  screw motions and the weights are C³; the argument of MATH.md §8 holds in any Lie group).
  What the tests check: interpolation, and velocity continuity at keys by one-sided differences
  (no analytic derivatives are offered for ScrewSpline).
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_times, pose_key_order, with_width
from .dualquat import dq_from_pose, dq_multiply, dq_power, dq_to_pose, dq_transform_point, sclerp

__all__ = ["ScrewSpline"]


class ScrewSpline:
    def __init__(self, quats, times, positions, smooth: bool = False, alpha=5 / 16, beta=0.0):
        quats, times = pose_key_order(quats, times, "ScrewSpline")
        t = np.ascontiguousarray(as_times(times, "times"), dtype=float)
        q = with_width(quats, "quats", 4)
        p = with_width(positions, "positions", 3)
        if t.ndim != 1 or q.shape != (len(t), 4) or p.shape != (len(t), 3):
            raise ValueError(
                "times/quats/positions: expected (N,), (N, 4), (N, 3); "
                f"got {t.shape}, {q.shape}, {p.shape}"
            )
        if len(t) < 2:
            raise ValueError(f"quats: needs at least 2 keys, got {len(t)}")
        if not np.all(np.isfinite(t)):
            raise ValueError(
                f"times: non-finite value at element {int(np.argmax(~np.isfinite(t)))}"
            )
        bad = np.diff(t) <= 0
        if np.any(bad):
            k = int(np.argmax(bad)) + 1
            raise ValueError(
                f"times: not strictly increasing at index {k} ({t[k]} after {t[k - 1]})"
            )
        dq = dq_from_pose(q, p)
        for k in range(1, len(dq)):
            if np.dot(dq[k - 1, :4], dq[k, :4]) < 0:
                dq[k] = -dq[k]
        self.times, self.keys, self.smooth = t, dq, bool(smooth)
        if self.smooth:
            a = np.atleast_1d(np.asarray(alpha, dtype=float))
            b = np.atleast_1d(np.asarray(beta, dtype=float))
            self._w = np.array(_core.c3_weights(t, a, b, "knot"))  # (S, 3, 8)
            padded = np.vstack([dq[:1], dq, dq[-1:]])
            conj = padded.copy()
            conj[:, 1:4] *= -1
            conj[:, 5:8] *= -1
            self._pad = padded
            self._rel = dq_multiply(conj[:-1], padded[1:])  # Ŵ₁ … Ŵ_{N+1}

    @property
    def domain(self) -> tuple[float, float]:
        return float(self.times[0]), float(self.times[-1])

    def dual_quaternions(self, t) -> np.ndarray:
        """The pose as unit dual quaternions (M, 8) at times t (inside the domain)."""
        x = np.atleast_1d(as_times(t, "t")).astype(float)
        a, b = self.domain
        if not np.all(np.isfinite(x)) or np.any((x < a) | (x > b)):
            raise ValueError(f"t: expected finite times inside the domain [{a}, {b}]")
        seg = np.clip(np.searchsorted(self.times, x, side="right") - 1, 0, len(self.times) - 2)
        u = (x - self.times[seg]) / (self.times[seg + 1] - self.times[seg])
        if not self.smooth:
            return sclerp(self.keys[seg], self.keys[seg + 1], u)
        out = self._pad[seg]
        powers = u[:, None] ** np.arange(8)
        for j in range(3):
            w = np.sum(self._w[seg, j] * powers, axis=1)
            out = dq_multiply(out, dq_power(self._rel[seg + j], w))
        return out

    def __call__(self, t):
        """(orientations (M, 4), positions (M, 3)) at t."""
        return dq_to_pose(self.dual_quaternions(t))

    def transform_points(self, t, points) -> np.ndarray:
        """World coordinates of body points (P, 3) at times (M,): (M, P, 3)."""
        d = self.dual_quaternions(t)
        v = with_width(points, "points", 3).reshape(-1, 3)
        return dq_transform_point(d[:, None, :], v[None, :, :])
