"""The posterior covariance of a fit: ``covariance``/``std`` of the orientation, of the angular
velocity and of positions. In Rust (``crates/quatspline/src/fit/covariance.rs``, ``position.rs``):
the Jacobians against finite differences, the band of H⁻¹ against dense inverses, and the
sample covariance of 200 fits at a fixed λ against the frequentist sandwich σ²H⁻¹GH⁻¹. Here:
coverage of the nominal 95 % intervals on synthetic data of known σ (Nychka's across-the-function
coverage: the fraction of (time, axis) pairs, over the sample times and many draws, whose error
lies within ±1.96 std), a Monte-Carlo check of the Bayesian variance against the mean squared
error, shapes, frames and errors."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline import plot


def truth_rotvec(t, ph):
    return np.column_stack(
        [
            0.8 * np.sin(1.1 * t + ph[0]),
            0.5 * np.cos(0.7 * t + ph[1]),
            0.3 * t + 0.2 * np.sin(2.3 * t + ph[2]),
        ]
    )


def truth_positions(t, ph):
    return np.column_stack([np.sin(t + ph[0]), np.cos(0.5 * t + ph[1]), 0.2 * t**2])


def errors(a, b):
    """Log(a⁻¹ b) per row: the rotation vector taking a to b, in a's body frame."""
    return 2 * qs.log(qs.multiply(qs.conjugate(a), b))[:, 1:]


def draw(rng, sigma, penalty, n=300, positions=True):
    t = np.linspace(0.0, 6.0, n)
    ph = rng.uniform(0, 2 * np.pi, 3)
    qt = qs.from_rotvec(truth_rotvec(t, ph))
    y = qs.multiply(qt, qs.from_rotvec(sigma * rng.normal(size=(n, 3))))
    xt = truth_positions(t, ph)
    x = xt + sigma * rng.normal(size=(n, 3)) if positions else None
    return t, qt, xt, qs.fit(t, y, positions=x, penalty=penalty)


@pytest.mark.parametrize("penalty", ["acceleration", "jerk"])
@pytest.mark.parametrize("sigma", [0.002, 0.02, 0.1])
def test_nominal_95_percent_intervals_cover_the_truth_90_to_98_percent(penalty, sigma):
    """Across-the-function coverage (Nychka 1988) at the sample times, averaged over 16
    draws (random phases of a smooth truth, Gaussian noise of known σ per axis, λ by GCV):
    orientation per body axis, positions per coordinate, and σ̂ estimates σ."""
    rng = np.random.default_rng(int(sigma * 1e4) + len(penalty))
    cov_q, cov_x, ratio = [], [], []
    for _ in range(16):
        t, qt, xt, f = draw(rng, sigma, penalty)
        e = errors(f.orientation(t), qt)
        cov_q.append(np.mean(np.abs(e) <= 1.96 * f.std(t)))
        cov_x.append(np.mean(np.abs(f.position(t) - xt) <= 1.96 * f.position_std(t)))
        ratio.append(f.noise_std / sigma)
    assert 0.90 <= np.mean(cov_q) <= 0.98, np.mean(cov_q)
    assert 0.90 <= np.mean(cov_x) <= 0.98, np.mean(cov_x)
    assert 0.9 < np.mean(ratio) < 1.1


def test_bayesian_variance_matches_the_mean_squared_error_in_monte_carlo():
    """200 noise draws of a small problem at a fixed λ near GCV's choice. Averaged over the
    curve, the Bayesian variance σ² J H⁻¹ Jᵀ (σ known; the covariance rescaled from σ̂²)
    matches the mean squared error of the fit (variance plus squared bias) to 20 %; the
    sample covariance about the draws' mean (the variance alone: the sandwich σ²J H⁻¹GH⁻¹Jᵀ,
    compared exactly in Rust) is below it at almost every time."""
    rng = np.random.default_rng(7)
    n, sigma = 60, 0.02
    t = np.linspace(0.0, 3.0, n)
    qt = qs.from_rotvec(truth_rotvec(t, [0.3, 1.0, 2.0]))
    lam = qs.fit(t, qs.multiply(qt, qs.from_rotvec(sigma * rng.normal(size=(n, 3))))).smoothing
    ts = np.linspace(0.0, 3.0, 31)
    qts = qs.from_rotvec(truth_rotvec(ts, [0.3, 1.0, 2.0]))
    e, bayes = [], []
    for _ in range(200):
        y = qs.multiply(qt, qs.from_rotvec(sigma * rng.normal(size=(n, 3))))
        f = qs.fit(t, y, smoothing=lam)
        e.append(errors(f(ts), qts))
        bayes.append(np.trace(f.covariance(ts), axis1=1, axis2=2) * sigma**2 / f.noise_std**2)
    e = np.array(e)  # (draws, times, 3)
    bayes = np.mean(bayes, axis=0)
    mse = np.mean(np.sum(e**2, axis=2), axis=0)
    var = np.sum(np.var(e, axis=0, ddof=1), axis=1)
    assert abs(np.mean(mse) / np.mean(bayes) - 1) < 0.2, (np.mean(mse), np.mean(bayes))
    assert np.mean(var <= 1.1 * bayes) > 0.9


