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

Each row of :data:`METHODS` carries everything its readers need: the builder and every
parameter with its converter, default, help, choices and range check. ``quatspline.spline``,
the operations, the command line and the viewer read the rows, so a new method is one class
plus one row. The registry checks the parameters against the row before building and raises
:class:`~quatspline.ops.ParameterError` itself for an unknown method or parameter or a value
the method does not accept; an error of the keys or times stays a plain ``ValueError``.

>>> from quatspline.registry import METHODS
>>> ends = METHODS["squad"].params["ends"]
>>> ends.default, ends.choices, ends.kind
('open', ('open', 'rest', 'closed'), 'str')
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._util.arrays import as_real, with_width
from ._util.errors import ParameterError
from ._util.options import parse_smoothing
from .core.algebra import conjugate, multiply, normalize
from .fitting import MinimumEnergySpline, fit
from .io._common import open_regular
from .splines import (
    BetaSpline,
    C3Spline,
    CatmullRom,
    CumulativeBezier,
    CumulativeBSpline,
    Hermite,
    KochanekBartels,
    NaturalSpline,
    PiecewiseLinEuler,
    PiecewiseLinMat,
    PiecewiseNlerp,
    PiecewiseSlerp,
    PoseBSpline,
    ScrewSpline,
    SphericalBezier,
    Spline,
    Squad,
)
from .splines.keys import bessel_rates, bspline_controls, bspline_hold_intervals

__all__ = [
    "EULER_SEQUENCES",
    "METHODS",
    "POSE_METHODS",
    "Method",
    "Param",
    "ParameterError",
    "interpolating_methods",
    "pose_spline",
    "spline",
]

#: The Euler sequences of ``lin_euler`` (scipy's convention: lower case extrinsic, upper case
#: intrinsic), in the core's order.
EULER_SEQUENCES = tuple(
    s
    for case in (str.lower, str.upper)
    for s in map(
        case, ("xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz")
    )
)
#: The core's bound on a shape parameter (tension, α, β, β₁, …): |value| ≤ 1e6.
SHAPE_RANGE = 1e6


# ---- parameter converters: a Python value or a command-line string → the parameter's value ---
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


def smoothing_spec(v):
    """λ of ``fit``: "auto" or a number ≥ 0 (CLI strings converted), read by the one parser
    of λ (:func:`quatspline._util.options.parse_smoothing`)."""
    return parse_smoothing(v)


def str_or_none(v):
    """A string, or None for None / "none"."""
    if v is None or (isinstance(v, str) and v.strip().lower() == "none"):
        return None
    return str(v)


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


#: What each converter accepts, in words (for messages), and the control a user interface
#: shows for it.
_EXPECTS = {
    float: ("a number", "float"),
    int: ("an integer", "int"),
    str: ("a string", "str"),
    float_or_none: ("a number or none", "float"),
    float_or_auto: ("a number or 'auto'", "float"),
    int_or_none: ("an integer or none", "int"),
    flag: ("true or false", "bool"),
    smoothing_spec: ("'auto' or a number ≥ 0", "str"),
    str_or_none: ("a string or none", "str"),
    rates_spec: ("'bessel', 'zero', a file of N×3 rates or an (N, 3) array", "str"),
}


# ---- parameter checks: check(name, value, params) raises ParameterError --------------------
def _display(x: float) -> str:
    """A number as the core prints it in messages (``1000000000``, ``-0.5``, ``NaN``)."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return np.format_float_positional(x, trim="-")


def _short(x: float) -> str:
    """A number as the core's short form prints it (exponent outside 1e-4 … 1e15)."""
    if x == 0 or not math.isfinite(x) or 1e-4 <= abs(x) < 1e15:
        return _display(x)
    return np.format_float_scientific(x, trim="-", exp_digits=1).replace("+", "")


def _shape(name, v, p) -> None:
    """A shape parameter: finite and within :data:`SHAPE_RANGE` (``None``/"auto" pass)."""
    if v is None or isinstance(v, str):
        return
    if not math.isfinite(v):
        raise ParameterError(f"{name}: non-finite value (NaN or inf) at element 0")
    if abs(v) > SHAPE_RANGE:
        raise ParameterError(
            f"{name}: {name}[0] = {_short(v)} is beyond the supported range |{name}| ≤ 1e6"
        )


