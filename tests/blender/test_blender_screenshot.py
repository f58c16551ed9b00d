"""The add-on's screenshot for the docs (docs/_static/blender-addon.png), taken in Blender with
its interface under Xvfb: written only with ``QUATSPLINE_SCREENSHOTS=1`` (like the viewer's
screenshots) where ``xvfb-run`` exists (Debian: ``apt-get install xvfb xauth``)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from .blender_run import BLENDER, HERE, env, needs_blender

DOCS_STATIC = HERE.parents[1] / "docs" / "_static"


@needs_blender
@pytest.mark.skipif(
    os.environ.get("QUATSPLINE_SCREENSHOTS") != "1" or shutil.which("xvfb-run") is None,
    reason="screenshots only with QUATSPLINE_SCREENSHOTS=1 and xvfb-run",
)
def test_screenshot_of_the_resampled_f_curves(tmp_path):
    e = env(tmp_path)
    r = subprocess.run(
        [sys.executable, "-m", "quatspline.blender", "install", "--blender", BLENDER],
        capture_output=True, text=True, env=e, timeout=300,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    prefs = "import bpy; bpy.context.preferences.view.show_splash = False; "
    prefs += "bpy.ops.wm.save_userpref()"
    subprocess.run([BLENDER, "-b", "--python-expr", prefs], env=e, timeout=300, check=True)
    out = tmp_path / "blender-addon.png"
    r = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1400x900x24", BLENDER, "--python",
         str(HERE / "blender_screenshot.py"), "--", str(out)],
        capture_output=True, text=True, env=e, timeout=300,
    )  # fmt: skip
    assert r.returncode == 0 and out.is_file(), (r.stdout[-2000:], r.stderr[-2000:])
    assert out.stat().st_size > 10_000  # an image of the interface, not an empty frame
    shutil.copyfile(out, DOCS_STATIC / "blender-addon.png")
