"""quatspline.angle_between: the one rotation distance, cross-checked against scipy and mpmath,
and the held-out error of ``compare`` (which reported half the true angle)."""

from __future__ import annotations

import json

import mpmath
import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline.cli import main
from scipy.spatial.transform import Rotation

from ..conftest import axis_angle_quat, random_quats


def scipy_angle(a, b):
    r1 = Rotation.from_quat(np.asarray(a)[..., [1, 2, 3, 0]])
    r2 = Rotation.from_quat(np.asarray(b)[..., [1, 2, 3, 0]])
    return (r1.inv() * r2).magnitude()


def mp_angle(a, b):
    """Reference: 2·atan2(|v|, |w|) of a* b in 50-digit arithmetic on the given (rounded) data."""
    mpmath.mp.dps = 50
    a = [mpmath.mpf(float(x)) for x in a]
    b = [mpmath.mpf(float(x)) for x in b]
    na = mpmath.sqrt(sum(x * x for x in a))
    nb = mpmath.sqrt(sum(x * x for x in b))
    a = [x / na for x in a]
    b = [x / nb for x in b]
    aw, av = a[0], a[1:]
    bw, bv = b[0], b[1:]
    w = aw * bw + sum(x * y for x, y in zip(av, bv))
    cross = [
        av[1] * bv[2] - av[2] * bv[1],
        av[2] * bv[0] - av[0] * bv[2],
        av[0] * bv[1] - av[1] * bv[0],
    ]
    v = [aw * bv[k] - bw * av[k] - cross[k] for k in range(3)]
    return float(2 * mpmath.atan2(mpmath.sqrt(sum(x * x for x in v)), abs(w)))


def test_angle_between_matches_scipy_on_random_pairs():
    a, b = random_quats(2000, seed=1), random_quats(2000, seed=2)
    got = qs.angle_between(a, b)
    np.testing.assert_allclose(got, scipy_angle(a, b), rtol=1e-12, atol=1e-14)
    assert got.shape == (2000,)
    assert np.all((got >= 0) & (got <= np.pi))


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-8, 1.0, np.pi / 2, np.pi - 1e-9, np.pi])
@pytest.mark.parametrize("flip", [1.0, -1.0])
def test_angle_between_edge_pairs_match_scipy_and_mpmath(angle, flip):
    base = axis_angle_quat([0.3, -0.4, 0.5], 0.7)
    rel = axis_angle_quat([-0.2, 0.9, 0.1], angle)
    b = flip * qs.multiply(base, rel)
    got = float(qs.angle_between(base, b))
    ref = mp_angle(base, b)
    assert got == pytest.approx(ref, rel=1e-9, abs=2e-16)
    assert got == pytest.approx(float(scipy_angle(base, b)), rel=1e-9, abs=2e-16)
    # the intended angle, up to the rounding of the inputs
    assert got == pytest.approx(angle, rel=1e-6, abs=1e-15)


def test_angle_between_q_and_minus_q_is_zero_and_symmetric():
    q = random_quats(50, seed=3)
    assert np.all(qs.angle_between(q, -q) == 0.0)
    assert np.all(qs.angle_between(q, q) == 0.0)
    p = random_quats(50, seed=4)
    np.testing.assert_array_equal(qs.angle_between(p, q), qs.angle_between(q, p))


def test_angle_between_degrees_broadcasting_and_unnormalised_input():
    z90 = axis_angle_quat([0, 0, 1], np.pi / 2)
    assert float(qs.angle_between([1, 0, 0, 0], z90, degrees=True)) == pytest.approx(90.0)
    assert float(qs.angle_between([2, 0, 0, 0], 5 * z90, degrees=True)) == pytest.approx(90.0)
    out = qs.angle_between(np.tile(z90, (3, 2, 1)), [1.0, 0, 0, 0])
    assert out.shape == (3, 2)


@pytest.mark.parametrize(
    ("a", "b", "exc", "text"),
    [
        ([1, 0, 0], [1, 0, 0, 0], ValueError, "a: expected shape (..., 4)"),
        ([1, 0, 0, 0], [np.nan, 0, 0, 0], ValueError, "b: non-finite"),
        ([0, 0, 0, 0], [1, 0, 0, 0], ValueError, "a: quaternion 0 has zero"),
        (np.ones((3, 4)), np.ones((2, 4)), ValueError, "shapes do not broadcast"),
        ([1j, 0, 0, 0], [1, 0, 0, 0], TypeError, "a: expected real numbers"),
    ],
)
def test_angle_between_bad_input_names_the_argument(a, b, exc, text):
    with pytest.raises(exc, match=text.replace("(", r"\(").replace(")", r"\)")):
        qs.angle_between(a, b)
    with pytest.raises(TypeError, match="degrees"):
        qs.angle_between([1, 0, 0, 0], [1, 0, 0, 0], degrees="yes")


def test_holdout_error_is_the_full_rotation_angle_not_half(tmp_path, capsys):
    """Keys at frames 0 and 2 (identity); frame 1 is a 90° turn: slerp predicts the identity
    there, so the held-out error is 90° (main reported 45°)."""
    q = np.array([[1.0, 0, 0, 0], axis_angle_quat([0, 0, 1], np.pi / 2), [1.0, 0, 0, 0]])
    p = tmp_path / "turn.csv"
    qio.write(p, qio.Trajectory([0.0, 1.0, 2.0], q))
    assert main(["compare", str(p), "--methods", "slerp", "--holdout", "2", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)
    assert row["holdout_max_deg"] == pytest.approx(90.0, abs=1e-9)
    assert row["holdout_median_deg"] == pytest.approx(90.0, abs=1e-9)
