"""Motion out to the tools animators use: glTF 2.0 (``.glb`` / ``.gltf``) with a guaranteed
playback error, and BVH.

``to_gltf(motion, path, max_error="0.01deg", max_position_error="0.1mm",
interpolation="linear")`` writes one animated node (a small axes mesh, or an empty node)
whose playback in any glTF player — slerp between keys for ``LINEAR``, the glTF
specification's normalised component-wise cubic Hermite for ``CUBICSPLINE`` — stays within
``max_error`` of the spline's orientation and within ``max_position_error`` of its position,
checked on a dense grid with the keys exactly as stored (float32 times and values).

Key reduction is adaptive, as animation compressors do: from each key the next one is placed
as far ahead as the bound allows (exponential then binary search over a dense grid of
candidate times that includes every spline joint); the bound is then verified on a grid four
times denser, splitting any interval that fails. The report gives the keys used and the
number a uniform resampling needs for the same bound.
"""

from __future__ import annotations

import base64
import json
import re
import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._atomic import atomic_write
from .interpolate import slerp

__all__ = ["GltfReport", "parse_angle", "parse_length", "to_bvh", "to_gltf"]

_ANGLE_UNITS = {
    "rad": 1.0,
    "mrad": 1e-3,
    "urad": 1e-6,
    "deg": np.pi / 180,
    "°": np.pi / 180,
    "arcmin": np.pi / 180 / 60,
    "arcsec": np.pi / 180 / 3600,
}
_LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6}
_NUM = r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*([^\s\d.+-][^\s]*)?\s*"


def _parse(value, name: str, units: dict, default_unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, str, np.floating)):
        raise TypeError(f"{name}: expected a number or a string such as '0.01{default_unit}'")
    if isinstance(value, str):
        m = re.fullmatch(_NUM, value)
        if not m or (m.group(2) is not None and m.group(2) not in units):
            raise ValueError(
                f"{name}: cannot parse {value!r}; expected a number with a unit "
                f"({', '.join(units)}), e.g. '0.01{default_unit}'"
            )
        x = float(m.group(1)) * units[m.group(2) or default_unit]
    else:
        x = float(value) * units[default_unit]
    if not (np.isfinite(x) and x > 0):
        raise ValueError(f"{name}: expected a positive finite bound, got {value!r}")
    return x


def parse_angle(value, name: str = "max_error") -> float:
    """An angle bound in radians from a number (degrees) or a string with a unit.

    Examples
    --------
    >>> round(parse_angle("0.5deg"), 9), parse_angle("2mrad"), round(parse_angle(1.0), 9)
    (0.008726646, 0.002, 0.017453293)
    """
    return _parse(value, name, _ANGLE_UNITS, "deg")


def parse_length(value, name: str = "max_position_error") -> float:
    """A length bound in metres from a number (metres) or a string with a unit.

    Examples
    --------
    >>> parse_length("1mm"), parse_length(0.25)
    (0.001, 0.25)
    """
    return _parse(value, name, _LENGTH_UNITS, "m")


