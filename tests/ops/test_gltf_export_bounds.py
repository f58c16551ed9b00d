"""glTF export bounds: the failing channel is named, keys are added where keys can meet the
bound (and only an unreachable bound is refused, with the best achievable error), the bound
holds as players compute (float32 keys and times, slerp as three.js and nlerp as Blender,
between any two check points), and ``samples`` is bounded."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.ops._export import MAX_SAMPLES, parse_angle, to_gltf

from ..splinekit import random_walk
from .test_gltf import load_channels, rotation_error, wavy_pose


def test_export_error_names_the_translation_bound_when_translation_fails(tmp_path):
    pose = wavy_pose(n=5)
    with pytest.raises(ValueError, match=r"^max_position_error: .*best achievable error"):
        to_gltf(pose, tmp_path / "p.glb", max_position_error="1e-9m", progress=False)
    assert not (tmp_path / "p.glb").exists()


def test_export_error_names_the_rotation_bound_when_rotation_fails(tmp_path):
    pose = wavy_pose(n=5)
    with pytest.raises(ValueError, match=r"^max_error: .*best achievable error"):
        to_gltf(pose, tmp_path / "r.glb", max_error="1e-9deg", progress=False)


@pytest.mark.parametrize("interpolation", ["linear", "cubicspline"])
def test_export_adds_keys_between_adjacent_candidates_instead_of_refusing(tmp_path, interpolation):
    """Two candidates per segment cannot meet 0.01°: new candidates are placed where it
    fails, and the file meets the bound on a grid the exporter never saw."""
    s = qs.C3Spline(random_walk(4, 2, step=0.6), np.arange(4.0))
    path = tmp_path / "s.glb"
    rep = to_gltf(s, path, max_error="0.01deg", samples=2, interpolation=interpolation)
    assert rep.rotation_keys > 8  # far more than the 7 candidates the grid started with
    kind, kt, kv = load_channels(path)["rotation"]
    t = np.linspace(kt[0], kt[-1], 200_001)
    e = rotation_error(_play(kind, kt, kv, t, "slerp"), s(t))
    assert e.max() <= parse_angle("0.01deg")


def _play(kind, kt, kv, t, how):
    """Playback of float32 keys (x, y, z, w) written here from the specification: slerp
    (three.js) or component-wise lerp then normalise (Blender) for LINEAR."""
    kv = kv.astype(np.float64)
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 2)
    u = ((t - kt[k]) / (kt[k + 1] - kt[k]))[:, None]
    if kind == "CUBICSPLINE":
        a, v, b = kv[0::3], kv[1::3], kv[2::3]
        td = (kt[k + 1] - kt[k])[:, None]
        h = (
            (2 * u**3 - 3 * u**2 + 1) * v[k]
            + td * (u**3 - 2 * u**2 + u) * b[k]
            + (-2 * u**3 + 3 * u**2) * v[k + 1]
            + td * (u**3 - u**2) * a[k + 1]
        )
        return h / np.linalg.norm(h, axis=1, keepdims=True)
    q0, q1 = kv[k], kv[k + 1]
    if how == "nlerp":
        h = q0 + u * (q1 - q0)
        return h / np.linalg.norm(h, axis=1, keepdims=True)
    q0 = q0 / np.linalg.norm(q0, axis=1, keepdims=True)
    q1 = q1 / np.linalg.norm(q1, axis=1, keepdims=True)
    d = np.clip(np.sum(q0 * q1, axis=1, keepdims=True), -1, 1)
    th = np.arccos(d)
    small = th[:, 0] < 1e-9
    s = np.where(small[:, None], 1.0, np.sin(th))
    w0 = np.where(small[:, None], 1 - u, np.sin((1 - u) * th) / s)
    w1 = np.where(small[:, None], u, np.sin(u * th) / s)
    return w0 * q0 + w1 * q1


@pytest.mark.parametrize("how", ["slerp", "nlerp"])
@pytest.mark.parametrize("kind", ["pose", "c3"])
def test_export_linear_bound_holds_as_players_compute_it(tmp_path, how, kind):
    """Float32 keys and times as stored; slerp (three.js) and nlerp (Blender); 128 points
    between every two keys: the error never exceeds the bound, not even by 1e-4 relative
    (these motions exceeded it by 1.7e-4 and 6.9e-4 between the exporter's check points)."""
    if kind == "pose":
        m = wavy_pose(n=8, seed=5)
        rot, t0 = m.rotation, m.domain[0]
    else:
        m = rot = qs.C3Spline(random_walk(8, 5, step=0.8), np.arange(8.0))
        t0 = 0.0
    path = tmp_path / "m.glb"
    rep = to_gltf(m, path, max_error="0.01deg", uniform=False, progress=False)
    kind, kt, kv = load_channels(path)["rotation"]
    u = np.linspace(0, 1, 129)[:-1]
    t = np.concatenate([(kt[:-1, None] + np.diff(kt)[:, None] * u).ravel(), kt[-1:]])
    e = rotation_error(_play(kind, kt, kv, t, how), rot(t0 + t))
    assert e.max() <= rep.rotation_bound, e.max() / rep.rotation_bound - 1
    assert rep.rotation_error <= rep.rotation_bound


@pytest.mark.parametrize("samples", [MAX_SAMPLES + 1, 5_000_000, True, 1.5])
def test_export_refuses_samples_beyond_the_bounded_maximum(tmp_path, samples):
    s = qs.C3Spline(random_walk(4, 2, step=0.6), np.arange(4.0))
    with pytest.raises(ValueError, match=rf"^samples: expected an integer in \[2, {MAX_SAMPLES}\]"):
        to_gltf(s, tmp_path / "s.glb", samples=samples)
    assert not (tmp_path / "s.glb").exists()


def test_export_meets_a_bound_near_float32_resolution_with_more_keys(tmp_path):
    """1e-4° (1.7e-6 rad, a few float32 units) is met by adding keys; 3e-5° is not, and the
    refusal gives the best achievable error, just above the bound (not the candidates'): the
    float32 keys' roundoff plus the float32 clock's (speed × time × 2⁻²³ at the end of this
    3 s motion)."""
    pose = wavy_pose(n=5)
    path = tmp_path / "t.glb"
    rep = to_gltf(pose, path, max_error="1e-4deg", uniform=False, progress=False)
    kind, kt, kv = load_channels(path)["rotation"]
    t = np.linspace(kt[0], kt[-1], 100_001)
    e = rotation_error(_play(kind, kt, kv, t, "slerp"), pose.rotation(pose.domain[0] + t))
    assert e.max() <= rep.rotation_bound
    with pytest.raises(ValueError, match=r"^max_error: .*best achievable error") as err:
        to_gltf(pose, tmp_path / "u.glb", max_error="3e-5deg", uniform=False, progress=False)
    best = float(str(err.value).split("best achievable error ")[1].split("°")[0])
    assert 3e-5 < best < 1e-4


def _blender_linear(kt, kv, t, fps=24.0):
    """LINEAR playback as Blender computes it, in float32 throughout (written here from
    Blender's F-curve code, independently of the exporter): the importer stores key frames
    ``float32(time × fps)``, the scene frame is a float32, and the interpolation factor and
    the component-wise blend are float32 operations; the quaternion is normalised after."""
    f32 = np.float32
    kf = (kt.astype(np.float64) * fps).astype(f32)
    kv = kv.astype(f32)
    fr = (t * fps).astype(f32)
    k = np.clip(np.searchsorted(kf, fr, side="right") - 1, 0, len(kf) - 2)
    u = ((fr - kf[k]) / (kf[k + 1] - kf[k])).astype(f32)[:, None]
    h = (kv[k] + u * (kv[k + 1] - kv[k])).astype(f32).astype(np.float64)
    return h


def test_linear_keys_hold_the_bound_under_float32_playback_late_in_a_long_motion(tmp_path):
    """Ten minutes of fast rotation (about 1.6 rad/s): at t = 600 s one float32 unit of the
    clock is 6e-5 s, i.e. 1e-4 rad of motion — comparable to the bound, so the exporter must
    count the players' float32 clock and frame rounding, not only the keys'."""
    rng = np.random.default_rng(11)
    n = 601
    t = np.arange(n, dtype=float)
    rv = np.cumsum(rng.normal(0, 0.9, (n, 3)), axis=0)
    s = qs.spline("slerp", qs.from_rotvec(rv), t)  # piecewise slerp: keys at the joints
    path = tmp_path / "long.glb"
    rep = to_gltf(s, path, max_error="0.02deg", progress=False)
    kind, kt, kv = load_channels(path)["rotation"]
    assert kind == "LINEAR"
    at = np.sort(np.random.default_rng(12).uniform(kt[0], kt[-1], 400_000))
    h = _blender_linear(kt, kv, at)
    e = rotation_error(h / np.linalg.norm(h, axis=1)[:, None], s(at))
    assert e.max() <= rep.rotation_bound, (np.degrees(e.max()), np.degrees(rep.rotation_bound))
