"""Bad input: one-line ValueErrors that name the argument; never a crash or a silent NaN."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs

Q = np.array([1.0, 0.0, 0.0, 0.0])


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_names_the_argument(bad):
    q = np.array([[1.0, 0, 0, 0], [1.0, bad, 0, 0]])
    with pytest.raises(ValueError, match=r"q1: non-finite .* element 1"):
        qs.slerp(Q, q, 0.5)
    with pytest.raises(ValueError, match=r"^t: non-finite"):
        qs.slerp(Q, Q, bad)
    with pytest.raises(ValueError, match=r"^angles: non-finite"):
        qs.from_euler("xyz", [0.0, bad, 0.0])
    with pytest.raises(ValueError, match=r"^matrix: non-finite"):
        qs.from_matrix(np.full((3, 3), bad))


def test_zero_quaternion():
    with pytest.raises(ValueError, match=r"q0: quaternion 2 has zero"):
        qs.slerp([[1.0, 0, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0]], Q, 0.5)
    with pytest.raises(ValueError, match="zero"):
        qs.normalize([1e-320, 0, 0, 0])
    with pytest.raises(ValueError, match="zero"):
        qs.inverse([0.0, 0, 0, 0])
    with pytest.raises(ValueError, match="zero"):
        qs.as_matrix([0.0, 0, 0, 0])


def test_non_unit_is_normalised():
    np.testing.assert_allclose(qs.slerp([2.0, 0, 0, 0], [0, 0, 0, 5.0], 1.0), [0, 0, 0, 1])
    np.testing.assert_allclose(qs.as_matrix([3.0, 0, 0, 0]), np.eye(3))


def test_shapes_named_with_both_shapes():
    with pytest.raises(ValueError, match=r"q0: expected shape \(\.\.\., 4\), got \(3,\)"):
        qs.slerp([1.0, 0, 0], Q, 0.5)
    with pytest.raises(ValueError, match=r"do not broadcast: q0 \(3, 4\), q1 \(2, 4\)"):
        qs.slerp(np.tile(Q, (3, 1)), np.tile(Q, (2, 1)), 0.5)
    with pytest.raises(ValueError, match=r"matrix: expected shape \(\.\.\., 3, 3\)"):
        qs.from_matrix(np.eye(4))
    with pytest.raises(ValueError, match=r"weights: expected shape \(\.\.\., 2\)"):
        qs.dlb(np.zeros((2, 8)) + [1, 0, 0, 0, 0, 0, 0, 0], [1.0, 2.0, 3.0])


def test_unknown_euler_sequence_lists_valid_ones():
    with pytest.raises(ValueError, match=r'seq: unknown rotation sequence "xyy".*"xyz".*"ZYZ"'):
        qs.from_euler("xyy", [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="unknown Euler sequence"):
        qs.as_euler(Q, "XyZ")


@pytest.mark.parametrize(
    "bad", [np.array([1 + 0j, 0, 0, 0]), np.array([1, 0, 0, "a"], dtype=object)]
)
def test_complex_and_object_dtypes_rejected(bad):
    with pytest.raises(TypeError, match="q: expected real numbers"):
        qs.normalize(bad)


def test_int_float32_readonly_and_strided_inputs_accepted():
    a = np.array([[1, 0, 0, 0], [0, 1, 0, 0]], dtype=np.int64)
    np.testing.assert_allclose(qs.normalize(a), a)
    f = np.array([0.5, 0.5, 0.5, 0.5], dtype=np.float32)
    assert qs.normalize(f).dtype == np.float64
    big = np.zeros((6, 8))
    big[:, 0] = 1.0
    strided = big[::2, ::2]  # non-contiguous (3, 4)
    strided.flags.writeable = False
    np.testing.assert_allclose(qs.normalize(strided), np.tile([1.0, 0, 0, 0], (3, 1)))


def test_det_non_positive_matrix():
    with pytest.raises(ValueError, match="matrix: matrix 0: non-positive determinant"):
        qs.from_matrix(-np.eye(3))


def test_zero_axis_and_dlb_zero_sum():
    with pytest.raises(ValueError, match="axis 0 is zero"):
        qs.from_axis_angle([0.0, 0, 0], 1.0)
    a = qs.dq_from_pose(Q, [0, 0, 0.0])
    with pytest.raises(ValueError, match="weights"):
        qs.dlb(np.stack([a, a]), [1.0, -1.0])


def test_empty_batches():
    assert qs.slerp(np.zeros((0, 4)), np.zeros((0, 4)), 0.5).shape == (0, 4)
    assert qs.as_matrix(np.zeros((0, 4))).shape == (0, 3, 3)
