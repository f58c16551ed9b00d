"""Fitting splines on the rotation group (the fitting splines, 拟合样条, of the Chinese tutorial
series on rigid-body motion after Gao Xiang's *14 Lectures on Visual SLAM*); the minimum-energy
interpolants are in :mod:`quatspline.fitting.min_energy`.

``fit(times, quats, ...)`` returns the smooth curve closest to noisy orientations in the
least-squares sense on SO(3) — it does not pass through the samples — minimising

    Σᵢ wᵢ ρ(|Log(q(tᵢ)⁻¹ qᵢ)|²) + λ ∫ |ω̇|² dt      (penalty="acceleration")
    Σᵢ wᵢ ρ(|Log(q(tᵢ)⁻¹ qᵢ)|²) + λ ∫ |ω̈|² dt      (penalty="jerk", body frame)

over a uniform cumulative B-spline (order 4, C², for the acceleration penalty; order 6, C⁴, for
jerk), with positions (if given) fitted by the same knots and penalty in ℝ³. λ = "auto" is
chosen by generalised cross-validation (GCV) of the Gauss–Newton linearisation, with the trace
of the hat matrix from the banded factor (selected inversion); ``smoothing=0`` interpolates (the
minimum-penalty curve through every sample). The solver (Rust core, ``quatspline::fit``) is
Gauss–Newton/Levenberg–Marquardt on the manifold with closed-form Jacobians (Sommer et al.
2020) and banded Cholesky: time and memory linear in the number of samples.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np
from tqdm import tqdm

from .. import _core
from .._util.arrays import as_real, with_width
from .._util.options import parse_smoothing
from ..core.algebra import rotate
from ..splines import Spline, describe

__all__ = ["FittedPose", "FittedSpline", "fit"]

_PENALTIES = ("acceleration", "jerk")
_ROBUST = (None, "huber", "cauchy")


def _times(times) -> np.ndarray:
    t = as_real(times, "times")
    if t.ndim != 1:
        raise ValueError(f"times: expected shape (N,), got {t.shape}")
    return np.ascontiguousarray(t)


def _quats(quats, n: int) -> np.ndarray:
    q = with_width(quats, "quats", 4)
    if q.ndim != 2 or len(q) != n:
        raise ValueError(f"quats: expected shape ({n}, 4) (one per time), got {q.shape}")
    return np.ascontiguousarray(q)


def _choice(value, name: str, valid: tuple):
    if value is not None and not isinstance(value, str):
        raise TypeError(f"{name}: expected a string, got {type(value).__name__}")
    if value not in valid:
        shown = ", ".join(repr(v) for v in valid)
        raise ValueError(f"{name}: unknown value {value!r}; valid: {shown}")
    return value


_MAX_ORDER = 64  # far above any order the core supports; it names the supported range
_MAX_ITER = 100_000


def _integer(value, name: str, lo: int, hi: int, what: str) -> int:
    """An integer argument in lo … hi (a ValueError naming it otherwise, never an overflow
    on its way to the core)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    v = int(value)
    if not lo <= v <= hi:
        shown = f"{v}" if abs(v) < 10**15 else f"{float(v):.6g}"
        raise ValueError(f"{name}: expected {what} in {lo} … {hi}, got {shown}")
    return v


def _lambda(value, name: str):
    """None for "auto", else a float (finite, ≥ 0)."""
    v = parse_smoothing(value, name)
    return None if v == "auto" else v


def _knots(knots):
    """(spacing, array) for the core."""
    if knots is None:
        return None, None
    if isinstance(knots, numbers.Real) and not isinstance(knots, bool):
        return float(knots), None
    if isinstance(knots, (str, bytes, dict, bool)):
        raise TypeError(f"knots: expected None, a spacing or an array, got {type(knots).__name__}")
    k = as_real(knots, "knots")
    if k.ndim != 1:
        raise ValueError(f"knots: expected a spacing or a 1-D array, got shape {k.shape}")
    return None, np.ascontiguousarray(k)


def _weights(weights, n: int):
    if weights is None:
        return None
    w = as_real(weights, "weights")
    if w.shape != (n,):
        raise ValueError(f"weights: expected shape ({n},), got {w.shape}")
    return np.ascontiguousarray(w)


