"""Dual quaternions for rigid-body poses: arrays of shape (..., 8).

Layout: real part (w, x, y, z) then dual part (w, x, y, z). A pose with rotation r and
translation t is q̂ = r + ε ½ (0, t) r and maps a point p to r p r* + t (Kavan et al. 2008;
see the documentation's mathematics pages). Inputs are normalised (``|r| = 1``, ``r·d = 0``)
before use.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_real, broadcast, quats, unary, with_width

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


def dq_from_pose(q: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
    """Dual quaternions ``r + ε ½ (0, t) r`` of poses.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Rotations (w, x, y, z) or a scipy ``Rotation``; normalised first.
    t : array_like, shape (..., 3)
        Translations; batch shapes broadcast with ``q``.

    Returns
    -------
    numpy.ndarray, shape (..., 8)
        Unit dual quaternions (real part, then dual part).

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, or a value is zero or not finite.

    See Also
    --------
    dq_to_pose

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0])
    array([1., 0., 0., 0., 0., 1., 0., 0.])
    """
    shape, (a, b) = broadcast((quats(q, "q"), 4, "q"), (with_width(t, "t", 3), 3, "t"))
    return _core.dq_from_pose(a, b).reshape((*shape, 8))


def dq_to_pose(dq: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotation and translation of dual quaternions (normalised first).

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.

    Returns
    -------
    rotation : numpy.ndarray, shape (..., 4)
    translation : numpy.ndarray, shape (..., 3)

    Raises
    ------
    ValueError
        If the shape is not (..., 8), or a real part is zero or a value not finite.

    See Also
    --------
    dq_from_pose

    Examples
    --------
    >>> import quatspline as qs
    >>> r, t = qs.dq_to_pose(qs.dq_from_pose([0.0, 0.0, 0.0, 1.0], [1.0, 2.0, 3.0]))
    >>> r, t.round(12)
    (array([0., 0., 0., 1.]), array([1., 2., 3.]))
    """
    a = _dq(dq, "dq")
    out = _core.dq_to_pose(a.reshape(-1, 8)).reshape((*a.shape[:-1], 7))
    return np.ascontiguousarray(out[..., :4]), np.ascontiguousarray(out[..., 4:])


def dq_normalize(dq: ArrayLike) -> NDArray[np.float64]:
    """Unit dual quaternions ``q̂ / ‖q̂‖``, with ``‖q̂‖ = |r| + ε (r·d)/|r|``.

    The result has a unit real part r and a dual part d with ``r · d = 0``.

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If the shape is not (..., 8), or a real part is zero or a value not finite.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.dq_normalize([2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0])
    array([1., 0., 0., 0., 0., 1., 0., 0.])
    """
    return unary(_core.dq_normalize, dq, "dq", 8, 8)


