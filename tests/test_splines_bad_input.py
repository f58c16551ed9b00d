"""Bad input to the spline constructors and evaluators: ValueErrors naming argument and index."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from .splinekit import random_walk

Q = random_walk(5, 1)
INTERPOLATING = [qs.PiecewiseSlerp, qs.Squad, qs.CatmullRom, qs.NaturalSpline]


@pytest.mark.parametrize("S", INTERPOLATING)
def test_too_few_keys(S):
    with pytest.raises(ValueError, match=r"quats: needs at least 2 keys, got 1"):
        S(Q[:1])


def test_bspline_needs_order_many_control_points_and_valid_params():
    with pytest.raises(ValueError, match=r"control_quats: needs at least 4 keys, got 3"):
        qs.CumulativeBSpline(Q[:3])
    with pytest.raises(ValueError, match=r"^dt: expected a finite positive"):
        qs.CumulativeBSpline(Q, dt=0.0)
    with pytest.raises(ValueError, match=r"^order: expected 2"):
        qs.CumulativeBSpline(Q, order=1)


@pytest.mark.parametrize("S", INTERPOLATING)
def test_times_not_strictly_increasing(S):
    with pytest.raises(
        ValueError, match=r"times: not strictly increasing at index 2 \(1 after 1\)"
    ):
        S(Q, times=[0.0, 1.0, 1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"times: not strictly increasing at index 1"):
        S(Q, times=[0.0, -1.0, 1.0, 2.0, 3.0])


@pytest.mark.parametrize("S", INTERPOLATING)
def test_times_and_quats_of_different_lengths(S):
    with pytest.raises(ValueError, match=r"times: expected 5 times \(one per key\), got 4"):
        S(Q, times=[0.0, 1.0, 2.0, 3.0])


@pytest.mark.parametrize("S", INTERPOLATING)
def test_nan_anywhere(S):
    bad = Q.copy()
    bad[3, 2] = np.nan
    with pytest.raises(ValueError, match=r"quats: non-finite value .* element 3"):
        S(bad)
    with pytest.raises(ValueError, match=r"times: non-finite value .* element 2"):
        S(Q, times=[0.0, 1.0, np.inf, 3.0, 4.0])
    s = S(Q)
    with pytest.raises(ValueError, match=r"^t: non-finite value .* element 1"):
        s([0.5, np.nan])


def test_zero_key():
    bad = Q.copy()
    bad[2] = 0.0
    with pytest.raises(ValueError, match=r"quats: quaternion 2 has zero"):
        qs.Squad(bad)


def test_shapes_and_options():
    with pytest.raises(ValueError, match=r"quats: expected shape \(N, 4\), got \(2, 5, 4\)"):
        qs.Squad(np.zeros((2, 5, 4)))
    with pytest.raises(ValueError, match=r"quats: expected shape \(\.\.\., 4\), got \(5, 3\)"):
        qs.Squad(np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"^ends: .*supported: reflect, duplicate, rest, closed"):
        qs.CatmullRom(Q, ends="loop")
    with pytest.raises(ValueError, match=r"^ends: .*supported: natural, clamped, rest, closed"):
        qs.NaturalSpline(Q, ends="periodic")
    with pytest.raises(ValueError, match=r"^extrapolate: expected"):
        qs.Squad(Q, extrapolate="wrap")
    with pytest.raises(ValueError, match=r"^frame: expected"):
        qs.Squad(Q).angular_velocity(1.0, frame="inertial")
    with pytest.raises(ValueError, match=r"^order: expected"):
        qs.Squad(Q).derivative(1.0, order=4)
    with pytest.raises(ValueError, match=r"^start_rate: expected shape \(3,\)"):
        qs.NaturalSpline(Q, ends="clamped", start_rate=[1.0, 2.0])
