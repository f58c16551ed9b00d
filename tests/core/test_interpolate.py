"""Two-key interpolation cross-checked against scipy and pytransform3d."""

from __future__ import annotations

import numpy as np
import pytransform3d.batch_rotations as pbr
import quatspline as qs
from scipy.spatial.transform import Rotation, Slerp

from ..conftest import random_quats


def test_slerp_matches_scipy_slerp():
    keys = random_quats(30, seed=21)
    times = np.arange(30.0)
    t = np.random.default_rng(1).uniform(0, 29, 2000)
    ref = Slerp(times, Rotation.from_quat(qs.as_xyzw(keys)))(t).as_quat()
    i = np.minimum(t.astype(int), 28)
    got = qs.slerp(keys[i], keys[i + 1], t - i)
    d = np.minimum(np.abs(got - qs.from_xyzw(ref)).max(1), np.abs(got + qs.from_xyzw(ref)).max(1))
    assert d.max() < 1e-14


def test_slerp_matches_pytransform3d_batch():
    a, b = random_quats(500, seed=22), random_quats(500, seed=23)
    b = qs.canonicalize(b, reference=a)
    t = np.random.default_rng(2).uniform(0, 1, 500)
    ref = np.stack([pbr.quaternion_slerp_batch(a[k], b[k], t[k : k + 1])[0] for k in range(500)])
    np.testing.assert_allclose(qs.slerp(a, b, t), ref, atol=1e-14)


def test_slerp_constant_angular_speed():
    a, b = random_quats(2, seed=24)
    t = np.linspace(0, 1, 101)
    s = qs.slerp(a, b, t)
    steps = 2 * np.arccos(np.clip(np.abs(np.sum(s[1:] * s[:-1], axis=1)), 0, 1))
    np.testing.assert_allclose(steps, steps.mean(), rtol=1e-6)
