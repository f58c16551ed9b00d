"""The splines package by family: one module per Rust file, a face that names everything, and
imports that point down (base < keys < families < joints < pose splines < timing < reparam)."""

from __future__ import annotations

import ast
import importlib
import inspect
import sys
import warnings
from pathlib import Path

import pytest
import quatspline as qs
import quatspline.splines as sp

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "python" / "quatspline" / "splines"
RUST = ROOT / "crates" / "quatspline" / "src" / "spline"

#: Each family and the module that holds it: the name of its Rust file (issue 3.2: ``squad.py``
#: beside ``spline/squad.rs``, ``CatmullRom`` with ``KochanekBartels``).
FAMILIES = {
    "PiecewiseSlerp": "piecewise_slerp",
    "PiecewiseNlerp": "nlerp",
    "PiecewiseLinEuler": "lin_euler",
    "PiecewiseLinMat": "lin_mat",
    "SphericalBezier": "spherical_bezier",
    "CumulativeBezier": "cumulative_bezier",
    "Squad": "squad",
    "CatmullRom": "catmull_rom",
    "KochanekBartels": "catmull_rom",
    "Hermite": "hermite",
    "CumulativeBSpline": "cumulative_bspline",
    "NaturalSpline": "natural_spline",
    "BetaSpline": "beta",
    "C3Spline": "c3",
}

#: Floor of each module of the package: a module imports only modules of lower floors.
FLOORS = {
    "base": 0,
    "keys": 1,
    "knots": 1,
    **{m: 2 for m in FAMILIES.values()},
    "joints": 3,
    "se3": 4,
    "screw": 5,
    "pose_bspline": 5,
    "timing": 5,
    "reparam": 6,
}


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_each_spline_family_lives_in_the_module_named_like_its_rust_file(name):
    module = FAMILIES[name]
    cls = getattr(sp, name)
    assert cls.__module__ == f"quatspline.splines.{module}"
    assert (RUST / f"{module}.rs").is_file(), module
    assert getattr(qs, name) is cls  # the public name is the same class
    assert issubclass(cls, sp.Spline)


def test_the_splines_face_names_every_public_class_and_function_of_its_modules():
    modules = sorted(p.stem for p in PKG.glob("*.py") if p.stem != "__init__")
    assert set(modules) == set(FLOORS), "a module of splines/ has no floor in this test"
    for stem in modules:
        module = importlib.import_module(f"quatspline.splines.{stem}")
        for name in getattr(module, "__all__", []):
            assert name in sp.__all__, f"quatspline.splines does not export {stem}.{name}"
            assert getattr(sp, name) is getattr(module, name)
    for name in ("DEFAULT_MAX_SAMPLES", "EXTRAPOLATE", "describe", "Spline"):
        assert name in sp.__all__
    assert not (PKG / "_families.py").exists() and not (PKG / "keyframe.py").exists()


def _our_imports(path: Path):
    """(imported splines module or None, line, at top level) of every import of our modules."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(n) for n in tree.body}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level > 0:
            if node.level == 1 and node.module:  # from .x import y
                yield node.module.split(".")[0], node.lineno, id(node) in top
            elif node.level == 1:  # from . import x
                for a in node.names:
                    yield a.name, node.lineno, id(node) in top
            else:  # from ..x import y: a lower package (core, _util, _core)
                yield None, node.lineno, id(node) in top
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module]
            if any(n == "quatspline" or (n or "").startswith("quatspline.") for n in names):
                yield None, node.lineno, id(node) in top


@pytest.mark.parametrize("stem", sorted(FLOORS))
def test_splines_modules_import_only_lower_floors_and_only_at_the_top(stem):
    path = PKG / f"{stem}.py"
    for target, line, at_top in _our_imports(path):
        assert at_top, f"splines/{stem}.py:{line}: an import inside a function or block"
        if target is not None:
            assert FLOORS[target] < FLOORS[stem], (
                f"splines/{stem}.py:{line} imports {target} (floor {FLOORS[target]}), "
                f"not below its own floor {FLOORS[stem]}"
            )


def test_spline_base_imports_nothing_but_the_core_and_utilities():
    tree = ast.parse((PKG / "base.py").read_text(encoding="utf-8"))
    sources = {
        ("." * n.level) + (n.module or "") for n in tree.body if isinstance(n, ast.ImportFrom)
    }
    ours = {s for s in sources if s.startswith(".")}
    assert ours <= {"..", ".._util.arrays", ".._util.checks"}, ours


def test_old_keyframe_path_still_gives_its_names_with_a_deprecation_warning():
    sys.modules.pop("quatspline.keyframe", None)
    with pytest.warns(DeprecationWarning, match="quatspline.keyframe is deprecated"):
        old = importlib.import_module("quatspline.keyframe")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for name in ("Hermite", "KochanekBartels", "bessel_rates", "bspline_controls"):
            assert getattr(old, name) is getattr(qs.splines, name)
        assert old.c3_speed_matched_alpha is sp.c3_speed_matched_alpha
    sys.modules.pop("quatspline.keyframe", None)


def test_retime_and_reparameterize_accept_the_same_spline_classes_after_the_split():
    # reparameterize(kind="arc_length") goes through timing.arc_length (imported at the top
    # of reparam.py now, inside the function before): the same result as arc_length itself.
    q = qs.from_rotvec([[0, 0, 0], [0, 0, 0.2], [0, 0.5, 1.0]])
    s = sp.Squad(q, [0.0, 1.0, 3.0])
    a, b = sp.reparameterize(s, "arc_length"), sp.arc_length(s)
    t = [0.0, 0.7, 1.9, 3.0]
    assert type(a) is type(b) and a.length == b.length
    assert (a(t) == b(t)).all()
    assert inspect.signature(sp.reparameterize) == inspect.signature(qs.reparameterize)
