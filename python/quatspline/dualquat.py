"""Dual quaternions for rigid-body poses: arrays of shape (..., 8).

Layout: real part (w, x, y, z) then dual part (w, x, y, z). A pose with rotation r and
translation t is q̂ = r + ε ½ (0, t) r and maps a point p to r p r* + t (MATH.md §3).
Inputs are normalised (|r| = 1, r·d = 0) before use.
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_real, broadcast, quats, unary, with_width

__all__ = [
    "dlb",
    "dq_conjugate",
    "dq_from_pose",
    "dq_multiply",
    "dq_normalize",
    "dq_power",
    "dq_screw",
    "dq_to_pose",
    "dq_transform_point",
    "sclerp",
]


def _dq(x, name):
    return with_width(x, name, 8)


def dq_from_pose(q, t) -> np.ndarray:
    """Dual quaternions (..., 8) of rotations q (..., 4) and translations t (..., 3)."""
    shape, (a, b) = broadcast((quats(q, "q"), 4, "q"), (with_width(t, "t", 3), 3, "t"))
    return _core.dq_from_pose(a, b).reshape((*shape, 8))


def dq_to_pose(dq) -> tuple[np.ndarray, np.ndarray]:
    """(rotation (..., 4), translation (..., 3)) of dual quaternions (normalised first)."""
    a = _dq(dq, "dq")
    out = _core.dq_to_pose(a.reshape(-1, 8)).reshape((*a.shape[:-1], 7))
    return np.ascontiguousarray(out[..., :4]), np.ascontiguousarray(out[..., 4:])


def dq_normalize(dq) -> np.ndarray:
    """q̂ / ‖q̂‖ with ‖q̂‖ = |r| + ε (r·d)/|r|: unit real part, r·d = 0."""
    return unary(_core.dq_normalize, dq, "dq", 8, 8)


def dq_multiply(a, b) -> np.ndarray:
    """(r₁ + εd₁)(r₂ + εd₂) = r₁r₂ + ε(r₁d₂ + d₁r₂): pose a after pose b."""
    shape, (x, y) = broadcast((_dq(a, "a"), 8, "a"), (_dq(b, "b"), 8, "b"))
    return _core.dq_multiply(x, y).reshape((*shape, 8))


def dq_conjugate(dq, kind: str = "quaternion") -> np.ndarray:
    """``kind``: "quaternion" (r*, d*) = inverse pose, "dual" (r, −d), "both" (r*, −d*)."""
    kinds = {"quaternion": 0, "dual": 1, "both": 2}
    if kind not in kinds:
        raise ValueError(f"kind: expected one of {sorted(kinds)}, got {kind!r}")
    a = _dq(dq, "dq")
    return _core.dq_conjugate(a.reshape(-1, 8), kinds[kind]).reshape(a.shape)


def dq_transform_point(dq, points) -> np.ndarray:
    """r p r* + t for points (..., 3)."""
    shape, (a, b) = broadcast(
        (_dq(dq, "dq"), 8, "dq"), (with_width(points, "points", 3), 3, "points")
    )
    return _core.dq_transform_point(a, b).reshape((*shape, 3))


def dq_screw(dq) -> dict[str, np.ndarray]:
    """Screw parameters: axis (..., 3), angle, displacement (signed, along the axis), moment.

    A pure translation has angle 0, axis t/|t| and zero moment.
    """
    a = _dq(dq, "dq")
    out = _core.dq_screw(a.reshape(-1, 8)).reshape((*a.shape[:-1], 8))
    return {
        "axis": out[..., 0:3],
        "angle": out[..., 3],
        "displacement": out[..., 4],
        "moment": out[..., 5:8],
    }


def dq_power(dq, t, long_path: bool = False) -> np.ndarray:
    """q̂^t on the screw: rotate t·θ about, and slide t·d along, the screw axis.

    q̂ and −q̂ are the same pose; by default the power follows the shortest screw (the
    representative with rotation part w ≥ 0, θ ∈ [0, π]), so ``dq_power(-q̂, t)`` and
    ``dq_power(q̂, t)`` are the same pose. ``long_path=True`` keeps the sign as given (θ up to
    2π, the other way round the screw), as ``slerp``'s ``long_path`` does.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> d = qs.dq_from_pose(qs.from_axis_angle([0, 0, 1], 3.0), [1.0, 0, 0])
    >>> a, b = qs.dq_power(d, 0.5), qs.dq_power(-d, 0.5)
    >>> bool(np.allclose(a, b) or np.allclose(a, -b))
    True
    """
    shape, (a, b) = broadcast((_dq(dq, "dq"), 8, "dq"), (as_real(t, "t"), 0, "t"))
    return _core.dq_power(a, b, bool(long_path)).reshape((*shape, 8))


def sclerp(dq0, dq1, t) -> np.ndarray:
    """Screw linear interpolation q̂₀ (q̂₀* q̂₁)^t along the shortest screw."""
    shape, (a, b, tt) = broadcast(
        (_dq(dq0, "dq0"), 8, "dq0"), (_dq(dq1, "dq1"), 8, "dq1"), (as_real(t, "t"), 0, "t")
    )
    return _core.sclerp(a, b, tt).reshape((*shape, 8))


def dlb(dqs, weights) -> np.ndarray:
    """Dual-quaternion linear blending of K poses: normalise(Σ wᵢ q̂ᵢ), signs aligned to the first.

    ``dqs`` has shape (..., K, 8), ``weights`` (..., K); batch axes broadcast.
    """
    d = _dq(dqs, "dqs")
    if d.ndim < 2:
        raise ValueError(f"dqs: expected shape (..., K, 8), got {d.shape}")
    k = d.shape[-2]
    w = as_real(weights, "weights")
    if w.ndim == 0 or w.shape[-1] != k:
        raise ValueError(f"weights: expected shape (..., {k}) for {k} poses, got {w.shape}")
    shape, (a, b) = broadcast((d.reshape((*d.shape[:-2], 8 * k)), 8 * k, "dqs"), (w, k, "weights"))
    return _core.dlb(a, b, k).reshape((*shape, 8))
