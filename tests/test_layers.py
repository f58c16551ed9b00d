"""The package's import graph: layers by concern, imports only downward, at the top of each file.

Walks the AST of every module of ``python/quatspline`` and fails on
- a function-level (or otherwise nested) import of one of our own modules (an optional
  third-party package goes through ``quatspline._util.optional.need`` instead);
- an import that points up the layers of :data:`RANK`, or sideways into another group of the
  same layer (``io`` and ``splines`` do not know each other);
- a cycle between modules;
- a module named like a function it exports (``import quatspline.fit as m`` must not give a
  function, and no ``quatspline/fit.py`` may shadow the function ``quatspline.fit``).
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest
import quatspline

PKG = Path(__file__).resolve().parents[1] / "python" / "quatspline"

#: Layer of each module or package (longest dotted prefix wins); an import must go to a lower
#: layer or stay inside its own group (same prefix entry).
RANK = {
    "quatspline._core": 0,
    "quatspline._util": 0,
    "quatspline.core": 1,
    "quatspline.io": 2,
    "quatspline.splines": 2,
    "quatspline.plot": 2,
    "quatspline.fitting": 3,
    "quatspline.examples": 3,
    "quatspline.registry": 4,
    "quatspline.poses": 5,
    "quatspline.imu": 5,
    "quatspline.ops": 6,
    "quatspline.arguments": 7,
    "quatspline.viewer": 7,
    "quatspline.blender": 7,
    "quatspline.demo": 7,
    "quatspline.batch": 8,
    "quatspline.cli": 9,
    "quatspline.__main__": 10,
    "quatspline": 11,
}


def _modules() -> dict[str, tuple[Path, bool]]:
    out = {}
    for path in sorted(PKG.rglob("*.py")):
        parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts = parts[:-1]
        out[".".join(parts)] = (path, is_pkg)
    return out


MODULES = _modules()
KNOWN = set(MODULES) | {"quatspline._core"}


def _group(name: str) -> str:
    return max((p for p in RANK if name == p or name.startswith(p + ".")), key=len)


def _resolve(name: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = name.split(".")
    if not is_pkg:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(name: str, path: Path, is_pkg: bool):
    """(target module, line, at top level) for every import of one of our own modules."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(n) for n in tree.body}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = _resolve(name, is_pkg, node)
            subs = [f"{base}.{a.name}" for a in node.names]
            targets = [s for s in subs if s in KNOWN] or [base]
            if node.module is None and base != "quatspline":
                targets.append(base)  # `from . import x` runs (and binds from) the face too
        else:
            continue
        for t in targets:
            if t == "quatspline" or t.startswith("quatspline."):
                yield t, node.lineno, id(node) in top


def _edges():
    for name, (path, is_pkg) in MODULES.items():
        for target, line, at_top in _imports(name, path, is_pkg):
            yield name, target, line, at_top, path


def test_imports_of_our_modules_stand_at_the_top_of_the_file():
    nested = [
        f"{path.relative_to(PKG.parent)}:{line}: imports {target} inside a function or block"
        for name, target, line, at_top, path in _edges()
        if not at_top
    ]
    assert not nested, "\n".join(nested)


def test_imports_point_down_the_layers():
    bad = []
    for name, target, line, _, path in _edges():
        if target == "quatspline._core":
            continue
        a, b = _group(name), _group(target)
        if a == b:
            continue
        if RANK[b] >= RANK[a]:
            bad.append(
                f"{path.relative_to(PKG.parent)}:{line}: {a} (layer {RANK[a]}) imports {b} "
                f"(layer {RANK[b]})"
            )
    assert not bad, "\n".join(bad)


def test_no_import_cycle():
    graph: dict[str, set[str]] = {m: set() for m in MODULES}
    for name, target, _, _, _ in _edges():
        # importing a.b.c runs the faces a/__init__ and a/b/__init__ first: they count too
        t = target
        while "." in t:
            if t in MODULES and t != name and not name.startswith(t + "."):
                graph[name].add(t)
            t = t.rsplit(".", 1)[0]
    state: dict[str, int] = {}
    stack: list[str] = []
    cycles: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for n in sorted(graph[m]):
            if state.get(n) == 1:
                cycles.append(" -> ".join(stack[stack.index(n) :] + [n]))
            elif n not in state:
                visit(n)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)
    assert not cycles, "\n".join(cycles)


@pytest.mark.parametrize("name", sorted(MODULES))
def test_no_module_is_named_like_a_function_it_exports(name):
    path, _ = MODULES[name]
    leaf = name.rsplit(".", 1)[-1]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    functions = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    assert leaf not in functions, f"{name} defines {leaf}()"


@pytest.mark.parametrize("name", ["fit", "spline", "continuity", "integrate", "mean", "retime"])
def test_public_functions_are_not_shadowed_by_modules(name):
    assert callable(getattr(quatspline, name))
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module(f"quatspline.{name}")


def test_import_quatspline_does_not_import_the_dask_front_end_or_heavy_extras():
    code = (
        "import sys, quatspline\n"
        "bad = [m for m in ('quatspline.batch', 'dask', 'matplotlib', 'pandas', 'starlette')"
        " if m in sys.modules]\n"
        "print(','.join(bad))\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert r.stdout.strip() == ""
    assert quatspline.batch.__name__ == "quatspline.batch"  # still there on first use


def test_no_import_statement_inside_a_function():
    # an optional third-party package is imported by quatspline._util.optional.need(), which
    # names its pip extra; the standard library and required packages stand at the top
    nested = []
    for path, _ in MODULES.values():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for fn in ast.walk(tree):
            if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
                for node in ast.walk(fn):
                    if isinstance(node, (ast.Import, ast.ImportFrom)):
                        nested.append(
                            f"{path.relative_to(PKG.parent)}:{node.lineno} in {fn.name}()"
                        )
    assert not nested, "\n".join(nested)
