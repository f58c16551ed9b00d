"""quatspline.imu.allan_deviation against the textbook definition written out directly."""

from __future__ import annotations

import numpy as np
import pytest
from quatspline.imu import allan_deviation


def _brute(y, rate, m):
    """Overlapping Allan deviation from the averages of m samples (NIST SP 1065, eq. 13):
    σ² = 1 / (2 (N − 2m + 1)) Σ_j (ȳ_{j+m} − ȳ_j)², ȳ_j the mean of y[j : j + m]."""
    n = len(y)
    means = np.array([y[j : j + m].mean() for j in range(n - m + 1)])
    d = means[m:] - means[:-m]
    return np.sqrt(np.sum(d**2) / (2 * d.size))


@pytest.mark.parametrize("m", [1, 2, 7, 24, 49])
def test_matches_the_definition(m):
    rng = np.random.default_rng(m)
    y = rng.standard_normal(99) + np.cumsum(rng.standard_normal(99)) * 0.1 + 5.0
    taus, adev = allan_deviation(y, 20.0, taus=[m / 20.0])
    assert taus[0] == m / 20.0
    assert adev[0] == pytest.approx(_brute(y, 20.0, m), rel=1e-12)


def test_columns_and_default_taus():
    rng = np.random.default_rng(0)
    y = rng.standard_normal((1000, 2))
    taus, adev = allan_deviation(y, 10.0)
    assert adev.shape == (taus.size, 2)
    assert taus[0] == 0.1 and taus[-1] == 49.9 and np.all(np.diff(taus) > 0)
    t1, a1 = allan_deviation(y[:, 1], 10.0)
    np.testing.assert_allclose(a1, adev[:, 1], rtol=1e-13)


@pytest.mark.parametrize(
    ("args", "exc", "match"),
    [
        (([1.0, 2.0], 1.0), ValueError, "at least 3"),
        ((np.zeros(10), 0.0), ValueError, "rate"),
        ((np.zeros(10), 1.0, [5.0]), ValueError, "outside"),
        ((np.zeros(10), 1.0, [0.1]), ValueError, "outside"),
        ((np.zeros((10, 2, 2)), 1.0), ValueError, "shape"),
        (([1.0, np.nan, 2.0], 1.0), ValueError, "not finite"),
        ((["a", "b", "c"], 1.0), TypeError, "samples"),
    ],
)
def test_bad_input(args, exc, match):
    with pytest.raises(exc, match=match):
        allan_deviation(*args)