def test_shapes_frames_and_symmetry():
    rng = np.random.default_rng(3)
    t, qt, xt, f = draw(rng, 0.01, "acceleration", n=120)
    assert f.covariance(1.0).shape == (3, 3)
    assert f.covariance([1.0, 2.0]).shape == (2, 3, 3)
    assert f.covariance(np.ones((2, 4))).shape == (2, 4, 3, 3)
    assert f.std(1.0).shape == (3,) and f.std([1.0, 2.0]).shape == (2, 3)
    assert f.angular_velocity_covariance([1.0]).shape == (1, 3, 3)
    assert f.angular_velocity_std(np.ones((2, 2))).shape == (2, 2, 3)
    assert f.position_covariance(1.0).shape == (3, 3)
    assert f.position_std([1.0, 2.0]).shape == (2, 3)
    assert f.position_std([1.0], derivative=1).shape == (1, 3)
    c = f.covariance(t)
    np.testing.assert_array_equal(c, np.swapaxes(c, 1, 2))
    assert np.all(np.linalg.eigvalsh(c) > 0)
    # world = R body Rᵀ (left vs right perturbation); the pose forwards to its rotation
    r = qs.as_matrix(f.orientation(t))
    np.testing.assert_allclose(
        f.covariance(t, frame="world"), r @ c @ np.swapaxes(r, 1, 2), atol=1e-12 * c.max()
    )
    np.testing.assert_array_equal(f.covariance(t), f.rotation.covariance(t))
    np.testing.assert_array_equal(f.std(t), np.sqrt(np.diagonal(c, axis1=1, axis2=2)))
    # positions: isotropic, the std the root of the diagonal
    pc = f.position_covariance(t)
    np.testing.assert_array_equal(pc[:, 0, 1], 0.0)
    np.testing.assert_array_equal(pc[:, 0, 0], pc[:, 2, 2])
    np.testing.assert_allclose(f.position_std(t)[:, 0], np.sqrt(pc[:, 0, 0]))


def test_the_ends_are_less_certain_and_more_noise_gives_wider_bands():
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 4.0, 200)
    qt = qs.from_rotvec(truth_rotvec(t, [0.0, 0.0, 0.0]))
    noise = rng.normal(size=(200, 3))
    f1 = qs.fit(t, qs.multiply(qt, qs.from_rotvec(0.01 * noise)), smoothing=1e-4)
    f2 = qs.fit(t, qs.multiply(qt, qs.from_rotvec(0.04 * noise)), smoothing=1e-4)
    s1, s2 = f1.std(t).mean(axis=1), f2.std(t).mean(axis=1)
    assert s1[0] > 1.5 * s1[100] and s1[-1] > 1.5 * s1[100]
    np.testing.assert_allclose(s2 / s1, 4.0, rtol=0.05)


def test_times_outside_the_domain_follow_extrapolate():
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 2.0, 80)
    y = qs.multiply(
        qs.from_rotvec(truth_rotvec(t, [0, 0, 0])), qs.from_rotvec(0.01 * rng.normal(size=(80, 3)))
    )
    x = truth_positions(t, [0, 0]) + 0.01 * rng.normal(size=(80, 3))
    f = qs.fit(t, y, positions=x)
    for fn in (f.covariance, f.std, f.angular_velocity_std, f.position_covariance, f.position_std):
        with pytest.raises(ValueError, match="outside the domain"):
            fn([1.0, 2.5])
        with pytest.raises(ValueError, match="non-finite"):
            fn([np.nan])
    g = qs.fit(t, y, positions=x, extrapolate="clamp")
    np.testing.assert_array_equal(g.covariance(2.5), g.covariance(2.0))
    np.testing.assert_array_equal(g.covariance(-1.0), g.covariance(0.0))
    np.testing.assert_array_equal(g.angular_velocity_covariance(3.0), np.zeros((3, 3)))
    np.testing.assert_array_equal(g.position_std(3.0), g.position_std(2.0))
    np.testing.assert_array_equal(g.position_std(3.0, derivative=1), np.zeros(3))
    assert np.all(g.angular_velocity_std(2.0) > 0)


