"""Attitude design as data: one call gives everything a designer looks at for a set of keys.

:func:`evaluate` builds a registry method through keys at times with the given parameters and
returns the sampled motion, the sizes of the angular velocity, acceleration and jerk, the
continuity certificate at every joint and the exact Python call that reproduces the curve.
The browser viewer (``quatspline view``) only calls these functions; they are equally usable
from a notebook.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from .. import _core
from .. import io as qio
from .._util import checks as _checks
from .._util.arrays import as_real, as_times
from .._util.errors import ParameterError
from .._util.options import parse_smoothing
from ..core.algebra import normalize
from ..registry import (
    METHODS,
    Param,
    flag,
    float_or_auto,
    float_or_none,
    int_or_none,
    rates_spec,
    smoothing_spec,
    spline,
    str_or_none,
)
from ..splines.joints import continuity
from ._export import to_gltf
from ._sample import evaluate as evaluate_samples
from ._sample import sample_times

__all__ = [
    "EXPORT_OPTIONS",
    "MAX_DESIGN_KEYS",
    "MAX_DESIGN_SAMPLES",
    "evaluate",
    "export_bytes",
    "method_specs",
    "python_call",
    "to_json",
]

#: Limits of one design evaluation (the viewer refuses larger requests before any work).
MAX_DESIGN_KEYS = 5_000
MAX_DESIGN_SAMPLES = 20_000
#: The glTF options an export may set, each with its range or choices; nothing else reaches
#: :func:`quatspline.ops.to_gltf`. ``max_error`` is in degrees, ``size`` in metres.
EXPORT_OPTIONS: dict[str, tuple] = {
    "max_error": (1e-3, 10.0),
    "size": (1e-3, 1e3),
    "interpolation": ("linear", "cubicspline"),
    "mesh": ("axes", None),
    "node": (1, 64),
}


def method_specs() -> list[dict]:
    """Every registry method with its parameters, in a form a user interface can render.

    Returns
    -------
    list of dict
        ``name``, ``summary``, ``interpolating``, ``continuity`` and ``params``: a list of
        ``{"name", "kind", "per", "default", "help", "choices"}`` where ``kind`` is
        ``"float"``, ``"int"``, ``"bool"`` or ``"str"``, ``per`` is ``"key"`` or
        ``"key/segment"`` for a shape parameter that also takes a list of one value per key
        (per segment; None otherwise) and ``choices`` lists the valid strings (or None).

    Examples
    --------
    >>> from quatspline.ops.design import method_specs
    >>> c3 = next(m for m in method_specs() if m["name"] == "c3")
    >>> [(p["name"], p["kind"]) for p in c3["params"]]
    [('alpha', 'float'), ('beta', 'float'), ('variant', 'str'), ('ends', 'str'), ('holds', 'bool')]
    """
    return [
        {
            "name": m.name,
            "summary": m.summary,
            "interpolating": m.interpolating,
            "continuity": m.continuity,
            "params": [_param_spec(name, p) for name, p in m.params.items()],
        }
        for m in METHODS.values()
    ]


def _param_spec(name: str, p: Param) -> dict:
    default = p.default
    if isinstance(default, float) and not math.isfinite(default):
        default = None
    return {
        "name": name,
        "kind": p.kind,
        # "key" or "key/segment": one value, or a list of one per key (segment)
        "per": p.per,
        "default": default,
        "help": p.help,
        # the row's named choices (Hermite rates: the estimates only; a design reads no
        # files, arrays come from the Python API)
        "choices": list(p.choices) if p.choices is not None else None,
    }


def _check_keys(quats, times) -> tuple[np.ndarray, np.ndarray]:
    """Keys and times as float arrays: real numbers of the right shapes (a ``TypeError`` for
    strings or objects, a ``ValueError`` naming the first bad element), finite, non-zero keys
    (returned normalised), strictly increasing times in the core's range."""
    if quats is None:
        raise TypeError("quats: missing (expected an (N, 4) array of numbers)")
    if times is None:
        raise TypeError("times: missing (expected N increasing numbers)")
    q = as_real(quats, "quats")
    t = as_times(times, "times")
    if q.ndim != 2 or q.shape[1] != 4:
        raise ValueError(f"quats: expected shape (N, 4), got {q.shape}")
    if t.shape != (len(q),):
        raise ValueError(f"times: expected shape ({len(q)},), got {t.shape}")
    if not 2 <= len(q) <= MAX_DESIGN_KEYS:
        raise ValueError(f"quats: expected 2 … {MAX_DESIGN_KEYS} keys, got {len(q)}")
    bad = ~np.all(np.isfinite(q), axis=1)
    if bad.any():
        raise ValueError(f"quats[{int(np.argmax(bad))}]: not finite")
    tiny = np.max(np.abs(q), axis=1) < np.finfo(float).tiny
    if tiny.any():
        raise ValueError(f"quats[{int(np.argmax(tiny))}]: zero (or denormal) quaternion")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"times[{int(np.argmax(~np.isfinite(t)))}]: not finite")
    with np.errstate(over="ignore", invalid="ignore"):  # ±1e308 steps: refused just below
        d = np.diff(t)
    if np.any(d <= 0):
        k = int(np.argmax(d <= 0)) + 1
        raise ValueError(
            f"times[{k}]: key times must increase ({t[k]:g} is not after {t[k - 1]:g})"
        )
    _core.check_times(np.ascontiguousarray(t), len(q))  # range and spacing, as every spline
    return normalize(q), t


