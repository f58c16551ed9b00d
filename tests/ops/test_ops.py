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
from quatspline.ops import IMPULSES, ParameterError, compare, format_table, sample_trajectory

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
            # None only where no finite RMS exists (an impulse at a C⁰/C¹ joint)
            assert type(v) in (str, float, int) or (v is None and k.startswith("rms_")), (k, v)


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


# ---- one route per operation: sample, fit, resample, compare ---------------------------------
def _outside_cases(traj):
    a, b = float(traj.times[0]), float(traj.times[-1])
    return {
        "before": [a + 0.5, a - 1.0],
        "after": [a + 0.5, b + 0.25],
        "all outside": [b + 1.0, b + 2.0],
        "nan": [a + 0.5, np.nan],
        "inf": [np.inf],
    }


@pytest.mark.parametrize("case", ["before", "after", "all outside", "nan", "inf"])
def test_out_of_range_times_are_worded_alike_by_sample_fit_and_resample(case):
    """``resample`` said "times[1] = … is before the trajectory's first time …", ``sample``
    "… is outside the recording's time range …": one raising helper words them all."""
    from quatspline.ops import check_times, fit_trajectory, sample

    traj = _traj()
    t = np.array(_outside_cases(traj)[case])
    with pytest.raises(ValueError) as ref:
        check_times(t, float(traj.times[0]), float(traj.times[-1]))
    calls = {
        "sample": lambda: sample(traj, "slerp", times=t),
        "sample_trajectory": lambda: sample_trajectory(traj, "c3", times=t, derivatives=True),
        "Trajectory.resample": lambda: traj.resample(t, method="natural"),
        "resample": lambda: quatspline.ops._resample.resample(traj, t),
        "fit_trajectory": lambda: fit_trajectory(traj, times=t, smoothing=1e-3),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError) as e:
            call()
        assert str(e.value) == str(ref.value), name
        assert type(e.value) is ValueError, name
    first = "times[0]" if case in ("all outside", "inf") else "times[1]"
    assert str(ref.value).startswith(f"times: {first} ")


def test_fit_trajectory_bounds_times_by_max_samples_in_the_words_of_sample():
    """fit said "times: 17 samples is more than 3", sample "… more than max_samples = 3"."""
    from quatspline.ops import fit_trajectory, sample

    traj = _traj()
    t = traj.times[3:20]
    with pytest.raises(ParameterError) as s:
        sample(traj, times=t, max_samples=3)
    with pytest.raises(ParameterError) as f:
        fit_trajectory(traj, times=t, max_samples=3)
    assert str(s.value) == str(f.value) == "times: 17 samples is more than max_samples = 3"


def test_fit_trajectory_refuses_bad_sample_times_before_fitting(monkeypatch):
    """The fit was computed (seconds on a long recording) before the times were checked."""
    import quatspline.ops._fit as fit_module

    def no_fit(*args, **kwargs):
        raise AssertionError("the fit ran before the sample times were checked")

    monkeypatch.setattr(fit_module, "fit", no_fit)
    traj = _traj()
    with pytest.raises(ValueError, match=r"^times: times\[0\] = 1000.0 is after"):
        fit_module.fit_trajectory(traj, times=[1000.0])
    with pytest.raises(ParameterError, match=r"^times: 3 samples is more than max_samples = 2"):
        fit_module.fit_trajectory(traj, times=traj.times[:3], max_samples=2)
    with pytest.raises(ParameterError, match=r"^rate, count, times: give exactly one"):
        fit_module.fit_trajectory(traj)
    with pytest.raises(ParameterError, match=r"^extrapolate: expected one of raise, clamp"):
        fit_module.fit_trajectory(traj, count=5, extrapolate="linear")


@pytest.mark.parametrize("positions", [True, False])
@pytest.mark.parametrize("extrapolate", ["raise", "clamp", "linear", "periodic"])
def test_resample_is_sample_at_times(positions, extrapolate):
    """Trajectory.resample had its own sampling code: it is ops.sample with ``times``."""
    from quatspline.ops import sample

    traj = _traj(positions=positions)
    a, b = float(traj.times[0]), float(traj.times[-1])
    t = np.linspace(a, b, 23) if extrapolate == "raise" else np.linspace(a - 0.7, b + 0.9, 23)
    got = traj.resample(t, method="natural", extrapolate=extrapolate)
    ref = sample(traj, "natural", times=t, extrapolate=extrapolate)
    np.testing.assert_array_equal(got.times, t)
    np.testing.assert_array_equal(got.quats, ref.quats)
    if positions:
        np.testing.assert_array_equal(got.positions, ref.positions)
    else:
        assert got.positions is None and ref.positions is None
    # independently: the spline of the method on the relative clock, with the same mode
    s = quatspline.spline("natural", traj.quats, traj.times - a)
    s.extrapolate = extrapolate
    np.testing.assert_allclose(np.abs(np.sum(got.quats * s(t - a), 1)), 1.0, atol=1e-12)


