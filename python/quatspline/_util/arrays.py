"""Input coercion and broadcasting shared by every public function.

Rules (documented in the README and docs/conventions.rst): inputs may be lists or arrays of any
real dtype (bool, int, float32, float64; any strides, read-only is fine); complex and object
arrays are rejected; NaN/inf are rejected by the core with the argument named; batch dimensions
broadcast like numpy. Every rotation argument (width 4) also accepts a
``scipy.spatial.transform.Rotation`` (one or many), converted here and nowhere else. Every time
argument also accepts datetime64/timedelta64 arrays and pandas ``DatetimeIndex``,
``TimedeltaIndex``, ``Series``, ``Timestamp`` and ``Timedelta`` (converted to seconds by
``as_times``).
"""

from __future__ import annotations

import warnings

import numpy as np


def is_scipy_rotation(x) -> bool:
    """Whether ``x`` is a ``scipy.spatial.transform.Rotation`` (checked without importing
    scipy)."""
    cls = type(x)
    return cls.__name__ == "Rotation" and cls.__module__.startswith("scipy.spatial.transform")


def rotation_to_wxyz(r) -> np.ndarray:
    """Quaternions (w, x, y, z) of a scipy ``Rotation``: shape (4,) for one rotation, (N, 4)
    for a stack. scipy stores (x, y, z, w); the sign scipy chose is kept."""
    xyzw = np.asarray(r.as_quat(), dtype=np.float64)
    return np.concatenate([xyzw[..., 3:], xyzw[..., :3]], axis=-1)


def _unmasked(x, name: str):
    """A masked array's data when nothing is masked; a ValueError naming ``name`` otherwise
    (numpy would silently drop the mask)."""
    if isinstance(x, np.ma.MaskedArray):
        m = np.ma.getmaskarray(x)
        if m.any():
            k = int(np.argmax(m.reshape(-1)))
            raise ValueError(
                f"{name}: masked array with {int(m.sum())} masked element(s) (first at flat "
                f"index {k}); fill or drop them first (e.g. x.filled(...) or x.compressed())"
            )
        return np.ma.getdata(x)
    return x


def as_real(x, name: str) -> np.ndarray:
    """``x`` as a float64 array, or an error naming ``name``: ``TypeError`` when the values are
    not real numbers (strings, objects, complex), ``ValueError`` for ragged nesting.

    A masked array with masked elements is refused (its mask would otherwise be silently
    dropped); one without masked elements is read as its data.
    """
    x = _unmasked(x, name)
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:  # ragged lists and the like
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind not in "biuf":
        raise TypeError(f"{name}: expected real numbers, got dtype {a.dtype}")
    return a.astype(np.float64, copy=False)


def as_times(x, name: str) -> np.ndarray:
    """Times as float64 seconds, or a ValueError naming ``name``.

    Numbers are taken as they are. ``datetime64`` values (and pandas ``DatetimeIndex``,
    ``Series`` of datetimes, ``Timestamp``; time-zone aware ones are converted to UTC) become
    seconds since 1970-01-01T00:00 UTC; ``timedelta64`` values (pandas ``TimedeltaIndex``,
    ``Timedelta``) become seconds. ``NaT`` is rejected.
    """
    x = _unmasked(x, name)
    tz = getattr(x, "tz", None)
    if tz is not None and hasattr(x, "tz_convert"):  # pandas, time-zone aware
        x = x.tz_convert("UTC").tz_localize(None)
    elif getattr(getattr(x, "dt", None), "tz", None) is not None:  # pandas Series, aware
        x = x.dt.tz_convert("UTC").dt.tz_localize(None)
    if hasattr(x, "to_datetime64"):  # pandas Timestamp
        x = x.to_datetime64()
    elif hasattr(x, "to_timedelta64"):  # pandas Timedelta
        x = x.to_timedelta64()
    try:
        a = np.asarray(x)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind in "mM":
        if np.isnat(a).any():
            i = np.unravel_index(int(np.argmax(np.isnat(a))), a.shape) if a.ndim else ()
            raise ValueError(f"{name}: NaT (not a time) at index {tuple(int(k) for k in i)}")
        if a.dtype.kind == "M":
            a = a - np.datetime64(0, "s").astype(a.dtype)
        ns = a.astype("timedelta64[ns]").astype(np.int64)
        return ns.astype(np.float64) / 1e9
    return as_real(a, name)


def with_width(x, name: str, width: int) -> np.ndarray:
    """``x`` as float64 with last axis of length ``width`` (a quaternion is width 4; a scipy
    ``Rotation`` is accepted there)."""
    if width == 4 and is_scipy_rotation(x):
        return rotation_to_wxyz(x)
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


def pose_key_order(first, second, cls: str):
    """(quats, times) from a pose class's first two arguments.

    The order is ``(quats, times, positions)``, as for every spline class. The old order
    ``(times, quats, positions)`` is recognised — times are one-dimensional, keys are (N, 4)
    or a scipy ``Rotation`` — and still accepted with a ``DeprecationWarning``.
    """
    if is_scipy_rotation(first):
        return first, second
    try:
        nd = np.ndim(first)
    except (ValueError, TypeError):  # ragged: let the checks name it
        return first, second
    if nd == 1:
        warnings.warn(
            f"{cls}(times, quats, positions) is deprecated: write {cls}(quats, times, "
            "positions), the order of every spline class (the old order goes in 0.3)",
            DeprecationWarning,
            stacklevel=3,
        )
        return second, first
    return first, second