def _param_value(method: str, name: str, value):
    """One parameter of ``method`` checked against the kind its converter declares: a
    ``TypeError`` for a value of another kind (a string or list for a number, a number for a
    flag), a ``ValueError`` naming it for a bad value. Never a file name: Hermite rates are
    ``"bessel"``, ``"zero"`` or an (N, 3) array (a design reads no files)."""
    spec = METHODS[method].params[name]
    conv = spec.type
    label = f"params.{name}"
    if spec.per is not None and isinstance(value, (list, tuple)):
        # one value per key (segment): each element a number; the count is the registry's
        return [_checks.real(x, f"{label}[{k}]") for k, x in enumerate(value)]
    if value is None and conv in (float_or_none, int_or_none, str_or_none):
        return None
    if conv in (float, float_or_none):
        return _checks.real(value, label)
    if conv is smoothing_spec:  # fit's λ: the page sends what was typed
        return parse_smoothing(value, label)
    if conv is float_or_auto:
        if isinstance(value, str):
            if value.strip().lower() == "auto":
                return "auto"
            raise TypeError(f"{label}: expected a number or 'auto', got str {value!r}")
        elif isinstance(value, (bool, np.bool_)) or not isinstance(
            value, (int, float, np.integer, np.floating)
        ):
            raise TypeError(f"{label}: expected a number or 'auto', got {type(value).__name__}")
        return _checks.real(value, label)
    if conv in (int, int_or_none):
        return _checks.integer(value, label, -(2**31), 2**31 - 1)
    if conv is flag:
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{label}: expected true or false, got {type(value).__name__}")
        return bool(value)
    if conv in (str, str_or_none):
        if not isinstance(value, str):
            raise TypeError(f"{label}: expected a string, got {type(value).__name__}")
        return value
    if conv is rates_spec:
        if isinstance(value, str):
            if value not in ("bessel", "zero"):
                raise ValueError(
                    f"{label}: expected 'bessel', 'zero' or an (N, 3) array of rates, got "
                    f"{value[:40]!r} (a design reads no files)"
                )
            return value
        r = as_real(value, label)
        if r.ndim != 2 or r.shape[1] != 3:
            raise ValueError(f"{label}: expected an (N, 3) array of rates, got shape {r.shape}")
        if not np.all(np.isfinite(r)):
            raise ValueError(f"{label}: not finite")
        return r.tolist()
    return value  # pragma: no cover - a converter this check does not know: the registry's


def _check_params(method, params) -> dict:
    """``params`` as a dict of the method's own parameters (a ValueError names any other)."""
    if not isinstance(method, str):
        raise TypeError(f"method: expected a string, got {type(method).__name__}")
    if method not in METHODS:
        raise ParameterError(f"method: unknown method {method!r}; valid: {', '.join(METHODS)}")
    if params is None:
        return {}
    if not isinstance(params, dict):
        raise TypeError(f"params: expected a dict, got {type(params).__name__}")
    valid = METHODS[method].params
    unknown = sorted(str(k) for k in params if k not in valid)
    if unknown:
        raise ParameterError(
            f"params: unknown parameter{'s' if len(unknown) > 1 else ''} of {method}: "
            f"{', '.join(unknown)}; valid: {', '.join(valid) or 'none'}"
        )
    return {name: _param_value(method, name, v) for name, v in params.items()}


def _check_work(method: str, params: dict, t: np.ndarray) -> None:
    """Refuses parameters that would make one design much larger than its keys: a ``fit``
    knot spacing giving more than :data:`MAX_DESIGN_KEYS` knot intervals."""
    spacing = params.get("knots")
    if method != "fit" or spacing is None or isinstance(spacing, (bool, str)):
        return  # anything else is the registry's to check (and refuse)
    if not isinstance(spacing, (int, float, np.integer, np.floating)):
        return
    span = float(t[-1] - t[0])
    if spacing > 0 and math.isfinite(spacing) and span / spacing > MAX_DESIGN_KEYS:
        raise ValueError(
            f"knots: spacing {float(spacing):g} gives {span / spacing:.4g} knot intervals; a "
            f"design has at most {MAX_DESIGN_KEYS} (quatspline.fit has no such limit)"
        )


