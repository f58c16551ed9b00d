"""Two-keyframe interpolation, vectorised with numpy broadcasting.

Every function takes keys of shape (..., 4) and parameters t of any shape that broadcasts
against the keys' batch shape; the result has shape broadcast(...) + (4,). Keys are normalised.

| function | formula | speed | source |
|---|---|---|---|
| ``lerp`` | (1−t) q₀ + t q₁ (not unit) | — | seed 001 |
| ``nlerp`` | lerp / ‖lerp‖, shortest arc | varies | seed 001 |
| ``slerp`` | q₀ (q₀* q₁)^t, shortest arc | constant | Shoemake 1985, seeds 001/003 |
| ``lin_euler`` | Euler angles lerped (baseline) | varies | seed 002 |
| ``lin_mat`` | matrices lerped, projected by SVD (baseline) | varies | seed 002 |
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_real, broadcast, quats

__all__ = ["lerp", "lin_euler", "lin_mat", "nlerp", "slerp"]


def _pair(fn, q0, q1, t, *extra):
    shape, (a, b, tt) = broadcast(
        (quats(q0, "q0"), 4, "q0"), (quats(q1, "q1"), 4, "q1"), (as_real(t, "t"), 0, "t")
    )
    return fn(a, b, tt, *extra).reshape((*shape, 4))


def lerp(q0, q1, t) -> np.ndarray:
    """(1−t) q₀ + t q₁ componentwise: not a unit quaternion, no sign flip, keys as given."""
    return _pair(_core.lerp, q0, q1, t)


def nlerp(q0, q1, t, long_path: bool = False) -> np.ndarray:
    """Normalised lerp on the shortest arc (q₁ → −q₁ when q₀·q₁ < 0 unless ``long_path``)."""
    return _pair(_core.nlerp, q0, q1, t, bool(long_path))


def slerp(q0, q1, t, long_path: bool = False) -> np.ndarray:
    """Spherical linear interpolation q₀ (q₀* q₁)^t: constant angular speed, fixed axis.

    Shortest path by default (q₁ is replaced by −q₁ when q₀·q₁ < 0, so at t = 1 the result
    is that representative); ``long_path=True`` keeps q₁ as given. Exact at t = 0 and 1; stable
    for nearly equal keys (Taylor weights) and for nearly opposite ones.

    Exactly opposite keys with ``long_path=True`` (q₁ = −q₀, a full turn with no axis of its
    own) turn about q₀'s body x axis: ``slerp(q, -q, t, True) = q ⊗ (cos πt, sin πt, 0, 0)``,
    a unit quaternion rotating by 2πt about the world axis R(q) eₓ.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> q = np.array([0, 0, 1, 1]) / np.sqrt(2)
    >>> m = qs.slerp(q, -q, 0.75, long_path=True)
    >>> float(np.linalg.norm(m))
    1.0
    """
    return _pair(_core.slerp, q0, q1, t, bool(long_path))


def lin_euler(q0, q1, t, seq: str = "xyz") -> np.ndarray:
    """Baseline: lerp the Euler angles (sequence ``seq``, each difference wrapped to (−π, π])."""
    return _pair(_core.lin_euler, q0, q1, t, str(seq))


def lin_mat(q0, q1, t) -> np.ndarray:
    """Baseline: lerp the rotation matrices entrywise, project back to SO(3) by SVD."""
    return _pair(_core.lin_mat, q0, q1, t)
