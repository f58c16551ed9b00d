"""Conversions: rotation matrices, rotation vectors, axis–angle, Euler angles, layouts, scipy.

Euler angles follow ``scipy.spatial.transform.Rotation``: uppercase sequences ("XYZ") are
intrinsic, lowercase ("xyz") extrinsic; all 12 sequences of each kind; ``degrees=True`` for
degrees. Quaternions are scalar first (w, x, y, z); ``from_xyzw``/``as_xyzw`` convert from and
to scalar-last storage (scipy, ROS, Eigen's coefficients).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import (
    as_real,
    broadcast,
    is_scipy_rotation,
    quats,
    rotation_to_wxyz,
    unary,
    with_width,
)
from .._util.optional import need

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


def as_matrix(q: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices of quaternions.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z), scalar first, or a scipy ``Rotation``; normalised first.

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)
        ``R`` with ``R v = q v q*``; its columns are the body axes in world coordinates.

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), or an element is zero or not finite.

    See Also
    --------
    from_matrix

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> np.round(qs.as_matrix(qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)), 12)
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    a = quats(q, "q")
    return _core.as_matrix(a.reshape(-1, 4)).reshape((*a.shape[:-1], 3, 3))


def from_matrix(matrix: ArrayLike) -> NDArray[np.float64]:
    """Quaternions of rotation matrices (Shepperd's method, robust at 180°).

    Matrices that are not orthogonal to 1e-12 are projected to the nearest rotation (SVD), as
    scipy does.

    Parameters
    ----------
    matrix : array_like, shape (..., 3, 3)
        Rotation matrices.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        Unit quaternions (w, x, y, z).

    Raises
    ------
    ValueError
        If the shape is not (..., 3, 3), an entry is not finite, or a determinant is ≤ 0
        (the message names the matrix).

    See Also
    --------
    as_matrix

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_matrix([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    >>> np.allclose(q, [np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)])
    True
    """
    m = as_real(matrix, "matrix")
    if m.ndim < 2 or m.shape[-2:] != (3, 3):
        raise ValueError(f"matrix: expected shape (..., 3, 3), got {m.shape}")
    return _core.from_matrix(m.reshape(-1, 9)).reshape((*m.shape[:-2], 4))


def as_rotvec(q: ArrayLike) -> NDArray[np.float64]:
    """Rotation vectors (unit axis × angle, angle in [0, π] radians).

    Exact near the identity (Taylor branch) and near 180° (atan2).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z), scalar first, or a scipy ``Rotation``; normalised first.

    Returns
    -------
    numpy.ndarray, shape (..., 3)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), or an element is zero or not finite.

    See Also
    --------
    from_rotvec, log

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> np.allclose(qs.as_rotvec(qs.from_axis_angle([0.0, 1.0, 0.0], 0.3)), [0.0, 0.3, 0.0])
    True
    """
    return unary(_core.as_rotvec, q, "q", 4, 3)


def from_rotvec(rotvec: ArrayLike) -> NDArray[np.float64]:
    """Unit quaternions of rotation vectors.

    Parameters
    ----------
    rotvec : array_like, shape (..., 3)
        Unit axis × angle (radians).

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If the shape is not (..., 3) or an element is not finite.

    See Also
    --------
    as_rotvec, from_axis_angle

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> np.allclose(qs.from_rotvec([0.0, 0.0, np.pi]), [0.0, 0.0, 0.0, 1.0])
    True
    """
    return unary(_core.from_rotvec, rotvec, "rotvec", 3, 4)


def from_axis_angle(axis: ArrayLike, angle: ArrayLike) -> NDArray[np.float64]:
    """Quaternions of rotations by ``angle`` about ``axis``.

    Parameters
    ----------
    axis : array_like, shape (..., 3)
        Rotation axes; normalised first.
    angle : array_like, shape (...)
        Angles in radians; broadcast against the axes' batch shape.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If an axis is zero, a value is not finite, or the shapes do not broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> qs.from_axis_angle([0.0, 0.0, 2.0], [0.0, np.pi]).round(12)
    array([[1., 0., 0., 0.],
           [0., 0., 0., 1.]])
    """
    shape, (a, g) = broadcast(
        (with_width(axis, "axis", 3), 3, "axis"), (as_real(angle, "angle"), 0, "angle")
    )
    return _core.from_axis_angle(a, g).reshape((*shape, 4))


def from_euler(seq: str, angles: ArrayLike, degrees: bool = False) -> NDArray[np.float64]:
    """Quaternions of Euler angles, in scipy's convention.

    Parameters
    ----------
    seq : str
        1 to 3 axes, all of ``xyz`` (extrinsic) or all of ``XYZ`` (intrinsic), no axis twice in
        a row: ``"X"``, ``"zx"``, ``"xyz"``, ``"ZYZ"``… (as ``scipy``'s ``from_euler``).
    angles : array_like, shape (..., len(seq))
        The angles, applied in the order of ``seq``. With one axis, a scalar or any array
        of angles (a trailing axis of length 1 is accepted too).
    degrees : bool, default False
        Angles in degrees instead of radians.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        The same rotations as ``scipy.spatial.transform.Rotation.from_euler(seq, angles)``.

    Raises
    ------
    TypeError
        ``seq`` is not a string.
    ValueError
        Unknown sequence, or ``angles`` of the wrong width.

    See Also
    --------
    as_euler

    Examples
    --------
    >>> import quatspline as qs
    >>> q = qs.from_euler("xyz", [0.0, 0.0, 90.0], degrees=True)
    >>> q.round(12)
    array([0.70710678, 0.        , 0.        , 0.70710678])
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


def as_euler(q: ArrayLike, seq: str, degrees: bool = False) -> NDArray[np.float64]:
    """Euler angles of quaternions, in scipy's convention.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z), scalar first, or a scipy ``Rotation``; normalised first.
    seq : str
        ``"xyz"``-style (extrinsic) or ``"XYZ"``-style (intrinsic) sequence, as in
        :func:`from_euler`.
    degrees : bool, default False
        Return degrees instead of radians.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        At gimbal lock the third angle is set to 0 (scipy does the same, with a warning).

    Raises
    ------
    ValueError
        If ``seq`` is not valid, or ``q`` is not of shape (..., 4) or not finite.

    See Also
    --------
    from_euler

    Examples
    --------
    >>> import quatspline as qs
    >>> q = qs.from_euler("ZYX", [30.0, 20.0, 10.0], degrees=True)
    >>> qs.as_euler(q, "ZYX", degrees=True).round(10)
    array([30., 20., 10.])
    """
    a = quats(q, "q")
    out = _core.as_euler(a.reshape(-1, 4), str(seq)).reshape((*a.shape[:-1], 3))
    return np.rad2deg(out) if degrees else out


def from_xyzw(q: ArrayLike) -> NDArray[np.float64]:
    """Scalar-first quaternions (w, x, y, z) from scalar-last ones (x, y, z, w).

    Scalar-last is the storage order of scipy, ROS and Eigen's coefficients.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (x, y, z, w). A scipy ``Rotation`` is converted as a rotation.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        The same quaternions as (w, x, y, z); not normalised.

    Raises
    ------
    ValueError
        If the shape is not (..., 4).

    See Also
    --------
    as_xyzw

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.from_xyzw([0.0, 0.0, 0.6, 0.8])
    array([0.8, 0. , 0. , 0.6])
    """
    if is_scipy_rotation(q):
        return rotation_to_wxyz(q)
    a = quats(q, "q")
    return np.ascontiguousarray(np.roll(a, 1, axis=-1))


def as_xyzw(q: ArrayLike) -> NDArray[np.float64]:
    """Scalar-last quaternions (x, y, z, w) from scalar-first ones (w, x, y, z).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        The same quaternions as (x, y, z, w), e.g. for ``Rotation.from_quat``.

    Raises
    ------
    ValueError
        If the shape is not (..., 4).

    See Also
    --------
    from_xyzw

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.as_xyzw([0.8, 0.0, 0.0, 0.6])
    array([0. , 0. , 0.6, 0.8])
    """
    a = quats(q, "q")
    return np.ascontiguousarray(np.roll(a, -1, axis=-1))


def from_scipy(rotation: Any) -> NDArray[np.float64]:
    """Quaternions (w, x, y, z) of a ``scipy.spatial.transform.Rotation``.

    Every rotation argument of quatspline also accepts a ``Rotation`` directly; this makes
    the array explicitly.

    Parameters
    ----------
    rotation : scipy.spatial.transform.Rotation
        One rotation or a stack of them.

    Returns
    -------
    numpy.ndarray, shape (4,) or (N, 4)
        The sign scipy stores is kept.

    Raises
    ------
    TypeError
        If ``rotation`` is not a scipy ``Rotation``.

    See Also
    --------
    to_scipy

    Examples
    --------
    >>> from scipy.spatial.transform import Rotation
    >>> import quatspline as qs
    >>> qs.from_scipy(Rotation.from_euler("z", 90, degrees=True)).round(12)
    array([0.70710678, 0.        , 0.        , 0.70710678])
    """
    if not is_scipy_rotation(rotation):
        raise TypeError(f"rotation: expected a scipy Rotation, got {type(rotation).__name__}")
    return rotation_to_wxyz(rotation)


def to_scipy(q: ArrayLike) -> Any:
    """A ``scipy.spatial.transform.Rotation`` of quaternions (needs scipy).

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4)
        Quaternions (w, x, y, z).

    Returns
    -------
    scipy.spatial.transform.Rotation

    Raises
    ------
    ImportError
        If scipy is not installed (the message says how to install it).
    ValueError
        If the shape is not (..., 4).

    See Also
    --------
    from_scipy

    Examples
    --------
    >>> import quatspline as qs
    >>> r = qs.to_scipy(qs.from_euler("xyz", [0.0, 0.0, 90.0], degrees=True))
    >>> r.as_euler("xyz", degrees=True).round(10)
    array([ 0.,  0., 90.])
    """
    transform = need("scipy.spatial.transform", extra="scipy", what="to_scipy")
    return transform.Rotation.from_quat(as_xyzw(q))
