"""The built wheel as a new user gets it (issue 2.6): installed into a fresh venv in a
temporary directory outside the source tree, without matplotlib, then ``import quatspline``,
the README's quick start, ``quatspline --help`` and ``quatspline demo -o DIR``.

Run by ``make test-wheel`` (part of ``make test``) after ``make wheel`` has put exactly one
wheel and one sdist into ``dist/``.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DIST = ROOT / "dist"


def _one(pattern: str) -> Path:
    found = sorted(DIST.glob(pattern))
    assert len(found) == 1, f"expected one {pattern} in {DIST} (run `make wheel`), got {found}"
    return found[0]


@pytest.fixture(scope="module")
def wheel() -> Path:
    return _one("quatspline-*.whl")


@pytest.fixture(scope="module")
def env(wheel, tmp_path_factory):
    """(python, bin dir, work dir) of a fresh venv with the wheel installed."""
    base = tmp_path_factory.mktemp("installed")
    assert ROOT not in base.parents
    subprocess.run([sys.executable, "-m", "venv", str(base / "venv")], check=True)
    bindir = base / "venv" / "bin"
    py = bindir / "python"
    subprocess.run(
        [str(py), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(wheel)],
        check=True,
    )
    work = base / "work"
    work.mkdir()
    return py, bindir, work


def _run(env, *args, **kw):
    py, bindir, work = env
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    clean["PATH"] = f"{bindir}{os.pathsep}{clean.get('PATH', '')}"
    return subprocess.run(
        list(args), cwd=work, env=clean, capture_output=True, text=True, timeout=600, **kw
    )


def test_wheel_tag_is_abi3_manylinux2014(wheel):
    # cp39-abi3: one wheel for every CPython >= 3.9; manylinux2014 = glibc 2.17 (CentOS 7,
    # Ubuntu 14.04+, RHEL 8/9). auditwheel confirms the symbols allow that tag.
    assert re.search(r"-cp39-abi3-manylinux2014_x86_64\.manylinux_2_17_x86_64\.whl$", wheel.name)
    show = subprocess.run(
        [sys.executable, "-m", "auditwheel", "show", str(wheel)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    assert '"manylinux_2_17_x86_64"' in " ".join(show.split())
    names = zipfile.ZipFile(wheel).namelist()
    assert "quatspline/data/freiburg1_xyz-groundtruth.txt" in names
    assert any(n.endswith("licenses/LICENSE") or n.endswith("/LICENSE") for n in names)
    assert "quatspline/py.typed" in names and "quatspline/_core.pyi" in names


def test_sdist_has_tests_license_and_data():
    sdist = _one("quatspline-*.tar.gz")
    with tarfile.open(sdist) as tar:
        names = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    for needed in (
        "LICENSE",
        "CHANGELOG.md",
        "pyproject.toml",
        "tests/test_package.py",
        "tests_installed/test_installed_wheel.py",
        "data/tum_rgbd_fr1_xyz/freiburg1_xyz-groundtruth.txt",
        "python/quatspline/data/freiburg1_xyz-groundtruth.txt",
        "crates/quatspline/Cargo.toml",
        "docs/conf.py",
        "examples/README.txt",
    ):
        assert needed in names, needed
    assert not any(n.startswith("docs/_build") for n in names)


def test_import_from_the_installed_wheel(env):
    r = _run(env, str(env[0]), "-c", "import quatspline as qs; print(qs.__version__, qs.__file__)")
    assert r.returncode == 0, r.stderr
    version, path = r.stdout.split()
    assert version == "0.1.0"
    assert str(ROOT) not in path and "site-packages" in path


def test_readme_quick_start(env):
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)
    assert blocks
    for code in blocks:
        r = _run(env, str(env[0]), "-c", code)
        assert r.returncode == 0, r.stderr


def test_cli_help(env):
    r = _run(env, "quatspline", "--help")
    assert r.returncode == 0, r.stderr
    for cmd in ("sample", "compare", "plot", "demo"):
        assert cmd in r.stdout
    # the wheel ships quatspline/__main__.py: `python -m quatspline` is the same command line
    r2 = _run(env, str(env[0]), "-m", "quatspline", "--help")
    assert r2.returncode == 0 and r2.stdout == r.stdout, r2.stderr


_COUNT_METHODS = "from quatspline.registry import interpolating_methods as m; print(len(m()))"


def test_demo_without_matplotlib(env):
    r = _run(env, str(env[0]), "-c", "import matplotlib")
    assert r.returncode != 0, "the fresh venv should not have matplotlib"
    out = env[2] / "demo-out"
    r = _run(env, "quatspline", "demo", "-o", str(out))
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[-1] == (
        "figures skipped: matplotlib is not installed (pip install 'quatspline[plot]')"
    )
    assert (out / "report.md").stat().st_size > 0
    assert (out / "compare.json").stat().st_size > 0
    r = _run(env, str(env[0]), "-c", _COUNT_METHODS)
    # one sample file per interpolating method, plus the Beta example
    assert len(list((out / "samples").glob("*.csv"))) == int(r.stdout) + 1
    assert sorted(p.name for p in out.parent.iterdir()) == ["demo-out"]


def test_viewer_assets_ship_in_the_wheel_and_missing_extras_give_a_hint(env):
    r = _run(
        env,
        str(env[0]),
        "-c",
        "from quatspline.viewer.server import missing_assets; print(missing_assets())",
    )
    assert r.returncode == 0 and r.stdout.strip() == "[]", (r.stdout, r.stderr)
    # the fresh venv has neither the viewer nor the dask extra: one line naming the extra
    r = _run(env, "quatspline", "view", "--no-browser")
    assert r.returncode == 1 and 'pip install "quatspline[viewer]"' in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    r = _run(
        env, "quatspline", "batch", "sample", str(env[2]), "-o", str(env[2] / "b"), "--count", "3"
    )
    assert r.returncode == 1 and 'pip install "quatspline[dask]"' in r.stderr, r.stderr


BLENDER_SCRIPT = """
import addon_utils, bpy, math
print("QS enabled", addon_utils.check("quatspline_addon")[1])
obj = bpy.data.objects.new("body", None)
bpy.context.collection.objects.link(obj)
bpy.context.view_layer.objects.active = obj
obj.select_set(True)
obj.rotation_mode = "QUATERNION"
for f, a in ((1, 0.0), (25, 1.0), (49, 2.5), (73, 3.0)):
    obj.rotation_quaternion = (math.cos(a / 2), 0.0, 0.0, math.sin(a / 2))
    obj.keyframe_insert("rotation_quaternion", frame=f)
