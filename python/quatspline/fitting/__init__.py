"""Smoothing splines fitted to noisy samples, and minimum-energy interpolation.

- ``smoothing``: :func:`fit`, :class:`FittedSpline`, :class:`FittedPose`.
- ``min_energy``: :class:`MinimumEnergySpline`.
"""

from .min_energy import MinimumEnergySpline
from .smoothing import FittedPose, FittedSpline, fit

__all__ = ["FittedPose", "FittedSpline", "MinimumEnergySpline", "fit"]
