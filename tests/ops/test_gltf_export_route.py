"""One export route: ``quatspline export`` translates its options and calls ``ops.export``, which
writes glTF through ``to_gltf`` (error-bounded keys) and the one glTF document writer of
``io.gltf``, and BVH from frames sampled by the one sampling route."""

from __future__ import annotations

import contextlib
import io as _io

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline import ops
from quatspline.cli import main
from quatspline.io import gltf

from ..splinekit import random_walk
from .test_gltf import load_channels, validate


def _recording(tmp_path, n=30, seed=3):
    rng = np.random.default_rng(seed)
    t = 100.0 + np.cumsum(np.r_[0.0, rng.uniform(0.05, 0.2, n - 1)])
    tr = qio.Trajectory(t, random_walk(n, seed, step=0.3), np.cumsum(rng.normal(size=(n, 3)), 0))
    src = tmp_path / "walk.csv"
    qio.write(src, tr)
    return src


#: (output name, CLI options, the same options for ops.export)
CASES = [
    ("a.glb", [], {}),
    (
        "b.gltf",
        ["--interpolation", "cubicspline", "--empty", "--node", "cam", "--max-error", "0.05deg",
         "--max-position-error", "1mm", "--method", "squad"],
        dict(interpolation="cubicspline", mesh=None, node="cam", max_error="0.05deg",
             max_position_error="1mm", method="squad"),
    ),
    ("c.glb", ["--method", "kochanek_bartels", "--param", "tension=0.2"],
     dict(method="kochanek_bartels", tension="0.2")),
    ("d.bvh", [], {}),
    ("e.bvh", ["--fps", "24", "--method", "natural"], dict(fps=24.0, method="natural")),
]  # fmt: skip


@pytest.mark.parametrize("name, cli, kwargs", CASES, ids=[c[0] for c in CASES])
def test_cli_export_and_ops_export_write_identical_files(tmp_path, name, cli, kwargs):
    """The command resampled BVH frames itself and passed glTF on to ``to_gltf``: two routes
    beside the library's. It now only translates options for ``ops.export``."""
    src = _recording(tmp_path)
    by_cli, by_lib = tmp_path / "cli" / name, tmp_path / "lib" / name
    by_cli.parent.mkdir()
    by_lib.parent.mkdir()
    out = _io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["export", str(src), "-o", str(by_cli), *cli]) == 0
    rep = ops.export(qio.read(src), by_lib, progress=False, **kwargs)
    assert by_cli.read_bytes() == by_lib.read_bytes()
    assert str(by_lib) in rep.summary()
    if name.endswith(".bvh"):
        assert out.getvalue() == f"wrote {rep.summary().replace(str(by_lib), str(by_cli))}\n"
        assert len(qio.read(by_lib)) == rep.frames
    else:
        assert out.getvalue() == rep.summary().replace(str(by_lib), str(by_cli)) + "\n"


def test_to_gltf_writes_through_the_io_document_writer(tmp_path):
    """``to_gltf`` built its own glTF document beside the format's writer; the keys it chose,
    given to ``io.gltf.write_animation``, give the very same file."""
    src = _recording(tmp_path)
    tr = qio.read(src)
    path = tmp_path / "m.glb"
    ops.to_gltf(tr, path, max_error="0.05deg", progress=False)
    ch = load_channels(path)  # an independent loader (pygltflib)
    (_, kt, kv), (_, pt, pv) = ch["rotation"], ch["translation"]
    again = tmp_path / "again.glb"
    gltf.write_animation(again, gltf.Keys(kt, kv[:, [3, 0, 1, 2]]), gltf.Keys(pt, pv), name=tr.name)
    assert again.read_bytes() == path.read_bytes()
    (v,) = validate(again)
    assert v["numErrors"] == 0, v["messages"]


def test_export_of_a_spline_to_bvh_samples_the_spline(tmp_path):
    q = random_walk(6, 1, step=0.5)
    s = qs.C3Spline(q, np.arange(6.0))
    rep = ops.export(s, tmp_path / "s.bvh", fps=10)
    back = qio.read(tmp_path / "s.bvh")
    assert rep.frames == len(back) == 51
    assert qs.angle_between(back.quats, s(np.arange(51) / 10)).max() < 1e-9
    x = np.arange(18.0).reshape(6, 3)
    pose = qs.PoseSpline(q, np.arange(6.0), x)
    ops.export(pose, tmp_path / "p.bvh", fps=4)
    np.testing.assert_allclose(qio.read(tmp_path / "p.bvh").positions[::4], x, atol=1e-12)
    with pytest.raises(TypeError, match=r"^method: a spline is exported as it is"):
        ops.export(s, tmp_path / "x.bvh", method="slerp")
    assert not (tmp_path / "x.bvh").exists()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(fps=0, path="x.bvh"), r"^fps: expected a frame rate in \(0, 10000\], got 0"),
        (dict(fps=np.nan, path="x.bvh"), r"^fps: expected a frame rate"),
        (
            dict(fps=10_000.0, path="long.bvh", span=1e9),
            r"^fps: 10000 fps over 1e\+09 s gives more",
        ),
        (dict(path="x.obj"), r"x\.obj: expected a \.glb, \.gltf or \.bvh output"),
        (dict(format="fbx"), r"^format: expected 'gltf' or 'bvh', got 'fbx'"),
        (dict(max_error="1parsec"), r"^max_error: cannot parse '1parsec'"),
        (dict(max_position_error=-1, path="x.bvh"), r"^max_position_error: expected a positive"),
    ],
)
def test_export_refuses_options_as_parameter_errors_before_writing(tmp_path, kwargs, match):
    """Bad options the command turned into usage errors itself (exit 2) are the library's
    ``ParameterError`` now, raised before any work; a frame rate giving more frames than the
    package's sample bound is refused instead of exhausting memory."""
    span = kwargs.pop("span", 2.0)
    path = tmp_path / kwargs.pop("path", "x.glb")
    tr = qio.Trajectory([0.0, span / 2, span], random_walk(3, 0, step=0.2))
    with pytest.raises(ops.ParameterError, match=match):
        ops.export(tr, path, progress=False, **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_export_arguments_of_the_wrong_kind_are_type_errors(tmp_path):
    tr = qio.Trajectory([0.0, 1.0], random_walk(2, 0, step=0.2))
    with pytest.raises(TypeError, match=r"^path: expected a file path, got NoneType"):
        ops.export(tr, None)
    with pytest.raises(TypeError, match=r"^fps: expected a number, got str"):
        ops.export(tr, tmp_path / "x.bvh", fps="24")
    with pytest.raises(TypeError, match=r"^joint: expected a string, got int"):
        ops.export(tr, tmp_path / "x.bvh", joint=5)
    assert list(tmp_path.iterdir()) == []


def test_cli_export_frame_rate_beyond_the_sample_bound_is_a_usage_error(tmp_path, capsys):
    src = tmp_path / "k.csv"
    qio.write(src, qio.Trajectory([0.0, 1e9], random_walk(2, 0, step=0.2)))
    out = tmp_path / "x.bvh"
    assert main(["export", str(src), "-o", str(out), "--fps", "100"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("quatspline: error: --fps: 100 fps over 1e+09 s gives more than")
    assert not out.exists()
