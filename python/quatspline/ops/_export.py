"""Motion out to the tools animators use: glTF 2.0 (``.glb`` / ``.gltf``) with a guaranteed
playback error, and BVH. ``export(motion, path, …)`` is the one route (the format from the
extension); ``to_gltf`` and ``to_bvh`` are its two writers.

``to_gltf(motion, path, max_error="0.01deg", max_position_error="0.1mm",
interpolation="linear")`` writes one animated node (a small axes mesh, or an empty node)
whose playback in a glTF player stays within ``max_error`` of the spline's orientation and
within ``max_position_error`` of its position. The check computes as players do: the keys
exactly as stored (float32 times and values); ``LINEAR`` rotations both as slerp (the
specification, three.js) and as component-wise interpolation normalised (nlerp, as Blender
plays quaternion curves), the worse of the two; ``CUBICSPLINE`` as the specification's
normalised component-wise cubic Hermite; the error between check points estimated by the
parabola through each sampled peak; and eight float32 units of roundoff added for the
players' own arithmetic (so a bound below about 5e-7 rad, or 5e-7 of the largest |position|,
is refused).

Key reduction is adaptive, as animation compressors do: from each key the next one is placed
as far ahead as the bound allows (exponential then binary search over a dense grid of
candidate times that includes every spline joint); the bound is then verified on a grid four
times denser, splitting any interval that fails. Where two adjacent candidates still fail,
new candidates (and check points) are placed between them, so a tight bound gets more keys
instead of an error; only a bound that keys at float32 time resolution cannot meet is refused,
naming the channel's bound (``max_error`` or ``max_position_error``) and the best achievable
error. The report gives the keys used and the number a uniform resampling needs for the same
bound. Memory is bounded: ``samples`` is at most :data:`MAX_SAMPLES` and the verification runs
in chunks.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._util.options import DEFAULT_METHOD, parse_angle, parse_length
from .._util.progress_bars import progress as bar
from ..core.interpolate import slerp
from ..core.metrics import angle_between
from ..fitting import FittedPose
from ..fitting import fit as fit_motion
from ..io import bvh, gltf
from ..io.gltf import F32_MAX, sign_continuous
from ..io.trajectory import Trajectory
from ..poses.pose_spline import PoseSpline
from ..registry import METHODS
from ..registry import spline as make_spline
from ..splines import Spline
from ._ops import DEFAULT_MAX_SAMPLES, ParameterError

__all__ = [
    "BvhReport",
    "GltfReport",
    "export",
    "keyframes",
    "parse_angle",
    "parse_length",
    "to_bvh",
    "to_gltf",
]


def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotation angle (radians) between quaternions a and b (q ≡ −q): the package's one
    rotation distance, :func:`quatspline.angle_between`."""
    return angle_between(a, b)


# ---- the motion to export -------------------------------------------------------------------
class _Motion:
    """Uniform access to a Spline, a PoseSpline or a Trajectory (through a spline)."""

    def __init__(self, motion, method: str, params: dict):
        self.name = ""
        if not isinstance(motion, Trajectory) and isinstance(motion, (Spline, PoseSpline)):
            if params:
                raise TypeError(
                    f"{sorted(params)[0]}: a spline is exported as it is; a method's parameters "
                    "apply to an io.Trajectory only"
                )
            if method is not None:
                raise TypeError(
                    "method: a spline is exported as it is; method applies to an io.Trajectory only"
                )
        method = DEFAULT_METHOD if method is None else method
        self.samples = None
        if isinstance(motion, Trajectory):
            self.name = motion.name
            self.samples = len(motion)
            t = motion.times
            if motion.positions is not None and method == "fit":
                # rotation and translation both smoothed, with the same knots and penalty
                p = METHODS["fit"].resolve(params)
                motion = fit_motion(
                    t,
                    motion.quats,
                    positions=motion.positions,
                    smoothing=p["smoothing"],
                    penalty=p["penalty"],
                    robust=p["robust"],
                    knots=p["knots"],
                )
            elif motion.positions is not None:
                motion = PoseSpline(motion.quats, t, motion.positions, rotation=method, **params)
            else:
                motion = make_spline(method, motion.quats, t, **params)
        if isinstance(motion, (PoseSpline, FittedPose)):
            self.rot, self.pos = motion.rotation, motion
        elif isinstance(motion, Spline):
            self.rot, self.pos = motion, None
        else:
            raise TypeError(
                "motion: expected a quatspline Spline, PoseSpline or io.Trajectory, "
                f"got {type(motion).__name__}"
            )
        a, b = self.rot.domain
        if self.pos is not None:
            a, b = max(a, self.pos.domain[0]), min(b, self.pos.domain[1])
        if not b > a:
            raise ValueError("motion: the domain is empty (one key?)")
        self.t0, self.t1 = a, b
        self.joints = np.asarray(self.rot.joints, dtype=float)

    def q(self, tau):
        return self.rot(np.clip(self.t0 + tau, self.t0, self.t1))

    def dq(self, tau):
        return self.rot.derivative(np.clip(self.t0 + tau, self.t0, self.t1), 1)

    def p(self, tau):
        return self.pos.position(np.clip(self.t0 + tau, self.t0, self.t1))

    def dp(self, tau):
        return self.pos.linear_velocity(np.clip(self.t0 + tau, self.t0, self.t1))


