"""Gyroscope calibration against a reference motion: sensor rotation, bias, scale (and
misalignment), time offset, with standard errors and residuals.

The model (rates in rad/s, the sensor frame on the left)::

    ω_meas(tᵢ) = K · R_bsᵀ · ω_body(tᵢ + δ) + b + noise

- ``ω_body(t)`` is the reference motion's angular velocity in its body frame (exact, from
  the spline's derivatives);
- ``R_bs`` is the sensor's orientation in the body frame (a vector in sensor axes ``v_s``
  is ``R_bs v_s`` in body axes), so the sensor sees ``R_bsᵀ ω_body``;
- ``K`` is the scale: diagonal (``"scale"``), or upper triangular with the scale on its
  diagonal and three non-orthogonality terms above it (``"misalignment"``: ``K[0, 1]``,
  ``K[0, 2]``, ``K[1, 2]``; a general 3 × 3 matrix would absorb the rotation, which is why
  only the upper triangle is free);
- ``b`` is a constant gyroscope bias;
- ``δ`` is the time offset: a sample stamped ``t`` on the IMU's clock measures the motion at
  ``t + δ`` (δ > 0: the IMU's stamps run behind the motion's clock), the sign of
  :class:`quatspline.imu.SensorModel`'s ``time_offset``.

The method: a coarse δ by the cross-correlation of the rotation-invariant ``|ω|`` over
``±max_offset``; the rotation by Kabsch (the SVD solution of Wahba's problem) on the
mean-removed rate vectors, the bias from the means; then a joint nonlinear least-squares
solve (``scipy.optimize.least_squares``, trust region, analytic Jacobian) over the rotation
(right perturbation ``R_bs · Exp(θ)``), bias, scale, misalignment and δ, on the samples that
lie inside the motion's domain after the shift. Standard errors are ``σ̂² (JᵀJ)⁻¹`` at the
solution, with ``σ̂²`` the residual sum of squares over the degrees of freedom (with a robust
loss: the iteratively reweighted form of the same).

Parameters the motion excites too little to be of use — a standard error above 1° for the
rotation, 1 % for scale and misalignment, 1 ms for δ, or resting on a sensor axis whose rate
varies less than √10 times its residual (the standard errors assume an exact reference; a
noisy one drags such an axis's scale towards 0) — are estimated but listed in
:attr:`Calibration.weak` and named in a ``RuntimeWarning``. Parameters the motion does not
excite at all (the Jacobian's columns, scaled to unit norm, have a
null space: a device at rest leaves rotation, scale and δ unobservable; a rotation about one
axis leaves the rotation about that axis and the other axes' scales) are held at their
starting values — rotation: the smallest one that aligns the rates, scale 1,
misalignment 0, δ from the correlation (0 without a peak) — listed in
:attr:`Calibration.unobservable` with infinite standard errors, and named in a
``RuntimeWarning``. The bias is observable from any motion.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._util.checks import choice, real
from .._util.optional import need
from ..core.convert import as_matrix, from_matrix, from_rotvec
from ..fitting import WEAK_STD, fit
from ..io import ImuData, Trajectory
from ..plot import save

__all__ = ["ESTIMATES", "Calibration", "calibrate"]

#: The parameters :func:`calibrate` can estimate.
ESTIMATES = ("rotation", "bias", "scale", "misalignment", "time_offset")
#: What :func:`calibrate` estimates by default.
DEFAULT_ESTIMATE = ("rotation", "bias", "scale", "time_offset")
#: Robust losses (those of ``quatspline.fit``).
ROBUST = ("huber", "cauchy")
#: Fewest samples inside the motion's domain: 13 parameters at most, 3 residuals a sample.
MIN_SAMPLES = 10

_AXES = "xyz"
#: The name of each component of the parameter vector [θ, b, s, m, δ].
COMPONENTS = (
    *(f"rotation[{a}]" for a in _AXES),
    *(f"bias[{a}]" for a in _AXES),
    *(f"scale[{a}]" for a in _AXES),
    "misalignment[xy]",
    "misalignment[xz]",
    "misalignment[yz]",
    "time_offset",
)
_SLICES = {
    "rotation": slice(0, 3),
    "bias": slice(3, 6),
    "scale": slice(6, 9),
    "misalignment": slice(9, 12),
    "time_offset": slice(12, 13),
}
# A direction of parameter space is unobservable when its scaled singular value is below this
# fraction of the largest (double precision leaves ~1e-16 on an exactly singular one).
_NULL_TOL = 1e-8
# A sensor axis is silent when its rate's variance is below this multiple of its residual's.
_SILENT = 10.0
# Constants of the robust losses at 95 % efficiency for Gaussian noise (Huber 1964; Holland
# & Welsch 1977), in units of the noise's standard deviation.
_ROBUST_C = {"huber": 1.345, "cauchy": 2.385}


@dataclass
class Calibration:
    """The result of :func:`calibrate`.

    Attributes
    ----------
    rotation : numpy.ndarray, shape (4,)
        ``R_bs`` as a unit quaternion (w, x, y, z): the sensor's orientation in the body frame.
    gyro_bias : numpy.ndarray, shape (3,)
        Bias, rad/s, sensor frame.
    scale : numpy.ndarray, shape (3,)
        The diagonal of ``K`` (1 = no scale error).
    misalignment : numpy.ndarray, shape (3,)
        ``K[0, 1]``, ``K[0, 2]``, ``K[1, 2]`` (zeros unless estimated).
    time_offset : float
        δ in seconds: the sample stamped ``t`` measures the motion at ``t + δ``.
    standard_errors : dict of str to numpy.ndarray
        One per parameter (``"rotation"``: rad, about the sensor's axes; ``"gyro_bias"``:
        rad/s; ``"scale"``, ``"misalignment"``: arrays of 3; ``"time_offset"``: a float,
        s). 0 for a parameter not estimated, inf for one the motion does not excite.
    covariance : numpy.ndarray, shape (13, 13)
        Of the components :data:`COMPONENTS` (rotation as the right perturbation).
    times : numpy.ndarray, shape (N,)
        The IMU times of the samples used.
    measured, predicted, residuals : numpy.ndarray, shape (N, 3)
        The gyroscope, the model at the solution and their difference (measured − predicted).
    rms : numpy.ndarray, shape (3,)
        RMS residual per axis, rad/s.
    sigma : float
        σ̂, the residual standard deviation per axis, rad/s.
    estimated : tuple of str
        The parameters estimated.
    unobservable : tuple of str
        Components the motion does not excite (held, standard error inf).
    weak : tuple of str
        Components estimated, but with a standard error above 1° (rotation), 1 % (scale,
        misalignment) or 1 ms (time offset), or resting on a sensor axis whose rate varies
        less than √10 times its residual (its scale, the misalignment terms it multiplies,
        the rotation about an axis whose two partners are both such): the motion excites
        them too little.
    converged : bool
        Whether the least-squares solver met its tolerance.
    """

    rotation: np.ndarray
    gyro_bias: np.ndarray
    scale: np.ndarray
    misalignment: np.ndarray
    time_offset: float
    standard_errors: dict
    covariance: np.ndarray
    times: np.ndarray
    measured: np.ndarray
    predicted: np.ndarray
    residuals: np.ndarray
    rms: np.ndarray
    sigma: float
    estimated: tuple
    unobservable: tuple = ()
    weak: tuple = ()
    converged: bool = True
    nfev: int = 0
    extra: dict = field(default_factory=dict)

    @property
    def scale_matrix(self) -> np.ndarray:
        """``K``: the scale on the diagonal, the misalignment above it."""
        return _k_matrix(self.scale, self.misalignment)

    @property
    def rotation_matrix(self) -> np.ndarray:
        """``R_bs`` as a 3 × 3 matrix."""
        return as_matrix(self.rotation)

    def correct(self, gyro) -> np.ndarray:
        """Corrected rates in the body frame: ``R_bs K⁻¹ (ω_meas − b)``, shape (N, 3)."""
        g = np.asarray(gyro, dtype=float)
        k_inv = np.linalg.inv(self.scale_matrix)
        return (g - self.gyro_bias) @ k_inv.T @ self.rotation_matrix.T

    def table(self) -> str:
        """The estimates with their standard errors, one line each (degrees, °/s, ms, ppm)."""
        se = self.standard_errors
        rv = _rotvec(self.rotation)
        rows = [
            ("rotation R_bs (rotation vector, °)", np.degrees(rv), np.degrees(se["rotation"])),
            ("gyro bias (°/s)", np.degrees(self.gyro_bias), np.degrees(se["gyro_bias"])),
            ("scale − 1 (ppm)", (self.scale - 1.0) * 1e6, se["scale"] * 1e6),
        ]
        if "misalignment" in self.estimated:
            rows.append(("misalignment (ppm)", self.misalignment * 1e6, se["misalignment"] * 1e6))
        rows.append(("time offset (ms)", [self.time_offset * 1e3], [se["time_offset"] * 1e3]))
        rows.append(("RMS residual (°/s)", np.degrees(self.rms), None))
        width = max(len(r[0]) for r in rows)
        lines = []
        for name, value, err in rows:
            if err is None:
                cells = [f"{v:12.5g}" for v in value]
            else:
                cells = [f"{v:12.5g} ± {e:<10.3g}" for v, e in zip(value, err)]
            lines.append(f"{name:<{width}}  " + "  ".join(cells))
        lines.append(f"{'samples':<{width}}  {len(self.times)}")
        if self.unobservable:
            lines.append(f"{'not excited (held)':<{width}}  {', '.join(self.unobservable)}")
        if self.weak:
            lines.append(f"{'weakly excited':<{width}}  {', '.join(self.weak)}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """The estimates, standard errors and residual statistics as plain JSON-ready data."""
        return {
            "rotation_wxyz": self.rotation.tolist(),
            "gyro_bias": self.gyro_bias.tolist(),
            "scale": self.scale.tolist(),
            "misalignment": self.misalignment.tolist(),
            "time_offset": float(self.time_offset),
            "standard_errors": {k: _finite_or_none(v) for k, v in self.standard_errors.items()},
            "rms": self.rms.tolist(),
            "sigma": float(self.sigma),
            "samples": int(len(self.times)),
            "estimated": list(self.estimated),
            "unobservable": list(self.unobservable),
            "weak": list(self.weak),
            "converged": bool(self.converged),
        }

    def plot_residuals(self, path=None, *, name: str = ""):
        """The figure: per axis the measured and predicted rates, then the residuals.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            Where to write it (.png, .svg or .pdf, atomically).
        name : str
            A title prefix (the recording's name).

        Returns
        -------
        matplotlib.figure.Figure
        """
        figure = need("matplotlib.figure", extra="plot", what="the calibration figure")
        fig = figure.Figure(figsize=(9, 8), layout="constrained")
        axes = fig.subplots(4, 1, sharex=True)
        t = self.times
        for j, ax in enumerate(axes[:3]):
            ax.plot(t, np.degrees(self.measured[:, j]), lw=0.6, color="0.55", label="measured")
            ax.plot(t, np.degrees(self.predicted[:, j]), lw=0.9, color="C0", label="predicted")
            ax.set_ylabel(f"ω_{_AXES[j]} (°/s)")
        axes[0].legend(loc="upper right", fontsize="small")
        for j in range(3):
            axes[3].plot(
                t,
                np.degrees(self.residuals[:, j]),
                lw=0.5,
                color=f"C{j + 1}",
                label=f"{_AXES[j]}: RMS {math.degrees(self.rms[j]):.3g} °/s",
            )
        axes[3].set_ylabel("residual (°/s)")
        axes[3].set_xlabel("IMU time (s)")
        axes[3].legend(loc="upper right", fontsize="small")
        title = (
            f"gyroscope calibration: δ = {self.time_offset * 1e3:.3g} ms, "
            f"σ̂ = {math.degrees(self.sigma):.3g} °/s"
        )
        fig.suptitle(f"{name}: {title}" if name else title)
        if path is not None:
            save(fig, path)
        return fig


# ---- small helpers ------------------------------------------------------------------------------
def _finite_or_none(v):
    """JSON has no inf: a number, None for an infinite one; lists element-wise."""
    if np.ndim(v):
        return [_finite_or_none(x) for x in v]
    return float(v) if np.isfinite(v) else None


def _rotvec(q) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    q = q if q[0] >= 0 else -q
    s = np.linalg.norm(q[1:])
    if s < 1e-300:
        return np.zeros(3)
    return q[1:] / s * 2.0 * math.atan2(s, q[0])


def _skew(v: np.ndarray) -> np.ndarray:
    """``[v]×`` for each row of v: shape (..., 3, 3)."""
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack(
        [np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2
    )


def _exp(theta: np.ndarray) -> np.ndarray:
    return as_matrix(from_rotvec(theta))


def _right_jacobian(theta: np.ndarray) -> np.ndarray:
    """``J_r(θ)`` of SO(3): ``Exp(θ + dθ) ≈ Exp(θ) Exp(J_r dθ)`` (Sola et al. 2018, eq. 143);
    a Taylor series below 1e-4 rad (error below 1e-17)."""
    phi = float(np.linalg.norm(theta))
    k = _skew(theta)
    if phi < 1e-4:
        a = 0.5 - phi**2 / 24.0
        b = 1.0 / 6.0 - phi**2 / 120.0
    else:
        a = (1.0 - math.cos(phi)) / phi**2
        b = (phi - math.sin(phi)) / phi**3
    return np.eye(3) - a * k + b * (k @ k)


def _k_matrix(s, m) -> np.ndarray:
    return np.array([[s[0], m[0], m[1]], [0.0, s[1], m[2]], [0.0, 0.0, s[2]]])


def _kabsch(body: np.ndarray, sensor: np.ndarray) -> np.ndarray:
    """R minimising Σ|bodyᵢ − R sensorᵢ|² (Wahba's problem, SVD solution; Markley 1988).
    Where the vectors span fewer than three directions the rotation about the missing
    axis is the smallest one (the SVD's choice); with no vectors at all, the identity."""
    h = body.T @ sensor
    u, sv, vt = np.linalg.svd(h)
    if not np.isfinite(sv[0]) or sv[0] <= 0.0:
        return np.eye(3)
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    return u @ np.diag([1.0, 1.0, d]) @ vt


def _as_data(data) -> ImuData:
    if isinstance(data, ImuData):
        return data
    if isinstance(data, tuple) and len(data) == 2:
        return ImuData(data[0], data[1])
    raise TypeError(f"data: expected an ImuData or a (times, gyro) pair, got {type(data).__name__}")


def _as_motion(motion, smoothing) -> tuple:
    """The reference spline and the time its clock starts at: a spline as given (0); a
    Trajectory through a smoothing fit on times relative to its first (for accuracy with
    large time stamps: the IMU's times are shifted alike)."""
    if isinstance(motion, Trajectory):
        t0 = float(motion.times[0])
        return fit(motion.times - t0, motion.quats, smoothing=smoothing), t0
    if not (hasattr(motion, "angular_velocity") and hasattr(motion, "domain")):
        raise TypeError(
            "motion: expected a rotation or pose spline (with angular_velocity and domain) or a "
            f"quatspline.io.Trajectory, got {type(motion).__name__}"
        )
    return motion, 0.0


def _coarse_offset(motion, t: np.ndarray, g: np.ndarray, max_offset: float) -> tuple:
    """δ maximising the correlation of |ω_meas(tᵢ)| with |ω_body(tᵢ + δ)| over lags of one
    sample interval in ±max_offset, refined by a parabola through the peak; 0 (and False)
    when |ω| does not vary."""
    a, b = motion.domain
    h = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    grid = np.arange(a, b + 0.5 * h, h)
    grid = np.clip(grid, a, b)
    wb = np.linalg.norm(motion.angular_velocity(grid, frame="body"), axis=-1)
    wm = np.linalg.norm(g, axis=-1)
    k = int(math.floor(max_offset / h))
    lags = np.arange(-k, k + 1) * h
    corr = np.full(lags.size, -np.inf)
    for j, d in enumerate(lags):
        tau = t + d
        inside = (tau >= a) & (tau <= b)
        if np.count_nonzero(inside) < MIN_SAMPLES:
            continue
        x = wm[inside]
        y = np.interp(tau[inside], grid, wb)
        x = x - x.mean()
        y = y - y.mean()
        # element-wise sums, not BLAS dot products: a threaded BLAS on a busy machine spends
        # milliseconds per call starting its threads (measured: 401 lags of 24,000 samples
        # took 23 s with `@`, 0.2 s this way)
        den = math.sqrt(float(np.sum(x * x)) * float(np.sum(y * y)))
        if den > 0.0:
            corr[j] = float(np.sum(x * y)) / den
    if not np.any(np.isfinite(corr)):
        return 0.0, False
    j = int(np.argmax(corr))
    d = float(lags[j])
    if 0 < j < lags.size - 1 and np.all(np.isfinite(corr[j - 1 : j + 2])):
        c0, c1, c2 = corr[j - 1], corr[j], corr[j + 1]
        den = c0 - 2.0 * c1 + c2
        if den < 0.0:
            d += 0.5 * h * (c0 - c2) / den
    return d, True


class _Problem:
    """Residuals and the analytic Jacobian of the gyroscope model on a fixed sample set."""

    def __init__(self, motion, t, g, r0):
        self.motion, self.t, self.g, self.r0 = motion, t, g, r0
        self.a, self.b = motion.domain

    def evaluate(self, x: np.ndarray, jacobian: bool = True):
        theta, bias, s, m, delta = x[0:3], x[3:6], x[6:9], x[9:12], x[12]
        rot = self.r0 @ _exp(theta)
        tau = np.clip(self.t + delta, self.a, self.b)
        wb = self.motion.angular_velocity(tau, frame="body")
        u = wb @ rot  # rows Rᵀ ω_body
        k = _k_matrix(s, m)
        pred = u @ k.T + bias
        if not jacobian:
            return pred, None
        n = self.t.size
        jac = np.zeros((n, 3, 13))
        jac[:, :, 0:3] = k @ _skew(u) @ _right_jacobian(theta)
        jac[:, :, 3:6] = np.eye(3)
        for i in range(3):
            jac[:, i, 6 + i] = u[:, i]
        jac[:, 0, 9] = u[:, 1]
        jac[:, 0, 10] = u[:, 2]
        jac[:, 1, 11] = u[:, 2]
        ab = self.motion.angular_acceleration(tau, frame="body")
        jac[:, :, 12] = (ab @ rot) @ k.T
        return pred, jac.reshape(3 * n, 13)


def _observable(jac: np.ndarray, free: np.ndarray) -> tuple:
    """The map from reduced coordinates to the free components that the data determine
    (column-scaled SVD), and the components with a part in the null space."""
    cols = np.flatnonzero(free)
    j = jac[:, cols]
    norms = np.linalg.norm(j, axis=0)
    scale = float(norms.max()) if norms.size else 0.0
    live = norms > _NULL_TOL * max(scale, 1e-300)
    dead = set(cols[~live].tolist())
    cols = cols[live]
    if cols.size:
        jn = jac[:, cols] / norms[live]
        _, sv, vt = np.linalg.svd(jn, full_matrices=False)
        keep = sv > _NULL_TOL * sv[0]
        null = vt[~keep]
        for v in null:
            dead |= {int(cols[i]) for i in np.flatnonzero(np.abs(v) > 1e-3)}
        basis = np.zeros((13, int(keep.sum())))
        basis[cols] = (vt[keep] / norms[live]).T
    else:
        basis = np.zeros((13, 0))
    return basis, sorted(dead)


def calibrate(
    motion,
    data,
    *,
    estimate=DEFAULT_ESTIMATE,
    max_offset: float = 1.0,
    robust: str | None = None,
    smoothing="auto",
) -> Calibration:
    """Calibrates a gyroscope against a reference motion sharing its clock up to an offset.

    Estimates ``R_bs``, bias ``b``, scale ``K`` and time offset δ of the model
    ``ω_meas(tᵢ) = K R_bsᵀ ω_body(tᵢ + δ) + b`` (the module's documentation gives the frames,
    signs and method).

    Parameters
    ----------
    motion : Spline, PoseSpline, FittedSpline, FittedPose or quatspline.io.Trajectory
        The reference (motion capture). Any spline is used as it is (its exact body-frame
        angular velocity and acceleration); a Trajectory is first smoothed by
        :func:`quatspline.fit` (``smoothing``; GCV by default), because differentiating an
        interpolant through noisy mocap amplifies the noise.
    data : quatspline.io.ImuData or (times, gyro)
        The IMU record; times on the IMU's clock, gyro in rad/s.
    estimate : sequence of str
        Some of ``"rotation"``, ``"bias"``, ``"scale"``, ``"misalignment"``,
        ``"time_offset"`` (default: all but misalignment). The others are held at identity,
        0, 1, 0 and 0.
    max_offset : float
        The largest offset magnitude ‖δ‖ searched, seconds (default 1).
    robust : {"huber", "cauchy"}, optional
        A robust loss against glitches (scale: 1.4826 × the median absolute residual of a
        first plain solve).
    smoothing : "auto" or float
        λ of the fit when ``motion`` is a Trajectory.

    Returns
    -------
    Calibration

    Raises
    ------
    ValueError
        An unknown parameter name, a negative or non-finite ``max_offset``, an IMU record
        whose times do not overlap the motion's domain (within ``max_offset``), fewer than
        10 samples inside it.
    TypeError
        ``motion`` or ``data`` of the wrong kind.
    ImportError
        scipy is missing (``pip install "quatspline[scipy]"``).

    Warns
    -----
    RuntimeWarning
        When the motion does not excite a parameter (named; held, standard error inf), or
        excites it weakly (named; standard error above 1°, 1 % or 1 ms).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> from quatspline.io import ImuData
    >>> from quatspline.imu import calibrate
    >>> tk = np.linspace(0, 10, 41)
    >>> keys = qs.from_rotvec(np.c_[np.sin(tk), np.cos(0.7 * tk), np.sin(1.3 * tk)])
    >>> motion = qs.spline("c3", keys, tk)
    >>> t = np.arange(0.5, 9.5, 0.01)
    >>> r_bs = qs.as_matrix(qs.from_rotvec([0.1, -0.2, 0.3]))
    >>> gyro = motion.angular_velocity(t + 0.02, frame="body") @ r_bs + [0.01, 0, -0.02]
    >>> cal = calibrate(motion, ImuData(t, gyro), estimate=("rotation", "bias", "time_offset"))
    >>> round(cal.time_offset, 6), np.round(cal.gyro_bias, 6).tolist()
    (0.02, [0.01, 0.0, -0.02])
    """
    opt = need("scipy.optimize", extra="scipy", what="quatspline.imu.calibrate")
    if isinstance(estimate, str):
        estimate = (estimate,)
    estimate = tuple(estimate)
    for e in estimate:
        choice(e, "estimate", ESTIMATES)
    max_offset = real(max_offset, "max_offset")
    if not math.isfinite(max_offset) or max_offset < 0:
        raise ValueError(f"max_offset: expected a finite number ≥ 0 seconds, got {max_offset}")
    if robust is not None:
        robust = choice(robust, "robust", ROBUST)
    data = _as_data(data)
    motion, t0 = _as_motion(motion, smoothing)
    a, b = (float(v) for v in motion.domain)
    t_all, g_all = data.times - t0, data.gyro
    if t_all.size == 0 or t_all[-1] + max_offset < a or t_all[0] - max_offset > b:
        span = "no samples" if t_all.size == 0 else f"[{t_all[0] + t0:g}, {t_all[-1] + t0:g}]"
        raise ValueError(
            f"data: the IMU's times {span} do not overlap the motion's domain "
            f"[{a + t0:g}, {b + t0:g}] "
            f"(within max_offset = {max_offset:g} s)"
        )

    # 1. coarse δ (rotation-invariant), 2. rotation and bias by Kabsch on centred rates
    delta0 = 0.0
    if "time_offset" in estimate and max_offset > 0:
        delta0, _ = _coarse_offset(motion, t_all, g_all, max_offset)
    h = float(np.median(np.diff(t_all))) if t_all.size > 1 else 0.0
    margin = min(5.0 * h, 0.05 * (b - a)) if "time_offset" in estimate else 0.0

    x = np.zeros(13)
    x[6:9] = 1.0
    x[12] = delta0
    free = np.zeros(13, dtype=bool)
    for e in estimate:
        free[_SLICES[e]] = True

    r0 = np.eye(3)
    fitted = None
    for _ in range(4):  # re-select the samples if δ moved beyond the margin
        tau = t_all + x[12]
        inside = (tau >= a + margin) & (tau <= b - margin)
        n = int(np.count_nonzero(inside))
        if n < MIN_SAMPLES:
            raise ValueError(
                f"data: {n} IMU samples inside the motion's domain [{a + t0:g}, {b + t0:g}] "
                "after the "
                f"time offset {x[12]:.6g} s; at least {MIN_SAMPLES} are needed"
            )
        t, g = t_all[inside], g_all[inside]
        if fitted is None:
            wb = motion.angular_velocity(np.clip(t + x[12], a, b), frame="body")
            if "rotation" in estimate:
                r0 = _kabsch(wb - wb.mean(0), g - g.mean(0))
            if "bias" in estimate:
                x[3:6] = g.mean(0) - wb.mean(0) @ r0
        problem = _Problem(motion, t, g, r0)
        fitted = _solve(problem, x, free, robust, opt)
        moved = abs(fitted["x"][12] - x[12]) if margin > 0 else 0.0
        r0 = problem.r0 @ _exp(fitted["x"][0:3])
        x = fitted["x"].copy()
        x[0:3] = 0.0
        if moved <= margin:
            break
    cal = _result(problem, r0, x, fitted, free, estimate)
    cal.times += t0
    return cal


def _solve(problem: _Problem, x0: np.ndarray, free: np.ndarray, robust, opt) -> dict:
    """Least squares in the observable coordinates; plain first, then the robust loss."""
    _, jac0 = problem.evaluate(x0)
    basis, dead = _observable(jac0, free)

    def full(y):
        return x0 + basis @ y

    def fun(y):
        pred, _ = problem.evaluate(full(y), jacobian=False)
        return (pred - problem.g).ravel()

    def jac(y):
        return problem.evaluate(full(y))[1] @ basis

    y = np.zeros(basis.shape[1])
    res = None
    nfev = 0
    if y.size:
        res = opt.least_squares(
            fun,
            y,
            jac=jac,
            method="trf",
            x_scale="jac",
            xtol=1e-12,
            ftol=1e-12,
            gtol=1e-12,
            max_nfev=200,
        )
        y, nfev = res.x, res.nfev
    f_scale = None
    if robust is not None and y.size:
        r = fun(y)
        f_scale = 1.4826 * float(np.median(np.abs(r - np.median(r))))
        if f_scale > 0:
            loss = "huber" if robust == "huber" else "cauchy"
            res = opt.least_squares(
                fun,
                y,
                jac=jac,
                method="trf",
                x_scale="jac",
                loss=loss,
                f_scale=_ROBUST_C[robust] * f_scale,
                xtol=1e-12,
                ftol=1e-12,
                gtol=1e-12,
                max_nfev=200,
            )
            y, nfev = res.x, nfev + res.nfev
            f_scale *= _ROBUST_C[robust]
        else:
            f_scale = None
    converged = bool(res is None or res.status > 0)
    return {
        "x": full(y),
        "dead": dead,
        "nfev": nfev,
        "converged": converged,
        "loss": robust if f_scale else None,
        "f_scale": f_scale,
    }


def _weights(r: np.ndarray, loss, f_scale) -> np.ndarray:
    """IRLS weights ρ'(z), z = (r/f)², of scipy's losses (1 for the plain loss)."""
    if loss is None:
        return np.ones_like(r)
    z = (r / f_scale) ** 2
    if loss == "huber":
        return np.where(z <= 1.0, 1.0, 1.0 / np.sqrt(np.maximum(z, 1.0)))
    return 1.0 / (1.0 + z)


def _result(problem, rot, x, fitted, free, estimate) -> Calibration:
    """The record at the solution: the Jacobian taken again at θ = 0 about the final rotation,
    so that the rotation's covariance is that of its right perturbation."""
    problem.r0 = rot
    pred, jac = problem.evaluate(x)
    resid = problem.g - pred
    r = resid.ravel()
    dead = fitted["dead"]
    cols = np.array([i for i in range(13) if free[i] and i not in dead], dtype=int)
    w = _weights(r, fitted["loss"], fitted["f_scale"])
    jw = jac[:, cols] * np.sqrt(w)[:, None]
    dof = max(r.size - cols.size, 1)
    sigma2 = float(np.sum(w * r**2)) / dof
    cov = np.zeros((13, 13))
    if cols.size:
        cov[np.ix_(cols, cols)] = sigma2 * np.linalg.pinv(jw.T @ jw)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    for i in dead:
        se[i] = np.inf
        cov[i, :] = cov[:, i] = np.nan
        cov[i, i] = np.inf
    unobservable = tuple(COMPONENTS[i] for i in dead)
    if unobservable:
        warnings.warn(
            "calibrate: the motion does not excite " + ", ".join(unobservable) + "; held at "
            "the starting values (standard errors inf)",
            RuntimeWarning,
            stacklevel=3,
        )
    weak_set = {
        i for name, limit in WEAK_STD.items() for i in range(13)[_SLICES[name]] if se[i] > limit
    }
    # A sensor axis whose measured rate varies less than √10 times what the model leaves
    # unexplained there carries no usable signal: the standard errors assume an exact
    # reference, and a noisy one drags the scale of such an axis towards 0 (errors in
    # variables), so its scale, the misalignment terms it multiplies and the rotation about
    # an axis with both other axes silent are weak whatever their standard errors say.
    # (residuals weighted as the loss weighs them: a robust loss discounts glitches here too)
    unexplained = np.mean((w * r**2).reshape(-1, 3), axis=0)
    snr = np.var(problem.g, axis=0) / np.maximum(unexplained, 1e-300)
    silent = snr < _SILENT
    for j in np.flatnonzero(silent):
        weak_set.add(6 + int(j))
    weak_set |= {9 + k for k, j in enumerate((1, 2, 2)) if silent[j]}
    weak_set |= {k for k in range(3) if all(silent[j] for j in range(3) if j != k)}
    weak = tuple(COMPONENTS[i] for i in sorted(weak_set) if i in cols)
    if weak:
        warnings.warn(
            "calibrate: the motion excites " + ", ".join(weak) + " weakly (standard errors "
            "above 1° for rotation, 1 % for scale and misalignment, 1 ms for the time offset, "
            "or a sensor axis whose rate hardly varies beyond the residual; see "
            "standard_errors and rms)",
            RuntimeWarning,
            stacklevel=3,
        )
    q = from_matrix(rot)
    q = q if q[0] >= 0 else -q
    return Calibration(
        rotation=q,
        gyro_bias=x[3:6].copy(),
        scale=x[6:9].copy(),
        misalignment=x[9:12].copy(),
        time_offset=float(x[12]),
        standard_errors={
            "rotation": se[0:3],
            "gyro_bias": se[3:6],
            "scale": se[6:9],
            "misalignment": se[9:12],
            "time_offset": float(se[12]),
        },
        covariance=cov,
        times=problem.t.copy(),
        measured=problem.g.copy(),
        predicted=pred,
        residuals=resid,
        rms=np.sqrt(np.mean(resid**2, axis=0)),
        sigma=math.sqrt(sigma2),
        estimated=tuple(e for e in ESTIMATES if e in estimate),
        unobservable=unobservable,
        weak=weak,
        converged=fitted["converged"],
        nfev=fitted["nfev"],
        extra={"loss": fitted["loss"], "f_scale": fitted["f_scale"]},
    )
