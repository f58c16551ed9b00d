"""``python -m quatspline.blender install|uninstall`` against a real Blender whose user
folders live in the test's temporary directory; and the add-on's modules outside Blender."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import quatspline.blender
from quatspline._util.optional import MissingDependency
from quatspline.blender import actions, installer

from .blender_run import BLENDER, BLENDERS, HERE, env, needs_blender, run

CHECK = """
import sys, addon_utils, bpy
print("QS enabled", addon_utils.check("quatspline_addon")[1])
print("QS ops", hasattr(bpy.types, "QUATSPLINE_OT_resample"),
      hasattr(bpy.types, "QUATSPLINE_PT_panel"))
stub = sys.modules.get("quatspline_addon")
print("QS paths", stub is not None and all(p in sys.path for p in stub.PATHS))
"""


def _module(tmp_path, *args):
    e = env(tmp_path)
    e["PYTHONPATH"] = installer._paths()[0]
    return subprocess.run(
        [sys.executable, "-m", "quatspline.blender", *args],
        capture_output=True, text=True, env=e, timeout=300,
    )  # fmt: skip


def _check(tmp_path):
    (tmp_path / "check.py").write_text(CHECK, encoding="utf-8")
    r = subprocess.run(
        [BLENDER, "-b", "--python-exit-code", "1", "--python", str(tmp_path / "check.py")],
        capture_output=True, text=True, env=env(tmp_path), timeout=300,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr[-2000:]
    return [ln for ln in r.stdout.splitlines() if ln.startswith("QS ")]


@needs_blender
def test_install_enables_the_addon_and_uninstall_removes_it(tmp_path):
    r = _module(tmp_path, "install", "--blender", BLENDER)
    assert r.returncode == 0, r.stderr
    stub = tmp_path / "blender-scripts" / "addons" / "quatspline_addon.py"
    assert f"installed and enabled: {stub}" in r.stdout
    assert "appends these folders to sys.path" in stub.read_text(encoding="utf-8")
    assert _check(tmp_path) == ["QS enabled True", "QS ops True True", "QS paths True"]
    r = _module(tmp_path, "uninstall", "--blender", BLENDER)
    assert r.returncode == 0 and not stub.exists(), r.stderr
    assert _check(tmp_path)[:2] == ["QS enabled False", "QS ops False False"]


STUB_CHECK = """
import math, sys, bpy
import addon_utils  # after bpy: Blender as a module puts it on sys.path
print("QS version", *bpy.app.version[:2])
before = list(sys.path)
bpy.ops.preferences.addon_enable(module="quatspline_addon")
print("QS enabled", addon_utils.check("quatspline_addon")[1],
      hasattr(bpy.types, "QUATSPLINE_OT_resample"))
paths = sys.modules["quatspline_addon"].PATHS
print("QS paths", all(p in sys.path for p in paths))
obj = bpy.data.objects.new("body", None)
bpy.context.collection.objects.link(obj)
bpy.context.view_layer.objects.active = obj
obj.rotation_mode = "QUATERNION"
for f, a in ((1, 0.0), (25, 1.0), (49, 2.5), (73, 3.0)):
    obj.rotation_quaternion = (math.cos(a / 2), 0.0, 0.0, math.sin(a / 2))
    obj.keyframe_insert("rotation_quaternion", frame=f)
print("QS op", sorted(bpy.ops.quatspline.resample(method="c3")))
fc = [c for c in obj.animation_data.action.fcurves if c.data_path == "rotation_quaternion"]
print("QS more keys", len(fc[0].keyframe_points) > 4)
bpy.ops.preferences.addon_disable(module="quatspline_addon")
print("QS disabled", not addon_utils.check("quatspline_addon")[1],
      not hasattr(bpy.types, "QUATSPLINE_OT_resample"), sys.path == before)
