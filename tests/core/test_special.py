"""The singular-ratio helpers against mpmath, on both sides of each Taylor switch.

Every entry of the core's table (`TABLE` in crates/quatspline/src/special.rs, read through
`_core.special_fn`) is compared with an mpmath reference at 50 digits (more where the closed
form cancels) at 0, 1e-300, 1e-12, 1e-8, just below, at and just above its switch, and beyond.
The tolerances are per side of the switch: the series sides are within ~1e-15 relative; a
closed form just above its switch loses digits to cancellation ((1 − cos x)/x² style) and
its tolerance says how many (moving a switch is a behaviour change, not made here).
`test_every_table_entry_is_tested` fails when a helper is added without a test here.
"""

from __future__ import annotations

import re
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from quatspline import _core

mp.mp.dps = 50
SWITCH = 1e-3  # SINC_SWITCH and ATAN2_OVER_SWITCH in crates/quatspline/src/special.rs
KIN_SWITCH = 0.5
HALF_COT_SQ_SWITCH = 0.3
HALF_COT_SWITCH = 0.1
CS_SERIES = 0.5
G_SERIES = 0.05
SINC_JET_SWITCH = 1e-2
SCALED_JR_SWITCH = 0.02
SPECIAL_RS = Path(__file__).resolve().parents[2] / "crates" / "quatspline" / "src" / "special.rs"
M = mp.mpf


def core(name, a, b=0.0):
    return float(_core.special_fn(name, np.array([[a, b]]))[0, 0])


def sides(s):
    return [0.0, 1e-300, 1e-12, 1e-8, s * (1 - 1e-9), s, s * (1 + 1e-9), 2 * s, 0.1, 1.0, 3.0]


def rel_err(got, ref):
    ref = float(ref)
    return abs(got - ref) / max(abs(ref), 1e-200)


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


# ---- one-argument ratios: (reference, its value at 0, switch, tolerance below, above) ----

RATIOS = {
    "one_minus_cos_over_sq": (
        lambda x: (1 - mp.cos(x)) / x**2,
        M(1) / 2,
        KIN_SWITCH,
        1e-15,
        1e-15,
    ),
    "x_minus_sin_over_cube": (
        lambda x: (x - mp.sin(x)) / x**3,
        M(1) / 6,
        KIN_SWITCH,
        1e-15,
        3e-15,
    ),
    "one_minus_half_cot_over_sq": (
        lambda x: (1 - (x / 2) * mp.cot(x / 2)) / x**2,
        M(1) / 12,
        HALF_COT_SQ_SWITCH,
        1e-15,
        2e-14,  # 1 − (x/2)cot(x/2) ≈ x²/12 cancels: 7.5e-15 measured at the switch
    ),
    "one_minus_half_cot_over_sq_fit": (
        lambda x: (1 - (x / 2) * mp.cot(x / 2)) / x**2,
        M(1) / 12,
        HALF_COT_SWITCH,
        5e-15,  # four terms: the next, x⁸/47900160, is 2.5e-15 relative at the switch
        6e-13,  # 1/x² − (1 + cos x)/(2x sin x) cancels: 2.5e-13 measured at the switch
    ),
    "half_cot": (
        lambda x: (x / 2) * mp.cot(x / 2),
        M(1),
        HALF_COT_SWITCH,
        2e-14,  # four terms: the next, x⁸/1209600, is 8.3e-15 at the switch
        1e-15,
    ),
    "accel_k1": (
        lambda x: (-x * mp.sin(x) - 2 * (mp.cos(x) - 1)) / x**4,
        M(1) / 12,
        KIN_SWITCH,
        1e-15,
        5e-14,  # x⁴/12 from O(1) terms: 1.7e-14 measured at the switch
    ),
    "accel_k2": (
        lambda x: (-2 * x + 3 * mp.sin(x) - x * mp.cos(x)) / x**5,
        -M(1) / 60,
        KIN_SWITCH,
        1e-15,
        8e-13,  # −x⁵/60 from O(x) terms: 2.9e-13 measured at the switch
    ),
}


RATIO_CASES = [
    pytest.param(name, x, lo if x < s else hi, id=f"{name}-{x!r}")
    for name, (_, _, s, lo, hi) in RATIOS.items()
    for x in sides(s)
]


@pytest.mark.parametrize(("name", "x", "tol"), RATIO_CASES)
def test_ratio_against_mpmath_on_both_sides_of_its_switch(name, x, tol):
    f, at0, _, _, _ = RATIOS[name]
    if x < 1e-50:  # the closed form would need ~1000 digits; the error of the limit is ~x²
        ref = at0
    else:
        with mp.workdps(250):
            ref = f(M(x))
    assert rel_err(core(name, x), ref) <= tol


@pytest.mark.parametrize("x", sides(HALF_COT_SWITCH))
def test_one_minus_sqrt_half_cot_over_sq(x):
    # the helper takes x² (the squared norm its caller has)
    x2 = x * x
    if x2 < 1e-100:
        ref = M(1) / 24
    else:
        with mp.workdps(250):
            r = mp.sqrt(M(x2))
            ref = (1 - mp.sqrt((r / 2) * mp.cot(r / 2))) / M(x2)
    # three terms below the switch (x⁶/1209600: 1e-11 relative there); 2e-13 above
    tol = 3e-11 if x < HALF_COT_SWITCH else 6e-13
    assert rel_err(core("one_minus_sqrt_half_cot_over_sq", x2), ref) <= tol


