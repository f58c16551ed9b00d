"""Runs scripts in a real Blender, headless, for the tests of this folder (skipped with a
message where no Blender is installed: ``make test`` installs Debian's ``blender`` when
root)."""

from __future__ import annotations

import json
import os
import shutil
import site
import subprocess
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
PACKAGE_ROOT = str(Path(__import__("quatspline").__file__).resolve().parents[1])
BLENDER = shutil.which(os.environ.get("QUATSPLINE_BLENDER", "blender"))

needs_blender = pytest.mark.skipif(
    BLENDER is None,
    reason="no blender on the PATH (Debian: apt-get install blender python3-numpy; "
    "`make test` installs it when root)",
)


def env(tmp_path: Path) -> dict:
    """Blender's user folders inside tmp_path (the tests never touch the user's Blender),
    and the folders quatspline imports from."""
    e = dict(os.environ)
    e["BLENDER_USER_CONFIG"] = str(tmp_path / "blender-config")
    e["BLENDER_USER_SCRIPTS"] = str(tmp_path / "blender-scripts")
    e["QS_PATHS"] = os.pathsep.join([PACKAGE_ROOT, *site.getsitepackages()])
    return e


def run(tmp_path: Path, script: str, *args, factory: bool = True, timeout: float = 300):
    """``blender -b [--factory-startup] --python script -- args``; fails with Blender's
    output when the script fails."""
    cmd = [BLENDER, "-b"] + (["--factory-startup"] if factory else [])
    cmd += ["--python-exit-code", "1", "--python", str(HERE / script), "--", *map(str, args)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env(tmp_path))
    assert r.returncode == 0, (r.stdout[-3000:], r.stderr[-3000:])
    return r


def jobs(tmp_path: Path, specs: dict) -> dict:
    """Runs the add-on driver once on every spec (name → spec); returns name → its .npz as
    a dict."""
    listed = []
    for name, spec in specs.items():
        listed.append({**spec, "out": str(tmp_path / f"{name}.npz")})
    jp = tmp_path / "jobs.json"
    jp.write_text(json.dumps(listed), encoding="utf-8")
    run(tmp_path, "blender_addon_driver.py", jp)
    out = {}
    for name in specs:
        with np.load(tmp_path / f"{name}.npz") as z:
            out[name] = {k: z[k] for k in z.files}
    return out
