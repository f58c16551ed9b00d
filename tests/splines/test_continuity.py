"""The continuity certificate reports what is true at every joint, for every method."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import random_times, random_walk

Q = random_walk(7, 31)
T = random_times(7, 31)

CASES = [
    (qs.PiecewiseSlerp(Q, T), 0),
    (qs.Squad(Q, T), 1),
    (qs.CatmullRom(Q, T), 1),
    (qs.NaturalSpline(Q, T), 2),
    (qs.CumulativeBSpline(Q, dt=0.5), 2),
    (qs.C3Spline(Q, T), 3),
]


@pytest.mark.parametrize(("spline", "expected"), CASES, ids=lambda c: getattr(c, "method", c))
def test_certificate_reports_the_order_of_each_method(spline, expected):
    cert = qs.continuity(spline)
    assert len(cert) == len(spline.joints) - 2
    for j, joint in zip(cert, spline.joints[1:-1]):
        assert j.time == joint
        assert j.order == expected, (j.order, j.jump_rel)
        assert j.jump_abs.shape == (4,) and j.jump_rel.shape == (4,)
        assert np.all(j.jump_rel[: expected + 1] <= 1e-9)
        if expected < 3:
            assert j.jump_rel[expected + 1] > 1e-6
        if expected >= 1:  # C¹ implies G¹ with ξ = 1
            assert abs(j.g1_xi - 1) < 1e-9 and j.g1_residual < 1e-9
        if expected >= 2:
            assert abs(j.g2_delta) < 1e-6 and j.g2_residual < 1e-9
        assert j.beta_g2_residual is None


def test_certificate_order_argument_and_tolerance():
    s = qs.Squad(Q, T)
    assert all(j.order == 0 for j in qs.continuity(s, order=0))
    assert all(j.order == 1 for j in qs.continuity(s, order=1))
    assert all(j.order == 3 for j in qs.continuity(s, order=3, tol=10.0))
    with pytest.raises(ValueError, match="order"):
        qs.continuity(s, order=6)
    with pytest.raises(ValueError, match="tol"):
        qs.continuity(s, tol=-1.0)


def test_certificate_with_zero_velocity_at_keys():
    s = qs.C3Spline(Q, T, alpha=0.0, beta=0.0)  # q' = 0 at every key
    assert all(j.order == 3 for j in qs.continuity(s))


def test_beta_spline_fields():
    s = qs.BetaSpline(Q, beta1=2.0, beta2=1.0)
    cert = qs.continuity(s)
    for j in cert:
        assert j.beta_g1_residual < 1e-12
        assert j.g1_residual < 1e-12 and j.order == 0  # G¹ with ξ = β₁/h ratio, not C¹
        assert j.beta_g2_residual > 1e-6 and j.theorem2_residual > 1e-7


def test_certificate_treats_q_and_minus_q_as_the_same_rotation():
    # Euler angles crossing ±180°: the LinEuler quaternion path ends a segment at −key
    keys = qs.from_euler(
        "xyz", [[0, 0, 150], [0, 0, 170], [0, 0, -175], [0, 0, -140]], degrees=True
    )
    s = qs.PiecewiseLinEuler(keys, seq="xyz")
    left = s.segment_derivatives(1, 2.0)[0]
    right = s.segment_derivatives(2, 2.0)[0]
    assert np.dot(left, right) < -0.99  # the raw quaternions are antipodal at joint 2
    assert [j.order for j in qs.continuity(s)] == [0, 0]
