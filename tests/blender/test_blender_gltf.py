"""glTF files from ``quatspline export`` imported by Blender's own glTF importer and played
by Blender's F-curve evaluation at random frames: LINEAR keys hold the bound there (float32
frames and values, no slack); CUBICSPLINE keys do not, because the importer drops the
tangents (what the export report and docs/export.md say)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.examples import load_recording
from quatspline.ops import to_gltf

from ..ops.test_gltf_export_defaults import noisy_recording
from .blender_run import needs_blender, run

pytestmark = needs_blender


def _blender_play(tmp_path, path, span, n=20000, seed=0):
    """Blender's playback of the file at n random frames: (times from 0, quats, positions)
    in glTF's axes (Blender imports Y-up as Z-up: x, −z, y)."""
    fps = 24
    frames = np.sort(np.random.default_rng(seed).uniform(0, span * fps, n))
    np.save(tmp_path / "frames.npy", frames)
    run(tmp_path, "blender_gltf_eval.py", path, tmp_path / "frames.npy", tmp_path / "out.npz")
    with np.load(tmp_path / "out.npz") as o:
        assert int(o["fps"]) == fps
        bq, bl = o["rotation"], o["location"]
    q = np.column_stack([bq[:, 0], bq[:, 1], bq[:, 3], -bq[:, 2]])
    q /= np.linalg.norm(q, axis=1)[:, None]
    p = np.column_stack([bl[:, 0], bl[:, 2], -bl[:, 1]])
    return frames / fps, q, p


def _pose(n=900):
    tr = load_recording()
    return qs.PoseSpline(tr.quats[:n], tr.times[:n], tr.positions[:n], rotation="c3")


@pytest.mark.parametrize(("rot", "pos"), [("0.01deg", "0.1mm"), ("0.1deg", "1mm")])
def test_linear_export_plays_within_the_bound_in_blenders_importer(tmp_path, rot, pos):
    pose = _pose()
    path = tmp_path / "m.glb"
    rep = to_gltf(pose, path, max_error=rot, max_position_error=pos, progress=False)
    t0, t1 = pose.domain
    t, q, p = _blender_play(tmp_path, path, t1 - t0)
    e = qs.angle_between(q, pose.orientation(t0 + t))
    ep = np.linalg.norm(p - pose.position(t0 + t), axis=1)
    assert e.max() <= rep.rotation_bound, (np.degrees(e.max()), np.degrees(rep.rotation_bound))
    assert ep.max() <= rep.translation_bound, (ep.max(), rep.translation_bound)
    assert e.max() > rep.rotation_bound / 3  # measured where the bound is in use


def test_cubicspline_tangents_are_dropped_by_blenders_importer(tmp_path):
    """The statement of the report: Blender rebuilds automatic handles, and the file's
    bound (held by three.js, tests/ops/test_gltf.py) is exceeded in Blender."""
    pose = _pose()
    path = tmp_path / "c.glb"
    rep = to_gltf(pose, path, max_error="0.1deg", max_position_error="1mm",
                  interpolation="cubicspline", progress=False)  # fmt: skip
    assert "Blender's glTF importer (3.4, checked) drops them" in rep.summary()
    t0, t1 = pose.domain
    t, q, _ = _blender_play(tmp_path, path, t1 - t0)
    assert qs.angle_between(q, pose.orientation(t0 + t)).max() > rep.rotation_bound


@pytest.mark.parametrize("method", [None, "fit"])
def test_default_export_of_a_noisy_recording_plays_within_its_reported_bound(tmp_path, method):
    """The defaults: no more keys than samples (the bound relaxed and reported) or, with
    ``method="fit"``, the smoothed motion at the asked bound — as Blender plays the file."""
    tr = noisy_recording(n=800)
    path = tmp_path / "n.glb"
    rep = to_gltf(tr, path, method=method, progress=False)
    assert rep.rotation_keys <= len(tr) and rep.translation_keys <= len(tr)
    if method == "fit":
        motion = qs.fit(tr.times, tr.quats, positions=tr.positions)
        rot = motion.rotation
    else:
        motion = qs.PoseSpline(tr.quats, tr.times, tr.positions, rotation="natural")
        rot = motion.rotation
    t0 = tr.times[0]
    t, q, p = _blender_play(tmp_path, path, tr.times[-1] - t0)
    e = qs.angle_between(q, rot(t0 + t))
    ep = np.linalg.norm(p - motion.position(t0 + t), axis=1)
    assert e.max() <= rep.rotation_bound and ep.max() <= rep.translation_bound, (
        np.degrees(e.max()), ep.max(), rep.summary())  # fmt: skip
