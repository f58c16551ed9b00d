"""The Beta quaternion spline: the paper's Example 1 and 2, G¹ exactly, G² as it really is."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.examples import BETA_EXAMPLE1_VERTICES, BETA_EXAMPLE2_VERTICES

from ..splinekit import random_walk

# MATH.md §7, Example 1: the paper's printed control points (β₁ = 1, β₂ = 0.5)
EXAMPLE1_EXPECTED = {
    (1, 0): [-0.3796, 0.4589, 0.1106, 0.7956],
    (1, 1): [-0.4610, 0.6671, -0.1507, 0.5655],
    (1, 2): [-0.5894, 0.4380, -0.6543, 0.1810],
    (1, 3): [-0.6093, 0.1514, -0.7734, -0.0877],
    (2, 0): [-0.6093, 0.1514, -0.7734, -0.0877],
    (2, 1): [-0.5263, -0.1607, -0.7619, -0.3415],
    (2, 2): [-0.5474, -0.3901, -0.6038, -0.4284],
    (2, 3): [-0.3509, -0.7065, -0.5548, -0.2642],
}


def example1(**kw):
    return qs.BetaSpline(BETA_EXAMPLE1_VERTICES, beta1=1.0, beta2=0.5, canonicalize=False, **kw)


def test_example1_control_points_to_four_decimals():
    cp = example1().control_points()
    assert cp.shape == (2, 4, 4)
    for (seg, j), expected in EXAMPLE1_EXPECTED.items():
        np.testing.assert_allclose(cp[seg - 1, j], expected, atol=5e-5, err_msg=f"q_{seg},{j}")


def test_example1_certificate_is_g1_not_g2():
    (joint,) = qs.continuity(example1())
    assert joint.beta_g1_residual < 1e-14
    assert joint.g1_residual < 1e-14 and abs(joint.g1_xi - 1.0) < 1e-14
    # MATH.md §7: the G² residual is 0.066 with |s''| ≈ 2.08 — the paper's G² claim is false
    assert abs(joint.beta_g2_residual - 0.066) < 0.0005
    assert abs(joint.second_derivative - 2.08) < 0.005
    assert joint.order == 1  # β₁ = 1 and unit spacing: C¹ too, but not C²


def random_betas(n, seed):
    rng = np.random.default_rng(seed)
    b1 = rng.uniform(0.2, 4.0, n)
    b2 = rng.uniform(-0.5, 3.0, n)
    return b1, b2


@pytest.mark.parametrize("seed", range(20))
def test_g1_exact_and_g2_equals_corrected_theorem2_on_random_data(seed):
    p = random_walk(9, seed, step=0.5)
    b1, b2 = random_betas(9, seed)
    s = qs.BetaSpline(p, beta1=b1, beta2=b2)
    res = s._core.beta_residuals()
    assert len(res) == 5  # l = 6 segments, 5 interior joints
    for _, g1, g2, th2, gamma, _ in res:
        assert np.linalg.norm(g1) <= 1e-12
        np.testing.assert_allclose(np.array(g2), 6.0 / gamma * np.array(th2), atol=1e-11)
    # and G² fails in general: the residual is visibly non-zero
    assert max(np.linalg.norm(r[2]) for r in res) > 1e-4


def test_g2_holds_when_all_rotations_share_one_axis():
    p = qs.from_axis_angle([0.2, -0.4, 0.9], np.cumsum([0.3, 0.5, 0.2, 0.7, 0.4, 0.6]))
    b1, b2 = random_betas(6, 1)
    for _, _g1, g2, th2, *_ in qs.BetaSpline(p, beta1=b1, beta2=b2)._core.beta_residuals():
        assert np.linalg.norm(g2) < 1e-12 and np.linalg.norm(th2) < 1e-12


def test_unit_betas_give_the_b_spline_bezier_points():
    p = random_walk(6, 2)
    cp = qs.BetaSpline(p).control_points()
    for i in range(1, 4):
        np.testing.assert_allclose(cp[i - 1, 1], qs.slerp(p[i], p[i + 1], 1 / 3), atol=1e-15)
        np.testing.assert_allclose(cp[i - 1, 2], qs.slerp(p[i], p[i + 1], 2 / 3), atol=1e-15)
        mid = qs.slerp(qs.slerp(p[i - 1], p[i], 2 / 3), qs.slerp(p[i], p[i + 1], 1 / 3), 0.5)
        np.testing.assert_allclose(cp[i - 1, 0], mid, atol=1e-15)


def test_unit_betas_equal_the_cumulative_b_spline_when_rotations_commute():
    """β₁ = 1, β₂ = 0 is the cumulative cubic B-spline exactly when all rotations share one
    axis. On general data the two curves differ at second order in the key spacing (the Beta
    spline blends slerp-derived Bézier points; Kim's B-spline blends the vertices' logs)."""
    p = qs.from_axis_angle([0.3, -0.2, 0.9], np.cumsum(np.linspace(0.2, 0.9, 7)))
    t = np.linspace(0, 4, 401)
    np.testing.assert_allclose(qs.BetaSpline(p)(t), qs.CumulativeBSpline(p)(t), atol=2e-15)
    diffs = []
    for step in (0.4, 0.2, 0.1):
        g = random_walk(7, 3, step=step)
        diffs.append(np.abs(qs.BetaSpline(g)(t) - qs.CumulativeBSpline(g)(t)).max())
    assert diffs[0] > diffs[1] > diffs[2] and diffs[2] < 3e-4


def test_example2_shape_parameters_change_the_shape_locally():
    # Example 2's vertices, extended by three vertices so segments away from vertex 1 exist
    extra = random_walk(4, 5, step=0.3)[1:]
    p = np.vstack([BETA_EXAMPLE2_VERTICES, qs.multiply(BETA_EXAMPLE2_VERTICES[-1], extra)])
    n = len(p)
    t = np.linspace(0, n - 3, 8 * (n - 3) + 1)
    curves = {}
    for b12 in (0.5, 2.0, 4.0):
        b2 = np.full(n, 0.5)
        b2[1] = b12
        curves[b12] = qs.BetaSpline(p, beta1=1.0, beta2=b2)(t)
    far = t >= 3.0  # segments 3 … l do not use vertex 1's parameters
    near = (t > 0) & (t < 2.0)
    for a, b in ((0.5, 2.0), (2.0, 4.0)):
        np.testing.assert_array_equal(curves[a][far], curves[b][far])
        assert np.abs(curves[a][near] - curves[b][near]).max() > 1e-3
    # a larger β₂ (tension) pulls the curve towards the vertex: the change is monotone
    d1 = np.abs(curves[2.0] - curves[0.5]).max()
    d2 = np.abs(curves[4.0] - curves[0.5]).max()
    assert d2 > d1


def test_rigid_body_points_on_example1():
    s = example1()
    t = np.linspace(0, 2, 5)
    body = np.array([[1.0, 0, 0], [0, 0.5, 0.2]])
    world = qs.rotate_points(s(t), body)
    assert world.shape == (5, 2, 3)
    q = s(t)
    for m in range(5):
        for k in range(2):
            ref = qs.multiply(qs.multiply(q[m], np.r_[0.0, body[k]]), qs.conjugate(q[m]))[1:]
            np.testing.assert_allclose(world[m, k], ref, atol=1e-15)


def test_bad_input():
    p = random_walk(5, 1)
    with pytest.raises(ValueError, match=r"beta1: beta1\[2\] = 0 must be > 0"):
        qs.BetaSpline(p, beta1=[1.0, 1.0, 0.0, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"beta1\[0\] = -1 must be > 0"):
        qs.BetaSpline(p, beta1=-1.0)
    # β₂ + 2β₁(1+β₁) = 0 with β₁ = 1: β₂ = −4
    with pytest.raises(ValueError, match=r"beta2: beta2\[0\] = -4 makes .* ≤ 0"):
        qs.BetaSpline(p, beta2=-4.0)
    with pytest.raises(ValueError, match=r"beta2: beta2\[3\] = -5"):
        qs.BetaSpline(p, beta2=[0, 0, 0, -5.0, 0])
    with pytest.raises(
        ValueError, match=r"beta1: expected 1 or 5 values \(one per vertex\), got 3"
    ):
        qs.BetaSpline(p, beta1=[1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"vertices: needs at least 4 keys, got 3"):
        qs.BetaSpline(p[:3])
    with pytest.raises(ValueError, match=r"times: not strictly increasing at index 1"):
        qs.BetaSpline(p, times=[0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match=r"times: expected 3 times"):
        qs.BetaSpline(p, times=[0.0, 1.0])
    with pytest.raises(ValueError, match=r"beta2: non-finite value .* element 1"):
        qs.BetaSpline(p, beta2=[0, np.nan, 0, 0, 0])
