"""Rotation and pose splines behind one interface, :class:`Spline`: one module per family,
named like its Rust file in ``crates/quatspline/src/spline/``, with joint continuity and
retiming.

================================ ============ ================== ================================
class                            interpolates continuity         source
================================ ============ ================== ================================
``PiecewiseSlerp``               yes          C⁰                 Shoemake 1985
``PiecewiseNlerp``               yes          C⁰                 baseline
``PiecewiseLinEuler``            yes          C⁰                 baseline
``PiecewiseLinMat``              yes          C⁰                 baseline
``SphericalBezier``              end points   C^∞ (one curve)    Shoemake 1985 (de Casteljau)
``CumulativeBezier``             end points   C^∞ (one curve)    Kim, Kim & Shin 1995
``Squad``                        yes          C¹                 Shoemake 1987
``CatmullRom``                   yes          C¹                 Gortler 2012, ch. 9
``CumulativeBSpline``            no           C^(k−2), C² cubic  Kim et al. 1995; Sommer et al.
                                                                 2020
``NaturalSpline``                yes          C² (global)        scipy ``RotationSpline``
``BetaSpline``                   no           G¹ (not G²)        He et al. 2022
``C3Spline``                     yes          C³                 Wang & Zhou 2023 (patent)
================================ ============ ================== ================================

The documentation's mathematics pages give every formula, with references and errata.

Modules, each importing only those listed before it (and ``core``, ``_util``):

- ``base``: :class:`Spline`, the interface of every curve; :data:`EXTRAPOLATE`,
  :data:`DEFAULT_MAX_SAMPLES`, :func:`describe`.
- ``keys``: validation of keys and times, and the keyframe controls (closed loops, holds, rest
  ends, :func:`bessel_rates`, :func:`bspline_controls`, :func:`c3_speed_matched_alpha`);
  ``knots``: knot vectors of the non-uniform B-spline.
- one module per family: ``piecewise_slerp``, ``nlerp``, ``lin_euler``, ``lin_mat``,
  ``spherical_bezier``, ``cumulative_bezier``, ``squad``, ``catmull_rom`` (with
  Kochanek–Bartels), ``hermite``, ``cumulative_bspline``, ``natural_spline``, ``beta``, ``c3``.
- ``joints``: the continuity certificate; ``se3``, ``screw``, ``pose_bspline``: pose splines;
  ``timing``: arc length and retiming; ``reparam``: path length and :func:`reparameterize`.
"""

from .base import DEFAULT_MAX_SAMPLES, EXTRAPOLATE, Spline, describe
from .beta import BetaSpline
from .c3 import C3Spline
from .catmull_rom import CatmullRom, KochanekBartels
from .cumulative_bezier import CumulativeBezier
from .cumulative_bspline import CumulativeBSpline
from .hermite import Hermite
from .joints import JointContinuity, continuity
from .keys import bessel_rates, bspline_controls, bspline_hold_intervals, c3_speed_matched_alpha
from .knots import clamped_knots, knots_from_spacing
from .lin_euler import PiecewiseLinEuler
from .lin_mat import PiecewiseLinMat
from .natural_spline import NaturalSpline
from .nlerp import PiecewiseNlerp
from .piecewise_slerp import PiecewiseSlerp
from .pose_bspline import PoseBSpline
from .reparam import path_length, reparameterize
from .screw import ScrewSpline
from .se3 import PoseCurveSpline
from .spherical_bezier import SphericalBezier
from .squad import Squad
from .timing import Reparameterized, arc_length, max_angular_rate, retime

__all__ = [
    "DEFAULT_MAX_SAMPLES",
    "EXTRAPOLATE",
    "BetaSpline",
    "C3Spline",
    "CatmullRom",
    "CumulativeBSpline",
    "CumulativeBezier",
    "Hermite",
    "JointContinuity",
    "KochanekBartels",
    "NaturalSpline",
    "PiecewiseLinEuler",
    "PiecewiseLinMat",
    "PiecewiseNlerp",
    "PiecewiseSlerp",
    "PoseBSpline",
    "PoseCurveSpline",
    "Reparameterized",
    "ScrewSpline",
    "SphericalBezier",
    "Spline",
    "Squad",
    "arc_length",
    "bessel_rates",
    "bspline_controls",
    "bspline_hold_intervals",
    "c3_speed_matched_alpha",
    "clamped_knots",
    "continuity",
    "describe",
    "knots_from_spacing",
    "max_angular_rate",
    "path_length",
    "reparameterize",
    "retime",
]
