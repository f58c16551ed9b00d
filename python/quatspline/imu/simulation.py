"""The IMU samples a designed motion would produce: gyroscope and accelerometer, with an
optional mounting, distortion and noise."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .._util import checks
from .._util.arrays import as_times
from ..core.algebra import conjugate, rotate
from ..io.inertial import ImuData, ImuNoise
from ._vectors import GRAVITY, cross, gravity_vector
from ._vectors import times as times_matrix
from .sensor import SensorModel

__all__ = ["simulate"]

_BLOCK = 1 << 15  # samples per block


def _kind(motion) -> str:
    """ "pose" (orientation and position), "rotation" (orientation only), or a TypeError."""
    if not (hasattr(motion, "angular_velocity") and hasattr(motion, "domain")):
        raise TypeError(
            "motion: expected a rotation spline or a pose spline (PoseSpline, FittedPose, "
            f"ScrewSpline, …), got {type(motion).__name__}"
        )
    if hasattr(motion, "linear_acceleration") and hasattr(motion, "orientation"):
        return "pose"
    return "rotation"


def _refuse_accelerometer(sensor: SensorModel) -> None:
    """A rotation spline has no positions, so no accelerometer: a sensor model that asks for
    one (a lever arm, an accelerometer bias or matrix) is refused rather than ignored."""
    asked = [
        name
        for name, on in (
            ("lever_arm", np.any(sensor.lever_arm)),
            ("accel_bias", np.any(sensor.accel_bias)),
            ("accel_matrix", sensor.accel_matrix is not None),
        )
        if on
    ]
    if asked:
        raise ValueError(
            f"sensor: {', '.join(asked)} describe the accelerometer, which needs positions: "
            "the motion is a rotation spline (give a pose spline, e.g. a PoseSpline or a fit "
            "with positions)"
        )


def _motion_times(motion, rate, times, offset: float) -> tuple[np.ndarray, np.ndarray]:
    """(sensor times, motion times = sensor times + offset), checked against the domain."""
    if (rate is None) == (times is None):
        raise ValueError("rate, times: give exactly one of them")
    a, b = (float(x) for x in motion.domain)
    if rate is not None:
        r = checks.real(rate, "rate", positive=True)
        n = int(np.floor((b - a) * r * (1 + 1e-12))) + 1
        tm = np.minimum(a + np.arange(n) / r, b)
        return tm - offset, tm
    t = as_times(times, "times")
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"times: expected a non-empty 1-D array, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"times: not finite at element {int(np.flatnonzero(~np.isfinite(t))[0])}")
    if t.size > 1 and not np.all(np.diff(t) > 0):
        k = int(np.flatnonzero(~(np.diff(t) > 0))[0]) + 1
        raise ValueError(f"times: not strictly increasing at element {k}")
    tm = t + offset
    if getattr(motion, "extrapolate", "raise") == "raise":
        out = (tm < a) | (tm > b)
        if np.any(out):
            k = int(np.flatnonzero(out)[0])
            shift = f" + time_offset {offset:g} = {float(tm[k])!r}" if offset else ""
            raise ValueError(
                f"times: times[{k}] = {float(t[k])!r}{shift} is outside the motion's domain "
                f"[{a}, {b}]"
            )
    return t, tm


def _ideal(motion, tm, g, sensor: SensorModel, turned: bool, gyro, accel) -> None:
    """The noise-free, undistorted sensor readings at motion times ``tm``, into ``gyro`` and
    (for a pose) ``accel``."""
    n = tm.size
    w_body = np.asarray(motion.angular_velocity(tm, frame="body"), dtype=float).reshape(n, 3)
    to_sensor = conjugate(sensor.rotation)
    gyro[...] = rotate(to_sensor, w_body) if turned else w_body
    if accel is None:
        return
    q = np.asarray(motion.orientation(tm), dtype=float).reshape(n, 4)
    a_world = np.asarray(motion.linear_acceleration(tm), dtype=float).reshape(n, 3)
    f_body = rotate(conjugate(q), a_world - g)
    r = sensor.lever_arm
    if np.any(r):
        alpha = np.asarray(motion.angular_acceleration(tm, frame="body"), dtype=float)
        f_body += cross(alpha.reshape(n, 3), r) + cross(w_body, cross(w_body, r))
    accel[...] = rotate(to_sensor, f_body) if turned else f_body


def _noise_model(noise) -> ImuNoise:
    if noise is None:
        return ImuNoise()
    if isinstance(noise, ImuNoise):
        return noise
    if isinstance(noise, Mapping):
        return ImuNoise.from_dict(noise)
    raise TypeError(f"noise: expected an ImuNoise or a mapping, got {type(noise).__name__}")


def _random_walk(rng, start: np.ndarray, step_std: np.ndarray, n: int) -> np.ndarray:
    """b[0] = start, b[k+1] = b[k] + N(0, step_std[k]²) per axis; shape (n, 3)."""
    if not np.any(step_std):
        return np.zeros((n, 3)) if not np.any(start) else np.tile(start, (n, 1))
    out = np.empty((n, 3))
    out[0] = start
    if n > 1:
        steps = out[1:]
        rng.standard_normal(out=steps)
        scale = step_std[0]
        if np.all(np.abs(step_std - scale) <= 1e-9 * scale):  # regular sampling: one scale
            steps *= scale
        else:
            steps *= step_std[:, None]
        np.cumsum(steps, axis=0, out=steps)
        steps += start
    return out


def _add_white(rng, values: np.ndarray, std: float) -> None:
    """values += N(0, std²) per element, in place."""
    noise = rng.standard_normal(values.shape)
    noise *= std
    values += noise


def simulate(
    motion,
    rate=None,
    times=None,
    *,
    gravity=GRAVITY,
    noise=None,
    sensor: SensorModel | None = None,
    seed=None,
) -> ImuData:
    r"""The gyroscope and accelerometer samples an IMU riding on a motion would record.

    For a rotation spline only the gyroscope is simulated; for a pose spline (anything with
    ``orientation``, ``position`` and ``linear_acceleration`` methods: :class:`PoseSpline`,
    :class:`FittedPose`, :class:`ScrewSpline`, …) the accelerometer too. Without ``sensor``
    and ``noise`` the values are exact:

    .. math::

        \omega = R^T \omega_w \ \text{(the body-frame rate)}, \qquad
        f = R^T (\ddot p - g) \ \text{(the specific force)},

    where :math:`R` (world from body) and :math:`p` are the motion's orientation and
    position, both in the motion's exact derivatives (no finite differences). With a
    :class:`SensorModel` the sensor may be rotated and displaced on the body (lever arm terms
    :math:`\dot\omega \times r + \omega \times (\omega \times r)`), its stamps shifted, its
    axes scaled and misaligned; with an :class:`~quatspline.io.ImuNoise` it adds white noise
    and bias random walks. See :class:`SensorModel` for the complete measurement model.

    Parameters
    ----------
    motion : rotation spline or pose spline
        Times in seconds, positions in metres (the accelerometer reads metres per second²
        of the motion's length unit).
    rate : float, optional
        Sample rate in Hz: samples at ``domain[0] + k / rate`` (shifted by the time offset,
        so that each one measures the motion inside its domain).
    times : array_like, shape (N,), optional
        Explicit sample times (sensor clock), strictly increasing; ``times + time_offset``
        must lie in the motion's domain unless the motion extrapolates. Exactly one of
        ``rate`` and ``times``.
    gravity : array_like, shape (3,), default (0, 0, −9.80665)
        The gravity vector in world coordinates, m/s² (z up by default).
    noise : ImuNoise or mapping, optional
        Continuous-time densities (Kalibr ``imu.yaml`` keys). White noise per sample has
        standard deviation σ·√rate (the ``rate`` given, or the median rate of ``times``);
        the bias random walk steps by σ_b·√Δt over each actual interval Δt. None: no noise.
    sensor : SensorModel, optional
        Mounting, time offset, scale and misalignment, initial biases. None: the sensor
        frame is the body frame.
    seed : int, numpy.random.Generator or None
        The random source of the noise. The four noise processes draw from independent
        streams, so switching one on or off leaves the others unchanged.

    Returns
    -------
    ImuData
        ``times`` (sensor clock), ``gyro`` (rad/s), ``accel`` (m/s², None for a rotation
        spline), and the true biases ``gyro_bias``, ``accel_bias`` at each sample.

    Raises
    ------
    ValueError
        Neither or both of ``rate`` and ``times``; times not increasing, not finite or
        outside the motion's domain; a bad gravity vector; white noise with a single sample
        (no rate to discretise with); accelerometer terms of ``sensor`` (``lever_arm``,
        ``accel_bias``, ``accel_matrix``) for a rotation spline, which has no positions.
    TypeError
        ``motion`` is not a spline, ``noise`` or ``sensor`` of the wrong kind.

    See Also
    --------
    integrate : the inverse, strapdown integration.
    SensorModel, quatspline.io.ImuNoise

    Examples
    --------
    A body spinning at 1 rad/s about the vertical while moving on a straight line:

    >>> import numpy as np
    >>> import quatspline as qs
    >>> from quatspline.imu import simulate
    >>> t = np.linspace(0.0, 2.0, 5)
    >>> keys = qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0]))
    >>> pose = qs.PoseSpline(keys, t, np.outer(t, [1.0, 0.0, 0.0]), rotation="slerp")
    >>> d = simulate(pose, rate=100)
    >>> len(d), d.gyro[50].round(12), d.accel[50].round(5)
    (201, array([0., 0., 1.]), array([0.     , 0.     , 9.80665]))
    """
    kind = _kind(motion)
    if sensor is None:
        sensor = SensorModel()
    elif not isinstance(sensor, SensorModel):
        raise TypeError(f"sensor: expected a SensorModel, got {type(sensor).__name__}")
    if kind == "rotation":
        _refuse_accelerometer(sensor)
    model = _noise_model(noise)
    g = gravity_vector(gravity)
    t, tm = _motion_times(motion, rate, times, sensor.time_offset)
    n = t.size

    turned = not np.array_equal(sensor.rotation, (1.0, 0.0, 0.0, 0.0))
    gyro = np.empty((n, 3))
    accel = np.empty((n, 3)) if kind == "pose" else None
    # blocks of samples, so that the temporaries stay in cache
    for first in range(0, n, _BLOCK):
        stop = min(first + _BLOCK, n)
        _ideal(
            motion,
            tm[first:stop],
            g,
            sensor,
            turned,
            gyro[first:stop],
            None if accel is None else accel[first:stop],
        )
    if sensor.gyro_matrix is not None:
        gyro = times_matrix(sensor.gyro_matrix, gyro)
    if accel is not None and sensor.accel_matrix is not None:
        accel = times_matrix(sensor.accel_matrix, accel)

    try:
        streams = np.random.default_rng(seed).spawn(4)
    except (TypeError, ValueError) as e:
        kind = TypeError if isinstance(e, TypeError) else ValueError
        raise kind(
            f"seed: expected an integer ≥ 0, a numpy Generator or None, got {seed!r:.40}"
        ) from e
    dt = np.diff(t)
    white_rate = float(rate) if rate is not None else (1.0 / np.median(dt) if n > 1 else None)
    white_g = model.gyroscope_noise_density
    white_a = model.accelerometer_noise_density if accel is not None else 0.0
    if white_rate is None and (white_g > 0 or white_a > 0):
        raise ValueError("noise: white noise needs a sample rate; give rate= or two or more times")
    gyro_bias = _random_walk(
        streams[0], sensor.gyro_bias, model.gyroscope_random_walk * np.sqrt(dt), n
    )
    if np.any(sensor.gyro_bias) or model.gyroscope_random_walk > 0:
        gyro += gyro_bias
    if white_g > 0:
        _add_white(streams[1], gyro, white_g * np.sqrt(white_rate))
    accel_bias = None
    if accel is not None:
        accel_bias = _random_walk(
            streams[2], sensor.accel_bias, model.accelerometer_random_walk * np.sqrt(dt), n
        )
        if np.any(sensor.accel_bias) or model.accelerometer_random_walk > 0:
            accel += accel_bias
        if white_a > 0:
            _add_white(streams[3], accel, white_a * np.sqrt(white_rate))
    return ImuData(
        times=t,
        gyro=gyro,
        accel=accel,
        gyro_bias=gyro_bias,
        accel_bias=accel_bias,
        name=f"simulated from {type(motion).__name__}",
    )
