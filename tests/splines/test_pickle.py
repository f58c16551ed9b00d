"""Splines pickle: they travel to Dask workers and multiprocessing pools, and come back as the
same curve bit for bit (values and every derivative), with their extrapolation rule."""

from __future__ import annotations

import multiprocessing
import pickle

import numpy as np
import pytest
import quatspline as qs
from quatspline import registry

RNG = np.random.default_rng(20261202)
TIMES = np.cumsum(RNG.uniform(0.2, 1.0, 9))
LOOP = np.append(TIMES, TIMES[-1] + 0.7)  # closed curves: one more time closes the loop
KEYS = qs.from_rotvec(RNG.normal(scale=1.2, size=(9, 3)))
POINTS = RNG.normal(size=(9, 3))


def _probe(s, t):
    return [s(t), s.angular_velocity(t), s.angular_acceleration(t, frame="body"), s.jerk(t)]


def _same(a, b):
    return all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


def _grid(s, n=257):
    a, b = s.domain
    return np.concatenate([np.linspace(a, b, n), np.random.default_rng(n).uniform(a, b, n)])


@pytest.mark.parametrize("method", list(registry.METHODS))
def test_every_registry_method_pickles_to_the_same_curve(method):
    s = qs.spline(method, KEYS, TIMES)
    t = _grid(s)
    back = pickle.loads(pickle.dumps(s))
    assert type(back) is type(s)
    assert back.domain == s.domain
    assert _same(_probe(back, t), _probe(s, t))


@pytest.mark.parametrize(
    "make",
    [
        lambda: qs.C3Spline(KEYS, LOOP, ends="closed", alpha=0.2, beta=0.1),
        lambda: qs.NaturalSpline(KEYS, LOOP, ends="closed"),
        lambda: qs.KochanekBartels(KEYS, TIMES, tension=0.3, continuity=-0.2, bias=0.1),
        lambda: qs.CumulativeBSpline(KEYS, dt=0.5, t0=1.0, order=5),
        lambda: qs.fit(TIMES, KEYS, smoothing=1e-3),
        lambda: qs.reparameterize(qs.C3Spline(KEYS, TIMES), "angle"),
    ],
    ids=["c3-closed", "natural-closed", "kb-tcb", "bspline-order5", "fit", "arc-length"],
)
def test_splines_with_their_options_pickle_to_the_same_curve(make):
    s = make()
    t = _grid(s)
    back = pickle.loads(pickle.dumps(s, protocol=pickle.HIGHEST_PROTOCOL))
    assert _same(_probe(back, t), _probe(s, t))


def test_pose_splines_pickle_to_the_same_motion():
    for s in (
        qs.PoseSpline(KEYS, TIMES, POINTS),
        qs.ScrewSpline(KEYS, TIMES, POINTS),
        qs.fit(TIMES, KEYS, positions=POINTS, smoothing=1e-3),
    ):
        back = pickle.loads(pickle.dumps(s))
        t = np.linspace(*s.domain, 101)
        assert np.array_equal(back.orientation(t), s.orientation(t))
        assert np.array_equal(back.position(t), s.position(t))


def test_a_changed_extrapolation_rule_travels_with_the_pickle():
    s = qs.C3Spline(KEYS, TIMES)
    s.extrapolate = "clamp"
    back = pickle.loads(pickle.dumps(s))
    assert back.extrapolate == "clamp"
    assert np.array_equal(back(TIMES[-1] + 5.0), s(TIMES[-1] + 5.0))


def test_mutating_the_callers_keys_after_construction_does_not_change_the_pickle():
    keys, times = KEYS.copy(), TIMES.copy()
    s = qs.NaturalSpline(keys, times)
    before = s(_grid(s))
    keys[:] = [1.0, 0.0, 0.0, 0.0]
    times *= 3.0
    back = pickle.loads(pickle.dumps(s))
    assert np.array_equal(back(_grid(s)), before)


def test_a_progress_callback_is_not_part_of_the_pickle():
    s = qs.MinimumEnergySpline(KEYS[:5], TIMES[:5], progress=lambda *a: None)
    back = pickle.loads(pickle.dumps(s))
    assert np.array_equal(back(_grid(s)), s(_grid(s)))


def _evaluate(s):
    return s(np.linspace(*s.domain, 64))


def test_splines_travel_to_a_spawned_process_pool():
    s = qs.C3Spline(KEYS, TIMES)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        (there,) = pool.map(_evaluate, [s])
    assert np.array_equal(there, _evaluate(s))
