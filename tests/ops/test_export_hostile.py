"""``to_gltf`` and ``to_bvh`` with hostile parameters: every option of the wrong kind is a
TypeError and every bad value a ValueError, each naming the option, and nothing a player or a
validator would reject (non-finite numbers, invalid Unicode) is ever written."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline.cli import main
from quatspline.ops._export import to_bvh, to_gltf


def _spline():
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    return qs.C3Spline(q, np.arange(6.0))


def _json_chunk(path) -> str:
    blob = path.read_bytes()
    n = struct.unpack("<I", blob[12:16])[0]
    return blob[20 : 20 + n].decode("ascii")


@pytest.mark.parametrize(
    ("size", "error"),
    [
        (float("nan"), ValueError),
        (float("inf"), ValueError),
        (-1.0, ValueError),
        (0.0, ValueError),
        (1e300, ValueError),
        ("big", TypeError),
        (True, TypeError),
        (None, TypeError),
    ],
)
def test_gltf_export_refuses_a_mesh_size_that_is_not_a_positive_float32_length(
    tmp_path, size, error
):
    with pytest.raises(error, match=r"^size: "):
        to_gltf(_spline(), tmp_path / "a.glb", size=size, progress=False)
    assert not (tmp_path / "a.glb").exists()


@pytest.mark.parametrize("name", ["uniform", "progress"])
@pytest.mark.parametrize("value", ["no", 0, None])
def test_gltf_export_refuses_flags_that_are_not_booleans(tmp_path, name, value):
    with pytest.raises(TypeError, match=rf"^{name}: expected True or False"):
        to_gltf(_spline(), tmp_path / "a.glb", **{"progress": False, name: value})


def test_gltf_export_node_name_must_be_a_unicode_string(tmp_path):
    with pytest.raises(TypeError, match=r"^node: expected a string, got int"):
        to_gltf(_spline(), tmp_path / "a.glb", node=5, progress=False)
    with pytest.raises(ValueError, match=r"^node: not valid Unicode"):
        to_gltf(_spline(), tmp_path / "a.glb", node="a\ud800b", progress=False)
    assert not (tmp_path / "a.glb").exists()


def test_gltf_export_of_a_trajectory_named_with_undecodable_bytes_writes_valid_unicode(tmp_path):
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    traj = qio.Trajectory(np.arange(6.0), q, name="take\udcff1")  # os.fsdecode of b"take\xff1"
    path = tmp_path / "a.glb"
    to_gltf(traj, path, max_error=1, progress=False)
    doc = json.loads(_json_chunk(path))
    for name in (doc["scenes"][0]["name"], doc["animations"][0]["name"]):
        assert name.startswith("take")
        name.encode("utf-8")  # no lone surrogate: every glTF string is UTF-8


def test_gltf_export_refuses_method_or_parameters_it_would_ignore(tmp_path):
    with pytest.raises(TypeError, match=r"^method: a spline is exported as it is"):
        to_gltf(_spline(), tmp_path / "a.glb", method="slerp", progress=False)
    with pytest.raises(TypeError, match=r"^alpha: a spline is exported as it is"):
        to_gltf(_spline(), tmp_path / "a.glb", alpha=0.1, progress=False)
    assert not (tmp_path / "a.glb").exists()
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    rep = to_gltf(
        qio.Trajectory(np.arange(6.0), q), tmp_path / "t.glb", method="slerp", max_keys=None,
        progress=False,
    )  # fmt: skip
    same = to_gltf(qs.PiecewiseSlerp(q, np.arange(6.0)), tmp_path / "s.glb", progress=False)
    assert (rep.rotation_keys, rep.rotation_error) == (same.rotation_keys, same.rotation_error)


def test_gltf_export_refuses_positions_beyond_float32_instead_of_writing_infinities(tmp_path):
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    far = qio.Trajectory(np.arange(6.0), q, positions=np.full((6, 3), 1e39))
    with pytest.raises(ValueError, match=r"^motion: positions reach 1e\+39 m, beyond the float32"):
        to_gltf(far, tmp_path / "a.glb", max_position_error=1e35, progress=False)
    assert not (tmp_path / "a.glb").exists()


def test_bvh_export_joint_of_the_wrong_kind_is_a_type_error(tmp_path):
    q = qs.from_axis_angle([0, 0, 1], np.linspace(0, 3, 6))
    with pytest.raises(TypeError, match=r"^joint: expected a string, got int"):
        to_bvh(qio.Trajectory(np.arange(6.0), q), tmp_path / "a.bvh", joint=5)
    assert not (tmp_path / "a.bvh").exists()


@pytest.mark.parametrize("path", [None, 5, b"a.glb"])
def test_gltf_export_path_of_the_wrong_kind_is_a_type_error_naming_it(path):
    with pytest.raises(TypeError, match=r"^path: expected a file path"):
        to_gltf(_spline(), path, progress=False)


def test_bvh_writer_accepts_uniform_frames_at_epoch_times_and_names_a_single_frame(tmp_path):
    """Uniform frames at 1.7e9 s differ by the rounding of the times (2.4e-7 s), which the
    writer took for uneven spacing; one frame has no frame time and is refused as such."""
    q = np.tile([1.0, 0.0, 0.0, 0.0], (600, 1))
    qio.write(tmp_path / "e.bvh", qio.Trajectory(1.7e9 + np.arange(600) / 120, q))
    back = qio.read(tmp_path / "e.bvh")
    assert len(back) == 600 and np.allclose(np.diff(back.times), 1 / 120)
    with pytest.raises(ValueError, match="at least 2 frames"):
        qio.write(tmp_path / "one.bvh", qio.Trajectory([0.0], q[:1]))
    with pytest.raises(ValueError, match="uniformly spaced"):
        qio.write(tmp_path / "u.bvh", qio.Trajectory([0.0, 1.0, 3.0], q[:3]))


def test_export_fps_zero_is_refused_not_taken_as_unset(tmp_path, capsys):
    tr = qio.Trajectory(np.arange(20) / 10, np.tile([1.0, 0.0, 0.0, 0.0], (20, 1)))
    src = tmp_path / "k.csv"
    qio.write(src, tr)
    out = tmp_path / "x.bvh"
    assert main(["export", str(src), "-o", str(out), "--fps", "0"]) == 2
    assert "--fps" in capsys.readouterr().err and not out.exists()
    assert main(["export", str(src), "-o", str(out), "--fps", "20"]) == 0
    assert len(qio.read(out)) == 39


@pytest.mark.parametrize(
    ("method", "params", "words"),
    [
        ("c3", {"alpha": "x"}, "a number or 'auto'"),
        ("c3", {"holds": "maybe"}, "true or false"),
        ("hermite", {"rates": "no-such-file"}, "'bessel', 'zero', a file"),
    ],
)
def test_registry_messages_say_what_a_parameter_accepts_not_the_converter(method, params, words):
    q = np.tile([1.0, 0.0, 0.0, 0.0], (3, 1))
    with pytest.raises(ValueError) as e:
        qs.spline(method, q, [0.0, 1.0, 2.0], **params)
    assert words in str(e.value) and "float_or_auto" not in str(e.value)