def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Rotation angle (radians) between quaternions a and b (q ≡ −q): the package's one
    rotation distance, :func:`quatspline.angle_between`."""
    from .metrics import angle_between

    return angle_between(a, b)


# ---- the motion to export -------------------------------------------------------------------
class _Motion:
    """Uniform access to a Spline, a PoseSpline or a Trajectory (through a spline)."""

    def __init__(self, motion, method: str, params: dict):
        from .io import Trajectory
        from .pose import PoseSpline
        from .registry import spline as make_spline
        from .spline import Spline

        self.name = ""
        if isinstance(motion, Trajectory):
            self.name = motion.name
            t = motion.times
            if motion.positions is not None:
                motion = PoseSpline(motion.quats, t, motion.positions, rotation=method, **params)
            else:
                motion = make_spline(method, motion.quats, t, **params)
        if isinstance(motion, PoseSpline):
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


def _sign_continuous(q: np.ndarray) -> np.ndarray:
    """Flips signs so consecutive quaternions have a non-negative dot product."""
    flips = np.concatenate([[False], np.sum(q[1:] * q[:-1], axis=1) < 0])
    sign = np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)
    return q * sign[:, None]


# ---- playback (the glTF 2.0 specification, Appendix C) ---------------------------------------
def _play(rot: bool, cubic: bool, kt, kv, ka, kb, t) -> np.ndarray:
    """Playback at times t of keys (kt, kv) with in/out tangents (ka, kb) for CUBICSPLINE."""
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
        return slerp(kv[k], kv[k + 1], u)
    return kv[k] + u[:, None] * (kv[k + 1] - kv[k])


@dataclass
class _Channel:
    rot: bool
    cubic: bool
    t: np.ndarray  # candidate key times (float32 values)
    v: np.ndarray  # target values there (exact), stored as float32 when keys
    a: np.ndarray  # in-tangents (d/dt from the left)
    b: np.ndarray  # out-tangents (d/dt from the right)

    def err(self, keys_t, keys_v, keys_a, keys_b, t, target) -> np.ndarray:
        got = _play(self.rot, self.cubic, keys_t, keys_v, keys_a, keys_b, t)
        if self.rot:
            return angle(got, target)
        return np.linalg.norm(got - target, axis=1)

    def keys(self, idx):
        return self.t[idx], _f32(self.v[idx]), _f32(self.a[idx]), _f32(self.b[idx])

    def interval_error(self, i: int, j: int) -> float:
        idx = np.array([i, j])
        kt, kv, ka, kb = self.keys(idx)
        if j - i < 2:
            return 0.0
        t = self.t[i + 1 : j]
        return float(self.err(kt, kv, ka, kb, t, self.v[i + 1 : j]).max())


def _greedy(ch: _Channel, tol: float) -> list[int]:
    """From each key, the farthest candidate the bound allows (exponential, then binary
    search); every accepted interval is checked on all candidates inside it."""
    n = len(ch.t)
    keys = [0]
    i = 0
    while i < n - 1:
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
    """``factor`` − 1 extra points inside every candidate interval."""
    f = np.arange(1, factor) / factor
    inner = (t[:-1, None] + np.diff(t)[:, None] * f[None, :]).ravel()
    return np.sort(np.concatenate([t, inner]))


def _fit(ch: _Channel, tol: float, check_t, check_v) -> tuple[list[int], float]:
    keys = _greedy(ch, tol)
    for _ in range(60):
        kt, kv, ka, kb = ch.keys(np.array(keys))
        e = ch.err(kt, kv, ka, kb, check_t, check_v)
        if e.max() <= tol:
            return keys, float(e.max())
        # split every failing key interval at its middle candidate
        seg = np.clip(np.searchsorted(kt, check_t[e > tol], side="right") - 1, 0, len(kt) - 2)
        new = set(keys)
        for s in np.unique(seg):
            a, b = keys[s], keys[s + 1]
            if b - a < 2:
                raise ValueError(
                    "max_error: the bound cannot be met between adjacent candidate times "
                    f"(error {e.max():.3g}); use a larger bound or more samples"
                )
            new.add((a + b) // 2)
        keys = sorted(new)
    raise AssertionError("key reduction did not converge")  # pragma: no cover


def _uniform_keys(m: _Motion, ch: _Channel, f, fd, tol, check_t, check_v, start: int) -> int:
    """The smallest number of evenly spaced keys meeting the same bound (doubling, then
    bisection), capped at 8× the adaptive count."""
    span = m.t1 - m.t0

    def ok(n):
        kt = np.unique(np.minimum(_f32(np.linspace(0, span, n)), _f32_floor(span)))
        v = f(kt)
        a, b = _tangents(fd, kt, span) if ch.cubic else (v, v)
        if ch.rot:
            sgn = np.sign(np.sum(_sign_continuous(v) * v, axis=1))[:, None]
            v, a, b = v * sgn, a * sgn, b * sgn
        e = ch.err(kt, _f32(v), _f32(a), _f32(b), check_t, check_v)
        return e.max() <= tol

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

    def summary(self) -> str:
        deg = np.degrees
        s = (
            f"{self.path}: {self.interpolation}, {self.duration:.6g} s; rotation "
            f"{self.rotation_keys} keys (uniform needs {self._u(self.rotation_uniform_keys)}), "
            f"max error {deg(self.rotation_error):.3g}° ≤ {deg(self.rotation_bound):.3g}°"
        )
        if self.translation_keys:
            s += (
                f"; translation {self.translation_keys} keys (uniform needs "
                f"{self._u(self.translation_uniform_keys)}), max error "
                f"{self.translation_error:.3g} m ≤ {self.translation_bound:.3g} m"
            )
        return s + f" (checked at {self.check_points} times)"

    @staticmethod
    def _u(n):
        return str(n) if n > 0 else "more than 8×"


def _axes_mesh(size: float):
    """Three boxes along +x, +y, +z (red, green, blue), 8 vertices and 12 triangles each."""
    w = size * 0.04
    prims = []
    for k in range(3):
        lo, hi = np.full(3, -w), np.full(3, w)
        hi[k] = size
        c = np.array(
            [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
        )
        faces = [
            (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
            (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),
        ]  # fmt: skip
        prims.append((c.astype(np.float32), np.array(faces, dtype=np.uint16).ravel()))
    return prims


class _Builder:
    def __init__(self):
        self.blob = bytearray()
        self.views, self.accessors = [], []

    def add(self, arr: np.ndarray, kind: str, target=None, minmax: bool = False) -> int:
        arr = np.ascontiguousarray(arr)
        while len(self.blob) % 4:
            self.blob.append(0)
        view = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": arr.nbytes}
        if target:
            view["target"] = target
        self.blob += arr.tobytes()
        self.views.append(view)
        comp = {np.dtype(np.float32): 5126, np.dtype(np.uint16): 5123}[arr.dtype]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[kind]
        acc = {
            "bufferView": len(self.views) - 1,
            "componentType": comp,
            "count": int(arr.size // width),
            "type": kind,
        }
        if minmax:
            a2 = arr.reshape(-1, width)
            acc["min"] = [float(x) for x in a2.min(axis=0)]
            acc["max"] = [float(x) for x in a2.max(axis=0)]
        self.accessors.append(acc)
        return len(self.accessors) - 1


def _write_file(path: Path, doc: dict, blob: bytes) -> None:
    if path.suffix.lower() == ".gltf":
        doc["buffers"] = [
            {
                "byteLength": len(blob),
                "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode(),
            }
        ]
        with atomic_write(path, encoding="utf-8") as f:
            json.dump(doc, f, separators=(",", ":"))
        return
    doc["buffers"] = [{"byteLength": len(blob)}]
    js = json.dumps(doc, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    bin_ = bytes(blob) + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(js) + 8 + len(bin_)
    with atomic_write(path, mode="wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(js), b"JSON") + js)
        f.write(struct.pack("<I4s", len(bin_), b"BIN\0") + bin_)


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
    method: str = "c3",
    uniform: bool = True,
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
        The animated node's name.
    mesh : {"axes", None}
        A small red/green/blue axes mesh of length ``size`` (metres), or an empty node.
    samples : int, optional
        Candidate key times (default: 16 per spline segment, at least 2000, at most 200000);
        the bound is verified on a grid four times denser.
    uniform : bool
        Also find how many evenly spaced keys the same bound needs (for the report).

    Returns
    -------
    GltfReport
        Keys used, the uniform count, the measured maximum errors and the bounds.

    Raises
    ------
    ValueError
        A bound that is not positive or cannot be parsed, an unknown interpolation.
    TypeError
        A motion of the wrong kind.

    Examples
    --------
    >>> import numpy as np, tempfile, os, quatspline as qs
    >>> q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    >>> s = qs.C3Spline(q, np.arange(6.0))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     r = to_gltf(s, os.path.join(d, "m.glb"), max_error="0.1deg", progress=False)
    >>> r.rotation_error <= r.rotation_bound, r.rotation_keys < r.rotation_uniform_keys
    (True, True)
    """
    tol_r = parse_angle(max_error, "max_error")
    tol_p = parse_length(max_position_error, "max_position_error")
    if interpolation not in ("linear", "cubicspline"):
        raise ValueError(
            f"interpolation: expected 'linear' or 'cubicspline', got {interpolation!r}"
        )
    if mesh not in ("axes", None):
        raise ValueError(f"mesh: expected 'axes' or None, got {mesh!r}")
    if not isinstance(node, str) or not node:
        raise ValueError("node: expected a non-empty name")
    path = Path(path)
    if path.suffix.lower() not in (".glb", ".gltf"):
        raise ValueError(f"{path}: expected a .glb or .gltf output")
    m = _Motion(motion, method, params)
    cubic = interpolation == "cubicspline"
    span = m.t1 - m.t0
    if samples is None:
        samples = int(min(max(16 * (len(m.joints) - 1), 2000), 200_000))
    if not (isinstance(samples, (int, np.integer)) and 2 <= samples <= 5_000_000):
        raise ValueError(f"samples: expected an integer in [2, 5000000], got {samples!r}")

    from ._progress import progress as bar

    chans = [("rotation", m.q, m.dq, tol_r, True)]
    if m.pos is not None:
        chans.append(("translation", m.p, m.dp, tol_p, False))
    t = _candidate_times(m, samples)
    check_t = _dense(t)
    results = {}
    with bar(total=len(chans) * (2 if uniform else 1), desc="export glTF", enabled=progress) as pb:
        for name, f, fd, tol, rot in chans:
            v = f(t)
            a, b = _tangents(fd, t, span)
            if rot:
                sgn = np.sign(np.sum(_sign_continuous(v) * v, axis=1))[:, None]
                v, a, b = v * sgn, a * sgn, b * sgn
            ch = _Channel(rot, cubic, t, v, a, b)
            check_v = f(check_t)
            keys, err = _fit(ch, tol, check_t, check_v)
            pb.update(1)
            nu = 0
            if uniform:
                nu = _uniform_keys(m, ch, f, fd, tol, check_t, check_v, len(keys))
                pb.update(1)
            results[name] = (ch, keys, err, nu, tol)

    b = _Builder()
    doc: dict = {
        "asset": {"version": "2.0", "generator": "quatspline"},
        "scene": 0,
        "scenes": [{"name": m.name or "quatspline", "nodes": [0]}],
        "nodes": [{"name": node}],
    }
    if mesh == "axes":
        colours = ([0.84, 0.15, 0.16, 1.0], [0.17, 0.63, 0.17, 1.0], [0.12, 0.47, 0.71, 1.0])
        prims = []
        for k, (pts, idx) in enumerate(_axes_mesh(float(size))):
            pa = b.add(pts, "VEC3", target=34962, minmax=True)
            ia = b.add(idx, "SCALAR", target=34963)
            prims.append({"attributes": {"POSITION": pa}, "indices": ia, "material": k})
        doc["materials"] = [
            {"name": f"axis {'xyz'[k]}", "pbrMetallicRoughness": {"baseColorFactor": c}}
            for k, c in enumerate(colours)
        ]
        doc["meshes"] = [{"name": "axes", "primitives": prims}]
        doc["nodes"][0]["mesh"] = 0
    channels, samplers = [], []
    for name, (ch, keys, _, _, _) in results.items():
        idx = np.array(keys)
        kt, kv, ka, kb = ch.t[idx], ch.v[idx], ch.a[idx], ch.b[idx]
        if ch.rot:
            kv, ka, kb = kv[:, [1, 2, 3, 0]], ka[:, [1, 2, 3, 0]], kb[:, [1, 2, 3, 0]]
        if cubic:
            out = np.stack([ka, kv, kb], axis=1).reshape(-1, kv.shape[1])
        else:
            out = kv
        ia = b.add(kt.astype(np.float32), "SCALAR", minmax=True)
        oa = b.add(out.astype(np.float32), "VEC4" if ch.rot else "VEC3")
        samplers.append({"input": ia, "output": oa, "interpolation": interpolation.upper()})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": 0, "path": name}})
        first = kv[0].astype(np.float32).astype(float).tolist()
        doc["nodes"][0][name] = first
    doc["animations"] = [{"name": m.name or "motion", "channels": channels, "samplers": samplers}]
    doc["accessors"], doc["bufferViews"] = b.accessors, b.views
    _write_file(path, doc, bytes(b.blob))
    r = results["rotation"]
    rep = GltfReport(
        str(path),
        interpolation,
        float(span),
        len(r[1]),
        r[3],
        r[2],
        r[4],
        check_points=len(check_t),
    )
    if "translation" in results:
        p = results["translation"]
        rep.translation_keys, rep.translation_uniform_keys = len(p[1]), p[3]
        rep.translation_error, rep.translation_bound = p[2], p[4]
    return rep


def to_bvh(trajectory, path, **options) -> None:
    """Writes a trajectory as a BVH joint (see :mod:`quatspline.io.bvh`)."""
    from .io import bvh

    bvh.write(Path(path), trajectory, **options)
