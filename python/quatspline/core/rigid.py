"""Rigid bodies: body points in world coordinates along a motion."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._util.arrays import with_width
from .algebra import rotate

__all__ = ["rotate_points"]


def rotate_points(orientations: ArrayLike, points: ArrayLike) -> NDArray[np.float64]:
    """World coordinates ``u = q v q⁻¹`` of body points, at every orientation.

    Parameters
    ----------
    orientations : array_like, shape (M, 4)
        Orientations (w, x, y, z), e.g. ``s(t)`` of a spline, or a scipy ``Rotation``;
        normalised.
    points : array_like, shape (P, 3)
        Points in body coordinates.

    Returns
    -------
    numpy.ndarray, shape (M, P, 3)

    Raises
    ------
    ValueError
        If a shape is wrong, or a value is zero or not finite.

    See Also
    --------
    rotate : broadcasting rotation of vectors.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_axis_angle([0.0, 0.0, 1.0], [0.0, np.pi / 2])
    >>> qs.rotate_points(q, [[1.0, 0.0, 0.0], [0.0, 0.0, 2.0]]).round(12)
    array([[[1., 0., 0.],
            [0., 0., 2.]],
    <BLANKLINE>
           [[0., 1., 0.],
            [0., 0., 2.]]])
    """
    q = with_width(orientations, "orientations", 4)
    v = with_width(points, "points", 3)
    if q.ndim != 2:
        raise ValueError(f"orientations: expected shape (M, 4), got {q.shape}")
    if v.ndim != 2:
        raise ValueError(f"points: expected shape (P, 3), got {v.shape}")
    bad = ~np.isfinite(v).all(axis=-1)
    if bad.any():
        raise ValueError(f"points: non-finite value (NaN or inf) at element {int(np.argmax(bad))}")
    return rotate(q[:, None, :], v[None, :, :])
