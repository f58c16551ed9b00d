"""The trajectory record every reader returns and every writer takes, the checks a record read
from a file passes (:func:`finish`), and its pandas DataFrame form.

:meth:`Trajectory.resample` samples a spline through the record. Sampling is a library
operation (:mod:`quatspline.ops`, a layer above ``io``): ``io`` does not import it; ops
registers its one sampling route here with :func:`set_sampler` when it is imported (as
``import quatspline`` does).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .._util.optional import need
from .._util.options import DEFAULT_METHOD
from ._columns import QUATS, TIME, clean, find, positions_for

__all__ = [
    "MIN_QUAT_NORM",
    "Trajectory",
    "TrajectoryError",
    "finish",
    "from_dataframe",
    "quat_norms",
    "set_sampler",
    "to_dataframe",
]

#: A line break and the blanks around it (messages are one line).
_LINE_BREAKS = re.compile(r"\s*[\r\n\v\f\x1c-\x1e\x85\u2028\u2029]+\s*")

#: Quaternions shorter than this are refused by the readers (and so by the writers).
MIN_QUAT_NORM = 1e-12


class TrajectoryError(ValueError):
    """A file that cannot be read as a trajectory; the message names file, line and column.

    A subclass of ``ValueError``: ``except ValueError`` catches it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from quatspline import io
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "bad.csv"
    >>> _ = path.write_text("t,qw,qx,qy,qz\\n0,1,0,0,zero\\n")
    >>> try:
    ...     io.read(path)
    ... except io.TrajectoryError as e:
    ...     print(str(e).split("bad.csv:")[1])
    2: column 5 ('qz'): not a number: 'zero'
    """

    def __init__(self, message: object = "", *args: object) -> None:
        # One line whatever it quotes (a parser's multi-line message, a cell with a newline).
        super().__init__(_LINE_BREAKS.sub(" ", str(message)), *args)


#: The sampling operation behind :meth:`Trajectory.resample`, set by :func:`set_sampler`.
_sampler: list[Callable] = []


def set_sampler(fn: Callable) -> None:
    """Registers the function behind :meth:`Trajectory.resample`.

    Set by :mod:`quatspline.ops`, the one sampling route, when it is imported; ``io`` lies
    below the operations and does not import them. ``fn(trajectory, times, method=…,
    extrapolate=…, **params)`` returns the sampled :class:`Trajectory`.

    Raises
    ------
    TypeError
        If ``fn`` is not callable.
    """
    if not callable(fn):
        raise TypeError(f"fn: expected a function, got {type(fn).__name__}")
    _sampler[:] = [fn]


@dataclass
class Trajectory:
    """A recorded or sampled motion: times, orientations, optional positions.

    Parameters
    ----------
    times : array_like, shape (N,)
        Times (seconds for every reader).
    quats : array_like, shape (N, 4)
        Unit quaternions (w, x, y, z).
    positions : array_like, shape (N, 3), optional
        Positions.
    extra : dict of str to numpy.ndarray, optional
        Extra columns, each (N,) or (N, k), e.g. angular velocity.
    name : str, optional
        A label (the file name for readers).
    stamps_ns : array_like of int64, shape (N,), optional
        Integer nanosecond stamps kept exactly (EuRoC, ROS bags), so a round trip does not
        pass them through float64 seconds; ``times`` is then ``stamps_ns / 1e9``.

    Raises
    ------
    ValueError
        If the lengths of times, quaternions, positions or stamps differ.

    Examples
    --------
    >>> from quatspline import io
    >>> q, x = [[1, 0, 0, 0], [0, 1, 0, 0]], [[0, 0, 0], [1, 0, 0]]
    >>> tr = io.Trajectory([0.0, 0.5], q, positions=x)
    >>> len(tr), tr.quats.dtype, tr.positions.shape
    (2, dtype('float64'), (2, 3))
    """

    times: np.ndarray
    quats: np.ndarray
    positions: np.ndarray | None = None
    extra: dict[str, np.ndarray] = field(default_factory=dict)
    name: str = ""
    stamps_ns: np.ndarray | None = None

    def __post_init__(self):
        self.times = np.asarray(self.times, dtype=float).reshape(-1)
        self.quats = np.asarray(self.quats, dtype=float).reshape(-1, 4)
        if self.positions is not None:
            self.positions = np.asarray(self.positions, dtype=float).reshape(-1, 3)
        if len(self.times) != len(self.quats):
            raise ValueError(
                f"trajectory: {len(self.times)} times but {len(self.quats)} quaternions"
            )
        if self.positions is not None and len(self.positions) != len(self.times):
            raise ValueError(
                f"trajectory: {len(self.times)} times but {len(self.positions)} positions"
            )

        if self.stamps_ns is not None:
            self.stamps_ns = np.asarray(self.stamps_ns, dtype=np.int64).reshape(-1)
            if len(self.stamps_ns) != len(self.times):
                raise ValueError(
                    f"trajectory: {len(self.times)} times but {len(self.stamps_ns)} stamps_ns"
                )

    def __len__(self) -> int:
        return len(self.times)

    def resample(self, times, method: str = DEFAULT_METHOD, extrapolate: str = "raise", **params):
        """This trajectory's spline sampled at ``times`` (absolute, in this trajectory's time
        unit; another :class:`Trajectory` gives its times).

        The library's one sampling route, :mod:`quatspline.ops`, does the work (see
        :func:`set_sampler`).

        Raises
        ------
        RuntimeError
            If no sampler is registered (:mod:`quatspline.ops` was never imported).
        """
        if not _sampler:
            raise RuntimeError(
                "Trajectory.resample: no sampler is registered; import quatspline.ops "
                "(import quatspline does)"
            )
        return _sampler[0](self, times, method=method, extrapolate=extrapolate, **params)

    def to_dataframe(self):
        """A pandas DataFrame: columns t, qw, qx, qy, qz (x, y, z; t_ns; extra columns).
        See :func:`to_dataframe`."""
        return to_dataframe(self)

    @classmethod
    def from_dataframe(cls, df, name: str = ""):
        """The inverse of :meth:`to_dataframe` (column names as in the CSV reader). See
        :func:`from_dataframe`."""
        return from_dataframe(df, name=name)


# ---- the checks a record read from a file passes ----------------------------------------
def quat_norms(quats: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(norms, unit quaternions) of finite quaternions (N, 4), scaled first so that components
    up to 1.8e308 (whose squares overflow) give the right unit quaternion; a norm beyond the
    float range is inf. Zero rows give norm 0 (and a meaningless unit row)."""
    scale = np.max(np.abs(quats), axis=1)
    safe = np.where(scale > 0, scale, 1.0)
    scaled = quats / safe[:, None]
    n = np.linalg.norm(scaled, axis=1)
    with np.errstate(over="ignore"):
        norm = scale * n
    return norm, scaled / np.where(n > 0, n, 1.0)[:, None]


