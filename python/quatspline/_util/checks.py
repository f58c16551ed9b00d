"""Scalar argument checks with one convention for every public function.

``TypeError`` for the wrong kind of object (a float or a string where an integer is needed, a
string where a number is needed), ``ValueError`` for a value of the right kind that is out of
range; both messages start with the argument's name. Numbers are printed plainly (never a
numpy repr).
"""

from __future__ import annotations

import math
import numbers

import numpy as np


def short(v) -> str:
    """A number as a message shows it: integers up to 15 digits in full, anything larger (and
    every float) in ``:.6g`` form, so 1e308 or 2**1000 never print hundreds of digits."""
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, numbers.Integral) and not isinstance(v, bool):
        i = int(v)
        if abs(i) < 10**15:
            return str(i)
        try:
            return f"{float(i):.6g}"
        except OverflowError:
            digits = len(str(abs(i)))  # huge ints: the order of magnitude only
            return f"{'-' if i < 0 else ''}~1e{digits - 1}"
    if isinstance(v, numbers.Real) and not isinstance(v, bool):
        return f"{float(v):.6g}"
    return str(v)


def _show(v) -> str:
    if isinstance(v, (numbers.Number, np.generic)) and not isinstance(v, (bool, np.bool_)):
        try:
            if isinstance(v, (numbers.Integral, np.integer)):
                return short(v)  # a float's repr is short already (1e+308)
            return str(v.item() if isinstance(v, np.generic) else v)
        except (ValueError, TypeError):  # pragma: no cover - exotic numbers
            return str(v)
    r = repr(v)
    return r if len(r) <= 40 else r[:37] + "..."


def integer(v, name: str, lo: int | None = None, hi: int | None = None) -> int:
    """``v`` as an int: a Python or numpy integer (not bool, not float — even 2.0)."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Integral, np.integer)):
        raise TypeError(f"{name}: expected an integer, got {type(v).__name__} {_show(v)}")
    i = int(v)
    if (lo is not None and i < lo) or (hi is not None and i > hi):
        if hi is None:
            want = f"an integer ≥ {lo}"
        elif lo is None:
            want = f"an integer ≤ {hi}"
        else:
            want = f"an integer from {lo} to {hi}"
        raise ValueError(f"{name}: expected {want}, got {short(i)}")
    return i


def real(v, name: str, positive: bool = False) -> float:
    """``v`` as a finite float: a Python or numpy real number (not bool, not a string)."""
    kinds = (numbers.Real, np.integer, np.floating)
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, kinds):
        raise TypeError(f"{name}: expected a real number, got {type(v).__name__} {_show(v)}")
    x = float(v)
    if not math.isfinite(x) or (positive and not x > 0):
        want = "a finite positive number" if positive else "a finite number"
        raise ValueError(f"{name}: expected {want}, got {_show(x)}")
    return x


def choice(v, name: str, options: tuple[str, ...]) -> str:
    """``v`` as one of ``options`` (TypeError for a non-string)."""
    if not isinstance(v, str):
        raise TypeError(f"{name}: expected one of {options}, got {type(v).__name__} {_show(v)}")
    if v not in options:
        raise ValueError(f"{name}: expected one of {options}, got {v!r}")
    return v