"""


@pytest.mark.parametrize("which", list(BLENDERS))
def test_the_stub_addon_enables_resamples_and_disables_in_each_blender(tmp_path, which):
    """The one-file add-on ``install`` writes, in Blender's user add-on folder, enabled and
    disabled by Blender's own add-on preferences operators (Debian's 3.4 and the official
    4.2 build, which has no executable to run ``install`` against as a module)."""
    addons = tmp_path / "blender-scripts" / "addons"
    addons.mkdir(parents=True)
    (addons / f"{installer.STUB}.py").write_text(installer.stub_text(), encoding="utf-8")
    (tmp_path / "check.py").write_text(STUB_CHECK, encoding="utf-8")
    r = run(tmp_path, tmp_path / "check.py", which=which)
    lines = [ln for ln in r.stdout.splitlines() if ln.startswith("QS ")]
    version = {"blender": "QS version 3 4", "bpy": "QS version 4 2"}[which]
    assert lines == [
        version, "QS enabled True True", "QS paths True", "QS op ['FINISHED']",
        "QS more keys True", "QS disabled True True True",
    ], r.stdout[-2000:]  # fmt: skip


def test_install_names_a_missing_blender(tmp_path):
    r = _module(tmp_path, "install", "--blender", str(tmp_path / "no-blender"))
    assert r.returncode == 1
    assert (
        r.stderr.strip()
        == f"quatspline.blender: --blender: no Blender executable at {tmp_path / 'no-blender'}"
    )


def test_the_addon_imports_outside_blender_and_says_where_it_runs():
    assert quatspline.blender.bl_info["name"] == "quatspline"
    with pytest.raises(
        MissingDependency, match=r"runs inside Blender .*quatspline.blender install"
    ):
        quatspline.blender.register()


def test_actions_translate_frames_rotation_modes_and_parameters():
    assert actions.frames_to_times([0, 12], 24).tolist() == [0.0, 0.5]
    q = actions.quats_from_rotation("ZYX", [[0.3, -0.2, 0.1]])
    # Blender's ZYX: Z first, then Y, then X, about fixed axes = Rx · Ry · Rz
    want = qs_mul(qs_mul(axis(0, 0.1), axis(1, -0.2)), axis(2, 0.3))
    assert min(np.abs(q[0] - want).max(), np.abs(q[0] + want).max()) < 1e-12
    with pytest.raises(ValueError, match=r"^mode: expected QUATERNION or an Euler mode"):
        actions.quats_from_rotation("AXIS_ANGLE", [[1, 0, 0, 0]])
    with pytest.raises(ValueError, match=r"^keys: .*fewer than two keyframes"):
        actions.curve_frames([[3.0], [3.0]])
    with pytest.raises(ValueError, match=r"^alpha: "):
        actions.parse_params("c3", "alpha=wide")
    with pytest.raises(ValueError, match=r"^fps: expected a positive frame rate"):
        actions.times_to_frames([0.0], 0)


def axis(i, a):
    q = np.zeros(4)
    q[0], q[1 + i] = np.cos(a / 2), np.sin(a / 2)
    return q


def qs_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ])  # fmt: skip


def test_the_docs_example_for_blender_as_a_module_runs_in_blender_42(tmp_path):
    """docs/blender.md's example for the bpy module, as written, on a keyed active object."""
    doc = (HERE.parents[1] / "docs" / "blender.md").read_text(encoding="utf-8")
    (example,) = re.findall(r"```python\n(.*?)```", doc, flags=re.S)
    setup = STUB_CHECK.split('print("QS version"')[0] + textwrap.dedent("""
        obj = bpy.data.objects.new("body", None)
        bpy.context.collection.objects.link(obj)
        bpy.context.view_layer.objects.active = obj
        obj.rotation_mode = "QUATERNION"
        for f, a in ((1, 0.0), (25, 1.0), (49, 2.5), (73, 3.0)):
            obj.rotation_quaternion = (math.cos(a / 2), 0.0, 0.0, math.sin(a / 2))
            obj.keyframe_insert("rotation_quaternion", frame=f)
        import os
        sys.path += os.environ["QS_PATHS"].split(os.pathsep)  # the environment quatspline is in
    """)
    check = textwrap.dedent("""
        fc = [c for c in obj.animation_data.action.fcurves
              if c.data_path == "rotation_quaternion"]
        print("QS keys", len(fc[0].keyframe_points), fc[0].keyframe_points[1].interpolation)
    """)
    (tmp_path / "example.py").write_text(setup + example + check, encoding="utf-8")
    r = run(tmp_path, tmp_path / "example.py", which="bpy")
    (line,) = [ln for ln in r.stdout.splitlines() if ln.startswith("QS keys")]
    assert int(line.split()[2]) > 4 and line.split()[3] == "LINEAR", line