def finish(
    path,
    times,
    quats,
    positions=None,
    lines=None,
    sort: bool = False,
    dedupe: bool = False,
    name: str = "",
    stamps_ns=None,
) -> Trajectory:
    """Validates what a reader parsed: finite values, non-zero quaternions (normalised),
    strictly increasing times (or sorted / de-duplicated on request). ``lines`` gives the file
    line of each row for messages."""
    times = np.asarray(times, dtype=float)
    quats = np.asarray(quats, dtype=float).reshape(-1, 4)
    pos = None if positions is None else np.asarray(positions, dtype=float).reshape(-1, 3)
    lines = np.arange(1, len(times) + 1) if lines is None else np.asarray(lines)
    ns = None if stamps_ns is None else np.asarray(stamps_ns, dtype=np.int64)
    if len(times) == 0:
        raise TrajectoryError(f"{path}: no data rows")
    bad = ~np.isfinite(times) | ~np.all(np.isfinite(quats), axis=1)
    if pos is not None:
        bad |= ~np.all(np.isfinite(pos), axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise TrajectoryError(f"{path}:{lines[k]}: NaN or inf in this row")
    norm, unit = quat_norms(quats)
    if np.any(norm < MIN_QUAT_NORM):
        k = int(np.argmax(norm < MIN_QUAT_NORM))
        raise TrajectoryError(f"{path}:{lines[k]}: quaternion of zero norm")
    quats = unit
    if sort:
        order = np.argsort(times, kind="stable")
        times, quats, lines = times[order], quats[order], lines[order]
        pos = None if pos is None else pos[order]
        ns = None if ns is None else ns[order]
    if dedupe:
        keep = np.concatenate([[True], np.diff(times) != 0])
        times, quats, lines = times[keep], quats[keep], lines[keep]
        pos = None if pos is None else pos[keep]
        ns = None if ns is None else ns[keep]
    dt = np.diff(times)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0)) + 1
        what = "duplicate" if dt[k - 1] == 0 else "decreasing"
        if ns is not None and ns[k] > ns[k - 1]:
            res = float(np.spacing(abs(times[k]))) * 1e9
            raise TrajectoryError(
                f"{path}:{lines[k]}: stamps {int(ns[k - 1])} and {int(ns[k])} ns are "
                f"{int(ns[k] - ns[k - 1])} ns apart, closer than float64 seconds resolve at "
                f"this time ({res:.3g} ns); use dedupe=True (--dedupe) to drop such rows"
            )
        raise TrajectoryError(
            f"{path}:{lines[k]}: {what} timestamp {float(times[k])!r} after "
            f"{float(times[k - 1])!r} "
            "(use --sort / --dedupe, or sort=True / dedupe=True)"
        )
    return Trajectory(times, quats, pos, name=name, stamps_ns=ns)


