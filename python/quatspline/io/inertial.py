"""The inertial-measurement record: what the IMU readers return, the IMU writers take,
:func:`quatspline.imu.simulate` produces and the strapdown integrator and the calibration read;
and the IMU noise model in the Kalibr ``imu.yaml`` convention.

Units are SI throughout: seconds, rad/s, m/s². Vectors are in the sensor frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields

import numpy as np

from .._util import checks

__all__ = ["ImuData", "ImuNoise"]


def _vectors(value, name: str, n: int) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name}: expected an array of shape ({n}, 3) of numbers") from e
    if a.shape != (n, 3):
        raise ValueError(f"{name}: expected shape ({n}, 3), got {a.shape}")
    if not np.all(np.isfinite(a)):
        i = int(np.flatnonzero(~np.all(np.isfinite(a), axis=1))[0])
        raise ValueError(f"{name}: not finite at row {i}")
    return a


@dataclass
class ImuData:
    """Inertial measurements: times, gyroscope and (optionally) accelerometer samples.

    Parameters
    ----------
    times : array_like, shape (N,)
        Sample times in seconds, finite and strictly increasing.
    gyro : array_like, shape (N, 3)
        Angular rate in the sensor frame, rad/s.
    accel : array_like, shape (N, 3), optional
        Specific force in the sensor frame, m/s² (what an accelerometer measures: a sensor at
        rest on a table reads +9.81 m/s² upwards). None for a gyroscope-only record.
    gyro_bias, accel_bias : array_like, shape (N, 3), optional
        The true biases at each sample, when known (simulated data).
    stamps_ns : array_like of int64, shape (N,), optional
        The original integer nanosecond stamps of a file that has them (EuRoC, bags), kept
        so that a round trip writes them back exactly.
    name : str
        Where the record came from (a file name), for messages.

    Raises
    ------
    ValueError
        Shapes that do not match, times that are not finite or not strictly increasing,
        non-finite samples (the message names the row).
    TypeError
        Values that are not numbers.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline.io import ImuData
    >>> d = ImuData(np.arange(3) * 0.005, np.zeros((3, 3)), accel=[[0, 0, 9.81]] * 3)
    >>> len(d), d.rate
    (3, 200.0)
    """

    times: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray | None = None
    gyro_bias: np.ndarray | None = None
    accel_bias: np.ndarray | None = None
    stamps_ns: np.ndarray | None = None
    name: str = ""
    extra: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        try:
            t = np.asarray(self.times, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise TypeError("times: expected a 1-D array of numbers") from e
        if t.ndim != 1:
            raise ValueError(f"times: expected a 1-D array, got shape {t.shape}")
        if not np.all(np.isfinite(t)):
            raise ValueError(f"times: not finite at row {int(np.flatnonzero(~np.isfinite(t))[0])}")
        if t.size > 1 and not np.all(np.diff(t) > 0):
            i = int(np.flatnonzero(~(np.diff(t) > 0))[0]) + 1
            raise ValueError(f"times: not strictly increasing at row {i}")
        n = t.size
        self.times = t
        self.gyro = _vectors(self.gyro, "gyro", n)
        for name in ("accel", "gyro_bias", "accel_bias"):
            v = getattr(self, name)
            if v is not None:
                setattr(self, name, _vectors(v, name, n))
        if self.stamps_ns is not None:
            s = np.asarray(self.stamps_ns)
            if s.shape != (n,) or s.dtype.kind not in "iu":
                raise ValueError(
                    f"stamps_ns: expected {n} integers, got shape {s.shape}, dtype {s.dtype}"
                )
            self.stamps_ns = s.astype(np.int64)

    def __len__(self) -> int:
        return int(self.times.size)

    @property
    def rate(self) -> float:
        """The median sample rate, Hz (nan with fewer than two samples)."""
        if self.times.size < 2:
            return float("nan")
        return float(1.0 / np.median(np.diff(self.times)))


@dataclass(frozen=True)
class ImuNoise:
    r"""Continuous-time IMU noise densities in the Kalibr ``imu.yaml`` convention.

    Each axis of each sensor is modelled as the true value plus a white noise and a bias that
    is a random walk (integrated white noise), independent between axes and sensors
    (Kalibr wiki, "IMU Noise Model", https://github.com/ethz-asl/kalibr/wiki/IMU-Noise-Model):

    .. math::

        \tilde\omega(t) = \omega(t) + b(t) + n(t), \qquad \dot b(t) = n_b(t),

    with :math:`n` and :math:`n_b` white of spectral densities :math:`\sigma^2` and
    :math:`\sigma_b^2`. Sampled every :math:`\Delta t` seconds (rate :math:`1/\Delta t`)
    they become, per sample and axis,

    .. math::

        n_d[k] \sim \mathcal N(0, \sigma_d^2),\ \sigma_d = \sigma / \sqrt{\Delta t};
        \qquad b[k+1] = b[k] + \mathcal N(0, \sigma_{bd}^2),\
        \sigma_{bd} = \sigma_b \sqrt{\Delta t}.

    The Allan deviation of such a sensor is :math:`\sigma/\sqrt{\tau}` at short averaging
    times (so :math:`\sigma` is read off at τ = 1 s) and :math:`\sigma_b\sqrt{\tau/3}` at
    long ones.

    Parameters
    ----------
    gyroscope_noise_density : float
        :math:`\sigma_g`, rad/s/√Hz (= rad/√s), the gyroscope's white noise ("angle random
        walk").
    gyroscope_random_walk : float
        :math:`\sigma_{bg}`, rad/s²/√Hz, the gyroscope bias random walk.
    accelerometer_noise_density : float
        :math:`\sigma_a`, m/s²/√Hz, the accelerometer's white noise ("velocity random walk").
    accelerometer_random_walk : float
        :math:`\sigma_{ba}`, m/s³/√Hz, the accelerometer bias random walk.

    All four default to 0 (no noise of that kind); each must be finite and ≥ 0.

    Raises
    ------
    TypeError
        A density that is not a real number.
    ValueError
        A negative or non-finite density.

    Examples
    --------
    The ADIS16448 of the EuRoC MAV datasets (its ``sensor.yaml``), sampled at 200 Hz:

    >>> from quatspline.io import ImuNoise
    >>> n = ImuNoise(gyroscope_noise_density=1.6968e-04, gyroscope_random_walk=1.9393e-05,
    ...              accelerometer_noise_density=2.0e-3, accelerometer_random_walk=3.0e-3)
    >>> gyro_white, accel_white = n.white_std(200.0)
    >>> round(gyro_white, 6), round(accel_white, 6)
    (0.0024, 0.028284)
    >>> gyro_step, accel_step = n.walk_std(1 / 200)
    >>> round(gyro_step, 8)
    1.37e-06
    >>> ImuNoise.from_dict(n.as_dict()) == n
    True
    """

    gyroscope_noise_density: float = 0.0
    gyroscope_random_walk: float = 0.0
    accelerometer_noise_density: float = 0.0
    accelerometer_random_walk: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            x = checks.real(getattr(self, f.name), f.name)
            if x < 0:
                raise ValueError(f"{f.name}: expected a density ≥ 0, got {checks.short(x)}")
            object.__setattr__(self, f.name, x)

    def white_std(self, rate: float) -> tuple[float, float]:
        r"""The per-sample white-noise standard deviations at a sample rate.

        :math:`\sigma_d = \sigma\sqrt{\text{rate}}` for the gyroscope (rad/s) and the
        accelerometer (m/s²).

        Parameters
        ----------
        rate : float
            Sample rate, Hz, finite and > 0.

        Returns
        -------
        (float, float)
            Gyroscope and accelerometer standard deviations per sample and axis.
        """
        r = checks.real(rate, "rate", positive=True)
        s = math.sqrt(r)
        return self.gyroscope_noise_density * s, self.accelerometer_noise_density * s

    def walk_std(self, dt: float) -> tuple[float, float]:
        r"""The per-step standard deviations of the bias random walks over a step ``dt``.

        :math:`\sigma_{bd} = \sigma_b\sqrt{\Delta t}` for the gyroscope (rad/s) and the
        accelerometer (m/s²).

        Parameters
        ----------
        dt : float
            Step, seconds, finite and > 0.

        Returns
        -------
        (float, float)
            Gyroscope and accelerometer bias increments' standard deviations per axis.
        """
        s = math.sqrt(checks.real(dt, "dt", positive=True))
        return self.gyroscope_random_walk * s, self.accelerometer_random_walk * s

    def as_dict(self) -> dict[str, float]:
        """The four densities under their Kalibr ``imu.yaml`` keys."""
        return {f.name: float(getattr(self, f.name)) for f in fields(self)}

    @classmethod
    def from_dict(cls, values: Mapping) -> ImuNoise:
        """The noise model from a mapping with the Kalibr ``imu.yaml`` keys.

        Other keys (``rostopic``, ``update_rate``, …) are ignored. A value may be a number or
        a string holding one (YAML 1.1 parsers read ``1e-3``, without a dot, as a string).

        Raises
        ------
        TypeError
            ``values`` is not a mapping, or a density is not a number.
        ValueError
            A key is missing (named), or a density is negative or not finite.
        """
        if not isinstance(values, Mapping):
            raise TypeError(f"noise: expected a mapping, got {type(values).__name__}")
        names = [f.name for f in fields(cls)]
        missing = [k for k in names if k not in values]
        if missing:
            raise ValueError(
                f"noise: missing key{'s' if len(missing) > 1 else ''} {', '.join(missing)}"
            )
        out = {}
        for k in names:
            v = values[k]
            if isinstance(v, str):  # YAML 1.1 reads 1e-3 (no dot) as a string
                try:
                    v = float(v)
                except ValueError:
                    raise ValueError(f"{k}: expected a number, got {v!r:.40}") from None
            out[k] = v
        return cls(**out)