def dq_multiply(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Products ``(r₁ + εd₁)(r₂ + εd₂) = r₁r₂ + ε(r₁d₂ + d₁r₂)``: pose ``a`` after pose ``b``.

    Parameters
    ----------
    a, b : array_like, shape (..., 8)
        Dual quaternions; batch shapes broadcast.

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If a shape is not (..., 8), the shapes do not broadcast, or a value is not finite.

    Examples
    --------
    >>> import quatspline as qs
    >>> a = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    >>> b = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [0.0, 2.0, 0.0])
    >>> qs.dq_to_pose(qs.dq_multiply(a, b))[1]  # translations add
    array([1., 2., 0.])
    """
    shape, (x, y) = broadcast((_dq(a, "a"), 8, "a"), (_dq(b, "b"), 8, "b"))
    return _core.dq_multiply(x, y).reshape((*shape, 8))


def dq_conjugate(dq: ArrayLike, kind: str = "quaternion") -> NDArray[np.float64]:
    """One of the three conjugates of dual quaternions.

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.
    kind : {"quaternion", "dual", "both"}, default "quaternion"
        ``"quaternion"``: (r*, d*), the inverse pose of a unit dual quaternion; ``"dual"``:
        (r, −d); ``"both"``: (r*, −d*), used to transform points.

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If ``kind`` is not one of the three, or the shape is not (..., 8).

    Examples
    --------
    >>> import quatspline as qs
    >>> dq = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0])
    >>> qs.dq_to_pose(qs.dq_conjugate(dq))[1]  # the inverse pose
    array([-2., -0., -0.])
    """
    kinds = {"quaternion": 0, "dual": 1, "both": 2}
    if kind not in kinds:
        raise ValueError(f"kind: expected one of {sorted(kinds)}, got {kind!r}")
    a = _dq(dq, "dq")
    return _core.dq_conjugate(a.reshape(-1, 8), kinds[kind]).reshape(a.shape)


def dq_transform_point(dq: ArrayLike, points: ArrayLike) -> NDArray[np.float64]:
    """Transforms points by poses: ``r p r* + t``.

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.
    points : array_like, shape (..., 3)
        Points; batch shapes broadcast with ``dq``.

    Returns
    -------
    numpy.ndarray, shape (..., 3)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, or a value is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> dq = qs.dq_from_pose(qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2), [0.0, 0.0, 1.0])
    >>> qs.dq_transform_point(dq, [1.0, 0.0, 0.0]).round(12)
    array([0., 1., 1.])
    """
    shape, (a, b) = broadcast(
        (_dq(dq, "dq"), 8, "dq"), (with_width(points, "points", 3), 3, "points")
    )
    return _core.dq_transform_point(a, b).reshape((*shape, 3))


def dq_screw(dq: ArrayLike) -> dict[str, NDArray[np.float64]]:
    """Screw parameters of poses (Chasles): rotate about a line while sliding along it.

    A pure translation has angle 0, axis ``t/|t|`` and zero moment.

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.

    Returns
    -------
    dict
        ``"axis"`` (..., 3) unit direction, ``"angle"`` (...) in radians, ``"displacement"``
        (...) signed slide along the axis, ``"moment"`` (..., 3) of the axis line.

    Raises
    ------
    ValueError
        If the shape is not (..., 8), or a real part is zero or a value not finite.

    See Also
    --------
    dq_power, sclerp

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> dq = qs.dq_from_pose(qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2), [0.0, 0.0, 3.0])
    >>> s = qs.dq_screw(dq)
    >>> s["axis"].round(12), float(s["angle"]).__round__(12), float(s["displacement"])
    (array([0., 0., 1.]), 1.570796326795, 3.0)
    """
    a = _dq(dq, "dq")
    out = _core.dq_screw(a.reshape(-1, 8)).reshape((*a.shape[:-1], 8))
    return {
        "axis": out[..., 0:3],
        "angle": out[..., 3],
        "displacement": out[..., 4],
        "moment": out[..., 5:8],
    }


def dq_power(dq: ArrayLike, t: ArrayLike, long_path: bool = False) -> NDArray[np.float64]:
    """Powers ``q̂^t`` on the screw: rotate ``t θ`` about, and slide ``t d`` along, its axis.

    q̂ and −q̂ are the same pose; by default the power follows the shortest screw (the
    representative with rotation part w ≥ 0, θ ∈ [0, π]), so ``dq_power(-q̂, t)`` and
    ``dq_power(q̂, t)`` are the same pose. ``long_path=True`` keeps the sign as given (θ up to
    2π, the other way round the screw), as ``slerp``'s ``long_path`` does.

    Parameters
    ----------
    dq : array_like, shape (..., 8)
        Dual quaternions: real part (w, x, y, z), then dual part.
    t : array_like, shape (...)
        Exponents; broadcast with the batch shape of ``dq``.
    long_path : bool, default False
        Keep the sign of ``dq`` as given instead of following the shortest screw.

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If the shape is not (..., 8), the shapes do not broadcast, or a value is not finite.

    Examples
    --------
    >>> import quatspline as qs
    >>> dq = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0])
    >>> qs.dq_to_pose(qs.dq_power(dq, 0.25))[1]
    array([0.5, 0. , 0. ])
    >>> d = qs.dq_from_pose(qs.from_axis_angle([0, 0, 1], 3.0), [1.0, 0, 0])
    >>> a, b = qs.dq_power(d, 0.5), qs.dq_power(-d, 0.5)
    >>> bool(np.allclose(a, b) or np.allclose(a, -b))
    True
    """
    shape, (a, b) = broadcast((_dq(dq, "dq"), 8, "dq"), (as_real(t, "t"), 0, "t"))
    return _core.dq_power(a, b, bool(long_path)).reshape((*shape, 8))


def sclerp(dq0: ArrayLike, dq1: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
    """Screw linear interpolation ``q̂₀ (q̂₀* q̂₁)^t`` along the shortest screw.

    A constant screw motion: rotation and translation move together at constant rates about
    and along one fixed line. Defined also for equal rotations and pure translations.

    Parameters
    ----------
    dq0, dq1 : array_like, shape (..., 8)
        Start and end poses as dual quaternions; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``dq0``, 1 gives ``dq1``).

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, or a value is not finite.

    See Also
    --------
    dlb : the cheaper blend, which keeps the screw axis but not the angle profile.
    ScrewSpline : ScLerp through many poses.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> a = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> b = qs.dq_from_pose(qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2), [1.0, 0.0, 0.5])
    >>> rotation, translation = qs.dq_to_pose(qs.sclerp(a, b, 0.5))
    >>> float(translation[2])  # half the slide along the axis
    0.25
    """
    shape, (a, b, tt) = broadcast(
        (_dq(dq0, "dq0"), 8, "dq0"), (_dq(dq1, "dq1"), 8, "dq1"), (as_real(t, "t"), 0, "t")
    )
    return _core.sclerp(a, b, tt).reshape((*shape, 8))


def dlb(dqs: ArrayLike, weights: ArrayLike) -> NDArray[np.float64]:
    """Dual-quaternion linear blending of K poses: ``normalise(Σ wᵢ q̂ᵢ)``.

    Each pose is first sign-aligned with the first one (Kavan et al. 2008, the skinning
    operator). With two poses this is nlerp on dual quaternions: it keeps ScLerp's screw
    axis but not its angle profile (about 0.9° off at 90°, 5.8° at 162°).

    Parameters
    ----------
    dqs : array_like, shape (..., K, 8)
        The poses to blend.
    weights : array_like, shape (..., K)
        Their weights; batch axes broadcast with those of ``dqs``.

    Returns
    -------
    numpy.ndarray, shape (..., 8)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a value is not finite, or the blend
        is zero.

    See Also
    --------
    sclerp

    Examples
    --------
    >>> import quatspline as qs
    >>> a = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    >>> b = qs.dq_from_pose([1.0, 0.0, 0.0, 0.0], [4.0, 0.0, 0.0])
    >>> qs.dq_to_pose(qs.dlb([a, b], [0.75, 0.25]))[1]
    array([1., 0., 0.])
    """
    d = _dq(dqs, "dqs")
    if d.ndim < 2:
        raise ValueError(f"dqs: expected shape (..., K, 8), got {d.shape}")
    k = d.shape[-2]
    if k == 0:
        raise ValueError(f"dqs: expected at least one pose (shape (..., K ≥ 1, 8)), got {d.shape}")
    w = as_real(weights, "weights")
    if w.ndim == 0 or w.shape[-1] != k:
        raise ValueError(f"weights: expected shape (..., {k}) for {k} poses, got {w.shape}")
    shape, (a, b) = broadcast((d.reshape((*d.shape[:-2], 8 * k)), 8 * k, "dqs"), (w, k, "weights"))
    return _core.dlb(a, b, k).reshape((*shape, 8))
