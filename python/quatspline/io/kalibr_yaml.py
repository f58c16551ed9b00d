"""Kalibr's IMU noise file (``imu.yaml``), read and written (PyYAML,
``pip install 'quatspline[imu]'``)::

    accelerometer_noise_density: 1.86e-03  # [m/s^2/sqrt(Hz)]   white noise
    accelerometer_random_walk: 4.33e-04    # [m/s^3/sqrt(Hz)]   bias random walk
    gyroscope_noise_density: 1.87e-04      # [rad/s/sqrt(Hz)]   white noise
    gyroscope_random_walk: 2.66e-05        # [rad/s^2/sqrt(Hz)] bias random walk
    rostopic: /imu0
    update_rate: 200.0                     # [Hz]

The four densities are continuous-time (Kalibr's convention: a discrete sample at rate f has
white-noise standard deviation density·√f and its bias steps random_walk/√f); each must be
a finite number ≥ 0, and ``update_rate`` a finite number > 0. They may also stand one level
down, under an ``imu0``/``imu1`` … key (Kalibr's IMU chain files, OpenVINS'
``kalibr_imu_chain.yaml``, whose OpenCV ``%YAML:1.0`` first line is skipped); ``imu=``
chooses one when there are several. ``rostopic`` is optional; other keys (``T_i_b``,
``time_offset``, …) are ignored.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping

from .._util.atomic import atomic_write
from .._util.optional import need
from ._common import open_regular, plain_number
from .trajectory import TrajectoryError

#: The keys read and written, with their units (for the written comments).
KEYS = {
    "accelerometer_noise_density": "m/s^2/sqrt(Hz)",
    "accelerometer_random_walk": "m/s^3/sqrt(Hz)",
    "gyroscope_noise_density": "rad/s/sqrt(Hz)",
    "gyroscope_random_walk": "rad/s^2/sqrt(Hz)",
    "update_rate": "Hz",
}
#: Largest file read: an imu.yaml is a few hundred bytes.
MAX_BYTES = 1 << 20
_IMU_KEY = re.compile(r"imu\d+$")


def _yaml():
    return need("yaml", extra="imu", what="reading and writing imu.yaml")


def read(path, imu: str | None = None) -> dict:
    """The noise parameters of a Kalibr ``imu.yaml``: a dict of the four densities,
    ``update_rate`` (floats) and ``rostopic`` (when the file has one). See the module."""
    yaml = _yaml()
    with open_regular(path, "rb") as f:
        raw = f.read(MAX_BYTES + 1)
    if len(raw) > MAX_BYTES:
        raise TrajectoryError(f"{path}: larger than {MAX_BYTES} bytes; not an imu.yaml")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise TrajectoryError(f"{path}: not a text file ({e.reason} at byte {e.start})") from None
    if text.startswith("%YAML:"):  # OpenCV's directive, not YAML's: a comment to PyYAML
        text = "#" + text
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
        doc = yaml.load(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark else f"{path}"
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise TrajectoryError(f"{where}: not YAML ({problem})") from None
    except RecursionError:
        raise TrajectoryError(f"{path}: not an imu.yaml (nested too deeply)") from None
    if not isinstance(doc, dict):
        raise TrajectoryError(
            f"{path}: not an imu.yaml (expected a mapping of noise parameters, got "
            f"{type(doc).__name__})"
        )
    doc, node, prefix = _choose(path, doc, root, imu)
    missing = [k for k in KEYS if k not in doc]
    if missing:
        raise TrajectoryError(f"{path}: missing {', '.join(missing)}{prefix}")
    out: dict = {}
    for key in KEYS:
        where = f"{path}:{_line(node, key)}"
        out[key] = _number(where, key, doc[key])
    if "rostopic" in doc:
        topic = doc["rostopic"]
        if not isinstance(topic, str):
            raise TrajectoryError(
                f"{path}:{_line(node, 'rostopic')}: rostopic: expected text, got "
                f"{type(topic).__name__} {topic!r:.40}"
            )
        out["rostopic"] = topic
    return out


def _choose(path, doc: dict, root, imu):
    """The mapping holding the parameters: the document itself, or its ``imuN`` entry."""
    if imu is None and any(k in doc for k in KEYS):
        return doc, root, ""
    chains = [k for k in doc if isinstance(k, str) and _IMU_KEY.match(k)]
    if imu is None:
        if len(chains) != 1:
            if not chains:
                raise TrajectoryError(
                    f"{path}: missing {', '.join(KEYS)} (not an imu.yaml, nor an IMU chain "
                    "with imu0 …)"
                )
            raise TrajectoryError(
                f"{path}: holds several IMUs ({', '.join(chains)}); choose one with imu="
            )
        imu = chains[0]
    if not isinstance(imu, str):
        raise TypeError(f"imu: expected a string such as 'imu0', got {type(imu).__name__}")
    if imu not in doc:
        raise ValueError(f"imu: {path} has no {imu!r}; it has {', '.join(chains) or 'none'}")
    sub = doc[imu]
    if not isinstance(sub, dict):
        raise TrajectoryError(f"{path}:{_line(root, imu)}: {imu}: expected a mapping")
    return sub, _child(root, imu), f" under {imu}"


def _child(node, key):
    for k, v in getattr(node, "value", []) if _is_mapping(node) else []:
        if getattr(k, "value", None) == key:
            return v
    return None


def _is_mapping(node) -> bool:
    return type(node).__name__ == "MappingNode"


def _line(node, key) -> str:
    """The line (and column) of ``key``'s value in the composed document."""
    if _is_mapping(node):
        for k, v in node.value:
            if getattr(k, "value", None) == key:
                m = v.start_mark
                return f"{m.line + 1}:{m.column + 1}"
    return "1"


