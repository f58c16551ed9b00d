"""Rotation means: the chordal L2 mean and the geodesic (Karcher) mean, also in windows.

- ``method="chordal"``: the rotation minimising Σ wᵢ ‖R − Rᵢ‖²_F, which is the unit
  eigenvector of the largest eigenvalue of K = Σ wᵢ qᵢ qᵢᵀ (Markley et al., "Averaging
  quaternions", JGCD 2007). It does not depend on the signs of the qᵢ and equals
  ``scipy.spatial.transform.Rotation.mean`` (tested).
- ``method="geodesic"``: the Karcher mean, the rotation minimising Σ wᵢ θ(R, Rᵢ)² with θ the
  rotation angle between them (Moakher 2002), by the fixed-point (Riemannian gradient)
  iteration q ← q exp(½ Σ wᵢ log_R(q* qᵢ) / Σ wᵢ) started at the chordal mean. It is unique
  when the rotations lie within a geodesic ball of radius π/2; the iteration count, the final
  step and whether it converged are reported with ``return_info=True``.

Why numpy and not Rust: a mean is one 4×4 eigenproblem (chordal) or a handful of vectorised
log/exp passes (geodesic); every step is already a batched numpy or core call, so a Rust
version would only move the same O(N) work across the binding.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._util.arrays import as_real, with_width

__all__ = ["MeanInfo", "mean", "moving_mean"]

_METHODS = ("chordal", "geodesic")


@dataclass(frozen=True)
class MeanInfo:
    """How the mean was reached (``return_info=True``).

    Attributes
    ----------
    method : str
        ``"chordal"`` or ``"geodesic"``.
    iterations, converged, step, cost
        See each field below.

    See Also
    --------
    mean

    Examples
    --------
    >>> import quatspline as qs
    >>> q = qs.from_rotvec([[0, 0, 0.1], [0, 0, 0.3]])
    >>> m, info = qs.mean(q, method="geodesic", return_info=True)
    >>> info.method, info.converged
    ('geodesic', True)
    """

    method: str
    iterations: int
    """Karcher iterations taken (0 for the chordal mean)."""
    converged: bool
    """Whether the last step was below ``tol`` (always True for the chordal mean)."""
    step: float
    """Rotation angle (rad) of the last Karcher update (0 for the chordal mean)."""
    cost: float
    """The minimised objective: Σ wᵢ ‖R − Rᵢ‖²_F (chordal) or Σ wᵢ θᵢ² (geodesic), wᵢ
    normalised to sum 1."""


def _check_method(method) -> str:
    if not isinstance(method, str):
        raise TypeError(f"method: expected a string, got {type(method).__name__}")
    if method not in _METHODS:
        raise ValueError(f"method: expected one of {_METHODS}, got {method!r}")
    return method


def _checked(quats) -> tuple[np.ndarray, np.ndarray]:
    """(q, |q|²) with every row finite and non-zero (rows rescaled where |q|² would
    over- or underflow)."""
    q = with_width(quats, "quats", 4)
    if q.ndim != 2:
        raise ValueError(f"quats: expected shape (N, 4), got {q.shape}")
    if len(q) == 0:
        raise ValueError("quats: expected at least one rotation, got none")
    n2 = np.einsum("ij,ij->i", q, q)  # one pass; NaN/inf propagate into it
    if not np.all(np.isfinite(n2)):
        bad = ~np.all(np.isfinite(q), axis=1)
        if np.any(bad):
            k = int(np.argmax(bad))
            raise ValueError(f"quats: non-finite value (NaN or inf) in quaternion {k}")
        q = q / np.max(np.abs(q), axis=1, keepdims=True)  # huge but finite: rescale first
        n2 = np.einsum("ij,ij->i", q, q)
    small = n2 < np.finfo(float).tiny
    if np.any(small):
        q = q / np.maximum(np.max(np.abs(q), axis=1, keepdims=True), np.finfo(float).tiny)
        n2 = np.einsum("ij,ij->i", q, q)
        small = n2 < np.finfo(float).tiny
        if np.any(small):
            raise ValueError(f"quats: quaternion {int(np.argmax(small))} is zero")
    return q, n2


def _unit_quats(quats) -> np.ndarray:
    q, n2 = _checked(quats)
    return q / np.sqrt(n2)[:, None]


def _weights(weights, n: int) -> np.ndarray:
    if weights is None:
        return np.full(n, 1.0 / n)
    if isinstance(weights, (str, bytes)):
        raise TypeError(f"weights: expected an array of numbers, got {type(weights).__name__}")
    w = as_real(weights, "weights")
    if w.shape != (n,):
        raise ValueError(f"weights: expected shape ({n},), one per rotation, got {w.shape}")
    if not np.all(np.isfinite(w)):
        raise ValueError(f"weights: non-finite value at element {int(np.argmax(~np.isfinite(w)))}")
    if np.any(w < 0):
        raise ValueError(f"weights: negative weight at element {int(np.argmax(w < 0))}")
    total = w.sum()
    if not total > 0:
        raise ValueError("weights: all weights are zero; at least one must be positive")
    return w / total


def _chordal(q: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Leading eigenvectors of K = Σ wᵢ qᵢ qᵢᵀ for stacked problems: q (..., N, 4)."""
    k = np.swapaxes(q * w[..., None], -1, -2) @ q  # BLAS, not einsum: 30× faster
    _, vec = np.linalg.eigh(k)
    m = vec[..., :, -1]
    return np.where(m[..., :1] < 0, -m, m)


