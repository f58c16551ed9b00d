"""The interface every spline shares: :class:`Spline`, and the names its users share.

Every spline maps time to unit quaternions (w, x, y, z) and gives exact time derivatives —
q', q'', q''' and the angular velocity, acceleration and jerk in the world or body frame — by
Taylor-mode differentiation of the same formula in the Rust core (never finite differences).
Times outside the domain follow one of :data:`EXTRAPOLATE` (Rust ``spline/eval.rs``).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_times
from .._util.checks import choice, integer, real, short

__all__ = ["DEFAULT_MAX_SAMPLES", "EXTRAPOLATE", "Spline", "describe"]

_FRAMES = ("world", "body")
# scipy's RotationSpline(t, order) returns body-frame rates; ours takes an output array there.
_F64 = np.dtype(np.float64)

_ORDER_HINT = (
    "{name}(t, {order}): the second argument is `out`, an output array, not scipy's derivative "
    "order; for RotationSpline(t, 1) / (t, 2) use s.angular_velocity(t, frame='body') / "
    "s.angular_acceleration(t, frame='body'), for the quaternion's derivative "
    "s.derivative(t, {order})"
)

#: The rules for times outside a spline's domain (``extrapolate=``).
EXTRAPOLATE = ("raise", "clamp", "linear", "periodic")

#: Samples a :meth:`Spline.sample` call produces at most unless told otherwise (also the
#: default of :func:`quatspline.ops.sample_times` and the commands).
DEFAULT_MAX_SAMPLES = 10_000_000


def _frozen_copy(v):
    if isinstance(v, np.ndarray):
        c = np.array(v, copy=True)
        c.flags.writeable = False
        return c
    return v


def _snapshot(v):
    """A copy of a construction argument that a caller's later mutation cannot reach
    (arrays, lists, tuples and dicts are copied; splines and scalars are immutable)."""
    if isinstance(v, np.ndarray):
        return _frozen_copy(v)
    if isinstance(v, (list, tuple)):
        return type(v)(_snapshot(x) for x in v) if type(v) in (list, tuple) else v
    if isinstance(v, dict):
        return {k: _snapshot(x) for k, x in v.items()}
    return v


def _recording(init):
    """Wraps a method class's ``__init__`` so that the outermost call keeps its arguments:
    what :meth:`Spline.__reduce__` rebuilds the spline from."""

    @functools.wraps(init)
    def __init__(self, *args, **kwargs):
        if "_made" not in self.__dict__:
            skip = type(self)._not_pickled
            kept = {k: _snapshot(v) for k, v in kwargs.items() if k not in skip}
            self.__dict__["_made"] = (type(self), tuple(_snapshot(a) for a in args), kept)
        init(self, *args, **kwargs)

    return __init__


def _rebuild(cls, args, kwargs):
    """Unpickles a spline: the same construction, so the same curve bit for bit."""
    return cls(*args, **kwargs)


def describe(obj, segments: int, **fields: object) -> str:
    """``Name(segments=…, domain=[a, b], field=value, …)``: the repr of every spline object
    (splines, pose splines, fitted poses)."""
    a, b = obj.domain
    extra = "".join(f", {k}={v}" for k, v in fields.items())
    return f"{type(obj).__name__}(segments={segments}, domain=[{a:g}, {b:g}]{extra})"


class Spline:
    """One interface for every curve: call it for orientations, ask it for derivatives.

    Do not make a ``Spline`` directly: use one of the method classes (:class:`C3Spline`,
    :class:`NaturalSpline`, …) or :func:`quatspline.spline` with a method name.

    ``s(t)`` gives orientations of shape ``t.shape + (4,)`` — (4,) for a scalar time. Times
    outside ``s.domain`` follow ``extrapolate``: ``"raise"`` (default, ``ValueError``),
    ``"clamp"`` (hold the end orientation, zero derivatives), ``"linear"`` (constant angular
    velocity: the end's one-sided rate, zero acceleration) or ``"periodic"`` (repeat the
    domain; smooth for ``ends="closed"`` splines, with a jump at every period boundary
    otherwise). Times need not be sorted (sorted times are fastest). Derivatives are exact:
    they come from the same formula as the orientation by Taylor-mode arithmetic, never by
    finite differences. Rates are in radians per unit of time.

    Parameters
    ----------
    core : quatspline._core.Spline
        The compiled curve (made by a method class).
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        What to do with times outside the domain.
    **params
        The construction parameters, kept in ``params`` (used by :func:`reparameterize`).

    Attributes
    ----------
    extrapolate : str
        ``"raise"``, ``"clamp"``, ``"linear"`` or ``"periodic"``; may be changed after
        construction.
    params : dict
        The construction parameters.

    See Also
    --------
    quatspline.spline : make any method by name.
    quatspline.continuity : the continuity certificate of every joint.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 180]], degrees=True)
    >>> s = qs.C3Spline(keys, [0.0, 1.0, 2.0])
    >>> s
    C3Spline(segments=2, domain=[0, 2])
    >>> s(np.linspace(0, 2, 5)).shape, s(1.0).shape
    ((5, 4), (4,))
    >>> s.method, s.continuity, s.interpolates
    ('c3', 3, True)
    """

    #: Construction arguments that are not part of the curve (callbacks) and are not pickled.
    _not_pickled: tuple[str, ...] = ("progress",)

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "__init__" in cls.__dict__:
            cls.__init__ = _recording(cls.__dict__["__init__"])

    def __reduce__(self):
        """Pickles a spline as its construction (class and arguments): unpickling rebuilds
        it, bit for bit the same curve; ``extrapolate`` travels with it. Splines so travel
        to Dask workers and to ``multiprocessing`` pools."""
        made = self.__dict__.get("_made")
        if made is None:
            raise TypeError(
                f"cannot pickle a {type(self).__name__} made from a compiled curve directly; "
                "make it with a method class or quatspline.spline()"
            )
        return (_rebuild, made, {"extrapolate": self.extrapolate})

    def __init__(self, core: _core.Spline, extrapolate: str = "raise", **params):
        choice(extrapolate, "extrapolate", EXTRAPOLATE)
        self._core = core
        self.extrapolate = extrapolate
        # Own copies (read-only) of array parameters: a caller mutating its keys or times after
        # construction must not change what reparameterize() and friends read.
        self.params = {k: _frozen_copy(v) for k, v in params.items()}

    # ---- description ------------------------------------------------------------------
    @property
    def method(self) -> str:
        """The method's registry name."""
        return self._core.name

    @property
    def domain(self) -> tuple[float, float]:
        """(t_start, t_end)."""
        return self._core.domain

    @property
    def joints(self) -> np.ndarray:
        """Times of the segment joints, both ends included."""
        return np.array(self._core.joints)

    @property
    def interpolates(self) -> bool:
        """Whether the curve passes through its keys at the joints."""
        return self._core.interpolates

    @property
    def closed(self) -> bool:
        """Whether the curve is a closed loop (``ends="closed"``): its end joins its start."""
        return self._core.closed

    @property
    def continuity(self) -> int | float:
        """The parametric continuity order in time guaranteed at interior joints."""
        c = self._core.continuity
        return float("inf") if c == 255 else c

    def __repr__(self) -> str:
        return describe(self, len(self.joints) - 1)

    # ---- evaluation -------------------------------------------------------------------
    def _eval(self, t, order: int):
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        out = self._core.evaluate(flat, order, self.extrapolate)
        return ta.shape, out

    def __call__(self, t: ArrayLike, out: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
        """Orientations at times ``t``.

        Parameters
        ----------
        t : array_like, any shape
            Times (also ``datetime64``/``timedelta64`` and pandas times, in seconds).
        out : numpy.ndarray, optional
            A float64, C-contiguous, writeable array of shape ``t.shape + (4,)``: the result
            is written there (no allocation) and ``out`` is returned. Not scipy's derivative
            order: ``s(t, 1)`` raises a ``TypeError`` that names
            ``s.angular_velocity(t, frame="body")``, the equivalent of scipy's
            ``RotationSpline(t, 1)``.

        Returns
        -------
        numpy.ndarray, shape t.shape + (4,)
            Unit quaternions (w, x, y, z).

        Raises
        ------
        ValueError
            If a time is not finite or outside the domain (with ``extrapolate="raise"``), or
            ``out`` has the wrong dtype, shape or layout.
        TypeError
            If ``out`` is an integer (scipy's ``order``).

        Examples
        --------
        >>> import numpy as np
        >>> import quatspline as qs
        >>> s = qs.PiecewiseSlerp(qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0]], degrees=True))
        >>> float(np.degrees(qs.as_rotvec(s(0.5)))[0].round(10))
        45.0
        >>> buf = np.empty((3, 4))
        >>> s([0.0, 0.5, 1.0], buf) is buf
        True
        """
        if out is None:
            # small-call fast paths: a float64 vector (the binding copies small ones without
            # borrow tracking and takes any strides), or one float; `is` against the canonical
            # dtype is a pointer test (`==` converts its operand first)
            tt = type(t)
            if tt is np.ndarray and t.dtype is _F64 and t.ndim == 1:
                return self._core.evaluate(t, 0, self.extrapolate)
            if tt is float:
                return self._core.evaluate1(t, self.extrapolate)
            shape, res = self._eval(t, 0)
            return res.reshape((*shape, 4))
        if isinstance(out, (int, np.integer)) and not isinstance(out, bool):
            raise TypeError(_ORDER_HINT.format(order=int(out), name=type(self).__name__))
        ta = as_times(t, "t")
        want = (*ta.shape, 4)
        if not isinstance(out, np.ndarray) or out.dtype != np.float64:
            raise ValueError(
                f"out: expected a float64 numpy array, got {getattr(out, 'dtype', type(out))}"
            )
        if out.shape != want:
            raise ValueError(f"out: expected shape {want}, got {out.shape}")
        if not out.flags.c_contiguous or not out.flags.writeable:
            raise ValueError("out: expected a writeable C-contiguous array")
        flat = np.ascontiguousarray(ta.reshape(-1))
        self._core.evaluate_out(flat, 0, self.extrapolate, out.reshape(-1, 4))
        return out

    def derivative(self, t: ArrayLike, order: int = 1) -> NDArray[np.float64]:
        """The ``order``-th time derivative of q, as quaternions.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        order : {0, 1, 2, 3}, default 1
            Derivative order.

        Returns
        -------
        numpy.ndarray, shape t.shape + (4,)
            q, q', q'' or q''' (per time unit to the power ``order``). At a joint the
            right-hand segment is used.

        Raises
        ------
        TypeError
            If ``order`` is not an integer (2.0 included).
        ValueError
            If ``order`` is not 0–3, or a time is not finite or outside the domain.

        See Also
        --------
        angular_velocity : the rotation rate as a 3-vector.

        Examples
        --------
        >>> import numpy as np
        >>> import quatspline as qs
        >>> s = qs.PiecewiseSlerp([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]], [0.0, 2.0])
        >>> dq = s.derivative(1.0)  # |q'| = half the angular speed: (π/2 rad/s) / 2
        >>> bool(np.isclose(np.linalg.norm(dq), np.pi / 4))
        True
        """
        order = integer(order, "order", 0, 3)
        shape, out = self._eval(t, order)
        return out[:, 4 * order :].reshape((*shape, 4))

    def derivatives(self, t: ArrayLike, order: int = 3) -> NDArray[np.float64]:
        """q, q', …, q^(order) together, from one evaluation.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        order : {0, 1, 2, 3}, default 3
            Highest derivative order.

        Returns
        -------
        numpy.ndarray, shape t.shape + (order + 1, 4)

        Raises
        ------
        TypeError
            If ``order`` is not an integer (2.0 included).
        ValueError
            If ``order`` is not 0–3, or a time is not finite or outside the domain.

        Examples
        --------
        >>> import quatspline as qs
        >>> s = qs.C3Spline(qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [45, 0, 0]], degrees=True))
        >>> s.derivatives([0.5, 1.5]).shape
        (2, 4, 4)
        """
        order = integer(order, "order", 0, 3)
        shape, out = self._eval(t, order)
        return out.reshape((*shape, order + 1, 4))

    def _angular(self, t, order: int, frame: str) -> np.ndarray:
        if frame not in _FRAMES:
            raise ValueError(f"frame: expected one of {_FRAMES}, got {frame!r}")
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        out = self._core.angular(flat, order, frame == "body", self.extrapolate)
        return out.reshape((*ta.shape, 3))

    def angular_velocity(self, t: ArrayLike, frame: str = "world") -> NDArray[np.float64]:
        """Angular velocity ω, exact, in radians per time unit.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        frame : {"world", "body"}, default "world"
            ``"world"``: the rate seen from the fixed frame, ``2 vec(q' q*)``. ``"body"``:
            the rate in the body's own axes, ``2 vec(q* q')``, what a gyroscope measures.
            scipy's ``RotationSpline(t, 1)`` / ``(t, 2)`` return the body frame;
            pytransform3d's ``quaternion_gradient`` the world frame. The norms are equal.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If ``frame`` is not "world" or "body", or a time is not finite or outside the
            domain.

        See Also
        --------
        angular_acceleration, jerk

        Examples
        --------
        >>> import numpy as np
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90]], degrees=True)
        >>> s = qs.PiecewiseSlerp(keys, [0.0, 2.0])
        >>> s.angular_velocity(1.0).round(12)  # 90° in 2 s about z
        array([0.        , 0.        , 0.78539816])
        >>> s.angular_velocity(1.0, frame="body").round(12)  # the same: the axis is fixed
        array([0.        , 0.        , 0.78539816])
        """
        return self._angular(t, 1, frame)

    def angular_acceleration(self, t: ArrayLike, frame: str = "world") -> NDArray[np.float64]:
        """Angular acceleration dω/dt, exact, in radians per time unit squared.

        World frame ``2 vec(q'' q*)``, body frame ``2 vec(q* q'')``.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        frame : {"world", "body"}, default "world"
            ``"world"``: the rate seen from the fixed frame, ``2 vec(q' q*)``. ``"body"``:
            the rate in the body's own axes, ``2 vec(q* q')``, what a gyroscope measures.
            scipy's ``RotationSpline(t, 1)`` / ``(t, 2)`` return the body frame;
            pytransform3d's ``quaternion_gradient`` the world frame. The norms are equal.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If ``frame`` is not "world" or "body", or a time is not finite or outside the
            domain.

        See Also
        --------
        angular_velocity, jerk

        Examples
        --------
        >>> import quatspline as qs
        >>> s = qs.PiecewiseSlerp(qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90]], degrees=True))
        >>> s.angular_acceleration(0.5)  # constant speed
        array([0., 0., 0.])
        """
        return self._angular(t, 2, frame)

    def jerk(self, t: ArrayLike, frame: str = "world") -> NDArray[np.float64]:
        """Angular jerk d²ω/dt², exact, in radians per time unit cubed.

        World frame ``2 vec(q''' q* + q'' q'*)``, body frame ``2 vec(q'* q'' + q* q''')``.

        Parameters
        ----------
        t : array_like, any shape
            Times.
        frame : {"world", "body"}, default "world"
            ``"world"``: the rate seen from the fixed frame, ``2 vec(q' q*)``. ``"body"``:
            the rate in the body's own axes, ``2 vec(q* q')``, what a gyroscope measures.
            scipy's ``RotationSpline(t, 1)`` / ``(t, 2)`` return the body frame;
            pytransform3d's ``quaternion_gradient`` the world frame. The norms are equal.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)

        Raises
        ------
        ValueError
            If ``frame`` is not "world" or "body", or a time is not finite or outside the
            domain.

        See Also
        --------
        angular_velocity, angular_acceleration

        Examples
        --------
        >>> import numpy as np
        >>> import quatspline as qs
        >>> s = qs.C3Spline(qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [45, 0, 0]], degrees=True))
        >>> left, right = s.jerk([1.0 - 1e-9, 1.0])
        >>> bool(np.allclose(left, right, atol=1e-6))  # C³: the jerk is continuous
        True
        """
        return self._angular(t, 3, frame)

    def segment_derivatives(self, segment: int, t: float) -> NDArray[np.float64]:
        """q, q', q'', q''' of one segment's formula at time ``t``.

        Gives one-sided limits at joints (each segment's own formula, also outside the segment
        but inside the spline's domain).

        Parameters
        ----------
        segment : int
            Segment index, 0 … ``len(s.joints) − 2``.
        t : float
            Time.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            Rows q, q', q'', q'''.

        Raises
        ------
        TypeError
            If ``segment`` is not an integer or ``t`` not a real number.
        ValueError
            If ``segment`` is out of range, or ``t`` is not finite or outside the domain.

        Examples
        --------
        >>> import numpy as np
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [0, 0, 0]], degrees=True)
        >>> s = qs.PiecewiseSlerp(keys)
        >>> left, right = s.segment_derivatives(0, 1.0), s.segment_derivatives(1, 1.0)
        >>> bool(np.allclose(left[0], right[0])), bool(np.allclose(left[1], right[1]))
        (True, False)
        """
        nseg = len(self.joints) - 1
        segment = integer(segment, "segment", 0, nseg - 1)
        x = real(t, "t")
        a, b = self.domain
        if not a <= x <= b:
            raise ValueError(f"t: t = {x} is outside the spline's domain [{a}, {b}]")
        return self._core.segment_derivatives(segment, x)

    def sample(
        self,
        n: int | None = None,
        rate: float | None = None,
        max_samples: int = DEFAULT_MAX_SAMPLES,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Evenly spaced samples over the whole domain.

        Parameters
        ----------
        n : int, optional
            Number of samples, both ends included.
        rate : float, optional
            Samples per time unit, starting at the domain's start. Give exactly one of ``n``
            and ``rate``.
        max_samples : int, default DEFAULT_MAX_SAMPLES
            Refuse to produce more samples than this: the count (for ``rate``, from
            rate × span) is checked before anything is allocated.

        Returns
        -------
        times : numpy.ndarray, shape (M,)
        quats : numpy.ndarray, shape (M, 4)

        Raises
        ------
        ValueError
            If neither or both of ``n`` and ``rate`` are given, either is not positive, or
            the number of samples would exceed ``max_samples``.

        Examples
        --------
        >>> import quatspline as qs
        >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [45, 0, 0]], degrees=True)
        >>> s = qs.C3Spline(keys, [0, 1, 3])
        >>> t, q = s.sample(rate=100)
        >>> t.shape, q.shape, float(t[-1])
        ((301,), (301, 4), 3.0)
        """
        a, b = self.domain
        if (n is None) == (rate is None):
            raise ValueError("sample: give exactly one of n or rate")
        max_samples = integer(max_samples, "max_samples", lo=1)
        if n is not None:
            n = integer(n, "n", lo=1)
            if n > max_samples:
                raise ValueError(
                    f"n: {short(n)} samples is more than max_samples = {short(max_samples)}"
                )
            t = np.linspace(a, b, n)
        else:
            rate = real(rate, "rate", positive=True)
            span = (b - a) * rate  # a Python float: nothing allocated yet (inf when huge)
            count = math.floor(span + 1e-9) + 1 if math.isfinite(span) else math.inf
            if not count <= max_samples:
                raise ValueError(
                    f"rate: {short(rate)} samples per unit over [{short(a)}, {short(b)}] gives "
                    f"{short(count)} samples, more than max_samples = {short(max_samples)}"
                )
            t = a + np.arange(int(count)) / rate
        return t, self(t)
