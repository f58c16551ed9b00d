"""The Beta quaternion spline (Rust ``spline/beta.rs``; He et al. 2022): approximating, G¹
exactly, not G² in general.

The paper's claim of G² is false in general; :func:`quatspline.continuity` reports the G²
residual and the residual of the corrected Theorem 2 condition instead.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .. import _core
from .base import Spline
from .keys import _keys, _per, _times

__all__ = ["BetaSpline"]


class BetaSpline(Spline):
    """The Beta quaternion spline (He et al. 2022): G¹ exactly, not G² in general.

    β₁ = 1, β₂ = 0 gives the Bézier points of the uniform cubic B-spline. The paper's claim
    of G² is false in general; :func:`quatspline.continuity` reports the G² residual and the
    residual of the corrected Theorem 2 condition instead.

    Parameters
    ----------
    vertices : array_like, shape (l + 3, 4)
        Auxiliary control vertices p₀ … p_{l+2} (at least 4), or a scipy ``Rotation``. The
        curve does not pass through them.
    beta1 : float or array_like, shape (l + 3,), default 1.0
        Bias β₁ > 0, one value or one per vertex.
    beta2 : float or array_like, shape (l + 3,), default 0.0
        Tension β₂, one value or one per vertex.
    times : array_like, shape (l + 1,), optional
        Joint times of the l segments; default 0 … l.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
        The paper's Example 1 is reproduced only with ``canonicalize=False``.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    quatspline.continuity : reports the G¹ and G² residuals.
    CumulativeBSpline

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.BetaSpline(qs.examples.BETA_EXAMPLE1_VERTICES, beta1=1.0, beta2=0.5,
    ...                   canonicalize=False)
    >>> s.control_points()[0, 0].round(4)  # the paper's q_{1,0}
    array([-0.3796,  0.4589,  0.1106,  0.7956])
    >>> (j,) = qs.continuity(s)
    >>> j.beta_g1_residual < 1e-13, round(j.beta_g2_residual, 3)  # G¹ holds, G² does not
    (True, 0.066)
    """

    def __init__(
        self,
        vertices,
        beta1=1.0,
        beta2=0.0,
        times=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        p = _keys(vertices, "vertices")
        t = _times(times, max(len(p) - 2, 0))
        super().__init__(
            _core.beta_spline(p, _per(beta1, "beta1"), _per(beta2, "beta2"), t, bool(canonicalize)),
            extrapolate,
        )

    def control_points(self) -> NDArray[np.float64]:
        """The Bézier points ``q_{i,0..3}`` of segments i = 1 … l.

        Returns
        -------
        numpy.ndarray, shape (l, 4, 4)
            Segment, point, quaternion (w, x, y, z).
        """
        return np.array(self._core.control_points())
