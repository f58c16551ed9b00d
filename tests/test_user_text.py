"""What a user reads holds no development history: no issue numbers, no "wave N", no load
averages or timestamps of a measurement session — in the README, the docs, the changelog,
every ``--help`` and the package's own text (docstrings and messages)."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest
from quatspline.cli._commands import build_parser

ROOT = Path(__file__).resolve().parents[1]

HISTORY = re.compile(
    r"\bissues? #?\d+(\.\d+)?\b"  # "issue 2.2", "issues 3.1"
    r"|\bwave[- ]\d+\b"  # "wave 2"
    r"|\bload(?: average)?\s*(?:of\s*|≈\s*|~\s*|=\s*|about\s*)?\d"  # "load 0.6", "load average ≈ 7"
    r"|\bat a load\b"
    r"|\b20\d\d-\d\d-\d\d \d\d:\d\d UTC\b",  # a session's timestamp
    re.IGNORECASE,
)


def _user_files() -> list[Path]:
    docs = ROOT / "docs"
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md"]
    for pattern in ("*.md", "*.rst", "maths/*.rst", "api/*.rst"):
        files += sorted(docs.glob(pattern))
    files += sorted((ROOT / "python" / "quatspline").rglob("*.py"))
    files += sorted((ROOT / "examples").glob("*.py"))
    return [f for f in files if f.is_file()]


def _offences(text: str) -> list[str]:
    out = []
    for no, line in enumerate(text.splitlines(), 1):
        for m in HISTORY.finditer(line):
            out.append(f"{no}: …{line[max(0, m.start() - 30) : m.end() + 10]}…")
    return out


@pytest.mark.parametrize("path", _user_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_user_text_holds_no_development_history(path):
    offences = _offences(path.read_text(encoding="utf-8"))
    assert not offences, f"{path.relative_to(ROOT)}:\n" + "\n".join(offences)


def _parsers(p: argparse.ArgumentParser, name: str = "quatspline"):
    yield name, p
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub, sp in action.choices.items():
                yield from _parsers(sp, f"{name} {sub}")


def test_no_help_holds_development_history():
    for name, p in _parsers(build_parser()):
        offences = _offences(p.format_help())
        assert not offences, f"{name} --help:\n" + "\n".join(offences)


@pytest.mark.parametrize(
    "text",
    [
        "as issue 2.2 asked",
        "Wave 3 added it",
        "at a load of 1.2",
        "load average ≈ 7",
        "2026-11-24 20:42 UTC",
    ],
)
def test_the_history_pattern_catches_what_it_is_for(text):
    assert _offences(text)


@pytest.mark.parametrize("text", ["a payload of 3 keys", "np.load(path)", "the issue is numerical"])
def test_the_history_pattern_leaves_ordinary_words(text):
    assert not _offences(text)
