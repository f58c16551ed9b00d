"""Two-keyframe interpolation, vectorised with numpy broadcasting.

Every function takes keys of shape (..., 4) and parameters t of any shape that broadcasts
against the keys' batch shape; the result has shape broadcast(...) + (4,). Keys are normalised.

============= ================================================ ========
function      formula                                          speed
============= ================================================ ========
``lerp``      ``(1−t) q₀ + t q₁`` (not unit)                   —
``nlerp``     ``lerp / ‖lerp‖``, shortest arc                  varies
``slerp``     ``q₀ (q₀* q₁)^t``, shortest arc (Shoemake 1985)  constant
``lin_euler`` Euler angles lerped (baseline)                   varies
``lin_mat``   matrices lerped, projected by SVD (baseline)     varies
============= ================================================ ========

The baselines are the naive methods the quaternion methods improve on (Gortler 2012, ch. 9);
they are kept for comparison. See the documentation's mathematics pages.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_real, broadcast, quats

__all__ = ["lerp", "lin_euler", "lin_mat", "nlerp", "slerp"]


def _pair(fn, q0, q1, t, *extra):
    shape, (a, b, tt) = broadcast(
        (quats(q0, "q0"), 4, "q0"), (quats(q1, "q1"), 4, "q1"), (as_real(t, "t"), 0, "t")
    )
    return fn(a, b, tt, *extra).reshape((*shape, 4))


def lerp(q0: ArrayLike, q1: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
    """Componentwise linear interpolation ``(1−t) q₀ + t q₁``.

    Not a unit quaternion in general; no sign flip; the keys are used as given.

    Parameters
    ----------
    q0, q1 : array_like, shape (..., 4)
        Keys (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``q0``, 1 gives ``q1``); ``|t| ≤ 1e12``;
        broadcast with the keys' batch shapes.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a key is zero or not finite, or a
        ``t`` is not finite or too large (the message names the argument and element).

    See Also
    --------
    nlerp, slerp

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.lerp([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], 0.5)
    array([0.5, 0.5, 0. , 0. ])
    """
    return _pair(_core.lerp, q0, q1, t)


def nlerp(
    q0: ArrayLike, q1: ArrayLike, t: ArrayLike, long_path: bool = False
) -> NDArray[np.float64]:
    """Normalised linear interpolation, on the shortest arc.

    Follows the same great arc as :func:`slerp` at a speed that varies (fastest in the
    middle).

    Parameters
    ----------
    q0, q1 : array_like, shape (..., 4)
        Keys (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``q0``, 1 gives ``q1``); ``|t| ≤ 1e12``;
        broadcast with the keys' batch shapes.
    long_path : bool, default False
        Keep ``q1`` as given; by default it is replaced by ``−q1`` when ``q0 · q1 < 0``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        Unit quaternions.

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a key is zero or not finite, or a
        ``t`` is not finite or too large (the message names the argument and element).

    See Also
    --------
    slerp, lerp

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.nlerp([1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.5, 1.0])
    >>> np.allclose(q[1], [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0])
    True
    """
    return _pair(_core.nlerp, q0, q1, t, bool(long_path))


def slerp(
    q0: ArrayLike, q1: ArrayLike, t: ArrayLike, long_path: bool = False
) -> NDArray[np.float64]:
    """Spherical linear interpolation ``q₀ (q₀* q₁)^t``: constant angular speed, fixed axis.

    Exact at t = 0 and 1; stable for nearly equal keys (Taylor weights) and for nearly
    opposite ones (Shoemake 1985).

    Exactly opposite keys with ``long_path=True`` (q₁ = −q₀, a full turn with no axis of its
    own) turn about q₀'s body x axis: ``slerp(q, -q, t, True) = q ⊗ (cos πt, sin πt, 0, 0)``,
    a unit quaternion rotating by 2πt about the world axis R(q) eₓ.

    Parameters
    ----------
    q0, q1 : array_like, shape (..., 4)
        Keys (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``q0``, 1 gives ``q1``); ``|t| ≤ 1e12``;
        broadcast with the keys' batch shapes.
    long_path : bool, default False
        Keep ``q1`` as given. By default the shortest path is taken: ``q1`` is replaced by
        ``−q1`` when ``q0 · q1 < 0``, so at ``t = 1`` the result is that representative.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        Unit quaternions.

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a key is zero or not finite, or a
        ``t`` is not finite or too large (the message names the argument and element).

    See Also
    --------
    PiecewiseSlerp : slerp through many keys.
    sclerp : the same for poses (dual quaternions).

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> a = [1.0, 0.0, 0.0, 0.0]
    >>> b = qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)
    >>> q = qs.slerp(a, b, np.linspace(0, 1, 5))
    >>> q.shape
    (5, 4)
    >>> np.degrees(qs.as_rotvec(q)[:, 2]).round(6)
    array([ 0. , 22.5, 45. , 67.5, 90. ])
    >>> q = np.array([0, 0, 1, 1]) / np.sqrt(2)
    >>> m = qs.slerp(q, -q, 0.75, long_path=True)
    >>> round(float(np.linalg.norm(m)), 12)
    1.0
    """
    return _pair(_core.slerp, q0, q1, t, bool(long_path))


def lin_euler(q0: ArrayLike, q1: ArrayLike, t: ArrayLike, seq: str = "xyz") -> NDArray[np.float64]:
    """Baseline: linear interpolation of Euler angles.

    Parameters
    ----------
    q0, q1 : array_like, shape (..., 4)
        Keys (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``q0``, 1 gives ``q1``); ``|t| ≤ 1e12``;
        broadcast with the keys' batch shapes.
    seq : str, default "xyz"
        Euler sequence (scipy's convention, see :func:`from_euler`); each angle difference is
        wrapped to (−π, π].

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a key is zero or not finite, or a
        ``t`` is not finite or too large (the message names the argument and element).

    See Also
    --------
    slerp : what to use instead.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> a = qs.from_euler("xyz", [0.0, 0.0, 0.0], degrees=True)
    >>> b = qs.from_euler("xyz", [0.0, 0.0, 80.0], degrees=True)
    >>> qs.as_euler(qs.lin_euler(a, b, 0.25), "xyz", degrees=True).round(10)
    array([ 0.,  0., 20.])
    """
    return _pair(_core.lin_euler, q0, q1, t, str(seq))


def lin_mat(q0: ArrayLike, q1: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
    """Baseline: entrywise interpolation of rotation matrices, projected back to rotations.

    The projection is the polar decomposition (SVD).

    Parameters
    ----------
    q0, q1 : array_like, shape (..., 4)
        Keys (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast.
    t : array_like, shape (...)
        Interpolation parameters (0 gives ``q0``, 1 gives ``q1``); ``|t| ≤ 1e12``;
        broadcast with the keys' batch shapes.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If a shape is wrong, the shapes do not broadcast, a key is zero or not finite, or a
        ``t`` is not finite or too large (the message names the argument and element).

    See Also
    --------
    slerp : what to use instead.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> a = [1.0, 0.0, 0.0, 0.0]
    >>> b = qs.from_axis_angle([1.0, 0.0, 0.0], np.pi / 2)
    >>> np.allclose(qs.lin_mat(a, b, 0.5), qs.slerp(a, b, 0.5))  # symmetric midpoint
    True
    """
    return _pair(_core.lin_mat, q0, q1, t)