# ---- pandas DataFrames -------------------------------------------------------------------
def _pandas():
    return need("pandas", extra="pandas", what="the DataFrame bridge")


def to_dataframe(traj: Trajectory):
    """A pandas DataFrame of a trajectory (needs pandas: ``pip install quatspline[pandas]``).

    Parameters
    ----------
    traj : Trajectory
        The trajectory.

    Returns
    -------
    pandas.DataFrame
        Columns ``t, qw, qx, qy, qz``, then ``x, y, z`` with positions, ``t_ns`` with exact
        nanosecond stamps, and the extra columns (vectors as ``name_x, name_y, name_z``).

    Raises
    ------
    TypeError
        If ``traj`` is not a :class:`Trajectory`.
    ImportError
        If pandas is not installed (the message says how to install it).

    Examples
    --------
    >>> tr = Trajectory([0.0, 0.5], [[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    >>> list(to_dataframe(tr).columns)
    ['t', 'qw', 'qx', 'qy', 'qz']
    """
    if not isinstance(traj, Trajectory):
        raise TypeError(f"traj: expected a quatspline.io.Trajectory, got {type(traj).__name__}")
    pd = _pandas()
    cols = {"t": traj.times}
    for k, c in enumerate(("qw", "qx", "qy", "qz")):
        cols[c] = traj.quats[:, k]
    if traj.positions is not None:
        for k, c in enumerate("xyz"):
            cols[c] = traj.positions[:, k]
    if traj.stamps_ns is not None:
        cols["t_ns"] = traj.stamps_ns
    for name, arr in traj.extra.items():
        a = np.asarray(arr, dtype=float).reshape(len(traj), -1)
        if a.shape[1] == 1:
            cols[name] = a[:, 0]
        else:
            for k in range(a.shape[1]):
                cols[f"{name}_{'xyz'[k] if a.shape[1] <= 3 else k}"] = a[:, k]
    return pd.DataFrame(cols)


def from_dataframe(df, name: str = "", sort: bool = False, dedupe: bool = False) -> Trajectory:
    """A trajectory from a DataFrame with a time column and quaternion columns.

    Columns are matched as the CSV reader matches headers (``t``/``time``/…, ``qw qx qy qz``
    or ``w x y z`` in any order, optional ``x y z``/``tx ty tz``/``px py pz``); a ``t_ns``
    int64 column gives exact stamps.

    Parameters
    ----------
    df : pandas.DataFrame
        The table.
    name : str, optional
        A label for the trajectory.
    sort, dedupe : bool, default False
        Sort by time / drop repeated times instead of raising.

    Returns
    -------
    Trajectory

    Raises
    ------
    TypeError
        If ``df`` is not a DataFrame.
    ValueError
        If columns are missing or a value is invalid (the message names the DataFrame row
        by its index label).
    ImportError
        If pandas is not installed (the message says how to install it).

    Examples
    --------
    >>> tr = Trajectory([0.0, 0.5], [[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    >>> from_dataframe(to_dataframe(tr)).quats[1]
    array([0., 1., 0., 0.])
    """
    pd = _pandas()
    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"df: expected a pandas DataFrame, got {type(df).__name__}")
    names = [clean(str(c)) for c in df.columns]
    ti = next((names.index(n) for n in TIME if n in names), None)
    ns = None
    if ti is None and "t_ns" in names:
        ti = names.index("t_ns")
    if ti is None:
        raise TrajectoryError(
            f"df: no time column (one of {', '.join(TIME)}); got {list(df.columns)}"
        )
    qi = find(names, QUATS)
    if qi is None:
        raise TrajectoryError(f"df: no quaternion columns (qw qx qy qz); got {list(df.columns)}")
    pi = find(names, positions_for(names, qi))
    try:
        a = df.to_numpy(dtype=float, na_value=np.nan)
    except (TypeError, ValueError) as e:
        raise TrajectoryError(f"df: columns must be numbers ({e})") from None
    if "t_ns" in names:
        col = df.iloc[:, names.index("t_ns")]
        if col.dtype.kind in "iu":
            ns = col.to_numpy(dtype=np.int64)
    t = ns * 1e-9 if (ns is not None and names[ti] == "t_ns") else a[:, ti]
    lines = np.array([str(i) for i in df.index])
    return finish(
        "df row",
        t,
        a[:, list(qi)],
        a[:, list(pi)] if pi is not None else None,
        lines,
        sort,
        dedupe,
        name=name,
        stamps_ns=ns,
    )
