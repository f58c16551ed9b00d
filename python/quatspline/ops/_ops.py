"""Sampling and comparing methods on recorded trajectories (behind :mod:`quatspline.ops`)."""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._util.checks import short
from .._util.errors import ParameterError
from .._util.progress_bars import progress as _progress_bar
from ..core.metrics import angle_between
from ..io import Trajectory
from ..registry import METHODS, interpolating_methods
from ..registry import spline as make_spline
from ..splines import DEFAULT_MAX_SAMPLES, path_length
from ..splines.joints import continuity

__all__ = [
    "DEFAULT_MAX_SAMPLES",
    "ParameterError",
    "build_spline",
    "compare",
    "format_table",
    "sample_times",
    "sample_trajectory",
]

#: Default bound on the number of samples one call may produce. Measured peak memory of
#: ``quatspline sample --derivatives`` on a recording with positions: 0.27 GB (NPZ) and 0.37 GB
#: (CSV) for 1,000,000 samples, i.e. about 300 bytes a sample: about 3 GB at this bound.


def _check_trajectory(traj) -> None:
    if not isinstance(traj, Trajectory):
        raise TypeError(f"traj: expected a quatspline.io.Trajectory, got {type(traj).__name__}")


def _int_arg(value, name: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    value = int(value)
    if value < minimum:
        raise ParameterError(f"{name}: expected an integer ≥ {minimum}, got {short(value)}")
    return value


def build_spline(method: str, traj: Trajectory, params: dict | None = None):
    """The spline of ``method`` through the keys of ``traj``, on times relative to the first
    key (``traj.times - traj.times[0]``, for accuracy with large timestamps).

    Parameters
    ----------
    method : str
        Registry method name.
    traj : quatspline.io.Trajectory
        The keys.
    params : dict, optional
        The method's parameters.

    Returns
    -------
    Spline

    Raises
    ------
    ParameterError
        Unknown method or parameter.
    ValueError
        Keys the method cannot use.

    Examples
    --------
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import build_spline
    >>> s = build_spline("slerp", Trajectory([5.0, 6.0], [[1, 0, 0, 0], [0, 0, 0, 1]]))
    >>> s.domain
    (0.0, 1.0)
    """
    _check_trajectory(traj)
    if params is not None and not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    return _build(method, traj, traj.times - traj.times[0], dict(params or {}))


def _build(method: str, traj: Trajectory, times: np.ndarray, params: dict):
    # the registry raises ParameterError itself for an unknown method or a bad parameter
    return make_spline(method, traj.quats, times, **params)


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


#: Samples per chunk when sampling with a progress bar (each sample is independent, so the
#: result does not depend on it).
SAMPLE_CHUNK = 1 << 18


def _evaluate(s, t: np.ndarray, derivatives: bool):
    """Orientations (and ω, α, jerk) at ``t``, in chunks under a progress bar (shown on a
    terminal once sampling takes more than a second)."""
    from .._util.progress_bars import progress

    names = ("omega", "alpha", "jerk") if derivatives else ()
    fns = {"omega": s.angular_velocity, "alpha": s.angular_acceleration, "jerk": s.jerk}
    if len(t) <= SAMPLE_CHUNK:
        return s(t), {k: fns[k](t) for k in names}
    q = np.empty((len(t), 4))
    extra = {k: np.empty((len(t), 3)) for k in names}
    with progress(len(t), "sampling", unit="sample") as bar:
        for a in range(0, len(t), SAMPLE_CHUNK):
            tc = t[a : a + SAMPLE_CHUNK]
            q[a : a + len(tc)] = s(tc)
            for k in names:
                extra[k][a : a + len(tc)] = fns[k](tc)
            bar.update(len(tc))
    return q, extra


def sample_trajectory(
    traj: Trajectory,
    method: str = "c3",
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

    The spline is built on the key times relative to the first one (for accuracy with large
    timestamps); the returned times are on the trajectory's own clock.

    Parameters
    ----------
    traj : quatspline.io.Trajectory
        The keys (times, quaternions, optional positions).
    method : str, default "c3"
        A method of :data:`quatspline.METHODS`.
    rate, count : optional
        Evenly spaced samples over the spline's domain (see :func:`sample_times`).
    times : array_like, optional
        Sample at these times instead (on the trajectory's clock, inside its time range).
        Exactly one of ``rate``, ``count`` and ``times`` must be given.
    params : dict, optional
        Method parameters, e.g. ``{"alpha": 0.3}`` (strings are converted).
    derivatives : bool, default False
        Add the angular velocity, acceleration and jerk (world frame) as extra columns
        ``omega``, ``alpha`` and ``jerk``.
    max_samples : int, default DEFAULT_MAX_SAMPLES
        Refuse to produce more samples than this (checked before allocating).
    extrapolate : {"raise", "clamp", "linear", "periodic"}, default "raise"
        Times outside the keys: an error, the end pose held, constant angular and linear
        velocity from the ends, or the key range repeated (orientation and position alike).

    Returns
    -------
    quatspline.io.Trajectory
        The samples. If ``traj`` has positions, so does the result: the natural cubic spline
        through the key positions, for every method (see the module notes).

    Raises
    ------
    ParameterError
        For an unknown method or parameter, a bad rate or count, or too many samples.
    ValueError
        For keys or times the method cannot use (the message names them).
    TypeError
        For a ``traj`` that is not a Trajectory or non-integer counts.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline import from_axis_angle
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import sample_trajectory
    >>> keys = from_axis_angle([0.0, 0.0, 1.0], [[0.0], [0.5], [1.0]])
    >>> traj = Trajectory([10.0, 11.0, 12.0], keys, positions=np.eye(3))
    >>> out = sample_trajectory(traj, "bspline", count=5)
    >>> out.times.tolist()
    [10.0, 10.5, 11.0, 11.5, 12.0]
    >>> out.positions.shape
    (5, 3)
    """
    _check_trajectory(traj)
    if params is not None and not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    if not isinstance(derivatives, (bool, np.bool_)):
        raise TypeError(f"derivatives: expected a bool, got {type(derivatives).__name__}")
    t0 = float(traj.times[0])
    s = _build(method, traj, traj.times - t0, dict(params or {}))
    from ..splines import EXTRAPOLATE as _EXTRAPOLATE

    if extrapolate not in _EXTRAPOLATE:
        raise ParameterError(f"extrapolate: expected one of {_EXTRAPOLATE}, got {extrapolate!r}")
    s.extrapolate = extrapolate
    given = sum(x is not None for x in (rate, count, times))
    if given != 1:
        raise ParameterError("rate, count, times: give exactly one of them")
    if times is not None:
        max_samples = _int_arg(max_samples, "max_samples", 1)
        from .._util.arrays import as_real

        t = as_real(times, "times").reshape(-1)
        if len(t) > max_samples:
            raise ParameterError(
                f"times: {len(t)} samples is more than max_samples = {short(max_samples)}"
            )
        lo, hi = t0, float(traj.times[-1])
        bad = ~np.isfinite(t)
        if extrapolate == "raise":
            bad |= (t < lo) | (t > hi)
        if np.any(bad):  # named on the recording's clock, not the spline's relative one
            k = int(np.argmax(bad))
            raise ValueError(
                f"times: times[{k}] = {float(t[k])!r} is outside the recording's time range "
                f"[{lo!r}, {hi!r}]"
            )
        t = t - t0
    else:
        t = sample_times(s.domain, rate=rate, count=count, max_samples=max_samples)
    q, extra = _evaluate(s, t, bool(derivatives))
    pos = None
    if traj.positions is not None:
        from ..poses.pose_spline import PoseSpline

        pos = PoseSpline(
            traj.quats,
            traj.times - t0,
            traj.positions,
            rotation="slerp",
            extrapolate="clamp" if extrapolate == "raise" else extrapolate,
        ).position(t)
    return Trajectory(t + t0, q, pos, extra=extra, name=traj.name)


def compare(
    traj: Trajectory,
    methods: list[str] | None = None,
    holdout: int | None = None,
    samples_per_key: int = 8,
    progress: bool = False,
) -> list[dict]:
    """Compares methods on a recording: smoothness figures and, with ``holdout``, accuracy.

    Parameters
    ----------
    traj : quatspline.io.Trajectory
        The recording.
    methods : list of str, optional
        Methods of :data:`quatspline.METHODS` (default: every interpolating method).
    holdout : int, optional
        If given (K ≥ 2), every K-th frame is a key and the frames between the first and last
        key are predicted; the error is the rotation angle between prediction and recording
        (:func:`quatspline.angle_between`). ``None`` uses every frame as a key.
    samples_per_key : int, default 8
        Density of the samples for the smoothness figures (at least 1,000, at most 400,000
        samples per method).
    progress : bool, default False
        Show a progress bar on a terminal (standard error).

    Returns
    -------
    list of dict
        One dict per method with plain ``float``/``int``/``str`` values: ``method``,
        ``max_speed``, ``rms_speed``, ``rms_acceleration``, ``rms_jerk`` (rad/s, rad/s²,
        rad/s³ in the recording's time unit), ``path_length`` (rad), ``continuity_order``
        (the lowest order of continuity measured at the joints) and, with ``holdout``,
        ``holdout_median_deg``, ``holdout_p95_deg``, ``holdout_max_deg``.

    Raises
    ------
    ParameterError
        For an unknown method, or ``holdout`` < 2 (``holdout=0`` is refused, not ignored).
    ValueError
        If fewer than 2 keys remain after the holdout.
    TypeError
        For a wrong kind of argument.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline import from_axis_angle
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import compare
    >>> t = np.linspace(0.0, 2.0, 21)
    >>> traj = Trajectory(t, from_axis_angle([0.0, 0.0, 1.0], t[:, None]))
    >>> rows = compare(traj, ["slerp"], holdout=5)
    >>> round(rows[0]["holdout_max_deg"], 6)  # a constant-rate turn is predicted exactly
    0.0
    """
    _check_trajectory(traj)
    if methods is None:
        methods = interpolating_methods()
    if isinstance(methods, str) or not all(isinstance(m, str) for m in methods):
        raise TypeError("methods: expected a list of method names")
    for m in methods:
        if m not in METHODS:
            raise ParameterError(f"methods: unknown method {m!r}; valid: {', '.join(METHODS)}")
    samples_per_key = _int_arg(samples_per_key, "samples_per_key", 1)
    t_all = traj.times - traj.times[0]
    if holdout is not None:
        holdout = _int_arg(holdout, "holdout", 2)
        idx = np.arange(0, len(t_all), holdout)
        if len(idx) < 2:
            raise ValueError(f"holdout: {holdout} leaves fewer than 2 keys in {len(t_all)} frames")
        rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
    else:
        idx = np.arange(len(t_all))
        rest = None
    keys, kt = traj.quats[idx], t_all[idx]
    rows = []
    with _progress_bar(total=len(methods), desc="methods", enabled=bool(progress)) as bar:
        for m in methods:
            rows.append(_compare_one(m, traj, kt, keys, t_all, rest, holdout, samples_per_key))
            bar.update()
    return rows


def _compare_one(m, traj, kt, keys, t_all, rest, holdout, samples_per_key) -> dict:
    """One row of :func:`compare` (see there)."""
    s = _build(m, Trajectory(kt, keys), kt, {})
    a, b = s.domain
    n = int(min(max(samples_per_key * len(kt), 1000), 400_000))
    t = np.linspace(a, b, n)
    w = np.linalg.norm(s.angular_velocity(t), axis=1)
    acc = np.linalg.norm(s.angular_acceleration(t), axis=1)
    jerk = np.linalg.norm(s.jerk(t), axis=1)
    orders = [j.order for j in continuity(s)] or [s.continuity]
    row = {
        "method": m,
        "max_speed": float(w.max()),
        "rms_speed": float(np.sqrt(np.mean(w**2))),
        "rms_acceleration": float(np.sqrt(np.mean(acc**2))),
        "rms_jerk": float(np.sqrt(np.mean(jerk**2))),
        "path_length": float(path_length(s, per_segment=2)),
        "continuity_order": int(min(orders)),
    }
    if holdout is not None:
        err = angle_between(s(t_all[rest]), traj.quats[rest], degrees=True)
        row.update(
            holdout_median_deg=float(np.median(err)),
            holdout_p95_deg=float(np.percentile(err, 95)),
            holdout_max_deg=float(err.max()),
        )
    return row


#: Columns of :func:`format_table`: key, header, format.
TABLE_COLUMNS = [
    ("method", "method", "{}"),
    ("max_speed", "max ‖ω‖", "{:.3g}"),
    ("rms_speed", "rms ‖ω‖", "{:.3g}"),
    ("rms_acceleration", "rms ‖α‖", "{:.3g}"),
    ("rms_jerk", "rms ‖jerk‖", "{:.3g}"),
    ("path_length", "path (rad)", "{:.4g}"),
    ("continuity_order", "C^k", "{}"),
    ("holdout_median_deg", "median err (°)", "{:.4f}"),
    ("holdout_p95_deg", "p95 err (°)", "{:.4f}"),
    ("holdout_max_deg", "max err (°)", "{:.4f}"),
]


def _cell(text: str) -> str:
    """A Markdown table cell: ``|`` and backslashes escaped, newlines flattened."""
    return str(text).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")


def format_table(rows: list[dict]) -> str:
    """The rows of :func:`compare` as a GitHub-flavoured Markdown table.

    Cells are escaped (``|`` → ``\\|``) so any renderer shows a table; numbers are plain
    decimals (no numpy reprs).

    Parameters
    ----------
    rows : list of dict
        As :func:`compare` returns them (only the columns present are shown).

    Returns
    -------
    str

    Examples
    --------
    >>> from quatspline.ops import format_table
    >>> print(format_table([{"method": "a|b", "max_speed": 1.5, "continuity_order": 2}]))
    | method | max ‖ω‖ | C^k |
    |---|---:|---:|
    | a\\|b | 1.5 | 2 |
    """
    if not rows:
        return ""
    cols = [c for c in TABLE_COLUMNS if c[0] in rows[0]]
    head = "| " + " | ".join(_cell(c[1]) for c in cols) + " |"
    sep = "|" + "|".join("---" if c[0] == "method" else "---:" for c in cols) + "|"
    body = ["| " + " | ".join(_cell(f.format(r[k])) for k, _, f in cols) + " |" for r in rows]
    return "\n".join([head, sep, *body])
