"""``io.write(…glb)``: the glTF writer stores a trajectory's own samples as LINEAR keys, exact at
every sample (float32), checked by the Khronos validator and an independent loader (pygltflib
and the specification's playback in tests/ops/test_gltf.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.io import gltf

from ..ops.test_gltf import load_channels, play, rotation_error, validate
from ..splinekit import random_walk

T0 = 1_305_031_102.0  # a Unix time as in TUM RGB-D


def _recording(n=50, seed=0, positions=True, t0=T0):
    rng = np.random.default_rng(seed)
    t = t0 + np.cumsum(np.r_[0.0, rng.uniform(0.02, 0.2, n - 1)])
    q = random_walk(n, seed, step=0.4)
    q[::3] *= -1  # both signs of a rotation, as recordings hold them
    p = rng.normal(size=(n, 3)) if positions else None
    return qio.Trajectory(t, q, p, name="walk")


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
@pytest.mark.parametrize("positions", [True, False])
def test_io_write_glb_writes_the_samples_exactly(tmp_path, suffix, positions):
    """``io.write(path.glb, trajectory)`` wrote an error-bounded export of a c3 spline through
    the samples (other keys, at other times); it writes the samples, like every writer."""
    tr = _recording(positions=positions)
    path = tmp_path / f"m{suffix}"
    qio.write(path, tr)
    (v,) = validate(path)
    assert v["numErrors"] == 0 and v["numWarnings"] == 0, v["messages"]
    ch = load_channels(path)
    kind, kt, kv = ch["rotation"]
    assert kind == "LINEAR"
    f32 = (tr.times - tr.times[0]).astype(np.float32).astype(float)
    np.testing.assert_array_equal(kt, f32)
    # every key is its sample (float32, either sign), consecutive keys in one hemisphere
    assert rotation_error(kv, tr.quats).max() < 1e-6
    assert np.all(np.sum(kv[1:] * kv[:-1], axis=1) >= 0)
    # the specification's playback at the sample times gives the samples
    assert rotation_error(play("LINEAR", kt, kv, kt, True), tr.quats).max() < 1e-6
    if positions:
        kind, pt, pv = ch["translation"]
        np.testing.assert_array_equal(pt, f32)
        np.testing.assert_array_equal(pv, tr.positions.astype(np.float32).astype(float))
    else:
        assert "translation" not in ch
    back = qio.read(path)
    assert len(back) == len(tr) and back.name == "body"
    np.testing.assert_array_equal(back.times, f32)
    assert rotation_error(back.quats[:, [1, 2, 3, 0]], tr.quats).max() < 1e-6


def test_io_write_gltf_of_one_sample_is_a_valid_file(tmp_path):
    tr = qio.Trajectory([5.0], [[0.0, 0.0, 1.0, 0.0]], [[1.0, 2.0, 3.0]])
    qio.write(tmp_path / "one.glb", tr)
    (v,) = validate(tmp_path / "one.glb")
    assert v["numErrors"] == 0, v["messages"]
    back = qio.read(tmp_path / "one.glb")
    assert back.times.tolist() == [0.0] and back.positions.tolist() == [[1.0, 2.0, 3.0]]


def test_io_write_passes_its_options_to_the_gltf_writer(tmp_path):
    """``io.write("m.gltf", traj, mesh=None, node=…)`` reaches the writer; the exporter's
    options (a bound, an interpolation) belong to ``ops.to_gltf`` and are refused by name."""
    tr = qio.Trajectory([0.0, 1.0, 2.0], random_walk(3, 1, step=0.3))
    qio.write(tmp_path / "w.gltf", tr, mesh=None, node="camera")
    doc = json.loads((tmp_path / "w.gltf").read_text())
    assert "meshes" not in doc and doc["nodes"][0]["name"] == "camera"
    back = qio.read(tmp_path / "w.gltf")
    assert back.times.tolist() == [0.0, 1.0, 2.0]
    for option in ("max_error", "interpolation", "method"):
        with pytest.raises(ValueError, match=rf"^{option}: unknown option for format gltf"):
            qio.write(tmp_path / "x.glb", tr, **{option: "linear"})
    with pytest.raises(ValueError, match=r"^mesh: expected 'axes' or None"):
        qio.write(tmp_path / "x.glb", tr, mesh="cube")
    assert not (tmp_path / "x.glb").exists()


def test_io_write_gltf_refuses_what_glb_cannot_hold_and_writes_nothing(tmp_path):
    """Extra columns (glTF has no place for them), times float32 cannot tell apart, positions
    beyond float32: one line naming the file, nothing written."""
    out = tmp_path / "m.glb"
    q = random_walk(3, 2, step=0.3)
    cases = [
        (qio.Trajectory([0.0, 1.0, 2.0], q, extra={"omega": np.zeros((3, 3))}),
         "the glTF format has no columns for omega"),
        (qio.Trajectory([0.0, 1000.0, 1000.00001], q),
         r"times 1000\.0 and 1000\.00001 \(keys 1 and 2\) are not increasing once stored as "
         "float32"),
        (qio.Trajectory(T0 + np.array([0.0, 600.0, 600.00001]), q), "not increasing once stored"),
        (qio.Trajectory([0.0, 1.0, 2.0], q, np.full((3, 3), 1e39)), "beyond float32 range"),
        (qio.Trajectory([-1e308, 0.0, 1e308], q), "is not a float32 time"),
    ]  # fmt: skip
    for tr, message in cases:
        with pytest.raises(ValueError, match=message) as e:
            qio.write(out, tr)
        assert str(e.value).startswith(f"{out}: ") and "\n" not in str(e.value)
    assert list(tmp_path.iterdir()) == []


def test_gltf_writer_refuses_keys_of_the_wrong_shape_or_kind(tmp_path):
    keys = gltf.Keys(np.arange(3.0), random_walk(3, 0))
    with pytest.raises(TypeError, match=r"^translation: expected gltf\.Keys"):
        gltf.write_animation(tmp_path / "a.glb", keys, np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"rotation keys: values of shape \(3, 3\)"):
        gltf.write_animation(tmp_path / "a.glb", gltf.Keys(np.arange(3.0), np.zeros((3, 3))))
    with pytest.raises(ValueError, match=r"CUBICSPLINE needs in_tangents"):
        gltf.write_animation(tmp_path / "a.glb", keys, interpolation="cubicspline")
    assert list(tmp_path.iterdir()) == []
