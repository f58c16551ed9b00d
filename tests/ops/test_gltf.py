"""glTF 2.0 export with an error bound: the Khronos validator, an independent loader
(pygltflib + scipy's Slerp / the specification's Hermite written here) measuring playback error
on a grid the exporter never saw, key counts, round trips, cross-reads and bad input."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline._util.options import DEFAULT_METHOD
from quatspline.ops._export import parse_angle, parse_length, to_gltf

from ..splinekit import random_walk

pygltflib = pytest.importorskip("pygltflib", reason="test extra: pip install pygltflib")
from scipy.spatial.transform import Rotation, Slerp  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
TUM = ROOT / "data" / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
VALIDATOR = ROOT / "tests" / "tools" / "validate_gltf.js"
NODE_MODULES = ROOT / ".npm" / "node_modules"


def validate(*files) -> list[dict]:
    """The Khronos glTF validator's reports (make test installs it into .npm/)."""
    if not (NODE_MODULES / "gltf-validator").is_dir() or shutil.which("node") is None:
        pytest.fail("the glTF validator is missing: run `make test` (npm install --prefix .npm)")
    env = {**os.environ, "NODE_PATH": str(NODE_MODULES)}
    out = subprocess.run(
        ["node", str(VALIDATOR), *map(str, files)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=True,
    )
    return json.loads(out.stdout)


# ---- an independent loader: pygltflib for the file, numpy for the bytes ---------------------
def load_channels(path) -> dict:
    g = pygltflib.GLTF2().load(str(path))
    blob = g.binary_blob()
    if blob is None:
        blob = g.get_data_from_buffer_uri(g.buffers[0].uri)

    def acc(k):
        a = g.accessors[k]
        v = g.bufferViews[a.bufferView]
        assert a.componentType == pygltflib.FLOAT
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[a.type]
        start = (v.byteOffset or 0) + (a.byteOffset or 0)
        arr = np.frombuffer(blob, dtype="<f4", count=a.count * width, offset=start)
        return arr.reshape(a.count, width).astype(float)

    (anim,) = g.animations
    out = {}
    for ch in anim.channels:
        s = anim.samplers[ch.sampler]
        out[ch.target.path] = (s.interpolation, acc(s.input)[:, 0], acc(s.output))
        assert g.nodes[ch.target.node].name == "body"
    return out


def play(kind, kt, kv, t, rot):
    """Playback per the glTF 2.0 specification (Appendix C), written independently of the
    exporter: scipy's Slerp for LINEAR rotations, the Hermite formula for CUBICSPLINE."""
    if kind == "LINEAR":
        if rot:
            return Slerp(kt, Rotation.from_quat(kv))(t).as_quat()  # (x, y, z, w)
        return np.column_stack([np.interp(t, kt, kv[:, i]) for i in range(kv.shape[1])])
    assert kind == "CUBICSPLINE"
    a, v, b = kv[0::3], kv[1::3], kv[2::3]
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 2)
    td = (kt[k + 1] - kt[k])[:, None]
    s = ((t - kt[k]) / (kt[k + 1] - kt[k]))[:, None]
    p = (
        (2 * s**3 - 3 * s**2 + 1) * v[k]
        + td * (s**3 - 2 * s**2 + s) * b[k]
        + (-2 * s**3 + 3 * s**2) * v[k + 1]
        + td * (s**3 - s**2) * a[k + 1]
    )
    return p / np.linalg.norm(p, axis=1, keepdims=True) if rot else p


def rotation_error(q_xyzw, q_wxyz):
    """Angles (rad) by scipy: |(r1⁻¹ r2)|."""
    r1 = Rotation.from_quat(q_xyzw)
    r2 = Rotation.from_quat(q_wxyz[:, [1, 2, 3, 0]])
    return (r1.inv() * r2).magnitude()


def measured_errors(path, motion, t0, n=40_000, seed=1):
    ch = load_channels(path)
    kind, kt, kv = ch["rotation"]
    rng = np.random.default_rng(seed)
    t = np.sort(np.concatenate([rng.uniform(kt[0], kt[-1], n), kt]))
    rot = motion.rotation if isinstance(motion, qs.PoseSpline) else motion
    e_rot = rotation_error(play(kind, kt, kv, t, True), rot(t0 + t))
    e_pos = None
    if "translation" in ch:
        kind, pt, pv = ch["translation"]
        e_pos = np.linalg.norm(play(kind, pt, pv, t, False) - motion.position(t0 + t), axis=1)
    return e_rot, e_pos, ch


def wavy_pose(n=12, seed=0):
    q = random_walk(n, seed, step=0.5)
    t = np.cumsum(np.r_[0.0, np.random.default_rng(seed).uniform(0.5, 1.5, n - 1)])
    p = np.random.default_rng(seed + 1).normal(size=(n, 3))
    return qs.PoseSpline(q, t, p, rotation="c3")