def _log_rel(m: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation vectors of m* qᵢ (shortest way): m (..., 4), q (..., N, 4) → (..., N, 3)."""
    mw, mv = m[..., None, :1], m[..., None, 1:]
    qw, qv = q[..., :1], q[..., 1:]
    # m* q = (mw qw + mv·qv, mw qv − qw mv − mv × qv)
    rw = mw * qw + np.sum(mv * qv, axis=-1, keepdims=True)
    rv = mw * qv - qw * mv - np.cross(np.broadcast_to(mv, qv.shape), qv)
    sign = np.where(rw < 0, -1.0, 1.0)
    rw, rv = rw * sign, rv * sign
    s = np.linalg.norm(rv, axis=-1, keepdims=True)
    ang = 2.0 * np.arctan2(s, rw)
    scale = np.where(s > 0, ang / np.where(s > 0, s, 1.0), 2.0)
    return rv * scale


def _apply(m: np.ndarray, rotvec: np.ndarray) -> np.ndarray:
    """m exp(rotvec / 2) for stacked m (..., 4) and rotation vectors (..., 3)."""
    a = np.linalg.norm(rotvec, axis=-1, keepdims=True)
    half = 0.5 * a
    e = np.concatenate([np.cos(half), 0.5 * np.sinc(half / np.pi) * rotvec], axis=-1)
    w1, v1 = m[..., :1], m[..., 1:]
    w2, v2 = e[..., :1], e[..., 1:]
    out = np.concatenate(
        [w1 * w2 - np.sum(v1 * v2, axis=-1, keepdims=True), w1 * v2 + w2 * v1 + np.cross(v1, v2)],
        axis=-1,
    )
    out /= np.linalg.norm(out, axis=-1, keepdims=True)
    return np.where(out[..., :1] < 0, -out, out)


def _karcher(q, w, start, max_iterations, tol):
    m = start
    step = np.zeros(m.shape[:-1])
    it = 0
    for it in range(1, max_iterations + 1):  # noqa: B007 — the count is reported
        delta = (w[..., None, :] @ _log_rel(m, q))[..., 0, :]
        m = _apply(m, delta)
        step = np.linalg.norm(delta, axis=-1)
        if np.all(step < tol):
            break
    return m, it, step


def _costs(method, q, w, m):
    if method == "chordal":
        # ‖R − Rᵢ‖²_F = 8 (1 − (m·qᵢ)²) for unit quaternions
        d = np.einsum("...i,...ni->...n", m, q)
        return np.einsum("...n,...n->...", w, 8.0 * (1.0 - d**2))
    th = np.linalg.norm(_log_rel(m, q), axis=-1)
    return np.einsum("...n,...n->...", w, th**2)


def _iter_args(max_iterations, tol):
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, (int, np.integer)):
        raise TypeError(f"max_iterations: expected an int, got {type(max_iterations).__name__}")
    if max_iterations < 1:
        raise ValueError(f"max_iterations: expected at least 1, got {max_iterations}")
    tol = float(tol)
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol: expected a finite positive angle, got {tol}")
    return int(max_iterations), tol


def mean(
    quats,
    weights=None,
    method: str = "chordal",
    *,
    max_iterations: int = 100,
    tol: float = 1e-14,
    return_info: bool = False,
):
    """The mean rotation of unit quaternions.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Rotations, scalar first (w, x, y, z); normalised here, signs do not matter.
    weights : array_like, shape (N,), optional
        Non-negative weights (not all zero); equal weights by default.
    method : {"chordal", "geodesic"}
        ``"chordal"``: the chordal L2 mean (equal to scipy's ``Rotation.mean``).
        ``"geodesic"``: the Karcher mean (least squares in rotation angle).
    max_iterations : int
        Karcher iterations at most (geodesic only).
    tol : float
        Stop when the Karcher update rotates by less than ``tol`` radians.
    return_info : bool
        Also return a :class:`MeanInfo` with the iteration count and convergence.

    Returns
    -------
    numpy.ndarray, shape (4,)
        The mean as a unit quaternion with w ≥ 0 (and the :class:`MeanInfo` when asked).

    Raises
    ------
    ValueError
        Empty input, non-finite or zero quaternions, weights of the wrong shape, negative,
        non-finite or all zero, an unknown method.
    TypeError
        ``method`` is not a string, ``weights`` is a string.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_rotvec([[0.0, 0.0, 0.1], [0.0, 0.0, 0.3]])
    >>> round(float(qs.as_rotvec(qs.mean(q))[2]), 12)
    0.2
    >>> m, info = qs.mean(q, weights=[3, 1], method="geodesic", return_info=True)
    >>> round(float(qs.as_rotvec(m)[2]), 12), info.converged
    (0.15, True)
    """
    method = _check_method(method)
    max_iterations, tol = _iter_args(max_iterations, tol)
    q, n2 = _checked(quats)
    w = _weights(weights, len(q))
    m = _chordal(q, w / n2)  # K = Σ wᵢ qᵢqᵢᵀ/|qᵢ|²: no normalised copy of the input
    it, step, converged = 0, 0.0, True
    if method == "geodesic" or return_info:
        q = q / np.sqrt(n2)[:, None]
    if method == "geodesic":
        m, it, st = _karcher(q, w, m, max_iterations, tol)
        step = float(st)
        converged = step < tol
    if not return_info:
        return m
    return m, MeanInfo(method, it, converged, step, float(_costs(method, q, w, m)))


def moving_mean(
    quats,
    window: int,
    method: str = "chordal",
    *,
    max_iterations: int = 100,
    tol: float = 1e-14,
) -> np.ndarray:
    """Centred moving mean along a trajectory: sample i averages samples
    i − window//2 … i + window//2 (fewer at the ends, where the window is cut off).

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Orientations in time order.
    window : int
        Odd window length ≥ 1.
    method : {"chordal", "geodesic"}
        As for :func:`mean` (equal weights in each window).
    max_iterations, tol
        As for :func:`mean` (geodesic only; every window iterates together).

    Returns
    -------
    numpy.ndarray, shape (N, 4)
        The mean of each window, w ≥ 0. The chordal version costs O(N) (running sums of
        qqᵀ and N 4×4 eigenproblems), the geodesic one O(N · window) per iteration.

    Raises
    ------
    ValueError
        A window that is even, < 1 or longer than the trajectory, and the input errors of
        :func:`mean`.
    TypeError
        ``window`` is not an int.

    Examples
    --------
    >>> import numpy as np
    >>> import quatspline as qs
    >>> q = qs.from_rotvec(np.outer(np.arange(5.0), [0.0, 0.0, 0.1]))
    >>> np.round(qs.as_rotvec(qs.moving_mean(q, 3))[:, 2], 12)
    array([0.05, 0.1 , 0.2 , 0.3 , 0.35])
    """
    method = _check_method(method)
    max_iterations, tol = _iter_args(max_iterations, tol)
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)):
        raise TypeError(f"window: expected an int, got {type(window).__name__}")
    q = _unit_quats(quats)
    n = len(q)
    if window < 1 or window % 2 == 0 or window > n:
        raise ValueError(f"window: expected an odd length between 1 and {n}, got {window}")
    h = window // 2
    lo = np.clip(np.arange(n) - h, 0, n)
    hi = np.clip(np.arange(n) + h + 1, 0, n)
    outer = np.einsum("ni,nj->nij", q, q)
    csum = np.concatenate([np.zeros((1, 4, 4)), np.cumsum(outer, axis=0)])
    k = (csum[hi] - csum[lo]) / (hi - lo)[:, None, None]
    _, vec = np.linalg.eigh(k)
    m = vec[:, :, -1]
    m = np.where(m[:, :1] < 0, -m, m)
    if method == "chordal":
        return m
    # Geodesic: pad by repeating nothing — gather each window with a validity mask as weights.
    idx = np.arange(n)[:, None] + np.arange(-h, h + 1)[None, :]
    valid = (idx >= 0) & (idx < n)
    w = valid / valid.sum(axis=1, keepdims=True)
    qq = q[np.clip(idx, 0, n - 1)]
    m, _, _ = _karcher(qq, w, m, max_iterations, tol)
    return m
