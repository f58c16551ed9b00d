"""Export defaults that fit recordings: a noisy recording never exports to more keys than it
has samples (the bound is relaxed and the report says so, unless ``max_keys`` asks
otherwise), ``method="fit"`` smooths rotation and translation, and the files still pass the
Khronos validator and play within the bound the report states."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
import quatspline.ops._export as ex
from quatspline.ops import export, to_gltf

from .test_gltf import measured_errors, validate


def noisy_recording(n=1500, rate=100.0, noise=1e-3, seed=0):
    """A dense recording: smooth motion plus white noise (σ = ``noise`` rad and m)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    rv = np.column_stack([np.sin(0.5 * t), np.cos(0.3 * t), 0.2 * t])
    p = np.column_stack([np.sin(t), np.cos(0.7 * t), 0.1 * t])
    q = qs.from_rotvec(rv + rng.normal(0, noise, rv.shape))
    return qio.Trajectory(t, q, p + rng.normal(0, noise, p.shape), name="noisy")


def test_a_noisy_recording_exports_to_no_more_keys_than_samples_by_default(tmp_path):
    tr = noisy_recording()
    path = tmp_path / "n.glb"
    rep = export(tr, path, progress=False)
    assert rep.rotation_keys <= len(tr) and rep.translation_keys <= len(tr)
    # the asked bounds cannot be met with that many keys: relaxed, and said so
    assert rep.rotation_requested == pytest.approx(np.radians(0.01))
    assert rep.rotation_bound > rep.rotation_requested
    assert rep.translation_bound > rep.translation_requested == pytest.approx(1e-4)
    assert "bound relaxed from 0.01° to keep at most 1500 keys" in rep.summary()
    assert "method='fit'" in rep.summary()
    # smaller than the samples themselves as float32 (8 numbers a sample)
    assert path.stat().st_size < len(tr) * 8 * 4
    (v,) = validate(path)
    assert v["numErrors"] == 0 and v["numWarnings"] == 0, v["messages"]
    pose = qs.PoseSpline(tr.quats, tr.times, tr.positions, rotation="natural")
    e_rot, e_pos, _ = measured_errors(path, pose, tr.times[0])
    assert e_rot.max() <= rep.rotation_bound and e_pos.max() <= rep.translation_bound


def test_max_keys_none_asks_for_the_bound_whatever_the_key_count(tmp_path):
    tr = noisy_recording(n=600)
    rep = to_gltf(tr, tmp_path / "a.glb", max_keys=None, progress=False)
    assert rep.rotation_bound == rep.rotation_requested
    assert rep.rotation_keys > len(tr)  # the interpolant wiggles between noisy samples


@pytest.mark.parametrize(("interpolation", "cap"), [("linear", 100), ("cubicspline", 40)])
@pytest.mark.parametrize("n", [600, 4000])  # the cap's probe starts at 512 keys
def test_a_key_cap_is_kept_and_the_file_holds_the_bound_it_reports(tmp_path, interpolation, cap, n):
    tr = noisy_recording(n=n)
    cap = cap if n < 4000 else 600
    path = tmp_path / "c.glb"
    rep = to_gltf(tr, path, max_keys=cap, interpolation=interpolation, progress=False)
    assert rep.rotation_keys <= cap and rep.translation_keys <= cap
    assert rep.rotation_bound > rep.rotation_requested
    pose = qs.PoseSpline(tr.quats, tr.times, tr.positions, rotation="natural")
    e_rot, e_pos, ch = measured_errors(path, pose, tr.times[0])
    assert ch["rotation"][0] == interpolation.upper()
    assert e_rot.max() <= rep.rotation_bound and e_pos.max() <= rep.translation_bound


def test_fit_smooths_translation_too(tmp_path):
    tr = noisy_recording()
    path = tmp_path / "f.glb"
    rep = export(tr, path, method="fit", progress=False)
    # both channels at the asked bound, with far fewer keys than samples
    assert rep.rotation_bound == rep.rotation_requested
    assert rep.translation_bound == rep.translation_requested
    assert rep.rotation_keys < len(tr) / 2 and rep.translation_keys < len(tr) / 2
    fitted = qs.fit(tr.times, tr.quats, positions=tr.positions)
    e_rot, e_pos, _ = measured_errors(path, fitted, tr.times[0])
    assert e_rot.max() <= rep.rotation_bound and e_pos.max() <= rep.translation_bound
    # the played positions are the smoothed ones: closer to the noiseless path than σ
    tt = np.linspace(tr.times[0], tr.times[-1], 2000)
    truth = np.column_stack([np.sin(tt), np.cos(0.7 * tt), 0.1 * tt])
    assert np.sqrt(np.mean(np.sum((fitted.position(tt) - truth) ** 2, axis=1))) < 1e-3


@pytest.mark.parametrize(
    ("value", "exc", "match"),
    [
        (1, ValueError, r"^max_keys: expected an integer ≥ 2, got 1$"),
        ("all", ValueError, r"^max_keys: expected 'samples', None or an integer ≥ 2"),
        (2.5, TypeError, r"^max_keys: expected an integer, 'samples' or None, got float$"),
    ],
)
def test_bad_max_keys(tmp_path, value, exc, match):
    with pytest.raises(exc, match=match):
        to_gltf(noisy_recording(n=20), tmp_path / "x.glb", max_keys=value, progress=False)


def test_uniform_count_only_on_request(tmp_path):
    s = qs.C3Spline(qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6)), np.arange(6.0))
    rep = to_gltf(s, tmp_path / "u.glb", max_error="0.1deg", progress=False)
    assert rep.rotation_uniform_keys == 0 and "uniform needs" not in rep.summary()
    rep = to_gltf(s, tmp_path / "v.glb", max_error="0.1deg", uniform=True, progress=False)
    assert f"(uniform needs {rep.rotation_uniform_keys})" in rep.summary()


def test_a_long_export_reports_progress_as_the_keys_advance(tmp_path, monkeypatch):
    """The bar advances with the share of the span keyed, not once per channel."""
    made = []

    class Bar:
        def __init__(self, total):
            self.total, self.steps = total, []

        def update(self, n=1):
            self.steps.append(n)

    @contextlib.contextmanager
    def fake(total=None, desc="", enabled=True, **kw):
        made.append(Bar(total))
        yield made[-1]

    monkeypatch.setattr(ex, "bar", fake)
    tr = noisy_recording(n=1500)
    to_gltf(tr, tmp_path / "p.glb", max_keys=None, progress=True)
    (b,) = made
    assert all(s > 0 for s in b.steps) and sum(b.steps) == b.total
    assert len(b.steps) >= 10  # thousands of keys: many steps per channel
