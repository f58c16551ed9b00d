"""The inertial-measurement record: what the IMU readers return, the IMU writers take,
:func:`quatspline.imu.simulate` produces and the strapdown integrator and the calibration read.

Units are SI throughout: seconds, rad/s, m/s². Vectors are in the sensor frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["ImuData"]


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
