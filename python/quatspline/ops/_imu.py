"""Inertial operations on recorded trajectories: the IMU a recording's motion would produce,
and a recorded IMU's calibration against it — the one route of ``quatspline imu simulate``,
``quatspline imu calibrate`` and ``quatspline batch imu-simulate``.

The motion of a recording is, for simulation, the spline of ``method`` through its keys (a
:class:`quatspline.PoseSpline` with the natural cubic translation when it has positions: the
accelerometer too; else the rotation spline: the gyroscope only), or with ``fit`` a smoothing
fit (:func:`quatspline.fit`; noisy motion capture differentiated through an interpolant gives
noisy rates). For calibration it is always the fit (:func:`quatspline.imu.calibrate`'s rule for
a Trajectory). Splines are built on times relative to the first key, for accuracy with large
time stamps, and the IMU's times are on the recording's clock.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from pathlib import Path

from .._util.options import DEFAULT_METHOD
from ..fitting import fit as fit_spline
from ..imu import Calibration, calibrate
from ..imu import simulate as simulate_motion
from ..io import ImuData, ImuNoise, Trajectory, read_imu, read_imu_noise, write_imu
from ..poses.pose_spline import PoseSpline
from ..registry import spline as make_spline
from ..splines import DEFAULT_MAX_SAMPLES
from ._ops import ParameterError, _check_trajectory, _int_arg

__all__ = ["calibrate_imu", "imu_motion", "simulate_imu", "write_simulated"]


def imu_motion(trajectory: Trajectory, method: str = DEFAULT_METHOD, params=None, fit=None):
    """The motion an IMU rides for :func:`simulate_imu`: the spline of ``method`` through the
    keys (a pose spline when there are positions), or the smoothing fit of ``fit`` (a dict of
    :func:`quatspline.fit`'s keyword arguments; ``{}`` for its defaults); on times relative
    to the first key.

    Examples
    --------
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import imu_motion
    >>> traj = Trajectory([10.0, 11.0, 12.0], [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])
    >>> imu_motion(traj).domain
    (0.0, 2.0)
    """
    _check_trajectory(trajectory, "trajectory")
    if params is not None and not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    rel = trajectory.times - trajectory.times[0]
    if fit is not None:
        if not isinstance(fit, Mapping):
            raise TypeError(f"fit: expected a dict of fit options, got {type(fit).__name__}")
        return fit_spline(rel, trajectory.quats, positions=trajectory.positions, **dict(fit))
    if trajectory.positions is not None:
        return PoseSpline(
            trajectory.quats, rel, trajectory.positions, rotation=method, **dict(params or {})
        )
    return make_spline(method, trajectory.quats, rel, **dict(params or {}))


def _noise(noise):
    if noise is None or isinstance(noise, ImuNoise):
        return noise
    if isinstance(noise, (str, Path)):
        return ImuNoise.from_dict(read_imu_noise(noise))
    if isinstance(noise, Mapping):
        return ImuNoise.from_dict(noise)
    raise TypeError(
        f"noise: expected an ImuNoise, a mapping or an imu.yaml path, got {type(noise).__name__}"
    )


def simulate_imu(
    trajectory: Trajectory,
    *,
    rate: float,
    method: str = DEFAULT_METHOD,
    params: dict | None = None,
    fit: dict | None = None,
    noise=None,
    seed=None,
    max_samples: int = DEFAULT_MAX_SAMPLES,
) -> ImuData:
    """The IMU samples a recording's motion would produce (:func:`quatspline.imu.simulate`).

    Parameters
    ----------
    trajectory : quatspline.io.Trajectory
        The recording; with positions the accelerometer is simulated too (gravity
        (0, 0, −9.80665) m/s², positions in metres).
    rate : float
        Sample rate, Hz (> 0); samples from the first key at ``1 / rate`` spacing.
    method, params : str, dict
        The spline through the keys (default: the natural spline, the command line's
        default, :data:`quatspline._util.options.DEFAULT_METHOD`).
    fit : dict, optional
        Instead, a smoothing fit with these options of :func:`quatspline.fit`.
    noise : ImuNoise, mapping or path, optional
        Kalibr ``imu.yaml`` densities (a path is read by :func:`quatspline.io.read_imu_noise`).
    seed : int, optional
        The noise's random seed.
    max_samples : int
        Refuse to produce more samples than this.

    Returns
    -------
    ImuData
        Times on the recording's clock.

    Raises
    ------
    ParameterError
        A rate that is not a positive number, too many samples, an unknown method or
        parameter.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import simulate_imu
    >>> t = np.linspace(100.0, 102.0, 5)
    >>> traj = Trajectory(t, qs.from_rotvec(np.outer(t - 100, [0, 0, 1.0])))
    >>> d = simulate_imu(traj, rate=10, method="slerp")
    >>> len(d), float(d.times[0]), d.gyro[10].round(9).tolist(), d.accel
    (21, 100.0, [0.0, 0.0, 1.0], None)
    """
    _check_trajectory(trajectory, "trajectory")
    if isinstance(rate, bool) or not isinstance(rate, numbers.Real):
        raise TypeError(f"rate: expected a number of samples per second, got {rate!r}")
    rate = float(rate)
    if not (math.isfinite(rate) and rate > 0):
        raise ParameterError(f"rate: expected a finite number > 0, got {rate:g}")
    max_samples = _int_arg(max_samples, "max_samples", 1)
    span = float(trajectory.times[-1] - trajectory.times[0])
    n = math.floor(span * rate * (1 + 1e-12)) + 1
    if n > max_samples:
        raise ParameterError(
            f"rate: {n:,} samples over {span:g} s is more than max_samples = {max_samples:,}"
        )
    noise = _noise(noise)
    motion = imu_motion(trajectory, method, params, fit)
    data = simulate_motion(motion, rate=rate, noise=noise, seed=seed)
    t0 = float(trajectory.times[0])
    return ImuData(
        data.times + t0,
        data.gyro,
        accel=data.accel,
        gyro_bias=data.gyro_bias,
        accel_bias=data.accel_bias,
        name=trajectory.name,
    )


def calibrate_imu(
    trajectory: Trajectory,
    imu,
    *,
    estimate=("rotation", "bias", "scale", "time_offset"),
    max_offset: float = 1.0,
    robust: str | None = None,
    smoothing="auto",
    imu_format: str | None = None,
) -> Calibration:
    """Calibrates a recorded gyroscope against a recording's motion
    (:func:`quatspline.imu.calibrate`, the reference a smoothing fit of the keys).

    Parameters
    ----------
    trajectory : quatspline.io.Trajectory
        The reference orientations (motion capture).
    imu : ImuData or path
        The IMU record, or a file read by :func:`quatspline.io.read_imu` (``imu_format``).
    estimate, max_offset, robust, smoothing
        As :func:`quatspline.imu.calibrate`.

    Returns
    -------
    Calibration

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline.io import Trajectory
    >>> from quatspline.ops import calibrate_imu, simulate_imu
    >>> t = np.linspace(0.0, 10.0, 201)
    >>> traj = Trajectory(t, qs.from_rotvec(np.c_[np.sin(t), np.cos(t), 0.5 * t]))
    >>> imu = simulate_imu(traj, rate=100, fit={})  # the motion the calibration fits, too
    >>> cal = calibrate_imu(traj, imu, estimate=("bias", "time_offset"))
    >>> bool(abs(cal.time_offset) < 1e-6), cal.weak
    (True, ())
    """
    _check_trajectory(trajectory, "trajectory")
    if isinstance(imu, (str, Path)):
        imu = read_imu(imu, format=imu_format)
    elif not isinstance(imu, ImuData):
        raise TypeError(f"imu: expected an ImuData or a file name, got {type(imu).__name__}")
    return calibrate(
        trajectory,
        imu,
        estimate=estimate,
        max_offset=max_offset,
        robust=robust,
        smoothing=smoothing,
    )


def write_simulated(path, data: ImuData, format: str | None = None) -> None:
    """Writes simulated samples with :func:`quatspline.io.write_imu` (atomically; the format
    from the extension: ``.csv`` EuRoC ``imu0/data.csv``, ``.bag``, ``.mcap``), without the
    true biases, which no IMU file holds: the file is what the sensor would have recorded.
    The one writer of ``quatspline imu simulate`` and ``batch imu-simulate``."""
    if not isinstance(data, ImuData):
        raise TypeError(f"data: expected a quatspline.io.ImuData, got {type(data).__name__}")
    plain = ImuData(data.times, data.gyro, accel=data.accel, name=data.name)
    write_imu(path, plain, format=format)
