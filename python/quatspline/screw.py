"""Screw-motion trajectories on dual quaternions (Kavan et al. 2008 for ScLerp).

``ScrewSpline(quats, times, positions)`` interpolates pose keys as unit dual quaternions
Q̂ₖ = rₖ + ε ½ (0, tₖ) rₖ (consecutive keys sign-aligned):

- ``smooth=False`` (default): piecewise ScLerp, Q̂ᵢ (Q̂ᵢ* Q̂ᵢ₊₁)^u, u = (τ − τᵢ)/hᵢ — each
  segment is one constant screw motion; C⁰ at keys (velocity jumps), interpolating; with two
  keys it *is* ScLerp.
- ``smooth=True``: the C³ spline's cumulative form on dual quaternions,
  Q̂(τ) = P̂ᵢ₋₁ Ŵᵢ^{C̃₁} Ŵᵢ₊₁^{C̃₂} Ŵᵢ₊₂^{C̃₃} with Ŵₖ = P̂ₖ₋₁* P̂ₖ (P̂ the keys with the ends
  doubled) and the knot-variant weights C̃ⱼ of ``C3Spline`` (α, β per key): interpolating
  and C³ in time for position and orientation together by construction (the powers are smooth
  screw motions and the weights are C³; the argument for the C³ spline holds in any Lie
  group).
  What the tests check: interpolation, and velocity continuity at keys by one-sided differences
  (no analytic derivatives are offered for ScrewSpline).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._arrays import as_times, pose_key_order, with_width
from .dualquat import dq_from_pose, dq_multiply, dq_power, dq_to_pose, dq_transform_point, sclerp

__all__ = ["ScrewSpline"]


class ScrewSpline:
    """Poses interpolated as unit dual quaternions: rotation and translation move together.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Key orientations (w, x, y, z) or a scipy ``Rotation``; N ≥ 2.
    times : array_like, shape (N,)
        Strictly increasing key times; pandas and numpy datetimes become seconds.
    positions : array_like, shape (N, 3)
        Key positions.
    smooth : bool, default False
        ``False``: piecewise ScLerp, one constant screw motion per segment (C⁰ at the keys;
        with two keys it *is* ScLerp). ``True``: the C³ spline's cumulative blending on dual
        quaternions (interpolating, C³ in time for rotation and translation together).
    alpha, beta : float or array_like, default 5/16 and 0.0
        Shape parameters of the smooth form, per key (see :class:`C3Spline`).

    Raises
    ------
    ValueError
        If the shapes are not (N, 4), (N,), (N, 3), N < 2, or the times are not finite and
        strictly increasing.

    Notes
    -----
    No analytic derivatives are offered. The old argument order ``(times, quats,
    positions)`` still works with a ``DeprecationWarning`` until 0.3.

    See Also
    --------
    PoseSpline : orientation and position from separate splines, with exact derivatives.
    quatspline.sclerp : two poses.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90]], degrees=True)
    >>> s = qs.ScrewSpline(keys, [0.0, 1.0], [[0, 0, 0], [0, 0, 1]])
    >>> q, x = s(0.5)  # a quarter turn about z while rising: the midpoint of the screw
    >>> x.round(12)
    array([[0. , 0. , 0.5]])
    """

    def __init__(
        self,
        quats: ArrayLike,
        times: ArrayLike,
        positions: ArrayLike,
        smooth: bool = False,
        alpha: ArrayLike = 5 / 16,
        beta: ArrayLike = 0.0,
    ):
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
        """(first key time, last key time)."""
        return float(self.times[0]), float(self.times[-1])

    def dual_quaternions(self, t: ArrayLike) -> NDArray[np.float64]:
        """The poses as unit dual quaternions.

        Parameters
        ----------
        t : array_like, shape (M,) or scalar
            Times inside the domain.

        Returns
        -------
        numpy.ndarray, shape (M, 8)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain.

        Examples
        --------
        >>> import quatspline as qs
        >>> s = qs.ScrewSpline([[1, 0, 0, 0], [1, 0, 0, 0]], [0, 2], [[0, 0, 0], [2, 0, 0]])
        >>> s.dual_quaternions([0.0, 1.0])
        array([[1. , 0. , 0. , 0. , 0. , 0. , 0. , 0. ],
               [1. , 0. , 0. , 0. , 0. , 0.5, 0. , 0. ]])
        """
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

    def __call__(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(orientations (M, 4), positions (M, 3)) at times ``t``."""
        return dq_to_pose(self.dual_quaternions(t))

    def transform_points(self, t: ArrayLike, points: ArrayLike) -> NDArray[np.float64]:
        """World coordinates of points fixed in the body.

        Parameters
        ----------
        t : array_like, shape (M,) or scalar
            Times inside the domain.
        points : array_like, shape (P, 3)
            Points in body coordinates.

        Returns
        -------
        numpy.ndarray, shape (M, P, 3)

        Raises
        ------
        ValueError
            If a time is outside the domain or ``points`` is not of shape (P, 3).

        Examples
        --------
        >>> import quatspline as qs
        >>> s = qs.ScrewSpline([[1, 0, 0, 0], [1, 0, 0, 0]], [0, 2], [[0, 0, 0], [2, 0, 0]])
        >>> s.transform_points(1.0, [[0.0, 1.0, 0.0]])
        array([[[1., 1., 0.]]])
        """
        d = self.dual_quaternions(t)
        v = with_width(points, "points", 3).reshape(-1, 3)
        return dq_transform_point(d[:, None, :], v[None, :, :])
