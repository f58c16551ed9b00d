"""Fitting a smooth spline to a noisy recording and sampling the fit: the one route of
``quatspline fit``, ``quatspline batch fit`` and :func:`quatspline.fit_trajectory` (behind
:mod:`quatspline.ops`). Where to sample is checked as :func:`quatspline.ops.sample` checks it,
before the fit is computed."""

from __future__ import annotations

import math
import numbers
from pathlib import Path

import numpy as np

from ..fitting import FittedPose, GyroEstimate, fit
from ..fitting._gyro import DEFAULT_ESTIMATE
from ..io import ImuData, Trajectory, read_imu
from ..splines import DEFAULT_MAX_SAMPLES
from ._imu import _noise
from ._ops import ParameterError, _check_trajectory
from ._sample import evaluate, requested_times, sample_times

__all__ = ["FIT_EXTRAPOLATE", "fit_trajectory", "gyro_summary", "rms_residual_deg"]

#: The extrapolation modes of a fit (:func:`quatspline.fit`).
FIT_EXTRAPOLATE = ("raise", "clamp")


def rms_residual_deg(f) -> float:
    """The root-mean-square orientation residual of a fit, in degrees; 0.0 for a fit
    without residuals (nothing to summarise; never a NaN from an empty mean).

    Parameters
    ----------
    f : FittedSpline or FittedPose
        A fit (anything with ``residuals`` in radians).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from quatspline.ops import rms_residual_deg
    >>> rms_residual_deg(SimpleNamespace(residuals=np.radians([3.0, 4.0])))  # √((9+16)/2)
    3.5355339059327378
    >>> rms_residual_deg(SimpleNamespace(residuals=np.array([])))
    0.0
    """
    r = np.asarray(f.residuals, dtype=float).reshape(-1)
    if r.size == 0:
        return 0.0
    return float(np.degrees(np.sqrt(np.mean(r**2))))


def _relative_knots(knots, t0: float):
    """Knot times given on the recording's clock, moved to the fit's (relative) clock; a
    spacing, None or anything else is passed on for :func:`quatspline.fit` to judge."""
    if knots is None or isinstance(knots, (numbers.Real, str, bytes, dict)):
        return knots
    k = np.asarray(knots)
    if k.dtype.kind not in "iuf":
        return knots
    return k.astype(float) - t0


def gyro_summary(g: GyroEstimate) -> str:
    """One line per estimated sensor parameter of a gyro-aided fit, with its standard
    deviation (degrees, °/s, milliseconds).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline.ops import gyro_summary
    >>> t = np.linspace(0.0, 4.0, 9)
    >>> gt = np.linspace(0.0, 4.0, 401)
    >>> f = qs.fit(t, qs.from_rotvec(np.outer(np.sin(t), [1.0, 0.5, 0.0])),
    ...            gyro=(gt, np.outer(np.cos(gt), [1.0, 0.5, 0.0])), gyro_noise=0.01,
    ...            noise_std=0.001, estimate=("bias",))
    >>> print(gyro_summary(f.gyro).splitlines()[0][:22])
    gyro bias (°/s):
    """
    lines = []
    est = set(g.estimated)

    def three(v, sd):
        return "  ".join(f"{a:+.4f} ± {b:.4f}" for a, b in zip(v, sd))

    if "bias" in est:
        lines.append(f"gyro bias (°/s):        {three(np.degrees(g.bias), np.degrees(g.bias_std))}")
    if "time_offset" in est:
        lines.append(
            f"time offset (ms):       {1e3 * g.time_offset:+.4f} ± {1e3 * g.time_offset_std:.4f}"
        )
    if "rotation" in est:
        w = np.clip(abs(float(g.rotation[0])), 0.0, 1.0)
        ang = math.degrees(2.0 * math.acos(w))
        lines.append(
            f"sensor rotation:        {ang:.4f}° (std per axis "
            + ", ".join(f"{math.degrees(s):.4f}°" for s in g.rotation_std)
            + ")"
        )
    if "scale" in est:
        lines.append(f"gyro scale − 1:         {three(g.scale, g.scale_std)}")
    rms = ", ".join(f"{math.degrees(v):.3f}" for v in g.rms)
    lines.append(f"gyro residual RMS (°/s): {rms} (σ_g {math.degrees(g.gyro_noise):.3f})")
    return "\n".join(lines)


def _gyro(gyro, t0: float):
    """The gyroscope for the fit: an ImuData, (times, rates) or a file read by
    :func:`quatspline.io.read_imu`, its times moved to the fit's (relative) clock."""
    if isinstance(gyro, (str, Path)):
        gyro = read_imu(gyro)
    if isinstance(gyro, ImuData):
        return (gyro.times - t0, gyro.gyro)
    if isinstance(gyro, (tuple, list)) and len(gyro) == 2:
        return (np.asarray(gyro[0], dtype=float) - t0, gyro[1])
    raise TypeError(
        f"gyro: expected an ImuData, a pair (times, rates) or a file name, got "
        f"{type(gyro).__name__}"
    )


def _uncertainty_columns(f, t: np.ndarray, derivatives: bool) -> dict:
    """The posterior standard deviations of a fit at ``t`` as extra columns."""
    cols = {"orientation_std": f.std(t)}
    if isinstance(f, FittedPose):
        cols["position_std"] = f.position_std(t)
    if derivatives:
        cols["omega_std"] = f.angular_velocity_std(t)
    return cols


