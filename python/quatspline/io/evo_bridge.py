"""evo's ``PoseTrajectory3D`` ↔ trajectories (``pip install 'quatspline[evo]'``).

evo keeps quaternions scalar first (w, x, y, z), as quatspline does, so nothing is reordered.
"""

from __future__ import annotations

import numpy as np

from .._util.optional import need
from .trajectory import Trajectory, finish


def _trajectory_module():
    """``evo.core.trajectory``; without evo, one ``ImportError`` naming the pip extra."""
    need("evo", extra="evo", what="the evo bridge")
    return need("evo.core.trajectory", extra="evo", what="the evo bridge")


def to_evo(traj: Trajectory):
    """An ``evo.core.trajectory.PoseTrajectory3D`` of a trajectory (needs evo).

    Parameters
    ----------
    traj : Trajectory
        The trajectory; positions become 0 when it has none, which evo's rotation-only
        metrics accept.

    Returns
    -------
    evo.core.trajectory.PoseTrajectory3D

    Raises
    ------
    TypeError
        If ``traj`` is not a :class:`Trajectory`.
    ImportError
        If evo is not installed (the message says how to install it).

    See Also
    --------
    from_evo

    Examples
    --------
    >>> from quatspline.io import Trajectory, to_evo
    >>> e = to_evo(Trajectory([0.0, 1.0], [[1, 0, 0, 0], [0, 0, 0, 1]]))
    >>> e.num_poses
    2
    """
    if not isinstance(traj, Trajectory):
        raise TypeError(f"traj: expected a quatspline.io.Trajectory, got {type(traj).__name__}")
    tm = _trajectory_module()
    pos = traj.positions if traj.positions is not None else np.zeros((len(traj), 3))
    return tm.PoseTrajectory3D(
        positions_xyz=np.array(pos, dtype=float),
        orientations_quat_wxyz=np.array(traj.quats, dtype=float),
        timestamps=np.array(traj.times, dtype=float),
    )


def from_evo(pose_trajectory, name: str = "", sort: bool = False, dedupe: bool = False):
    """A trajectory from an evo ``PoseTrajectory3D`` (times, orientations, positions).

    Parameters
    ----------
    pose_trajectory : evo.core.trajectory.PoseTrajectory3D
        The evo trajectory.
    name : str, optional
        A label.
    sort, dedupe : bool, default False
        Sort by time / drop repeated times instead of raising.

    Returns
    -------
    Trajectory

    Raises
    ------
    TypeError
        If the argument is not a ``PoseTrajectory3D``.
    ValueError
        If its times or orientations are invalid.

    Examples
    --------
    >>> from quatspline.io import Trajectory, from_evo, to_evo
    >>> tr = Trajectory([0.0, 0.5], [[1.0, 0, 0, 0], [0, 0, 0, 1.0]])
    >>> from_evo(to_evo(tr)).quats[1]
    array([0., 0., 0., 1.])
    """
    tm = _trajectory_module()
    if not isinstance(pose_trajectory, tm.PoseTrajectory3D):
        raise TypeError(
            "pose_trajectory: expected an evo PoseTrajectory3D, got "
            f"{type(pose_trajectory).__name__}"
        )
    pt = pose_trajectory
    return finish(
        "evo trajectory",
        np.asarray(pt.timestamps, dtype=float),
        np.asarray(pt.orientations_quat_wxyz, dtype=float),
        np.asarray(pt.positions_xyz, dtype=float),
        None,
        sort,
        dedupe,
        name=name,
    )
