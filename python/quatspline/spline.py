"""Keyframe splines behind one interface: ``quatspline.Spline``.

Every spline maps time to unit quaternions (w, x, y, z) and gives exact time derivatives —
q', q'', q''' and the angular velocity, acceleration and jerk in the world or body frame — by
Taylor-mode differentiation of the same formula in the Rust core (never finite differences).

| class | interpolates | continuity | source |
|---|---|---|---|
| ``PiecewiseSlerp`` | yes | C⁰ | seeds 001/003 |
| ``PiecewiseNlerp``, ``…LinEuler``, ``…LinMat`` | yes | C⁰ | baselines, seeds 001/002 |
| ``SphericalBezier`` | end points | C^∞ (one curve) | Shoemake 1985 (de Casteljau) |
| ``CumulativeBezier`` | end points | C^∞ (one curve) | Kim, Kim & Shin 1995 |
| ``Squad`` | yes | C¹ | Shoemake 1987, seed 003 |
| ``CatmullRom`` | yes | C¹ | Gortler ch. 9, seed 002 |
| ``CumulativeBSpline`` | no | C^(k−2) (C² cubic) | Kim et al. 1995, Sommer et al. 2020 |
| ``NaturalSpline`` | yes | C² (global) | seed 002 §9.4; scipy ``RotationSpline`` |
| ``BetaSpline`` | no | G¹ (not G² in general) | seed 000 (Beta quaternion spline) |
| ``C3Spline`` | yes | C³ | seed 004 (patent) |
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._arrays import as_real, as_times, with_width

__all__ = [
    "BetaSpline",
    "C3Spline",
    "CatmullRom",
    "CumulativeBSpline",
    "CumulativeBezier",
    "NaturalSpline",
    "PiecewiseLinEuler",
    "PiecewiseLinMat",
    "PiecewiseNlerp",
    "PiecewiseSlerp",
    "Spline",
    "SphericalBezier",
    "Squad",
    "path_length",
    "reparameterize",
]

_FRAMES = ("world", "body")
# scipy's RotationSpline(t, order) returns body-frame rates; ours takes an output array there.
_ORDER_HINT = (
    "{name}(t, {order}): the second argument is `out`, an output array, not scipy's derivative "
    "order; for RotationSpline(t, 1) / (t, 2) use s.angular_velocity(t, frame='body') / "
    "s.angular_acceleration(t, frame='body'), for the quaternion's derivative "
    "s.derivative(t, {order})"
)
_EXTRAPOLATE = ("raise", "clamp")


def _keys(q, name: str) -> np.ndarray:
    a = with_width(q, name, 4)
    if a.ndim != 2:
        raise ValueError(f"{name}: expected shape (N, 4), got {a.shape}")
    return a


def _times(times, n: int):
    if times is None:
        return None
    t = as_times(times, "times")
    if t.ndim != 1:
        raise ValueError(f"times: expected shape ({n},), got {t.shape}")
    return np.ascontiguousarray(t)


class Spline:
    """One interface for every curve: call it for orientations, ask it for derivatives.

    ``s(t)`` → (M, 4) for an array of times (any shape: the result has shape t.shape + (4,)),
    (4,) for a scalar. Times outside ``s.domain`` raise ``ValueError`` unless the spline was
    made with ``extrapolate="clamp"``, which holds the end orientation (zero derivatives).
    Times need not be sorted.
    """

    def __init__(self, core: _core.Spline, extrapolate: str = "raise", **params):
        if extrapolate not in _EXTRAPOLATE:
            raise ValueError(f"extrapolate: expected one of {_EXTRAPOLATE}, got {extrapolate!r}")
        self._core = core
        self.extrapolate = extrapolate
        self.params = params

    # ---- description ------------------------------------------------------------------
    @property
    def method(self) -> str:
        """The method's registry name."""
        return self._core.name

    @property
    def domain(self) -> tuple[float, float]:
        """(t_start, t_end)."""
        return self._core.domain

    @property
    def joints(self) -> np.ndarray:
        """Times of the segment joints, both ends included."""
        return np.array(self._core.joints)

    @property
    def interpolates(self) -> bool:
        """Whether the curve passes through its keys at the joints."""
        return self._core.interpolates

    @property
    def continuity(self) -> int | float:
        """The parametric continuity order in time guaranteed at interior joints."""
        c = self._core.continuity
        return float("inf") if c == 255 else c

    def __repr__(self) -> str:
        a, b = self.domain
        return f"{type(self).__name__}(segments={len(self.joints) - 1}, domain=[{a:g}, {b:g}])"

    # ---- evaluation -------------------------------------------------------------------
    def _eval(self, t, order: int):
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        out = self._core.evaluate(flat, order, self.extrapolate == "clamp")
        return ta.shape, out

    def __call__(self, t, out: np.ndarray | None = None) -> np.ndarray:
        """Orientations at t; with ``out`` (float64, C-contiguous, shape t.shape + (4,)) the
        result is written there (no allocation) and ``out`` is returned."""
        if out is None:
            shape, res = self._eval(t, 0)
            return res.reshape((*shape, 4))
        if isinstance(out, (int, np.integer)) and not isinstance(out, bool):
            raise TypeError(_ORDER_HINT.format(order=int(out), name=type(self).__name__))
        ta = as_times(t, "t")
        want = (*ta.shape, 4)
        if not isinstance(out, np.ndarray) or out.dtype != np.float64:
            raise ValueError(
                f"out: expected a float64 numpy array, got {getattr(out, 'dtype', type(out))}"
            )
        if out.shape != want:
            raise ValueError(f"out: expected shape {want}, got {out.shape}")
        if not out.flags.c_contiguous or not out.flags.writeable:
            raise ValueError("out: expected a writeable C-contiguous array")
        flat = np.ascontiguousarray(ta.reshape(-1))
        self._core.evaluate_out(flat, 0, self.extrapolate == "clamp", out.reshape(-1, 4))
        return out

    def derivative(self, t, order: int = 1) -> np.ndarray:
        """The order-th time derivative of q (order 0…3) as quaternions, shape t.shape + (4,)."""
        if order not in (0, 1, 2, 3):
            raise ValueError(f"order: expected 0, 1, 2 or 3, got {order!r}")
        shape, out = self._eval(t, order)
        return out[:, 4 * order :].reshape((*shape, 4))

    def derivatives(self, t, order: int = 3) -> np.ndarray:
        """q, q', …, q^(order) stacked: shape t.shape + (order + 1, 4)."""
        if order not in (0, 1, 2, 3):
            raise ValueError(f"order: expected 0, 1, 2 or 3, got {order!r}")
        shape, out = self._eval(t, order)
        return out.reshape((*shape, order + 1, 4))

    def _angular(self, t, order: int, frame: str) -> np.ndarray:
        if frame not in _FRAMES:
            raise ValueError(f"frame: expected one of {_FRAMES}, got {frame!r}")
        ta = as_times(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        out = self._core.angular(flat, order, frame == "body", self.extrapolate == "clamp")
        return out.reshape((*ta.shape, 3))

    def angular_velocity(self, t, frame: str = "world") -> np.ndarray:
        """ω (rad per time unit): world 2 q' q*, body 2 q* q' (vector parts)."""
        return self._angular(t, 1, frame)

    def angular_acceleration(self, t, frame: str = "world") -> np.ndarray:
        """dω/dt: world 2 vec(q'' q*), body 2 vec(q* q'')."""
        return self._angular(t, 2, frame)

    def jerk(self, t, frame: str = "world") -> np.ndarray:
        """d²ω/dt²: world 2 vec(q''' q* + q'' q'*), body 2 vec(q'* q'' + q* q''')."""
        return self._angular(t, 3, frame)

    def segment_derivatives(self, segment: int, t: float) -> np.ndarray:
        """(4, 4): q, q', q'', q''' of one segment's formula at t (one-sided limits at joints)."""
        return self._core.segment_derivatives(int(segment), float(t))

    def sample(self, n: int | None = None, rate: float | None = None):
        """Evenly spaced samples over the domain: ``n`` samples or ``rate`` per time unit.

        Returns (times (M,), quats (M, 4)).
        """
        a, b = self.domain
        if (n is None) == (rate is None):
            raise ValueError("sample: give exactly one of n or rate")
        if n is not None:
            if int(n) < 1:
                raise ValueError(f"n: expected at least 1 sample, got {n}")
            t = np.linspace(a, b, int(n))
        else:
            if not (np.isfinite(rate) and rate > 0):
                raise ValueError(f"rate: expected a finite positive rate, got {rate}")
            t = a + np.arange(int(np.floor((b - a) * rate + 1e-9)) + 1) / rate
        return t, self(t)


class PiecewiseNlerp(Spline):
    """Baseline: normalised lerp between consecutive keys (C⁰, non-constant speed)."""

    def __init__(self, quats, times=None, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(_core.nlerp_spline(q, t), extrapolate, quats=q, times=t)


class PiecewiseLinEuler(Spline):
    """Baseline: Euler angles (sequence ``seq``) lerped between keys (C⁰)."""

    def __init__(self, quats, times=None, seq: str = "xyz", extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.lin_euler_spline(q, t, str(seq)), extrapolate, quats=q, times=t, seq=seq
        )


class PiecewiseLinMat(Spline):
    """Baseline: rotation matrices lerped and projected back to SO(3) (C⁰)."""

    def __init__(self, quats, times=None, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(_core.lin_mat_spline(q, t), extrapolate, quats=q, times=t)


class PiecewiseSlerp(Spline):
    """Slerp between consecutive keys: C⁰, constant speed within each segment."""

    def __init__(self, quats, times=None, canonicalize: bool = True, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.piecewise_slerp(q, t, bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
        )


class SphericalBezier(Spline):
    """One spherical Bézier curve (de Casteljau with slerp) of any degree, on ``domain``
    (default [0, 1])."""

    def __init__(
        self,
        control_points,
        domain=(0.0, 1.0),
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(control_points, "control_points")
        d = (float(domain[0]), float(domain[1]))
        super().__init__(_core.spherical_bezier(q, d, bool(canonicalize)), extrapolate)


class CumulativeBezier(Spline):
    """One cumulative spherical Bézier curve (Kim–Kim–Shin) on [0, 1]; same end tangents as
    ``SphericalBezier`` with the same control points, a different curve in between."""

    def __init__(
        self,
        control_points,
        domain=(0.0, 1.0),
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(control_points, "control_points")
        d = (float(domain[0]), float(domain[1]))
        super().__init__(_core.cumulative_bezier(q, d, bool(canonicalize)), extrapolate)


class Squad(Spline):
    """Shoemake's Squad; non-uniform times get incoming/outgoing control points: C¹ in time."""

    def __init__(self, quats, times=None, canonicalize: bool = True, extrapolate: str = "raise"):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.squad(q, t, bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            canonicalize=canonicalize,
        )


class CatmullRom(Spline):
    """Catmull–Rom with spherical Bézier segments (Gortler): C¹ in time, also non-uniform.

    ``ends="reflect"`` (default) mirrors the missing end neighbours (two keys give slerp);
    ``ends="duplicate"`` repeats the end keys as in MATH.md §4.
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "reflect",
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.catmull_rom(q, t, str(ends), bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            canonicalize=canonicalize,
        )


class CumulativeBSpline(Spline):
    """Uniform cumulative B-spline of order k (cubic by default): C^(k−2), approximating.

    Segment i spans [t0 + i·dt, t0 + (i+1)·dt] with control rotations i … i+k−1, so the
    domain is [t0, t0 + (n − k + 1)·dt]. Non-uniform: ``knots=`` (n + k non-decreasing knots,
    domain [u_{k−1}, u_n]) or ``dt=[…]`` (the n + k − 1 knot spacings, u_{k−1} = t0) give
    the non-uniform cumulative B-spline (De Boor basis, see ``quatspline.bspline``).
    """

    def __init__(
        self,
        control_quats,
        dt: float = 1.0,
        t0: float = 0.0,
        order: int = 4,
        canonicalize: bool = True,
        extrapolate: str = "raise",
        knots=None,
    ):
        q = _keys(control_quats, "control_quats")
        if knots is not None or np.ndim(dt) != 0:
            # Non-uniform knots (explicit, or per-interval spacings): see bspline.py.
            from .bspline import _core_spline

            core = _core_spline(q, dt, t0, order, bool(canonicalize), knots)
            super().__init__(core, extrapolate)
            return
        super().__init__(
            _core.cumulative_bspline(q, float(dt), float(t0), int(order), bool(canonicalize)),
            extrapolate,
        )


class NaturalSpline(Spline):
    """The global interpolating C² spline (scipy ``RotationSpline``'s construction).

    ``ends="natural"``: zero angular acceleration at both ends. ``ends="clamped"``: body
    angular velocities ``start_rate``/``end_rate`` at the ends, by default the end segments'
    chord rates — which is exactly what scipy's ``RotationSpline`` does.
    """

    def __init__(
        self,
        quats,
        times=None,
        ends: str = "natural",
        start_rate=None,
        end_rate=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        rates = []
        for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
            if r is None:
                rates.append(None)
                continue
            v = as_real(r, name)
            if v.shape != (3,):
                raise ValueError(f"{name}: expected shape (3,), got {v.shape}")
            rates.append(tuple(float(x) for x in v))
        super().__init__(
            _core.natural_spline(q, t, str(ends), rates[0], rates[1], bool(canonicalize)),
            extrapolate,
            quats=q,
            times=t,
            ends=ends,
            start_rate=start_rate,
            end_rate=end_rate,
            canonicalize=canonicalize,
        )


def path_length(spline: Spline, per_segment: int = 8) -> float:
    """Total rotation angle ∫|ω| dt over the domain (radians), by Gauss–Legendre quadrature
    (8 nodes on each of ``per_segment`` pieces of every segment)."""
    x, w = np.polynomial.legendre.leggauss(8)
    j = spline.joints
    edges = np.concatenate(
        [np.linspace(a, b, per_segment + 1)[:-1] for a, b in zip(j[:-1], j[1:])] + [j[-1:]]
    )
    a, b = edges[:-1, None], edges[1:, None]
    t = (0.5 * (b - a) * x + 0.5 * (a + b)).ravel()
    speed = np.linalg.norm(spline.angular_velocity(t), axis=1).reshape(a.shape[0], -1)
    return float(np.sum(0.5 * (b - a) * speed * w))


def reparameterize(spline: Spline, kind: str = "angle") -> Spline:
    """The same method through the same keys, with key times re-spaced so each segment's
    duration is proportional to its rotation angle (seed 003), keeping the start and end
    times: angular speed becomes (near) constant across segments.

    Works for the interpolating methods made from keys and times (``PiecewiseSlerp``,
    ``Squad``, ``CatmullRom``, ``NaturalSpline``).

    ``kind="arc_length"`` works for ANY spline: the same path at exactly constant angular
    speed over the same domain, with exact derivatives (``quatspline.retime.arc_length``).
    """
    if kind == "arc_length":
        from .retime import arc_length

        return arc_length(spline)
    if kind != "angle":
        raise ValueError(f"kind: expected 'angle' or 'arc_length', got {kind!r}")
    if "quats" not in spline.params:
        raise ValueError(
            f"reparameterize: {type(spline).__name__} is not built from keys at times; "
            "angle reparameterisation needs an interpolating spline"
        )
    q = spline.params["quats"]
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    ang = 2 * np.arctan2(
        np.linalg.norm(q[1:] - q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
        np.linalg.norm(q[1:] + q[:-1] * np.sign(np.sum(q[1:] * q[:-1], axis=1))[:, None], axis=1),
    )
    a, b = spline.domain
    total = ang.sum()
    if total == 0:
        return spline
    share = np.maximum(ang, 1e-9 * total)
    times = a + (b - a) * np.concatenate([[0.0], np.cumsum(share) / share.sum()])
    times[-1] = b
    params = dict(spline.params, times=times)
    return type(spline)(**params, extrapolate=spline.extrapolate)


def _per(v, name: str) -> np.ndarray:
    a = np.atleast_1d(as_real(v, name)).astype(np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a scalar or a 1-D array, got shape {a.shape}")
    return np.ascontiguousarray(a)


class BetaSpline(Spline):
    """The Beta quaternion spline (seed 000, MATH.md §7): G¹ exactly, not G² in general.

    ``vertices`` are the auxiliary control vertices p₀ … p_{l+2} (at least 4); ``beta1`` (> 0)
    and ``beta2`` are scalars or one value per vertex. The curve has l segments, mapped to
    ``times`` (l+1 joint times, default 0 … l). β₁ = 1, β₂ = 0 is the uniform cubic B-spline.
    With ``canonicalize=False`` the paper's Example 1 is reproduced.
    """

    def __init__(
        self,
        vertices,
        beta1=1.0,
        beta2=0.0,
        times=None,
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        p = _keys(vertices, "vertices")
        t = _times(times, max(len(p) - 2, 0))
        super().__init__(
            _core.beta_spline(p, _per(beta1, "beta1"), _per(beta2, "beta2"), t, bool(canonicalize)),
            extrapolate,
        )

    def control_points(self) -> np.ndarray:
        """The Bézier points q_{i,0..3} of segments i = 1 … l, shape (l, 4, 4)."""
        return np.array(self._core.control_points())


class C3Spline(Spline):
    """The patent's interpolating C³ spline with shape parameters α, β (seed 004, MATH.md §8).

    ``variant="knot"`` (default): α, β per key (scalar or N values), C³ in time for any key
    spacing and parameters. ``variant="patent"``: α, β per segment (scalar or N−1 values),
    exactly the patent's blending functions (C³ in the local parameter for uniform times and
    shared parameters; only G³ in time otherwise). (α, β) = (5/16, 0) is the quintic C³
    scheme; α = β = 0 is slerp with degree-7 smoothstep timing.
    """

    def __init__(
        self,
        quats,
        times=None,
        alpha=5 / 16,
        beta=0.0,
        variant: str = "knot",
        canonicalize: bool = True,
        extrapolate: str = "raise",
    ):
        q = _keys(quats, "quats")
        t = _times(times, len(q))
        super().__init__(
            _core.c3_spline(
                q, t, _per(alpha, "alpha"), _per(beta, "beta"), str(variant), bool(canonicalize)
            ),
            extrapolate,
            quats=q,
            times=t,
            alpha=alpha,
            beta=beta,
            variant=variant,
            canonicalize=canonicalize,
        )
