"""Inertial measurements: calibration of a gyroscope against a reference motion.

- ``calibration``: :func:`calibrate`, :class:`Calibration`.
"""

from .calibration import Calibration, calibrate

__all__ = ["Calibration", "calibrate"]
