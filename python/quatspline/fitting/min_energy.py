"""Minimum-energy interpolation on the rotation group (the minimum-energy interpolants Spicv and
Sping named in the Chinese tutorial series on rigid-body motion after Gao Xiang's *14 Lectures
on Visual SLAM*).

``MinimumEnergySpline(quats, times)`` passes through every key and minimises ∫|ω̇|² (C²: the
natural spline times a correction that vanishes at the keys, never above the natural spline's
energy; or, with ``mode="exact"``, the continuous optimum itself, the Riemannian cubic spline)
or ∫|ω̈|² (C⁴: over a fine uniform B-spline space); see its docstring for how this relates to
Spicv and Sping.
"""

from __future__ import annotations

import numbers
import warnings

import numpy as np

from .. import _core
from .._util.arrays import as_real, with_width
from .._util.checks import integer
from ..splines import NaturalSpline, Spline
from ..splines.reparam import gauss_legendre
from .smoothing import _PENALTIES, _choice, _FitProgress, _times

__all__ = ["MinimumEnergySpline"]


class _StageProgress(_FitProgress):
    """The core's reports (stage, iteration, step) of a minimum-energy construction as
    (stage, done, total), per stage: ``"exact"`` (Newton's method for the Riemannian cubic;
    step = largest mismatch, to 1e-12), ``"descent"`` (the discrete form's descent; step =
    relative energy decrease, to 1e-13) and ``"fit"`` (the jerk form's solver, to 1e-12).
    ``total`` is the iterations done plus those the step's rate of decrease still needs (None
    while unknown); every stage ends with a report whose done == total."""

    TOL = {"exact": 1e-12, "descent": 1e-13, "fit": 1e-12}
    CAP = {"exact": 60, "descent": 200, "fit": 2000}

    def __init__(self, progress):
        super().__init__(progress, 1e-12, 60)
        self.stage, self.done = "", 0

    def __call__(self, stage: str, it: int, step: float) -> None:
        if stage != self.stage:
            self.end_stage()
            self.stage, self.steps, self.total = stage, [], None
            self.tol, self.max_iter = self.TOL.get(stage, 1e-12), self.CAP.get(stage, 2000)
        self.done = it
        super().__call__(stage, it, step)

    def end_stage(self) -> None:
        """The current stage ended (a last report with done == total)."""
        if self.stage and self.done:
            self.finish(self.done)
        self.done = 0


