"""Keyframe splines behind one interface: ``quatspline.Spline``.

Every spline maps time to unit quaternions (w, x, y, z) and gives exact time derivatives —
q', q'', q''' and the angular velocity, acceleration and jerk in the world or body frame — by
Taylor-mode differentiation of the same formula in the Rust core (never finite differences).

================================ ============ ================== ================================
class                            interpolates continuity         source
================================ ============ ================== ================================
``PiecewiseSlerp``               yes          C⁰                 Shoemake 1985
``PiecewiseNlerp``               yes          C⁰                 baseline
``PiecewiseLinEuler``            yes          C⁰                 baseline
``PiecewiseLinMat``              yes          C⁰                 baseline
``SphericalBezier``              end points   C^∞ (one curve)    Shoemake 1985 (de Casteljau)
``CumulativeBezier``             end points   C^∞ (one curve)    Kim, Kim & Shin 1995
``Squad``                        yes          C¹                 Shoemake 1987
``CatmullRom``                   yes          C¹                 Gortler 2012, ch. 9
``CumulativeBSpline``            no           C^(k−2), C² cubic  Kim et al. 1995; Sommer et al.
                                                                 2020
``NaturalSpline``                yes          C² (global)        scipy ``RotationSpline``
``BetaSpline``                   no           G¹ (not G²)        He et al. 2022
``C3Spline``                     yes          C³                 Wang & Zhou 2023 (patent)
================================ ============ ================== ================================

The documentation's mathematics pages give every formula, with references and errata.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _core
from .._util.arrays import as_real, as_times, with_width
from .._util.checks import choice, integer, real, short

__all__ = [
    "BetaSpline",
    "C3Spline",
    "CatmullRom",
    "CumulativeBSpline",
    "CumulativeBezier",
    "NaturalSpline",
    "PiecewiseLinEuler",
    "PiecewiseLinMat",
    "PiecewiseNlerp",
    "PiecewiseSlerp",
    "Spline",
    "SphericalBezier",
    "Squad",
    "path_length",
    "reparameterize",
]

_FRAMES = ("world", "body")
# scipy's RotationSpline(t, order) returns body-frame rates; ours takes an output array there.
_F64 = np.dtype(np.float64)

_ORDER_HINT = (
    "{name}(t, {order}): the second argument is `out`, an output array, not scipy's derivative "
    "order; for RotationSpline(t, 1) / (t, 2) use s.angular_velocity(t, frame='body') / "
    "s.angular_acceleration(t, frame='body'), for the quaternion's derivative "
    "s.derivative(t, {order})"
)
_EXTRAPOLATE = ("raise", "clamp", "linear", "periodic")


#: Samples a :meth:`Spline.sample` call produces at most unless told otherwise (also the
#: default of :func:`quatspline.ops.sample_times` and the commands).
DEFAULT_MAX_SAMPLES = 10_000_000


def _domain(domain) -> tuple[float, float]:
    """``domain`` as (t0, t1): a pair of real numbers (TypeError otherwise), finite with
    t0 < t1 (ValueError otherwise)."""
    kinds = (numbers.Real, np.integer, np.floating)
    if isinstance(domain, (str, bytes)) or not hasattr(domain, "__len__") or len(domain) != 2:
        raise TypeError(
            f"domain: expected a pair (t0, t1) of real numbers, got {type(domain).__name__} "
            f"{short(domain) if isinstance(domain, kinds) else ''}".rstrip()
        )
    if any(isinstance(v, (bool, np.bool_)) or not isinstance(v, kinds) for v in domain):
        kinds_given = ", ".join(type(v).__name__ for v in domain)
        raise TypeError(f"domain: expected a pair (t0, t1) of real numbers, got ({kinds_given})")
    t0, t1 = float(domain[0]), float(domain[1])
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < t1):
        raise ValueError(f"domain: expected finite t0 < t1, got ({short(t0)}, {short(t1)})")
    return t0, t1


def _keys(q, name: str) -> np.ndarray:
    a = with_width(q, name, 4)
    if a.ndim != 2:
        raise ValueError(f"{name}: expected shape (N, 4), got {a.shape}")
    return a


def _times(times, n: int):
    if times is None:
        return None
    t = as_times(times, "times")
    if t.ndim != 1:
        raise ValueError(f"times: expected shape ({n},), got {t.shape}")
    return np.ascontiguousarray(t)


def _frozen_copy(v):
    if isinstance(v, np.ndarray):
        c = np.array(v, copy=True)
        c.flags.writeable = False
        return c
    return v


def _describe(obj, segments: int, **fields: object) -> str:
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

    def __init__(self, core: _core.Spline, extrapolate: str = "raise", **params):
        choice(extrapolate, "extrapolate", _EXTRAPOLATE)
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
        return _describe(self, len(self.joints) - 1)

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


class PiecewiseNlerp(Spline):
    """Baseline: normalised lerp between consecutive keys (C⁰, speed varies).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    PiecewiseSlerp : the same path at constant speed.

    Examples
    --------
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [45, 0, 0]], degrees=True)
    >>> s = qs.PiecewiseNlerp(keys)
    >>> s.continuity, s.domain
    (0, (0.0, 2.0))
    """

    def __init__(self, quats, times=None, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(_core.nlerp_spline(q, t), extrapolate, quats=q, times=t)


class PiecewiseLinEuler(Spline):
    """Baseline: Euler angles interpolated linearly between keys (C⁰).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    seq : str, default "xyz"
        Euler sequence, scipy's convention (see :func:`quatspline.from_euler`).
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    PiecewiseSlerp

    Examples
    --------
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0.0, 0.0, 0.0], [0.0, 0.0, 80.0]], degrees=True)
    >>> s = qs.PiecewiseLinEuler(keys, seq="xyz")
    >>> qs.as_euler(s(0.25), "xyz", degrees=True).round(10)
    array([ 0.,  0., 20.])
    """

    def __init__(self, quats, times=None, seq: str = "xyz", extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.lin_euler_spline(q, t, str(seq)), extrapolate, quats=q, times=t, seq=seq
        )


class PiecewiseLinMat(Spline):
    """Baseline: rotation matrices interpolated entrywise, projected back to rotations (C⁰).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    PiecewiseSlerp

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.PiecewiseLinMat(qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0]], degrees=True))
    >>> s(0.5).shape
    (4,)
    """

    def __init__(self, quats, times=None, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(_core.lin_mat_spline(q, t), extrapolate, quats=q, times=t)


class PiecewiseSlerp(Spline):
    """Slerp between consecutive keys: C⁰, constant angular speed within each segment.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    quatspline.slerp : two keys.
    reparameterize : even out the speed across segments.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 90]], degrees=True)
    >>> s = qs.PiecewiseSlerp(keys, [0.0, 1.0, 3.0])
    >>> np.linalg.norm(s.angular_velocity([0.5, 2.0]), axis=1).round(12)  # π/2 rad/s, then 0
    array([1.57079633, 0.        ])
    """

    def __init__(self, quats, times=None, canonicalize: bool = True, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.piecewise_slerp(q, t, bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
        )


class SphericalBezier(Spline):
    """One spherical Bézier curve of any degree: de Casteljau's algorithm with slerp.

    Shoemake (1985). The end tangents are ``q'(0) = n b₀ log(b₀* b₁)`` and
    ``q'(1) = n bₙ log(bₙ₋₁* bₙ)`` (per unit of the local parameter).

    Parameters
    ----------
    control_points : array_like, shape (n + 1, 4)
        Control quaternions b₀ … bₙ (or a scipy ``Rotation``); the curve starts at b₀ and
        ends at bₙ.
    domain : tuple of float, default (0.0, 1.0)
        The time interval the curve is mapped to.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    CumulativeBezier : the same end points and tangents, another curve.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> cp = qs.from_euler("xyz", [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0]], degrees=True)
    >>> s = qs.SphericalBezier(cp, domain=(0.0, 2.0))
    >>> bool(np.allclose(s([0.0, 2.0]), cp[[0, -1]]))
    True
    """

    def __init__(
        self,
        control_points,
        domain=(0.0, 1.0),
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(control_points, "control_points")
        d = _domain(domain)
        super().__init__(_core.spherical_bezier(q, d, bool(canonicalize)), extrapolate)


class CumulativeBezier(Spline):
    """One cumulative spherical Bézier curve (Kim, Kim & Shin 1995).

    ``q(t) = b₀ Π_j (b_{j−1}* b_j)^{B̃_j(t)}`` with the cumulative Bernstein polynomials
    ``B̃_j``. It has the end points and end tangents of :class:`SphericalBezier` with the
    same control points, and is a different curve in between.

    Parameters
    ----------
    control_points : array_like, shape (n + 1, 4)
        Control quaternions b₀ … bₙ (or a scipy ``Rotation``).
    domain : tuple of float, default (0.0, 1.0)
        The time interval the curve is mapped to.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    SphericalBezier

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> cp = qs.from_euler("xyz", [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0]], degrees=True)
    >>> s, b = qs.CumulativeBezier(cp), qs.SphericalBezier(cp)
    >>> bool(np.allclose(s.derivative(0.0), b.derivative(0.0)))  # same end tangent
    True
    """

    def __init__(
        self,
        control_points,
        domain=(0.0, 1.0),
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(control_points, "control_points")
        d = _domain(domain)
        super().__init__(_core.cumulative_bezier(q, d, bool(canonicalize)), extrapolate)


class Squad(Spline):
    """Shoemake's Squad (spherical quadrangle interpolation): interpolating, C¹ in time.

    Shoemake (1987). For non-uniform times each key gets an incoming and an outgoing inner
    point, chosen so that both sides have the same velocity in time; with uniform times
    both are Shoemake's. Squad is C¹, not C².

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"open"``: s₀⁺ = q₀, sₙ⁻ = qₙ. ``"rest"``: zero angular velocity at both ends.
        ``"closed"``: a periodic loop, C¹ across the seam (see ``quatspline.splines.keyframe``).
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still, with zero velocity at both ends
        of the hold.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    CatmullRom : also C¹, Gortler's construction.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [90, 45, 0], [0, 45, 30]], degrees=True)
    >>> s = qs.Squad(keys, [0.0, 1.0, 3.0, 3.5])
    >>> bool(np.allclose(s([0.0, 1.0, 3.0, 3.5]), keys)), [j.order for j in qs.continuity(s)]
    (True, [1, 1])
    """

    def __init__(
        self,
        quats,
        times=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        ends: str = "open",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.squad(q, t, bool(canonicalize), str(ends), bool(holds)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
            ends=ends,
            holds=holds,
        )


class CatmullRom(Spline):
    """Catmull–Rom through the keys with spherical Bézier segments: C¹ in time.

    Gortler (2012, ch. 9): segment i has inner control points ``exp(hᵢ Wᵢ/3) cᵢ`` and
    ``exp(−hᵢ Wᵢ₊₁/3) cᵢ₊₁`` with the key tangent ``Wᵢ = log(cᵢ₊₁ cᵢ₋₁⁻¹)/(hᵢ₋₁ + hᵢ)``;
    for uniform times this is exactly Gortler's construction.

    ``ends="reflect"`` (default) mirrors the missing end neighbours (two keys give slerp);
    ``ends="duplicate"`` repeats the end keys; ``ends="rest"`` stops at both ends;
    ``ends="closed"`` makes a periodic loop (see ``quatspline.splines.keyframe``). Without
    ``times``, ``alpha`` (0 uniform, 0.5 centripetal, 1 chordal) spaces the keys by their angles
    as the ``splines`` package does. ``holds`` (default True): consecutive equal keys hold exactly
    still. This is ``KochanekBartels`` at tension = continuity = bias = 0.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    ends : {"reflect", "duplicate", "rest", "closed"}, default "reflect"
        How the missing neighbours of the end keys are made: mirrored (two keys then give
        slerp), the end keys repeated, zero rate at both ends, or a closed loop.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain raise ``ValueError``, are clamped to it (the end
        orientation held, zero derivatives), continue at the end's angular velocity, or
        repeat the domain.
    alpha : float in [0, 1], optional
        Without ``times``: key spacing by angle to the power ``alpha`` (0 uniform, 0.5
        centripetal, 1 chordal). With ``times``, the times rule.
    holds : bool, default True
        Consecutive equal keys (q and −q count as equal) hold the orientation exactly.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    Squad

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [90, 0, 0], [90, 45, 0], [0, 45, 30]], degrees=True)
    >>> s = qs.CatmullRom(keys, [0.0, 1.0, 3.0, 3.5])
    >>> [j.order for j in qs.continuity(s)]
    [1, 1]
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "reflect",
        canonicalize: bool = True,
        extrapolate: str = "raise",
        alpha=None,
        holds: bool = True,
    ):
        from .keyframe import _alpha

        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.catmull_rom(q, t, str(ends), bool(canonicalize), _alpha(alpha), bool(holds)),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            canonicalize=canonicalize,
            alpha=alpha,
            holds=holds,
        )


