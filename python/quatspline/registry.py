"""Every method by name, with its parameters: one table for ``quatspline.spline`` and the CLI.

``spline(method, quats, times=None, **params)`` builds any method from keys at times. The
approximating methods are adapted to keys at times as follows (documented choices):

- ``bezier`` / ``cumulative_bezier``: one curve with the keys as control points, over
  [t₀, t_last] (passes through the first and last key only);
- ``bspline``: the uniform cumulative B-spline with the keys as control points, the first and
  last key doubled so the curve spans [t₀, t_last]; it treats the key times as uniform
  (``ends="rest"``: tripled, zero velocity and acceleration at both ends; ``ends="closed"``:
  the keys used cyclically, no padding);
- ``nonuniform_bspline``: the cumulative cubic B-spline with the keys as control points (first
  and last doubled) and knots at the key times (extended past the ends by the end spacings),
  so non-uniform times are respected;
- ``beta``: the Beta spline with the keys as vertices, the first and last doubled, one segment
  per key interval (joints at the key times).

Closed loops (``ends="closed"``) from N keys at N times: if the last key equals the first it
is the closing key (dropped, its time closes the loop); otherwise the loop closes one mean key
spacing, (t_last − t_first)/(N − 1), after the last key.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._util.arrays import as_real, with_width
from ._util.options import parse_smoothing
from .io._common import open_regular
from .splines import _families as sp

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
    return np.arange(n, dtype=float) if times is None else as_real(times, "times")


def int_or_none(v):
    """An int, or None for None / "none" / "" (an optional parameter)."""
    if v is None or (isinstance(v, str) and v.strip().lower() in ("", "none")):
        return None
    return int(v)


def float_or_none(v):
    """A float, or None for None / "none" / "" (an optional parameter)."""
    if v is None or (isinstance(v, str) and v.strip().lower() in ("none", "")):
        return None
    return float(v)


def flag(v) -> bool:
    """A bool from a bool or "true"/"false"/"1"/"0" (CLI strings)."""
    if isinstance(v, str):
        low = v.strip().lower()
        if low in ("true", "1", "yes"):
            return True
        if low in ("false", "0", "no"):
            return False
        raise ValueError(v)
    return bool(v)


def float_or_auto(v):
    """A float, or "auto" (the C³ spline's ripple-free shape)."""
    if isinstance(v, str) and v.strip().lower() == "auto":
        return "auto"
    return float(v)


# the control kind of each converter in the viewer (quatspline.ops._design.method_specs)
float_or_none.kind = "float"  # type: ignore[attr-defined]
float_or_auto.kind = "float"  # type: ignore[attr-defined]
int_or_none.kind = "int"  # type: ignore[attr-defined]
flag.kind = "bool"  # type: ignore[attr-defined]


def _expects(convert) -> str:
    """What a parameter converter accepts, in words (for messages)."""
    words = {
        float: "a number",
        int: "an integer",
        str: "a string",
        float_or_none: "a number or none",
        float_or_auto: "a number or 'auto'",
        int_or_none: "an integer or none",
        flag: "true or false",
    }
    if convert is rates_spec:
        return "'bessel', 'zero', a file of N×3 rates or an (N, 3) array"
    return words.get(convert, convert.__name__)


def rates_spec(v):
    """Hermite key rates: "bessel" (estimated from the keys), "zero", a file of N×3 values
    (text or .npy) or an (N, 3) array."""
    if isinstance(v, str):
        if v in ("bessel", "zero"):
            return v
        try:  # a FIFO or a device such as /dev/zero is refused, not read for ever
            with open_regular(v, "rb") as f:
                if v.endswith(".npy"):
                    return np.load(f, allow_pickle=False)
                return np.loadtxt(f, ndmin=2, comments="#", delimiter=None)
        except OSError as e:
            raise ValueError(f"cannot read {v!r} ({e})") from None
    return np.asarray(v, dtype=float)


def _hermite(q, times, p):
    from .splines import keyframe as kf

    r = p["rates"]
    if isinstance(r, str):
        q = np.asarray(q, dtype=float)
        r = kf.bessel_rates(q, times) if r == "bessel" else np.zeros((len(q), 3))
        frame = "body"
    else:
        frame = p["frame"]
    return kf.Hermite(q, times, angular_velocity=r, frame=frame, ends=p["ends"], holds=p["holds"])


def _loop_times(q, times, p):
    """Times for a closed loop from N keys at N times (see the module doc)."""
    if times is None or p.get("ends") != "closed":
        return times
    t = np.asarray(times, dtype=float)
    q = np.asarray(q, dtype=float)
    if t.ndim != 1 or len(t) != len(q) or len(t) < 2:
        return times
    from .core.algebra import conjugate, multiply, normalize

    d = multiply(conjugate(normalize(q[0])), normalize(q[-1]))
    if 2 * np.arctan2(np.linalg.norm(d[1:]), abs(d[0])) <= 1e-12:
        return times
    return np.r_[t, t[-1] + (t[-1] - t[0]) / (len(t) - 1)]


def _closed_bspline(q, times, p):
    """The closed cubic B-spline with the keys as control points, spanning the loop's times
    (a closing key equal to the first is dropped, as for the interpolating methods)."""
    if int(p["order"]) != 4:
        raise ValueError("order: the registry's bspline spans the keys with order 4 only")
    q = np.asarray(q, dtype=float)
    t = np.arange(len(q) + 1, dtype=float) if times is None else np.asarray(times, dtype=float)
    if len(t) == len(q):  # the last key is the closing key (see _loop_times)
        q = q[:-1]
    if t.ndim != 1 or len(t) != len(q) + 1:
        raise ValueError(f"times: a closed curve expects {len(q) + 1} times, got {t.shape}")
    if p.get("holds"):
        return _held_bspline(q, "closed", t[0], t[-1])
    return sp.CumulativeBSpline(q, dt=(t[-1] - t[0]) / len(q), t0=t[0], order=4, ends="closed")


def _held_bspline(q, ends, t0, t1):
    """The registry's cubic B-spline with holds: runs of equal keys repeated (see
    ``keyframe.bspline_controls``), the end keys padded as without holds, the segments spread
    over [t0, t1]; ``hold_intervals`` set."""
    from .splines.keyframe import _bspline_hold_intervals, bspline_controls

    c = bspline_controls(
        np.asarray(q, dtype=float), 4, "closed" if ends == "closed" else "open", True
    )
    if ends != "closed":
        c = _pad(_pad(c)) if ends == "rest" else _pad(c)
    segs = len(c) if ends == "closed" else len(c) - 3
    dt = (t1 - t0) / segs
    s = sp.CumulativeBSpline(
        c, dt=dt, t0=t0, order=4, ends="closed" if ends == "closed" else "open"
    )
    s.hold_intervals = _bspline_hold_intervals(c, 4, ends == "closed", dt, t0)
    return s


def _build(name, q, times, p):
    q = with_width(q, "quats", 4)
    times = _loop_times(q, times, p)
    if name == "slerp":
        return sp.PiecewiseSlerp(q, times)
    if name == "nlerp":
        return sp.PiecewiseNlerp(q, times)
    if name == "lin_euler":
        return sp.PiecewiseLinEuler(q, times, seq=p["seq"])
    if name == "lin_mat":
        return sp.PiecewiseLinMat(q, times)
    if name == "squad":
        return sp.Squad(q, times, ends=p["ends"], holds=p["holds"])
    if name == "catmull_rom":
        return sp.CatmullRom(q, times, ends=p["ends"], alpha=p["alpha"], holds=p["holds"])
    if name == "hermite":
        return _hermite(q, times, p)
    if name == "kochanek_bartels":
        from .splines.keyframe import KochanekBartels

        return KochanekBartels(
            q,
            times,
            tension=p["tension"],
            continuity=p["continuity"],
            bias=p["bias"],
            alpha=p["alpha"],
            ends=p["ends"],
            holds=p["holds"],
        )
    if name == "natural":
        return sp.NaturalSpline(q, times, ends=p["ends"], holds=p["holds"])
    if name == "c3":
        return sp.C3Spline(
            q,
            times,
            alpha=p["alpha"],
            beta=p["beta"],
            variant=p["variant"],
            ends=p["ends"],
            holds=p["holds"],
        )
    if name == "bspline" and p["ends"] == "closed":
        return _closed_bspline(q, times, p)
    if name in ("fit", "min_energy"):
        return _fitted(name, q, times, p)
    t = _times_or_default(times, len(q))
    if t.ndim != 1 or len(t) != len(q):
        raise ValueError(f"times: expected {len(q)} times (one per key), got shape {t.shape}")
    # Only the ends (and, for bspline, the mean spacing) are used, but the times must be as
    # valid as for every other method: finite, strictly increasing, in range.
    _core.check_times(np.ascontiguousarray(t), len(q))
    if name == "bezier":
        return sp.SphericalBezier(q, domain=(t[0], t[-1]))
    if name == "cumulative_bezier":
        return sp.CumulativeBezier(q, domain=(t[0], t[-1]))
    if name == "bspline":
        k = int(p["order"])
        if k != 4:
            raise ValueError("order: the registry's bspline spans the keys with order 4 only")
        if p["ends"] in ("open", "rest") and p["holds"]:
            return _held_bspline(q, p["ends"], t[0], t[-1])
        if p["ends"] == "rest":
            # end keys tripled: zero angular velocity and acceleration at both ends
            qq = _pad(_pad(q))
            return sp.CumulativeBSpline(qq, dt=(t[-1] - t[0]) / (len(q) + 1), t0=t[0], order=4)
        if p["ends"] != "open":
            raise ValueError(
                f"ends: bspline does not support {p['ends']!r}; supported: open, rest, closed"
            )
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


def smoothing_spec(v):
    """λ of ``fit``: "auto" or a number ≥ 0 (CLI strings converted)."""
    return parse_smoothing(v)


def str_or_none(v):
    """A string, or None for None / "none"."""
    if v is None or (isinstance(v, str) and v.strip().lower() == "none"):
        return None
    return str(v)


def _fitted(name, q, times, p):
    from .fitting.smoothing import MinimumEnergySpline, fit

    t = _times_or_default(times, len(q))
    if name == "fit":
        return fit(
            t,
            q,
            smoothing=p["smoothing"],
            penalty=p["penalty"],
            robust=p["robust"],
            knots=p["knots"],
        )
    return MinimumEnergySpline(q, t, penalty=p["penalty"], resolution=p["resolution"])


#: Every method by name: ``Method`` records with the class, whether it interpolates, and its
#: parameters (type, default, help), shared by :func:`spline` and the command line.
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
        Method(
            "squad",
            "Shoemake's Squad, C¹ in time",
            True,
            "C1",
            {
                "ends": Param(str, "open", "open | rest | closed"),
                "holds": Param(flag, True, "equal consecutive keys hold still"),
            },
        ),
        Method(
            "catmull_rom",
            "Catmull–Rom (Gortler), C¹ in time",
            True,
            "C1",
            {
                "ends": Param(str, "reflect", "reflect | duplicate | rest | closed"),
                "alpha": Param(
                    float_or_none, None, "key spacing θ^α without times: 0, 0.5 centripetal, 1"
                ),
                "holds": Param(flag, True, "equal consecutive keys hold still"),
            },
        ),
        Method(
            "natural",
            "global C² spline (scipy RotationSpline's construction)",
            True,
            "C2",
            {
                "ends": Param(
                    str,
                    "natural",
                    "natural | clamped (= scipy's RotationSpline) | rest | closed",
                ),
                "holds": Param(flag, True, "equal consecutive keys hold still (C¹ there)"),
            },
        ),
        Method(
            "c3",
            "the patent's C³ spline",
            True,
            "C3",
            {
                "alpha": Param(
                    float_or_auto, 5 / 16, "shape parameter α (q', q'', q''' at keys) | auto"
                ),
                "beta": Param(
                    float_or_none, None, "shape parameter β (q''' at keys; default 0, −3 auto)"
                ),
                "variant": Param(str, "knot", "knot | patent"),
                "ends": Param(str, "open", "open | rest | closed"),
                "holds": Param(flag, True, "equal consecutive keys hold still"),
            },
        ),
        Method(
            "hermite",
            "keys with angular velocities (cubic Hermite on SO(3)), C¹",
            True,
            "C1",
            {
                "rates": Param(rates_spec, "bessel", "bessel | zero | FILE of N×3 rates"),
                "frame": Param(str, "body", "frame of rates from a file: world | body"),
                "ends": Param(str, "open", "open | rest | closed"),
                "holds": Param(flag, True, "equal consecutive keys hold still (zero rates)"),
            },
        ),
        Method(
            "kochanek_bartels",
            "Kochanek–Bartels (tension, continuity, bias), C¹ (C⁰ if continuity ≠ 0)",
            True,
            "C1",
            {
                "tension": Param(float, 0.0, "tension T (1: stop at keys)"),
                "continuity": Param(float, 0.0, "continuity C (≠ 0: a corner at keys)"),
                "bias": Param(float, 0.0, "bias B (−1 … 1: towards the next / previous key)"),
                "alpha": Param(
                    float_or_none, None, "key spacing θ^α without times: 0, 0.5 centripetal, 1"
                ),
                "ends": Param(str, "reflect", "reflect | duplicate | rest | closed"),
                "holds": Param(flag, True, "equal consecutive keys hold still"),
            },
        ),
        Method("bezier", "one spherical Bézier curve over all keys", False, "C∞ (one curve)", {}),
        Method("cumulative_bezier", "one cumulative Bézier curve over all keys", False, "C∞", {}),
        Method(
            "bspline",
            "cumulative cubic B-spline with the keys as control points",
            False,
            "C2",
            {
                "order": Param(int, 4, "spline order (4 = cubic)"),
                "ends": Param(str, "open", "open | rest (end keys tripled) | closed"),
                "holds": Param(flag, False, "runs of equal keys repeated: exactly constant"),
            },
        ),
        Method(
            "nonuniform_bspline",
            "cumulative cubic B-spline, keys as control points, joints at the key times",
            False,
            "C2",
            {},
        ),
        Method(
            "fit",
            "least-squares fitting spline on SO(3) with a roughness penalty (noisy data)",
            False,
            "C2 (C4 with penalty=jerk)",
            {
                "smoothing": Param(smoothing_spec, "auto", "λ: auto (GCV) | a number ≥ 0"),
                "penalty": Param(str, "acceleration", "acceleration | jerk | auto (GCV picks)"),
                "robust": Param(str_or_none, None, "none | huber | cauchy"),
                "knots": Param(float_or_none, None, "knot spacing (default: the data rate)"),
            },
        ),
        Method(
            "min_energy",
            "minimum-energy interpolating spline (least ∫|ω̇|² or ∫|ω̈|² through the keys)",
            True,
            "C2 (C4 with penalty=jerk)",
            {
                "penalty": Param(str, "acceleration", "acceleration | jerk"),
                "resolution": Param(
                    int_or_none,
                    None,
                    "bubble polynomials (acceleration, default 4) or knot intervals (jerk, "
                    "default 8) per key interval",
                ),
            },
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
    """Names of the methods that pass through their keys, in registry order.

    Examples
    --------
    >>> from quatspline.registry import interpolating_methods
    >>> "c3" in interpolating_methods(), "bspline" in interpolating_methods()
    (True, False)
    """
    return [m.name for m in METHODS.values() if m.interpolating]


def spline(
    method: str, quats: ArrayLike, times: ArrayLike | None = None, **params: object
) -> sp.Spline:
    """Any method by name, through keys at times.

    Parameters
    ----------
    method : str
        A name of :data:`METHODS`: ``slerp``, ``nlerp``, ``lin_euler``, ``lin_mat``,
        ``squad``, ``catmull_rom``, ``natural``, ``c3``, ``min_energy`` (interpolating), or
        ``bezier``, ``cumulative_bezier``, ``bspline``, ``beta`` (approximating; fitted to keys
        at times as the module documentation describes), or ``fit`` (least squares through
        noisy samples, :func:`quatspline.fit`).
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z) or a scipy ``Rotation``.
    times : array_like, shape (N,), optional
        Strictly increasing key times (default 0 … N−1); pandas/numpy datetimes become
        seconds.
    **params
        The method's parameters (e.g. ``alpha``, ``beta`` for ``c3``; ``ends`` for
        ``natural``), converted to their declared types.

    Returns
    -------
    Spline

    Raises
    ------
    ValueError
        If the method or a parameter is unknown (the message lists the valid ones), a
        parameter has the wrong type, or the keys or times are invalid.

    See Also
    --------
    METHODS : the table of methods and parameters.

    Examples
    --------
    >>> import quatspline as qs
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [0, 90, 90]], degrees=True)
    >>> s = qs.spline("c3", keys, [0.0, 1.0, 3.0], alpha=0.5)
    >>> type(s).__name__, s.domain
    ('C3Spline', (0.0, 3.0))
    >>> qs.spline("cubic", keys)
    Traceback (most recent call last):
    ...
    ValueError: method: unknown method 'cubic'; valid: slerp, nlerp, ...
    """
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
            raise ValueError(f"{name}: expected {_expects(spec.type)}, got {v!r}") from None
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
        from .splines.screw import ScrewSpline

        return ScrewSpline(quats, times, positions, smooth=method == "screw_smooth")
    from .splines.pose_bspline import PoseBSpline

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
