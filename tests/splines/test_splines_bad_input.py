"""Bad input to the spline constructors and evaluators: ValueErrors naming argument and index."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import random_walk

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


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(rate=1e12), r"rate: 1e\+12 samples per unit .* more than max_samples = 10000000"),
        (dict(rate=1e308), "gives inf samples, more than max_samples"),
        (dict(n=2**70), "n: 1.18059e\\+21 samples is more than max_samples"),
        (dict(rate=100.0, max_samples=50), "more than max_samples = 50"),
        (dict(n=51, max_samples=50), "more than max_samples = 50"),
    ],
)
def test_sample_refuses_more_than_max_samples_before_allocating(kwargs, match):
    # rate=1e12 over 2 time units ended in numpy's "Unable to allocate 21.8 TiB" MemoryError
    s = qs.NaturalSpline(random_walk(3, 0))
    with pytest.raises(ValueError, match=match):
        s.sample(**kwargs)
    t, q = s.sample(rate=10.0, max_samples=21)
    assert len(t) == len(q) == 21


@pytest.mark.parametrize("S", [qs.SphericalBezier, qs.CumulativeBezier])
@pytest.mark.parametrize(
    "domain, exc, match",
    [
        (5, TypeError, r"domain: expected a pair \(t0, t1\) of real numbers, got int 5"),
        ("ab", TypeError, r"domain: expected a pair \(t0, t1\)"),
        ((0.0,), TypeError, r"domain: expected a pair \(t0, t1\)"),
        (
            (0.0, "1"),
            TypeError,
            r"domain: expected a pair \(t0, t1\) of real numbers, got \(float, str\)",
        ),
        ((1.0, 0.0), ValueError, r"domain: expected finite t0 < t1, got \(1, 0\)"),
        ((0.0, np.inf), ValueError, r"domain: expected finite t0 < t1"),
    ],
)
def test_bezier_domain_that_is_not_a_pair_names_domain(S, domain, exc, match):
    # SphericalBezier(domain=5) raised "'int' object is not subscriptable"
    with pytest.raises(exc, match=match):
        S(random_walk(4, 1), domain=domain)
    assert S(random_walk(4, 1), domain=np.array([0, 2])).domain == (0.0, 2.0)


@pytest.mark.parametrize(
    "build",
    [
        lambda q: qs.MinimumEnergySpline(q, resolution=2**70),
        lambda q: qs.MinimumEnergySpline(q, penalty="jerk", resolution=2**70),
        lambda q: qs.CumulativeBSpline(q, order=2**70),
        lambda q: qs.CumulativeBSpline(q, order=10**400),
        lambda q: qs.NaturalSpline(q).sample(n=10**400),
        lambda q: qs.NaturalSpline(q).derivative([0.5], order=2**70),
        lambda q: qs.NaturalSpline(q).segment_derivatives(2**70, 0.5),
    ],
)
def test_huge_integer_arguments_are_value_errors_naming_the_argument(build):
    # MinimumEnergySpline(resolution=2**70) raised OverflowError from the binding
    q = random_walk(6, 2)
    with pytest.raises(ValueError) as e:
        build(q)
    name = str(e.value).split(":")[0]
    assert name in ("resolution", "order", "n", "segment"), str(e.value)
    assert len(str(e.value)) < 200, str(e.value)  # no 400-digit number in the message


def test_core_integer_arguments_beyond_64_bits_are_value_errors_not_overflow():
    # the binding's one conversion for integers: ValueError with a short number
    from quatspline import _core

    q = np.ascontiguousarray(random_walk(6, 2))
    for bad in (2**70, -1, 10**400):
        with pytest.raises(ValueError, match=r"expected an integer from 0 to \d+, got -?(~1e|\d)"):
            _core.cumulative_bspline(q, 1.0, 0.0, bad, True)
    with pytest.raises(TypeError):
        _core.cumulative_bspline(q, 1.0, 0.0, 2.5, True)
