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

import math
import numbers
import warnings

import numpy as np
from tqdm import tqdm

from .. import _core
from .._util.arrays import as_real, with_width
from .._util.options import parse_smoothing
from ..core.algebra import rotate
from ..splines import Spline, describe
from ._gyro import DEFAULT_ESTIMATE, GyroEstimate, estimate_names, gyro_record, gyro_sigma

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
    """(λ, adaptivity) for the core: (None, "auto" | "gcv" | "adaptive") for a λ chosen from
    the data, else (a float ≥ 0, "gcv")."""
    v = parse_smoothing(value, name)
    return (None, v) if isinstance(v, str) else (v, "gcv")


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


_FRAMES = ("body", "world")


def _frame(frame) -> str:
    if not isinstance(frame, str):
        raise TypeError(f"frame: expected a string, got {type(frame).__name__}")
    if frame not in _FRAMES:
        raise ValueError(f"frame: expected one of 'body', 'world', got {frame!r}")
    return frame


def _domain_times(t, domain, extrapolate: str):
    """(shape, times clipped to the domain, mask of those outside) for a posterior; times
    outside the domain are an error unless ``extrapolate == "clamp"`` (the end pose held)."""
    ta = as_real(t, "t")
    flat = np.ascontiguousarray(ta.reshape(-1))
    a, b = domain
    if not np.all(np.isfinite(flat)):
        k = int(np.argmax(~np.isfinite(flat)))
        raise ValueError(f"t: non-finite value (NaN or inf) at element {k}")
    outside = (flat < a) | (flat > b)
    if np.any(outside) and extrapolate != "clamp":
        k = int(np.argmax(outside))
        raise ValueError(
            f"t: t[{k}] = {flat[k]} is outside the domain [{a}, {b}] "
            '(use extrapolate="clamp" to hold the end pose)'
        )
    return ta.shape, np.clip(flat, a, b), outside


def remaining_iterations(steps, tol: float) -> int | None:
    """Gauss–Newton iterations still to come if the step keeps shrinking at its last rate.

    Gauss–Newton converges linearly (quadratically near zero residuals): with the last two
    steps s₁ > s₂ the rate is r = s₂/s₁, and the step falls below ``tol`` after
    ⌈ln(tol/s₂) / ln r⌉ more iterations. None while no rate is known (one step so far, or a
    step that grew: a new λ or a new stage of the solver).

    Examples
    --------
    >>> remaining_iterations([3e-2, 2.4e-4], 1e-10)  # r ≈ 8e-3: 2.4e-4 → 1e-10 in 3.03 rates
    4
    >>> remaining_iterations([3e-2], 1e-10) is None, remaining_iterations([1e-3, 1e-11], 1e-10)
    (True, 0)
    """
    if steps[-1] <= tol:
        return 0
    if len(steps) < 2 or not 0.0 < steps[-1] < steps[-2]:
        return None
    return max(1, math.ceil(math.log(tol / steps[-1]) / math.log(steps[-1] / steps[-2])))