def _positive_shape(name, v, p) -> None:
    _shape(name, v, p)
    if not v > 0:
        raise ParameterError(f"{name}: {name}[0] = {_short(v)} must be > 0")


def _unit_interval(name, v, p) -> None:
    if v is not None and not 0 <= v <= 1:
        raise ParameterError(f"{name}: expected a value in [0, 1], got {v!r}")


def _bspline_order(name, v, p) -> None:
    if v != 4:
        raise ParameterError("order: the registry's bspline spans the keys with order 4 only")


def _smoothing(name, v, p) -> None:
    if not isinstance(v, str) and not (math.isfinite(v) and v >= 0):
        raise ParameterError(f"{name}: expected 'auto' or a finite λ ≥ 0, got {v:.6g}")


def _spacing(name, v, p) -> None:
    if v is not None and not (math.isfinite(v) and v > 0):
        raise ParameterError(f"{name}: expected a finite positive spacing, got {_short(v)}")


def _resolution(name, v, p) -> None:
    lo, hi = (0, 16) if p.get("penalty") == "acceleration" else (1, 64)
    if v is not None and not lo <= v <= hi:
        raise ParameterError(f"{name}: expected an integer from {lo} to {hi}, got {v}")


@dataclass(frozen=True)
class Param:
    """One parameter of a method: its converter (a Python value or a command-line string →
    the value), default, help, the strings it may take (``choices``, offered by user
    interfaces; ``aliases`` are accepted too but not offered; None: any value of its kind)
    and an optional ``check(name, value, params)`` of the converted value that raises
    :class:`ParameterError`."""

    type: Callable
    default: object
    help: str
    choices: tuple[str, ...] | None = None
    check: Callable | None = None
    aliases: tuple[str, ...] = ()

    @property
    def kind(self) -> str:
        """The control a user interface shows: ``"float"``, ``"int"``, ``"bool"`` or ``"str"``."""
        known = _EXPECTS.get(self.type)
        if known is not None:
            return known[1]
        return "bool" if isinstance(self.default, bool) else "str"

    @property
    def expects(self) -> str:
        """What the parameter accepts, in words (for messages)."""
        known = _EXPECTS.get(self.type)
        return known[0] if known is not None else getattr(self.type, "__name__", "a value")

    def convert(self, name: str, v):
        """``v`` converted to the parameter's type (a :class:`ParameterError` naming it)."""
        try:
            return self.type(v)
        except ParameterError:
            raise  # a shared option parser's own message (it names the option)
        except (TypeError, ValueError):
            raise ParameterError(f"{name}: expected {self.expects}, got {v!r}") from None

    def validate(self, name: str, method: str, v, params: dict) -> None:
        """A converted value against the choices (``None`` stands for ``"none"``) and the
        check; a :class:`ParameterError` naming the parameter otherwise."""
        shown = "none" if v is None else v
        if (
            self.choices is not None
            and isinstance(shown, str)
            and shown not in self.choices
            and shown not in self.aliases
        ):
            raise ParameterError(
                f"{name}: {method} does not support {json.dumps(shown, ensure_ascii=False)}; "
                f"supported: {', '.join(self.choices)}"
            )
        if self.check is not None:
            self.check(name, v, params)


@dataclass(frozen=True)
class Method:
    """One method: its name, a one-line summary, whether it passes through its keys, its
    guaranteed continuity, its parameters by name and its builder ``build(quats, times,
    params)`` (``build(quats, times, positions, params)`` for a pose method), called with
    the keys checked and the parameters converted and checked."""

    name: str
    summary: str
    interpolating: bool
    continuity: str
    params: dict = field(default_factory=dict)
    build: Callable | None = None

    def resolve(self, params: dict) -> dict:
        """Every parameter of the method, from ``params`` or its default, converted and
        checked (a :class:`ParameterError` names an unknown or bad one)."""
        unknown = sorted(set(params) - set(self.params))
        if unknown:
            valid = ", ".join(self.params) or "none"
            raise ParameterError(f"{unknown[0]}: unknown parameter of {self.name}; valid: {valid}")
        p = {
            name: spec.convert(name, params.get(name, spec.default))
            for name, spec in self.params.items()
        }
        for name, spec in self.params.items():
            spec.validate(name, self.name, p[name], p)
        return p