def _progress(progress, total: int | None = None):
    """A core callback from ``progress``: None, True (a tqdm bar) or a callable."""
    if progress is None or progress is False:
        return None
    if progress is True:
        bar = tqdm(total=total, desc="fit", unit="it", leave=False)

        def cb(stage, it, step):
            bar.update(1)
            bar.set_postfix_str(f"step {step:.1e}")

        cb.close = bar.close
        return cb
    if not callable(progress):
        kind = type(progress).__name__
        raise TypeError(f"progress: expected None, True or a callable, got {kind}")
    return progress


class FittedSpline(Spline):
    """A fitted orientation curve: a uniform cumulative B-spline on SO(3) (``method == "fit"``).

    Made by :func:`fit` (not constructed directly). It is a :class:`Spline`: exact
    orientations, angular velocity, acceleration and jerk, and a continuity certificate.

    Attributes
    ----------
    residuals : numpy.ndarray, shape (N,)
        Per sample, the rotation angle (radians) between the curve and the sample.
    smoothing : float
        λ used.
    effective_dof : float
        Trace of the hat matrix, in scalar observations (3 per sample).
    score : float
        The GCV score at λ.
    iterations : int
        Gauss–Newton / Levenberg–Marquardt iterations of the final solve.
    final_step : float
        Size of the last update (radians).
    converged : bool
        Always True (a fit that does not converge raises ``RuntimeError``).
    robust_weights : numpy.ndarray, shape (N,)
        Final weights of the robust loss (ones without one).
    robust_scale : float or None
        Scale of the robust loss (radians).
    control_quats, knots, order, penalty
        The B-spline that was fitted.

    See Also
    --------
    fit, FittedPose, MinimumEnergySpline

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> t = np.linspace(0.0, 2.0, 41)
    >>> f = qs.fit(t, qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0])), smoothing=1e-6)
    >>> type(f).__name__, f.method, bool(np.max(f.residuals) < 1e-3)
    ('FittedSpline', 'fit', True)
    """

    _method = "fit"

    def __init__(self, result: dict, penalty: str, extrapolate: str = "raise"):
        ctrl = result["ctrl"]
        full = result.get("knots_full")
        if full is None:
            core = _core.cumulative_bspline(ctrl, result["dt"], result["t0"], result["order"], True)
        else:  # non-uniform knots: the same spline on its full knot vector
            core = _core.nonuniform_bspline(ctrl, np.asarray(full), result["order"], True)
        super().__init__(core, extrapolate)
        self.control_quats = ctrl
        self.order = int(result["order"])
        self.penalty = penalty
        self.residuals = np.asarray(result["residuals"])
        self.smoothing = float(result.get("smoothing", 0.0))
        self.effective_dof = float(result.get("effective_dof", np.nan))
        self.score = float(result.get("score", np.nan))
        self.iterations = int(result["iterations"])
        self.final_step = float(result["final_step"])
        self.converged = bool(result.get("converged", True))
        self.robust_weights = np.asarray(result.get("robust_weights", np.ones(len(self.residuals))))
        self.robust_scale = float(result.get("robust_scale", np.inf))

    @property
    def method(self) -> str:
        return self._method

    @property
    def knots(self) -> np.ndarray:
        """The knot (joint) times, spanning the data's time range (uniform unless given)."""
        return self.joints