def _f32(x):
    return np.asarray(x, dtype=np.float32).astype(np.float64)


# ---- playback (the glTF 2.0 specification, Appendix C) ---------------------------------------
#: Players interpolate in their own arithmetic (three.js in float64 with float32 results,
#: Blender in float32): every measured error gets this many float32 units of roundoff on top
#: (radians for rotations, times the largest |position| for translations).
_ROUNDOFF = 8 * 2.0**-24
#: Check points evaluated at once (bounds the memory of the verification).
_CHUNK = 1 << 18
#: The largest ``samples``: a CUBICSPLINE pose export then peaks at about 0.8 GB (measured;
#: the candidates' values and tangents, the check grid, chunks of it being verified).
MAX_SAMPLES = 1_000_000


def _nlerp(a, b, u):
    h = a + u[:, None] * (b - a)
    return h / np.linalg.norm(h, axis=1)[:, None]


def _play(rot: bool, cubic: bool, kt, kv, ka, kb, t, variant: str = "slerp") -> np.ndarray:
    """Playback at times t of keys (kt, kv) with in/out tangents (ka, kb) for CUBICSPLINE;
    LINEAR rotations as ``variant``: "slerp" (the specification, three.js) or "nlerp"
    (component-wise keys normalised, as Blender plays them)."""
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 2)
    td = kt[k + 1] - kt[k]
    u = np.clip((t - kt[k]) / td, 0.0, 1.0)
    if cubic:
        u2, u3 = u * u, u * u * u
        h = (
            (2 * u3 - 3 * u2 + 1)[:, None] * kv[k]
            + (td * (u3 - 2 * u2 + u))[:, None] * kb[k]
            + (-2 * u3 + 3 * u2)[:, None] * kv[k + 1]
            + (td * (u3 - u2))[:, None] * ka[k + 1]
        )
        return h / np.linalg.norm(h, axis=1)[:, None] if rot else h
    if rot:
        return _nlerp(kv[k], kv[k + 1], u) if variant == "nlerp" else slerp(kv[k], kv[k + 1], u)
    return kv[k] + u[:, None] * (kv[k + 1] - kv[k])


@dataclass
class _Channel:
    rot: bool
    cubic: bool
    t: np.ndarray  # candidate key times (float32 values)
    v: np.ndarray  # target values there (exact), stored as float32 when keys
    a: np.ndarray  # in-tangents (d/dt from the left)
    b: np.ndarray  # out-tangents (d/dt from the right)
    f: object = None  # the motion (values at times)
    fd: object = None  # its derivative
    span: float = 0.0
    roundoff: float = 0.0  # added to every measured error (players' float32 arithmetic)
    clock: float = 0.0  # times |t| + origin added too (players' float32 clock, see _clock)
    origin: float = 0.0  # the player's time at the motion's start (Blender: frame 0 at t = 0)
    tick: object = None  # called with the share of the span the key placement has reached

    def err(self, keys_t, keys_v, keys_a, keys_b, t, target) -> np.ndarray:
        """Playback error at t, the worst of the players' interpolations, plus roundoff."""
        variants = ("slerp", "nlerp") if self.rot and not self.cubic else ("slerp",)
        worst = np.zeros(len(t))
        for var in variants:
            got = _play(self.rot, self.cubic, keys_t, keys_v, keys_a, keys_b, t, var)
            if self.rot:
                e = angle(got, target)
            else:
                e = np.linalg.norm(got - target, axis=1)
            worst = np.maximum(worst, e)
        return worst + self.roundoff + self.clock * (np.abs(t) + self.origin)

    def keys(self, idx):
        return self.t[idx], _f32(self.v[idx]), _f32(self.a[idx]), _f32(self.b[idx])

    def interval_error(self, i: int, j: int) -> float:
        if j - i < 2:
            return 0.0
        kt, kv, ka, kb = self.keys(np.array([i, j]))
        t = self.t[i + 1 : j]
        return float(self.err(kt, kv, ka, kb, t, self.v[i + 1 : j]).max())

    def values(self, t):
        """Values and one-sided tangents at times t, sign-continuous with the neighbours
        given by ``ref`` (rotations) — see :meth:`insert`."""
        v = self.f(t)
        a, b = _tangents(self.fd, t, self.span) if self.cubic else (v, v)
        return v, a, b

    def insert(self, new_t: np.ndarray) -> np.ndarray:
        """Adds candidate times (float32 values strictly between existing ones); returns the
        old indices' new positions."""
        v, a, b = self.values(new_t)
        pos = np.searchsorted(self.t, new_t)
        if self.rot:  # the sign of the candidate before each new time
            sgn = np.where(np.sum(v * self.v[pos - 1], axis=1) < 0, -1.0, 1.0)[:, None]
            v, a, b = v * sgn, a * sgn, b * sgn
        old = np.arange(len(self.t)) + np.searchsorted(new_t, self.t, side="right")
        self.t = np.insert(self.t, pos, new_t)
        self.v = np.insert(self.v, pos, v, axis=0)
        if self.cubic:
            self.a = np.insert(self.a, pos, a, axis=0)
            self.b = np.insert(self.b, pos, b, axis=0)
        else:
            self.a = self.b = self.v
        return old


