"""Every ``quatspline …`` invocation shown in the README and the docs parses, as written, with
the command line's own parser (no command runs: the files they name need not exist)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from quatspline.cli._commands import build_parser

ROOT = Path(__file__).resolve().parents[2]
SOURCES = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").glob("*.rst")),
    *sorted((ROOT / "docs").glob("*.md")),
    *sorted((ROOT / "docs").glob("*/*.rst")),
]
COMMANDS = (
    "sample",
    "fit",
    "compare",
    "plot",
    "export",
    "batch",
    "imu",
    "view",
    "demo",
    "info",
    "convert",
)


def _invocations():
    found = []
    for path in SOURCES:
        if "_build" in path.parts or "auto_examples" in path.parts:
            continue
        lines = path.read_text(encoding="utf-8").splitlines()
        i = 0
        while i < len(lines):
            line = lines[i].strip()
            m = re.match(r"^(?:\$\s+)?quatspline\s+(\S+)", line)
            start = i
            if m and m.group(1) in COMMANDS:
                text = line
                while text.endswith("\\") and i + 1 < len(lines):
                    i += 1
                    text = text[:-1] + " " + lines[i].strip()
                text = re.sub(r"\s+#.*$", "", text)  # a trailing comment
                text = re.sub(r"^\$\s+", "", text)
                found.append(pytest.param(text, id=f"{path.name}:{start + 1}"))
            i += 1
    return found


INVOCATIONS = _invocations()


def test_the_docs_show_invocations_of_every_main_command():
    shown = {shlex.split(p.values[0])[1] for p in INVOCATIONS}
    assert {"sample", "compare", "export", "batch", "view", "demo", "plot"} <= shown, shown


@pytest.mark.parametrize("text", INVOCATIONS)
def test_documented_invocation_parses_as_written(text):
    argv = shlex.split(text)[1:]
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as e:  # argparse: exit code 2 and a usage message on stderr
        pytest.fail(f"{text!r} does not parse (exit {e.code})")
    assert getattr(args, "func", None) is not None, text
