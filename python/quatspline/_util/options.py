"""Option values from text: every string → value parser of the command line, batch and viewer.

A front end reads an option as text (``--smoothing 1e-3``, ``--max-error 0.5deg``,
``--param ends=closed``); the library takes values. Each conversion is written here once, so
that ``quatspline fit``, ``quatspline batch fit``, the viewer and the library accept the same
spellings and word their refusals the same way. Every parser also takes the value it produces
(a number for a number), so a library caller and a command line can share it.

A bad value is a :class:`~quatspline._util.errors.ParameterError` (a ``ValueError``) whose
message starts with the option's name and says what is allowed; a value of the wrong kind (a
list where text or a number is expected) is a ``TypeError``.
"""

from __future__ import annotations

import math
import numbers
import re

import numpy as np

from .errors import ParameterError

__all__ = [
    "ANGLE_UNITS",
    "DEFAULT_METHOD",
    "LENGTH_UNITS",
    "parse_angle",
    "parse_choice",
    "parse_length",
    "parse_list",
    "parse_pairs",
    "parse_positive_int",
    "parse_smoothing",
    "parse_spacing_or_file",
]

#: The method a spline through a recording's keys uses unless told otherwise: ``quatspline
#: sample``, ``plot``, ``export``, :func:`quatspline.ops.sample`, ``Trajectory.resample`` and
#: the rotation of ``PoseSpline``. The natural spline (C², scipy's ``RotationSpline``
#: construction): the most accurate method on held-out frames of three of the four bundled
#: recordings and within 2 % on the fourth (docs: Performance, "Accuracy on real recordings"),
#: continuous angular acceleration, no speed ripple at the keys. The C³ spline with its default
#: shape undershoots the speed at every key on dense recordings (5/8 of the chord speed); it is
#: the method for designed keys that need continuous jerk (``--method c3``, and the viewer's
#: first choice), with ``alpha="auto"`` for a ripple-free speed.
DEFAULT_METHOD = "natural"

#: Units of an angle (radians per unit); a bare number is in degrees.
ANGLE_UNITS = {
    "rad": 1.0,
    "mrad": 1e-3,
    "urad": 1e-6,
    "deg": math.pi / 180,
    "°": math.pi / 180,
    "arcmin": math.pi / 180 / 60,
    "arcsec": math.pi / 180 / 3600,
}
#: Units of a length (metres per unit); a bare number is in metres.
LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6}

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_WITH_UNIT = rf"\s*({_NUMBER})\s*([^\s\d.+-][^\s]*)?\s*"


def _is_real(value) -> bool:
    return isinstance(value, (numbers.Real, np.floating, np.integer)) and not isinstance(
        value, (bool, np.bool_)
    )


def _bound(value, name: str, units: dict, default_unit: str) -> float:
    if not (isinstance(value, str) or _is_real(value)):
        raise TypeError(f"{name}: expected a number or a string such as '0.01{default_unit}'")
    if isinstance(value, str):
        m = re.fullmatch(_WITH_UNIT, value)
        if not m or (m.group(2) is not None and m.group(2) not in units):
            raise ParameterError(
                f"{name}: cannot parse {value!r}; expected a number with a unit "
                f"({', '.join(units)}), e.g. '0.01{default_unit}'"
            )
        x = float(m.group(1)) * units[m.group(2) or default_unit]
    else:
        x = float(value) * units[default_unit]
    if not (math.isfinite(x) and x > 0):
        raise ParameterError(f"{name}: expected a positive finite bound, got {value!r}")
    return x


def parse_angle(value, name: str = "max_error") -> float:
    """A positive angle in radians from a number (degrees) or a string with a unit
    (``rad``, ``mrad``, ``urad``, ``deg``, ``°``, ``arcmin``, ``arcsec``).

    Examples
    --------
    >>> round(parse_angle("0.5deg"), 9), parse_angle("2mrad"), round(parse_angle(1.0), 9)
    (0.008726646, 0.002, 0.017453293)
    >>> parse_angle("1parsec", "--max-error")
    Traceback (most recent call last):
    ...
    quatspline.ops.ParameterError: --max-error: cannot parse '1parsec'; expected ...
    """
    return _bound(value, name, ANGLE_UNITS, "deg")


def parse_length(value, name: str = "max_position_error") -> float:
    """A positive length in metres from a number (metres) or a string with a unit
    (``m``, ``cm``, ``mm``, ``um``, ``µm``).

    Examples
    --------
    >>> parse_length("1mm"), parse_length(0.25)
    (0.001, 0.25)
    """
    return _bound(value, name, LENGTH_UNITS, "m")