class CumulativeBSpline(Spline):
    """Uniform cumulative B-spline of order k (cubic by default): C^(k−2), approximating.

    Kim, Kim & Shin (1995); the form used in visual-inertial estimation (Sommer et al.
    2020). Segment i spans ``[t0 + i·dt, t0 + (i+1)·dt]`` and uses control rotations
    i … i+k−1, so the domain is ``[t0, t0 + (n − k + 1)·dt]``. Non-uniform: ``knots=``
    (n + k non-decreasing knots, domain ``[u_{k−1}, u_n]``) or ``dt=[…]`` (the n + k − 1 knot
    spacings, ``u_{k−1} = t0``) give the non-uniform cumulative B-spline (De Boor basis, see
    ``quatspline.splines.knots``).

    Parameters
    ----------
    control_quats : array_like, shape (n, 4)
        Control rotations (or a scipy ``Rotation``); at least ``order`` of them. The curve
        does not pass through them.
    dt : float or array_like, default 1.0
        Knot spacing (time per segment), > 0; or the n + k − 1 knot spacings.
    t0 : float, default 0.0
        Start time.
    order : int, default 4
        B-spline order k (degree k − 1), 2 … 8.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"closed"``: the control rotations are used cyclically — n segments over
        ``[t0, t0 + n·dt]``, C^(k−2) across the seam (uniform knots only); a last control
        rotation equal to the first is kept (a hold across the seam with ``holds=True``),
        not dropped as the interpolating methods' closing key is. ``"rest"``
        (order ≥ 3, uniform knots): k − 2 copies of the first and last control rotation are
        added (fewer if a hold is there already), so the curve starts and ends on them with
        zero angular velocity (and acceleration, … up to derivative k − 2); the domain grows
        by 2(k − 2)·dt.
    holds : bool, default False
        Runs of consecutive equal control rotations (q or −q) become exact holds: a run of
        m is repeated to m + k − 2 copies, so the curve is exactly constant on m − 1 whole
        segments (listed in ``hold_intervals``) with derivatives up to k − 2 zero at their
        ends; each added copy lengthens the domain by ``dt`` (see
        ``quatspline.splines.keyframe.bspline_controls``). Off by default because control rotations
        are not keys: the construction moves the domain. Uniform knots only.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    BetaSpline : shape parameters, G¹.

    Examples
    --------
    >>> import quatspline as qs
    >>> angles = [[0, 0, 0], [30, 0, 0], [60, 0, 0], [90, 0, 0], [60, 0, 0]]
    >>> cp = qs.from_euler("xyz", angles, degrees=True)
    >>> s = qs.CumulativeBSpline(cp, dt=0.5)
    >>> s.domain, s.continuity, s.interpolates
    ((0.0, 1.0), 2, False)
    """

    def __init__(
        self,
        control_quats,
        dt: float = 1.0,
        t0: float = 0.0,
        order: int = 4,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        knots=None,
        ends: str = "open",
        holds: bool = False,
    ):
        if ends not in ("open", "rest", "closed"):
            raise ValueError(
                f"ends: CumulativeBSpline does not support {ends!r}; supported: open, rest, closed"
            )
        q = _keys(control_quats, "control_quats")
        order = integer(order, "order")
        if not 2 <= order <= 12:  # the core's rule and message (-1 overflowed its usize before)
            raise ValueError(f"order: expected 2 ≤ order ≤ 12, got {short(order)}")
        self.hold_intervals: list[tuple[float, float]] = []
        if (ends != "open" or holds) and (knots is not None or np.ndim(dt) != 0):
            raise ValueError(
                f"{'ends' if ends != 'open' else 'holds'}: closed and rest ends and holds need "
                "uniform knots (a scalar dt, no knots=)"
            )
        if ends == "rest" or holds:
            from .keyframe import bspline_controls

            q = bspline_controls(q, order, ends, bool(holds))
        if knots is not None or np.ndim(dt) != 0:
            # Non-uniform knots (explicit, or per-interval spacings): see bspline.py.
            from .knots import _core_spline

            core = _core_spline(q, dt, t0, order, bool(canonicalize), knots)
            super().__init__(core, extrapolate)
            return
        dt, t0 = real(dt, "dt", positive=True), real(t0, "t0")
        super().__init__(
            _core.cumulative_bspline(
                q, float(dt), float(t0), int(order), bool(canonicalize), ends == "closed"
            ),
            extrapolate,
        )
        if holds:
            from .keyframe import _bspline_hold_intervals

            self.hold_intervals = _bspline_hold_intervals(q, order, ends == "closed", dt, t0)