class FittedPose:
    """A fitted pose trajectory: ``rotation`` (a :class:`FittedSpline`) and positions (a
    penalised B-spline in ℝ³ with the same knots and penalty), with exact derivatives.

    Made by :func:`fit` with ``positions=`` (not constructed directly).

    Attributes
    ----------
    rotation : FittedSpline
        The orientation part, with its ``residuals``, ``smoothing``, ``effective_dof``, ``score``.
    position_residuals : numpy.ndarray, shape (N,)
        Per sample, the distance (length units) between the curve and the sample.
    position_smoothing, position_effective_dof, position_score : float
        λ, effective degrees of freedom and GCV score of the position fit.

    See Also
    --------
    fit, FittedSpline, PoseSpline

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> t = np.linspace(0.0, 2.0, 41)
    >>> q = qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0]))
    >>> f = qs.fit(t, q, positions=np.column_stack([t, t**2, 0 * t]), smoothing=1e-6)
    >>> type(f).__name__, bool(np.max(f.position_residuals) < 1e-3)
    ('FittedPose', True)
    """

    def __init__(self, rotation: FittedSpline, pos: dict, extrapolate: str = "raise"):
        self.rotation = rotation
        self.extrapolate = extrapolate
        self._pc = np.ascontiguousarray(pos["ctrl"])
        self._pdt, self._pt0, self._porder = float(pos["dt"]), float(pos["t0"]), int(pos["order"])
        br = pos.get("breaks")
        self._pbreaks = None if br is None else np.ascontiguousarray(br, dtype=float)
        self.position_residuals = np.asarray(pos["residuals"])
        self.position_smoothing = float(pos["smoothing"])
        self.position_effective_dof = float(pos["effective_dof"])
        self.position_score = float(pos["score"])
        self.position_robust_weights = np.asarray(pos["robust_weights"])

    method = "fit"

    def __getattr__(self, name):
        # residuals, smoothing, effective_dof, score, iterations, … of the orientation fit
        if name.startswith("_") or name == "rotation":
            raise AttributeError(name)
        return getattr(self.rotation, name)

    def __repr__(self) -> str:
        return describe(
            self,
            len(self.rotation.joints) - 1,
            smoothing=f"{self.rotation.smoothing:.3g}",
            position_smoothing=f"{self.position_smoothing:.3g}",
        )

    @property
    def domain(self) -> tuple[float, float]:
        return self.rotation.domain

    def _pos(self, t):
        ta = as_real(t, "t")
        flat = np.ascontiguousarray(ta.reshape(-1))
        a, b = self.domain
        if not np.all(np.isfinite(flat)):
            k = int(np.argmax(~np.isfinite(flat)))
            raise ValueError(f"t: non-finite value (NaN or inf) at element {k}")
        outside = (flat < a) | (flat > b)
        if np.any(outside) and self.extrapolate == "raise":
            k = int(np.argmax(outside))
            raise ValueError(f"t: t[{k}] = {flat[k]} is outside the domain [{a}, {b}]")
        out = _core.position_bspline_eval(
            self._pc, self._pdt, self._pt0, self._porder, np.clip(flat, a, b), self._pbreaks
        )
        out[outside, 3:] = 0.0
        return ta.shape, out

    def orientation(self, t) -> np.ndarray:
        return self.rotation(t)

    def position(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 0:3].reshape((*shape, 3))

    def linear_velocity(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 3:6].reshape((*shape, 3))

    def linear_acceleration(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 6:9].reshape((*shape, 3))

    def linear_jerk(self, t) -> np.ndarray:
        shape, out = self._pos(t)
        return out[:, 9:12].reshape((*shape, 3))

    def angular_velocity(self, t, frame: str = "world") -> np.ndarray:
        return self.rotation.angular_velocity(t, frame)

    def angular_acceleration(self, t, frame: str = "world") -> np.ndarray:
        return self.rotation.angular_acceleration(t, frame)

    def jerk(self, t, frame: str = "world") -> np.ndarray:
        return self.rotation.jerk(t, frame)

    def __call__(self, t):
        """(orientations, positions) at t."""
        return self.orientation(t), self.position(t)

    def transform_points(self, t, points) -> np.ndarray:
        """World coordinates R(t) p + x(t) of body points (P, 3) at times (M,): (M, P, 3)."""
        q = np.atleast_2d(self.orientation(np.atleast_1d(t)))
        x = np.atleast_2d(self.position(np.atleast_1d(t)))
        v = with_width(points, "points", 3).reshape(-1, 3)
        return rotate(q[:, None, :], v[None, :, :]) + x[:, None, :]


