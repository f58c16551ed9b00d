"""CumulativeBezier: the windowed evaluation against mpmath, finite differences and the ends.

The curve is evaluated over a window of the Bernstein basis (terms at least 2⁻⁶⁰ times the
largest); these tests check it against an exact evaluation of the whole product in mpmath,
so that they fail if the window drops mass above round-off.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import quatspline as qs

from ..splinekit import fd, random_walk


def _qmul(a, b):
    return (
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] + a[2] * b[0] + a[3] * b[1] - a[1] * b[3],
        a[0] * b[3] + a[3] * b[0] + a[1] * b[2] - a[2] * b[1],
    )


class _Exact:
    """q(u) = q₀ Π_j exp(B̃_j(u) log(q_{j−1}* q_j)) with every step in mpmath (40 digits)."""

    def __init__(self, ctrl):
        mp.mp.dps = 40
        q = [tuple(mp.mpf(float(x)) for x in row) for row in ctrl]
        q = [tuple(x / mp.sqrt(sum(y * y for y in r)) for x in r) for r in q]
        self.q0 = q[0]
        self.logs = []
        for a, b in zip(q[:-1], q[1:], strict=True):
            w, x, y, z = _qmul((a[0], -a[1], -a[2], -a[3]), b)
            v = mp.sqrt(x * x + y * y + z * z)
            th = mp.atan2(v, w)
            self.logs.append((th, (x / v, y / v, z / v)))
        self.n = len(q) - 1
        self.cache = {}

    def __call__(self, u):
        key = mp.mpf(u)
        if key in self.cache:
            return self.cache[key]
        n = self.n
        terms = [mp.binomial(n, i) * key**i * (1 - key) ** (n - i) for i in range(n + 1)]
        q, tail = self.q0, mp.fsum(terms[1:])
        for j in range(1, n + 1):
            th, ax = self.logs[j - 1]
            s, c = mp.sin(tail * th), mp.cos(tail * th)
            q = _qmul(q, (c, s * ax[0], s * ax[1], s * ax[2]))
            tail -= terms[j]
        self.cache[key] = q
        return q


@pytest.mark.parametrize("seed", [3, 8])
def test_values_and_derivatives_equal_an_exact_mpmath_evaluation_at_200_points(seed):
    """Fails if the window is too narrow: with steps of up to 1.2 rad, a window dropping
    Bernstein mass of ~1e-13 (a cut near 2⁻³⁶) moves the curve by more than the tolerance."""
    c = random_walk(201, seed, step=0.6)
    s = qs.CumulativeBezier(c)
    exact = _Exact(c)
    for u in (0.0, 1e-9, 0.004, 0.093, 0.5, 0.61803, 0.91, 0.9995, 1.0):
        want = np.array([float(x) for x in exact(u)], dtype=float)
        np.testing.assert_allclose(s(u), want, rtol=0, atol=2e-15 * np.sqrt(200), err_msg=f"u {u}")
        if 0.0 < u < 1.0:
            got = s.derivatives(u, 3)
            for k in (1, 2, 3):
                dk = np.array(
                    [
                        float(mp.diff(lambda x, i=i: exact(x)[i], u, k, h=mp.mpf("1e-11")))
                        for i in range(4)
                    ]
                )
                scale = max(1.0, np.abs(dk).max())
                np.testing.assert_allclose(
                    got[k], dk, rtol=0, atol=1e-12 * scale, err_msg=f"u {u} order {k}"
                )


@pytest.mark.parametrize("points", [17, 100, 1000, 4096])
def test_derivatives_match_finite_differences_and_the_ends_are_the_end_points(points):
    c = random_walk(points, 5, step=0.3)
    s = qs.CumulativeBezier(c, domain=(2.0, 5.0))
    h = 0.03 / points  # 1 % of the basis's scale in t near the ends, 3/n
    t = np.array([2.0 + 3 * h, 2.9, 3.5, 4.2, 5.0 - 3 * h])
    for k, f in ((1, s), (2, lambda x: s.derivative(x, 1)), (3, lambda x: s.derivative(x, 2))):
        want = fd(f, t, h)
        scale = np.abs(want).max()
        np.testing.assert_allclose(s.derivative(t, k), want, rtol=0, atol=1e-6 * scale)
    w = s.angular_velocity(t)
    np.testing.assert_allclose(np.linalg.norm(w, axis=-1) > 0, True)
    ends = s(np.array([2.0, 5.0]))
    want = c[[0, -1]] / np.linalg.norm(c[[0, -1]], axis=-1, keepdims=True)
    np.testing.assert_allclose(ends, want, rtol=0, atol=4e-16)


def test_values_and_rates_are_bit_identical_on_one_and_two_threads():
    """The window's buffers are per thread: sharing them would change results."""
    s = qs.CumulativeBezier(random_walk(4096, 2, 0.3))
    t = np.linspace(0.0, 1.0, 20_001)
    before = qs.get_num_threads()
    try:
        qs.set_num_threads(1)
        one = (s(t), s.angular_velocity(t))
        qs.set_num_threads(2)
        two = (s(t), s.angular_velocity(t))
    finally:
        qs.set_num_threads(before)
    np.testing.assert_array_equal(one[0], two[0])
    np.testing.assert_array_equal(one[1], two[1])