class NaturalSpline(Spline):
    """The global interpolating C² spline (the construction of scipy's ``RotationSpline``).

    Every key moves every segment (global support). Segment i is
    ``qᵢ exp(½ rᵢ(τ − τᵢ))`` with a cubic rotation vector ``rᵢ``; the key rates follow from
    continuity of angular velocity and acceleration, a non-linear system solved by
    iterating a block-tridiagonal solve.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    ends : {"natural", "clamped", "rest", "closed"}, default "natural"
        ``"natural"``: zero angular acceleration at both ends. ``"clamped"``: the body
        angular velocities ``start_rate`` and ``end_rate`` at the ends. ``"rest"``: zero
        angular velocity at both ends. ``"closed"``: a periodic loop, C² across the seam
        (see ``quatspline.splines.keyframe``).
    start_rate, end_rate : array_like, shape (3,), optional
        Body-frame end rates for ``ends="clamped"`` (rad per time unit); by default the end
        segments' chord rates, which is exactly what scipy's ``RotationSpline`` does.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still: the rates at the keys bounding
        a hold are pinned to zero, so the curve is C¹ (not C²) there — a cubic cannot also
        zero the acceleration (``continuity`` then reports 1).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    C3Spline : local support, C³.

    Examples
    --------
    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation, RotationSpline
    >>> import quatspline as qs
    >>> keys, times = Rotation.random(5, random_state=0), [0.0, 1.0, 1.5, 3.0, 4.0]
    >>> s = qs.NaturalSpline(keys, times, ends="clamped")
    >>> t = np.linspace(0, 4, 9)
    >>> bool(np.allclose(s.angular_velocity(t, frame="body"), RotationSpline(times, keys)(t, 1),
    ...                  rtol=1e-5, atol=1e-6))
    True
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "natural",
        start_rate=None,
        end_rate=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        if not isinstance(ends, str):
            raise TypeError(f"ends: expected a string, got {type(ends).__name__}")
        if ends == "natural":
            for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
                if r is not None:
                    raise ValueError(
                        f"{name}: only used with ends='clamped' (natural ends have zero angular "
                        "acceleration, not a given rate)"
                    )
        rates = []
        for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
            if r is None:
                rates.append(None)
                continue
            v = as_real(r, name)
            if v.shape != (3,):
                raise ValueError(f"{name}: expected shape (3,), got {v.shape}")
            rates.append(tuple(float(x) for x in v))
        super().__init__(
            _core.natural_spline(
                q, t, str(ends), rates[0], rates[1], bool(canonicalize), bool(holds)
            ),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            start_rate=start_rate,
            end_rate=end_rate,
            canonicalize=canonicalize,
            holds=holds,
        )


def path_length(spline: Spline, per_segment: int = 8) -> float:
    """Total rotation angle ``∫|ω| dt`` over the domain, in radians.

    Computed by Gauss–Legendre quadrature with 8 nodes on each of ``per_segment`` pieces of
    every segment.

    Parameters
    ----------
    spline : Spline
        Any spline.
    per_segment : int, default 8
        Pieces per segment.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 0, 0]], degrees=True)
    >>> s = qs.PiecewiseSlerp(keys)
    >>> round(float(np.degrees(qs.path_length(s))), 9)
    180.0
    """
    j = spline.joints
    edges = np.concatenate(
        [np.linspace(a, b, per_segment + 1)[:-1] for a, b in zip(j[:-1], j[1:])] + [j[-1:]]
    )
    return _gauss_legendre(edges, lambda t: np.linalg.norm(spline.angular_velocity(t), axis=-1))


def _gauss_legendre(edges: np.ndarray, f) -> float:
    """∫ f(t) dt from ``edges[0]`` to ``edges[-1]``, by 8-point Gauss–Legendre on every interval
    between consecutive ``edges`` (place them where ``f`` is not smooth: spline joints).
    ``f`` maps an array of times (n_intervals, 8) to values of the same shape."""
    x, w = np.polynomial.legendre.leggauss(8)
    a, b = edges[:-1, None], edges[1:, None]
    return float(np.sum(0.5 * (b - a) * w * f(0.5 * (b - a) * x + 0.5 * (a + b))))


def reparameterize(spline: Spline, kind: str = "angle") -> Spline:
    """The same method through the same keys, re-timed for an even angular speed.

    ``kind="angle"``: each segment's duration becomes proportional to its rotation angle,
    keeping the start and end times, so the angular speed is (near) constant across
    segments (interpolating methods made from keys and times). ``kind="arc_length"`` works
    for ANY spline: the same path at exactly constant angular speed over the same domain,
    with exact derivatives (``quatspline.splines.timing.arc_length``).

    Parameters
    ----------
    spline : Spline
        An interpolating spline made from keys and times (``PiecewiseSlerp``, ``Squad``,
        ``CatmullRom``, ``NaturalSpline``, ``C3Spline``, the baselines).
    kind : {"angle", "arc_length"}, default "angle"
        Re-timing rule.

    Returns
    -------
    Spline
        A new spline of the same class (the input itself if every key is the same).

    Raises
    ------
    ValueError
        If ``kind`` is unknown or the spline is not built from keys at times.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 10], [0, 0, 100]], degrees=True)
    >>> s = qs.reparameterize(qs.PiecewiseSlerp(keys, [0.0, 1.0, 2.0]))
    >>> s.joints.round(6)
    array([0. , 0.2, 2. ])
    """
    if kind == "arc_length":
        from .timing import arc_length

        return arc_length(spline)
    if kind != "angle":
        raise ValueError(f"kind: expected 'angle' or 'arc_length', got {kind!r}")
    if "quats" not in spline.params:
        raise ValueError(
            f"reparameterize: {type(spline).__name__} is not built from keys at times; "
            "angle reparameterisation needs an interpolating spline"
        )
    q = spline.params["quats"]
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    ang = 2 * np.arctan2(
        np.linalg.norm(q[1:] - q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
        np.linalg.norm(q[1:] + q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
    )
    a, b = spline.domain
    total = ang.sum()
    if total == 0:
        return spline
    share = np.maximum(ang, 1e-9 * total)
    times = a + (b - a) * np.concatenate([[0.0], np.cumsum(share) / share.sum()])
    times[-1] = b
    params = dict(spline.params, times=times)
    return type(spline)(**params, extrapolate=spline.extrapolate)


def _per(v, name: str) -> np.ndarray:
    a = np.atleast_1d(as_real(v, name)).astype(np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a scalar or a 1-D array, got shape {a.shape}")
    return np.ascontiguousarray(a)


class BetaSpline(Spline):
    """The Beta quaternion spline (He et al. 2022): G¹ exactly, not G² in general.

    β₁ = 1, β₂ = 0 gives the Bézier points of the uniform cubic B-spline. The paper's claim
    of G² is false in general; :func:`quatspline.continuity` reports the G² residual and the
    residual of the corrected Theorem 2 condition instead.

    Parameters
    ----------
    vertices : array_like, shape (l + 3, 4)
        Auxiliary control vertices p₀ … p_{l+2} (at least 4), or a scipy ``Rotation``. The
        curve does not pass through them.
    beta1 : float or array_like, shape (l + 3,), default 1.0
        Bias β₁ > 0, one value or one per vertex.
    beta2 : float or array_like, shape (l + 3,), default 0.0
        Tension β₂, one value or one per vertex.
    times : array_like, shape (l + 1,), optional
        Joint times of the l segments; default 0 … l.
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
        The paper's Example 1 is reproduced only with ``canonicalize=False``.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the domain raise ``ValueError``, or are clamped to it (the end
        orientation held, zero derivatives).

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    quatspline.continuity : reports the G¹ and G² residuals.
    CumulativeBSpline

    Examples
    --------
    >>> import quatspline as qs
    >>> s = qs.BetaSpline(qs.examples.BETA_EXAMPLE1_VERTICES, beta1=1.0, beta2=0.5,
    ...                   canonicalize=False)
    >>> s.control_points()[0, 0].round(4)  # the paper's q_{1,0}
    array([-0.3796,  0.4589,  0.1106,  0.7956])
    >>> (j,) = qs.continuity(s)
    >>> j.beta_g1_residual < 1e-13, round(j.beta_g2_residual, 3)  # G¹ holds, G² does not
    (True, 0.066)
    """

    def __init__(
        self,
        vertices,
        beta1=1.0,
        beta2=0.0,
        times=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        p = _keys(vertices, "vertices")
        t = _times(times, max(len(p) - 2, 0))
        super().__init__(
            _core.beta_spline(p, _per(beta1, "beta1"), _per(beta2, "beta2"), t, bool(canonicalize)),
            extrapolate,
        )

    def control_points(self) -> NDArray[np.float64]:
        """The Bézier points ``q_{i,0..3}`` of segments i = 1 … l.

        Returns
        -------
        numpy.ndarray, shape (l, 4, 4)
            Segment, point, quaternion (w, x, y, z).
        """
        return np.array(self._core.control_points())


C3_AUTO = (0.5, -3.0)


def c3_shape(alpha, beta):
    """Per-key (or per-segment) α, β arrays for the C³ spline; ``alpha="auto"`` is
    (1/2, −3) (see :class:`C3Spline`), ``beta=None`` is 0, or −3 with auto."""
    if isinstance(alpha, str):
        if alpha != "auto":
            raise ValueError(f"alpha: expected a number, numbers or 'auto', got {alpha!r}")
        alpha = C3_AUTO[0]
        if beta is None:
            beta = C3_AUTO[1]
    if beta is None:
        beta = 0.0
    return _per(alpha, "alpha"), _per(beta, "beta")


class C3Spline(Spline):
    """The interpolating C³ spline with shape parameters α and β (Wang & Zhou 2023).

    The patent's formulas were published as images and are lost; this is a reconstruction
    with every stated property (documented in the mathematics pages). (α, β) = (5/16, 0) is
    the quintic C³ scheme (speed at a key 5/8 of the chord speed); α = β = 0 is slerp timed
    by the degree-7 smoothstep (zero velocity at the keys).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), or a scipy ``Rotation`` holding N rotations; normalised.
    times : array_like, shape (N,), optional
        Strictly increasing key times (any unit; rates are per that unit); pandas
        ``DatetimeIndex`` and ``datetime64``/``timedelta64`` arrays become seconds. Default
        0, 1, …, N−1.
    alpha : float, array_like or "auto", default 5/16
        α: scales the key velocities and changes the first three derivatives at the keys.
        One value, or one per key (``"knot"``, N values) or per segment (``"patent"``, N−1).
        ``"auto"``: (α, β) = (1/2, −3), the only pair under which a constant-speed great
        circle is reproduced exactly (key velocity = chord rate, α(ω_k/h_l + ω_{k+1}/h_r) =
        2α·c; key jerk 0, 36α + 6β = 0; the degree-7 blend is then linear in time): speed
        ripple (max/min over the interior) 1.000 against 2.125 for (5/16, 0), whose key speed
        is 5/8 of the chord speed. Held-out accuracy in ``benchmarks/c3_auto.py``; a per-key
        rule (``quatspline.splines.keyframe.c3_speed_matched_alpha``, key speed = mean chord speed)
        was measured there too and is less accurate on every bundled recording.
    beta : float or array_like, optional
        β: changes only the third derivative at the keys; same sizes as ``alpha``. Default
        0, or −3 with ``alpha="auto"``.
    variant : {"knot", "patent"}, default "knot"
        ``"knot"``: parameters belong to keys and the curve is C³ in time for any key
        spacing. ``"patent"``: the patent's blending functions exactly, C³ in the local
        parameter (in time only for uniform times and shared parameters; G³ otherwise).
    canonicalize : bool, default True
        Flip each key to the hemisphere of the previous one, so that consecutive keys are
        joined the short way.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the domain: an error, the end orientation held (zero derivatives),
        constant angular velocity from the end, or the domain repeated.
    ends : {"open", "rest", "closed"}, default "open"
        ``"rest"``: zero angular velocity, acceleration and jerk at the end keys (the
        rest-to-rest manoeuvre), still C³ — by α = β = 0 there (knot variant) or by the end
        segments' blending functions flattened at the end keys (patent variant). ``"closed"``
        (both variants): a periodic loop, C³ across the seam (see ``quatspline.splines.keyframe``).
    holds : bool, default True
        Consecutive equal keys (q or −q) hold exactly still, with zero angular velocity,
        acceleration and jerk at both ends of the hold. Knot variant: α = β = 0 at the keys
        bounding the hold, C³. Patent variant: the blending functions next to those keys
        are flattened there (first three derivatives zero, the other end the patent's), so
        the joint is C³ in time from both sides.

    Raises
    ------
    ValueError
        If a shape is wrong, there are too few keys, a key is zero or not finite, the times
        are not finite and strictly increasing, or a parameter is out of range (the message
        names the argument and the index).

    See Also
    --------
    NaturalSpline : global C², closest to the data.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> angles = [[0, 0, 0], [0, 0, 90], [45, 0, 90], [45, 30, 120]]
    >>> keys = qs.from_euler("xyz", angles, degrees=True)
    >>> s = qs.C3Spline(keys, [0.0, 1.0, 2.5, 3.0], alpha=5 / 16, beta=0.0)
    >>> bool(np.allclose(s([0.0, 1.0, 2.5, 3.0]), keys))
    True
    >>> [j.order for j in qs.continuity(s)]
    [3, 3]
    """

    def __init__(
        self,
        quats,
        times=None,
        alpha=5 / 16,
        beta=None,
        variant: str = "knot",
        canonicalize: bool = True,
        extrapolate: str = "raise",
        ends: str = "open",
        holds: bool = True,
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        use_holds = bool(holds)
        a, b = c3_shape(alpha, beta)
        super().__init__(
            _core.c3_spline(
                q,
                t,
                a,
                b,
                str(variant),
                bool(canonicalize),
                str(ends),
                use_holds,
            ),
            extrapolate,
            quats=q,
            times=t,
            alpha=alpha,
            beta=beta,
            variant=variant,
            canonicalize=canonicalize,
            ends=ends,
            holds=holds,
        )