# ---- builders: one per method, from keys at times and converted parameters ------------------
def _pad(q):
    q = np.asarray(q, dtype=float)
    return np.vstack([q[:1], q, q[-1:]])


def _times_or_default(times, n):
    return np.arange(n, dtype=float) if times is None else as_real(times, "times")


def _key_times(q, times) -> np.ndarray:
    """The key times of an approximating method (only their ends, and for bspline their mean
    spacing, are used), checked as strictly as for every other method: one per key, finite,
    strictly increasing, in range."""
    t = _times_or_default(times, len(q))
    if t.ndim != 1 or len(t) != len(q):
        raise ValueError(f"times: expected {len(q)} times (one per key), got shape {t.shape}")
    _core.check_times(np.ascontiguousarray(t), len(q))
    return t


def _loop_times(q, times, p):
    """Times for a closed loop from N keys at N times (see the module doc)."""
    if times is None or p.get("ends") != "closed":
        return times
    t = np.asarray(times, dtype=float)
    q = np.asarray(q, dtype=float)
    if t.ndim != 1 or len(t) != len(q) or len(t) < 2:
        return times
    d = multiply(conjugate(normalize(q[0])), normalize(q[-1]))
    if 2 * np.arctan2(np.linalg.norm(d[1:]), abs(d[0])) <= 1e-12:
        return times
    return np.r_[t, t[-1] + (t[-1] - t[0]) / (len(t) - 1)]


def _hermite(q, times, p):
    r = p["rates"]
    if isinstance(r, str):
        q = np.asarray(q, dtype=float)
        r = bessel_rates(q, times) if r == "bessel" else np.zeros((len(q), 3))
        frame = "body"
    else:
        frame = p["frame"]
    return Hermite(q, times, angular_velocity=r, frame=frame, ends=p["ends"], holds=p["holds"])


def _kochanek_bartels(q, times, p):
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


def _c3(q, times, p):
    return C3Spline(
        q,
        times,
        alpha=p["alpha"],
        beta=p["beta"],
        variant=p["variant"],
        ends=p["ends"],
        holds=p["holds"],
    )


def _closed_bspline(q, times, p):
    """The closed cubic B-spline with the keys as control points, spanning the loop's times
    (a closing key equal to the first is dropped, as for the interpolating methods)."""
    q = np.asarray(q, dtype=float)
    t = np.arange(len(q) + 1, dtype=float) if times is None else np.asarray(times, dtype=float)
    if len(t) == len(q):  # the last key is the closing key (see _loop_times)
        q = q[:-1]
    if t.ndim != 1 or len(t) != len(q) + 1:
        raise ValueError(f"times: a closed curve expects {len(q) + 1} times, got {t.shape}")
    if p.get("holds"):
        return _held_bspline(q, "closed", t[0], t[-1])
    return CumulativeBSpline(q, dt=(t[-1] - t[0]) / len(q), t0=t[0], order=4, ends="closed")


def _held_bspline(q, ends, t0, t1):
    """The registry's cubic B-spline with holds: runs of equal keys repeated (see
    ``splines.keys.bspline_controls``), the end keys padded as without holds, the segments spread
    over [t0, t1]; ``hold_intervals`` set."""
    c = bspline_controls(
        np.asarray(q, dtype=float), 4, "closed" if ends == "closed" else "open", True
    )
    if ends != "closed":
        c = _pad(_pad(c)) if ends == "rest" else _pad(c)
    segs = len(c) if ends == "closed" else len(c) - 3
    dt = (t1 - t0) / segs
    s = CumulativeBSpline(c, dt=dt, t0=t0, order=4, ends="closed" if ends == "closed" else "open")
    s.hold_intervals = bspline_hold_intervals(c, 4, ends == "closed", dt, t0)
    return s


def _one_curve(cls):
    """The builder of one curve with the keys as control points over [t₀, t_last]."""

    def build(q, times, p):
        t = _key_times(q, times)
        return cls(q, domain=(t[0], t[-1]))

    return build


