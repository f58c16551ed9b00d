"""The column names a table of poses may use, shared by the CSV reader and the DataFrame
bridge. Names are matched case-insensitively, with ``#``, surrounding spaces and units in
brackets (``t [s]``) ignored.

- time: ``t``, ``time``, ``timestamp``, ``times``, ``sec``, ``seconds``;
- quaternion: ``qw qx qy qz``, ``w x y z`` or ``q_w q_x q_y q_z`` (any column order);
- Euler angles: ``roll pitch yaw``, ``rx ry rz``, ``e1 e2 e3`` or ``a1 a2 a3``;
- positions: ``tx ty tz``, ``px py pz`` or ``x y z`` (the last only beside ``qw…`` columns).
"""

from __future__ import annotations

import re

TIME = ("t", "time", "timestamp", "times", "sec", "seconds")
QUATS = (("qw", "qx", "qy", "qz"), ("w", "x", "y", "z"), ("q_w", "q_x", "q_y", "q_z"))
EULER = (("roll", "pitch", "yaw"), ("rx", "ry", "rz"), ("e1", "e2", "e3"), ("a1", "a2", "a3"))
POSITIONS = (("tx", "ty", "tz"), ("px", "py", "pz"), ("x", "y", "z"))


def clean(name: str) -> str:
    """A column name as matched: units in brackets, ``#`` and spaces dropped, lower case.

    Examples
    --------
    >>> clean("# Time [s]")
    'time'
    """
    return re.sub(r"\[.*?\]", "", name).strip().lstrip("#").strip().lower()


def find(names: list[str], groups) -> tuple[int, ...] | None:
    """The indices in ``names`` of the first group of ``groups`` whose names are all there.

    Examples
    --------
    >>> find(["t", "qx", "qy", "qz", "qw"], QUATS)
    (4, 1, 2, 3)
    """
    for group in groups:
        if all(g in names for g in group):
            return tuple(names.index(g) for g in group)
    return None


def positions_for(names: list[str], quats: tuple[int, ...]):
    """The position column groups that may go with the quaternion columns ``quats``: not
    ``x y z`` when the quaternion itself is ``w x y z``."""
    return POSITIONS if names[quats[0]] != "w" else POSITIONS[:2]
