"""Library operations on recorded trajectories: sampling a spline, fitting, comparing methods,
exporting, and simulating or calibrating an IMU.

These are the functions behind ``quatspline sample``, ``fit``, ``compare``, ``export`` and
``imu simulate|calibrate`` (:func:`simulate_imu`, :func:`calibrate_imu`); the
command line, batch runs and viewers only call them, one operation each: :func:`sample` is the
only sampling route (``--rate``, ``--count``, ``--at``; :meth:`quatspline.io.Trajectory.resample`
too), :func:`fit_trajectory` the only fitting route, :func:`compare` the only comparison.
They take and return plain data (a :class:`quatspline.io.Trajectory`, lists of dicts of
floats, a Markdown string) and raise ``ValueError`` naming the argument for a bad value
(:class:`ParameterError` when the value is an option the caller chose rather than the data)
and ``TypeError`` for a wrong kind of object.

Positions: when a trajectory has positions they follow every method, interpolating or
approximating. They are always interpolated by the natural cubic spline through the key
positions (C², the ``translation="cubic"`` construction of :class:`quatspline.PoseSpline`),
independently of the rotation method: recorded positions are measurements to pass through,
and the choice of rotation method is about orientation only.
"""

from __future__ import annotations

from ..io.trajectory import set_sampler
from . import _resample
from ._compare import IMPULSES, compare, format_table, markdown_cell
from ._export import BvhReport, GltfReport, export, keyframes, to_bvh, to_gltf
from ._fit import FIT_EXTRAPOLATE, fit_trajectory, gyro_summary, rms_residual_deg
from ._imu import calibrate_imu, imu_motion, simulate_imu, write_simulated
from ._ops import DEFAULT_MAX_SAMPLES, ParameterError, build_spline
from ._sample import (
    check_times,
    sample,
    sample_times,
    sample_trajectory,
    times_from_file,
)

__all__ = [
    "FIT_EXTRAPOLATE",
    "IMPULSES",
    "BvhReport",
    "export",
    "GltfReport",
    "keyframes",
    "to_bvh",
    "to_gltf",
    "DEFAULT_MAX_SAMPLES",
    "ParameterError",
    "build_spline",
    "calibrate_imu",
    "check_times",
    "compare",
    "fit_trajectory",
    "gyro_summary",
    "format_table",
    "imu_motion",
    "markdown_cell",
    "rms_residual_deg",
    "sample",
    "sample_times",
    "sample_trajectory",
    "simulate_imu",
    "times_from_file",
    "write_simulated",
]

# the one sampling route behind io.Trajectory.resample (io lies below ops)
set_sampler(_resample.resample)
