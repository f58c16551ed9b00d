"""Quaternion algebra on arrays of shape (..., 4), scalar first (w, x, y, z).

``multiply``, ``conjugate``, ``inverse``, ``exp``, ``log`` and ``power`` are exact quaternion
algebra on any finite input (``power`` and rotation functions normalise first). ``log`` uses
atan2, never acos; ``exp`` and ``log`` switch to Taylor series near the identity.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_real, broadcast, quats, unary, with_width

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


def normalize(q: ArrayLike) -> NDArray[np.float64]:
    """Unit quaternions ``q / |q|``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z), scalar first, or a scipy ``Rotation``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        Each quaternion divided by its norm. A quaternion whose ``|q|²`` is within 4 ulp of 1
        is returned unchanged.

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), or an element is zero, denormal, NaN or inf (the
        message names the element).

    See Also
    --------
    canonicalize : choose the sign of each quaternion.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.normalize([2.0, 0.0, 0.0, 0.0])
    array([1., 0., 0., 0.])
    >>> qs.normalize([[1.0, 1.0, 1.0, 1.0]])
    array([[0.5, 0.5, 0.5, 0.5]])
    """
    return unary(_core.normalize, q, "q", 4, 4)


def multiply(p: ArrayLike, q: ArrayLike) -> NDArray[np.float64]:
    """Hamilton product ``p q``.

    As rotations, ``p q`` applies ``q`` first, then ``p`` (like scipy's ``r_p * r_q``).

    Parameters
    ----------
    p, q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or scipy ``Rotation`` objects; batch shapes broadcast like
        numpy's. Not normalised.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        The products.

    Raises
    ------
    ValueError
        If a shape is not (..., 4), the batch shapes do not broadcast, or an element is not
        finite.

    See Also
    --------
    conjugate, inverse

    Examples
    --------
    >>> import quatspline as qs
    >>> i, j = [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]
    >>> qs.multiply(i, j)  # i j = k
    array([0., 0., 0., 1.])
    """
    shape, (a, b) = broadcast((quats(p, "p"), 4, "p"), (quats(q, "q"), 4, "q"))
    return _core.multiply(a, b).reshape((*shape, 4))


def conjugate(q: ArrayLike) -> NDArray[np.float64]:
    """Conjugates ``q* = (w, −x, −y, −z)``: the inverse rotation of a unit quaternion.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4) or holds NaN or inf.

    See Also
    --------
    inverse : ``q* / |q|²``, for quaternions that are not unit.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.conjugate([0.5, 0.5, -0.5, 0.5])
    array([ 0.5, -0.5,  0.5, -0.5])
    """
    return unary(_core.conjugate, q, "q", 4, 4)


def inverse(q: ArrayLike) -> NDArray[np.float64]:
    """Inverses ``q⁻¹ = q* / |q|²``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``; any non-zero norm.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), or an element is zero, NaN or inf.

    See Also
    --------
    conjugate

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.inverse([0.0, 2.0, 0.0, 0.0])
    array([ 0. , -0.5, -0. , -0. ])
    """
    return unary(_core.inverse, q, "q", 4, 4)


def exp(q: ArrayLike) -> NDArray[np.float64]:
    """Quaternion exponential ``exp(w + v) = e^w (cos|v|, sin|v| v/|v|)``.

    ``sin|v|/|v|`` switches to its Taylor series near ``v = 0``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z); usually pure (``w = 0``), e.g. ``(0, θ n)`` for a rotation
        by ``2θ`` about the unit axis ``n``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4) or holds NaN or inf.

    See Also
    --------
    log : the inverse on unit quaternions.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.exp([0.0, 0.0, 0.0, np.pi / 4])  # 90° about z
    >>> np.allclose(q, [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])
    True
    """
    return unary(_core.exp, q, "q", 4, 4)


def log(q: ArrayLike) -> NDArray[np.float64]:
    """Principal logarithm ``(ln|q|, θ v/|v|)`` with ``θ = atan2(|v|, w)`` in [0, π].

    ``θ`` comes from atan2, never from acos, so it keeps full accuracy near 0 and π; ``θ/|v|``
    switches to its Taylor series near the identity. For a unit quaternion the result is
    pure, ``(0, θ n)``: half the rotation vector.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``; any non-zero norm.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), or an element is zero, NaN or inf.

    See Also
    --------
    exp, power, as_rotvec

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)
    >>> np.allclose(qs.log(q), [0.0, 0.0, 0.0, np.pi / 4])
    True
    >>> np.allclose(qs.exp(qs.log(q)), q)
    True
    """
    return unary(_core.log, q, "q", 4, 4)


def power(q: ArrayLike, t: ArrayLike) -> NDArray[np.float64]:
    """Powers ``q^t = exp(t log q)`` of the normalised ``q``.

    No shortest-path flip is made: ``q`` and ``−q`` give different powers (rotations by
    ``t·2θ`` and ``t·(2θ − 2π)``).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``; normalised first.
    t : array_like, shape (...)
        Exponents; broadcast against the batch shape of ``q``.

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If ``q`` is not of shape (..., 4), an element is zero or not finite, or the shapes do
        not broadcast.

    See Also
    --------
    slerp : ``q0 (q0* q1)^t`` with the shortest path.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_axis_angle([1.0, 0.0, 0.0], np.pi / 2)
    >>> np.allclose(qs.power(q, [0.5, 2.0]),
    ...             qs.from_axis_angle([1.0, 0.0, 0.0], [np.pi / 4, np.pi]))
    True
    """
    q = quats(q, "q")
    shape, (a, b) = broadcast((q, 4, "q"), (as_real(t, "t"), 0, "t"))
    return _core.power(a, b).reshape((*shape, 4))


def rotate(q: ArrayLike, vectors: ArrayLike) -> NDArray[np.float64]:
    """Rotates vectors by unit quaternions: ``q v q*`` (body coordinates to world).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``; normalised first.
    vectors : array_like, shape (..., 3)
        Vectors; batch shapes broadcast with those of ``q``.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        The same as scipy's ``Rotation.apply``.

    Raises
    ------
    ValueError
        If a shape is wrong, the batch shapes do not broadcast, or an element is zero or not
        finite.

    See Also
    --------
    rotate_points : every point at every time, shape (M, P, 3).

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_axis_angle([0.0, 0.0, 1.0], np.pi / 2)  # 90° about z
    >>> np.round(qs.rotate(q, [1.0, 0.0, 0.0]), 12)
    array([0., 1., 0.])
    """
    shape, (a, b) = broadcast(
        (quats(q, "q"), 4, "q"), (with_width(vectors, "vectors", 3), 3, "vectors")
    )
    return _core.rotate(a, b).reshape((*shape, 3))


def canonicalize(q: ArrayLike, reference: ArrayLike | None = None) -> NDArray[np.float64]:
    """Chooses the sign of each quaternion (``q`` and ``−q`` are the same rotation).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions (w, x, y, z) or a scipy ``Rotation``.
    reference : array_like, shape (..., 4), optional
        Without it, each quaternion is flipped to ``w ≥ 0``; with it, to the hemisphere of
        the reference (``q · reference ≥ 0``).

    Returns
    -------
    numpy.ndarray, shape (..., 4)

    Raises
    ------
    ValueError
        If a shape is not (..., 4).

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.canonicalize([[-0.6, 0.8, 0.0, 0.0], [0.6, 0.8, 0.0, 0.0]])
    array([[ 0.6, -0.8, -0. , -0. ],
           [ 0.6,  0.8,  0. ,  0. ]])
    >>> qs.canonicalize([0.6, 0.8, 0.0, 0.0], reference=[0.0, -1.0, 0.0, 0.0])
    array([-0.6, -0.8, -0. , -0. ])
    """
    q = quats(q, "q")
    if reference is None:
        sign = np.where(q[..., 0] < 0, -1.0, 1.0)
    else:
        r = quats(reference, "reference")
        sign = np.where(np.sum(q * r, axis=-1) < 0, -1.0, 1.0)
    return q * sign[..., None]
