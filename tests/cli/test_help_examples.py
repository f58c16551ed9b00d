"""Every command's ``--help`` ends with examples, and every example parses: its options exist
and take the values shown."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path

import pytest
from quatspline.arguments import EXAMPLES
from quatspline.cli._commands import build_parser, main


def _commands(p: argparse.ArgumentParser, name: str = ""):
    yield name, p
    for action in p._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub, sp in action.choices.items():
                yield from _commands(sp, f"{name} {sub}".strip())


COMMANDS = dict(_commands(build_parser()))


@pytest.mark.parametrize("command", sorted(COMMANDS), ids=lambda c: c or "quatspline")
def test_every_help_ends_with_examples(command):
    text = COMMANDS[command].format_help().rstrip()
    tail = text[text.rindex("examples:") :].splitlines()
    assert len(tail) >= 2 and all(line.startswith("  quatspline") for line in tail[1:])
    assert len(tail) - 1 == len(EXAMPLES[command or "quatspline"])


@pytest.mark.parametrize(
    "line", [line for lines in EXAMPLES.values() for line in lines], ids=lambda s: s[:60]
)
def test_every_example_parses(line):
    argv = shlex.split(line)
    assert argv[0] == "quatspline"
    args = build_parser().parse_args(argv[1:])  # argparse exits (SystemExit) on a bad option
    assert getattr(args, "func", None) is not None


def test_help_is_printed_with_its_examples(capsys):
    with pytest.raises(SystemExit) as e:
        main(["fit", "--help"])
    assert e.value.code == 0
    assert capsys.readouterr().out.rstrip().endswith(EXAMPLES["fit"][-1])


TUM = str(
    Path(__file__).resolve().parents[2]
    / "data"
    / "tum_rgbd_fr1_xyz"
    / "freiburg1_xyz-groundtruth.txt"
)


@pytest.mark.parametrize(
    "extra, expected",
    [
        (["--count", "100000000000"], "more than --max-samples = 10000000"),
        (
            ["--rate", "10", "--method", "c3", "--param", "alpha=abc"],
            "--param alpha: expected a number or 'auto', got 'abc'",
        ),
        (
            ["--rate", "10", "--method", "catmull_rom", "--param", "ends=loop"],
            '--param ends: catmull_rom does not support "loop"',
        ),
    ],
)
def test_messages_use_the_options_spelling(tmp_path, capsys, extra, expected):
    assert main(["sample", TUM, "-o", str(tmp_path / "out.csv"), *extra]) == 2
    err = capsys.readouterr().err
    assert expected in err and "max_samples" not in err
    assert not (tmp_path / "out.csv").exists()
