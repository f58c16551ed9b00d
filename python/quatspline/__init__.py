"""quatspline: keyframe orientations and poses in, smooth rigid-body motion out.

Quaternions are numpy arrays of shape (..., 4), scalar first (w, x, y, z); dual quaternions
are (..., 8). The numerics live in a Rust core (``quatspline._core``); this package adds
broadcasting, conversions, the CLI, file I/O and plots.
"""

from __future__ import annotations

import importlib

from . import examples, imu, io, ops
from ._core import __version__
from ._util import moved as _moved
from ._util.simd import set_simd, simd_status
from ._util.threads import get_num_threads, set_num_threads
from .core.algebra import (
    canonicalize,
    conjugate,
    exp,
    inverse,
    log,
    multiply,
    normalize,
    power,
    rotate,
)
from .core.averaging import MeanInfo, mean, moving_mean
from .core.convert import (
    as_euler,
    as_matrix,
    as_rotvec,
    as_xyzw,
    from_axis_angle,
    from_euler,
    from_matrix,
    from_rotvec,
    from_scipy,
    from_xyzw,
    to_scipy,
)
from .core.dualquat import (
    dlb,
    dq_conjugate,
    dq_from_pose,
    dq_multiply,
    dq_normalize,
    dq_power,
    dq_screw,
    dq_to_pose,
    dq_transform_point,
    sclerp,
)
from .core.integration import integrate
from .core.interpolate import lerp, lin_euler, lin_mat, nlerp, slerp
from .core.metrics import angle_between
from .core.rigid import rotate_points
from .fitting import FittedPose, FittedSpline, MinimumEnergySpline, fit
from .ops import fit_trajectory
from .poses.pose_spline import PoseSpline
from .registry import METHODS, spline
from .splines import (
    BetaSpline,
    C3Spline,
    CatmullRom,
    CumulativeBezier,
    CumulativeBSpline,
    Hermite,
    KochanekBartels,
    NaturalSpline,
    PiecewiseLinEuler,
    PiecewiseLinMat,
    PiecewiseNlerp,
    PiecewiseSlerp,
    SphericalBezier,
    Spline,
    Squad,
    path_length,
    reparameterize,
)
from .splines.joints import JointContinuity, continuity
from .splines.pose_bspline import PoseBSpline
from .splines.screw import ScrewSpline
from .splines.timing import Reparameterized, arc_length, max_angular_rate, retime

_moved.install()


def __getattr__(name: str) -> object:
    # quatspline.batch (the Dask front end) is imported on first use, not by `import quatspline`
    if name == "batch":
        return importlib.import_module(f"{__name__}.batch")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "batch",
    "__version__",
    "get_num_threads",
    "set_num_threads",
    "set_simd",
    "simd_status",
    "METHODS",
    "PiecewiseLinEuler",
    "PiecewiseLinMat",
    "PiecewiseNlerp",
    "PoseSpline",
    "ScrewSpline",
    "spline",
    "BetaSpline",
    "C3Spline",
    "JointContinuity",
    "continuity",
    "rotate_points",
    "CatmullRom",
    "CumulativeBSpline",
    "CumulativeBezier",
    "NaturalSpline",
    "PiecewiseSlerp",
    "Spline",
    "SphericalBezier",
    "Squad",
    "path_length",
    "reparameterize",
    "Hermite",
    "KochanekBartels",
    "as_euler",
    "as_matrix",
    "as_rotvec",
    "as_xyzw",
    "canonicalize",
    "conjugate",
    "dlb",
    "dq_conjugate",
    "dq_from_pose",
    "dq_multiply",
    "dq_normalize",
    "dq_power",
    "dq_screw",
    "dq_to_pose",
    "dq_transform_point",
    "examples",
    "imu",
    "io",
    "exp",
    "from_axis_angle",
    "from_euler",
    "from_matrix",
    "from_rotvec",
    "from_scipy",
    "from_xyzw",
    "inverse",
    "lerp",
    "lin_euler",
    "lin_mat",
    "log",
    "multiply",
    "nlerp",
    "normalize",
    "power",
    "rotate",
    "sclerp",
    "slerp",
    "to_scipy",
    "angle_between",
    "ops",
    "FittedPose",
    "FittedSpline",
    "MinimumEnergySpline",
    "fit",
    "fit_trajectory",
    "integrate",
    "MeanInfo",
    "mean",
    "moving_mean",
    "Reparameterized",
    "arc_length",
    "max_angular_rate",
    "retime",
    "PoseBSpline",
]
