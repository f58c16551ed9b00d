"""Runs scripts in a real Blender, headless, for the tests of this folder. Two Blenders:

- ``blender`` — Debian's package (Blender 3.4, system Python): ``blender -b --python
  script -- args``; ``make test`` installs it when root;
- ``bpy`` — the official Blender 4.2 build as a Python module (PyPI's ``bpy==4.2.0``, its
  own numpy) in the virtual environment ``.venv-bpy`` that ``make blender-bpy`` creates:
  ``python script -- args``.

A test run on one that is absent skips with a one-line message naming how to get it."""

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
_BPY = os.environ.get(
    "QUATSPLINE_BPY_PYTHON", str(HERE.parents[1] / ".venv-bpy" / "bin" / "python")
)
BPY_PYTHON = _BPY if os.access(_BPY, os.X_OK) else None

#: The Blenders the tests run in (id → the command before the script), absent ones as None.
BLENDERS = {
    "blender": None if BLENDER is None else [BLENDER, "-b", "--factory-startup",
                                             "--python-exit-code", "1", "--python"],
    "bpy": None if BPY_PYTHON is None else [BPY_PYTHON],
}  # fmt: skip
_MISSING = {
    "blender": "no blender on the PATH (Debian: apt-get install blender python3-numpy; "
    "`make test` installs it when root)",
    "bpy": f"no Blender 4.2 Python module at {_BPY} (`make blender-bpy` creates it: "
    "pip install bpy==4.2.0 into .venv-bpy)",
}

needs_blender = pytest.mark.skipif(BLENDER is None, reason=_MISSING["blender"])


def skip_unless(which: str) -> None:
    """Skips the calling test when Blender ``which`` ("blender" or "bpy") is absent."""
    if BLENDERS[which] is None:
        pytest.skip(_MISSING[which])


def env(tmp_path: Path) -> dict:
    """Blender's user folders inside tmp_path (the tests never touch the user's Blender),
    and the folders quatspline imports from."""
    e = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # quatspline: QS_PATHS
    e["BLENDER_USER_CONFIG"] = str(tmp_path / "blender-config")
    e["BLENDER_USER_SCRIPTS"] = str(tmp_path / "blender-scripts")
    e["QS_PATHS"] = os.pathsep.join([PACKAGE_ROOT, *site.getsitepackages()])
    return e


def run(tmp_path: Path, script: str, *args, which: str = "blender", timeout: float = 300):
    """The script in Blender ``which`` (``-- args`` after it); fails with Blender's output
    when the script fails."""
    skip_unless(which)
    cmd = [*BLENDERS[which], str(HERE / script), "--", *map(str, args)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env(tmp_path))
    assert r.returncode == 0, (r.stdout[-3000:], r.stderr[-3000:])
    return r


def jobs(tmp_path: Path, specs: dict, which: str = "blender") -> dict:
    """Runs the add-on driver once on every spec (name → spec) in Blender ``which``;
    returns name → its .npz as a dict."""
    listed = []
    for name, spec in specs.items():
        listed.append({**spec, "out": str(tmp_path / f"{name}.npz")})
    jp = tmp_path / "jobs.json"
    jp.write_text(json.dumps(listed), encoding="utf-8")
    run(tmp_path, "blender_addon_driver.py", jp, which=which)
    out = {}
    for name in specs:
        with np.load(tmp_path / f"{name}.npz") as z:
            out[name] = {k: z[k] for k in z.files}
    return out