# ---- derivative tables: the n-th derivative, n = 0 … 5 ----


def nth_derivative(f, x, n):
    with mp.workdps(80):
        return mp.re(mp.diff(f, M(x), n))


# Tolerance per derivative order below / above the switch. Above, the closed-form recursions
# (S⁽ⁿ⁾ = (C⁽ⁿ⁻¹⁾ − (2n − 1) S⁽ⁿ⁻¹⁾)/(2x), (1 − w²) g⁽ⁿ⁾ = …, sin x · x⁻¹ on jets) lose about
# one digit per order just above the switch; the measured errors are within a third of these.
CS_ABOVE = [1e-15, 1e-15, 1e-15, 3e-14, 2e-12, 2.5e-10]
G_ABOVE = [1e-15, 1e-14, 5e-13, 2e-11, 6e-10, 2.5e-8]


@pytest.mark.parametrize("n", range(6))
@pytest.mark.parametrize("x", [*sides(CS_SERIES), 9.0])
def test_cos_sqrt_derivatives(x, n):
    ref = nth_derivative(lambda t: mp.cos(mp.sqrt(t)), x, n)
    tol = 1e-15 if x < CS_SERIES else CS_ABOVE[n]
    assert rel_err(core("cos_sqrt", x, n), ref) <= tol


@pytest.mark.parametrize("n", range(6))
@pytest.mark.parametrize("x", [*sides(CS_SERIES), 9.0])
def test_sinc_sqrt_derivatives(x, n):
    ref = nth_derivative(lambda t: mp.sinc(mp.sqrt(t)), x, n)
    tol = 1e-15 if x < CS_SERIES else [*CS_ABOVE[1:], 5e-8][n]
    assert rel_err(core("sinc_sqrt", x, n), ref) <= tol


@pytest.mark.parametrize("n", range(6))
@pytest.mark.parametrize(
    "y", [1e-12, 1e-8, G_SERIES * (1 - 1e-9), G_SERIES, G_SERIES * (1 + 1e-9), 0.1, 0.5, 1.0, 1.5]
)
def test_theta_over_sin_derivatives(y, n):
    # g(w) = θ/sin θ with w = cos θ, switch on y = 1 − w
    w = 1.0 - y
    ref = nth_derivative(lambda v: mp.acos(v) / mp.sqrt(1 - v * v), w, n)
    tol = 1e-15 if y < G_SERIES else G_ABOVE[n]
    assert rel_err(core("theta_over_sin", w, n), ref) <= tol


SINC_JET_BELOW = [1e-15, 1e-15, 1e-15, 1e-15, 2e-15, 2e-10]  # 5 terms: x¹⁰/11! missing at n = 5
SINC_JET_ABOVE = [1e-15, 1e-11, 3e-11, 1e-6, 1e-5, 0.1]  # sin x · x⁻¹: derivatives of 1/x cancel


@pytest.mark.parametrize("n", range(6))
@pytest.mark.parametrize("x", [v for x in sides(SINC_JET_SWITCH) for v in (x, -x)])
def test_sinc_jet_derivatives(x, n):
    ref = nth_derivative(mp.sinc, x, n)
    got = core("sinc_jet", x, n)
    if abs(x) < SINC_JET_SWITCH:
        # odd derivatives vanish at 0 like x: compare absolutely against the size of the
        # derivative's scale (1/(n + 1)) there
        assert abs(got - float(ref)) <= SINC_JET_BELOW[n] * max(abs(float(ref)), 1e-3)
    else:
        assert rel_err(got, ref) <= SINC_JET_ABOVE[n]


# ---- two-argument: (b, a) ----

SCALED_JR = {
    # name: (reference, tolerance below, above)
    "one_minus_cos_ba_over_a": (lambda b, a: (1 - mp.cos(b * a)) / a, 1e-14, 8e-12),
    "b_minus_sin_ba_over_a": (lambda b, a: b - mp.sin(b * a) / a, 3e-15, 5e-11),
}


@pytest.mark.parametrize("name", SCALED_JR)
@pytest.mark.parametrize("b", [0.3, 0.999, 1.0])
@pytest.mark.parametrize("a", sides(SCALED_JR_SWITCH))
def test_scaled_jr_coefficients(name, b, a):
    f, lo, hi = SCALED_JR[name]
    got = core(name, b, a)
    if a < 1e-100:
        assert abs(got) <= 1e-200  # both vanish like a
        return
    with mp.workdps(400):
        ref = f(M(b), M(a))
    # Above the switch the closed forms cancel (1 − cos(ba) ≈ (ba)²/2): 2.6e-12 and 1.4e-11
    # measured just above it.
    assert rel_err(got, ref) <= (lo if a < SCALED_JR_SWITCH else hi)


TESTED = {
    "sinc",
    "atan2_over",
    "sin_ratio",
    *RATIOS,
    "one_minus_sqrt_half_cot_over_sq",
    "cos_sqrt",
    "sinc_sqrt",
    "theta_over_sin",
    "sinc_jet",
    *SCALED_JR,
}


def table_names():
    text = SPECIAL_RS.read_text(encoding="utf-8")
    body = text[text.index("pub const TABLE") :]
    body = body[: body.index("];")]
    return re.findall(r'^\s*\("(\w+)",', body, flags=re.MULTILINE)


def test_every_table_entry_is_tested():
    names = table_names()
    assert len(names) == len(set(names))
    assert set(names) == TESTED
    for name in names:  # and the binding reaches each of them
        assert np.isfinite(core(name, 0.25, 1.0))
