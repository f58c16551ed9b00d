"""Keys and the keyframe controls shared by the spline families (Rust ``spline/keys.rs``
and ``spline/keyframe.rs``): validation of keys and key times, closed loops, holds, rest ends,
and key rates estimated from the keys alone.

Closed loops (``ends="closed"``) take n keys at n + 1 times: the last time closes the loop
(the segment from the last key back to the first). If the last key given equals the first
(q or −q, within 1e-12 rad) it is the closing key: it is dropped and its time closes the loop,
so keys ``A B C A`` at 0 1 2 3 and ``A B C`` at 0 1 2 3 are the same loop. Without times the
keys are at 0, 1, …, n. ``extrapolate="periodic"`` repeats a closed loop smoothly.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._util.arrays import as_real, as_times, with_width
from .._util.checks import short
from ..core.algebra import canonicalize, conjugate, multiply, normalize
from ..core.convert import as_rotvec

__all__ = ["bessel_rates", "bspline_controls", "bspline_hold_intervals", "c3_speed_matched_alpha"]


def _domain(domain) -> tuple[float, float]:
    """``domain`` as (t0, t1): a pair of real numbers (TypeError otherwise), finite with
    t0 < t1 (ValueError otherwise)."""
    kinds = (numbers.Real, np.integer, np.floating)
    if isinstance(domain, (str, bytes)) or not hasattr(domain, "__len__") or len(domain) != 2:
        raise TypeError(
            f"domain: expected a pair (t0, t1) of real numbers, got {type(domain).__name__} "
            f"{short(domain) if isinstance(domain, kinds) else ''}".rstrip()
        )
    if any(isinstance(v, (bool, np.bool_)) or not isinstance(v, kinds) for v in domain):
        kinds_given = ", ".join(type(v).__name__ for v in domain)
        raise TypeError(f"domain: expected a pair (t0, t1) of real numbers, got ({kinds_given})")
    t0, t1 = float(domain[0]), float(domain[1])
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < t1):
        raise ValueError(f"domain: expected finite t0 < t1, got ({short(t0)}, {short(t1)})")
    return t0, t1


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


def _per(v, name: str) -> np.ndarray:
    a = np.atleast_1d(as_real(v, name)).astype(np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a scalar or a 1-D array, got shape {a.shape}")
    return np.ascontiguousarray(a)


def bessel_rates(quats, times=None, closed: bool = False) -> np.ndarray:
    """Body angular velocities at keys estimated from the keys alone (Bessel's rule).

    At an interior key the time-weighted average (hᵢ mᵢ₋₁ + hᵢ₋₁ mᵢ)/(hᵢ₋₁ + hᵢ) of the
    neighbouring chord rates mₖ = rotvec(qₖ* qₖ₊₁)/hₖ (each is the same vector in the body
    frames of both its keys); at the ends of an open curve the end chord rate; on a closed
    loop every key is interior (the closing chord runs from the last key back to the first).
    Exact for a constant-speed great circle. The registry's default rates for ``hermite``.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys, N ≥ 2.
    times : array_like, shape (N,) or (N + 1,) when ``closed``, optional
        Key times (default 0, 1, …); a closed loop takes one more time, closing the loop,
        unless the last key equals the first (then it is the closing key, as for
        ``ends="closed"``, and its row repeats the first).
    closed : bool
        Rates for the closed loop through the keys (``ends="closed"``).

    Returns
    -------
    numpy.ndarray, shape (N, 3)
        Body-frame rates, rad per time unit.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline import splines
    >>> q = qs.from_rotvec([[0, 0, 0], [0, 0, 0.2], [0, 0, 0.4]])
    >>> bool(np.allclose(splines.bessel_rates(q, [0, 1, 2]), [0, 0, 0.2]))
    True
    >>> w = splines.bessel_rates(q, [0, 1, 2, 3], closed=True)
    >>> bool(np.allclose(w[0], [0, 0, (0.2 - 0.4) / 2]))
    True
    """
    q = canonicalize(normalize(_keys(quats, "quats")))
    n = len(q)
    if n < 2:
        raise ValueError(f"quats: needs at least 2 keys, got {n}")
    dropped = bool(closed) and bool(_same_rotations(q[:1], q[-1:])[0])
    loop = n - 1 if dropped else n  # distinct keys of a closed loop
    expected = (loop + 1,) if closed else (n,)
    t = np.arange(expected[0], dtype=float) if times is None else as_real(times, "times")
    if t.shape != expected:
        what = "one more than the distinct keys, closing the loop" if closed else "one per key"
        raise ValueError(f"times: expected shape {expected} ({what}), got {t.shape}")
    h = np.diff(t)
    if not np.all(h > 0):
        raise ValueError("times: not strictly increasing")
    if closed:
        k = q[:loop]
        m = as_rotvec(multiply(conjugate(k), np.roll(k, -1, axis=0))) / h[:, None]
        hp, mp = np.roll(h, 1), np.roll(m, 1, axis=0)  # the chord before each key
        w = (h[:, None] * mp + hp[:, None] * m) / (hp + h)[:, None]
        return np.vstack([w, w[:1]]) if dropped else w
    m = as_rotvec(multiply(conjugate(q[:-1]), q[1:])) / h[:, None]
    w = np.empty((n, 3))
    w[0], w[-1] = m[0], m[-1]
    w[1:-1] = (h[1:, None] * m[:-1] + h[:-1, None] * m[1:]) / (h[1:] + h[:-1])[:, None]
    return w


def _same_rotations(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise, the core's hold test: the angle between a and b (q ≡ −q) is ≤ 1e-12 rad."""
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    d = np.abs(np.sum(a * b, axis=-1))
    v = a[..., :1] * b[..., 1:] - b[..., :1] * a[..., 1:] - np.cross(a[..., 1:], b[..., 1:])
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=-1), d) <= 1e-12