def _clock(rot: bool, t: np.ndarray, v: np.ndarray) -> float:
    """Error per second of playback time from the players' float32 clock: the time and
    the frame (Blender: ``frame = time × fps``, a float32) each rounded to float32 (two
    roundings of at most half a unit, relative 2⁻²⁴; the key times are float32 already and
    the offset from a key is exact), times the motion's largest speed (the largest chord
    speed over the candidates, with a quarter more for the arc)."""
    if len(t) < 2:
        return 0.0
    dt = np.diff(t)
    step = angle(v[:-1], v[1:]) if rot else np.linalg.norm(np.diff(v, axis=0), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = np.where(dt > 0, step / np.where(dt > 0, dt, 1.0), 0.0)
    return 2 * 2.0**-24 * 1.25 * float(speed.max(initial=0.0))


def _greedy(ch: _Channel, tol: float, cap: int | None = None) -> list[int] | float:
    """From each key, the farthest candidate the bound allows (exponential, then binary
    search); every accepted interval is checked on all candidates inside it. With ``cap``,
    stops once more than ``cap`` keys are placed and returns the fraction of the span they
    covered instead."""
    n = len(ch.t)
    keys = [0]
    i = 0
    while i < n - 1:
        if ch.tick is not None and len(keys) % 64 == 0:
            ch.tick(float(ch.t[i] / ch.t[-1]))
        if cap is not None and len(keys) > cap:
            return float(ch.t[i] / ch.t[-1]) if ch.t[-1] > 0 else 0.0
        step, good = 1, i + 1
        while True:
            j = min(i + step, n - 1)
            if ch.interval_error(i, j) <= tol:
                good = j
                if j == n - 1:
                    break
                step *= 2
            else:
                break
        bad = min(i + step, n - 1)
        if good < n - 1 and bad > good:
            lo, hi = good, bad  # lo feasible, hi not
            while hi - lo > 1:
                mid = (lo + hi) // 2
                if ch.interval_error(i, mid) <= tol:
                    lo = mid
                else:
                    hi = mid
            good = lo
        keys.append(good)
        i = good
    return keys


def _tangents(f_d, t: np.ndarray, span: float):
    """In/out derivatives at t: one-sided (evaluated just before and after each time)."""
    eps = 1e-9 * max(span, 1e-300)
    return f_d(t - eps), f_d(t + eps)


def _candidate_times(m: _Motion, samples: int) -> np.ndarray:
    span = m.t1 - m.t0
    per = max(2, int(np.ceil(samples / max(len(m.joints) - 1, 1))))
    j = m.joints[(m.joints >= m.t0) & (m.joints <= m.t1)] - m.t0
    pieces = [np.linspace(a, b, per + 1)[:-1] for a, b in zip(j[:-1], j[1:]) if b > a]
    t = np.concatenate([*pieces, [span], np.linspace(0, span, samples)])
    return np.unique(np.minimum(_f32(np.clip(t, 0, span)), _f32_floor(span)))


def _f32_floor(x: float) -> float:
    """The largest float32 value ≤ x (the last key time stays inside the domain)."""
    y = np.float32(x)
    if float(y) > x:
        y = np.nextafter(y, np.float32(-np.inf))
    return float(y)


def _dense(t: np.ndarray, factor: int = 4) -> np.ndarray:
    """``factor`` − 1 extra points inside every interval of t."""
    f = np.arange(1, factor) / factor
    inner = (t[:-1, None] + np.diff(t)[:, None] * f[None, :]).ravel()
    return np.sort(np.concatenate([t, inner]))


def _peaks(t: np.ndarray, e: np.ndarray) -> np.ndarray:
    """The error between check points: at each sampled local maximum, the vertex of the
    parabola through it and its two neighbours (exact for the quadratic bump of an
    interpolation error; never below the sample, capped as said below)."""
    out = e.copy()
    if len(e) < 3:
        return out
    e0, e1, e2 = e[:-2], e[1:-1], e[2:]
    h0, h1 = t[1:-1] - t[:-2], t[2:] - t[1:-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        d0, d1 = (e1 - e0) / h0, (e2 - e1) / h1
        c = (d1 - d0) / (h0 + h1)  # half the second derivative
        slope = d0 + c * h0  # the derivative at the middle point
        top = e1 - slope * slope / (4 * c)
    peak = (e1 >= e0) & (e1 >= e2) & (c < 0) & np.isfinite(top)
    # An exact parabola sampled evenly overshoots its middle sample by at most a quarter of
    # the rise from the lower neighbour; half of it caps wild fits through uneven spacing
    # or roundoff noise.
    top = np.minimum(top, e1 + 0.5 * (e1 - np.minimum(e0, e2)))
    out[1:-1] = np.where(peak, np.maximum(e1, top), e1)
    return out


def _check(ch: _Channel, keys, check_t) -> np.ndarray:
    """Estimated continuous-time error at the check points, in chunks of :data:`_CHUNK`
    points so that memory does not grow with the grid."""
    kt, kv, ka, kb = ch.keys(np.array(keys))
    n = len(check_t)
    out = np.empty(n)
    for s in range(0, n, _CHUNK):
        m = min(_CHUNK, n - s)
        lo, hi = max(s - 1, 0), min(s + m + 1, n)  # a neighbour each side for the parabola
        tt = check_t[lo:hi]
        e = _peaks(tt, ch.err(kt, kv, ka, kb, tt, ch.f(tt)))
        out[s : s + m] = e[s - lo : s - lo + m]
    return out


def _refuse(name: str, tol: float, best: float, why: str):
    unit, scale = ("°", 180 / np.pi) if name == "max_error" else (" m", 1.0)
    raise ValueError(
        f"{name}: the bound {tol * scale:.3g}{unit} cannot be met {why} (best achievable "
        f"error {best * scale:.3g}{unit} where it fails); use a larger bound"
    )


def _fit(ch: _Channel, tol: float, check_t, name: str, max_candidates: int):
    """Keys meeting the bound on the check grid: the greedy placement, then every failing key
    interval split at its middle candidate; an interval between adjacent candidates that
    still fails gets new candidates (and check points) inside it, up to ``max_candidates``.
    Returns (keys, measured error, check points)."""
    keys = _greedy(ch, tol)
    return _verify(ch, keys, tol, check_t, name, max_candidates)


def _verify(ch: _Channel, keys, tol: float, check_t, name: str, max_candidates: int):
    """The verification and splitting rounds of :func:`_fit` from the keys given."""
    for _ in range(200):
        kt = ch.t[np.array(keys)]
        e = _check(ch, keys, check_t)
        seg = np.clip(np.searchsorted(kt, check_t, side="right") - 1, 0, len(kt) - 2)
        fail = np.unique(seg[~(e <= tol)])  # NaN fails too
        if len(fail) == 0:
            return keys, float(e.max()), check_t
        new, refine = set(keys), []
        for s in fail:
            a, b = keys[s], keys[s + 1]
            if b - a >= 2:
                new.add((a + b) // 2)
            else:
                refine.append(s)
        if refine:
            lo = ch.t[[keys[s] for s in refine]]
            hi = ch.t[[keys[s + 1] for s in refine]]
            mid = _f32((lo + hi) / 2)
            ok = (mid > lo) & (mid < hi)
            if not ok.all() or len(ch.t) + len(mid) > max_candidates:
                why = (
                    "even with keys at float32 time resolution"
                    if not ok.all()
                    else f"with {max_candidates} candidate key times"
                )
                _refuse(name, tol, float(e[np.isin(seg, refine)].max()), why)
            old = ch.insert(mid)
            added = np.flatnonzero(np.isin(ch.t, mid))
            keys = sorted({int(old[k]) for k in new} | {int(k) for k in added})
            around = np.sort(np.concatenate([lo, mid, hi]))
            check_t = np.union1d(check_t, _dense(around, 4))
        else:
            keys = sorted(new)
    _refuse(name, tol, float(e.max()), "after 200 rounds of adding keys")


def _fit_capped(ch: _Channel, tol: float, check_t, name: str, max_candidates: int, cap):
    """:func:`_fit` with at most ``cap`` keys: when the bound needs more, the bound is
    relaxed until it does not. How far: an eighth of ``cap`` keys are placed first, and the
    share of the span they cover estimates the keys the whole span needs (LINEAR keys grow as
    tol^-½, cubic ones as tol^-¼, so the bound grows by the square or the fourth power of the
    excess, with a tenth to spare); then the full placement, relaxed again by the share of
    the span it reached if it still stops at ``cap``. Returns (keys, error, check points,
    bound met)."""
    if cap is None:
        return (*_fit(ch, tol, check_t, name, max_candidates), tol)
    power = 4 if ch.cubic else 2
    bound = tol
    probe = cap // 8 if cap >= 512 else None
    for _ in range(60):
        if probe is not None:
            got, probe_keys, probe = _greedy(ch, bound, probe), probe, None
            if isinstance(got, list):
                continue  # the probe's keys covered the span: place them all
            excess = probe_keys / max(got, 1e-3) / cap  # needed keys / cap, estimated
            if excess > 0.9:
                bound *= (1.1 * excess) ** power
            continue
        got = _greedy(ch, bound, cap)
        if isinstance(got, list):
            keys, err, grid = _verify(ch, got, bound, check_t, name, max_candidates)
            if len(keys) <= cap:
                return keys, err, grid, bound
            got = len(got) / len(keys)  # verification added keys: relax by their share
        reach = min(max(got, 1e-3), 0.95)
        bound *= max(1.5, (1.2 / reach) ** power)
    _refuse(name, tol, bound, f"with at most {cap} keys (max_keys)")


def _uniform_keys(ch: _Channel, tol: float, check_t, start: int) -> int:
    """The smallest number of evenly spaced keys meeting the same bound (doubling, then
    bisection), capped at 8× the adaptive count."""

    def ok(n):
        kt = np.unique(np.minimum(_f32(np.linspace(0, ch.span, n)), _f32_floor(ch.span)))
        v, a, b = ch.values(kt)
        if ch.rot:
            sgn = np.sign(np.sum(sign_continuous(v) * v, axis=1))[:, None]
            v, a, b = v * sgn, a * sgn, b * sgn
        u = _Channel(
            ch.rot, ch.cubic, kt, v, a, b, ch.f, ch.fd, ch.span, ch.roundoff, ch.clock, ch.origin
        )
        return _check(u, np.arange(len(kt)), check_t).max() <= tol

    lo, hi = 1, max(2, start // 2)
    cap = 8 * start + 16
    while not ok(hi):
        lo, hi = hi, hi * 2
        if hi > cap:
            return -1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ok(mid):
            hi = mid
        else:
            lo = mid
    return hi


# ---- the file -------------------------------------------------------------------------------
@dataclass
class GltfReport:
    """What ``to_gltf`` wrote and measured (angles in radians, lengths in metres)."""

    path: str
    interpolation: str
    duration: float
    rotation_keys: int
    rotation_uniform_keys: int
    rotation_error: float
    rotation_bound: float
    translation_keys: int = 0
    translation_uniform_keys: int = 0
    translation_error: float = 0.0
    translation_bound: float = 0.0
    check_points: int = 0
    rotation_requested: float = 0.0
    translation_requested: float = 0.0
    max_keys: int | None = None
    samples: int | None = None
    start: float = 0.0

    def summary(self) -> str:
        deg = np.degrees
        s = (
            f"{self.path}: {self.interpolation}, {self.duration:.6g} s; rotation "
            f"{self.rotation_keys} keys{self._u(self.rotation_uniform_keys)}, "
            f"max error {deg(self.rotation_error):.3g}° ≤ {deg(self.rotation_bound):.3g}°"
        )
        if self.translation_keys:
            s += (
                f"; translation {self.translation_keys} keys"
                f"{self._u(self.translation_uniform_keys)}, max error "
                f"{self.translation_error:.3g} m ≤ {self.translation_bound:.3g} m"
            )
        s += f" (checked at {self.check_points} times)"
        relaxed = [
            f"{what} bound relaxed from {asked} to keep at most {self.max_keys} keys"
            for what, asked, met in (
                ("rotation", f"{deg(self.rotation_requested):.3g}°", self.rotation_bound),
                ("translation", f"{self.translation_requested:.3g} m", self.translation_bound),
            )
            if met > 0
            and met
            != (self.rotation_requested if what == "rotation" else self.translation_requested)
        ]
        if relaxed:
            s += (
                "; "
                + "; ".join(relaxed)
                + (
                    " (the input's sample count; a noisy recording exports closer with "
                    "method='fit', or give max_keys=None)"
                    if self.max_keys == self.samples
                    else ""
                )
            )
        if self.interpolation == "cubicspline":
            s += "; CUBICSPLINE tangents: " + TANGENTS
        return s

    @staticmethod
    def _u(n):
        if n == 0:
            return ""
        return f" (uniform needs {n if n > 0 else 'more than 8×'})"


#: Which players honour CUBICSPLINE tangents (stated in the export report and the docs).
TANGENTS = (
    "three.js and Babylon.js play them; Blender's glTF importer (3.4 and 4.2, checked) drops "
    "them and rebuilds automatic Bézier handles, so in Blender the bound holds for LINEAR only "
    "(or import with the quatspline Blender add-on)"
)


def to_gltf(
    motion,
    path,
    *,
    max_error="0.01deg",
    max_position_error="0.1mm",
    interpolation: str = "linear",
    node: str = "body",
    mesh: str | None = "axes",
    size: float = 0.1,
    samples: int | None = None,
    method: str | None = None,
    uniform: bool = False,
    max_keys="samples",
    progress: bool = True,
    **params,
) -> GltfReport:
    """Writes ``motion`` as a glTF 2.0 animation whose playback stays within the bounds.

    Parameters
    ----------
    motion : Spline, PoseSpline or io.Trajectory
        The motion; a Trajectory goes through ``method`` (and ``params``) first, with a
        cubic position spline when it has positions. Times start at 0 in the file.
    path : path-like
        ``.glb`` (binary) or ``.gltf`` (JSON with the data embedded). Written atomically.
    max_error : float or str
        Orientation bound: a number in degrees, or a string with a unit (``"0.01deg"``,
        ``"0.2mrad"``, ``"30arcsec"``). Must be positive.
    max_position_error : float or str
        Position bound: metres, or ``"0.1mm"``, ``"1cm"``.
    interpolation : {"linear", "cubicspline"}
        The glTF sampler interpolation. CUBICSPLINE keys carry the spline's one-sided
        derivatives as in/out tangents.
    node : str
        The animated node's name (any non-empty Unicode text).
    mesh : {"axes", None}
        A small red/green/blue axes mesh of length ``size`` (metres, positive and within
        float32 range), or an empty node.
    samples : int, optional
        Candidate key times (default: 16 per spline segment, at least 2000, at most 200000;
        at most :data:`MAX_SAMPLES` = 1,000,000); the bound is verified on a grid four times
        denser, and candidates are added where adjacent ones cannot meet it.
    method : str, optional
        For a Trajectory: the registry method its spline is built with (default ``"natural"``),
        with ``params``; a spline is exported as it is (giving ``method`` or parameters with
        one is a ``TypeError``).
    uniform : bool
        Also find how many evenly spaced keys the same bound needs (for the report; about
        doubles the time).
    max_keys : "samples", int or None
        The most keys a channel gets. ``"samples"`` (default): an io.Trajectory's sample
        count (no limit for a spline), so a recording never exports to more keys than it
        has samples; ``None``: no limit. When the bound needs more keys, the bound is
        relaxed until it does not, and the report says so (the bound met is in
        ``rotation_bound`` / ``translation_bound``, the one asked in ``*_requested``).
        An interpolating spline through a noisy recording wiggles between the samples by
        about the noise; ``method="fit"`` smooths rotation and translation instead.
    progress : bool
        Show a progress bar.

    Returns
    -------
    GltfReport
        Keys used, the uniform count, the measured maximum errors and the bounds.

    Raises
    ------
    ValueError
        A bound that is not positive or cannot be parsed, an unknown interpolation,
        ``samples`` outside [2, MAX_SAMPLES], a bound no keys can meet (the message names
        ``max_error`` or ``max_position_error`` and the best achievable error), positions
        beyond float32 range.
    TypeError
        A motion or an option of the wrong kind.

    Examples
    --------
    >>> import numpy as np, tempfile, os, quatspline as qs
    >>> q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    >>> s = qs.C3Spline(q, np.arange(6.0))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     r = to_gltf(s, os.path.join(d, "m.glb"), max_error="0.1deg", uniform=True,
    ...                 progress=False)
    >>> r.rotation_error <= r.rotation_bound, r.rotation_keys < r.rotation_uniform_keys
    (True, True)
    """
    tol_r = parse_angle(max_error, "max_error")
    tol_p = parse_length(max_position_error, "max_position_error")
    for flag_name, flag_value in (("uniform", uniform), ("progress", progress)):
        if not isinstance(flag_value, (bool, np.bool_)):
            raise TypeError(f"{flag_name}: expected True or False, got {type(flag_value).__name__}")
    path, size = gltf.check_options(path, interpolation, node, mesh, size)
    rep, chosen, name = _bounded_keys(
        motion, str(path), tol_r, tol_p, interpolation, samples, method, uniform, max_keys,
        progress, params,
    )  # fmt: skip
    # the format's writer stores the chosen keys (one document builder for every glTF route)
    gltf.write_animation(
        path,
        chosen["rotation"],
        chosen.get("translation"),
        interpolation=interpolation,
        node=node,
        mesh=mesh,
        size=size,
        name=name,
    )
    return rep


def keyframes(
    motion,
    *,
    max_error="0.01deg",
    max_position_error="0.1mm",
    method: str | None = None,
    max_keys="samples",
    samples: int | None = None,
    progress: bool = False,
    **params,
):
    """LINEAR keys whose playback stays within the bounds: the key placement of
    :func:`to_gltf` without the file, for front ends that write keys themselves (the
    Blender add-on writes them as F-curves).

    The bound holds for slerp and for component-wise interpolation normalised (as Blender
    plays quaternion F-curves), with float32 keys, times and clock (Blender's frames are
    float32: ``frame = start + time × fps`` adds one rounding, which the check includes).

    Parameters
    ----------
    motion, max_error, max_position_error, method, max_keys, samples, progress, **params
        As :func:`to_gltf`.

    Returns
    -------
    (dict, GltfReport)
        ``{"rotation": (times, quats wxyz), "translation": (times, positions)}`` (translation
        only with positions; times from 0, at the motion's start ``report.start``), and the
        report (its ``path`` is empty).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> s = qs.C3Spline(qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6)), np.arange(6.0))
    >>> keys, rep = keyframes(s, max_error="0.1deg")
    >>> t, q = keys["rotation"]
    >>> len(t) == rep.rotation_keys, rep.rotation_error <= rep.rotation_bound, q.shape[1]
    (True, True, 4)
    """
    tol_r = parse_angle(max_error, "max_error")
    tol_p = parse_length(max_position_error, "max_position_error")
    if not isinstance(progress, (bool, np.bool_)):
        raise TypeError(f"progress: expected True or False, got {type(progress).__name__}")
    rep, chosen, _ = _bounded_keys(
        motion, "", tol_r, tol_p, "linear", samples, method, False, max_keys, progress, params,
        absolute=True,
    )  # fmt: skip
    out = {
        name: (np.asarray(k.times, float), np.asarray(k.values, float))
        for name, k in chosen.items()
    }
    return out, rep


def _bounded_keys(
    motion, path, tol_r, tol_p, interpolation, samples, method, uniform, max_keys, progress, params,
    absolute=False,
):  # fmt: skip
    """The keys of each channel meeting its bound, and the report."""
    m = _Motion(motion, method, params)
    cap = _max_keys(max_keys, m.samples)
    cubic = interpolation == "cubicspline"
    span = m.t1 - m.t0
    if samples is None:
        samples = int(min(max(16 * (len(m.joints) - 1), 2000), 200_000))
    if not (
        isinstance(samples, (int, np.integer))
        and not isinstance(samples, bool)
        and 2 <= samples <= MAX_SAMPLES
    ):
        raise ValueError(f"samples: expected an integer in [2, {MAX_SAMPLES}], got {samples!r}")

    chans = [("rotation", "max_error", m.q, m.dq, tol_r, True)]
    if m.pos is not None:
        chans.append(("translation", "max_position_error", m.p, m.dp, tol_p, False))
    t = _candidate_times(m, samples)
    results = {}
    per = 1000  # bar units per channel and stage: the share of the span keyed so far
    total = len(chans) * (2 if uniform else 1) * per
    with bar(total=total, desc="export glTF", enabled=progress) as pb:
        for name, bound, f, fd, tol, rot in chans:
            ch = _Channel(rot, cubic, t, None, None, None, f, fd, span)
            shown = [0]

            def tick(share, shown=shown):
                step = int(per * min(max(share, 0.0), 1.0)) - shown[0]
                if step > 0:
                    pb.update(step)
                    shown[0] += step

            ch.tick = tick
            v, a, b = ch.values(t)
            if rot:
                sgn = np.sign(np.sum(sign_continuous(v) * v, axis=1))[:, None]
                v, a, b = v * sgn, a * sgn, b * sgn
                ch.roundoff = _ROUNDOFF
            else:
                ch.roundoff = _ROUNDOFF * float(np.abs(v).max(initial=0.0)) * np.sqrt(3)
            ch.v, ch.a, ch.b = v, a, b
            ch.clock = _clock(rot, t, v)
            ch.origin = abs(m.t0) if absolute else 0.0
            if not rot and not np.abs(v).max(initial=0.0) <= F32_MAX:
                raise ValueError(
                    f"motion: positions reach {float(np.abs(v).max()):.3g} m, beyond the float32 "
                    "range of glTF (3.4e38)"
                )
            if ch.roundoff >= tol:
                _refuse(bound, tol, ch.roundoff, "by float32 keys (players' roundoff)")
            keys, err, check_t, met = _fit_capped(
                ch, tol, _dense(ch.t), bound, 2 * MAX_SAMPLES, cap
            )
            ch.tick = None
            pb.update(per - shown[0])
            nu = 0
            if uniform:
                nu = _uniform_keys(ch, tol, check_t, len(keys))
                pb.update(per)
            idx = np.array(keys)  # keep the keys only: the candidates' memory is released
            kept = (ch.t[idx], ch.v[idx], ch.a[idx], ch.b[idx])
            results[name] = (kept, keys, err, nu, met, len(check_t), tol)
            del ch, check_t, v, a, b

    chosen = {}
    for name, ((kt, kv, ka, kb), *_) in results.items():
        chosen[name] = gltf.Keys(kt, kv, ka if cubic else None, kb if cubic else None)
    r = results["rotation"]
    rep = GltfReport(
        str(path),
        interpolation,
        float(span),
        len(r[1]),
        r[3],
        r[2],
        r[4],
        check_points=max(r[5] for r in results.values()),
        rotation_requested=r[6],
        max_keys=cap,
        samples=m.samples,
        start=float(m.t0),
    )
    if "translation" in results:
        p = results["translation"]
        rep.translation_keys, rep.translation_uniform_keys = len(p[1]), p[3]
        rep.translation_error, rep.translation_bound = p[2], p[4]
        rep.translation_requested = p[6]
    return rep, chosen, m.name


def _max_keys(max_keys, samples: int | None) -> int | None:
    """The key cap: "samples" (a Trajectory's sample count, none for a spline), None or an
    integer ≥ 2."""
    if isinstance(max_keys, str):
        if max_keys != "samples":
            raise ValueError(
                f"max_keys: expected 'samples', None or an integer ≥ 2, got {max_keys!r}"
            )
        return None if samples is None else max(samples, 2)
    if max_keys is None:
        return None
    if isinstance(max_keys, bool) or not isinstance(max_keys, (int, np.integer)):
        raise TypeError(
            f"max_keys: expected an integer, 'samples' or None, got {type(max_keys).__name__}"
        )
    if max_keys < 2:
        raise ValueError(f"max_keys: expected an integer ≥ 2, got {max_keys}")
    return int(max_keys)


def to_bvh(trajectory, path, *, joint: str = "Root") -> None:
    """Writes a trajectory as a BVH joint named ``joint`` (the trajectory's name when it has
    one; see :mod:`quatspline.io.bvh`)."""
    if not isinstance(joint, str):
        raise TypeError(f"joint: expected a string, got {type(joint).__name__}")
    bvh.write(Path(path), trajectory, joint=joint)


# ---- the one export route -------------------------------------------------------------------
@dataclass
class BvhReport:
    """What ``export`` wrote to BVH: frames, their rate, the spline they were sampled from."""

    path: str
    frames: int
    fps: float
    method: str

    def summary(self) -> str:
        return (
            f"{self.path}: BVH joint, {self.frames} frames at {self.fps:.6g} fps "
            f"({self.method} spline)"
        )


#: Output extensions and the export format each one means.
EXPORT_EXTENSIONS = {".glb": "gltf", ".gltf": "gltf", ".bvh": "bvh"}


def export(
    motion,
    path,
    *,
    format: str | None = None,
    method: str | None = None,
    max_error="0.01deg",
    max_position_error="0.1mm",
    interpolation: str = "linear",
    node: str = "body",
    mesh: str | None = "axes",
    size: float = 0.1,
    samples: int | None = None,
    uniform: bool = False,
    max_keys="samples",
    fps: float | None = None,
    joint: str = "Root",
    progress: bool = True,
    **params,
) -> GltfReport | BvhReport:
    """Exports a motion to glTF 2.0 (error-bounded) or BVH: the one route behind
    ``quatspline export`` and batch exports.

    Parameters
    ----------
    motion : io.Trajectory, Spline or PoseSpline
        The motion; a Trajectory goes through the spline ``method`` (default ``"natural"``) with
        ``params``; a spline is exported as it is.
    path : path-like
        The output: ``.glb`` / ``.gltf`` (glTF) or ``.bvh``. Written atomically.
    format : {"gltf", "bvh"}, optional
        Default: from the extension.
    method : str, optional
        For a Trajectory, the registry method of its spline; ``params`` its parameters.
    max_error, max_position_error, interpolation, node, mesh, size, samples, uniform, max_keys
        glTF: as for :func:`to_gltf` (the bounds are checked for BVH too; the other glTF
        options are not used by BVH).
    fps : float, optional
        BVH: the frame rate, in (0, 10000] (default: one over the median key spacing);
        frames are sampled from the spline at ``t0 + k / fps`` up to the last key, and
        written from time 0.
    joint : str
        BVH: the joint's name when the trajectory has none.
    progress : bool
        glTF: show a progress bar.

    Returns
    -------
    GltfReport or BvhReport
        What was written; ``summary()`` is one line.

    Raises
    ------
    ParameterError
        An option the caller chose: an unknown format or extension, a bound that cannot be
        parsed, a frame rate out of range or one that gives more than
        :data:`~quatspline.ops.DEFAULT_MAX_SAMPLES` frames, an unknown method or parameter.
    ValueError
        What the motion cannot give (a bound no keys can meet, one key, …).
    TypeError
        An argument of the wrong kind.

    Examples
    --------
    >>> import numpy as np, tempfile, os, quatspline as qs
    >>> tr = qs.io.Trajectory(np.arange(5.0), qs.from_axis_angle([0, 0, 1], np.arange(5.0)))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     print(export(tr, os.path.join(d, "m.bvh"), fps=2).summary().split(": ")[1])
    BVH joint, 9 frames at 2 fps (natural spline)
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file path, got {type(path).__name__}")
    path = Path(path)
    if format is None:
        format = EXPORT_EXTENSIONS.get(path.suffix.lower())
        if format is None:
            raise ParameterError(
                f"{path}: expected a .glb, .gltf or .bvh output (or give the format)"
            )
    elif format not in ("gltf", "bvh"):
        raise ParameterError(f"format: expected 'gltf' or 'bvh', got {format!r}")
    for name, value, parse in (
        ("max_error", max_error, parse_angle),
        ("max_position_error", max_position_error, parse_length),
    ):
        try:
            parse(value, name)
        except TypeError:
            raise
        except ValueError as e:
            raise ParameterError(str(e)) from None
    if format == "gltf":
        return to_gltf(
            motion,
            path,
            max_error=max_error,
            max_position_error=max_position_error,
            interpolation=interpolation,
            node=node,
            mesh=mesh,
            size=size,
            samples=samples,
            method=method,
            uniform=uniform,
            max_keys=max_keys,
            progress=progress,
            **params,
        )
    return _export_bvh(motion, path, method, fps, joint, params)


def _export_bvh(motion, path: Path, method, fps, joint, params: dict) -> BvhReport:
    """BVH frames at a uniform rate sampled from the motion's spline, written from time 0."""
    if not isinstance(joint, str):
        raise TypeError(f"joint: expected a string, got {type(joint).__name__}")
    if isinstance(motion, Trajectory):
        method = DEFAULT_METHOD if method is None else method
        t0, t1, keys = float(motion.times[0]), float(motion.times[-1]), motion.times
    else:
        m = _Motion(motion, method, params)  # refuses a method or parameters with a spline
        t0, t1, keys = m.t0, m.t1, m.joints
        method = type(m.rot).__name__
    if fps is None:
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            fps = 1.0 / float(np.median(np.diff(keys))) if len(keys) > 1 else np.nan
    elif isinstance(fps, bool) or not isinstance(fps, (int, float, np.integer, np.floating)):
        raise TypeError(f"fps: expected a number, got {type(fps).__name__}")
    if not (np.isfinite(fps) and 0 < fps <= 10_000):
        raise ParameterError(f"fps: expected a frame rate in (0, 10000], got {fps}")
    fps = float(fps)
    with np.errstate(over="ignore"):
        count = (t1 - t0) * fps
    if not count < DEFAULT_MAX_SAMPLES:
        raise ParameterError(
            f"fps: {fps:.6g} fps over {t1 - t0:.6g} s gives more than {DEFAULT_MAX_SAMPLES} "
            "frames; choose a lower rate"
        )
    n = int(np.floor(count + 1e-9)) + 1
    at = np.minimum(t0 + np.arange(n) / fps, t1)
    if isinstance(motion, Trajectory):
        frames = motion.resample(at, method=method, **params)
    else:
        pos = None if m.pos is None else m.pos.position(at)
        frames = Trajectory(at, m.rot(at), pos)
    frames.times = np.arange(n) / fps  # BVH frames: uniform from 0
    bvh.write(path, frames, joint=joint)
    return BvhReport(str(path), n, fps, method)
