"""Pose trajectories: an orientation spline (any registered method) and a position spline.

``PoseSpline(quats, times, positions, rotation="c3", translation="cubic", **params)``:
orientation and angular rates come from the rotation spline (exact derivatives), positions
from a natural cubic spline (C², zero acceleration at the ends) or piecewise-linear
interpolation (C⁰), with exact velocity and acceleration. Outside the key times both follow
``extrapolate``: "raise", "clamp" (hold the end pose), "linear" (constant angular and linear
velocity from the ends) or "periodic" (repeat).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_times, pose_key_order, with_width
from .._util.checks import choice
from .._util.options import DEFAULT_METHOD
from ..core.algebra import rotate
from ..registry import spline as make_spline
from ..splines import EXTRAPOLATE, describe

__all__ = ["PoseSpline"]


class PoseSpline:
    """Orientation and position through pose keys.

    Orientation and angular rates come from any registered rotation method (exact
    derivatives); positions from a natural cubic spline (C², zero acceleration at the ends)
    or piecewise-linear interpolation (C⁰), with exact velocity and acceleration.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Key orientations (w, x, y, z) or a scipy ``Rotation`` of N rotations.
    times : array_like, shape (N,)
        Strictly increasing key times; pandas and numpy datetimes become seconds.
    positions : array_like, shape (N, 3)
        Key positions (any length unit).
    rotation : str, default "natural"
        A method name of :data:`quatspline.METHODS` (``"slerp"``, ``"c3"``, …).
    translation : {"cubic", "linear"}, default "cubic"
        Natural cubic spline or piecewise-linear positions.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain raise, hold the end pose with zero rates, continue at the
        end's angular and linear velocity (zero accelerations), or repeat the domain.
    **params
        Parameters of the rotation method (e.g. ``alpha`` for ``"c3"``).

    Attributes
    ----------
    rotation : Spline
        The orientation spline.

    Raises
    ------
    ValueError
        If a shape is wrong, the times are not strictly increasing, a value is not finite,
        or a method or parameter is unknown.

    Notes
    -----
    The order ``(quats, times, positions)`` is that of every spline class. The old order
    ``(times, quats, positions)`` still works with a ``DeprecationWarning`` until 0.3.

    See Also
    --------
    ScrewSpline : orientation and position moved together along screws.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 90, 90]], degrees=True)
    >>> pose = qs.PoseSpline(keys, [0.0, 1.0, 2.0], [[0, 0, 0], [1, 0, 0], [1, 1, 0]])
    >>> q, x = pose([0.0, 0.5, 2.0])
    >>> q.shape, x.shape
    ((3, 4), (3, 3))
    >>> pose.transform_points(1.0, [[0.0, 0.0, 1.0]]).round(12)  # (M, P, 3)
    array([[[1., 0., 1.]]])
    """

    def __init__(
        self,
        quats: ArrayLike,
        times: ArrayLike,
        positions: ArrayLike,
        rotation: str = DEFAULT_METHOD,
        translation: str = "cubic",
        extrapolate: str = "raise",
        **params,
    ):
        choice(extrapolate, "extrapolate", EXTRAPOLATE)
        if translation not in ("cubic", "linear"):
            raise ValueError(f"translation: expected 'cubic' or 'linear', got {translation!r}")
        quats, times = pose_key_order(quats, times, "PoseSpline")
        t = as_times(times, "times")
        p = with_width(positions, "positions", 3)
        if p.ndim != 2 or len(p) != len(t):
            raise ValueError(f"positions: expected shape ({len(t)}, 3), got {p.shape}")
        self.rotation = make_spline(rotation, quats, t, **params)
        self.rotation.extrapolate = extrapolate
        self.extrapolate = extrapolate
        self._times = np.ascontiguousarray(t, dtype=float)
        self._points = np.ascontiguousarray(p, dtype=float)
        if not np.all(np.isfinite(self._points)):
            k = int(np.argmax(~np.all(np.isfinite(self._points), axis=1)))
            raise ValueError(f"positions: non-finite value (NaN or inf) at element {k}")
        self._cubic = translation == "cubic"

    def __repr__(self) -> str:
        return describe(
            self,
            len(self._times) - 1,
            rotation=type(self.rotation).__name__,
            translation="cubic" if self._cubic else "linear",
        )

    @property
    def domain(self) -> tuple[float, float]:
        """(first key time, last key time)."""
        return float(self._times[0]), float(self._times[-1])

    def _pos(self, t):
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        a, b = self.domain
        if not np.all(np.isfinite(flat)):
            k = int(np.argmax(~np.isfinite(flat)))
            raise ValueError(f"t: non-finite value (NaN or inf) at element {k}")
        outside = (flat < a) | (flat > b)
        if np.any(outside) and self.extrapolate == "raise":
            k = int(np.argmax(outside))
            raise ValueError(f"t: t[{k}] = {flat[k]} is outside the domain [{a}, {b}]")
        if self.extrapolate == "periodic":
            inside = np.clip(a + np.mod(flat - a, b - a), a, b)
            return ta.shape, _core.position_eval(self._times, self._points, self._cubic, inside)
        out = _core.position_eval(self._times, self._points, self._cubic, np.clip(flat, a, b))
        if self.extrapolate == "linear":
            # Constant velocity beyond the ends: p(e) + v(e) (t − e), zero acceleration.
            dt = flat - np.clip(flat, a, b)
            out[outside, 0:3] += out[outside, 3:6] * dt[outside, None]
            out[outside, 6:9] = 0.0
        else:
            out[outside, 3:] = 0.0
        return ta.shape, out

    def orientation(self, t: ArrayLike) -> NDArray[np.float64]:
        """Orientations at times ``t``.

        Parameters
        ----------
        t : array_like, any shape
            Times.

        Returns
        -------
        numpy.ndarray, shape t.shape + (4,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.orientation(2.0).round(12)
        array([0., 0., 0., 1.])
        """
        return self.rotation(t)

    def position(self, t: ArrayLike) -> NDArray[np.float64]:
        """Positions at times ``t``.

        Parameters
        ----------
        t : array_like, any shape
            Times.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.position([0.5, 1.5]).round(12)
        array([[0.5, 0. , 0. ],
               [1.5, 0. , 0. ]])
        """
        shape, out = self._pos(t)
        return out[:, 0:3].reshape((*shape, 3))

    def linear_velocity(self, t: ArrayLike) -> NDArray[np.float64]:
        """Linear velocities (length unit per time unit), exact.

        Parameters
        ----------
        t : array_like, any shape
            Times.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.linear_velocity(1.0).round(12)
        array([1., 0., 0.])
        """
        shape, out = self._pos(t)
        return out[:, 3:6].reshape((*shape, 3))

    def linear_acceleration(self, t: ArrayLike) -> NDArray[np.float64]:
        """Linear accelerations, exact (zero at the ends for the natural cubic).

        Parameters
        ----------
        t : array_like, any shape
            Times.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.linear_acceleration(0.0).round(12)
        array([0., 0., 0.])
        """
        shape, out = self._pos(t)
        return out[:, 6:9].reshape((*shape, 3))

    def angular_velocity(self, t: ArrayLike, frame: str = "world") -> NDArray[np.float64]:
        """Angular velocities (rad per time unit) of the orientation spline.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        frame : {"world", "body"}, default "world"
            World or body frame; scipy's ``RotationSpline`` gives the body frame.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.angular_velocity(1.0, frame="body").shape
        (3,)
        """
        return self.rotation.angular_velocity(t, frame)

    def angular_acceleration(self, t: ArrayLike, frame: str = "world") -> NDArray[np.float64]:
        """Angular accelerations (rad per time unit squared) of the orientation spline.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        frame : {"world", "body"}, default "world"
            World or body frame; scipy's ``RotationSpline`` gives the body frame.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1, 2], [[0, 0, 0], [1, 0, 0], [2, 0, 0]])
        >>> pose.angular_acceleration([0.5, 1.5]).shape
        (2, 3)
        """
        return self.rotation.angular_acceleration(t, frame)

    def __call__(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(orientations, positions) at times ``t``: shapes t.shape + (4,) and t.shape + (3,)."""
        return self.orientation(t), self.position(t)

    def transform_points(self, t: ArrayLike, points: ArrayLike) -> NDArray[np.float64]:
        """World coordinates ``R(t) p + x(t)`` of points fixed in the body.

        Parameters
        ----------
        t : array_like, shape (M,) or scalar
            Times.
        points : array_like, shape (P, 3)
            Points in body coordinates.

        Returns
        -------
        numpy.ndarray, shape (M, P, 3)

        Raises
        ------
        ValueError
            If a time is outside the domain or ``points`` is not of shape (P, 3).

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90]], degrees=True)
        >>> pose = qs.PoseSpline(keys, [0, 1], [[0, 0, 0], [0, 0, 1]], rotation="slerp")
        >>> pose.transform_points([0.0, 1.0], [[1.0, 0.0, 0.0]]).round(12)
        array([[[1., 0., 0.]],
        <BLANKLINE>
               [[0., 1., 1.]]])
        """
        q = np.atleast_2d(self.orientation(np.atleast_1d(t)))
        x = np.atleast_2d(self.position(np.atleast_1d(t)))
        v = with_width(points, "points", 3).reshape(-1, 3)
        return rotate(q[:, None, :], v[None, :, :]) + x[:, None, :]
