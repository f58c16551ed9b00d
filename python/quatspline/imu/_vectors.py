"""Small helpers shared by the simulation and the integration: gravity and row-wise vector
products (written out: numpy's ``cross`` and a BLAS 3×3 product cost more than the
arithmetic for millions of rows)."""

from __future__ import annotations

import numpy as np

from .._util.arrays import as_real

#: Standard gravity (m/s², ISO 80000-3), pointing down the world z axis.
GRAVITY = (0.0, 0.0, -9.80665)


def gravity_vector(value) -> np.ndarray:
    """The gravity argument as a finite 3-vector."""
    g = as_real(value, "gravity")
    if g.shape != (3,):
        raise ValueError(f"gravity: expected 3 numbers, got shape {g.shape}")
    if not np.all(np.isfinite(g)):
        raise ValueError("gravity: not finite")
    return g


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a × b for arrays of shape (N, 3) (either may be one (3,) vector)."""
    a = np.broadcast_to(a, np.broadcast_shapes(np.shape(a), np.shape(b)))
    b = np.broadcast_to(b, a.shape)
    out = np.empty(a.shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def times(matrix: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """``matrix @ v`` for each row v of ``vectors`` (N, 3)."""
    return np.einsum("ij,nj->ni", matrix, vectors)
