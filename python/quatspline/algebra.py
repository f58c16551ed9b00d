"""Quaternion algebra on arrays of shape (..., 4), scalar first (w, x, y, z).

``multiply``, ``conjugate``, ``inverse``, ``exp``, ``log`` and ``power`` are exact quaternion
algebra on any finite input (``power`` and rotation functions normalise first). ``log`` uses
atan2, never acos; ``exp`` and ``log`` switch to Taylor series near the identity.
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_real, broadcast, quats, unary, with_width

__all__ = [
    "canonicalize",
    "conjugate",
    "exp",
    "inverse",
    "log",
    "multiply",
    "normalize",
    "power",
    "rotate",
]


def normalize(q) -> np.ndarray:
    """``q / |q|``. Zero (or denormal) quaternions raise ValueError."""
    return unary(_core.normalize, q, "q", 4, 4)


def multiply(p, q) -> np.ndarray:
    """Hamilton product p q (broadcasting over leading axes)."""
    shape, (a, b) = broadcast((quats(p, "p"), 4, "p"), (quats(q, "q"), 4, "q"))
    return _core.multiply(a, b).reshape((*shape, 4))


def conjugate(q) -> np.ndarray:
    """q* = (w, −x, −y, −z): the inverse rotation of a unit quaternion."""
    return unary(_core.conjugate, q, "q", 4, 4)


def inverse(q) -> np.ndarray:
    """``q⁻¹ = q* / |q|²``; a zero quaternion raises ValueError."""
    return unary(_core.inverse, q, "q", 4, 4)


def exp(q) -> np.ndarray:
    """``exp(w + v) = e^w (cos|v|, sin|v| v/|v|)``."""
    return unary(_core.exp, q, "q", 4, 4)


def log(q) -> np.ndarray:
    """Principal log ``(ln|q|, θ v/|v|)``, ``θ = atan2(|v|, w)`` ∈ [0, π]."""
    return unary(_core.log, q, "q", 4, 4)


def power(q, t) -> np.ndarray:
    """q^t = exp(t log q) of the normalised q (no shortest-path flip)."""
    q = quats(q, "q")
    shape, (a, b) = broadcast((q, 4, "q"), (as_real(t, "t"), 0, "t"))
    return _core.power(a, b).reshape((*shape, 4))


def rotate(q, vectors) -> np.ndarray:
    """Rotates vectors (..., 3) by unit quaternions: q v q* (body → world)."""
    shape, (a, b) = broadcast(
        (quats(q, "q"), 4, "q"), (with_width(vectors, "vectors", 3), 3, "vectors")
    )
    return _core.rotate(a, b).reshape((*shape, 3))


def canonicalize(q, reference=None) -> np.ndarray:
    """Sign-flips q to w ≥ 0, or (with ``reference``) to the hemisphere of the reference."""
    q = quats(q, "q")
    if reference is None:
        sign = np.where(q[..., 0] < 0, -1.0, 1.0)
    else:
        r = quats(reference, "reference")
        sign = np.where(np.sum(q * r, axis=-1) < 0, -1.0, 1.0)
    return q * sign[..., None]