def fit(
    times,
    quats,
    *,
    positions=None,
    weights=None,
    smoothing="auto",
    penalty: str = "acceleration",
    knots=None,
    robust: str | None = None,
    robust_scale: float | None = None,
    order: int | None = None,
    max_iter: int = 1000,
    tol: float = 1e-10,
    progress=None,
    extrapolate: str = "raise",
):
    """Fits a smooth orientation (and position) trajectory to noisy samples.

    Parameters
    ----------
    times : array_like, shape (N,)
        Sample times, strictly increasing (duplicates are an error).
    quats : array_like, shape (N, 4)
        Measured orientations (w, x, y, z); q and −q are the same rotation (any mix is fine).
    positions : array_like, shape (N, 3), optional
        Measured positions; fitted with the same knots and penalty in ℝ³.
    weights : array_like, shape (N,), optional
        Non-negative sample weights (not all zero; normalised to mean 1). A zero weight drops
        the sample from the data term.
    smoothing : "auto", float or (float, float)
        λ: "auto" chooses it by generalised cross-validation; a float fixes it (units: rad² per
        ``∫|penalty|² dt``, i.e. time³ for acceleration, time⁵ for jerk); 0 interpolates every
        sample (the minimum-penalty curve through them; needs at least as many knots as
        samples). With positions, a pair gives (orientation λ, position λ); a single float
        is used for both. A λ beyond what double precision resolves for the data (about
        1e15 · max diag G / max diag P of the normal equations) is fitted at that bound with a
        ``RuntimeWarning``; ``smoothing`` then reports the λ used.
    penalty : {"acceleration", "jerk", "auto"}
        Integrate ``|ω̇|²`` (order-4 spline, C²) or the body-frame ``|ω̈|²`` (order-6 spline,
        C⁴). "auto" (with ``smoothing="auto"``) fits both and keeps the one with the lower
        GCV score — the same criterion that chooses λ, here choosing between the two model
        classes (about twice the time). On the bundled recordings it picks jerk for fast
        motion (MocapBank, 30 Hz) and is never worse than the better penalty by more than
        0.005 in the benchmark's error ratios (``benchmarks/fit.py``).
    knots : None, float or array_like
        None: one knot interval per median sample spacing. A float: about that spacing
        (rounded so the knots span the data exactly). An array: the knot (joint) times, strictly
        increasing from the first to the last sample time — uniform or not (denser knots where
        the motion is faster); the spline is then a non-uniform cumulative B-spline with the
        same continuity (C² / C⁴), extended beyond the ends with the end intervals' widths.
    robust : {None, "huber", "cauchy"}
        Robust loss (iteratively reweighted), so bad frames do not bend the curve. The fit
        starts from a high-breakdown pilot (a running medoid of ±20 samples, then the Cauchy
        loss), so up to half of the frames may be far glitches (tracker flips up to a half
        turn, bursts of up to 20 consecutive frames); beyond that a ``ValueError``. Cauchy
        gives far glitches weight ≈ 0; Huber bounds their pull at c each.
    robust_scale : float, optional
        The loss's scale c in radians (default: 3.067 σ̂ for Huber, 5.439 σ̂ for Cauchy — over
        99 % efficiency at Gaussian noise — with σ̂ the per-axis noise estimated robustly from
        the pilot's residuals). For positions the scale is at least 1e-6 × their extent and
        otherwise estimated from the position residuals.
    order : int, optional
        Spline order (default 4 for acceleration, 6 for jerk).
    max_iter : int
        Gauss–Newton iterations allowed (1 … 100000); beyond them ``RuntimeError`` (never a
        silent result). Gauss–Newton converges only linearly where residuals are large (samples
        far from any smooth curve): such fits take a few hundred iterations.
    tol : float
        Convergence: largest control-point step in radians.
    progress : None, True or callable
        True shows a tqdm bar; a callable gets (stage, iteration, step) after each iteration.
    extrapolate : {"raise", "clamp"}
        Behaviour outside the data's time range.

    Returns
    -------
    FittedSpline or FittedPose
        A ``quatspline.Spline`` (``method == "fit"``) with ``residuals``, ``smoothing``,
        ``effective_dof``, ``score``, ``iterations``, ``final_step``; a :class:`FittedPose`
        when positions are given.

    Raises
    ------
    ValueError
        Bad input: too few samples (the message names the minimum), times not strictly
        increasing, negative/non-finite/all-zero weights, λ < 0 or non-finite, unknown
        penalty or robust loss, knots outside the data range or not increasing.
    TypeError
        A wrong kind of object (e.g. ``penalty=3``, ``smoothing=[1]``).
    RuntimeError
        The solver did not converge (the message gives the iteration count and last step).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> t = np.linspace(0.0, 2.0, 41)
    >>> q = qs.from_rotvec(np.stack([0.5 * t, 0.2 * t**2, 0 * t], axis=1))
    >>> f = qs.fit(t, q, smoothing=1e-6)
    >>> f.method, bool(np.max(f.residuals) < 1e-3)
    ('fit', True)
    >>> f.angular_velocity(1.0).shape
    (3,)
    """
    t = _times(times)
    q = _quats(quats, len(t))
    penalty = _choice(penalty, "penalty", (*_PENALTIES, "auto"))
    robust = _choice(robust, "robust", _ROBUST)
    if penalty == "auto":
        if smoothing != "auto" or order is not None:
            raise ValueError(
                "penalty: 'auto' compares GCV scores, so it needs smoothing='auto' and no order"
            )
        kw = dict(positions=positions, weights=weights, knots=knots, robust=robust)
        kw.update(robust_scale=robust_scale, max_iter=max_iter, tol=tol, progress=progress)
        fits = [fit(t, q, penalty=pen, extrapolate=extrapolate, **kw) for pen in _PENALTIES]
        return fits[int(np.argmin([f.score for f in fits]))]  # orientation GCV decides
    if isinstance(smoothing, tuple):
        if positions is None or len(smoothing) != 2:
            raise ValueError("smoothing: a pair (orientation λ, position λ) needs positions")
        lam_q, lam_p = _lambda(smoothing[0], "smoothing[0]"), _lambda(smoothing[1], "smoothing[1]")
    else:
        lam_q = lam_p = _lambda(smoothing, "smoothing")
    if robust_scale is not None:
        if isinstance(robust_scale, bool) or not isinstance(robust_scale, numbers.Real):
            raise TypeError(f"robust_scale: expected a number, got {type(robust_scale).__name__}")
        robust_scale = float(robust_scale)
    if order is not None:
        # the core checks the order against the penalty; this bounds it to what it can receive
        order = _integer(order, "order", 1, _MAX_ORDER, "a spline order")
    max_iter = _integer(max_iter, "max_iter", 1, _MAX_ITER, "an iteration count")
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise TypeError(f"tol: expected a number, got {type(tol).__name__}")
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol: expected a finite positive tolerance, got {float(tol):.6g}")
    w = _weights(weights, len(t))
    ks, ka = _knots(knots)
    p = None
    if positions is not None:
        p = with_width(positions, "positions", 3)
        if p.ndim != 2 or len(p) != len(t):
            raise ValueError(f"positions: expected shape ({len(t)}, 3), got {p.shape}")
        p = np.ascontiguousarray(p)
    cb = _progress(progress, int(max_iter))
    try:
        res = _core.fit_rotations(
            t,
            q,
            w,
            penalty,
            order,
            lam_q,
            ks,
            ka,
            robust,
            robust_scale,
            int(max_iter),
            float(tol),
            cb,
        )
    finally:
        if cb is not None and hasattr(cb, "close"):
            cb.close()
    _warn_capped(res, "smoothing[0]" if isinstance(smoothing, tuple) else "smoothing")
    rot = FittedSpline(res, penalty, extrapolate)
    if p is None:
        return rot
    pos = _core.fit_positions(t, p, w, penalty, order, lam_p, ks, ka, robust, None)
    _warn_capped(pos, "smoothing[1]" if isinstance(smoothing, tuple) else "smoothing (positions)")
    return FittedPose(rot, pos, extrapolate)


def _warn_capped(res: dict, name: str) -> None:
    """A fixed λ beyond what double precision resolves was fitted at the largest λ that it
    does (the core's ``lambda_cap``): say so, since ``smoothing`` then differs from the λ given."""
    asked = res.get("smoothing_requested")
    if asked is not None:
        warnings.warn(
            f"{name}: λ = {asked:.3g} is beyond what double precision resolves for these knots "
            f"and data; fitted with λ = {res['smoothing']:.3g}, the largest it resolves",
            RuntimeWarning,
            stacklevel=3,
        )
