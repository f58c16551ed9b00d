"""Comparing methods on a recording: smoothness figures and hold-out accuracy, and their
Markdown table — the one route of ``quatspline compare`` and ``quatspline batch compare``
(behind :mod:`quatspline.ops`)."""

from __future__ import annotations

import numpy as np

from .._util.progress_bars import progress as _progress_bar
from ..core.metrics import angle_between
from ..io import Trajectory
from ..registry import METHODS, interpolating_methods
from ..splines import path_length
from ..splines.joints import continuity
from ._ops import ParameterError, _build, _check_trajectory, _int_arg

__all__ = ["IMPULSES", "TABLE_COLUMNS", "compare", "format_table", "markdown_cell"]


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
        One dict per method with plain ``float``/``int``/``str`` values (or ``None``, see
        below): ``method``, ``max_speed``, ``rms_speed``, ``rms_acceleration``, ``rms_jerk``
        (rad/s, rad/s², rad/s³ in the recording's time unit), ``path_length`` (rad),
        ``continuity_order`` (the lowest order of continuity measured at the joints) and,
        with ``holdout``,
        ``holdout_median_deg``, ``holdout_p95_deg``, ``holdout_max_deg``. Where ω jumps at a
        joint (C⁰) the angular acceleration is an impulse there and ``rms_acceleration`` and
        ``rms_jerk`` are ``None`` (no finite RMS exists); where α jumps (C¹) ``rms_jerk`` is
        ``None``. The table (:func:`format_table`) shows them as "impulses".

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
    order = int(min([j.order for j in continuity(s)] or [s.continuity]))
    row = {
        "method": m,
        "max_speed": float(w.max()),
        "rms_speed": float(np.sqrt(np.mean(w**2))),
        # A jump of ω (C⁰) is an impulse of α at the joint, a jump of α (C¹) one of the jerk:
        # the samples between joints would report a finite RMS that the motion does not have.
        "rms_acceleration": float(np.sqrt(np.mean(acc**2))) if order >= 1 else None,
        "rms_jerk": float(np.sqrt(np.mean(jerk**2))) if order >= 2 else None,
        "path_length": float(path_length(s, per_segment=2)),
        "continuity_order": order,
    }
    if holdout is not None:
        err = angle_between(s(t_all[rest]), traj.quats[rest], degrees=True)
        row.update(
            holdout_median_deg=float(np.median(err)),
            holdout_p95_deg=float(np.percentile(err, 95)),
            holdout_max_deg=float(err.max()),
        )
    return row


#: Columns of :func:`format_table`: key, header, format (rates per second of the recording's
#: clock; a ``None`` value is shown as :data:`IMPULSES`).
TABLE_COLUMNS = [
    ("method", "method", "{}"),
    ("max_speed", "max ‖ω‖ (rad/s)", "{:.3g}"),
    ("rms_speed", "rms ‖ω‖ (rad/s)", "{:.3g}"),
    ("rms_acceleration", "rms ‖α‖ (rad/s²)", "{:.3g}"),
    ("rms_jerk", "rms ‖jerk‖ (rad/s³)", "{:.3g}"),
    ("path_length", "path (rad)", "{:.4g}"),
    ("continuity_order", "C^k", "{}"),
    ("holdout_median_deg", "median err (°)", "{:.4f}"),
    ("holdout_p95_deg", "p95 err (°)", "{:.4f}"),
    ("holdout_max_deg", "max err (°)", "{:.4f}"),
]


#: The cell of an RMS that does not exist: the rate jumps at a joint, its derivative is an
#: impulse there.
IMPULSES = "impulses"


def markdown_cell(text) -> str:
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
    >>> print(format_table([{"method": "a|b", "max_speed": 1.5, "rms_jerk": None,
    ...                      "continuity_order": 1}]))
    | method | max ‖ω‖ (rad/s) | rms ‖jerk‖ (rad/s³) | C^k |
    |---|---:|---:|---:|
    | a\\|b | 1.5 | impulses | 1 |
    """
    if not rows:
        return ""
    cols = [c for c in TABLE_COLUMNS if c[0] in rows[0]]
    head = "| " + " | ".join(markdown_cell(c[1]) for c in cols) + " |"
    sep = "|" + "|".join("---" if c[0] == "method" else "---:" for c in cols) + "|"
    body = [
        "| "
        + " | ".join(
            markdown_cell(IMPULSES if r[k] is None else f.format(r[k])) for k, _, f in cols
        )
        + " |"
        for r in rows
    ]
    return "\n".join([head, sep, *body])
