"""Smoothing splines fitted to noisy samples, and minimum-energy interpolation.

- ``smoothing``: :func:`fit`, :class:`FittedSpline`, :class:`FittedPose`; with a gyroscope
  (``fit(..., gyro=...)``) the sensor's estimates are a :class:`GyroEstimate`.
- ``min_energy``: :class:`MinimumEnergySpline`.
"""

from ._gyro import ESTIMATES as GYRO_ESTIMATES
from ._gyro import WEAK_STD, GyroEstimate
from .min_energy import MinimumEnergySpline
from .smoothing import FittedPose, FittedSpline, fit

__all__ = [
    "GYRO_ESTIMATES",
    "FittedPose",
    "FittedSpline",
    "GyroEstimate",
    "MinimumEnergySpline",
    "WEAK_STD",
    "fit",
]