def _same_rotation(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(_same_rotations(a, b))


def bspline_controls(q: np.ndarray, order: int, ends: str, holds: bool) -> np.ndarray:
    """Control rotations of a uniform cumulative B-spline with holds and rest ends.

    A segment of the order-k B-spline is constant exactly when its k control rotations are
    equal, and its first k − 2 derivatives vanish at its start (end) when its first (last)
    k − 1 control rotations are equal. So:

    - **holds**: every run of m ≥ 2 consecutive equal control rotations (q or −q, within
      1e-12 rad) is replaced by m + k − 2 exact copies of its first rotation: the curve is
      exactly constant on m − 1 whole segments (one per equal pair) and its first k − 2
      derivatives vanish at both ends of the hold. For a closed curve a run may wrap across
      the seam.
    - **rest** (``ends="rest"``, order k ≥ 3): copies of the first and of the last control
      rotation are added at the ends until k − 1 of them are equal (k − 2 copies unless a
      hold is there already), so the curve starts and ends exactly on them
      with zero angular velocity, acceleration, … up to derivative k − 2 (ω and α for the
      cubic; the jerk of a cubic cannot vanish without stopping the whole segment).

    Each added copy lengthens the domain by one ``dt`` (the spacing is kept).

    Parameters
    ----------
    q : numpy.ndarray, shape (n, 4)
        Control rotations as given.
    order : int
        B-spline order k.
    ends : {"open", "rest", "closed"}
        End condition.
    holds : bool
        Whether runs of equal rotations are turned into exact holds.

    Returns
    -------
    numpy.ndarray, shape (n', 4)
        The control rotations to build the spline from.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline import splines
    >>> a, b = qs.from_rotvec([[0, 0, 0.3], [0.4, 0, 0]])
    >>> splines.bspline_controls(np.array([a, a, b]), 4, "open", True).shape
    (5, 4)
    """
    q = np.asarray(q, dtype=np.float64)
    n = len(q)
    # the core's checks, before anything divides by a norm
    bad = ~np.all(np.isfinite(q), axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"control_quats: non-finite value (NaN or inf) at element {i}")
    zero = ~(np.linalg.norm(q, axis=1) > 1e-300)
    if zero.any():
        raise ValueError(
            f"control_quats: quaternion {int(np.argmax(zero))} has zero (or denormal) norm"
        )
    extra = order - 2
    if ends == "rest" and order < 3:
        raise ValueError(
            "ends: rest needs order ≥ 3 (an order-2 B-spline is piecewise geodesic: its "
            "velocity cannot vanish at an end without the end segment standing still)"
        )
    same = []
    if holds and n >= 2:
        nxt = np.roll(q, -1, axis=0) if ends == "closed" else q[1:]
        same = _same_rotations(q[: len(nxt)], nxt).tolist()
    if same and all(same):  # every control rotation the same: one constant curve
        q = np.repeat(q[:1], n, axis=0)
    elif same:
        # start at a key that begins a run (or stands alone), so no run is split
        start = 0
        if ends == "closed":
            while same[(start - 1) % n]:
                start += 1
        order_idx = [(start + i) % n for i in range(n)] if ends == "closed" else list(range(n))
        out: list[np.ndarray] = []
        label: list[int] = []  # the given index of each output row (-1: an added copy)
        i = 0
        while i < n:
            j = i
            while j + 1 < n and same[order_idx[j]]:
                j += 1
            first = q[order_idx[i]]
            m = j - i + 1
            out.extend([first] * (m + extra if m >= 2 else 1))
            label.extend(order_idx[i : j + 1] + ([-1] * extra if m >= 2 else []))
            i = j + 1
        # a closed run wrapping the seam: rotate so that the given first rotation leads
        q = np.roll(np.array(out), -label.index(0), axis=0)
    if ends == "rest":
        # the first (last) k − 1 rows equal: add only the copies a run there lacks
        def lead(r: np.ndarray) -> int:
            return next((i for i in range(1, len(r)) if not np.array_equal(r[i], r[0])), len(r))

        a, b = max(0, order - 1 - lead(q)), max(0, order - 1 - lead(q[::-1]))
        q = np.vstack([np.repeat(q[:1], a, axis=0), q, np.repeat(q[-1:], b, axis=0)])
    return np.ascontiguousarray(q)


def c3_speed_matched_alpha(quats, times=None, closed: bool = False) -> np.ndarray:
    """Per-key α of the C³ knot spline whose key speed is the mean of the neighbouring chords'.

    The knot variant's body rate at key k is α_k (m_l + m_r), with m_l = rotvec(Q_{k−1}* Q_k)/h_l
    and m_r = rotvec(Q_k* Q_{k+1})/h_r the chord rates on either side (both in key k's body
    frame). This rule takes α_k = ½ (|m_l| + |m_r|) / |m_l + m_r|, clipped to [0, 1], so the
    speed at every key is the mean of the two chord speeds also where the path turns
    (α_k = ½ where it does not); the paired β_k = −6 α_k keeps the key jerk at zero. At
    open end keys (one chord) α = ½, and where both chords vanish (holds) α = ½ as well.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys (w, x, y, z).
    times : array_like, shape (N,) or, closed, (N + 1,), optional
        Key times (default 0, 1, …).
    closed : bool
        Keys of a closed loop (the last time closes it; a last key equal to the first is
        dropped as the closing key).

    Returns
    -------
    numpy.ndarray, shape (n,)
        α per key (n distinct keys of a closed loop).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline import splines
    >>> q = qs.from_rotvec([[0, 0, 0], [0, 0, 0.5], [0.5, 0, 0.5]])
    >>> np.round(splines.c3_speed_matched_alpha(q), 4)
    array([0.5   , 0.6998, 0.5   ])
    """
    q = canonicalize(normalize(_keys(quats, "quats")))
    if closed and len(q) >= 2 and _same_rotation(q[0], q[-1]):
        q = q[:-1]
    n = len(q)
    m = n + 1 if closed else n
    t = np.arange(m, dtype=float) if times is None else np.asarray(times, dtype=float)
    if t.shape != (m,) or not np.all(np.diff(t) > 0):
        raise ValueError(f"times: expected {m} strictly increasing times, got shape {t.shape}")
    nxt = np.roll(q, -1, axis=0) if closed else q[1:]
    chords = as_rotvec(multiply(conjugate(q[: len(nxt)]), nxt)) / np.diff(t)[:, None]
    left = np.roll(chords, 1, axis=0) if closed else np.vstack([np.zeros(3), chords])
    right = chords if closed else np.vstack([chords, np.zeros(3)])
    both = np.linalg.norm(left + right, axis=1)
    mean = 0.5 * (np.linalg.norm(left, axis=1) + np.linalg.norm(right, axis=1))
    alpha = np.full(n, 0.5)
    inner = np.ones(n, bool) if closed else np.r_[False, np.ones(n - 2, bool), False]
    ok = inner & (both > 1e-300) & (mean > 0)
    alpha[ok] = np.clip(mean[ok] / both[ok], 0.0, 1.0)
    return alpha


def bspline_hold_intervals(q, order: int, closed: bool, dt: float, t0: float):
    """Time spans on which a uniform B-spline with control rotations q is exactly constant
    (segment i is when its k control rotations are identical), adjacent spans merged."""
    m = len(q)
    segs = m if closed else m - order + 1
    ext = np.vstack([q, q[: order - 1]]) if closed else q
    equal = np.all(ext[1:] == ext[:-1], axis=1)  # equal[i]: rows i and i + 1 identical
    # segment i: rows i … i + k − 1 identical, i.e. equal[i … i + k − 2] all true
    c = np.r_[0, np.cumsum(~equal)]
    held = c[order - 1 : order - 1 + segs] - c[:segs] == 0
    out: list[tuple[float, float]] = []
    for i in np.flatnonzero(held):
        a, b = t0 + i * dt, t0 + (i + 1) * dt
        if out and out[-1][1] == a:
            a = out.pop()[0]
        out.append((float(a), float(b)))
    return out
