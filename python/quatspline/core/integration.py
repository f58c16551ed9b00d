"""Orientations from angular velocity: integrating gyro-like rates.

The Rust core steps q' = ½ q ω (body) or q' = ½ ω q (world) once per sample interval:
``"zoh"`` is exact for piecewise-constant rates, ``"linear"`` is the fourth-order Magnus
(coning-corrected) step for piecewise-linear rates, ``"cubic"`` interpolates the rates with the
cubic through the four nearest samples and takes the same fourth-order step, which makes it
fourth order for samples of any smooth rate (``"linear"`` is only second order there, since
linear interpolation of a curved rate is).
"""

from __future__ import annotations

import numpy as np

from .. import _core
from .._util.arrays import as_real, with_width

__all__ = ["integrate"]

_FRAMES = ("body", "world")
_METHODS = ("zoh", "linear", "cubic")


def integrate(times, angular_velocity, q0=(1.0, 0.0, 0.0, 0.0), frame="body", method="linear"):
    """Orientations from angular-velocity samples.

    Parameters
    ----------
    times : array_like, shape (N,)
        Sample times, finite and strictly increasing.
    angular_velocity : array_like, shape (N, 3)
        ω at each time (rad per time unit), in body or world coordinates.
    q0 : array_like, shape (4,)
        The orientation at ``times[0]``, a unit quaternion (w, x, y, z) to within 1e-6.
    frame : {"body", "world"}
        Body rates (gyroscopes: q' = ½ q ω) or world rates (q' = ½ ω q).
    method : {"zoh", "linear", "cubic"}
        How ω varies between samples: held constant (exact), linear (fourth-order Magnus
        step) or the local cubic through four samples (fourth order for smooth rates).

    Returns
    -------
    numpy.ndarray, shape (N, 4)
        The orientation at every sample time; the first row is ``q0`` normalised.

    Raises
    ------
    ValueError
        Rates of the wrong shape, times not strictly increasing or non-finite, ``q0`` not a
        rotation (``|q0| ≠ 1``), an unknown frame or method.
    TypeError
        ``frame`` or ``method`` is not a string.

    Examples
    --------
    A constant rate of π/2 rad/s about z for one second turns the body a quarter turn:

    >>> import numpy as np
    >>> import quatspline as qs
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> w = np.tile([0.0, 0.0, np.pi / 2], (5, 1))
    >>> np.round(qs.as_rotvec(qs.integrate(t, w)[-1]), 12)
    array([0.        , 0.        , 1.57079633])
    """
    for name, v, allowed in (("frame", frame, _FRAMES), ("method", method, _METHODS)):
        if not isinstance(v, str):
            raise TypeError(f"{name}: expected a string, got {type(v).__name__}")
        if v not in allowed:
            raise ValueError(f"{name}: expected one of {allowed}, got {v!r}")
    t = as_real(times, "times")
    if t.ndim != 1:
        raise ValueError(f"times: expected shape (N,), got {t.shape}")
    w = with_width(angular_velocity, "angular_velocity", 3)
    if w.shape != (len(t), 3):
        raise ValueError(
            f"angular_velocity: expected shape ({len(t)}, 3), one rate per time, got {w.shape}"
        )
    q = as_real(q0, "q0")
    if q.shape != (4,):
        raise ValueError(f"q0: expected shape (4,), got {q.shape}")
    return _core.integrate_rates(
        np.ascontiguousarray(t),
        np.ascontiguousarray(w),
        [float(x) for x in q],
        frame,
        method,
    )
