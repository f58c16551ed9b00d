"""Sampling a spline through a recording's keys: the one route of ``quatspline sample``, batch
runs, the viewer and :meth:`quatspline.io.Trajectory.resample` (behind :mod:`quatspline.ops`).

Where to sample is given once, in one of three ways (``rate``, ``count`` or ``times``), and
checked once: the bound on the number of samples, finite times, and times outside the
recording (named by :func:`check_times`, whose wording every operation shares).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .._util.arrays import as_real
from .._util.checks import short
from .._util.options import DEFAULT_METHOD
from .._util.progress_bars import progress
from ..io import Trajectory
from ..io import read as read_trajectory
from ..io.kitti import read_times
from ..poses.pose_spline import PoseSpline
from ..splines import DEFAULT_MAX_SAMPLES
from ..splines import EXTRAPOLATE as _EXTRAPOLATE
from ._ops import ParameterError, _build, _check_trajectory, _int_arg

__all__ = [
    "SAMPLE_CHUNK",
    "check_times",
    "evaluate",
    "requested_times",
    "sample",
    "sample_times",
    "sample_trajectory",
    "times_from_file",
]

#: Samples per chunk when sampling under a progress bar (each sample is independent, so the
#: result does not depend on it).
SAMPLE_CHUNK = 1 << 18


def sample_times(
    domain: tuple[float, float],
    *,
    rate: float | None = None,
    count: int | None = None,
    max_samples: int = DEFAULT_MAX_SAMPLES,
) -> np.ndarray:
    """Evenly spaced sample times over ``domain``, bounded before anything is allocated.

    Parameters
    ----------
    domain : (float, float)
        The interval [a, b] to sample (a ≤ b, both finite).
    rate : float, optional
        Samples per time unit: times a, a + 1/rate, … ≤ b. Exactly one of ``rate`` and
        ``count`` must be given.
    count : int, optional
        Number of samples, from a to b inclusive.
    max_samples : int, default DEFAULT_MAX_SAMPLES
        Refuse to produce more samples than this.

    Returns
    -------
    numpy.ndarray, shape (n,)

    Raises
    ------
    ParameterError
        If ``rate`` is not a positive finite number, ``count`` < 1, or the number of samples
        would exceed ``max_samples`` (the message gives the number and the limit).
    TypeError
        If ``count`` or ``max_samples`` is not an integer.

    Examples
    --------
    >>> from quatspline.ops import sample_times
    >>> sample_times((0.0, 1.0), rate=4.0).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    >>> sample_times((0.0, 1.0), count=3).tolist()
    [0.0, 0.5, 1.0]
    """
    max_samples = _int_arg(max_samples, "max_samples", 1)
    if (rate is None) == (count is None):
        raise ParameterError("rate, count: give exactly one of them")
    a, b = (float(v) for v in domain)
    if rate is not None:
        try:
            rate = float(rate)
        except (TypeError, ValueError):
            raise TypeError(f"rate: expected a number, got {type(rate).__name__}") from None
        if not (rate > 0 and math.isfinite(rate)):
            raise ParameterError(f"rate: expected a positive finite rate, got {rate:g}")
        span = (b - a) * rate  # a Python float: no allocation yet (inf for a huge rate)
        n = math.floor(span + 1e-9) + 1 if math.isfinite(span) else math.inf
        if not n <= max_samples:
            raise ParameterError(
                f"rate: {rate:g} samples per unit over [{a:g}, {b:g}] gives {n:.4g} samples, "
                f"more than max_samples = {short(max_samples)}"
            )
        return a + np.arange(int(n)) / rate
    count = _int_arg(count, "count", 1)
    if count > max_samples:
        raise ParameterError(
            f"count: {short(count)} samples is more than max_samples = {short(max_samples)}"
        )
    return np.linspace(a, b, count)


def check_times(t: np.ndarray, first: float, last: float, extrapolate: str = "raise") -> None:
    """Refuses sample times that are not finite, or outside [first, last] with
    ``extrapolate="raise"``: the one wording of every operation that samples at given times
    (:func:`sample`, :func:`fit_trajectory`, :meth:`~quatspline.io.Trajectory.resample`).

    The first bad time is named by its index and its value, as in the input (absolute times,
    on the recording's clock).

    Parameters
    ----------
    t : numpy.ndarray, shape (N,)
        The times, on the recording's clock.
    first, last : float
        The recording's time range.
    extrapolate : str
        ``"raise"`` refuses times outside the range; any other mode allows them.

    Raises
    ------
    ValueError
        For a NaN or infinite time, or a time outside the range with ``extrapolate="raise"``.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline.ops import check_times
    >>> check_times(np.array([1.0, 4.0]), 1.0, 3.0)
    Traceback (most recent call last):
    ...
    ValueError: times: times[1] = 4.0 is after the trajectory's last time 3.0 (range [1.0, 3.0]; use extrapolate="clamp" to hold the end pose)
    >>> check_times(np.array([1.0, 4.0]), 1.0, 3.0, extrapolate="clamp")
    """  # noqa: E501
    finite = np.isfinite(t)
    if not np.all(finite):
        k = int(np.argmax(~finite))
        raise ValueError(f"times: times[{k}] is {float(t[k])} (NaN or inf)")
    if extrapolate != "raise":
        return
    before, after = t < first, t > last
    out = before | after
    if np.any(out):
        k = int(np.argmax(out))
        where = (
            f"before the trajectory's first time {first!r}"
            if before[k]
            else f"after the trajectory's last time {last!r}"
        )
        allout = " (all of them are outside)" if np.all(out) else ""
        raise ValueError(
            f"times: times[{k}] = {float(t[k])!r} is {where}{allout} (range [{first!r}, "
            f'{last!r}]; use extrapolate="clamp" to hold the end pose)'
        )


def _given_times(times) -> tuple[np.ndarray, np.ndarray | None]:
    """(times as a 1-D float array, their exact ``stamps_ns`` or None) of ``times=``."""
    if isinstance(times, Trajectory):
        return np.asarray(times.times, dtype=float), times.stamps_ns
    if isinstance(times, (str, bytes, Path)):
        raise TypeError(
            f"times: expected an array of times or a Trajectory, got {type(times).__name__} "
            "(read a file of times with quatspline.ops.times_from_file)"
        )
    flags = (bool, np.bool_)
    if (
        isinstance(times, flags)
        or getattr(getattr(times, "dtype", None), "kind", "") == "b"
        or (isinstance(times, (list, tuple)) and any(isinstance(x, flags) for x in times))
    ):
        raise TypeError("times: expected real numbers, got dtype bool")
    t = as_real(times, "times")
    if t.ndim > 1:
        raise ValueError(f"times: expected a 1-D array of times, got shape {t.shape}")
    t = t.reshape(-1)
    if len(t) == 0:
        raise ValueError("times: no times to sample at")
    return t, None


def requested_times(
    traj: Trajectory,
    *,
    rate=None,
    count=None,
    times=None,
    max_samples: int = DEFAULT_MAX_SAMPLES,
    extrapolate: str = "raise",
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The checks every sampling operation makes before any work, in one place.

    Returns ``(t, stamps_ns)``: with ``times``, the times relative to the first key and
    their exact nanosecond stamps (or None); with ``rate`` or ``count``, ``(None, None)``
    (the times depend on the curve's domain: :func:`sample_times`).

    Raises
    ------
    ParameterError
        Not exactly one of ``rate``, ``count``, ``times``; more times than ``max_samples``.
    ValueError
        Bad times (see :func:`check_times`).
    """
    if sum(x is not None for x in (rate, count, times)) != 1:
        raise ParameterError("rate, count, times: give exactly one of them")
    max_samples = _int_arg(max_samples, "max_samples", 1)
    if times is None:
        return None, None
    t, ns = _given_times(times)
    if len(t) > max_samples:
        raise ParameterError(
            f"times: {short(len(t))} samples is more than max_samples = {short(max_samples)}"
        )
    first, last = float(traj.times[0]), float(traj.times[-1])
    check_times(t, first, last, extrapolate)
    return t - first, ns


def evaluate(rotation, t: np.ndarray, derivatives: bool, position=None):
    """Orientations (with ``derivatives``: ω, α and jerk, world frame) and positions at
    ``t``, in chunks under a progress bar (shown on a terminal once sampling takes more
    than a second). ``rotation`` is a spline; ``position`` a function of time, or None.

    Returns ``(quats, positions or None, extra columns)``."""
    names = ("omega", "alpha", "jerk") if derivatives else ()
    fns = {
        "omega": rotation.angular_velocity,
        "alpha": rotation.angular_acceleration,
        "jerk": rotation.jerk,
    }
    n = len(t)
    q = np.empty((n, 4))
    p = None if position is None else np.empty((n, 3))
    extra = {k: np.empty((n, 3)) for k in names}
    with progress(total=n, desc="sampling", unit="sample") as bar:
        for a in range(0, n, SAMPLE_CHUNK):
            tc = t[a : a + SAMPLE_CHUNK]
            q[a : a + len(tc)] = rotation(tc)
            if p is not None:
                p[a : a + len(tc)] = position(tc)
            for k in names:
                extra[k][a : a + len(tc)] = fns[k](tc)
            bar.update(len(tc))
    return q, p, extra


def sample(
    trajectory: Trajectory,
    method: str = DEFAULT_METHOD,
    *,
    rate: float | None = None,
    count: int | None = None,
    times=None,
    params: dict | None = None,
    derivatives: bool = False,
    max_samples: int = DEFAULT_MAX_SAMPLES,
    extrapolate: str = "raise",
) -> Trajectory:
    """Samples a spline of ``method`` through the keys of a recorded trajectory.

    The one sampling route: ``quatspline sample`` (``--rate``, ``--count``, ``--at``), batch
    runs and :meth:`quatspline.io.Trajectory.resample` all call it. The spline is built on the
    key times relative to the first one (for accuracy with large timestamps); the returned
    times are on the trajectory's own clock. ``sample_trajectory`` is the same function.

    Parameters
    ----------
    trajectory : quatspline.io.Trajectory
        The keys (times, quaternions, optional positions).
    method : str, default "natural"
        A method of :data:`quatspline.METHODS` (the default: the one for recordings,
        ``quatspline._util.options.DEFAULT_METHOD``).
    rate, count : optional
        Evenly spaced samples over the spline's domain (see :func:`sample_times`).
    times : array_like or quatspline.io.Trajectory, optional
        Sample at these times instead (on the trajectory's clock); a Trajectory gives its
        times and keeps its exact ``stamps_ns``. Exactly one of ``rate``, ``count`` and
        ``times`` must be given. A file of times: :func:`times_from_file`.
    params : dict, optional
        Method parameters, e.g. ``{"alpha": 0.3}`` (strings are converted).
    derivatives : bool, default False
        Add the angular velocity, acceleration and jerk (world frame) as extra columns
        ``omega``, ``alpha`` and ``jerk``.
    max_samples : int, default DEFAULT_MAX_SAMPLES
        Refuse to produce more samples than this (checked before allocating), for ``times``
        as for ``rate`` and ``count``.
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the keys: an error (:func:`check_times`), the end pose held, constant
        angular and linear velocity from the ends, or the key range repeated (orientation and
        position alike).

    Returns
    -------
    quatspline.io.Trajectory
        The samples. If ``trajectory`` has positions, so does the result: the natural cubic
        spline through the key positions, for every method (see :mod:`quatspline.ops`).

    Raises
    ------
    ParameterError
        For an unknown method or parameter, a bad rate, count or extrapolation mode, or too
        many samples.
    ValueError
        For keys or times the method cannot use (the message names them).
    TypeError
        For a ``trajectory`` that is not a Trajectory or non-integer counts.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline import from_axis_angle
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import sample
    >>> keys = from_axis_angle([0.0, 0.0, 1.0], [[0.0], [0.5], [1.0]])
    >>> traj = Trajectory([10.0, 11.0, 12.0], keys, positions=np.eye(3))
    >>> out = sample(traj, "bspline", count=5)
    >>> out.times.tolist()
    [10.0, 10.5, 11.0, 11.5, 12.0]
    >>> out.positions.shape
    (5, 3)
    >>> sample(traj, "slerp", times=[10.5, 13.0], derivatives=True)
    Traceback (most recent call last):
    ...
    ValueError: times: times[1] = 13.0 is after the trajectory's last time 12.0 (range [10.0, 12.0]; use extrapolate="clamp" to hold the end pose)
    """  # noqa: E501
    _check_trajectory(trajectory, "trajectory")
    if params is not None and not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    if not isinstance(derivatives, (bool, np.bool_)):
        raise TypeError(f"derivatives: expected a bool, got {type(derivatives).__name__}")
    if not isinstance(extrapolate, str) or extrapolate not in _EXTRAPOLATE:
        raise ParameterError(
            f"extrapolate: expected one of {', '.join(_EXTRAPOLATE)}, got {extrapolate!r}"
        )
    t, ns = requested_times(
        trajectory,
        rate=rate,
        count=count,
        times=times,
        max_samples=max_samples,
        extrapolate=extrapolate,
    )
    t0 = float(trajectory.times[0])
    rel = trajectory.times - t0
    s = _build(method, trajectory, rel, dict(params or {}))
    s.extrapolate = extrapolate
    if t is None:
        t = sample_times(s.domain, rate=rate, count=count, max_samples=max_samples)
    position = None
    if trajectory.positions is not None:
        position = PoseSpline(
            trajectory.quats,
            rel,
            trajectory.positions,
            rotation="slerp",
            extrapolate="clamp" if extrapolate == "raise" else extrapolate,
        ).position
    q, pos, extra = evaluate(s, t, bool(derivatives), position)
    return Trajectory(t + t0, q, pos, extra=extra, name=trajectory.name, stamps_ns=ns)


#: The former name of :func:`sample` (the same function).
sample_trajectory = sample


def times_from_file(path) -> np.ndarray:
    """The times of a file, for ``--at`` wherever it is accepted (``sample``, ``fit``,
    batch): a trajectory file of any readable format (its times), or a file of times — one
    number a line, ``#`` comments (the KITTI ``times.txt`` format).

    Parameters
    ----------
    path : str or pathlib.Path

    Returns
    -------
    numpy.ndarray, shape (N,), N ≥ 1

    Raises
    ------
    ValueError
        A file that is neither (the trajectory reader's message, file:line), or holds no
        times.
    OSError
        A file that cannot be opened.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from quatspline.ops import times_from_file
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "t.txt").write_text("# times\\n1.5\\n2.5\\n")
    >>> times_from_file(d / "t.txt").tolist()
    [1.5, 2.5]
    >>> _ = (d / "gt.tum").write_text("1.0 0 0 0 0 0 0 1\\n2.0 0 0 0 0 0 0 1\\n")
    >>> times_from_file(d / "gt.tum").tolist()
    [1.0, 2.0]
    """
    if not isinstance(path, (str, Path)):
        raise TypeError(f"times: expected a file path, got {type(path).__name__}")
    p = Path(path)
    try:
        t = read_trajectory(p).times
    except ValueError as first:
        if not p.is_file():  # missing, a directory, a FIFO: the reader's message says it all
            raise ValueError(f"times: {first}") from None
        try:
            t = read_times(p)
        except ValueError:
            raise ValueError(
                f"times: {first} (and not a file of times, one a line, either)"
            ) from None
    if t.size == 0:
        raise ValueError(f"times: {p}: the file holds no times")
    return np.asarray(t, dtype=float)
