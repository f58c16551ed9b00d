"""The command-line page (docs/cli.md) documents every command and every option the parser
has: a command without its section, or an option named nowhere on the page, fails here."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest
from quatspline.arguments import EXAMPLES
from quatspline.cli._commands import build_parser

PAGE = Path(__file__).resolve().parents[1] / "docs" / "cli.md"


def commands(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(command path, parser) for every leaf command."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield path, parser
        return
    for name, sub in subs[0].choices.items():
        yield from commands(sub, (*path, name))


def sections() -> dict[str, str]:
    text = PAGE.read_text(encoding="utf-8")
    parts = re.split(r"^## ", text, flags=re.M)[1:]
    return {p.split("\n", 1)[0].strip(): p for p in parts}


LEAVES = list(commands(build_parser()))


def test_the_page_has_a_section_for_every_command():
    heads = sections()
    for path, _ in LEAVES:
        # the batch operations share one section: they are the single-file commands
        head = "quatspline " + (path[0] if path[0] == "batch" else " ".join(path))
        assert head in heads, f"docs/cli.md has no section '## {head}'"
        assert f"quatspline {' '.join(path)}" in heads[head] or path[0] == "batch", head


@pytest.mark.parametrize("path", [p for p, _ in LEAVES], ids=lambda p: " ".join(p))
def test_every_option_is_named_in_its_section_or_the_shared_one(path):
    parser = dict(LEAVES)[path]
    heads = sections()
    shared = heads["Options every command shares"]
    own = heads["quatspline " + (path[0] if path[0] == "batch" else " ".join(path))]
    # a batch operation has its single-file command's options ("imu-simulate": "imu simulate")
    single = heads.get("quatspline " + path[-1].replace("-", " "), "") if path[0] == "batch" else ""
    missing = [
        opt
        for action in parser._actions
        for opt in action.option_strings
        if opt.startswith("--") and opt != "--help"
        if not any(re.search(rf"`[^`]*{re.escape(opt)}\b", s) for s in (own, shared, single))
    ]
    assert not missing, f"docs/cli.md does not name {missing} for quatspline {' '.join(path)}"


def test_every_example_of_help_is_on_the_page():
    text = PAGE.read_text(encoding="utf-8")
    absent = sorted({e for lines in EXAMPLES.values() for e in lines if e not in text})
    assert not absent, f"docs/cli.md lacks these --help examples: {absent}"
