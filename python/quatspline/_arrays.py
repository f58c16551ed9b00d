"""Input coercion and broadcasting shared by every public function.

Rules (documented in the README): inputs may be lists or arrays of any real dtype (bool, int,
float32, float64; any strides, read-only is fine); complex and object arrays are rejected;
NaN/inf are rejected by the core with the argument named; batch dimensions broadcast like numpy.
"""

from __future__ import annotations

import numpy as np


def as_real(x, name: str) -> np.ndarray:
    """``x`` as a float64 array, or a ValueError naming ``name``."""
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:  # ragged lists and the like
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind not in "biuf":
        raise ValueError(f"{name}: expected real numbers, got dtype {a.dtype}")
    return a.astype(np.float64, copy=False)


def with_width(x, name: str, width: int) -> np.ndarray:
    """``x`` as float64 with last axis of length ``width`` (a quaternion is width 4)."""
    a = as_real(x, name)
    if a.ndim == 0 or a.shape[-1] != width:
        raise ValueError(f"{name}: expected shape (..., {width}), got {a.shape}")
    return a


def broadcast(*specs: tuple[np.ndarray, int, str]) -> tuple[tuple[int, ...], list[np.ndarray]]:
    """Broadcasts batch shapes. Each spec is (array, width, name); width 0 means scalars.

    Returns the common batch shape and, per input, a 2-D (n, max(width, 1)) view or copy.
    """
    batch = [a.shape if w == 0 else a.shape[:-1] for a, w, _ in specs]
    try:
        shape = np.broadcast_shapes(*batch)
    except ValueError:
        desc = ", ".join(f"{n} {a.shape}" for a, _, n in specs)
        raise ValueError(f"shapes do not broadcast: {desc}") from None
    flats = []
    for a, w, _ in specs:
        if w == 0:
            flats.append(np.broadcast_to(a, shape).reshape(-1, 1))
        else:
            flats.append(np.broadcast_to(a, (*shape, w)).reshape(-1, w))
    return shape, flats


def quats(x, name: str) -> np.ndarray:
    return with_width(x, name, 4)


def unary(fn, x, name: str, width: int, out_width: int) -> np.ndarray:
    """Applies a flat core function to (..., width) input, returning (..., out_width)."""
    a = with_width(x, name, width)
    out = fn(a.reshape(-1, width))
    return out.reshape((*a.shape[:-1], out_width))