def test_bad_arguments_name_what_is_wrong():
    rng = np.random.default_rng(6)
    t = np.linspace(0.0, 2.0, 50)
    y = qs.multiply(
        qs.from_rotvec(truth_rotvec(t, [0, 0, 0])), qs.from_rotvec(0.01 * rng.normal(size=(50, 3)))
    )
    f = qs.fit(t, y, positions=np.zeros((50, 3)) + 0.01 * rng.normal(size=(50, 3)))
    with pytest.raises(ValueError, match="frame"):
        f.covariance(1.0, frame="space")
    with pytest.raises(TypeError, match="frame"):
        f.std(1.0, frame=1)
    with pytest.raises(ValueError, match="derivative"):
        f.position_covariance(1.0, derivative=2)
    with pytest.raises(TypeError, match="derivative"):
        f.position_std(1.0, derivative=0.5)
    with pytest.raises(TypeError, match="t: expected real numbers"):
        f.covariance("soon")
    # an interpolating fit has no residuals to estimate the noise from
    g = qs.fit(t, y, smoothing=0)
    with pytest.raises(ValueError, match="smoothing"):
        g.covariance(1.0)


def test_weights_robust_losses_and_uneven_knots():
    """A zero weight drops a sample from n_obs and the data; a robust fit uses its final
    weights (a far glitch does not inflate σ̂ as in least squares); uneven knots work."""
    rng = np.random.default_rng(8)
    t = np.linspace(0.0, 4.0, 200)
    qt = qs.from_rotvec(truth_rotvec(t, [0.5, 0.5, 0.5]))
    y = qs.multiply(qt, qs.from_rotvec(0.01 * rng.normal(size=(200, 3))))
    y[50] = qs.multiply(y[50], qs.from_rotvec([0.0, 2.0, 0.0]))
    w = np.ones(200)
    w[50] = 0.0
    clean = qs.fit(t, y, weights=w, smoothing=1e-4)
    plain = qs.fit(t, y, smoothing=1e-4)
    huber = qs.fit(t, y, robust="huber", smoothing=1e-4)
    assert 0.9 < clean.noise_std / 0.01 < 1.1
    assert plain.noise_std > 5 * clean.noise_std
    assert huber.noise_std < 3 * clean.noise_std
    knots = np.concatenate([np.linspace(0, 2, 80), np.linspace(2.05, 4, 30)])
    u = qs.fit(t, y, weights=w, knots=knots)
    s = u.std(t)
    assert np.all(np.isfinite(s)) and np.all(s > 0)
    e = errors(u(t), qt)
    assert np.mean(np.abs(e) <= 1.96 * s) > 0.85


def test_rates_plot_shades_two_sigma_about_the_angular_speed():
    pytest.importorskip("matplotlib")
    rng = np.random.default_rng(9)
    t = np.linspace(0.0, 3.0, 150)
    y = qs.multiply(
        qs.from_rotvec(truth_rotvec(t, [0, 0, 0])), qs.from_rotvec(0.02 * rng.normal(size=(150, 3)))
    )
    f = qs.fit(t, y)
    fig = plot.rates(f, show=("omega", "alpha"), band=True, n=50)
    a0, a1 = fig.axes
    assert len(a0.collections) == 1 and len(a1.collections) == 0
    assert any("2σ" in x.get_text() for x in a0.get_legend().get_texts())
    # the band's upper edge is |ω| + 2σ, σ² = ûᵀ Cov(ω) û (checked at the middle time)
    verts = a0.collections[0].get_paths()[0].vertices
    tm = np.linspace(*f.domain, 50)[25]
    top = verts[np.isclose(verts[:, 0], tm)][:, 1].max()
    w = f.angular_velocity(tm)
    u = w / np.linalg.norm(w)
    sd = np.sqrt(u @ f.angular_velocity_covariance(tm) @ u)
    assert abs(top - (np.linalg.norm(w) + 2 * sd)) < 1e-9
    with pytest.raises(TypeError, match="band"):
        plot.rates(qs.C3Spline(y[:5]), band=True)
    with pytest.raises(TypeError, match="band"):
        plot.rates(f, band="yes")
