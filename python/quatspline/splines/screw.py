"""Screw-motion trajectories on dual quaternions (Kavan et al. 2008 for ScLerp), with exact
derivatives (Rust ``crates/quatspline/src/se3/screw_spline.rs``).

``ScrewSpline(quats, times, positions)`` interpolates pose keys as unit dual quaternions
Q̂ₖ = rₖ + ε ½ (0, tₖ) rₖ (consecutive keys sign-aligned):

- ``smooth=False`` (default): piecewise ScLerp, Q̂ᵢ (Q̂ᵢ* Q̂ᵢ₊₁)^u, u = (τ − τᵢ)/hᵢ — each
  segment is one constant screw motion; C⁰ at keys (velocity jumps), interpolating; with two
  keys it *is* ScLerp.
- ``smooth=True``: the C³ spline's cumulative form on dual quaternions,
  Q̂(τ) = P̂ᵢ₋₁ Ŵᵢ^{C̃₁} Ŵᵢ₊₁^{C̃₂} Ŵᵢ₊₂^{C̃₃} with Ŵₖ = P̂ₖ₋₁* P̂ₖ (P̂ the keys with the ends
  doubled) and the knot-variant weights C̃ⱼ of ``C3Spline`` (α, β per key): interpolating
  and C³ in time for position and orientation together.

It is a ``quatspline.Spline`` (rotation part: angular rates, continuity certificate) with
positions, linear velocity/acceleration/jerk, body and spatial twists and their derivatives
(exact: Taylor-mode jets through the screw powers), ``transform_points`` and the certificate
of the translation (``continuity_translation``). Tested: derivatives against finite
differences, certificates against one-sided differences, ScLerp on two keys.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import as_real, as_times, pose_key_order, with_width
from .se3 import PoseCurveSpline

__all__ = ["ScrewSpline"]


class ScrewSpline(PoseCurveSpline):
    """Screw-motion spline through pose keys (see the module doc).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Key orientations (w, x, y, z) or a scipy ``Rotation``; N ≥ 2.
    times : array_like, shape (N,)
        Strictly increasing key times (pandas/numpy datetimes become seconds).
    positions : array_like, shape (N, 3)
        Key positions (length units; rates are per time unit).
    smooth : bool, default False
        ``False``: piecewise ScLerp (one constant screw per segment, C⁰ at keys; two keys give
        exactly ScLerp). ``True``: the C³ spline's cumulative blending on dual quaternions
        (interpolating, C³ in time for rotation and translation together).
    alpha, beta : float or array_like, default 5/16 and 0.0
        Shape parameters of the smooth form, one value or one per key (see :class:`C3Spline`).
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain.

    Raises
    ------
    ValueError
        Shapes other than (N, 4), (N,), (N, 3), N < 2, times not finite and strictly
        increasing, or non-finite positions (the message names the argument and the index).

    See Also
    --------
    PoseSpline : orientation and position from separate splines.
    PoseBSpline : cumulative B-spline on SE(3).
    quatspline.sclerp : two poses.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_rotvec([[0, 0, 0], [0, 0, np.pi / 2]])
    >>> s = qs.ScrewSpline(q, [0.0, 1.0], [[0, 0, 0], [0, 0, 1.0]])
    >>> np.round(s.twist(0.5, frame="body"), 12)  # constant screw: ω_z = π/2, v_z = 1
    array([0.        , 0.        , 1.57079633, 0.        , 0.        , 1.        ])
    """

    def __init__(
        self,
        quats,
        times,
        positions,
        smooth: bool = False,
        alpha=5 / 16,
        beta=0.0,
        extrapolate: str = "raise",
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
        a = np.ascontiguousarray(np.atleast_1d(as_real(alpha, "alpha")), dtype=float)
        b = np.ascontiguousarray(np.atleast_1d(as_real(beta, "beta")), dtype=float)
        core = _core.screw_spline(
            np.ascontiguousarray(q), np.ascontiguousarray(p), t, bool(smooth), a, b
        )
        super().__init__(core, extrapolate, quats=q, times=t, positions=p, smooth=bool(smooth))
        self.times, self.smooth = t, bool(smooth)

    @property
    def keys(self) -> np.ndarray:
        """The pose keys as sign-aligned unit dual quaternions (N, 8)."""
        return self.dual_quaternions(self.times)