print("QS op", sorted(bpy.ops.quatspline.resample()))
fc = [c for c in obj.animation_data.action.fcurves if c.data_path == "rotation_quaternion"]
print("QS keys", len(fc[0].keyframe_points))
"""


@pytest.mark.skipif(shutil.which("blender") is None, reason="no blender on the PATH")
def test_blender_addon_installs_from_the_wheel_and_resamples(env):
    """The add-on as a wheel user installs it: ``python -m quatspline.blender install`` from
    the wheel's environment, then a real, headless Blender runs its resample operator."""
    py, _, work = env
    cfg = {
        "BLENDER_USER_CONFIG": str(work / "blender-config"),
        "BLENDER_USER_SCRIPTS": str(work / "blender-scripts"),
    }
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    r = subprocess.run(
        [str(py), "-m", "quatspline.blender", "install", "--blender", shutil.which("blender")],
        cwd=work, env={**clean, **cfg}, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    (work / "resample.py").write_text(BLENDER_SCRIPT, encoding="utf-8")
    r = subprocess.run(
        ["blender", "-b", "--python-exit-code", "1", "--python", str(work / "resample.py")],
        cwd=work, env={**clean, **cfg}, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    lines = [ln for ln in r.stdout.splitlines() if ln.startswith("QS ")]
    assert r.returncode == 0, (r.stdout[-2000:], r.stderr[-2000:])
    assert lines[:2] == ["QS enabled True", "QS op ['FINISHED']"], lines
    assert int(lines[2].split()[-1]) > 4  # keys placed along the spline, not only the four


BPY_PYTHON = Path(os.environ.get("QUATSPLINE_BPY_PYTHON", ROOT / ".venv-bpy" / "bin" / "python"))


@pytest.mark.skipif(
    not os.access(BPY_PYTHON, os.X_OK),
    reason=f"no Blender 4.2 Python module at {BPY_PYTHON} (`make blender-bpy` creates it)",
)
def test_blender_42_enables_the_addon_from_the_wheel_and_resamples(env):
    """The stub add-on that ``install`` writes, made from the wheel's environment, enabled by
    the official Blender 4.2 build (PyPI's bpy module, which has no executable for
    ``install`` to run) through its add-on preferences; its resample operator runs."""
    py, _, work = env
    scripts = work / "bpy-scripts"
    (scripts / "addons").mkdir(parents=True)
    cfg = {"BLENDER_USER_CONFIG": str(work / "bpy-config"), "BLENDER_USER_SCRIPTS": str(scripts)}
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    r = _run(env, str(py), "-c", "from quatspline.blender.installer import stub_text as s; "
             "print(s(), end='')")  # fmt: skip
    assert r.returncode == 0, r.stderr
    (scripts / "addons" / "quatspline_addon.py").write_text(r.stdout, encoding="utf-8")
    script = (
        "import bpy\nbpy.ops.preferences.addon_enable(module='quatspline_addon')\n"
        + BLENDER_SCRIPT
        + "import quatspline\nprint('QS from', quatspline.__file__)\n"
    )
    (work / "resample42.py").write_text(script, encoding="utf-8")
    r = subprocess.run(
        [str(BPY_PYTHON), str(work / "resample42.py")],
        cwd=work, env={**clean, **cfg}, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    lines = [ln for ln in r.stdout.splitlines() if ln.startswith("QS ")]
    assert r.returncode == 0, (r.stdout[-2000:], r.stderr[-2000:])
    assert lines[:2] == ["QS enabled True", "QS op ['FINISHED']"], lines
    assert int(lines[2].split()[-1]) > 4
    assert Path(lines[3].split(maxsplit=2)[2]).is_relative_to(py.parent.parent), lines[3]
