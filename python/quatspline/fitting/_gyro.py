"""The gyroscope term of :func:`quatspline.fit`: its arguments and the estimated sensor.

The model (the convention of :func:`quatspline.imu.calibrate`; rates in rad/s, the sensor
frame on the left): a gyroscope sample stamped ``t`` measures
``K · R_bsᵀ · ω_body(t + δ) + b`` plus noise, with ``ω_body`` the fitted curve's body
angular velocity, ``R_bs`` the sensor's orientation in the body frame, ``b`` the bias
(sensor frame), δ the time offset (δ > 0: the IMU's stamps run behind the orientations'
clock) and ``K = diag(1 + s)`` the scale (identity unless estimated).
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass

import numpy as np

from .._util.arrays import as_real
from ..io import ImuData, ImuNoise

__all__ = ["ESTIMATES", "GyroEstimate"]

#: The sensor parameters the gyro-aided fit can estimate.
ESTIMATES = ("bias", "time_offset", "rotation", "scale")
DEFAULT_ESTIMATE = ("bias", "time_offset", "rotation")
#: Standard deviations above which an estimated sensor parameter counts as weakly determined
#: by the motion (named in a warning by the gyro-aided fit and by ``imu.calibrate``): 1° of
#: rotation, 1 % of scale or misalignment, 1 ms of time offset.
WEAK_STD = {
    "rotation": math.radians(1.0),
    "scale": 0.01,
    "misalignment": 0.01,
    "time_offset": 1e-3,
}


def weak_components(names, std: dict) -> tuple:
    """The names among ``names`` (``"rotation_x"``, ``"scale_y"``, ``"time_offset"``, …) whose
    standard deviation in ``std`` exceeds :data:`WEAK_STD` for their kind (or is not finite)."""

    def kind(name: str) -> str:
        return name if name in WEAK_STD else name.rpartition("_")[0]

    return tuple(
        n for n in names if kind(n) in WEAK_STD and not std.get(n, 0.0) <= WEAK_STD[kind(n)]
    )


@dataclass(frozen=True)
class GyroEstimate:
    """The gyroscope's parameters estimated by a gyro-aided :func:`quatspline.fit`.

    Attributes
    ----------
    bias : numpy.ndarray, shape (3,)
        Gyroscope bias ``b``, rad/s, sensor frame.
    bias_std : numpy.ndarray, shape (3,)
        Its standard deviations (0 when held).
    time_offset : float
        δ, seconds: a sample stamped ``t`` measures the motion at ``t + δ``.
    time_offset_std : float
    rotation : numpy.ndarray, shape (4,)
        ``R_bs`` (w, x, y, z): the sensor's orientation in the body frame.
    rotation_std : numpy.ndarray, shape (3,)
        Standard deviations of the rotation's right perturbation ``R_bs · Exp(θ)``, radians.
    scale : numpy.ndarray, shape (3,)
        ``s`` in ``K = diag(1 + s)`` (zeros unless estimated).
    scale_std : numpy.ndarray, shape (3,)
    estimated : tuple of str
        The parameters estimated (the others were held at their starting values).
    covariance : numpy.ndarray, shape (p, p)
        Covariance of the estimated parameters in the order of ``parameters`` (units: rad/s,
        s, rad, 1), given the noise levels used (``gyro_noise``, ``noise_std``).
    parameters : tuple of str
        Names of the covariance's rows (``"bias_x"``, …, ``"time_offset"``,
        ``"rotation_x"``, …, ``"scale_x"``, …).
    gyro_noise : float
        σ_g used, rad/s per axis and sample.
    noise_std : float
        σ_q used for the orientations, radians per axis.
    times : numpy.ndarray, shape (M,)
        The gyroscope samples used (inside the orientations' time range).
    residuals : numpy.ndarray, shape (M, 3)
        Measured minus predicted rate at the solution, rad/s, sensor frame.
    rms : numpy.ndarray, shape (3,)
        RMS of ``residuals`` per axis, rad/s.
    weak : tuple of str
        Estimated components (names as in ``parameters``) whose standard deviation exceeds
        :data:`WEAK_STD` (1° of rotation, 1 % of scale, 1 ms of time offset): the motion
        determines them too loosely for their values to be used; the fit warns naming them.
    """

    bias: np.ndarray
    bias_std: np.ndarray
    time_offset: float
    time_offset_std: float
    rotation: np.ndarray
    rotation_std: np.ndarray
    scale: np.ndarray
    scale_std: np.ndarray
    estimated: tuple
    covariance: np.ndarray
    parameters: tuple
    gyro_noise: float
    noise_std: float
    times: np.ndarray
    residuals: np.ndarray
    rms: np.ndarray
    weak: tuple = ()

    @classmethod
    def from_result(cls, res: dict, estimated, sigma_g, sigma_q, times) -> GyroEstimate:
        names = tuple(res["gyro_parameters"])
        cov = np.asarray(res["gyro_covariance"])
        sd = np.sqrt(np.maximum(np.diagonal(cov), 0.0)) if cov.size else np.zeros(0)
        std = dict(zip(names, sd))

        def three(prefix):
            return np.array([std.get(f"{prefix}_{a}", 0.0) for a in "xyz"])

        res_g = -np.asarray(res["gyro_residuals"])
        return cls(
            bias=np.asarray(res["gyro_bias"]),
            bias_std=three("bias"),
            time_offset=float(res["time_offset"]),
            time_offset_std=float(std.get("time_offset", 0.0)),
            rotation=np.asarray(res["sensor_rotation"]),
            rotation_std=three("rotation"),
            scale=np.asarray(res["gyro_scale"]),
            scale_std=three("scale"),
            estimated=tuple(estimated),
            covariance=cov,
            parameters=names,
            gyro_noise=float(sigma_g),
            noise_std=float(sigma_q),
            times=times,
            residuals=res_g,
            rms=np.sqrt(np.mean(res_g**2, axis=0)) if len(res_g) else np.full(3, np.nan),
            weak=weak_components(names, std),
        )


def gyro_record(gyro, domain: tuple) -> tuple:
    """(times, rates, rate Hz, ImuData or None) of ``gyro`` inside ``domain``; samples outside
    it are dropped with a ``RuntimeWarning`` naming how many."""
    if isinstance(gyro, ImuData):
        t, w, record = gyro.times, gyro.gyro, gyro
    elif isinstance(gyro, (tuple, list)) and len(gyro) == 2:
        t = as_real(gyro[0], "gyro times")
        w = as_real(gyro[1], "gyro")
        record = None
    else:
        raise TypeError(
            f"gyro: expected an ImuData or a pair (times, rates), got {type(gyro).__name__}"
        )
    t = np.asarray(t, dtype=np.float64)
    w = np.asarray(w, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"gyro: expected times of shape (M,), got {t.shape}")
    if w.shape != (t.size, 3):
        raise ValueError(f"gyro: expected rates of shape ({t.size}, 3), got {w.shape}")
    bad = ~np.isfinite(t)
    if bad.any():
        raise ValueError(f"gyro: time not finite at row {int(np.flatnonzero(bad)[0])}")
    bad = ~np.isfinite(w).all(axis=1)
    if bad.any():
        raise ValueError(f"gyro: rate not finite at row {int(np.flatnonzero(bad)[0])}")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        i = int(np.flatnonzero(~(np.diff(t) > 0))[0]) + 1
        raise ValueError(f"gyro: times not strictly increasing at row {i}")
    inside = (t >= domain[0]) & (t <= domain[1])
    if not inside.all():
        dropped = int((~inside).sum())
        warnings.warn(
            f"gyro: {dropped} of {t.size} samples lie outside the orientations' time range "
            f"[{domain[0]:.6g}, {domain[1]:.6g}] and are not used",
            RuntimeWarning,
            stacklevel=3,
        )
        t, w = t[inside], w[inside]
    if t.size < 2:
        raise ValueError(
            f"gyro: needs at least 2 samples inside the orientations' time range "
            f"[{domain[0]:.6g}, {domain[1]:.6g}], got {t.size}"
        )
    rate = 1.0 / float(np.median(np.diff(t)))
    return np.ascontiguousarray(t), np.ascontiguousarray(w), rate, record


def gyro_sigma(gyro_noise, rates: np.ndarray, rate: float) -> float:
    """σ_g per axis and sample (rad/s): from an ImuNoise (its white noise density at the
    record's rate), a number, or (None) estimated from the record itself: 1.4826 × the median
    absolute second difference over √6 (white noise of σ has second differences of variance
    6σ²; a smooth motion's contribution, ω̈ Δt², is far below it at IMU rates)."""
    if gyro_noise is None:
        d2 = np.diff(rates, n=2, axis=0)
        if d2.size == 0:
            raise ValueError("gyro_noise: too few gyroscope samples to estimate it; give it")
        s = 1.4826 * float(np.median(np.abs(d2))) / math.sqrt(6.0)
        # a quantised or noise-free record: a floor far below any real gyroscope's noise
        return max(s, 1e-6 * max(float(np.abs(rates).max()), 1e-3))
    if isinstance(gyro_noise, ImuNoise):
        s = gyro_noise.white_std(rate)[0]
    elif isinstance(gyro_noise, numbers.Real) and not isinstance(gyro_noise, bool):
        s = float(gyro_noise)
    else:
        raise TypeError(
            "gyro_noise: expected None, an ImuNoise or a standard deviation (rad/s), got "
            f"{type(gyro_noise).__name__}"
        )
    if not (math.isfinite(s) and s > 0):
        raise ValueError(f"gyro_noise: expected a finite positive standard deviation, got {s:.6g}")
    return s


def estimate_names(estimate) -> tuple:
    """The parameter names of ``estimate`` (a string or a sequence of them)."""
    if isinstance(estimate, str):
        estimate = (estimate,) if estimate else ()
    if not isinstance(estimate, (tuple, list)):
        raise TypeError(
            f"estimate: expected a sequence of parameter names, got {type(estimate).__name__}"
        )
    out = []
    for e in estimate:
        if not isinstance(e, str):
            raise TypeError(f"estimate: expected parameter names, got {type(e).__name__}")
        if e not in ESTIMATES:
            raise ValueError(f"estimate: unknown parameter {e!r}; valid: {', '.join(ESTIMATES)}")
        if e in out:
            raise ValueError(f"estimate: {e!r} named twice")
        out.append(e)
    return tuple(out)
