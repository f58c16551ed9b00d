"""Rigid bodies: body points in world coordinates along a motion."""

from __future__ import annotations

import numpy as np

from ._arrays import with_width
from .algebra import rotate

__all__ = ["rotate_points"]


def rotate_points(orientations, points) -> np.ndarray:
    """World coordinates u = q v q⁻¹ of body points: orientations (M, 4), points (P, 3) →
    (M, P, 3). Orientations are normalised."""
    q = with_width(orientations, "orientations", 4)
    v = with_width(points, "points", 3)
    if q.ndim != 2:
        raise ValueError(f"orientations: expected shape (M, 4), got {q.shape}")
    if v.ndim != 2:
        raise ValueError(f"points: expected shape (P, 3), got {v.shape}")
    return rotate(q[:, None, :], v[None, :, :])
