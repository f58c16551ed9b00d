"""Shared fixtures: the hard-case corpus and random data generators."""

from __future__ import annotations

import numpy as np
import pytest


def axis_angle_quat(axis, angle):
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


#: The corpus of MATH.md / STYLE.md: identity, tiny angles, near π, sign, unnormalised.
HARD_CASES = {
    "identity": np.array([1.0, 0.0, 0.0, 0.0]),
    "1e-12 rad": axis_angle_quat([0.3, -0.5, 0.8], 1e-12),
    "1e-8 rad": axis_angle_quat([1.0, 2.0, 3.0], 1e-8),
    "pi - 1e-9": axis_angle_quat([-0.2, 0.9, 0.1], np.pi - 1e-9),
    "negated": -axis_angle_quat([0.5, 0.5, -0.7], 1.1),
    "unnormalised": 3.7 * axis_angle_quat([0.0, 1.0, 1.0], 0.4),
    "generic": axis_angle_quat([0.6, -0.3, 0.2], 2.3),
}


@pytest.fixture(params=list(HARD_CASES), ids=list(HARD_CASES))
def hard_quat(request):
    return HARD_CASES[request.param]


def random_quats(n, seed=0):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
