"""Packaging (issue 2.6): version, metadata, the embedded recording, the demo's atomic output
and its behaviour without matplotlib."""

from __future__ import annotations

import hashlib
import importlib.metadata
import re
from pathlib import Path

import pytest
import quatspline as qs
from quatspline import cli, demo

ROOT = Path(__file__).resolve().parent.parent


def test_version_matches_metadata_and_changelog():
    assert qs.__version__ == importlib.metadata.version("quatspline")
    assert re.fullmatch(r"\d+\.\d+\.\d+", qs.__version__)
    assert f"## [{qs.__version__}]" in (ROOT / "CHANGELOG.md").read_text()
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert 'license = { text = "MIT" }' in pyproject
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_no_placeholder_urls():
    for name in ("pyproject.toml", "Cargo.toml", "README.md"):
        text = (ROOT / name).read_text()
        assert "example.invalid" not in text and "example.com" not in text, name


def test_bundled_recording_is_the_source_tree_copy():
    a = (ROOT / "python/quatspline/data/freiburg1_xyz-groundtruth.txt").read_bytes()
    b = (ROOT / "data/tum_rgbd_fr1_xyz/freiburg1_xyz-groundtruth.txt").read_bytes()
    assert a == b
    assert (
        hashlib.sha256(a).hexdigest()
        == "aac0319a6ef4e1cdf61e779d2152b95aa7e9f7b1749d6d18717b43ddabffede2"
    )
    rec = qs.examples.load_recording()
    assert rec.quats.shape == (3000, 4) and rec.positions.shape == (3000, 3)


def test_demo_without_matplotlib_writes_all_but_figures(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(demo, "_have_matplotlib", lambda: False)
    out = tmp_path / "out"
    assert cli.main(["demo", "-o", str(out)]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"report.md", "compare.md", "compare.json", "samples"} <= names
    assert not any(n.endswith(".png") for n in names)
    from quatspline.registry import interpolating_methods

    assert len(list((out / "samples").iterdir())) == len(interpolating_methods()) + 1
    lines = capsys.readouterr().out.splitlines()
    assert (
        lines[-1] == "figures skipped: matplotlib is not installed (pip install 'quatspline[plot]')"
    )
    assert ".png" not in (out / "report.md").read_text()
    assert list(tmp_path.iterdir()) == [out]  # no temporary directory left behind


def test_demo_failure_leaves_output_untouched(tmp_path, monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    (out / "report.md").write_text("old report")

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(demo, "_have_matplotlib", lambda: False)
    monkeypatch.setattr(demo, "compare", boom)
    with pytest.raises(RuntimeError, match="disk full"):
        demo.run(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt", "report.md"]
    assert (out / "report.md").read_text() == "old report"


def test_demo_replaces_files_of_a_previous_run_and_keeps_others(tmp_path, monkeypatch):
    monkeypatch.setattr(demo, "_have_matplotlib", lambda: False)
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    assert demo.run(out) == 0  # a previous run: its files are recorded in its manifest
    (out / "report.md").write_text("old report")
    assert demo.run(out) == 0
    assert (out / "keep.txt").read_text() == "mine"
    assert (out / "report.md").read_text().startswith("# quatspline demo")


def test_demo_refuses_a_file_as_output(tmp_path):
    f = tmp_path / "out"
    f.write_text("x")
    assert cli.main(["demo", "-o", str(f)]) == 1
    assert f.read_text() == "x"


def test_compiled_functions_have_running_examples():
    import doctest
    import inspect

    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    for fn in (qs.set_num_threads, qs.get_num_threads):
        assert "Examples\n--------" in inspect.cleandoc(fn.__doc__)
        tests = doctest.DocTestFinder().find(fn, fn.__name__, globs={})
        assert tests and tests[0].examples
        for t in tests:
            runner.run(t)
    assert runner.summarize(verbose=False).failed == 0
    assert qs.get_num_threads() >= 1