class _FitProgress:
    """The core's reports (stage, iteration, step) of a fit as (stage, done, total): ``total``
    is the iterations done plus :func:`remaining_iterations` (at most ``max_iter``), updated
    at every iteration, None while unknown; the last report has done == total. Drives a tqdm
    bar (``progress=True``) or a callable."""

    def __init__(self, progress, tol: float, max_iter: int):
        if not (progress is True or callable(progress)):
            kind = type(progress).__name__
            raise TypeError(f"progress: expected None, True or a callable, got {kind}")
        self.tol, self.max_iter = tol, max_iter
        self.steps: list[float] = []
        self.total: int | None = None
        self.stage = "fit"
        self.bar = (
            tqdm(total=None, desc="fit", unit="it", leave=False) if progress is True else None
        )
        self.user = None if progress is True else progress

    def _report(self, stage: str, done: int, total: int | None, note: str = "") -> None:
        if self.bar is not None:
            self.bar.set_description_str(stage, refresh=False)
            self.bar.total = total
            self.bar.n = done
            if note:
                self.bar.set_postfix_str(note, refresh=False)
            self.bar.refresh()
        else:
            self.user(stage, done, total)

    def __call__(self, stage: str, it: int, step: float) -> None:
        self.stage = stage
        self.steps.append(float(step))
        rem = remaining_iterations(self.steps, self.tol)
        if rem is not None:
            self.total = min(it + rem, self.max_iter)
        elif self.total is not None and self.total <= it:
            self.total = None  # the estimate ran out: unknown until a rate is seen again
        self._report(stage, it, self.total, f"step {step:.1e}")

    def finish(self, done: int) -> None:
        """The fit ended after ``done`` iterations."""
        self.total = done
        self._report(self.stage, done, done)

    def stage_done(self, stage: str, done: int, total: int) -> None:
        """A stage without iterations of its own (the position fit): ``done`` of ``total``."""
        self._report(stage, done, total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


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
    penalty_weights : numpy.ndarray or None
        Locally adaptive smoothing: the penalty's weight wᵢ on each knot interval (geometric
        mean 1), so that the local λ there is ``smoothing * penalty_weights[i]``; None for one
        global λ.
    noise_std : float
        σ̂, the noise per axis (radians) that the posterior estimates: √(RSS / (3 n − tr A))
        (see :meth:`covariance`).
    gyro : GyroEstimate or None
        A gyro-aided fit (``fit(..., gyro=...)``): the gyroscope's estimated bias, time
        offset, sensor rotation (and scale) with their standard deviations and covariance;
        None otherwise. ``gyro_bias``, ``time_offset`` and ``sensor_rotation`` are shortcuts
        to its fields (None without a gyroscope).
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

    def __init__(self, result: dict, penalty: str, extrapolate: str = "raise", data=None):
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
        pw = result.get("penalty_weights")
        self.penalty_weights = None if pw is None else np.asarray(pw)
        self._layout = (float(result["dt"]), float(result["t0"]), result.get("breaks"))
        self._data = data  # (times, quats, weights) of the fit, for its posterior
        self._post = None
        self.gyro = None  # a GyroEstimate, set by a gyro-aided fit

    @property
    def gyro_bias(self):
        return None if self.gyro is None else self.gyro.bias

    @property
    def time_offset(self):
        return None if self.gyro is None else self.gyro.time_offset

    @property
    def sensor_rotation(self):
        return None if self.gyro is None else self.gyro.rotation

    @property
    def method(self) -> str:
        return self._method

    # ---- uncertainty ------------------------------------------------------------------
    def _posterior(self):
        if self._post is None:
            if self.gyro is not None:
                raise ValueError(
                    "covariance: the curve's posterior is not available for a gyro-aided fit "
                    "(the sensor parameters' covariance is in .gyro)"
                )
            if self._data is None:
                raise ValueError(
                    "covariance: this curve does not hold the samples it was fitted to"
                )
            t, q, w = self._data
            dt, t0, breaks = self._layout
            self._post = _core.fit_posterior(
                t,
                q,
                w,
                self.robust_weights,
                self.control_quats,
                dt,
                t0,
                self.order,
                breaks,
                self.penalty,
                self.smoothing,
                self.penalty_weights,
            )
        return self._post

    @property
    def noise_std(self) -> float:
        return float(np.sqrt(self._posterior().sigma2))

    def _cov(self, t, quantity: str, frame: str) -> np.ndarray:
        frame = _frame(frame)
        shape, flat, outside = _domain_times(t, self.domain, self.extrapolate)
        out = self._posterior().covariance(flat, quantity, frame)
        if quantity == "angular_velocity":
            out[outside] = 0.0  # the held end pose does not turn
        return out.reshape((*shape, 3, 3))

    def covariance(self, t, frame: str = "body") -> np.ndarray:
        """Posterior covariance of the orientation at times ``t``, radians².

        The fit's Bayesian posterior (Wahba 1983; Nychka 1988): the curve's perturbation
        ξ(t) in q(t)·Exp(ξ) (``frame="body"``: the tangent space at q(t), right perturbation)
        or Exp(ε)·q(t) (``"world"``: left perturbation, ε = R(t) ξ) has covariance
        σ̂² J(t) H⁻¹ J(t)ᵀ, with H = G + λP the Gauss–Newton normal matrix of the fit at its
        solution (data and penalty), J(t) the Jacobian of ξ(t) with respect to the control
        points of t's knot interval, and σ̂² = RSS / (n_obs − tr A), n_obs = 3 × the samples of
        positive weight. With a robust loss, the final robust weights are part of the
        weights (the posterior of that weighted fit). Only the band of H⁻¹ is needed
        (selected inversion of the fit's banded factor): built once, on the first call, in
        time and memory linear in the samples; every call is vectorised over ``t``.

        Pointwise intervals q(t)·Exp(±1.96 σ_c e_c) per body axis c are meant to cover the
        truth about 95 % of the time *on average over the curve* (Nychka's across-the-function
        coverage; locally they are wider where the curve is straight and narrower at sharp
        turns, where the penalty's bias is largest). The fit must smooth (λ > 0): an
        interpolating fit (``smoothing=0``) has no residuals to estimate the noise from
        (``ValueError``).

        Parameters
        ----------
        t : float or array_like, any shape
            Times inside the domain (outside it: ``ValueError``, or with
            ``extrapolate="clamp"`` the covariance of the held end pose).
        frame : {"body", "world"}, default "body"

        Returns
        -------
        numpy.ndarray, shape t.shape + (3, 3)

        Examples
        --------
        >>> import numpy as np, quatspline as qs
        >>> rng = np.random.default_rng(0)
        >>> t = np.linspace(0.0, 4.0, 201)
        >>> noise = 0.01 * rng.normal(size=(201, 3))  # radians per axis
        >>> f = qs.fit(t, qs.from_rotvec(np.outer(np.sin(t), [0.3, 0.0, 1.0]) + noise))
        >>> f.covariance(2.0).shape, f.covariance([1.0, 2.0]).shape
        ((3, 3), (2, 3, 3))
        >>> bool(0.004 < np.degrees(f.std(2.0)).mean() < 0.4)  # about 0.1° for 0.57° of noise
        True
        >>> round(float(np.degrees(f.noise_std)), 1)  # σ̂ per axis: 0.01 rad = 0.57°
        0.6
        """
        return self._cov(t, "orientation", frame)

    def std(self, t, frame: str = "body") -> np.ndarray:
        """Posterior standard deviation of the orientation per axis at times ``t``, radians:
        the square root of the diagonal of :meth:`covariance` (same arguments).

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)
        """
        c = self._cov(t, "orientation", frame)
        return np.sqrt(np.maximum(np.diagonal(c, axis1=-2, axis2=-1), 0.0))

    def angular_velocity_covariance(self, t, frame: str = "world") -> np.ndarray:
        """Posterior covariance of the angular velocity at times ``t``, (rad per time unit)².

        As :meth:`covariance`, for ω = :meth:`angular_velocity` (the same ``frame``
        convention): to first order the body rate moves by ξ̇ + ω_b × ξ and the world rate
        by R(t) ξ̇, both linear in the control points' perturbations, so the covariance is
        σ̂² D(t) H⁻¹ D(t)ᵀ with D(t) their Jacobian. Zero outside the domain with
        ``extrapolate="clamp"`` (the end pose is held).

        Returns
        -------
        numpy.ndarray, shape t.shape + (3, 3)

        Examples
        --------
        >>> import numpy as np, quatspline as qs
        >>> rng = np.random.default_rng(0)
        >>> t = np.linspace(0.0, 4.0, 201)
        >>> q = qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0]) + 0.01 * rng.normal(size=(201, 3)))
        >>> f = qs.fit(t, q)
        >>> f.angular_velocity_covariance([1.0, 2.0], frame="body").shape
        (2, 3, 3)
        """
        return self._cov(t, "angular_velocity", frame)

    def angular_velocity_std(self, t, frame: str = "world") -> np.ndarray:
        """Posterior standard deviation of ω per axis at times ``t`` (rad per time unit): the
        square root of the diagonal of :meth:`angular_velocity_covariance`.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)
        """
        c = self._cov(t, "angular_velocity", frame)
        return np.sqrt(np.maximum(np.diagonal(c, axis1=-2, axis2=-1), 0.0))

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
        self._ppen, self._pdata, self._ppost = pos.get("penalty"), pos.get("data"), None

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

    # ---- uncertainty ------------------------------------------------------------------
    def covariance(self, t, frame: str = "body") -> np.ndarray:
        """Posterior covariance of the orientation (see :meth:`FittedSpline.covariance`)."""
        return self.rotation.covariance(t, frame)

    def std(self, t, frame: str = "body") -> np.ndarray:
        """Posterior standard deviation of the orientation (see :meth:`FittedSpline.std`)."""
        return self.rotation.std(t, frame)

    def _position_var(self, t, derivative: int):
        shape, flat, outside = _domain_times(t, self.domain, self.extrapolate)
        if self._ppost is None:
            if self._pdata is None:
                raise ValueError("position_covariance: this fit does not hold its samples")
            tt, x, w = self._pdata
            self._ppost = _core.position_posterior(
                tt,
                x,
                w,
                self.position_robust_weights,
                self._pc,
                self._pdt,
                self._pt0,
                self._porder,
                self._pbreaks,
                self._ppen,
                self.position_smoothing,
            )
        v = self._ppost.variances(flat, derivative)
        if derivative:
            v[outside] = 0.0  # the held end position does not move
        return shape, v

    def position_covariance(self, t, derivative: int = 0) -> np.ndarray:
        """Posterior covariance of the position (``derivative=0``, length²) or of the linear
        velocity (``1``, (length per time unit)²) at times ``t``.

        The position fit is linear, with one normal matrix H = G + λP for the three
        coordinates, so the covariance is isotropic: σ̂² b(t)ᵀ H⁻¹ b(t) · I₃ (b the B-spline
        basis, or its derivative, at t; σ̂² = RSS / (n_obs − tr A) of the position fit;
        Wahba 1983, Nychka 1988). Same times and ``extrapolate`` rule as
        :meth:`FittedSpline.covariance`.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3, 3)

        Examples
        --------
        >>> import numpy as np, quatspline as qs
        >>> rng = np.random.default_rng(1)
        >>> t = np.linspace(0.0, 2.0, 101)
        >>> x = np.column_stack([t, t**2, 0 * t]) + 0.01 * rng.normal(size=(101, 3))
        >>> q = qs.from_rotvec(np.outer(t, [0, 0, 1.0]))
        >>> f = qs.fit(t, q, positions=x, smoothing=(1e-6, "auto"))
        >>> f.position_covariance([0.5, 1.0]).shape, f.position_std(1.0).shape
        ((2, 3, 3), (3,))
        """
        derivative = _integer(derivative, "derivative", 0, 1, "a derivative order")
        shape, v = self._position_var(t, derivative)
        return (v[:, None, None] * np.eye(3)).reshape((*shape, 3, 3))

    def position_std(self, t, derivative: int = 0) -> np.ndarray:
        """Posterior standard deviation of each position coordinate (or of the linear
        velocity, ``derivative=1``) at times ``t``: the square root of the diagonal of
        :meth:`position_covariance`.

        Returns
        -------
        numpy.ndarray, shape t.shape + (3,)
        """
        derivative = _integer(derivative, "derivative", 0, 1, "a derivative order")
        shape, v = self._position_var(t, derivative)
        return np.repeat(np.sqrt(np.maximum(v, 0.0))[:, None], 3, axis=1).reshape((*shape, 3))

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
    gyro=None,
    gyro_noise=None,
    noise_std=None,
    estimate=DEFAULT_ESTIMATE,
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
    smoothing : "auto", "gcv", "adaptive", float or (float, float)
        λ. "gcv": one λ for the whole recording, chosen by generalised cross-validation.
        "adaptive": a λ that varies along the recording, λ(t) = λ·w(t) with w piecewise
        constant on the knot intervals — the penalty is relaxed where the GCV fit is rough and
        stiffened where it is smooth (w = local roughness^−α, α ∈ {¼, ½, ¾, 1} and λ chosen
        together by GCV; see ``docs/maths/fitting.rst``, "Locally adaptive smoothing").
        "auto" (default): "gcv", then the adaptive candidate, kept only if its GCV score —
        counting α as one more parameter — is lower than the global fit's; the result's
        ``penalty_weights`` says which (None: global). Costs the global fit plus a few
        factorisations, and a second fit only when the adaptive one wins. Positions always
        use one λ by GCV.
        A float fixes λ (units: rad² per ``∫|penalty|² dt``, i.e. time³ for acceleration,
        time⁵ for jerk); 0 interpolates every sample (the minimum-penalty curve through them;
        needs at least as many knots as samples). With positions, a pair gives (orientation λ,
        position λ); a single float is used for both. A λ beyond what double precision
        resolves for the data (about 1e15 · max diag G / max diag P of the normal equations)
        is fitted at that bound with a ``RuntimeWarning``; ``smoothing`` then reports the λ
        used.
    penalty : {"acceleration", "jerk", "auto"}
        Integrate ``|ω̇|²`` (order-4 spline, C²) or the body-frame ``|ω̈|²`` (order-6 spline,
        C⁴). "auto" (λ chosen from the data, no ``order``) fits both and returns the one with
        the lower GCV score of its orientation fit (about twice the time). GCV(λ) estimates
        σ² plus the fit's mean squared error at the sample times, so the lower score is the
        better penalty *in expectation*; one recording's two scores differ by less than
        their sampling noise when the penalties fit about equally well, and "auto" then picks
        either — including the one whose error to the true motion is several per cent larger
        (measured: jerk picked on a TUM-VI recording where the acceleration penalty's angle
        error was 7 % lower; on the recordings of ``benchmarks/fit.py`` the pick's angle
        error is within 1 % of the better penalty's). It does not guarantee the better
        penalty; fix ``penalty`` when that matters.
    knots : None, float or array_like
        None: one knot interval per median sample spacing. A float: about that spacing
        (rounded so the knots span the data exactly). An array: the knot (joint) times, strictly
        increasing from the first to the last sample time — uniform or not (denser knots where
        the motion is faster); the spline is then a non-uniform cumulative B-spline with the
        same continuity (C² / C⁴), extended beyond the ends with the end intervals' widths.
    robust : {None, "huber", "cauchy"}
        Robust loss (iteratively reweighted), so bad frames do not bend the curve. The fit
        starts from a high-breakdown pilot: runs of samples that jump more than 30° from
        their neighbours and disagree with the consensus of the recording (the chain of runs
        holding the most samples) are dropped (weight 0), then a running medoid of ±20
        samples and the Cauchy loss. Scattered glitches of any size and number that do not
        agree with each other, and bursts of consecutive flipped frames, are rejected; a
        burst longer than 20 frames that the frames it contradicts do not outnumber two to
        one raises ``ValueError`` naming its time range (give the bad frames weight 0), as
        does a scale beyond the breakdown point. Cauchy gives far glitches weight ≈ 0; Huber
        bounds their pull at c each.
    robust_scale : float, optional
        The loss's scale c in radians (default: 1.628 σ̂ for Huber, 2.666 σ̂ for Cauchy — 95 %
        efficiency at Gaussian noise — with σ̂ the per-axis noise estimated robustly from the
        pilot's residuals, at least √tol). For positions: 1.345 and 2.385 × 1.4826 × the median
        residual of the non-robust position fit, at least 1e-6 × their extent.
    order : int, optional
        Spline order (default 4 for acceleration, 6 for jerk).
    max_iter : int
        Gauss–Newton iterations allowed (1 … 100000); beyond them ``RuntimeError`` (never a
        silent result). Gauss–Newton converges only linearly where residuals are large (samples
        far from any smooth curve): such fits take a few hundred iterations.
    tol : float
        Convergence: largest control-point step in radians.
    progress : None, True or callable
        True shows a tqdm bar of the iterations, whose total is an estimate updated at every
        iteration (the iterations done plus those the step's rate of decrease still needs to
        reach ``tol``; unknown until two steps are seen). A callable gets ``(stage, done,
        total)``: after each iteration ``("fit", iterations so far, estimated total or None)``,
        once more at the end with ``done == total``, then, with positions,
        ``("positions", 0, 1)`` and ``("positions", 1, 1)`` around the position fit. An
        exception raised by the callable cancels the fit (``ValueError``).
    extrapolate : {"raise", "clamp"}
        Behaviour outside the data's time range.
    gyro : quatspline.io.ImuData or (times, rates), optional
        A gyroscope record (rates in rad/s, sensor frame) fitted together with the
        orientations: the objective gains ``κ Σⱼ |K R_bsᵀ ω(tⱼ + δ) + b − mⱼ|²``, κ = σ_q²/σ_g²,
        and the bias ``b``, time offset δ, sensor rotation ``R_bs`` (and scale ``K``) named in
        ``estimate`` are estimated jointly with the curve (see the "Fitting with a gyroscope"
        section of the IMU guide). Samples outside the orientations' time range are dropped
        with a ``RuntimeWarning``. With a gyroscope, knots default to one interval per
        gyroscope sample and ``smoothing="auto"`` to λ = κ ρ_g h^{2m} (ρ_g the gyroscope's
        rate, h one gyroscope sample spacing; "gcv" and "adaptive" are not available); robust
        losses and ``penalty="auto"`` are not available. The result's ``gyro`` holds the
        estimates and their standard deviations (the marginal covariance of the joint fit,
        given σ_g and σ_q; see the IMU guide on the estimates' bias at the default knots);
        ``effective_dof`` and ``score`` are those of the orientation term in the joint fit.
    gyro_noise : None, quatspline.io.ImuNoise or float
        σ_g, the gyroscope's white noise per axis and sample (rad/s): an ImuNoise gives it
        from its noise density at the record's rate; None estimates it from the record
        (1.4826 × the median absolute second difference / √6).
    noise_std : float, optional
        σ_q, the orientations' noise per axis (radians), with a gyroscope; None: the
        ``noise_std`` of the plain fit of the orientations.
    estimate : sequence of str
        With a gyroscope: some of ``"bias"``, ``"time_offset"``, ``"rotation"``, ``"scale"``
        (default the first three); the others are held at 0, 0, identity and 1.

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
    if gyro is not None:
        kw = dict(weights=weights, smoothing=smoothing, penalty=penalty, knots=knots)
        kw.update(robust=robust, order=order, max_iter=max_iter, tol=tol, progress=progress)
        kw.update(extrapolate=extrapolate, gyro_noise=gyro_noise, noise_std=noise_std)
        rot = _fit_gyro(t, q, gyro, estimate=estimate, **kw)
        if positions is None:
            return rot
        # positions: their own fit (λ by GCV), as without a gyroscope
        p = with_width(positions, "positions", 3)
        if p.ndim != 2 or len(p) != len(t):
            raise ValueError(f"positions: expected shape ({len(t)}, 3), got {p.shape}")
        w, (ks, ka) = _weights(weights, len(t)), _knots(knots)
        p = np.ascontiguousarray(p)
        pos = _core.fit_positions(t, p, w, penalty, order, None, ks, ka, None, None)
        pos.update(penalty=penalty, data=(t, p, w))
        return FittedPose(rot, pos, extrapolate)
    if gyro_noise is not None or noise_std is not None:
        raise ValueError("gyro_noise, noise_std: only with a gyroscope (gyro=...)")
    if penalty == "auto":
        if _lambda(smoothing, "smoothing")[0] is not None or order is not None:
            raise ValueError(
                "penalty: 'auto' compares GCV scores, so it needs λ chosen from the data "
                "(smoothing='auto', 'gcv' or 'adaptive') and no order"
            )
        kw = dict(positions=positions, weights=weights, knots=knots, robust=robust)
        kw.update(smoothing=smoothing)
        kw.update(robust_scale=robust_scale, max_iter=max_iter, tol=tol, progress=progress)
        fits = [fit(t, q, penalty=pen, extrapolate=extrapolate, **kw) for pen in _PENALTIES]
        return fits[int(np.argmin([f.score for f in fits]))]  # orientation GCV decides
    if isinstance(smoothing, tuple):
        if positions is None or len(smoothing) != 2:
            raise ValueError("smoothing: a pair (orientation λ, position λ) needs positions")
        (lam_q, mode), (lam_p, _) = (
            _lambda(smoothing[0], "smoothing[0]"),
            _lambda(smoothing[1], "smoothing[1]"),
        )
    else:
        (lam_q, mode), lam_p = _lambda(smoothing, "smoothing"), None
        lam_p = lam_q
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
    cb = None if progress is None or progress is False else _FitProgress(progress, tol, max_iter)
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
            mode,
        )
        if cb is not None:
            cb.finish(int(res["iterations"]))
        _warn_capped(res, "smoothing[0]" if isinstance(smoothing, tuple) else "smoothing")
        rot = FittedSpline(res, penalty, extrapolate, data=(t, q, w))
        if p is None:
            return rot
        if cb is not None:
            cb.stage_done("positions", 0, 1)
        pos = _core.fit_positions(t, p, w, penalty, order, lam_p, ks, ka, robust, None)
        pos.update(penalty=penalty, data=(t, p, w))
        if cb is not None:
            cb.stage_done("positions", 1, 1)
    finally:
        if cb is not None:
            cb.close()
    _warn_capped(pos, "smoothing[1]" if isinstance(smoothing, tuple) else "smoothing (positions)")
    return FittedPose(rot, pos, extrapolate)


def _fit_gyro(t, q, gyro, *, estimate, smoothing, penalty, robust, gyro_noise, noise_std, **kw):
    """The gyro-aided orientation fit (see :func:`fit`'s ``gyro``)."""
    if penalty == "auto":
        raise ValueError("penalty: 'auto' is not available with a gyroscope; give the penalty")
    if robust is not None:
        raise ValueError("robust: robust losses are not available with a gyroscope")
    lam, mode = _lambda(smoothing, "smoothing")
    if lam is None and mode != "auto":
        raise ValueError(
            f"smoothing: {mode!r} is not available with a gyroscope; use 'auto' or a number"
        )
    if lam == 0.0:
        raise ValueError("smoothing: λ = 0 (interpolation) is not available with a gyroscope")
    names = estimate_names(estimate)
    gt, gw, rate, _ = gyro_record(gyro, (float(t[0]), float(t[-1])))
    sigma_g = gyro_sigma(gyro_noise, gw, rate)
    w = _weights(kw["weights"], len(t))
    order = kw["order"]
    if order is not None:
        order = _integer(order, "order", 1, _MAX_ORDER, "a spline order")
    max_iter = _integer(kw["max_iter"], "max_iter", 1, _MAX_ITER, "an iteration count")
    tol = kw["tol"]
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise TypeError(f"tol: expected a number, got {type(tol).__name__}")
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol: expected a finite positive tolerance, got {float(tol):.6g}")
    if noise_std is None:
        sigma_q = fit(t, q, weights=w, penalty=penalty, order=order).noise_std
    elif isinstance(noise_std, numbers.Real) and not isinstance(noise_std, bool):
        sigma_q = float(noise_std)
        if not (math.isfinite(sigma_q) and sigma_q > 0):
            raise ValueError(f"noise_std: expected a finite positive angle, got {sigma_q:.6g}")
    else:
        raise TypeError(f"noise_std: expected a number, got {type(noise_std).__name__}")
    ks, ka = _knots(kw["knots"])
    cb = _progress(kw["progress"])
    try:
        res = _core.fit_rotations_gyro(
            t,
            q,
            w,
            gt,
            gw,
            penalty,
            order,
            lam,
            ks,
            ka,
            int(max_iter),
            float(tol),
            float(sigma_g),
            float(sigma_q),
            list(names),
            [0.0, 0.0, 0.0],
            0.0,
            [1.0, 0.0, 0.0, 0.0],
            progress=cb,
        )
    finally:
        if cb is not None and hasattr(cb, "close"):
            cb.close()
    out = FittedSpline(res, penalty, kw["extrapolate"], data=None)
    out.gyro = GyroEstimate.from_result(res, names, sigma_g, sigma_q, gt)
    if out.gyro.weak:
        warnings.warn(
            "fit: the motion determines " + ", ".join(out.gyro.weak) + " weakly (standard "
            "deviations above 1° for rotation, 1 % for scale, 1 ms for the time offset); see "
            "the fit's gyro.covariance, or hold them (estimate=...)",
            RuntimeWarning,
            stacklevel=3,
        )
    return out


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
