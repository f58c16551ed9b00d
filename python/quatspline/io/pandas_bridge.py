"""pandas DataFrames ↔ trajectories (``pip install 'quatspline[pandas]'``)."""

from __future__ import annotations

import numpy as np

from ._common import Trajectory

HINT = "DataFrames need pandas: pip install 'quatspline[pandas]'"


def _pd():
    try:
        import pandas as pd
    except ImportError as e:
        raise ImportError(HINT) from e
    return pd


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

    Examples
    --------
    >>> import numpy as np
    >>> tr = Trajectory([0.0, 0.5], [[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    >>> list(to_dataframe(tr).columns)
    ['t', 'qw', 'qx', 'qy', 'qz']
    """
    pd = _pd()
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

    Examples
    --------
    >>> from quatspline.io import Trajectory, from_dataframe, to_dataframe
    >>> tr = Trajectory([0.0, 0.5], [[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    >>> from_dataframe(to_dataframe(tr)).quats[1]
    array([0., 1., 0., 0.])
    """
    from . import csv_format
    from ._common import TrajectoryError, finish

    pd = _pd()
    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"df: expected a pandas DataFrame, got {type(df).__name__}")
    names = [csv_format._clean(str(c)) for c in df.columns]
    ti = next((names.index(n) for n in csv_format.TIME if n in names), None)
    ns = None
    if ti is None and "t_ns" in names:
        ti = names.index("t_ns")
    if ti is None:
        raise TrajectoryError(
            f"df: no time column (one of {', '.join(csv_format.TIME)}); got {list(df.columns)}"
        )
    qi = csv_format._find(names, csv_format.QUATS)
    if qi is None:
        raise TrajectoryError(f"df: no quaternion columns (qw qx qy qz); got {list(df.columns)}")
    pi = csv_format._find(
        names, csv_format.POSITIONS if names[qi[0]] != "w" else csv_format.POSITIONS[:2]
    )
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
