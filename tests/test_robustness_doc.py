"""docs/robustness.md: every row names tests, and every named test exists (a row whose test
was renamed or deleted would otherwise claim a guarantee nothing checks)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "robustness.md"


def _python_tests(module: str) -> set[str]:
    found = sorted((ROOT / "tests").rglob(f"{module}.py"))
    assert len(found) == 1, f"docs/robustness.md names {module}.py: found {found}"
    path = found[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {n.name for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}


def test_every_test_named_in_the_robustness_table_exists():
    text = DOC.read_text(encoding="utf-8")
    refs = re.findall(r"\b(test_\w+)::(test_\w+\*?)", text)
    assert len(refs) > 50
    for module, name in refs:
        names = _python_tests(module)
        if name.endswith("_") or name.endswith("*"):  # a family: test_extreme_floats_*
            assert any(n.startswith(name.rstrip("*")) for n in names), (module, name)
        else:
            assert name in names, f"docs/robustness.md: {module}::{name} does not exist"
    for path, name in re.findall(r"\b((?:crates/[\w/]+/)?tests/\w+\.rs)::(\w+)", text):
        candidates = (
            [ROOT / path] if path.startswith("crates") else list(ROOT.glob(f"crates/*/{path}"))
        )
        assert any(
            f"fn {name}" in p.read_text(encoding="utf-8") for p in candidates if p.is_file()
        ), (
            path,
            name,
        )


def test_every_table_row_names_a_test():
    rows = [
        line
        for line in DOC.read_text(encoding="utf-8").splitlines()
        if line.startswith("| ") and not line.startswith("| input ")
    ]
    assert rows
    for row in rows:
        assert re.search(r"test_\w+|tests/\w+\.rs|fuzz_targets", row), row
