"""Helpers shared by the spline tests: random keys, finite differences, joint jumps."""

from __future__ import annotations

import numpy as np
import quatspline as qs


def random_walk(n, seed, step=0.6):
    """Keys whose consecutive relative rotations are random with angle ≤ 2·step."""
    rng = np.random.default_rng(seed)
    q = [qs.normalize(rng.normal(size=4))]
    for _ in range(n - 1):
        v = rng.normal(size=3)
        v *= rng.uniform(0.05, step) / np.linalg.norm(v)
        q.append(qs.multiply(q[-1], qs.exp(np.r_[0.0, v])))
    return np.array(q)


def random_times(n, seed):
    rng = np.random.default_rng(seed + 1000)
    return np.concatenate([[0.0], np.cumsum(rng.uniform(0.3, 2.0, n - 1))])


def fd(f, t, h):
    """4th-order central difference of f at t."""
    return (-f(t + 2 * h) + 8 * f(t + h) - 8 * f(t - h) + f(t - 2 * h)) / (12 * h)


def joint_jumps(s, order=3):
    """Per interior joint: relative jumps |L − R| / max(1, |L|, |R|) of q, q', …, q^(order)."""
    j = s.joints
    out = []
    for k in range(1, len(j) - 1):
        left = s.segment_derivatives(k - 1, j[k])
        right = s.segment_derivatives(k, j[k])
        row = []
        for m in range(order + 1):
            scale = max(1.0, np.linalg.norm(left[m]), np.linalg.norm(right[m]))
            row.append(np.linalg.norm(left[m] - right[m]) / scale)
        out.append(row)
    return np.array(out)
