"""Conversions: rotation matrices, rotation vectors, axis–angle, Euler angles, layouts, scipy.

Euler angles follow ``scipy.spatial.transform.Rotation``: uppercase sequences ("XYZ") are
intrinsic, lowercase ("xyz") extrinsic; all 12 sequences of each kind; ``degrees=True`` for
degrees. Quaternions are scalar first (w, x, y, z); ``from_xyzw``/``as_xyzw`` convert from and
to scalar-last storage (scipy, ROS, Eigen's coefficients).
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_real, broadcast, quats, unary, with_width

__all__ = [
    "as_euler",
    "as_matrix",
    "as_rotvec",
    "as_xyzw",
    "from_axis_angle",
    "from_euler",
    "from_matrix",
    "from_rotvec",
    "from_scipy",
    "from_xyzw",
    "to_scipy",
]


def as_matrix(q) -> np.ndarray:
    """(..., 4) unit quaternions → (..., 3, 3) rotation matrices (columns: body axes)."""
    a = quats(q, "q")
    return _core.as_matrix(a.reshape(-1, 4)).reshape((*a.shape[:-1], 3, 3))


def from_matrix(matrix) -> np.ndarray:
    """(..., 3, 3) rotation matrices → quaternions (Shepperd's method, robust at 180°).

    Matrices that are not orthogonal to 1e-12 are projected to the nearest rotation (SVD), as
    scipy does; a determinant ≤ 0 raises ValueError naming the matrix.
    """
    m = as_real(matrix, "matrix")
    if m.ndim < 2 or m.shape[-2:] != (3, 3):
        raise ValueError(f"matrix: expected shape (..., 3, 3), got {m.shape}")
    return _core.from_matrix(m.reshape(-1, 9)).reshape((*m.shape[:-2], 4))


def as_rotvec(q) -> np.ndarray:
    """Rotation vectors (axis × angle, angle in [0, π]); exact near the identity."""
    return unary(_core.as_rotvec, q, "q", 4, 3)


def from_rotvec(rotvec) -> np.ndarray:
    """Unit quaternions of rotation vectors (..., 3)."""
    return unary(_core.from_rotvec, rotvec, "rotvec", 3, 4)


def from_axis_angle(axis, angle) -> np.ndarray:
    """Rotation by ``angle`` (radians) about ``axis`` (normalised; zero axis → ValueError)."""
    shape, (a, g) = broadcast(
        (with_width(axis, "axis", 3), 3, "axis"), (as_real(angle, "angle"), 0, "angle")
    )
    return _core.from_axis_angle(a, g).reshape((*shape, 4))


def from_euler(seq: str, angles, degrees: bool = False) -> np.ndarray:
    """Quaternions of Euler angles in sequence ``seq`` (scipy's convention).

    Parameters
    ----------
    seq : str
        1 to 3 axes, all of ``xyz`` (extrinsic) or all of ``XYZ`` (intrinsic), no axis twice in
        a row: ``"X"``, ``"zx"``, ``"xyz"``, ``"ZYZ"``… (as ``scipy``'s ``from_euler``).
    angles : array_like
        Shape (..., len(seq)). With one axis, a scalar or any array of angles (a trailing axis
        of length 1 is accepted too).
    degrees : bool
        Angles in degrees.

    Returns
    -------
    ndarray
        Unit quaternions (..., 4).

    Raises
    ------
    TypeError
        ``seq`` is not a string.
    ValueError
        Unknown sequence, or ``angles`` of the wrong width.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.from_euler("zx", [90, 90], degrees=True).round(3)
    array([ 0.5,  0.5, -0.5,  0.5])
    """
    if not isinstance(seq, str):
        raise TypeError(f"seq: expected a string such as 'xyz', got {type(seq).__name__}")
    k = len(seq)
    _core.from_euler(seq, np.zeros((0, min(max(k, 1), 3))))  # the core names a bad ``seq``
    a = as_real(angles, "angles")
    if k == 1 and not (a.ndim >= 2 and a.shape[-1] == 1):
        a = a[..., None]
    if a.ndim == 0 or a.shape[-1] != k:
        raise ValueError(f"angles: expected shape (..., {k}) for sequence {seq!r}, got {a.shape}")
    if degrees:
        a = np.deg2rad(a)
    return _core.from_euler(seq, a.reshape(-1, k)).reshape((*a.shape[:-1], 4))


def as_euler(q, seq: str, degrees: bool = False) -> np.ndarray:
    """Euler angles (..., 3) in sequence ``seq``; at gimbal lock the third angle is 0."""
    a = quats(q, "q")
    out = _core.as_euler(a.reshape(-1, 4), str(seq)).reshape((*a.shape[:-1], 3))
    return np.rad2deg(out) if degrees else out


def from_xyzw(q) -> np.ndarray:
    """Scalar-last (x, y, z, w) → scalar-first (w, x, y, z)."""
    a = quats(q, "q")
    return np.ascontiguousarray(np.roll(a, 1, axis=-1))


def as_xyzw(q) -> np.ndarray:
    """Scalar-first (w, x, y, z) → scalar-last (x, y, z, w)."""
    a = quats(q, "q")
    return np.ascontiguousarray(np.roll(a, -1, axis=-1))


def from_scipy(rotation) -> np.ndarray:
    """Quaternions (w, x, y, z) of a ``scipy.spatial.transform.Rotation``."""
    return from_xyzw(rotation.as_quat())


def to_scipy(q):
    """A ``scipy.spatial.transform.Rotation`` of quaternions (..., 4). Needs scipy."""
    try:
        from scipy.spatial.transform import Rotation
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("to_scipy needs scipy: pip install scipy") from e
    return Rotation.from_quat(as_xyzw(q))
