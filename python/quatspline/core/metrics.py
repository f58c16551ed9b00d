"""Distances between rotations.

One function, :func:`angle_between`, is the rotation distance used everywhere in quatspline
(``compare --holdout``, ``benchmarks/accuracy.py``, the README's accuracy table).
"""

from __future__ import annotations

import numpy as np

from .._util.arrays import broadcast, quats

__all__ = ["angle_between"]


def angle_between(a, b, degrees: bool = False) -> np.ndarray:
    """The angle of the rotation that takes orientation ``a`` to orientation ``b``.

    This is the full rotation angle θ ∈ [0, π] of a⁻¹ b (the geodesic distance on SO(3)), the
    same quantity as scipy's ``(r1.inv() * r2).magnitude()``. q and −q are the same rotation,
    so the result does not depend on the signs of ``a`` and ``b``.

    It is computed as ``θ = 4 atan2(|a − s b|, |a + s b|)`` with ``s = sign(a · b)`` on the
    normalised quaternions: for unit a, b with a · b = cos(θ/2) ≥ 0, ``|a − b| = 2 sin(θ/4)`` and
    ``|a + b| = 2 cos(θ/4)``. Unlike ``2 acos(|a · b|)`` this keeps full relative accuracy near 0
    (1e-12 rad is returned to ~1e-4 relative error, the limit set by rounding a and b) and
    is exact up to rounding near π.

    Parameters
    ----------
    a, b : array_like, shape (..., 4)
        Quaternions (w, x, y, z), scalar first. They need not be unit (each is normalised)
        and their batch shapes broadcast like numpy's.
    degrees : bool, default False
        Return degrees instead of radians.

    Returns
    -------
    numpy.ndarray, shape (...)
        The angles, in [0, π] (or [0, 180] with ``degrees=True``).

    Raises
    ------
    ValueError
        If ``a`` or ``b`` is not of shape (..., 4), holds NaN or inf, has zero norm, or the
        batch shapes do not broadcast (the message names the argument).
    TypeError
        If ``degrees`` is not a bool.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline import angle_between, from_axis_angle
    >>> identity = np.array([1.0, 0.0, 0.0, 0.0])
    >>> quarter = from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)
    >>> float(angle_between(identity, quarter, degrees=True))
    90.0
    >>> float(angle_between(quarter, -quarter))  # q and -q are the same rotation
    0.0
    """
    if not isinstance(degrees, (bool, np.bool_)):
        raise TypeError(f"degrees: expected a bool, got {type(degrees).__name__}")
    qa, qb = quats(a, "a"), quats(b, "b")
    shape, (fa, fb) = broadcast((qa, 4, "a"), (qb, 4, "b"))
    for name, f in (("a", fa), ("b", fb)):
        bad = ~np.all(np.isfinite(f), axis=1)
        if np.any(bad):
            k = int(np.argmax(bad))
            raise ValueError(f"{name}: non-finite value (NaN or inf) at index {k}")
    na = np.linalg.norm(fa, axis=1)
    nb = np.linalg.norm(fb, axis=1)
    for name, n in (("a", na), ("b", nb)):
        tiny = n < 1e-150
        if np.any(tiny):
            raise ValueError(
                f"{name}: quaternion {int(np.argmax(tiny))} has zero (or too small) norm"
            )
    ua, ub = fa / na[:, None], fb / nb[:, None]
    s = np.where(np.sum(ua * ub, axis=1) < 0, -1.0, 1.0)[:, None]
    theta = 4.0 * np.arctan2(
        np.linalg.norm(ua - s * ub, axis=1), np.linalg.norm(ua + s * ub, axis=1)
    )
    if degrees:
        theta = np.degrees(theta)
    return theta.reshape(shape)
