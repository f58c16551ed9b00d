"""The io layer imports nothing above it: only ``quatspline._core``, ``quatspline._util``,
``quatspline.core`` and its own modules, each import at the top of its file."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

IO = Path(__file__).resolve().parents[2] / "python" / "quatspline" / "io"
ALLOWED = ("quatspline._core", "quatspline._util", "quatspline.core", "quatspline.io")


def _imports(path: Path):
    """(absolute target, line, at top level) of every import of the package in ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(n) for n in tree.body}
    package = ["quatspline", "io"]  # every file of io is in this package
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package[: len(package) - (node.level - 1)]
            names = [".".join(base + ([node.module] if node.module else []))]
        elif isinstance(node, ast.ImportFrom):
            names = [node.module or ""]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        for name in names:
            if name == "quatspline" or name.startswith("quatspline."):
                yield name, node.lineno, id(node) in top


@pytest.mark.parametrize("path", sorted(IO.glob("*.py")), ids=lambda p: p.name)
def test_io_imports_nothing_above_it_and_only_at_the_top(path):
    """io._common imported the resampling operation and io.gltf the spline exporter inside
    functions (io reaching up to ops, splines and the registry); every format imported
    conversions inside its functions."""
    bad = [
        f"{path.name}:{line}: {name}" + ("" if top else " (inside a function)")
        for name, line, top in _imports(path)
        if not top or not any(name == a or name.startswith(a + ".") for a in ALLOWED)
    ]
    assert not bad, bad