def parse_smoothing(value, name: str = "smoothing"):
    """λ of a smoothing fit: ``"auto"`` (chosen from the data: by generalised
    cross-validation, locally adaptive where that lowers the GCV score), ``"gcv"`` (one λ by
    GCV), ``"adaptive"`` (a λ varying along the recording, always) — any case, blanks around
    them ignored — or a finite number ≥ 0, given as a number or as text.

    Returns
    -------
    "auto", "gcv", "adaptive" or float

    Examples
    --------
    >>> parse_smoothing("auto"), parse_smoothing(" AUTO "), parse_smoothing("1e-3")
    ('auto', 'auto', 0.001)
    >>> parse_smoothing("GCV"), parse_smoothing("adaptive")
    ('gcv', 'adaptive')
    >>> parse_smoothing(0)
    0.0
    >>> parse_smoothing("lots", "--smoothing")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    quatspline.ops.ParameterError: --smoothing: expected 'auto', 'gcv', 'adaptive' or a ... 'lots'
    """
    if isinstance(value, str):
        text = value.strip()
        if text.lower() in SMOOTHING_MODES:
            return text.lower()
        try:
            x = float(text)
        except ValueError:
            raise ParameterError(
                f"{name}: expected 'auto', 'gcv', 'adaptive' or a number ≥ 0, got {value!r}"
            ) from None
    elif _is_real(value):
        x = float(value)
    else:
        raise TypeError(f"{name}: expected a number or 'auto', got {type(value).__name__}")
    if not (math.isfinite(x) and x >= 0):
        raise ParameterError(f"{name}: expected 'auto' or a finite λ ≥ 0, got {x:.6g}")
    return x


#: The named choices of λ (:func:`parse_smoothing`).
SMOOTHING_MODES = ("auto", "gcv", "adaptive")


def parse_spacing_or_file(value, name: str = "knots"):
    """A positive spacing (a number, or text that reads as one), or else the name of a file
    (returned as given, for the caller to read).

    Examples
    --------
    >>> parse_spacing_or_file("0.1"), parse_spacing_or_file("knots.txt")
    (0.1, 'knots.txt')
    """
    if _is_real(value):
        x = float(value)
    elif isinstance(value, str):
        try:
            x = float(value.strip())
        except ValueError:
            if not value:
                raise ParameterError(f"{name}: expected a spacing or a file name, got ''") from None
            return value
    else:
        raise TypeError(f"{name}: expected a spacing or a file name, got {type(value).__name__}")
    if not (math.isfinite(x) and x > 0):
        raise ParameterError(f"{name}: expected a positive finite spacing, got {x:.6g}")
    return x


def parse_pairs(pairs, name: str = "--param") -> dict[str, str]:
    """``NAME=VALUE`` texts as a dict (names and values stripped; a later pair wins). The
    values stay text: each parameter's own converter reads its value.

    Examples
    --------
    >>> parse_pairs(["ends=closed", " alpha = 0.3"])
    {'ends': 'closed', 'alpha': '0.3'}
    >>> parse_pairs(["alpha"])
    Traceback (most recent call last):
    ...
    quatspline.ops.ParameterError: --param: expected name=value, got 'alpha'
    """
    out: dict[str, str] = {}
    for p in pairs or ():
        if not isinstance(p, str):
            raise TypeError(f"{name}: expected name=value text, got {type(p).__name__}")
        if "=" not in p:
            raise ParameterError(f"{name}: expected name=value, got {p!r}")
        k, v = p.split("=", 1)
        if not k.strip():
            raise ParameterError(f"{name}: expected name=value, got {p!r} (no name)")
        out[k.strip()] = v.strip()
    return out


def parse_list(value, name: str) -> list[str]:
    """A comma-separated list (blanks around items and empty items dropped); a list of
    strings is taken as it is.

    Examples
    --------
    >>> parse_list("slerp, squad,,natural", "--methods")
    ['slerp', 'squad', 'natural']
    """
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, (list, tuple)):
        items = list(value)
        for x in items:
            if not isinstance(x, str):
                raise TypeError(f"{name}: expected names, got {type(x).__name__}")
    else:
        raise TypeError(f"{name}: expected a comma-separated list, got {type(value).__name__}")
    out = [x.strip() for x in items if x.strip()]
    if not out:
        raise ParameterError(f"{name}: expected at least one name, got {value!r}")
    return out


def parse_choice(value, name: str, choices) -> str:
    """One of ``choices`` (exact text).

    Examples
    --------
    >>> parse_choice("clamp", "--extrapolate", ("raise", "clamp"))
    'clamp'
    """
    if not isinstance(value, str):
        raise TypeError(f"{name}: expected one of {', '.join(choices)}, got {type(value).__name__}")
    if value not in choices:
        raise ParameterError(f"{name}: expected one of {', '.join(choices)}, got {value!r}")
    return value


def parse_positive_int(value, name: str, minimum: int = 1) -> int:
    """An integer ≥ ``minimum``, from an integer or its text.

    Examples
    --------
    >>> parse_positive_int("3", "--workers"), parse_positive_int(7, "--holdout", 2)
    (3, 7)
    """
    if isinstance(value, str):
        try:
            value = int(value.strip())
        except ValueError:
            raise ParameterError(f"{name}: expected an integer, got {value!r}") from None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    if value < minimum:
        raise ParameterError(f"{name}: expected an integer ≥ {minimum}, got {int(value)}")
    return int(value)
