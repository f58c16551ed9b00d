"""Locally adaptive smoothing (``fit(smoothing="auto" | "gcv" | "adaptive")``): it reduces to
the global λ on uniformly rough motion, beats it on motion whose smoothness varies along time,
and "gcv" keeps the global fit."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs


def angle(a, b):
    r = qs.multiply(qs.conjugate(qs.normalize(a)), qs.normalize(b))
    return 2 * np.arctan2(np.linalg.norm(r[..., 1:], axis=-1), np.abs(r[..., 0]))


def rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def noisy(q, deg, seed):
    rng = np.random.default_rng(seed)
    return qs.multiply(q, qs.from_rotvec(rng.normal(size=(len(q), 3)) * np.deg2rad(deg) / 3**0.5))


T = np.arange(0.0, 12.0, 0.01)


def uniform_motion(t):
    """A helix in rotation-vector space: |r''| is constant along the recording."""
    w = 2 * np.pi * 0.5
    return qs.from_rotvec(np.stack([0.5 * np.cos(w * t), 0.5 * np.sin(w * t), 0.2 * t], 1))


def slow_then_fast(t):
    """0.15 Hz for the first half, 1.5 Hz for the second, joined smoothly."""
    s = 1 / (1 + np.exp(-(t - t[-1] / 2) / 0.3))
    ph = 2 * np.pi * (0.15 * t + 1.35 * np.cumsum(s) * (t[1] - t[0]))
    return qs.from_rotvec(0.6 * np.stack([np.sin(ph), 0.6 * np.cos(0.8 * ph), 0.3 * t / t[-1]], 1))


@pytest.mark.parametrize("penalty", ["acceleration", "jerk"])
def test_adaptive_weights_are_nearly_constant_and_the_fit_global_on_uniform_motion(penalty):
    truth = uniform_motion(T)
    q = noisy(truth, 1.0, seed=3)
    g = qs.fit(T, q, smoothing="gcv", penalty=penalty)
    a = qs.fit(T, q, smoothing="adaptive", penalty=penalty)
    assert g.penalty_weights is None
    w = a.penalty_weights
    assert w is not None and len(w) == len(a.knots) - 1
    assert np.isclose(np.exp(np.mean(np.log(w))), 1.0)
    # nearly constant: within a factor 1.5 of each other (varying motion: a factor > 20, below)
    assert w.max() / w.min() < 1.5, w.max() / w.min()
    # and the fit nearly the global one: the two curves differ by < 10 % of their error
    err = rms(angle(g(T), truth))
    assert rms(angle(a(T), g(T))) < 0.1 * err
    assert abs(rms(angle(a(T), truth)) / err - 1) < 0.03


@pytest.mark.parametrize("seed", range(5))
def test_adaptive_beats_global_on_motion_slow_then_fast(seed):
    truth = slow_then_fast(T)
    q = noisy(truth, 1.0, seed)
    g = qs.fit(T, q, smoothing="gcv")
    a = qs.fit(T, q)  # "auto"
    assert a.penalty_weights is not None, "auto kept the global λ"
    w = a.penalty_weights
    # stiffer where the motion is slow (first half) than where it is fast
    mid = len(w) // 2
    assert np.median(w[: mid // 2]) > 20 * np.median(w[-mid // 2 :])
    eg, ea = rms(angle(g(T), truth)), rms(angle(a(T), truth))
    omega = lambda f: rms(  # noqa: E731
        np.linalg.norm(
            f.angular_velocity(T) - qs.NaturalSpline(truth, T).angular_velocity(T), axis=1
        )
    )
    assert ea < 0.95 * eg, (ea, eg)
    assert omega(a) < 0.9 * omega(g)


def test_gcv_is_the_global_fit_and_auto_is_at_least_as_good_by_gcv():
    truth = uniform_motion(T[:600])
    q = noisy(truth, 0.5, seed=1)
    g = qs.fit(T[:600], q, smoothing="gcv")
    a = qs.fit(T[:600], q)
    assert g.penalty_weights is None
    if a.penalty_weights is None:
        assert a.smoothing == g.smoothing and np.array_equal(a.control_quats, g.control_quats)
    else:
        assert a.score < g.score


def test_smoothing_spellings():
    q = noisy(uniform_motion(T[:200]), 0.5, seed=0)
    for s in (" GCV ", "Adaptive", "auto"):
        qs.fit(T[:200], q, smoothing=s)
    with pytest.raises(ValueError, match="'auto', 'gcv', 'adaptive'"):
        qs.fit(T[:200], q, smoothing="adaptve")
    with pytest.raises(ValueError, match="penalty: 'auto'"):
        qs.fit(T[:200], q, smoothing=1e-3, penalty="auto")
    f = qs.fit(T[:200], q, smoothing="gcv", penalty="auto")
    assert f.penalty in ("acceleration", "jerk")
