"""Damaged files of the new formats (glTF, GLB, ROS 1 bag, MCAP, KITTI): valid files with
random byte edits are read or refused with one ValueError naming the file — never another
exception or a warning (found this way: rosbags' AssertionError on a damaged chunk, a TypeError
from a glTF field set to null, numpy's cast warning on NaN keys)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio

pytest.importorskip("rosbags")
pytest.importorskip("pygltflib")

EDITS = 120


@pytest.fixture(scope="module")
def sources(tmp_path_factory):
    d = tmp_path_factory.mktemp("src")
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 2, 5))
    tr = qio.Trajectory(np.arange(5.0) + 1, q, np.eye(5)[:, :3])
    from quatspline.ops._export import to_gltf

    to_gltf(tr, d / "m.glb", max_error=1, progress=False, method="c3")  # ≥ 5 keys
    to_gltf(tr, d / "m.gltf", max_error=1, progress=False, method="c3")
    qio.write(d / "m.bag", tr, format="rosbag")
    qio.write(d / "m.mcap", tr, format="rosbag")
    qio.write(d / "k.txt", qio.Trajectory(np.arange(5.0), q, np.eye(5)[:, :3]), format="kitti")
    return d


@pytest.mark.parametrize("name", ["m.glb", "m.gltf", "m.bag", "m.mcap", "k.txt"])
def test_damaged_files_are_read_or_refused_naming_the_file(sources, tmp_path, name):
    src = (sources / name).read_bytes()
    assert len(qio.read(sources / name)) >= 5  # the export may add keys
    rng = np.random.default_rng(sum(map(ord, name)))
    path = tmp_path / ("x" + (sources / name).suffix)
    refused = 0
    for _ in range(EDITS):
        b = bytearray(src)
        for _ in range(int(rng.integers(1, 6))):
            k = int(rng.integers(len(b)))
            op = rng.integers(3)
            if op == 0:
                b[k] = int(rng.integers(256))
            elif op == 1:
                del b[k : k + int(rng.integers(1, 16))]
            else:
                b[k:k] = bytes(rng.integers(0, 256, int(rng.integers(1, 8))).astype(np.uint8))
        path.write_bytes(bytes(b))
        try:
            tr = qio.read(path)
        except ValueError as e:
            assert str(path) in str(e), e
            refused += 1
            continue
        assert np.all(np.isfinite(tr.times)) and np.all(np.diff(tr.times) > 0)
        assert np.allclose(np.linalg.norm(tr.quats, axis=1), 1.0)
    assert refused > 0  # the edits do reach the parsers