@pytest.mark.parametrize("interpolation", ["linear", "cubicspline"])
@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_export_passes_validator_and_playback_within_bound(tmp_path, interpolation, suffix):
    pose = wavy_pose()
    path = tmp_path / f"m{suffix}"
    rep = to_gltf(pose, path, max_error="0.02deg", max_position_error="0.5mm",
                  interpolation=interpolation)  # fmt: skip
    (v,) = validate(path)
    assert v["numErrors"] == 0, v["messages"]
    assert v["numWarnings"] == 0, v["messages"]
    assert v["animations"] == 1
    e_rot, e_pos, ch = measured_errors(path, pose, pose.domain[0])
    assert ch["rotation"][0] == interpolation.upper()
    # the bound holds on 40 000 random times the exporter never checked
    assert e_rot.max() <= parse_angle("0.02deg") * (1 + 1e-3), np.degrees(e_rot.max())
    assert e_pos.max() <= 0.5e-3 * (1 + 1e-3), e_pos.max()
    # and the bound is used, not wasted: the error reaches at least a third of it
    assert e_rot.max() > parse_angle("0.02deg") / 3
    assert rep.rotation_keys == len(ch["rotation"][1])
    assert rep.translation_keys == len(ch["translation"][1])
    # adaptive keys beat a uniform resampling at the same bound
    assert 0 < rep.rotation_keys < rep.rotation_uniform_keys
    # (-1: a uniform resampling needs more than 8× the adaptive keys: cubic Hermite keys at
    # the position spline's joints reproduce it exactly, uniform keys miss the joints)
    assert 0 < rep.translation_keys
    assert rep.translation_uniform_keys == -1 or rep.translation_keys < rep.translation_uniform_keys
    if interpolation == "linear":
        assert rep.translation_keys < rep.translation_uniform_keys


def test_real_recording_export(tmp_path):
    traj = qio.read(TUM)
    traj = qio.Trajectory(traj.times[:400], traj.quats[:400], traj.positions[:400])
    path = tmp_path / "fr1.glb"
    rep = to_gltf(traj, path, max_error="0.05deg", max_position_error="1mm")
    (v,) = validate(path)
    assert v["numErrors"] == 0, v["messages"]
    ps = qs.PoseSpline(
        traj.quats, traj.times, traj.positions, rotation=DEFAULT_METHOD
    )  # the export default
    e_rot, e_pos, _ = measured_errors(path, ps, traj.times[0])
    assert e_rot.max() <= rep.rotation_bound * (1 + 1e-3)
    assert e_pos.max() <= rep.translation_bound * (1 + 1e-3)
    assert rep.rotation_keys < rep.rotation_uniform_keys


def test_cubicspline_needs_fewer_keys_than_linear(tmp_path):
    s = qs.C3Spline(random_walk(10, 3, step=0.6), np.arange(10.0))
    lin = to_gltf(s, tmp_path / "l.glb", max_error=0.01)
    cub = to_gltf(s, tmp_path / "c.glb", max_error=0.01, interpolation="cubicspline")
    assert cub.rotation_keys < lin.rotation_keys / 2
    assert cub.rotation_error <= cub.rotation_bound


def test_slerp_spline_exports_with_joint_keys(tmp_path):
    """A C⁰ spline: every joint is a LINEAR key (slerp reproduces the spline between joints;
    the keys between them are for players that interpolate component-wise, as Blender does)."""
    q = random_walk(6, 4, step=0.7)
    s = qs.PiecewiseSlerp(q, np.arange(6.0))
    rep = to_gltf(s, tmp_path / "s.glb", max_error="0.001deg")
    e_rot, _, ch = measured_errors(tmp_path / "s.glb", s, 0.0)
    assert set(np.arange(6.0)) <= set(ch["rotation"][1])
    assert rep.rotation_keys == len(ch["rotation"][1])
    assert e_rot.max() <= rep.rotation_bound


def test_round_trip_through_reader(tmp_path):
    pose = wavy_pose(seed=5)
    for interp in ("linear", "cubicspline"):
        path = tmp_path / f"{interp}.glb"
        to_gltf(pose, path, max_error="0.05deg", interpolation=interp, node="body")
        tr = qio.read(path)
        assert tr.name == "body"
        t0 = pose.domain[0]
        # translation keys are not at the rotation's times: the reader plays them back there
        err = rotation_error(tr.quats[:, [1, 2, 3, 0]], pose.rotation(t0 + tr.times))
        assert err.max() < 1e-6
        assert np.abs(tr.positions - pose.position(t0 + tr.times)).max() < 1e-3


