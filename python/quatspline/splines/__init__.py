"""Rotation and pose splines, one module per family, with joint continuity and retiming."""

from ._families import (
    BetaSpline,
    C3Spline,
    CatmullRom,
    CumulativeBezier,
    CumulativeBSpline,
    NaturalSpline,
    PiecewiseLinEuler,
    PiecewiseLinMat,
    PiecewiseNlerp,
    PiecewiseSlerp,
    SphericalBezier,
    Spline,
    Squad,
)
from .keyframe import Hermite, KochanekBartels
from .pose_bspline import PoseBSpline
from .screw import ScrewSpline

__all__ = [
    "BetaSpline",
    "C3Spline",
    "CatmullRom",
    "CumulativeBSpline",
    "CumulativeBezier",
    "Hermite",
    "KochanekBartels",
    "NaturalSpline",
    "PiecewiseLinEuler",
    "PiecewiseLinMat",
    "PiecewiseNlerp",
    "PiecewiseSlerp",
    "PoseBSpline",
    "ScrewSpline",
    "SphericalBezier",
    "Spline",
    "Squad",
]