def _bspline(q, times, p):
    if p["ends"] == "closed":
        return _closed_bspline(q, times, p)
    t = _key_times(q, times)
    if p["holds"]:
        return _held_bspline(q, p["ends"], t[0], t[-1])
    if p["ends"] == "rest":
        # end keys tripled: zero angular velocity and acceleration at both ends
        qq = _pad(_pad(q))
        return CumulativeBSpline(qq, dt=(t[-1] - t[0]) / (len(q) + 1), t0=t[0], order=4)
    return CumulativeBSpline(_pad(q), dt=(t[-1] - t[0]) / (len(q) - 1), t0=t[0], order=4)


def _nonuniform_bspline(q, times, p):
    # keys as control points (ends doubled), joints at the key times, end knots extended by
    # the end spacings: simple knots, C², non-uniform times respected
    t = _key_times(q, times)
    h0, h1 = t[1] - t[0], t[-1] - t[-2]
    knots = np.concatenate([t[0] - h0 * np.arange(3, 0, -1), t, t[-1] + h1 * np.arange(1, 4)])
    return CumulativeBSpline(_pad(q), knots=knots, order=4)


def _beta(q, times, p):
    t = _key_times(q, times)
    return BetaSpline(_pad(q), beta1=p["beta1"], beta2=p["beta2"], times=t)


def _knot_spacing(spacing, t) -> None:
    """The fit's knot spacing against the span of valid sample times (as the fit lays its
    knots out): no longer than the span, at most 5e7 knot intervals."""
    if spacing is None or t.ndim != 1 or len(t) < 2 or not np.all(np.diff(t) > 0):
        return  # bad times: the fit's own error names them
    span = float(t[-1] - t[0])
    if spacing > span:
        raise ParameterError(
            f"knots: spacing {_short(spacing)} exceeds the data's time span {_short(span)}"
        )
    intervals = max(math.floor(span / spacing + 0.5), 1.0)  # Rust's round
    if intervals > 5e7:
        shown = np.format_float_scientific(intervals, trim="-", exp_digits=1).replace("+", "")
        raise ParameterError(
            f"knots: spacing {_short(spacing)} gives {shown} knot intervals (limit 5e7)"
        )


def _fit(q, times, p):
    t = _times_or_default(times, len(q))
    _knot_spacing(p["knots"], t)
    return fit(
        t,
        q,
        smoothing=p["smoothing"],
        penalty=p["penalty"],
        robust=p["robust"],
        knots=p["knots"],
    )


def _min_energy(q, times, p):
    t = _times_or_default(times, len(q))
    return MinimumEnergySpline(
        q, t, penalty=p["penalty"], resolution=p["resolution"], mode=p["mode"]
    )


_HOLDS = Param(flag, True, "equal consecutive keys hold still")
_OPEN_ENDS = ("open", "rest", "closed")
_REFLECT_ENDS = ("reflect", "duplicate", "rest", "closed")
# "open" is the core's other name of "reflect"
_REFLECT = Param(
    str, "reflect", "reflect | duplicate | rest | closed", _REFLECT_ENDS, aliases=("open",)
)
_ALPHA = Param(
    float_or_none,
    None,
    "key spacing θ^α without times: 0, 0.5 centripetal, 1",
    check=_unit_interval,
)

