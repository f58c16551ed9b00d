"""Quaternion algebra: hard-case corpus against mpmath, properties with hypothesis."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from .. import mpref
from ..conftest import HARD_CASES

TOL = 1e-15  # absolute, per component (issue 1/6)


def mp_close(got, ref_mp, tol=TOL):
    ref = np.array(mpref.to_float(ref_mp))
    assert np.max(np.abs(got - ref)) <= tol, (got, ref)


def test_log_exp_power_against_mpmath(hard_quat):
    q = hard_quat
    m = mpref.mq(q)
    mp_close(qs.log(q), mpref.log(m))
    mp_close(qs.exp(qs.log(q)), m, tol=4e-15 * np.linalg.norm(q))
    unit = mpref.normalize(m)
    for t in (0.3, -1.7, 2.0):
        mp_close(qs.power(q, t), mpref.power(unit, t))


@pytest.mark.parametrize("other", list(HARD_CASES))
def test_slerp_against_mpmath(hard_quat, other):
    p, q = hard_quat, HARD_CASES[other]
    for t in (0.0, 1e-9, 0.25, 0.5, 0.9, 1.0):
        mp_close(qs.slerp(p, q, t), mpref.slerp(mpref.mq(p), mpref.mq(q), t))


def test_multiply_matches_mpmath(hard_quat):
    p = HARD_CASES["generic"]
    mp_close(qs.multiply(p, hard_quat), mpref.mul(mpref.mq(p), mpref.mq(hard_quat)), tol=4e-16 * 4)


def test_rotate_is_sandwich():
    q = qs.normalize([0.3, -0.2, 0.9, 0.1])
    v = np.array([0.5, -1.0, 2.0])
    ref = qs.multiply(qs.multiply(q, np.r_[0.0, v]), qs.conjugate(q))[1:]
    np.testing.assert_allclose(qs.rotate(q, v), ref, atol=1e-15)


def test_inverse_of_unnormalised():
    q = np.array([1.0, 2.0, -2.0, 4.0])
    np.testing.assert_allclose(qs.multiply(q, qs.inverse(q)), [1, 0, 0, 0], atol=1e-16)


def test_canonicalize():
    q = np.array([[-0.5, 0.5, 0.5, 0.5], [0.5, 0.5, 0.5, 0.5]])
    assert np.all(qs.canonicalize(q)[:, 0] > 0)
    flipped = qs.canonicalize(q, reference=[[0.5, 0.5, 0.5, 0.5]] * 2)
    assert np.all(np.sum(flipped * 0.5, axis=1) >= 0)


# ---- properties -------------------------------------------------------------------------

finite = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
quat = arrays(np.float64, 4, elements=finite).filter(lambda q: np.linalg.norm(q) > 1e-3)
param = st.floats(0.0, 1.0)


def unit(q):
    return q / np.linalg.norm(q)


def same_rotation(a, b, tol=1e-13):
    return min(np.max(np.abs(a - b)), np.max(np.abs(a + b))) <= tol


@settings(max_examples=200, deadline=None)
@given(quat, quat, param)
def test_slerp_properties(p, q, t):
    p, q = unit(p), unit(q)
    s = qs.slerp(p, q, t)
    assert abs(np.linalg.norm(s) - 1) < 1e-15
    np.testing.assert_array_equal(qs.slerp(p, q, 0.0), p)
    assert same_rotation(qs.slerp(p, q, 1.0), q, 0.0)
    # q/−q invariance: the same rotations give the same curve (away from p·q = 0, where
    # rounding decides between two equally short paths)
    if abs(np.dot(p, q)) > 1e-9:
        np.testing.assert_allclose(qs.slerp(p, -q, t), s, atol=1e-15)
    # reversal
    assert same_rotation(qs.slerp(q, p, 1 - t), s, 1e-14)


@settings(max_examples=200, deadline=None)
@given(quat, quat, quat, param)
def test_slerp_left_and_right_invariance(p, q, g, t):
    p, q, g = unit(p), unit(q), unit(g)
    # At p·q = 0 (rotations 180° apart) rounding picks the path; both are valid.
    assume(abs(np.dot(p, q)) > 1e-9)
    s = qs.slerp(p, q, t)
    assert same_rotation(qs.multiply(g, s), qs.slerp(qs.multiply(g, p), qs.multiply(g, q), t))
    assert same_rotation(qs.multiply(s, g), qs.slerp(qs.multiply(p, g), qs.multiply(q, g), t))


@settings(max_examples=300, deadline=None)
@given(quat)
def test_exp_log_round_trip(q):
    np.testing.assert_allclose(qs.exp(qs.log(q)), q, atol=4e-16 * 4)


@settings(max_examples=200, deadline=None)
@given(quat, quat, param)
def test_nlerp_is_unit_and_between(p, q, t):
    p, q = unit(p), unit(q)
    n = qs.nlerp(p, q, t)
    assert abs(np.linalg.norm(n) - 1) < 1e-15
    np.testing.assert_allclose(qs.lerp(p, q, t), (1 - t) * p + t * q, atol=1e-16)


def test_broadcasting_shapes():
    keys = qs.normalize(np.random.default_rng(0).normal(size=(5, 1, 4)))
    t = np.linspace(0, 1, 7)
    out = qs.slerp(keys, keys[::-1], t)
    assert out.shape == (5, 7, 4)
    assert qs.slerp([1, 0, 0, 0], [0, 1, 0, 0], 0.5).shape == (4,)
    np.testing.assert_allclose(out[2, 3], qs.slerp(keys[2, 0], keys[2, 0][None][0], t[3]))


def test_slerp_nearly_equal_and_antipodal():
    p = HARD_CASES["generic"]
    q = qs.multiply(p, HARD_CASES["1e-12 rad"])
    s = qs.slerp(p, q, np.linspace(0, 1, 11))
    assert np.all(np.isfinite(s))
    # exactly antipodal keys are the same rotation: the shortest path stays put
    np.testing.assert_allclose(qs.slerp(p, -p, 0.37), p, atol=1e-16)
    lp = qs.slerp(p, -p, 0.5, long_path=True)
    assert np.all(np.isfinite(lp)) and abs(np.linalg.norm(lp) - 1) < 1e-15
    # the long path from p to -p is a full turn: half way is a half-turn away from p
    assert abs(abs(np.dot(lp, p))) < 1e-15


def test_lin_mat_and_lin_euler_hit_their_keys():
    p = qs.from_euler("xyz", [0.1, 0.4, -0.3])
    q = qs.from_euler("xyz", [1.0, -0.2, 0.5])
    for f in (qs.lin_mat, qs.lin_euler):
        assert same_rotation(f(p, q, 0.0), p, 1e-14)
        assert same_rotation(f(p, q, 1.0), q, 1e-14)
    # the baselines are not slerp: they leave the geodesic in between
    mid = qs.slerp(p, q, 0.5)
    assert not same_rotation(qs.lin_euler(p, q, 0.5), mid, 1e-6)