class MinimumEnergySpline(Spline):
    """The interpolating spline of least turning energy through every key.

    ``penalty="acceleration"`` minimises ∫|ω̇|² dt subject to q(tᵢ) = qᵢ (C²; the rotation-group
    analogue of the natural cubic spline, whose exact solutions are Riemannian cubics,
    ω‴ + ω × ω″ = 0 between keys); ``penalty="jerk"`` minimises the body-frame ∫|ω̈|² (C⁴).

    Construction (acceleration): q(t) = N(t)·Exp(δ(t)), N the :class:`NaturalSpline` through
    the same keys with the same ``ends``, δ a C² correction that vanishes at every key (per key
    interval: quintic Hermite terms in the rates vᵢ = δ′(tᵢ), aᵢ = δ″(tᵢ) plus ``resolution``
    polynomial bubbles s³(1−s)³P_k). δ = 0 is the natural spline itself, and the energy (an
    8-piece × 10-node Gauss–Legendre sum per key interval) is lowered from there by
    Levenberg–Marquardt accepting only descent steps, so the result's ∫|ω̇|² is never above the
    natural spline's (equal only when that is already optimal). Raising ``resolution`` nests the
    spaces and converges to the continuous optimum (Spicv, analytic, in that tutorial's terms;
    this is the discrete numerical route, Sping). Joints are the key times.

    Holds: consecutive equal keys give an exactly constant interval (ω = α = jerk = 0 there),
    as in the other interpolating splines: the natural spline pins the rate to zero at both
    keys of a hold and δ is held at zero on it (the curve is C¹ at those keys, C² elsewhere).

    The descent stops at its criterion or after 200 iterations; either way the result is the
    best iterate found, never above the natural spline's energy. When the cap is reached
    first, ``converged`` is False and a ``RuntimeWarning`` says how far it got (iterations,
    energy against the natural spline's, gradient norm) — the curve is valid and
    interpolating, only not the optimum to the solver's precision.

    ``mode="exact"`` (acceleration only) returns the continuous optimum itself, the Riemannian
    cubic spline (Spicv): between keys ω⃛ + ω × ω̈ = 0 (body frame; Noakes, Heinzinger & Paden
    1989; Crouch & Silva Leite 1995), with ω and ω̇ continuous at the keys (the jump of ω̈ there
    is the Lagrange multiplier of the interpolation constraint) and ω̇ = 0 at natural ends.
    Each key interval is integrated by a Taylor series method of order 20 (steps to 1e-16
    relative), and the states (ω, ω̇, ω̈) at the keys are found by Newton's method on the
    banded shooting system (linear in the keys), starting from the natural spline; it stops
    when the largest mismatch at the keys (radians; ω·h, ω̇·h² for interval length h) is at
    most 1e-12. ω, ω̇, jerk are those of the series (exact to ~1e-14); the Euler–Lagrange
    residual ‖ω⃛ + ω × ω̈‖ is at the series' truncation level (tested ≤ 1e-8 by finite
    differences). When Newton's method does not converge (keys far apart, where the start
    lies outside its basin) a ``RuntimeError`` says so; the discrete mode still returns a
    curve. Holds are constant as above.

    Construction (jerk): the minimum-∫|ω̈|² curve through the keys in a uniform cumulative
    B-spline space of order 6 with ``resolution`` knot intervals per mean key interval
    (doubled where keys crowd), by Gauss–Newton with Bregman iteration to 1e-11 rad.

    Parameters
    ----------
    quats : array_like, shape (N, 4)
        Keys, N ≥ 2 (N ≥ 3 for jerk and for ``ends="closed"``).
    times : array_like, shape (N,), optional
        Strictly increasing key times (default 0 … N−1); with ``ends="closed"`` N + 1 times (the
        last closes the loop), as :class:`NaturalSpline`.
    penalty : {"acceleration", "jerk"}
    ends : {"natural", "rest", "clamped", "closed"}
        ``natural``: free ends (the optimum has ω̇ = 0 there); ``rest``: zero angular velocity
        at both ends; ``clamped``: the given ``start_rate`` / ``end_rate`` (body frame, rad/s;
        default the end chords' rates); ``closed``: a C² loop. Jerk: ``natural`` only.
    mode : {"discrete", "exact"}
        Acceleration: the discrete optimum over ``resolution`` bubbles (default) or the
        continuous optimum (the Riemannian cubic; ``resolution`` must then be None).
    start_rate, end_rate : array_like, shape (3,), optional
        With ``ends="clamped"``.
    resolution : int, optional
        Acceleration: bubble polynomials per key interval (0 … 16, default 4). Jerk: knot
        intervals per mean key interval (1 … 64, default 8).
    extrapolate : {"raise", "clamp"}
    progress : None, True or callable
        True shows a tqdm bar; a callable gets ``(stage, done, total)`` after every iteration
        of each stage: ``"exact"`` (Newton's method for the Riemannian cubic: the exact mode,
        and the discrete mode's start), ``"descent"`` (the discrete descent) or ``"fit"`` (the
        jerk form's solver). ``total`` is the iterations done plus those the rate of decrease
        of the step still needs (None until two steps are seen); each stage ends with a report
        whose ``done == total``. An exception raised by the callable cancels the construction.

    Attributes
    ----------
    energy, natural_energy : float
        The penalised energy of this spline and of :class:`NaturalSpline` through the same
        keys with the same ends: ∫|ω̇|² for ``acceleration`` (the quadrature above), the
        body-frame ∫|ω̈|² for ``jerk`` (8-point Gauss–Legendre between the joints of both).
    iterations : int
    converged : bool
        Acceleration: whether the descent met its criterion (else: the best iterate after
        the iteration cap, with a ``RuntimeWarning``). Jerk: True (that solver raises when it
        does not converge).
    gradient_norm : float
        Acceleration: the norm of the energy's gradient over the free parameters at the
        result (NaN for jerk and for ``mode="exact"``).
    jacobian_passes : int
        The discrete acceleration form: passes of the Jacobian over all quadrature nodes (its
        construction's dominant cost: one per descent iteration, plus one for the gradient at
        the result when the last step moved it); 0 otherwise.
    residual : float
        ``mode="exact"``: the largest scaled mismatch of the shooting equations at the keys
        (≤ 1e-12); NaN otherwise.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> q = qs.from_rotvec([[0, 0, 0], [0.5, 0, 0], [0.5, 0.5, 0], [0, 0.5, 0.3]])
    >>> s = qs.MinimumEnergySpline(q)
    >>> bool(np.allclose(np.abs(np.sum(s([0.0, 1.0, 2.0, 3.0]) * q, axis=1)), 1.0))
    True
    >>> bool(s.energy <= s.natural_energy)
    True
    >>> e = qs.MinimumEnergySpline(q, mode="exact")
    >>> bool(e.energy <= s.energy and e.residual <= 1e-12)
    True
    """

    @property
    def interpolates(self) -> bool:
        return True

    @property
    def method(self) -> str:
        return "min_energy"

    def __init__(
        self,
        quats,
        times=None,
        penalty: str = "acceleration",
        ends: str = "natural",
        resolution: int | None = None,
        extrapolate: str = "raise",
        progress=None,
        start_rate=None,
        end_rate=None,
        mode: str = "discrete",
    ):
        penalty = _choice(penalty, "penalty", _PENALTIES)
        mode = _choice(mode, "mode", ("discrete", "exact"))
        if mode == "exact" and penalty != "acceleration":
            raise ValueError(f"mode: 'exact' is for penalty='acceleration', got {penalty!r}")
        if mode == "exact" and resolution is not None:
            raise ValueError(f"resolution: only with mode='discrete', got {resolution!r}")
        ends = _choice(ends, "ends", ("natural", "rest", "clamped", "closed"))
        if penalty == "jerk" and ends != "natural":
            raise ValueError(f"ends: penalty='jerk' supports ends='natural' only, got {ends!r}")
        q = with_width(quats, "quats", 4)
        if q.ndim != 2:
            raise ValueError(f"quats: expected shape (N, 4), got {q.shape}")
        closed = ends == "closed"
        n_t = len(q) + 1 if closed else len(q)
        t = np.arange(n_t, dtype=float) if times is None else _times(times)
        if len(t) != n_t:
            what = "one per key plus one closing the loop" if closed else "one per key"
            raise ValueError(f"times: expected {n_t} times ({what}), got {len(t)}")
        if resolution is None and mode == "discrete":
            resolution = 4 if penalty == "acceleration" else 8
        if mode == "discrete":
            if isinstance(resolution, bool) or not isinstance(resolution, numbers.Integral):
                raise TypeError(f"resolution: expected an integer, got {type(resolution).__name__}")
            resolution = integer(
                resolution, "resolution", *((0, 16) if penalty == "acceleration" else (1, 64))
            )
        rates = []
        for name, r in (("start_rate", start_rate), ("end_rate", end_rate)):
            if r is not None and ends != "clamped":
                raise ValueError(f"{name}: only with ends='clamped'")
            if r is not None:
                r = as_real(r, name).reshape(-1)
                if r.shape != (3,):
                    raise ValueError(f"{name}: expected 3 components (rad/s), got {r.size}")
                if not np.all(np.isfinite(r)):
                    raise ValueError(
                        f"{name}: non-finite component {int(np.argmin(np.isfinite(r)))}"
                    )
                r = r.tolist()
            rates.append(r)
        if progress is None or progress is False:
            cb = None
        else:
            cb = _StageProgress(progress)
        self.residual = float("nan")
        self.jacobian_passes = 0
        try:
            if mode == "exact":
                tt = None if times is None else np.ascontiguousarray(t)
                core, res = _core.riemannian_cubic_spline(
                    np.ascontiguousarray(q), tt, ends, rates[0], rates[1], cb
                )
                self.energy = float(res["energy"])
                self.natural_energy = float(res["energy_natural"])
                self.converged, self.gradient_norm = True, float("nan")
                self.residual = float(res["residual"])
            elif penalty == "jerk":
                res = _core.min_energy(
                    np.ascontiguousarray(t), np.ascontiguousarray(q), penalty, int(resolution), cb
                )
                core = _core.cumulative_bspline(
                    res["ctrl"], res["dt"], res["t0"], res["order"], True
                )
                self.control_quats = res["ctrl"]
                self.order = int(res["order"])
                self.converged, self.gradient_norm = True, float("nan")
                self.energy = self.natural_energy = float("nan")  # set below, once built
            else:
                tt = None if times is None else np.ascontiguousarray(t)
                core, res = _core.min_energy_spline(
                    np.ascontiguousarray(q), tt, ends, rates[0], rates[1], int(resolution), cb
                )
                self.energy = float(res["energy"])
                self.natural_energy = float(res["energy_natural"])
                self.converged = bool(res["converged"])
                self.gradient_norm = float(res["gradient_norm"])
                self.jacobian_passes = int(res["jacobian_passes"])
                if not self.converged:
                    warnings.warn(
                        f"MinimumEnergySpline: stopped after {int(res['iterations'])} "
                        f"iterations before converging; returning the best iterate (energy "
                        f"{self.energy:.6g}, natural spline {self.natural_energy:.6g}, "
                        f"gradient norm {self.gradient_norm:.3g})",
                        RuntimeWarning,
                        stacklevel=2,
                    )
            if cb is not None:
                cb.end_stage()
        finally:
            if cb is not None:
                cb.close()
        super().__init__(core, extrapolate)
        if penalty == "jerk":
            natural = NaturalSpline(q, t)
            self.energy = _jerk_energy(self, natural)
            self.natural_energy = _jerk_energy(natural, self)
        self.iterations = int(res["iterations"])
        self.penalty = penalty
        self.params = dict(
            quats=q, times=t, penalty=penalty, ends=ends, resolution=resolution, mode=mode
        )
        self.ends = ends
        self.mode = mode


def _jerk_energy(s: Spline, other: Spline) -> float:
    """∫|ω̈|² dt (body frame) of ``s`` over its domain: 8-point Gauss–Legendre on every interval
    between the joints of ``s`` and ``other`` (both smooth inside them)."""
    lo, hi = s.domain
    edges = np.unique(np.clip(np.r_[s.joints, other.joints, lo, hi], lo, hi))
    return gauss_legendre(edges, lambda t: np.sum(s.jerk(np.clip(t, lo, hi), "body") ** 2, -1))