def test_sample_at_a_trajectory_keeps_its_exact_stamps_and_honours_every_option():
    from quatspline.ops import sample

    traj = _traj()
    ns = np.round(traj.times[4:9] * 1e9).astype(np.int64) + 3
    other = qio.Trajectory(ns * 1e-9, random_quats(5, seed=1), stamps_ns=ns)
    out = sample(traj, "c3", times=other, derivatives=True)
    np.testing.assert_array_equal(out.stamps_ns, ns)
    assert set(out.extra) == {"omega", "alpha", "jerk"}
    with pytest.raises(ParameterError, match="more than max_samples = 4"):
        sample(traj, "c3", times=other, max_samples=4)


def test_sample_times_of_the_wrong_kind_are_named():
    from quatspline.ops import sample

    traj = _traj()
    with pytest.raises(TypeError, match=r"^times: expected an array of times or a Trajectory"):
        sample(traj, times="at.txt")
    with pytest.raises(ValueError, match=r"^times: no times to sample at"):
        sample(traj, times=[])
    with pytest.raises(ValueError, match=r"^times: expected a 1-D array of times, got shape"):
        sample(traj, times=np.full((2, 2), 101.0))
    with pytest.raises(TypeError, match=r"^times: expected real numbers, got dtype bool"):
        sample(traj, times=[True, False])
    with pytest.raises(TypeError, match=r"^times: expected real numbers, got dtype bool"):
        sample(traj, times=np.array([True]))
    assert len(sample(traj, times=101.0)) == 1  # one time is a valid request


@pytest.mark.parametrize("route", ["sample", "fit"])
@pytest.mark.parametrize("derivatives", [False, True])
@pytest.mark.parametrize("max_samples", [None, 16, 17])
@pytest.mark.parametrize("extrapolate", ["raise", "clamp"])
@pytest.mark.parametrize("outside", [False, True])
def test_sample_and_fit_cross_times_derivatives_max_samples_extrapolate(
    route, derivatives, max_samples, extrapolate, outside
):
    """``times`` with every other option, for both routes: the samples at those times with
    the derivative columns asked for, the bound applied, the mode applied."""
    from quatspline.ops import fit_trajectory, sample

    traj = _traj()
    t = np.array(traj.times[3:20], copy=True)
    if outside:
        t[-1] = traj.times[-1] + 0.5
    kw = {"times": t, "derivatives": derivatives, "extrapolate": extrapolate}
    if max_samples is not None:
        kw["max_samples"] = max_samples

    def run(**kw):
        if route == "sample":
            return sample(traj, "c3", **kw), None
        return fit_trajectory(traj, smoothing=1e-4, **kw)

    if max_samples == 16:
        with pytest.raises(ParameterError, match="^times: 17 samples is more than max_samples"):
            run(**kw)
        return
    if outside and extrapolate == "raise":
        with pytest.raises(ValueError, match=r"^times: times\[16\] = 104.4 is after"):
            run(**kw)
        return
    out, f = run(**kw)
    np.testing.assert_array_equal(out.times, t)
    assert set(out.extra) == ({"omega", "alpha", "jerk"} if derivatives else set())
    rel = t - traj.times[0]
    curve = quatspline.spline("c3", traj.quats, traj.times - traj.times[0]) if f is None else f
    curve = curve.rotation if f is not None else curve
    curve.extrapolate = extrapolate
    np.testing.assert_allclose(np.abs(np.sum(out.quats * curve(rel), 1)), 1.0, atol=1e-12)
    if outside:  # clamped: the end pose held, at rest
        np.testing.assert_allclose(
            np.abs(np.sum(out.quats[-1] * curve(rel[-2:-1] * 0 + curve.domain[1]), 1)),
            1.0,
            atol=1e-12,
        )
        if derivatives:
            np.testing.assert_array_equal(out.extra["omega"][-1], 0.0)
    if derivatives:
        np.testing.assert_allclose(out.extra["omega"], curve.angular_velocity(rel), atol=1e-12)
        np.testing.assert_allclose(out.extra["jerk"], curve.jerk(rel), atol=1e-9)
    assert out.positions is not None and out.positions.shape == (17, 3)


def test_fit_trajectory_lives_in_ops_and_the_fitting_layer_does_not_import_ops():
    """fitting/smoothing.py imported ``ops`` (a layer above it) inside fit_trajectory."""
    import ast
    import inspect

    import quatspline.fitting.smoothing as smoothing
    from quatspline.ops import fit_trajectory

    assert quatspline.fit_trajectory is fit_trajectory
    assert fit_trajectory.__module__ == "quatspline.ops._fit"
    assert not hasattr(smoothing, "fit_trajectory")
    tree = ast.parse(inspect.getsource(smoothing))
    imported = [
        (node.level, node.module or "", [a.name for a in node.names])
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom)
    ]
    for level, module, names in imported:
        assert not module.startswith("ops") and "ops" not in names, (level, module, names)


def test_sample_trajectory_is_the_same_function_as_sample():
    from quatspline import ops

    assert ops.sample_trajectory is ops.sample


