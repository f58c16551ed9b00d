"""Inertial measurements: simulate the IMU a motion would produce, integrate IMU samples back
into a trajectory, and describe the sensor's mounting and noise.

- :func:`simulate` — gyroscope and accelerometer samples of a rotation or pose spline, exact
  or through a :class:`SensorModel` (mounting, time offset, scale, misalignment, biases) and
  an :class:`~quatspline.io.ImuNoise` (Kalibr ``imu.yaml`` densities);
- :func:`integrate` — fourth-order strapdown integration, the inverse;
- :func:`allan_deviation` — the overlapping Allan deviation, to check or estimate densities;
- :func:`calibrate` — a gyroscope's mounting rotation, bias, scale (and misalignment) and time
  offset against a reference motion, with standard errors (:class:`Calibration`).

The records :class:`quatspline.io.ImuData` (samples) and :class:`quatspline.io.ImuNoise`
(noise densities) are importable from here as well.

Frames: orientations map body (or sensor) coordinates to world coordinates; gyroscope and
accelerometer samples are in the sensor frame; the accelerometer reads the specific force
:math:`R^T(\\ddot p - g)` (+9.81 m/s² upwards at rest, with gravity (0, 0, −9.80665)).
"""

from __future__ import annotations

from ..io.inertial import ImuData as ImuData
from ..io.inertial import ImuNoise as ImuNoise
from ._vectors import GRAVITY
from .allan import allan_deviation
from .calibration import Calibration, calibrate
from .sensor import SensorModel
from .simulation import simulate
from .strapdown import integrate

# ImuData and ImuNoise are importable from here too; they are documented (and listed) in
# quatspline.io, where they live, below this package.
__all__ = [
    "GRAVITY",
    "Calibration",
    "SensorModel",
    "allan_deviation",
    "calibrate",
    "integrate",
    "simulate",
]
