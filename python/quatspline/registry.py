"""Every method by name, with its parameters: one table for ``quatspline.spline`` and the CLI.

``spline(method, quats, times=None, **params)`` builds any method from keys at times. The
approximating methods are adapted to keys at times as follows (documented choices):

- ``bezier`` / ``cumulative_bezier``: one curve with the keys as control points, over
  [t₀, t_last] (passes through the first and last key only);
- ``bspline``: the uniform cumulative B-spline with the keys as control points, the first and
  last key doubled so the curve spans [t₀, t_last]; it treats the key times as uniform;
- ``nonuniform_bspline``: the cumulative cubic B-spline with the keys as control points (first
  and last doubled) and knots at the key times (extended past the ends by the end spacings),
  so non-uniform times are respected;
- ``beta``: the Beta spline with the keys as vertices, the first and last doubled, one segment
  per key interval (joints at the key times).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import spline as sp

__all__ = [
    "METHODS",
    "POSE_METHODS",
    "Method",
    "Param",
    "interpolating_methods",
    "pose_spline",
    "spline",
]


@dataclass(frozen=True)
class Param:
    type: type
    default: object
    help: str


@dataclass(frozen=True)
class Method:
    name: str
    summary: str
    interpolating: bool
    continuity: str
    params: dict


def _pad(q):
    q = np.asarray(q, dtype=float)
    return np.vstack([q[:1], q, q[-1:]])


def _times_or_default(times, n):
    return np.arange(n, dtype=float) if times is None else np.asarray(times, dtype=float)


def _build(name, q, times, p):
    if name == "slerp":
        return sp.PiecewiseSlerp(q, times)
    if name == "nlerp":
        return sp.PiecewiseNlerp(q, times)
    if name == "lin_euler":
        return sp.PiecewiseLinEuler(q, times, seq=p["seq"])
    if name == "lin_mat":
        return sp.PiecewiseLinMat(q, times)
    if name == "squad":
        return sp.Squad(q, times)
    if name == "catmull_rom":
        return sp.CatmullRom(q, times, ends=p["ends"])
    if name == "natural":
        return sp.NaturalSpline(q, times, ends=p["ends"])
    if name == "c3":
        return sp.C3Spline(q, times, alpha=p["alpha"], beta=p["beta"], variant=p["variant"])
    t = _times_or_default(times, len(q))
    if len(t) != len(q):
        raise ValueError(f"times: expected {len(q)} times (one per key), got {len(t)}")
    if name == "bezier":
        return sp.SphericalBezier(q, domain=(t[0], t[-1]))
    if name == "cumulative_bezier":
        return sp.CumulativeBezier(q, domain=(t[0], t[-1]))
    if name == "bspline":
        k = int(p["order"])
        if k != 4:
            raise ValueError("order: the registry's bspline spans the keys with order 4 only")
        return sp.CumulativeBSpline(_pad(q), dt=(t[-1] - t[0]) / (len(q) - 1), t0=t[0], order=4)
    if name == "nonuniform_bspline":
        # keys as control points (ends doubled), joints at the key times, end knots
        # extended by the end spacings: simple knots, C², non-uniform times respected
        h0, h1 = t[1] - t[0], t[-1] - t[-2]
        knots = np.concatenate([t[0] - h0 * np.arange(3, 0, -1), t, t[-1] + h1 * np.arange(1, 4)])
        return sp.CumulativeBSpline(_pad(q), knots=knots, order=4)
    if name == "beta":
        return sp.BetaSpline(_pad(q), beta1=p["beta1"], beta2=p["beta2"], times=t)
    raise AssertionError(name)


METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method("slerp", "piecewise slerp", True, "C0", {}),
        Method("nlerp", "piecewise normalised lerp (baseline)", True, "C0", {}),
        Method(
            "lin_euler",
            "Euler angles lerped (baseline)",
            True,
            "C0",
            {"seq": Param(str, "xyz", "Euler sequence, scipy's convention")},
        ),
        Method("lin_mat", "matrices lerped and projected (baseline)", True, "C0", {}),
        Method("squad", "Shoemake's Squad, C¹ in time", True, "C1", {}),
        Method(
            "catmull_rom",
            "Catmull–Rom (Gortler), C¹ in time",
            True,
            "C1",
            {"ends": Param(str, "reflect", "reflect | duplicate")},
        ),
        Method(
            "natural",
            "global C² spline (scipy RotationSpline's construction)",
            True,
            "C2",
            {"ends": Param(str, "natural", "natural | clamped (clamped = scipy's RotationSpline)")},
        ),
        Method(
            "c3",
            "the patent's C³ spline",
            True,
            "C3",
            {
                "alpha": Param(float, 5 / 16, "shape parameter α (q', q'', q''' at keys)"),
                "beta": Param(float, 0.0, "shape parameter β (q''' at keys)"),
                "variant": Param(str, "knot", "knot | patent"),
            },
        ),
        Method("bezier", "one spherical Bézier curve over all keys", False, "C∞ (one curve)", {}),
        Method("cumulative_bezier", "one cumulative Bézier curve over all keys", False, "C∞", {}),
        Method(
            "bspline",
            "cumulative cubic B-spline with the keys as control points",
            False,
            "C2",
            {"order": Param(int, 4, "spline order (4 = cubic)")},
        ),
        Method(
            "nonuniform_bspline",
            "cumulative cubic B-spline, keys as control points, joints at the key times",
            False,
            "C2",
            {},
        ),
        Method(
            "beta",
            "Beta quaternion spline with the keys as vertices",
            False,
            "G1",
            {
                "beta1": Param(float, 1.0, "shape parameter β₁ > 0 (bias)"),
                "beta2": Param(float, 0.0, "shape parameter β₂ (tension)"),
            },
        ),
    ]
}


def interpolating_methods() -> list[str]:
    return [m.name for m in METHODS.values() if m.interpolating]


def spline(method: str, quats, times=None, **params) -> sp.Spline:
    """Builds ``method`` through ``quats`` at ``times``; unknown names and parameters raise a
    ValueError that lists the valid ones."""
    if method not in METHODS:
        raise ValueError(f"method: unknown method {method!r}; valid: {', '.join(METHODS)}")
    m = METHODS[method]
    unknown = sorted(set(params) - set(m.params))
    if unknown:
        valid = ", ".join(m.params) or "none"
        raise ValueError(f"{unknown[0]}: unknown parameter of {method}; valid: {valid}")
    p = {}
    for name, spec in m.params.items():
        v = params.get(name, spec.default)
        try:
            p[name] = spec.type(v)
        except (TypeError, ValueError):
            raise ValueError(f"{name}: expected {spec.type.__name__}, got {v!r}") from None
    return _build(method, quats, times, p)


# ---- pose methods (issue 2.4): splines of poses, built from keys at times ----------------

POSE_METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method("screw", "piecewise ScLerp (constant screw per segment)", True, "C0", {}),
        Method(
            "screw_smooth", "C³ cumulative screw spline (the c3 weights on SE(3))", True, "C3", {}
        ),
        Method(
            "pose_bspline",
            "cumulative cubic B-spline on SE(3), keys as control poses, joints at key times",
            False,
            "C2",
            {"formulation": Param(str, "se3", "se3 | split")},
        ),
    ]
}


def pose_spline(method: str, quats, times, positions, **params):
    """Builds the pose method ``method`` (see ``POSE_METHODS``) through pose keys at times;
    unknown names and parameters raise a ValueError listing the valid ones."""
    if method not in POSE_METHODS:
        raise ValueError(
            f"method: unknown pose method {method!r}; valid: {', '.join(POSE_METHODS)}"
        )
    m = POSE_METHODS[method]
    unknown = sorted(set(params) - set(m.params))
    if unknown:
        valid = ", ".join(m.params) or "none"
        raise ValueError(f"{unknown[0]}: unknown parameter of {method}; valid: {valid}")
    if method in ("screw", "screw_smooth"):
        from .screw import ScrewSpline

        return ScrewSpline(quats, times, positions, smooth=method == "screw_smooth")
    from .pose_bspline import PoseBSpline

    q = np.asarray(quats, dtype=float)
    p = np.asarray(positions, dtype=float)
    t = _times_or_default(times, len(q))
    if len(t) < 2 or len(t) != len(q):
        raise ValueError(f"times: expected {len(q)} times (one per key, at least 2), got {len(t)}")
    h0, h1 = t[1] - t[0], t[-1] - t[-2]
    knots = np.concatenate([t[0] - h0 * np.arange(3, 0, -1), t, t[-1] + h1 * np.arange(1, 4)])
    return PoseBSpline(
        _pad(q), _pad(p), knots=knots, order=4, formulation=params.get("formulation", "se3")
    )