def test_rms_residual_of_a_fit_without_residuals_is_zero_not_nan():
    """The CLI computed √mean(r²) unguarded (NaN and a RuntimeWarning for no residuals),
    batch guarded it: one function, used by both."""
    from types import SimpleNamespace

    from quatspline.ops import fit_trajectory, rms_residual_deg

    assert rms_residual_deg(SimpleNamespace(residuals=np.array([]))) == 0.0
    assert rms_residual_deg(SimpleNamespace(residuals=[])) == 0.0
    r = np.radians([1.0, 2.0, 2.0])  # √((1 + 4 + 4)/3) = √3 degrees
    assert rms_residual_deg(SimpleNamespace(residuals=r)) == pytest.approx(np.sqrt(3.0), 1e-14)
    _, f = fit_trajectory(_traj(), count=5, smoothing=1e-3)
    expected = np.sqrt(sum(np.degrees(x) ** 2 for x in f.residuals) / len(f.residuals))
    assert rms_residual_deg(f) == pytest.approx(expected, rel=1e-12)


def test_times_from_file_reads_a_times_file_or_any_trajectory_file(tmp_path):
    """``--at`` files: one number a line (KITTI times, comments) or a trajectory file of any
    readable format, whose times are used (not every number in it)."""
    from quatspline.ops import times_from_file

    traj = _traj()
    want = traj.times[2:19]
    sub = qio.Trajectory(want, traj.quats[2:19], traj.positions[2:19])
    for name in ("sub.tum", "sub.txt", "sub.csv", "sub.json", "sub.npz"):
        fmt = "tum" if name == "sub.txt" else None
        qio.write(tmp_path / name, sub, format=fmt)
        np.testing.assert_array_equal(times_from_file(tmp_path / name), want, err_msg=name)
    plain = tmp_path / "times.txt"
    plain.write_text("# times\n" + "".join(f"{float(t)!r}\n" for t in want))
    np.testing.assert_array_equal(times_from_file(str(plain)), want)
    kitti = tmp_path / "kitti_times.txt"
    kitti.write_text("0.000000e+00\n1.036130e-01\n2.072260e-01\n")
    np.testing.assert_array_equal(times_from_file(kitti), [0.0, 0.103613, 0.207226])
    bad = tmp_path / "bad.txt"
    bad.write_text("1.0 2.0 3.0\n")
    with pytest.raises(ValueError, match=r"^times: .*bad\.txt.*not a file of times"):
        times_from_file(bad)
    empty = tmp_path / "empty.txt"
    empty.write_text("# nothing\n")
    with pytest.raises(ValueError, match=r"^times: .*empty\.txt: the file holds no times"):
        times_from_file(empty)
    with pytest.raises(TypeError, match=r"^times: expected a file path, got list"):
        times_from_file([1.0])
    with pytest.raises(ValueError, match=r"^times: .*missing\.txt: no such file$"):
        times_from_file(tmp_path / "missing.txt")
    with pytest.raises(
        ValueError, match=r"^times: .*: is a directory; only regular files are read$"
    ):
        times_from_file(tmp_path)


def test_compare_is_the_route_of_the_cli(tmp_path, capsys, monkeypatch):
    """``quatspline compare --json`` prints what ops.compare returns (no CLI-side figures)."""
    import json

    from quatspline import ops
    from quatspline.cli import main

    traj = _traj()
    p = tmp_path / "k.csv"
    qio.write(p, traj)
    assert main(["compare", str(p), "--methods", "slerp,natural", "--holdout", "3", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got == compare(qio.read(p), ["slerp", "natural"], 3)
    seen = []
    monkeypatch.setattr(ops, "compare", lambda *a, **k: seen.append((a, k)) or [])
    assert main(["compare", str(p), "--json"]) == 0
    assert seen and seen[0][1]["methods"] is None  # no --methods: the library's default list


def test_compare_gives_no_rms_for_an_impulse_and_the_table_names_units():
    """A C⁰ method's α is an impulse at every joint (ω jumps): no finite RMS exists, so
    ``compare`` reports None and the table says "impulses" rather than "rms α 0"; a C¹
    method has no finite RMS jerk. Headers carry units."""
    t = np.linspace(0.0, 3.0, 13)
    rv = np.stack([np.sin(t), 0.3 * t**2, np.cos(2 * t)], axis=1)
    rows = compare(qio.Trajectory(t, quatspline.from_rotvec(rv)), ["slerp", "squad", "natural"])
    by = {r["method"]: r for r in rows}
    assert by["slerp"]["continuity_order"] == 0
    assert by["slerp"]["rms_acceleration"] is None and by["slerp"]["rms_jerk"] is None
    assert by["squad"]["continuity_order"] == 1
    assert by["squad"]["rms_acceleration"] > 0 and by["squad"]["rms_jerk"] is None
    assert by["natural"]["rms_acceleration"] > 0 and by["natural"]["rms_jerk"] > 0
    table = format_table(rows)
    head, _, slerp_line, squad_line, _ = table.splitlines()
    for unit in ("(rad/s)", "(rad/s²)", "(rad/s³)", "(rad)"):
        assert unit in head
    assert slerp_line.count(IMPULSES) == 2
    assert squad_line.count(IMPULSES) == 1