def _check_samples(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
        raise TypeError(f"samples: expected an integer, got {type(samples).__name__}")
    if not 2 <= samples <= MAX_DESIGN_SAMPLES:
        raise ValueError(f"samples: expected 2 … {MAX_DESIGN_SAMPLES}, got {samples}")
    return int(samples)


def _check_options(options) -> dict:
    """The glTF options of an export, each checked against :data:`EXPORT_OPTIONS`."""
    if options is None:
        return {}
    if not isinstance(options, dict):
        raise TypeError(f"options: expected a dict, got {type(options).__name__}")
    unknown = sorted(str(k) for k in options if k not in EXPORT_OPTIONS)
    if unknown:
        raise ValueError(
            f"options: unknown glTF option{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(unknown)}; valid: {', '.join(EXPORT_OPTIONS)}"
        )
    out = {}
    for name, v in options.items():
        rule = EXPORT_OPTIONS[name]
        if name == "node":
            if not isinstance(v, str):
                raise TypeError(f"options.node: expected a string, got {type(v).__name__}")
            if not rule[0] <= len(v) <= rule[1]:
                raise ValueError(f"options.node: expected {rule[0]} … {rule[1]} characters")
        elif isinstance(rule[0], float):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise TypeError(f"options.{name}: expected a number, got {type(v).__name__}")
            if not rule[0] <= v <= rule[1]:
                raise ValueError(f"options.{name}: expected {rule[0]:g} … {rule[1]:g}, got {v!r}")
            v = float(v)
        elif v not in rule:
            choices = ", ".join("null" if c is None else c for c in rule)
            raise ValueError(f"options.{name}: expected one of {choices}, got {v!r}")
        out[name] = v
    return out


def _fmt(x) -> str:
    if isinstance(x, (bool, np.bool_)):
        return "True" if x else "False"
    if isinstance(x, (float, np.floating)):
        return repr(float(x))
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_fmt(v) for v in x) + "]"
    return repr(x)


def python_call(method: str, quats, times, params: dict | None = None) -> str:
    """The Python code that builds exactly this curve.

    Parameters
    ----------
    method : str
        Registry method name.
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z).
    times : array_like, shape (N,)
        Key times.
    params : dict, optional
        The method's parameters.

    Returns
    -------
    str
        A runnable snippet ending in ``s = qs.spline(...)``.

    Examples
    --------
    >>> from quatspline.ops.design import python_call
    >>> code = python_call("c3", [[1, 0, 0, 0], [0, 0, 0, 1]], [0, 1], {"alpha": 0.25})
    >>> namespace = {}
    >>> exec(code, namespace)
    >>> namespace["s"].method
    'c3'
    """
    q = np.asarray(quats, dtype=float)
    t = np.asarray(times, dtype=float)
    rows = ",\n    ".join("[" + ", ".join(repr(float(v)) for v in r) + "]" for r in q)
    args = "".join(f", {k}={_fmt(v)}" for k, v in (params or {}).items())
    return (
        "import numpy as np\nimport quatspline as qs\n\n"
        f"keys = np.array([\n    {rows},\n])\n"
        f"times = np.array([{', '.join(repr(float(v)) for v in t)}])\n"
        f"s = qs.spline({method!r}, keys, times{args})\n"
    )


