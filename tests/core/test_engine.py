"""The evaluation engine: equal to the straightforward scalar path, independent of the thread
count, writing into caller buffers; no panic reaches Python."""

from __future__ import annotations

import threading

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import random_times, random_walk
from .test_simd import MODES, force, worst

Q = random_walk(40, 1)
T = random_times(40, 1)
SPLINES = {
    "slerp": qs.PiecewiseSlerp(Q, T),
    "nlerp": qs.PiecewiseNlerp(Q, T),
    "lin_euler": qs.PiecewiseLinEuler(Q, T),
    "lin_mat": qs.PiecewiseLinMat(Q, T),
    "squad": qs.Squad(Q, T),
    "catmull_rom": qs.CatmullRom(Q, T),
    "natural": qs.NaturalSpline(Q, T),
    "bspline": qs.CumulativeBSpline(Q, dt=0.5, t0=T[0]),
    "beta": qs.BetaSpline(Q, beta1=1.3, beta2=0.4, times=T[:38]),
    "c3": qs.C3Spline(Q, T),
    "bezier": qs.SphericalBezier(Q[:6], domain=(T[0], T[-1])),
    "cumulative_bezier": qs.CumulativeBezier(Q[:6], domain=(T[0], T[-1])),
}


def sample_sets(s):
    a, b = s.domain
    rng = np.random.default_rng(0)
    sorted_t = np.linspace(a, b, 20_001)  # > 2 chunks: the parallel path
    return {
        "sorted": sorted_t,
        "unsorted": rng.permutation(sorted_t),
        "single": np.array([0.5 * (a + b)]),
        "empty": np.zeros(0),
        "joints_and_ends": np.concatenate([s.joints, s.joints[::-1]]),
    }


@pytest.fixture(autouse=True)
def _restore_mode():
    yield
    qs.set_simd("auto")


@pytest.mark.parametrize("name", list(SPLINES))
@pytest.mark.parametrize("mode", MODES)
def test_engine_equals_scalar_path(name, mode):
    force(mode)
    s = SPLINES[name]
    for kind, t in sample_sets(s).items():
        for order in (0, 1, 2, 3):
            fast = s._core.evaluate(np.ascontiguousarray(t), order, "raise")
            ref = s._core.evaluate_scalar(np.ascontiguousarray(t), order)[:, : 4 * (order + 1)]
            assert fast.shape == ref.shape
            # the documented bound of the batch kernels (tests/core/test_simd.py)
            assert worst(s, t, fast, ref, 4, 0) <= 1.0, (kind, order)


@pytest.mark.parametrize("mode", MODES)
def test_thread_count_independence(mode):
    force(mode)
    s = SPLINES["c3"]
    t = np.random.default_rng(1).uniform(*s.domain, 100_000)
    results = []
    try:
        for n in (1, 2, 8):
            qs.set_num_threads(n)
            assert qs.get_num_threads() == n
            results.append((s(t), s.jerk(t), qs.slerp(Q[0], Q[1], t / t.max())))
    finally:
        qs.set_num_threads(0)
    for r in results[1:]:
        for a, b in zip(results[0], r):
            np.testing.assert_array_equal(a, b)


def test_eight_python_threads_give_identical_bits():
    s = SPLINES["natural"]
    t = np.random.default_rng(2).uniform(*s.domain, 50_000)
    ref = s.angular_velocity(t)
    out = [None] * 8

    def work(k):
        out[k] = s.angular_velocity(t)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for r in out:
        np.testing.assert_array_equal(r, ref)


def test_out_parameter():
    s = SPLINES["squad"]
    t = np.linspace(*s.domain, 1000)
    buf = np.empty((1000, 4))
    res = s(t, out=buf)
    assert res is buf
    np.testing.assert_array_equal(buf, s(t))
    with pytest.raises(ValueError, match=r"out: expected shape \(1000, 4\), got \(999, 4\)"):
        s(t, out=np.empty((999, 4)))
    with pytest.raises(ValueError, match=r"out: expected a float64 numpy array, got float32"):
        s(t, out=np.empty((1000, 4), dtype=np.float32))
    with pytest.raises(ValueError, match="C-contiguous"):
        s(t, out=np.empty((4, 1000)).T)
    ro = np.empty((1000, 4))
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="writeable"):
        s(t, out=ro)


def test_no_panic_reaches_python():
    with pytest.raises(
        RuntimeError, match=r"internal error in _panic_for_test .*deliberate test panic"
    ):
        qs._core._panic_for_test()
    # the library still works afterwards
    assert qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], 0.5).shape == (4,)
