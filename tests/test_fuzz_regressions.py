"""Replays every fuzzer finding kept in fuzz/regressions/ through its fuzz target's invariant.

``fuzz/regressions/readers``: inputs that once broke a reader (first found by atheris as the
``crash-*`` files that sat at the repository root): each must now read or raise a ValueError
naming the file. The splines target's findings are Rust regression tests in
crates/quatspline/tests/splines.rs.
"""

from __future__ import annotations

import importlib.util
import pathlib

import pytest
import quatspline.io as qio

ROOT = pathlib.Path(__file__).resolve().parents[1]
FINDINGS = sorted((ROOT / "fuzz" / "regressions" / "readers").glob("*"))


def _module():
    spec = importlib.util.spec_from_file_location(
        "readers_check", ROOT / "fuzz" / "readers_check.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _check():
    return _module().check_one


def test_readers_fuzzer_reaches_every_format_the_library_reads(tmp_path):
    """The fuzzer's formats are the readers' formats, and the corpus holds a valid seed of
    every entry (file names, bag directories) that reads back as a trajectory."""
    mod = _module()
    assert set(mod.FORMATS) == set(qio.FORMATS)
    fuzz_source = (ROOT / "fuzz" / "readers_fuzz.py").read_text()
    assert "readers_check.check_one" in fuzz_source and "NAMES" not in fuzz_source
    seeds = sorted((ROOT / "fuzz" / "corpus" / "readers").glob("seed-*"))
    reached = set()
    for seed in seeds:
        data = seed.read_bytes()
        got = mod.check_one(data, str(tmp_path))
        assert isinstance(got, qio.Trajectory), (seed.name, got)
        reached.add(data[0] % len(mod.ENTRIES))
    assert reached == set(range(len(mod.ENTRIES)))
    assert {mod.ENTRIES[k][1] for k in reached} >= set(qio.FORMATS)


def test_the_two_root_crash_files_are_kept_as_regressions():
    names = {p.name for p in FINDINGS}
    assert "crash-06c1074c6b1d703b528bb7a27e7538099510c429" in names
    assert "crash-756455bc670cff15626279597f095914eea59326" in names
    assert not list(ROOT.glob("crash-*")), "fuzzer crash files belong in fuzz/regressions/"


@pytest.mark.parametrize("path", FINDINGS, ids=[p.name for p in FINDINGS])
def test_reader_fuzz_finding_is_a_value_error_naming_the_file(path, tmp_path):
    _check()(path.read_bytes(), str(tmp_path))
