"""Installing the add-on into a Blender: a one-file add-on ``quatspline_addon.py`` in
Blender's user add-on folder, enabled and saved in its preferences.

The stub makes this environment's quatspline importable inside Blender: on enable it
appends two folders to ``sys.path`` — the one holding the ``quatspline`` package and this
environment's site-packages (for tqdm and the other dependencies; Blender's own numpy stays
first) — and removes them again on disable. Both paths are written into the stub, which says
so at its top; ``python -m quatspline.blender uninstall`` disables it and deletes the file.
Debian's ``blender`` runs the system Python (3.11 on Debian 12); quatspline's compiled core
is abi3, so any Python ≥ 3.9 of the same platform loads it. A Blender whose bundled Python
differs in minor version still loads the core, but the dependencies in site-packages must
suit it (pure-Python tqdm does; numpy comes from Blender).
"""

from __future__ import annotations

import argparse
import os
import shutil
import site
import subprocess
import sys
import sysconfig
from pathlib import Path

__all__ = ["BL_INFO", "STUB", "addon_folder", "find_blender", "install", "stub_text", "uninstall"]

#: What Blender's add-on list shows.
BL_INFO = {
    "name": "quatspline",
    "author": "quatspline",
    "version": (0, 1, 0),
    "blender": (3, 0, 0),
    "location": "View3D > Sidebar > quatspline; File > Import > Trajectory (quatspline)",
    "description": "Rotation splines with bounded playback error: resample, fit, import, "
    "angular velocity, acceleration and jerk",
    "category": "Animation",
}

#: The module name of the stub add-on in Blender's add-on folder.
STUB = "quatspline_addon"

_TEMPLATE = '''"""quatspline add-on, written by `python -m quatspline.blender install`.

On enable it appends these folders to sys.path (removed again on disable):
{paths}
Remove it with `python -m quatspline.blender uninstall` (or Blender's add-on preferences).
"""

import sys

bl_info = {bl_info!r}

PATHS = {path_list!r}
_added = []


def register():
    for p in PATHS:
        if p not in sys.path:
            sys.path.append(p)
            _added.append(p)
    import quatspline.blender

    quatspline.blender.register()


def unregister():
    import quatspline.blender

    quatspline.blender.unregister()
    for p in _added:
        if p in sys.path:
            sys.path.remove(p)
    _added.clear()
'''


def _paths() -> list[str]:
    pkg = str(Path(__file__).resolve().parents[2])
    out = [pkg]
    for p in [*site.getsitepackages(), sysconfig.get_paths()["purelib"]]:
        if p not in out and Path(p).is_dir():
            out.append(p)
    return out


def stub_text() -> str:
    """The stub add-on's source for this environment.

    Examples
    --------
    >>> "quatspline.blender.register()" in stub_text()
    True
    """
    paths = _paths()
    return _TEMPLATE.format(
        paths="\n".join(f"    {p}" for p in paths), bl_info=BL_INFO, path_list=paths
    )


def find_blender(blender: str | os.PathLike | None = None) -> str:
    """The Blender executable: ``blender`` as given, else ``blender`` on the PATH.

    Raises
    ------
    FileNotFoundError
        No Blender there (the message says how to give one).
    """
    if blender is not None:
        path = shutil.which(str(blender))
        if path is None:
            raise FileNotFoundError(f"--blender: no Blender executable at {blender}")
        return path
    path = shutil.which("blender")
    if path is None:
        raise FileNotFoundError(
            "blender: not on the PATH; give its executable with --blender PATH "
            "(Debian: apt-get install blender)"
        )
    return path


def _run(blender: str, expr: str) -> str:
    r = subprocess.run(
        [blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python-expr", expr],
        capture_output=True,
        text=True,
        timeout=300,
    )
    if r.returncode != 0:
        tail = (r.stderr or r.stdout).strip().splitlines()[-5:]
        raise RuntimeError(f"{blender}: failed: " + " | ".join(tail))
    return r.stdout


def addon_folder(blender: str) -> Path:
    """Blender's user add-on folder (honours ``BLENDER_USER_SCRIPTS``), created if needed."""
    out = _run(
        blender,
        "import bpy; print('QS_ADDONS=' + bpy.utils.user_resource('SCRIPTS', path='addons', "
        "create=True))",
    )
    for line in out.splitlines():
        if line.startswith("QS_ADDONS="):
            return Path(line[len("QS_ADDONS=") :])
    raise RuntimeError(f"{blender}: did not report its add-on folder")


def install(blender: str | os.PathLike | None = None) -> Path:
    """Writes the stub add-on into Blender's user add-on folder, enables it and saves the
    preferences; returns the stub's path."""
    exe = find_blender(blender)
    folder = addon_folder(exe)
    path = folder / f"{STUB}.py"
    tmp = path.with_suffix(".tmp")
    tmp.write_text(stub_text(), encoding="utf-8")
    os.replace(tmp, path)
    # factory startup keeps the user's startup file out, but the preferences are saved
    _run(
        exe,
        "import bpy, addon_utils; bpy.ops.preferences.addon_enable(module='quatspline_addon'); "
        "assert addon_utils.check('quatspline_addon')[1], 'not enabled'; "
        "bpy.context.preferences.use_preferences_save = True; bpy.ops.wm.save_userpref()",
    )
    return path


def uninstall(blender: str | os.PathLike | None = None) -> Path | None:
    """Disables the add-on, saves the preferences and deletes the stub; returns the deleted
    path (None when it was not installed)."""
    exe = find_blender(blender)
    path = addon_folder(exe) / f"{STUB}.py"
    if not path.exists():
        return None
    _run(
        exe,
        "import bpy; bpy.ops.preferences.addon_disable(module='quatspline_addon'); "
        "bpy.ops.wm.save_userpref()",
    )
    path.unlink()
    return path


def main(argv: list[str] | None = None) -> int:
    """``python -m quatspline.blender install|uninstall [--blender PATH]``."""
    ap = argparse.ArgumentParser(prog="python -m quatspline.blender")
    ap.add_argument("action", choices=("install", "uninstall"))
    ap.add_argument("--blender", help="the Blender executable (default: blender on the PATH)")
    a = ap.parse_args(argv)
    try:
        if a.action == "install":
            print(f"installed and enabled: {install(a.blender)}")
        else:
            done = uninstall(a.blender)
            print(f"removed: {done}" if done else "not installed")
    except (FileNotFoundError, RuntimeError) as e:
        print(f"quatspline.blender: {e}", file=sys.stderr)
        return 1
    return 0
