"""The singular-ratio helpers against mpmath, on both sides of each Taylor switch."""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from quatspline import _core

mp.mp.dps = 50
SWITCH = 1e-3  # SINC_SWITCH and ATAN2_OVER_SWITCH in crates/quatspline/src/special.rs


def core(name, a, b=0.0):
    return float(_core.special_fn(name, np.array([[a, b]]))[0, 0])


def sides(s):
    return [0.0, 1e-300, 1e-12, 1e-8, s * (1 - 1e-9), s, s * (1 + 1e-9), 2 * s, 0.1, 1.0, 3.0]


@pytest.mark.parametrize("x", sides(SWITCH))
def test_sinc(x):
    ref = mp.mpf(1) if x == 0 else mp.sin(mp.mpf(x)) / mp.mpf(x)
    assert abs(core("sinc", x) - float(ref)) <= 2.3e-16  # one ulp at 1
    assert core("sinc", -x) == core("sinc", x)


@pytest.mark.parametrize("c", [1.0, 0.5, 2.0])
@pytest.mark.parametrize("r", sides(SWITCH))
def test_atan2_over(r, c):
    s = r * c
    ref = 1 / mp.mpf(c) if s == 0 else mp.atan2(mp.mpf(s), mp.mpf(c)) / mp.mpf(s)
    assert abs(core("atan2_over", s, c) - float(ref)) <= 1e-15 * float(abs(ref))


@pytest.mark.parametrize("a", [0.0, 0.25, 0.5, 0.999, 1.0, 1.5])
@pytest.mark.parametrize("x", sides(SWITCH)[:-1] + [1.5])
def test_sin_ratio(a, x):
    ref = mp.mpf(a) if x == 0 else mp.sin(mp.mpf(a) * mp.mpf(x)) / mp.sin(mp.mpf(x))
    assert abs(core("sin_ratio", a, x) - float(ref)) <= 1e-15


def test_atan2_over_negative_real_axis_is_large_not_nan():
    assert core("atan2_over", 1e-300, -1.0) > 1e299