def _number(where: str, key: str, value) -> float:
    """A parameter as a float: a number, or text that is one (PyYAML reads ``1e-3``,
    without a dot, as text); ≥ 0 and finite, ``update_rate`` > 0."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, str)):
        raise TrajectoryError(
            f"{where}: {key}: expected a number, got {type(value).__name__} {value!r:.40}"
        )
    if isinstance(value, str):
        try:
            x = float(plain_number(value.strip()))
        except ValueError:
            raise TrajectoryError(f"{where}: {key}: not a number: {value[:40]!r}") from None
    else:
        x = float(value)
    if not math.isfinite(x):
        raise TrajectoryError(f"{where}: {key}: not finite ({x!r})")
    if key == "update_rate" and x <= 0:
        raise TrajectoryError(f"{where}: {key}: expected a rate > 0 Hz, got {x!r}")
    if x < 0:
        raise TrajectoryError(f"{where}: {key}: a noise density cannot be negative, got {x!r}")
    return x


def _value(noise, key: str):
    """``noise``'s ``key`` (a mapping's item or an object's attribute), or None."""
    if isinstance(noise, Mapping):
        return noise.get(key)
    return getattr(noise, key, None)


def parameters(noise, update_rate=None) -> dict:
    """The five parameters of ``noise`` (a mapping, or any object with the four densities as
    attributes; ``update_rate`` from the argument, else from ``noise``) as checked floats; a
    one-line error names a missing, non-numeric, negative or non-finite one."""
    out = {}
    for key in KEYS:
        v = update_rate if key == "update_rate" and update_rate is not None else _value(noise, key)
        if v is None:
            if key == "update_rate":
                raise ValueError(
                    "update_rate: needed (the sample rate the densities are given for); pass "
                    "update_rate="
                )
            kind = "mapping" if isinstance(noise, Mapping) else type(noise).__name__
            raise (ValueError if isinstance(noise, Mapping) else TypeError)(
                f"noise: missing {key!r} (the {kind} holds no {key})"
            )
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise TypeError(f"{key}: expected a number, got {type(v).__name__}")
        try:
            out[key] = _number(key, key, v)
        except TrajectoryError as e:
            raise ValueError(str(e).split(": ", 1)[1]) from None
    return out


def write(path, noise, rostopic: str | None = None, update_rate: float | None = None) -> None:
    """Writes a Kalibr ``imu.yaml`` atomically. ``noise``: a mapping or any object with the
    four densities (and ``update_rate``, unless given here); ``rostopic``: the topic written
    (else the noise's own ``rostopic``, else ``/imu0``). Values are written so that they
    read back exactly."""
    values = parameters(noise, update_rate)
    if rostopic is None:
        rostopic = _value(noise, "rostopic")
    rostopic = "/imu0" if rostopic is None else rostopic
    if not isinstance(rostopic, str):
        raise TypeError(f"rostopic: expected a string, got {type(rostopic).__name__}")
    lines = ["# IMU noise parameters, Kalibr convention (continuous-time densities)\n"]
    for key, unit in KEYS.items():
        if key == "update_rate":
            lines.append(f"rostopic: {_text(rostopic)}\n")
        lines.append(f"{key}: {_float(values[key])}  # [{unit}]\n")
    with atomic_write(path, encoding="utf-8") as f:
        f.writelines(lines)


def _float(x: float) -> str:
    """The shortest repr of ``x`` in a form YAML 1.1 (PyYAML, Kalibr) reads as a float:
    with a dot in the mantissa (``1e-05`` would be text, ``1.0e-05`` is a float)."""
    s = repr(float(x))
    mantissa, e, exponent = s.partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    return mantissa + e + exponent


def _text(s: str) -> str:
    """A topic as a YAML scalar: bare when it is a plain ROS name, else double-quoted with
    quotes, backslashes and unprintable characters escaped."""
    if re.fullmatch(r"/?[A-Za-z_][A-Za-z0-9_/]*", s):
        return s
    return '"' + "".join(map(_char, s)) + '"'


def _char(c: str) -> str:
    if c.isprintable() and c not in '"\\':
        return c
    return f"\\u{ord(c):04x}" if ord(c) < 0x10000 else f"\\U{ord(c):08x}"
