"""The oracle of ``benchmarks/fit.py`` (least squares in the truth's own spline space) against
an independent dense least-squares solve: the cumulative cubic B-spline on SO(3) evaluated
here with scipy's B-spline basis and scipy's rotations, its control rotations fitted by
``scipy.optimize.least_squares`` to the same samples."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs

scipy = pytest.importorskip("scipy")
from scipy.interpolate import BSpline  # noqa: E402
from scipy.optimize import least_squares  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "fit.py"


def load_benchmark():
    spec = importlib.util.spec_from_file_location("fit_benchmark", BENCH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def rot(q):
    """quatspline's (w, x, y, z) → scipy Rotation."""
    q = np.atleast_2d(q)
    return Rotation.from_quat(q[:, [1, 2, 3, 0]])


def full_knots(joints, k):
    """Joints extended by k − 1 knots at each end with the end intervals' widths."""
    h0, h1 = joints[1] - joints[0], joints[-1] - joints[-2]
    lo = joints[0] - h0 * np.arange(k - 1, 0, -1)
    hi = joints[-1] + h1 * np.arange(1, k)
    return np.r_[lo, joints, hi]


def cumulative(ctrl: Rotation, u, k, t):
    """q(t) = R₀ ∏ⱼ Exp(B̃ⱼ(t) Log(Rⱼ₋₁⁻¹ Rⱼ)), B̃ⱼ = Σ_{r ≥ j} B_{r,k} (Kim, Kim & Shin 1995)."""
    b = BSpline.design_matrix(t, u, k - 1).toarray()
    bt = np.cumsum(b[:, ::-1], axis=1)[:, ::-1]
    out = Rotation.from_quat(np.tile(ctrl[0].as_quat(), (len(t), 1)))
    for j in range(1, len(ctrl)):
        d = (ctrl[j - 1].inv() * ctrl[j]).as_rotvec()
        out = out * Rotation.from_rotvec(bt[:, j, None] * d[None, :])
    return out


def problem(seed, n=81, every=10):
    rng = np.random.default_rng(seed)
    t = np.cumsum(0.01 + 0.01 * rng.random(n))
    t -= t[0]
    rv = np.stack([0.8 * np.sin(3 * t), 0.5 * np.cos(5 * t), 0.7 * t], 1)
    keys_q = qs.from_rotvec(rv[::every])
    truth = qs.NaturalSpline(keys_q, t[::every])
    y = qs.multiply(truth(t), qs.from_rotvec(rng.normal(size=(n, 3)) * np.deg2rad(1.0)))
    return t, y, t[::every]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_oracle_is_the_least_squares_fit_in_the_truths_spline_space(seed):
    bench = load_benchmark()
    t, y, keys = problem(seed)
    f = bench.oracle(t, y, keys)
    np.testing.assert_allclose(f.knots, keys, rtol=0, atol=1e-12)
    k = f.order
    u = full_knots(keys, k)
    ctrl0 = rot(f.control_quats)
    # the evaluator here reproduces the fitted spline (same space, same parametrisation)
    grid = np.linspace(t[0], t[-1], 500)
    here = cumulative(ctrl0, u, k, grid)
    assert np.max((here.inv() * rot(f(grid))).magnitude()) < 1e-10
    # dense least squares over the control rotations, from a start 0.1 rad off the oracle's
    yr = rot(y)
    rng = np.random.default_rng(100 + seed)
    start = ctrl0 * Rotation.from_rotvec(0.1 * rng.normal(size=(len(ctrl0), 3)))

    def residuals(x):
        c = start * Rotation.from_rotvec(x.reshape(-1, 3))
        return (cumulative(c, u, k, t).inv() * yr).as_rotvec().ravel()

    sol = least_squares(residuals, np.zeros(3 * len(ctrl0)), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    dense = start * Rotation.from_rotvec(sol.x.reshape(-1, 3))
    gap = (cumulative(dense, u, k, grid).inv() * rot(f(grid))).magnitude()
    assert np.max(gap) < 1e-7, np.max(gap)
    # and it is not the trivial answer: the samples are 1° off the curve
    assert np.sqrt(np.mean(f.residuals**2)) > np.deg2rad(0.5)