#: Every method by name: ``Method`` records with whether it interpolates, its continuity, its
#: parameters (converter, default, help, choices, check) and its builder, read by
#: :func:`spline`, the command line, the viewer and the documentation.
METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method("slerp", "piecewise slerp", True, "C0", {}, lambda q, t, p: PiecewiseSlerp(q, t)),
        Method(
            "nlerp",
            "piecewise normalised lerp (baseline)",
            True,
            "C0",
            {},
            lambda q, t, p: PiecewiseNlerp(q, t),
        ),
        Method(
            "lin_euler",
            "Euler angles lerped (baseline)",
            True,
            "C0",
            {"seq": Param(str, "xyz", "Euler sequence, scipy's convention", EULER_SEQUENCES)},
            lambda q, t, p: PiecewiseLinEuler(q, t, seq=p["seq"]),
        ),
        Method(
            "lin_mat",
            "matrices lerped and projected (baseline)",
            True,
            "C0",
            {},
            lambda q, t, p: PiecewiseLinMat(q, t),
        ),
        Method(
            "squad",
            "Shoemake's Squad, C¹ in time",
            True,
            "C1",
            {"ends": Param(str, "open", "open | rest | closed", _OPEN_ENDS), "holds": _HOLDS},
            lambda q, t, p: Squad(q, t, ends=p["ends"], holds=p["holds"]),
        ),
        Method(
            "catmull_rom",
            "Catmull–Rom (Gortler), C¹ in time",
            True,
            "C1",
            {
                "ends": _REFLECT,
                "alpha": _ALPHA,
                "holds": _HOLDS,
            },
            lambda q, t, p: CatmullRom(q, t, ends=p["ends"], alpha=p["alpha"], holds=p["holds"]),
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
                    ("natural", "clamped", "rest", "closed"),
                ),
                "holds": Param(flag, True, "equal consecutive keys hold still (C¹ there)"),
            },
            lambda q, t, p: NaturalSpline(q, t, ends=p["ends"], holds=p["holds"]),
        ),
        Method(
            "c3",
            "the patent's C³ spline",
            True,
            "C3",
            {
                "alpha": Param(
                    float_or_auto,
                    5 / 16,
                    "shape parameter α (q', q'', q''' at keys) | auto",
                    check=_shape,
                ),
                "beta": Param(
                    float_or_none,
                    None,
                    "shape parameter β (q''' at keys; default 0, −3 auto)",
                    check=_shape,
                ),
                "variant": Param(str, "knot", "knot | patent", ("knot", "patent")),
                "ends": Param(str, "open", "open | rest | closed", _OPEN_ENDS),
                "holds": _HOLDS,
            },
            _c3,
        ),
        Method(
            "hermite",
            "keys with angular velocities (cubic Hermite on SO(3)), C¹",
            True,
            "C1",
            {
                # the named estimates; a file or an (N, 3) array is accepted too
                "rates": Param(
                    rates_spec, "bessel", "bessel | zero | FILE of N×3 rates", ("bessel", "zero")
                ),
                "frame": Param(
                    str, "body", "frame of rates from a file: world | body", ("world", "body")
                ),
                "ends": Param(str, "open", "open | rest | closed", _OPEN_ENDS),
                "holds": Param(flag, True, "equal consecutive keys hold still (zero rates)"),
            },
            _hermite,
        ),
        Method(
            "kochanek_bartels",
            "Kochanek–Bartels (tension, continuity, bias), C¹ (C⁰ if continuity ≠ 0)",
            True,
            "C1",
            {
                "tension": Param(float, 0.0, "tension T (1: stop at keys)", check=_shape),
                "continuity": Param(
                    float, 0.0, "continuity C (≠ 0: a corner at keys)", check=_shape
                ),
                "bias": Param(
                    float, 0.0, "bias B (−1 … 1: towards the next / previous key)", check=_shape
                ),
                "alpha": _ALPHA,
                "ends": _REFLECT,
                "holds": _HOLDS,
            },
            _kochanek_bartels,
        ),
        Method(
            "bezier",
            "one spherical Bézier curve over all keys",
            False,
            "C∞ (one curve)",
            {},
            _one_curve(SphericalBezier),
        ),
        Method(
            "cumulative_bezier",
            "one cumulative Bézier curve over all keys",
            False,
            "C∞",
            {},
            _one_curve(CumulativeBezier),
        ),
        Method(
            "bspline",
            "cumulative cubic B-spline with the keys as control points",
            False,
            "C2",
            {
                "order": Param(int, 4, "spline order (4 = cubic)", check=_bspline_order),
                "ends": Param(str, "open", "open | rest (end keys tripled) | closed", _OPEN_ENDS),
                "holds": Param(flag, False, "runs of equal keys repeated: exactly constant"),
            },
            _bspline,
        ),
        Method(
            "nonuniform_bspline",
            "cumulative cubic B-spline, keys as control points, joints at the key times",
            False,
            "C2",
            {},
            _nonuniform_bspline,
        ),
        Method(
            "fit",
            "least-squares fitting spline on SO(3) with a roughness penalty (noisy data)",
            False,
            "C2 (C4 with penalty=jerk)",
            {
                "smoothing": Param(
                    smoothing_spec,
                    "auto",
                    "λ: auto | gcv | adaptive | a number ≥ 0",
                    check=_smoothing,
                ),
                "penalty": Param(
                    str,
                    "acceleration",
                    "acceleration | jerk | auto (GCV picks)",
                    ("acceleration", "jerk", "auto"),
                ),
                "robust": Param(
                    str_or_none, None, "none | huber | cauchy", ("none", "huber", "cauchy")
                ),
                "knots": Param(
                    float_or_none,
                    None,
                    "knot spacing (default: the data rate)",
                    check=_spacing,
                ),
            },
            _fit,
        ),
        Method(
            "min_energy",
            "minimum-energy interpolating spline (least ∫|ω̇|² or ∫|ω̈|² through the keys)",
            True,
            "C2 (C4 with penalty=jerk)",
            {
                "penalty": Param(
                    str, "acceleration", "acceleration | jerk", ("acceleration", "jerk")
                ),
                "resolution": Param(
                    int_or_none,
                    None,
                    "bubble polynomials (acceleration, default 4) or knot intervals (jerk, "
                    "default 8) per key interval",
                    check=_resolution,
                ),
                "mode": Param(
                    str,
                    "discrete",
                    "discrete (over `resolution` bubbles) | exact (the Riemannian cubic)",
                    ("discrete", "exact"),
                ),
            },
            _min_energy,
        ),
        Method(
            "beta",
            "Beta quaternion spline with the keys as vertices",
            False,
            "G1",
            {
                "beta1": Param(float, 1.0, "shape parameter β₁ > 0 (bias)", check=_positive_shape),
                "beta2": Param(float, 0.0, "shape parameter β₂ (tension)", check=_shape),
            },
            _beta,
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


def _method(table: dict, method, what: str = "method") -> Method:
    if not isinstance(method, str):
        raise TypeError(f"method: expected a str, got {type(method).__name__}")
    if method not in table:
        raise ParameterError(f"method: unknown {what} {method!r}; valid: {', '.join(table)}")
    return table[method]


def spline(
    method: str, quats: ArrayLike, times: ArrayLike | None = None, **params: object
) -> Spline:
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
    ParameterError
        (a ``ValueError``) If the method or a parameter is unknown (the message lists the
        valid ones), or a parameter's value is not one it accepts.
    TypeError
        If ``method`` is not a string.
    ValueError
        If the keys or times are invalid.

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
    quatspline.ops.ParameterError: method: unknown method 'cubic'; valid: slerp, ...
    """
    m = _method(METHODS, method)
    p = m.resolve(params)
    q = with_width(quats, "quats", 4)
    return m.build(q, _loop_times(q, times, p), p)


# ---- pose methods: splines of poses, built from keys at times -------------------------------
def _pose_bspline(quats, times, positions, p):
    q = np.asarray(quats, dtype=float)
    x = np.asarray(positions, dtype=float)
    t = _times_or_default(times, len(q))
    if len(t) < 2 or len(t) != len(q):
        raise ValueError(f"times: expected {len(q)} times (one per key, at least 2), got {len(t)}")
    h0, h1 = t[1] - t[0], t[-1] - t[-2]
    knots = np.concatenate([t[0] - h0 * np.arange(3, 0, -1), t, t[-1] + h1 * np.arange(1, 4)])
    return PoseBSpline(_pad(q), _pad(x), knots=knots, order=4, formulation=p["formulation"])


POSE_METHODS: dict[str, Method] = {
    m.name: m
    for m in [
        Method(
            "screw",
            "piecewise ScLerp (constant screw per segment)",
            True,
            "C0",
            {},
            lambda q, t, x, p: ScrewSpline(q, t, x, smooth=False),
        ),
        Method(
            "screw_smooth",
            "C³ cumulative screw spline (the c3 weights on SE(3))",
            True,
            "C3",
            {},
            lambda q, t, x, p: ScrewSpline(q, t, x, smooth=True),
        ),
        Method(
            "pose_bspline",
            "cumulative cubic B-spline on SE(3), keys as control poses, joints at key times",
            False,
            "C2",
            {"formulation": Param(str, "se3", "se3 | split", ("se3", "split"))},
            _pose_bspline,
        ),
    ]
}


def pose_spline(method: str, quats, times, positions, **params):
    """Builds the pose method ``method`` (see ``POSE_METHODS``) through pose keys at times;
    unknown names and parameters raise a :class:`ParameterError` listing the valid ones."""
    m = _method(POSE_METHODS, method, "pose method")
    return m.build(quats, times, positions, m.resolve(params))