def evaluate(
    method: str,
    quats,
    times,
    params: dict | None = None,
    samples: int = 2000,
) -> dict:
    """Samples one design: motion, rate sizes, continuity certificate and the Python call.

    Parameters
    ----------
    method : str
        Registry method name (see :data:`quatspline.METHODS`).
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z), 2 ≤ N ≤ :data:`MAX_DESIGN_KEYS`.
    times : array_like, shape (N,)
        Strictly increasing key times.
    params : dict, optional
        The method's parameters (unknown names are a ``ValueError`` listing the valid ones).
    samples : int, default 2000
        Number of evenly spaced samples over the domain, 2 … :data:`MAX_DESIGN_SAMPLES`.

    Returns
    -------
    dict
        ``t`` (M,), ``quats`` (M, 4), ``omega`` (M, 3): the world-frame angular velocity,
        ``speed``, ``acceleration``, ``jerk`` (M,): the norms of the world-frame angular
        velocity, acceleration and jerk; ``joints``: one dict per
        interior joint (``time``, ``order``, ``jumps``: relative jumps of q … q'''),
        ``continuity`` (the method's guaranteed order), ``interpolates``, ``key_times``,
        ``domain`` and ``python`` (the code that reproduces the curve). Arrays are numpy
        arrays; :func:`to_json` makes them lists.

    Raises
    ------
    ValueError
        Bad keys, times, method, parameters or sample count (the message names which).

    Examples
    --------
    >>> import quatspline as qs
    >>> from quatspline.ops.design import evaluate
    >>> keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [90, 0, 90]], degrees=True)
    >>> d = evaluate("c3", keys, [0.0, 1.0, 2.0], {"alpha": 0.3}, samples=5)
    >>> d["t"].tolist(), [j["order"] for j in d["joints"]]
    ([0.0, 0.5, 1.0, 1.5, 2.0], [3])
    """
    q, t = _check_keys(quats, times)
    samples = _check_samples(samples)
    params = _check_params(method, params)
    _check_work(method, params, t)
    s = spline(method, q, t, **params)
    a, b = s.domain
    # the one sampling route of ops (the times and the evaluation `quatspline sample` uses)
    ts = sample_times((a, b), count=int(samples))
    qs_, _, rates = evaluate_samples(s, ts, derivatives=True)
    w, acc, jerk = (np.linalg.norm(rates[k], axis=1) for k in ("omega", "alpha", "jerk"))
    key_quats = s(np.clip(t, a, b))
    joints = [
        {
            "time": float(j.time),
            "order": int(j.order),
            "jumps": [float(x) for x in np.asarray(j.jump_rel, dtype=float)],
        }
        for j in continuity(s)
    ]
    c = s.continuity
    return {
        "method": method,
        "params": params,
        "t": ts,
        "quats": qs_,
        "omega": rates["omega"],
        "speed": w,
        "acceleration": acc,
        "jerk": jerk,
        "joints": joints,
        "continuity": None if c == float("inf") else int(c),
        "interpolates": bool(s.interpolates),
        "key_times": t,
        "key_quats": key_quats,
        "domain": [float(a), float(b)],
        "python": python_call(method, q, t, params),
    }


def to_json(d: dict) -> dict:
    """``d`` with numpy arrays as lists and non-finite numbers as None (valid JSON)."""

    def conv(x):
        if isinstance(x, np.ndarray):
            if x.dtype.kind == "f" and np.all(np.isfinite(x)):
                return x.tolist()  # the common case, without visiting every element
            return conv(x.tolist())
        if isinstance(x, dict):
            return {k: conv(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [conv(v) for v in x]
        if isinstance(x, (float, np.floating)):
            return float(x) if math.isfinite(x) else None
        if isinstance(x, np.integer):
            return int(x)
        return x

    return conv(d)


def export_bytes(
    fmt: str,
    method: str,
    quats,
    times,
    params: dict | None = None,
    samples=2000,
    options: dict | None = None,
):
    """One design as the bytes of a file: ``"csv"`` or ``"json"`` (the sampled motion, with
    ω, α and jerk columns), ``"glb"`` (a glTF 2.0 animation within 0.01° of the curve) or
    ``"keys"`` (the keys themselves as a JSON trajectory, to open again).

    Parameters
    ----------
    fmt : {"csv", "json", "glb", "keys"}
    method, quats, times, params, samples
        As for :func:`evaluate`; ``params`` are the method's own parameters only.
    options : dict, optional
        glTF options (``fmt="glb"`` only): the names and ranges of :data:`EXPORT_OPTIONS`;
        any other name is a ``ValueError`` naming it.

    Returns
    -------
    bytes

    Examples
    --------
    >>> from quatspline.ops.design import export_bytes
    >>> blob = export_bytes("csv", "slerp", [[1, 0, 0, 0], [0, 0, 0, 1]], [0, 1], samples=3)
    >>> blob.decode().splitlines()[0].split(",")[:5]
    ['t', 'qw', 'qx', 'qy', 'qz']
    """
    if fmt not in ("csv", "json", "glb", "keys"):
        raise ValueError(f"format: expected csv, json, glb or keys, got {fmt!r}")
    q, t = _check_keys(quats, times)
    params = _check_params(method, params)
    _check_work(method, params, t)
    samples = _check_samples(samples)
    if options is not None and fmt != "glb":
        raise ValueError(f"options: glTF options apply to format glb only, not {fmt}")
    options = _check_options(options)
    # the keys were checked as every spline checks them (and normalised), so the keys file
    # holds exactly the keys the design uses and opens again
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / ("keys.json" if fmt == "keys" else f"design.{fmt}")
        if fmt == "keys":
            qio.write(path, qio.Trajectory(t, q))
        elif fmt == "glb":
            to_gltf(spline(method, q, t, **params), path, progress=False, **options)
        else:
            s = spline(method, q, t, **params)
            ts = np.linspace(*s.domain, samples)
            extra = {
                "omega": s.angular_velocity(ts),
                "alpha": s.angular_acceleration(ts),
                "jerk": s.jerk(ts),
            }
            qio.write(path, qio.Trajectory(ts, s(ts), extra=extra))
        return path.read_bytes()
