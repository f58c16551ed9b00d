"""Rotation means: chordal vs scipy and brute force, Karcher mean vs brute force, windows."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

from ..conftest import random_quats


def _cluster(n, spread, seed):
    rng = np.random.default_rng(seed)
    centre = qs.from_rotvec(rng.normal(size=3))
    d = qs.from_rotvec(spread * rng.normal(size=(n, 3)))
    q = qs.multiply(centre, d)
    return q * np.where(rng.random(n) < 0.5, -1.0, 1.0)[:, None]  # random signs


def _same_rotation(a, b, tol):
    assert min(np.abs(a - b).max(), np.abs(a + b).max()) < tol


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("weighted", [False, True])
def test_chordal_equals_scipy(seed, weighted):
    q = _cluster(40, 0.8, seed)
    w = np.random.default_rng(seed).random(40) if weighted else None
    ours = qs.mean(q, weights=w)
    ref = qs.from_xyzw(Rotation.from_quat(qs.as_xyzw(q)).mean(weights=w).as_quat())
    _same_rotation(ours, ref, 1e-12)


def test_chordal_equals_scipy_for_scattered_rotations():
    q = random_quats(200, seed=3)
    ref = qs.from_xyzw(Rotation.from_quat(qs.as_xyzw(q)).mean().as_quat())
    _same_rotation(qs.mean(q), ref, 1e-10)


def _brute(q, w, cost):
    start = qs.as_rotvec(qs.mean(q, weights=w))
    best = min(
        (
            minimize(
                lambda r: cost(qs.from_rotvec(r)),
                x0,
                method="Nelder-Mead",
                options=dict(xatol=1e-12, fatol=1e-16, maxiter=20000, maxfev=40000),
            )
            for x0 in (start, start + 0.05)
        ),
        key=lambda r: r.fun,
    )
    return qs.from_rotvec(best.x), best.fun


@pytest.mark.parametrize("seed", range(3))
def test_chordal_and_geodesic_against_brute_force(seed):
    q = _cluster(12, 0.6, seed)
    w = np.random.default_rng(seed + 10).random(12)
    wn = w / w.sum()
    mats = qs.as_matrix(q)

    def chordal_cost(m):
        return float(np.sum(wn * np.sum((qs.as_matrix(m) - mats) ** 2, axis=(1, 2))))

    def geodesic_cost(m):
        rel = qs.multiply(qs.conjugate(m)[None, :], q)
        return float(np.sum(wn * np.linalg.norm(qs.as_rotvec(rel), axis=1) ** 2))

    mc, info_c = qs.mean(q, weights=w, return_info=True)
    bc, fc = _brute(q, w, chordal_cost)
    assert info_c.cost == pytest.approx(chordal_cost(mc), rel=1e-12)
    assert chordal_cost(mc) <= fc + 1e-13
    _same_rotation(mc, bc, 1e-5)

    mg, info = qs.mean(q, weights=w, method="geodesic", return_info=True)
    bg, fg = _brute(q, w, geodesic_cost)
    assert info.converged and info.iterations < 100 and info.step < 1e-14
    assert info.cost == pytest.approx(geodesic_cost(mg), rel=1e-12)
    assert geodesic_cost(mg) <= fg + 1e-13
    _same_rotation(mg, bg, 1e-5)
    # the two means differ for a spread cluster: the test can tell them apart
    assert np.linalg.norm(qs.as_rotvec(qs.multiply(qs.conjugate(mc), mg))) > 1e-6


def test_geodesic_mean_of_two_is_the_slerp_midpoint():
    a, b = qs.from_rotvec([[0.0, 0.0, 0.0], [0.0, 2.5, 0.0]])
    m = qs.mean([a, -b], method="geodesic", weights=[1.0, 3.0])
    _same_rotation(m, qs.slerp(a, b, 0.75), 1e-14)


def test_non_convergence_is_reported():
    q = _cluster(10, 1.0, 1)
    _, info = qs.mean(q, method="geodesic", max_iterations=1, return_info=True)
    assert info.iterations == 1 and not info.converged and info.step > 1e-14


def test_single_rotation_and_zero_weights_elsewhere():
    q = _cluster(5, 0.5, 2)
    m = qs.mean(q, weights=[0, 0, 1, 0, 0], method="geodesic")
    _same_rotation(m, q[2] / np.linalg.norm(q[2]), 1e-15)


@pytest.mark.parametrize("method", ["chordal", "geodesic"])
def test_moving_mean_matches_mean_of_each_window(method):
    q = _cluster(30, 0.4, 4)
    out = qs.moving_mean(q, 5, method=method)
    for i in range(30):
        lo, hi = max(0, i - 2), min(30, i + 3)
        _same_rotation(out[i], qs.mean(q[lo:hi], method=method), 1e-12)


@pytest.mark.parametrize(
    ("kwargs", "err", "msg"),
    [
        (dict(quats=np.zeros((0, 4))), ValueError, "quats: expected at least one"),
        (dict(quats=np.ones((3, 3))), ValueError, "quats"),
        (dict(quats=[[1, 0, 0, np.nan]]), ValueError, "quats: non-finite"),
        (dict(quats=[[0, 0, 0, 0]]), ValueError, "quats: quaternion 0 is zero"),
        (dict(weights=[0.0, 0.0]), ValueError, "weights: all weights are zero"),
        (dict(weights=[]), ValueError, "weights: expected shape"),
        (dict(weights=[1.0]), ValueError, "weights: expected shape"),
        (dict(weights=[1.0, -1.0]), ValueError, "weights: negative"),
        (dict(weights=[1.0, np.inf]), ValueError, "weights: non-finite"),
        (dict(weights="ab"), TypeError, "weights"),
        (dict(method="median"), ValueError, "method"),
        (dict(method=3), TypeError, "method"),
        (dict(tol=0.0), ValueError, "tol"),
        (dict(max_iterations=0), ValueError, "max_iterations"),
        (dict(max_iterations=2.5), TypeError, "max_iterations"),
    ],
)
def test_bad_input(kwargs, err, msg):
    args = dict(quats=[[1.0, 0, 0, 0], [0.0, 1, 0, 0]])
    args.update(kwargs)
    q = args.pop("quats")
    with pytest.raises(err, match=msg):
        qs.mean(q, **args)


@pytest.mark.parametrize(
    ("window", "err"), [(0, ValueError), (4, ValueError), (99, ValueError), (2.0, TypeError)]
)
def test_moving_mean_bad_window(window, err):
    with pytest.raises(err, match="window"):
        qs.moving_mean(random_quats(10), window)


@pytest.mark.parametrize("method", ["chordal", "geodesic"])
@pytest.mark.parametrize("seed", range(4))
def test_means_are_bi_invariant(method, seed):
    q = _cluster(15, 0.7, seed)
    g, h = random_quats(2, seed=seed + 50)
    m = qs.mean(q, method=method)
    _same_rotation(qs.mean(qs.multiply(g, q), method=method), qs.multiply(g, m), 1e-12)
    _same_rotation(qs.mean(qs.multiply(q, h), method=method), qs.multiply(m, h), 1e-12)


def test_hard_cases_against_scipy():
    from ..conftest import HARD_CASES

    q = np.array(list(HARD_CASES.values()))
    ref = qs.from_xyzw(
        Rotation.from_quat(qs.as_xyzw(q / np.linalg.norm(q, axis=1)[:, None])).mean().as_quat()
    )
    _same_rotation(qs.mean(q), ref, 1e-12)
    # a tight cluster around π: the Karcher mean stays there (no wrap-around)
    near_pi = qs.multiply(qs.from_rotvec([np.pi - 1e-9, 0, 0]), qs.from_rotvec(1e-3 * np.eye(3)))
    m, info = qs.mean(near_pi, method="geodesic", return_info=True)
    assert info.converged and abs(np.linalg.norm(qs.as_rotvec(m)) - np.pi) < 2e-3
