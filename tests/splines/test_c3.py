"""The patent's C³ spline: both variants, special cases, key derivatives, locality, C⁴ jump."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

from ..splinekit import joint_jumps, random_times, random_walk


def same_rotation(a, b, tol):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    assert np.max(d) <= tol, np.max(d)


def fourth_derivative_jumps(s, h=1e-4):
    """One-sided q'''' at each interior joint by differences of the analytic q''' inside each
    neighbouring segment; returns |jump| / max(1, |q''''|)."""
    j = s.joints
    out = []
    for k in range(1, len(j) - 1):
        hk = h * min(j[k] - j[k - 1], j[k + 1] - j[k])
        right = (
            -3 * s.segment_derivatives(k, j[k])[3]
            + 4 * s.segment_derivatives(k, j[k] + hk)[3]
            - s.segment_derivatives(k, j[k] + 2 * hk)[3]
        ) / (2 * hk)
        left = (
            3 * s.segment_derivatives(k - 1, j[k])[3]
            - 4 * s.segment_derivatives(k - 1, j[k] - hk)[3]
            + s.segment_derivatives(k - 1, j[k] - 2 * hk)[3]
        ) / (2 * hk)
        out.append(np.linalg.norm(right - left) / max(1.0, np.linalg.norm(right)))
    return np.array(out)


def test_knot_variant_is_c3_in_time_with_nonuniform_times_and_per_key_parameters():
    q, t = random_walk(9, 1), random_times(9, 1)
    rng = np.random.default_rng(1)
    s = qs.C3Spline(q, t, alpha=rng.uniform(0.1, 0.6, 9), beta=rng.uniform(-0.3, 0.5, 9))
    same_rotation(s(t), q, 1e-14)
    assert np.all(joint_jumps(s, 3) <= 1e-9)
    cert = qs.continuity(s)
    assert all(j.order == 3 for j in cert)
    # not C⁴: the fourth derivative visibly jumps
    assert np.max(fourth_derivative_jumps(s)) > 1e-2


def test_patent_variant_uniform_shared_parameters_is_c3():
    q = random_walk(8, 2)
    s = qs.C3Spline(q, alpha=0.4, beta=0.2, variant="patent")
    assert all(j.order == 3 for j in qs.continuity(s))
    assert np.max(fourth_derivative_jumps(s)) > 1e-2


def test_patent_variant_nonuniform_times_is_only_g1_in_time_and_the_certificate_shows_it():
    q, t = random_walk(7, 3), random_times(7, 3)
    s = qs.C3Spline(q, t, variant="patent")
    cert = qs.continuity(s)
    h = np.diff(t)
    for j in cert:
        assert j.order == 0  # velocity jumps in time …
        assert j.g1_residual < 1e-12  # … but only by a factor: G¹
        # speed ratio at key k: right/left = h_{k−1}/h_k
        assert abs(j.g1_xi - h[j.index - 1] / h[j.index]) < 1e-12


def test_patent_per_segment_parameters_break_continuity_knot_does_not():
    q = random_walk(6, 4)
    alphas = [0.1, 0.5, 0.2, 0.6, 0.3]
    patent = qs.C3Spline(q, alpha=alphas, variant="patent")
    assert min(j.order for j in qs.continuity(patent)) < 3
    knot = qs.C3Spline(q, alpha=alphas + [0.4])
    assert all(j.order == 3 for j in qs.continuity(knot))


def test_knot_equals_patent_for_uniform_times_and_constant_parameters():
    q = random_walk(7, 5)
    x = np.linspace(0, 6, 601)
    for a, b in ((5 / 16, 0.0), (0.3, -0.2), (0.0, 0.0)):
        k = qs.C3Spline(q, alpha=a, beta=b)
        p = qs.C3Spline(q, alpha=a, beta=b, variant="patent")
        np.testing.assert_allclose(k(x), p(x), atol=1e-14)
        np.testing.assert_allclose(k.jerk(x), p.jerk(x), atol=1e-9)


def test_zero_parameters_are_slerp_with_smoothstep7_timing():
    q, t = random_walk(5, 6), random_times(5, 6)
    s = qs.C3Spline(q, t, alpha=0.0, beta=0.0)
    for i in range(4):
        u = np.linspace(0, 1, 21)
        smooth = 35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7
        same_rotation(s(t[i] + u * (t[i + 1] - t[i])), qs.slerp(q[i], q[i + 1], smooth), 1e-14)
    np.testing.assert_allclose(s.angular_velocity(t), 0.0, atol=1e-14)


def test_quintic_case_has_degree_five_blending():
    # keys about one axis: the rotation angle along the curve is Σ C̃ⱼ(t) θⱼ, a polynomial
    ang = np.array([0.0, 0.4, 1.1, 1.3, 2.0])
    q = qs.from_axis_angle([0.0, 0.0, 1.0], ang)
    u = np.linspace(0, 1, 60)
    for (a, b), deg in (((5 / 16, 0.0), 5), ((0.3, 0.2), 7)):
        s = qs.C3Spline(q, alpha=a, beta=b, variant="patent")
        theta = 2 * np.arctan2(s(1 + u)[:, 3], s(1 + u)[:, 0])
        coef = np.polynomial.polynomial.polyfit(u, theta, 7)
        if deg == 5:
            assert np.all(np.abs(coef[6:]) < 1e-8), coef
        else:
            assert np.max(np.abs(coef[6:])) > 1e-3, coef


def test_key_derivatives_match_the_patent_formulas():
    """MATH.md §8: at the start of segment i (uniform times, local t = time),
    q' = α Qᵢ(a+b), q'' = Qᵢ[8α(b−a) + α²(a+b)²],
    q''' = Qᵢ[(36α+6β)(a+b) + 24α²(b²−a²) + α³(a+b)³], a = ωᵢ, b = ωᵢ₊₁, where the
    powers of (a+b) are expanded in order (every a before every b, as the product rule gives):
    (a+b)² → a² + 2ab + b², (a+b)³ → a³ + 3a²b + 3ab² + b³."""
    q = random_walk(6, 7)
    alpha, beta = 0.37, -0.21
    s = qs.C3Spline(q, alpha=alpha, beta=beta, variant="patent")
    m = qs.multiply
    for i in (1, 2, 3):
        a = qs.log(m(qs.conjugate(q[i - 1]), q[i]))
        b = qs.log(m(qs.conjugate(q[i]), q[i + 1]))
        d = s.segment_derivatives(i, float(i))
        ab = a + b
        sq = m(a, a) + 2 * m(a, b) + m(b, b)
        cube = m(m(a, a), a) + 3 * m(m(a, a), b) + 3 * m(a, m(b, b)) + m(m(b, b), b)
        np.testing.assert_allclose(d[1], alpha * m(q[i], ab), atol=1e-13)
        np.testing.assert_allclose(d[2], m(q[i], 8 * alpha * (b - a) + alpha**2 * sq), atol=1e-12)
        third = (36 * alpha + 6 * beta) * ab + 24 * alpha**2 * (m(b, b) - m(a, a)) + alpha**3 * cube
        np.testing.assert_allclose(d[3], m(q[i], third), atol=1e-11)


def test_alpha_changes_velocity_beta_only_jerk_at_keys():
    q = random_walk(6, 8)
    base = qs.C3Spline(q, alpha=0.3, beta=0.0)
    more_beta = qs.C3Spline(q, alpha=0.3, beta=0.4)
    more_alpha = qs.C3Spline(q, alpha=0.4, beta=0.0)
    keys = np.arange(1.0, 5.0)
    for f in (base.angular_velocity, base.angular_acceleration):
        g = getattr(more_beta, f.__name__)
        np.testing.assert_allclose(f(keys), g(keys), atol=1e-13)
    assert np.abs(base.jerk(keys) - more_beta.jerk(keys)).max() > 1e-3
    assert np.abs(base.angular_velocity(keys) - more_alpha.angular_velocity(keys)).max() > 1e-3


def test_locality_moving_one_key_changes_only_four_segments():
    q, t = random_walk(10, 9), random_times(10, 9)
    moved = q.copy()
    k = 5
    moved[k] = qs.multiply(q[k], qs.from_axis_angle([1.0, 0.3, 0.0], 0.2))
    a, b = qs.C3Spline(q, t), qs.C3Spline(moved, t)
    changed = []
    for seg in range(9):
        x = np.linspace(t[seg], t[seg + 1], 50)
        if np.abs(a(x) - b(x)).max() > 1e-15:
            changed.append(seg)
    assert changed == [k - 2, k - 1, k, k + 1]


def test_two_keys_and_clamped_ends():
    q = random_walk(2, 10)
    s = qs.C3Spline(q, [0.0, 2.0])
    same_rotation(s([0.0, 2.0]), q, 1e-15)
    assert np.all(np.isfinite(s.jerk(np.linspace(0, 2, 11))))


def test_bad_input():
    q = random_walk(5, 11)
    with pytest.raises(ValueError, match=r"alpha: expected 1 or 5 values \(one per key\), got 4"):
        qs.C3Spline(q, alpha=[0.3] * 4)
    with pytest.raises(
        ValueError, match=r"beta: expected 1 or 4 values \(one per segment\), got 5"
    ):
        qs.C3Spline(q, beta=[0.0] * 5, variant="patent")
    with pytest.raises(ValueError, match=r"quats: needs at least 2 keys, got 1"):
        qs.C3Spline(q[:1])
    with pytest.raises(ValueError, match=r"times: not strictly increasing at index 3"):
        qs.C3Spline(q, times=[0.0, 1.0, 2.0, 1.5, 3.0])
    with pytest.raises(ValueError, match=r"^variant: expected"):
        qs.C3Spline(q, variant="spline")
    with pytest.raises(ValueError, match=r"alpha: non-finite value .* element 0"):
        qs.C3Spline(q, alpha=np.nan)
