"""Regression tests for the command line defects of issue 2.1 (each failed on main)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.cli import main

from ..conftest import random_quats


@pytest.fixture
def keys_csv(tmp_path):
    t = np.linspace(0.0, 3.9, 40)
    p = tmp_path / "keys.csv"
    qio.write(p, qio.Trajectory(t, random_quats(40, seed=7), np.column_stack([t, t, t])))
    return p


def test_compare_holdout_zero_is_a_usage_error(keys_csv, capsys):
    assert main(["compare", str(keys_csv), "--holdout", "0", "--methods", "slerp"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--holdout: expected an integer ≥ 2, got 0" in err


# ---- item 8: positions follow every method; formats that need positions refuse without ------
@pytest.mark.parametrize(
    "method", ["slerp", "c3", "bspline", "beta", "bezier", "cumulative_bezier"]
)
def test_sample_keeps_positions_for_every_method(tmp_path, keys_csv, method):
    out = tmp_path / "out.csv"
    assert main(["sample", str(keys_csv), "-o", str(out), "--method", method, "--count", "50"]) == 0
    t = qio.read(out)
    assert t.positions is not None
    # the natural cubic spline through the key positions (x = y = z = t here) reproduces them
    np.testing.assert_allclose(t.positions, np.column_stack([t.times] * 3), atol=1e-12)


@pytest.mark.parametrize(("ext", "fmt"), [(".txt", "TUM"), (".csv", "EuRoC")])
def test_tum_and_euroc_refuse_a_trajectory_without_positions(tmp_path, ext, fmt, capsys):
    src = tmp_path / "rot.csv"
    qio.write(src, qio.Trajectory([0.0, 1.0, 2.0], random_quats(3, seed=1)))
    out = tmp_path / f"out{ext}"
    args = ["sample", str(src), "-o", str(out), "--count", "5"]
    if fmt == "EuRoC":
        args += ["--format", "euroc"]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"the {fmt} format needs positions and this trajectory has none" in err
    assert not out.exists()


@pytest.mark.parametrize("ext", [".xlsx", ".parquet", ""])
def test_unknown_output_extension_is_refused_listing_the_formats(tmp_path, keys_csv, ext, capsys):
    out = tmp_path / f"out{ext}"
    assert main(["sample", str(keys_csv), "-o", str(out), "--count", "5"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown output extension" in err
    assert ".csv (csv), .json (json), .npz (npz)" in err
    assert not out.exists()
    with pytest.raises(ValueError, match="unknown output extension '.xlsx'"):
        qio.write(tmp_path / "x.xlsx", qio.read(keys_csv))


# ---- item 10: sample counts bounded before allocating; every error one line ----------------
@pytest.mark.parametrize(
    ("opt", "value", "text"),
    [
        ("--rate", "1e12", "--rate: 1e+12 samples per unit over [0, 3.9] gives 3.9e+12 samples"),
        ("--rate", "4e8", "--rate: 4e+08 samples per unit over [0, 3.9] gives 1.56e+09 samples"),
        ("--count", "1000000000000", "--count: 1000000000000 samples is more than --max-samples"),
        ("--rate", "nan", "--rate: expected a positive finite rate, got nan"),
        ("--rate", "-1", "--rate: expected a positive finite rate, got -1"),
        ("--count", "0", "--count: expected an integer ≥ 1, got 0"),
    ],
)
def test_huge_sample_counts_are_refused_before_allocating(
    tmp_path, keys_csv, opt, value, text, capsys
):
    out = tmp_path / "out.csv"
    assert main(["sample", str(keys_csv), "-o", str(out), opt, value]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and text in err
    assert not out.exists()


def test_max_samples_option_is_honoured(tmp_path, keys_csv, capsys):
    out = tmp_path / "out.csv"
    args = ["sample", str(keys_csv), "-o", str(out), "--count", "100", "--max-samples", "99"]
    assert main(args) == 2
    assert "--count: 100 samples is more than --max-samples = 99" in capsys.readouterr().err
    assert main([*args[:-1], "100"]) == 0
    assert len(qio.read(out)) == 100


def test_unexpected_errors_are_one_line_and_debug_shows_the_traceback(
    tmp_path, keys_csv, monkeypatch, capsys
):
    from quatspline import ops

    def boom(*a, **k):
        raise MemoryError("Unable to allocate 7.28 TiB")

    monkeypatch.setattr(ops, "sample", boom)
    args = ["sample", str(keys_csv), "-o", str(tmp_path / "o.csv"), "--count", "5"]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "out of memory (Unable to allocate 7.28 TiB)" in err
    assert main(["--debug", *args]) == 1
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and "MemoryError" in err

    def bug(*a, **k):
        raise KeyError("x")

    monkeypatch.setattr(ops, "sample", bug)
    assert main(args) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "KeyError" in err and "--debug" in err


def test_usage_errors_from_the_option_parser_are_one_line(keys_csv, capsys):
    """argparse printed the usage block and the error: two or more lines."""
    with pytest.raises(SystemExit) as e:
        main(["sample", str(keys_csv), "-o", "x.csv", "--count", "1e12"])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("quatspline sample: error: argument --count: invalid int value: '1e12'")