def fit_trajectory(
    traj,
    *,
    rate: float | None = None,
    count: int | None = None,
    times=None,
    smoothing="auto",
    penalty: str = "acceleration",
    robust: str | None = None,
    knots=None,
    derivatives: bool = False,
    uncertainty: bool = False,
    max_samples: int | None = None,
    extrapolate: str = "raise",
    progress=None,
    gyro=None,
    gyro_noise=None,
    estimate=DEFAULT_ESTIMATE,
):
    """Fits a recorded trajectory and samples the fit: the operation behind ``quatspline fit``.

    Parameters
    ----------
    traj : quatspline.io.Trajectory
        The measurements (times, orientations, optional positions — fitted too).
    rate, count, times
        Where to sample: exactly one of a rate, a count over the time range, or times on the
        recording's clock (an array or a Trajectory), checked as :func:`quatspline.ops.sample`
        checks them, before fitting.
    smoothing, penalty, robust
        As :func:`quatspline.fit`.
    knots : None, float or array_like
        As :func:`quatspline.fit`; an array holds knot times on the recording's clock (as
        ``times``).
    derivatives : bool
        Add ``omega``, ``alpha`` and ``jerk`` columns (world frame).
    uncertainty : bool
        Add the fit's posterior standard deviations (:meth:`quatspline.FittedSpline.std`):
        ``orientation_std`` (radians, about the body axes), ``position_std`` (with positions)
        and, with ``derivatives``, ``omega_std`` (world frame). The fit must smooth (λ > 0).
    max_samples : int, optional
        Refuse to produce more samples (default :data:`quatspline.ops.DEFAULT_MAX_SAMPLES`),
        for ``times`` as for ``rate`` and ``count``.
    extrapolate : {"raise", "clamp"}, default "raise"
        Times outside the recording: an error (:func:`quatspline.ops.check_times`) or the end
        pose held.
    progress : None, True or callable
        As :func:`quatspline.fit`.
    gyro : None, quatspline.io.ImuData, (times, rates) or path
        A gyroscope fitted with the orientations (:func:`quatspline.fit`'s ``gyro``), its
        times on the recording's clock; a path is read by :func:`quatspline.io.read_imu`.
    gyro_noise : None, ImuNoise, mapping, imu.yaml path or float
        The gyroscope's noise (:func:`quatspline.fit`'s ``gyro_noise``; a path or mapping is
        read as Kalibr ``imu.yaml`` densities).
    estimate : sequence of str
        With ``gyro``: the sensor parameters to estimate (as :func:`quatspline.fit`).

    Returns
    -------
    (quatspline.io.Trajectory, FittedSpline or FittedPose)
        The samples and the fit (with ``smoothing``, ``effective_dof``, ``residuals``, …;
        :func:`rms_residual_deg` summarises the residuals).

    Raises
    ------
    ParameterError
        Not exactly one of ``rate``, ``count``, ``times``; too many samples; an extrapolation
        mode a fit does not have.
    ValueError
        Measurements or times the fit cannot use (see :func:`quatspline.fit`).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline.io import Trajectory
    >>> t = 100.0 + np.linspace(0, 2, 41)
    >>> traj = Trajectory(t, qs.from_rotvec(np.outer(t - 100, [0.1, 0.2, 0.0])))
    >>> out, f = qs.fit_trajectory(traj, count=5, smoothing=1e-6)
    >>> out.times.tolist()
    [100.0, 100.5, 101.0, 101.5, 102.0]
    """
    _check_trajectory(traj)
    if max_samples is None:
        max_samples = DEFAULT_MAX_SAMPLES
    if not isinstance(derivatives, (bool, np.bool_)):
        raise TypeError(f"derivatives: expected a bool, got {type(derivatives).__name__}")
    if not isinstance(uncertainty, (bool, np.bool_)):
        raise TypeError(f"uncertainty: expected a bool, got {type(uncertainty).__name__}")
    if not isinstance(extrapolate, str) or extrapolate not in FIT_EXTRAPOLATE:
        raise ParameterError(
            f"extrapolate: expected one of {', '.join(FIT_EXTRAPOLATE)} for a fit, "
            f"got {extrapolate!r}"
        )
    t, ns = requested_times(
        traj,
        rate=rate,
        count=count,
        times=times,
        max_samples=max_samples,
        extrapolate=extrapolate,
    )
    t0 = float(traj.times[0])
    extra_kw = {}
    if gyro is not None:
        if isinstance(gyro_noise, (str, Path)) or hasattr(gyro_noise, "keys"):
            gyro_noise = _noise(gyro_noise)
        extra_kw = {"gyro": _gyro(gyro, t0), "gyro_noise": gyro_noise, "estimate": estimate}
    elif gyro_noise is not None:
        raise ParameterError("gyro_noise: only with a gyroscope (gyro=...)")
    f = fit(
        traj.times - t0,
        traj.quats,
        positions=traj.positions,
        smoothing=smoothing,
        penalty=penalty,
        robust=robust,
        knots=_relative_knots(knots, t0),
        progress=progress,
        extrapolate=extrapolate,
        **extra_kw,
    )
    if t is None:
        t = sample_times(f.domain, rate=rate, count=count, max_samples=max_samples)
    if isinstance(f, FittedPose):
        q, pos, extra = evaluate(f.rotation, t, bool(derivatives), f.position)
    else:
        q, pos, extra = evaluate(f, t, bool(derivatives))
    if uncertainty:
        extra.update(_uncertainty_columns(f, t, bool(derivatives)))
    return Trajectory(t + t0, q, pos, extra=extra, name=traj.name, stamps_ns=ns), f
