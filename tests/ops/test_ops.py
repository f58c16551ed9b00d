"""quatspline.ops: the library operations behind the CLI (sample, compare, tables), their
docstring examples, and the defects of issue 2.1 that lived in the CLI."""

from __future__ import annotations

import doctest

import numpy as np
import pytest
import quatspline.core.metrics
import quatspline.io as qio
import quatspline.ops._compare
import quatspline.ops._fit
import quatspline.ops._ops
import quatspline.ops._resample
import quatspline.ops._sample
from quatspline.ops import ParameterError, compare, format_table, sample_trajectory

from ..conftest import random_quats


@pytest.mark.parametrize(
    "module",
    [
        quatspline.ops._ops,
        quatspline.ops._sample,
        quatspline.ops._fit,
        quatspline.ops._compare,
        quatspline.ops._resample,
        quatspline.core.metrics,
    ],
    ids=lambda m: m.__name__,
)
def test_docstring_examples_run(module):
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0


def _traj(n=40, positions=True):
    t = np.linspace(0.0, 3.9, n)
    q = random_quats(n, seed=5)
    q = q * np.sign(np.cumsum(np.ones(n)))[:, None]
    pos = np.column_stack([np.sin(t), np.cos(t), t]) if positions else None
    return qio.Trajectory(t + 100.0, q, pos)


def test_compare_returns_plain_numbers():
    rows = compare(_traj(), ["slerp", "natural"], holdout=3)
    assert [r["method"] for r in rows] == ["slerp", "natural"]
    for r in rows:
        for k, v in r.items():
            assert type(v) in (str, float, int), (k, type(v))


def test_compare_holdout_zero_is_an_error_not_no_holdout():
    with pytest.raises(ParameterError, match=r"^holdout: expected an integer ≥ 2, got 0"):
        compare(_traj(), ["slerp"], holdout=0)
    with pytest.raises(TypeError, match="^holdout"):
        compare(_traj(), ["slerp"], holdout=2.5)


def _cells(line: str) -> list[str]:
    """Cells of a GitHub-flavoured Markdown table row (``\\|`` is an escaped pipe)."""
    import re

    assert line.startswith("|") and line.endswith("|"), line
    return re.split(r"(?<!\\)\|", line[1:-1])


def test_markdown_tables_escape_pipes_so_renderers_show_a_table(tmp_path, capsys):
    """main printed ``max |ω|`` in the header: every renderer saw a ragged table."""
    from quatspline.cli import main

    p = tmp_path / "k.csv"
    qio.write(p, _traj())
    assert main(["compare", str(p), "--methods", "slerp,c3", "--holdout", "3"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    widths = {len(_cells(line)) for line in lines}
    assert widths == {10}, lines[0]
    assert set(_cells(lines[1])) <= {"---", "---:"}
    assert "np." not in "\n".join(lines)
    rows = [{"method": "odd|name\\", "max_speed": np.float64(2.5), "continuity_order": 3}]
    table = format_table(rows).splitlines()
    assert [len(_cells(line)) for line in table] == [3, 3, 3]
    assert table[2] == "| odd\\|name\\\\ | 2.5 | 3 |"


def test_error_messages_have_no_numpy_reprs(tmp_path):
    p = tmp_path / "dup.csv"
    p.write_text("t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0,0\n1,1,0,0,0\n")
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "duplicate timestamp 1.0 after 1.0" in str(e.value)
    assert "np." not in str(e.value)


def test_sample_times_outside_the_recording_are_named_on_its_clock():
    """The spline runs on times relative to the first key: main's message gave those."""
    traj = _traj()  # times 100 … 103.9
    with pytest.raises(
        ValueError,
        match=r"^times: times\[1\] = 99.0 is before the trajectory's first time 100.0 "
        r"\(range \[100.0, 103.9\]",
    ):
        sample_trajectory(traj, "slerp", times=[100.5, 99.0])
    with pytest.raises(ValueError, match=r"^times: times\[0\] is nan"):
        sample_trajectory(traj, "slerp", times=[np.nan])
    out = sample_trajectory(traj, "slerp", times=[100.0, 101.25, 103.9])
    np.testing.assert_array_equal(out.times, [100.0, 101.25, 103.9])


def test_sample_trajectory_argument_kinds():
    traj = _traj()
    with pytest.raises(TypeError, match="^trajectory: expected a quatspline.io.Trajectory"):
        sample_trajectory("file.csv", count=3)
    with pytest.raises(ParameterError, match="^rate, count, times: give exactly one"):
        sample_trajectory(traj, rate=2.0, count=3)
    with pytest.raises(TypeError, match="^count: expected an integer"):
        sample_trajectory(traj, count=2.7)
    with pytest.raises(ParameterError, match="^method: unknown method 'nope'"):
        sample_trajectory(traj, "nope", count=3)
    with pytest.raises(ParameterError, match="^alpha: "):
        sample_trajectory(traj, "c3", count=3, params={"alpha": "x"})


@pytest.mark.parametrize("rate", [1e308, 1.7976931348623157e308])
def test_sample_count_of_an_overflowing_rate_is_refused_not_overflow_error(rate):
    from quatspline.ops import sample_times

    with pytest.raises(ParameterError, match=r"^rate: .* gives inf samples, more than max_samples"):
        sample_times((0.0, 10.0), rate=rate)


def test_sampling_in_chunks_under_a_progress_bar_equals_one_call(monkeypatch):
    import quatspline.ops._sample as ops

    keys = quatspline.from_rotvec([[0, 0, 0], [0, 0, 0.5], [0, 0.4, 1.0], [0.2, 0.1, 1.5]])
    traj = qio.Trajectory([0.0, 1.0, 2.0, 3.0], keys)
    whole = ops.sample_trajectory(traj, "c3", count=1001, derivatives=True)
    monkeypatch.setattr(ops, "SAMPLE_CHUNK", 64)
    chunked = ops.sample_trajectory(traj, "c3", count=1001, derivatives=True)
    np.testing.assert_array_equal(chunked.quats, whole.quats)
    for k in ("omega", "alpha", "jerk"):
        np.testing.assert_array_equal(chunked.extra[k], whole.extra[k])
