"""glTF files from ``quatspline export`` imported by Blender's own glTF importer and played
by Blender's F-curve evaluation at random frames, in each Blender of
:data:`blender_run.BLENDERS` (Debian's 3.4, the official 4.2 module): LINEAR keys hold the
bound there (float32 frames and values, no slack); CUBICSPLINE keys do not, because both
importers drop the tangents and set automatic Bézier handles (what the export report and
docs/export.md say)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.examples import load_recording
from quatspline.ops import to_gltf

from ..ops.test_gltf_export_defaults import noisy_recording
from .blender_run import BLENDERS, run

FPS = 24
#: Blender's version per runner, and the handles its importer gives CUBICSPLINE keys.
VERSION = {"blender": (3, 4), "bpy": (4, 2)}
AUTO_HANDLES = {"blender": ["AUTO_CLAMPED"], "bpy": ["AUTO"]}


@pytest.fixture(params=list(BLENDERS))
def which(request):
    return request.param


def _blender_play(tmp_path, which, path, span, n=20000, seed=0):
    """Blender's playback of the file at n random frames: (times from 0, quats, positions)
    in glTF's axes (Blender imports Y-up as Z-up: x, −z, y), and the raw output."""
    frames = np.sort(np.random.default_rng(seed).uniform(0, span * FPS, n))
    np.save(tmp_path / "frames.npy", frames)
    out = tmp_path / "out.npz"
    run(tmp_path, "blender_gltf_eval.py", path, tmp_path / "frames.npy", out, which=which)
    with np.load(out) as o:
        raw = {k: o[k] for k in o.files}
    assert int(raw["fps"]) == FPS
    assert tuple(raw["blender"][:2]) == VERSION[which], raw["blender"]
    bq, bl = raw["rotation"], raw["location"]
    q = np.column_stack([bq[:, 0], bq[:, 1], bq[:, 3], -bq[:, 2]])
    q /= np.linalg.norm(q, axis=1)[:, None]
    p = np.column_stack([bl[:, 0], bl[:, 2], -bl[:, 1]])
    return frames / FPS, q, p, raw


def _pose(n=900):
    tr = load_recording()
    return qs.PoseSpline(tr.quats[:n], tr.times[:n], tr.positions[:n], rotation="c3")


@pytest.mark.parametrize(("rot", "pos"), [("0.01deg", "0.1mm"), ("0.1deg", "1mm")])
def test_linear_export_plays_within_the_bound_in_blenders_importer(tmp_path, which, rot, pos):
    pose = _pose()
    path = tmp_path / "m.glb"
    rep = to_gltf(pose, path, max_error=rot, max_position_error=pos, progress=False)
    t0, t1 = pose.domain
    t, q, p, raw = _blender_play(tmp_path, which, path, t1 - t0)
    assert raw["interpolation"].tolist() == ["LINEAR"]
    e = qs.angle_between(q, pose.orientation(t0 + t))
    ep = np.linalg.norm(p - pose.position(t0 + t), axis=1)
    assert e.max() <= rep.rotation_bound, (np.degrees(e.max()), np.degrees(rep.rotation_bound))
    assert ep.max() <= rep.translation_bound, (ep.max(), rep.translation_bound)
    assert e.max() > rep.rotation_bound / 3  # measured where the bound is in use


def test_cubicspline_tangents_are_dropped_by_blenders_importer(tmp_path, which):
    """The statement of the report: Blender's importer (3.4 and 4.2) keeps the key values,
    ignores the file's tangents and sets automatic Bézier handles, so the file's bound (held
    by three.js, tests/ops/test_gltf.py) is exceeded in Blender."""
    pose = _pose()
    path = tmp_path / "c.glb"
    rep = to_gltf(pose, path, max_error="0.1deg", max_position_error="1mm",
                  interpolation="cubicspline", progress=False)  # fmt: skip
    assert "Blender's glTF importer (3.4 and 4.2, checked) drops them" in rep.summary()
    t0, t1 = pose.domain
    t, q, p, raw = _blender_play(tmp_path, which, path, t1 - t0)
    assert raw["interpolation"].tolist() == ["BEZIER"]
    assert raw["handle_types"].tolist() == AUTO_HANDLES[which]
    # the handles the file's tangents would give (a cubic Hermite piece is the Bézier with
    # handles a third of the interval away along the tangent; the tangents are the spline's
    # velocity), on the location x curve (glTF's x is Blender's x)
    h = raw["handles"]  # frame, value, left frame, left value, right frame, right value
    tk = h[:, 0] / FPS
    assert np.max(np.abs(h[:, 1] - pose.position(t0 + tk)[:, 0])) < 1e-6  # the key values
    dt = np.diff(tk)
    np.testing.assert_allclose(h[:-1, 4], h[:-1, 0] + dt * FPS / 3, atol=1e-3)
    hermite = h[:-1, 1] + pose.linear_velocity(t0 + tk[:-1])[:, 0] * dt / 3
    assert np.max(np.abs(h[:-1, 5] - hermite)) > 1e-3  # not the tangents' handles
    e = qs.angle_between(q, pose.orientation(t0 + t))
    ep = np.linalg.norm(p - pose.position(t0 + t), axis=1)
    assert e.max() > rep.rotation_bound and ep.max() > rep.translation_bound, (
        np.degrees(e.max()), ep.max())  # fmt: skip


@pytest.mark.parametrize("method", [None, "fit"])
def test_default_export_of_a_noisy_recording_plays_within_its_reported_bound(
    tmp_path, which, method
):
    """The defaults: no more keys than samples (the bound relaxed and reported) or, with
    ``method="fit"``, the smoothed motion at the asked bound — as Blender plays the file."""
    tr = noisy_recording(n=800)
    path = tmp_path / "n.glb"
    rep = to_gltf(tr, path, method=method, progress=False)
    assert rep.rotation_keys <= len(tr) and rep.translation_keys <= len(tr)
    if method == "fit":
        motion = qs.fit(tr.times, tr.quats, positions=tr.positions)
    else:
        motion = qs.PoseSpline(tr.quats, tr.times, tr.positions, rotation="natural")
    t0 = tr.times[0]
    t, q, p, _ = _blender_play(tmp_path, which, path, tr.times[-1] - t0)
    e = qs.angle_between(q, motion.rotation(t0 + t))
    ep = np.linalg.norm(p - motion.position(t0 + t), axis=1)
    assert e.max() <= rep.rotation_bound and ep.max() <= rep.translation_bound, (
        np.degrees(e.max()), ep.max(), rep.summary())  # fmt: skip