def test_reads_a_file_written_by_pygltflib(tmp_path):
    """Cross-read: a file made with pygltflib's own writer, STEP translation, two nodes."""
    g = pygltflib
    kt = np.array([0.0, 0.5, 1.0, 2.0], dtype=np.float32)
    r = Rotation.from_rotvec(np.outer([0.2, 0.5, 1.2, 2.0], [0, 0, 1]))
    kq = r.as_quat().astype(np.float32)
    pt = np.array([0.0, 2.0], dtype=np.float32)
    pv = np.array([[0, 0, 0], [1, 2, 3]], dtype=np.float32)
    blob = kt.tobytes() + kq.tobytes() + pt.tobytes() + pv.tobytes()
    offs = np.cumsum([0, kt.nbytes, kq.nbytes, pt.nbytes])
    views = [
        g.BufferView(buffer=0, byteOffset=int(o), byteLength=int(a.nbytes))
        for o, a in zip(offs, (kt, kq, pt, pv))
    ]
    F = g.FLOAT
    accs = [
        g.Accessor(bufferView=0, componentType=F, count=4, type=g.SCALAR, min=[0.0], max=[2.0]),
        g.Accessor(bufferView=1, componentType=g.FLOAT, count=4, type=g.VEC4),
        g.Accessor(bufferView=2, componentType=F, count=2, type=g.SCALAR, min=[0.0], max=[2.0]),
        g.Accessor(bufferView=3, componentType=g.FLOAT, count=2, type=g.VEC3),
    ]  # fmt: skip
    tgt = g.AnimationChannelTarget
    anim = g.Animation(
        samplers=[
            g.AnimationSampler(input=0, output=1, interpolation="LINEAR"),
            g.AnimationSampler(input=2, output=3, interpolation="STEP"),
        ],
        channels=[
            g.AnimationChannel(sampler=0, target=tgt(node=1, path="rotation")),
            g.AnimationChannel(sampler=1, target=tgt(node=1, path="translation")),
        ],
    )  # fmt: skip
    gl = g.GLTF2(
        scene=0,
        scenes=[g.Scene(nodes=[0])],
        nodes=[g.Node(name="root", children=[1]), g.Node(name="arm")],
        buffers=[g.Buffer(byteLength=len(blob))],
        bufferViews=views,
        accessors=accs,
        animations=[anim],
    )
    gl.set_binary_blob(blob)
    path = tmp_path / "py.glb"
    gl.save_binary(str(path))
    assert validate(path)[0]["numErrors"] == 0
    tr = qio.read(path)
    assert tr.name == "arm"
    np.testing.assert_allclose(tr.times, kt)
    np.testing.assert_allclose(np.abs(tr.quats[:, 3]), np.abs(kq[:, 2]), atol=1e-7)
    # STEP: the first value until the last key time, then the second
    np.testing.assert_allclose(tr.positions, [[0, 0, 0]] * 3 + [[1, 2, 3]])
    assert qio.read(path, node="arm").name == "arm"
    with pytest.raises(ValueError, match=r"no node 'leg'; animated nodes: arm"):
        qio.read(path, node="leg")
    with pytest.raises(ValueError, match=r"node 'root' has no rotation or translation"):
        qio.read(path, node="root")


def test_without_animation_or_node(tmp_path):
    g = pygltflib
    gl = g.GLTF2(scene=0, scenes=[g.Scene(nodes=[0])], nodes=[g.Node(name="a")])
    path = tmp_path / "still.gltf"
    gl.save(str(path))
    with pytest.raises(ValueError, match=r"still.gltf: no animations in this file"):
        qio.read(path)
    bad = tmp_path / "bad.glb"
    bad.write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(ValueError, match=r"bad.glb: not a readable glTF/GLB file"):
        qio.read(bad)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"max_error": 0}, r"max_error: expected a positive finite bound"),
        ({"max_error": "-1deg"}, r"max_error: expected a positive finite bound"),
        ({"max_error": "0.01 furlongs"}, r"max_error: cannot parse '0.01 furlongs'"),
        ({"max_error": "deg"}, r"max_error: cannot parse 'deg'"),
        ({"max_error": float("nan")}, r"max_error: expected a positive finite bound"),
        ({"max_position_error": "1 deg"}, r"max_position_error: cannot parse '1 deg'"),
        ({"interpolation": "step"}, r"interpolation: expected 'linear' or 'cubicspline'"),
        ({"mesh": "teapot"}, r"mesh: expected 'axes' or None"),
        ({"samples": 1}, r"samples: expected an integer"),
    ],
)
def test_bad_arguments(tmp_path, kwargs, match):
    s = qs.C3Spline(random_walk(4, 0), np.arange(4.0))
    with pytest.raises(ValueError, match=match):
        to_gltf(s, tmp_path / "x.glb", **kwargs)
    assert not (tmp_path / "x.glb").exists()


def test_bad_kinds(tmp_path):
    with pytest.raises(TypeError, match="motion: expected a quatspline Spline"):
        to_gltf(np.zeros((3, 4)), tmp_path / "x.glb")
    with pytest.raises(TypeError, match="max_error: expected a number or a string"):
        to_gltf(qs.C3Spline(random_walk(4, 0)), tmp_path / "x.glb", max_error=[1])
    with pytest.raises(ValueError, match=r"x.obj: expected a .glb or .gltf output"):
        to_gltf(qs.C3Spline(random_walk(4, 0)), tmp_path / "x.obj")


def test_units():
    assert parse_angle("1deg") == pytest.approx(np.pi / 180)
    assert parse_angle("60arcmin") == pytest.approx(np.pi / 180)
    assert parse_angle("1e-3rad") == 1e-3
    assert parse_angle("0.5°") == pytest.approx(np.pi / 360)
    assert parse_length("2cm") == pytest.approx(0.02)
    assert parse_length(".5mm") == pytest.approx(5e-4)
