"""``--at FILE`` crossed with ``--derivatives``, ``--max-samples`` and ``--extrapolate``, for
``sample`` and ``fit``: the command writes what the library route writes (ops.sample,
ops.fit_trajectory with ops.times_from_file), byte for byte, or fails with its message."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline.io as qio
from quatspline import ops
from quatspline.cli import main

from ..splinekit import random_walk

T0 = 1_305_031_102.0
TUM = Path(__file__).resolve().parents[2] / "data" / "tum_rgbd_fr1_xyz"
TUM = TUM / "freiburg1_xyz-groundtruth.txt"


def recording(tmp_path, n=60, t0=T0):
    q = random_walk(n, 0, step=0.15)
    t = t0 + 0.05 * np.arange(n)
    p = np.random.default_rng(0).normal(size=(n, 3)) * 0.1
    tr = qio.Trajectory(t, q, p)
    qio.write(tmp_path / "est.tum", tr)
    return tr, tmp_path / "est.tum"


def at_file(tmp_path, kind: str, times: np.ndarray) -> Path:
    """A file of ``times`` in one of the forms ``--at`` accepts."""
    if kind == "times":
        path = tmp_path / "at.txt"
        path.write_text("# times\n" + "".join(f"{float(t)!r}\n" for t in times))
        return path
    other = qio.Trajectory(times, random_walk(len(times), 3), np.zeros((len(times), 3)))
    path = tmp_path / {"tum": "at.tum", "csv": "at.csv", "npz": "at.npz"}[kind]
    qio.write(path, other)
    return path


def library(command, traj, times, derivatives, max_samples, extrapolate):
    kw = {"times": times, "derivatives": derivatives, "extrapolate": extrapolate}
    if max_samples is not None:
        kw["max_samples"] = max_samples
    if command == "sample":
        return ops.sample(traj, **kw)  # the command's default method
    return ops.fit_trajectory(traj, smoothing=1e-4, **kw)[0]


@pytest.mark.parametrize("command", ["sample", "fit"])
@pytest.mark.parametrize("kind", ["times", "tum", "csv", "npz"])
@pytest.mark.parametrize("derivatives", [False, True])
@pytest.mark.parametrize("max_samples", [None, 3, 17])
@pytest.mark.parametrize("extrapolate", ["raise", "clamp"])
@pytest.mark.parametrize("outside", [False, True])
def test_at_crossed_with_derivatives_max_samples_extrapolate_writes_the_library_route(
    tmp_path, capsys, command, kind, derivatives, max_samples, extrapolate, outside
):
    tr, src = recording(tmp_path)
    times = np.array(tr.times[3:20], copy=True)
    if outside:
        times[-1] = tr.times[-1] + 0.4
    at = at_file(tmp_path, kind, times)
    out = tmp_path / "out.csv"
    argv = [command, str(src), "-o", str(out), "--at", str(at), "--extrapolate", extrapolate]
    if command == "fit":
        argv += ["--smoothing", "1e-4"]
    if derivatives:
        argv.append("--derivatives")
    if max_samples is not None:
        argv += ["--max-samples", str(max_samples)]
    traj = qio.read(src)
    read_back = ops.times_from_file(at)
    np.testing.assert_array_equal(read_back, times)  # the file's times, not every number
    try:
        want = library(command, traj, read_back, derivatives, max_samples, extrapolate)
    except ValueError as e:
        capsys.readouterr()
        code = main(argv)
        err = capsys.readouterr().err
        assert code == (2 if isinstance(e, ops.ParameterError) else 1)
        # the library's message in the options' spelling (max_samples → --max-samples)
        lib = str(e)[len("times") :].replace("max_samples", "--max-samples")
        assert err == f"quatspline: error: --at{lib}\n"
        assert not out.exists()
        assert (max_samples == 3) or (outside and extrapolate == "raise")
        return
    assert main(argv) == 0
    expected = tmp_path / "expected.csv"
    qio.write(expected, want)
    assert out.read_bytes() == expected.read_bytes()
    header = out.read_text().splitlines()[0].split(",")
    assert ("omega_x" in header and "jerk_z" in header) == derivatives
    assert len(qio.read(out)) == 17


@pytest.mark.parametrize("command", ["sample", "fit"])
def test_at_derivatives_writes_the_columns_of_the_count_route(tmp_path, command):
    """``sample --at FILE --derivatives`` wrote no ω/α/jerk columns (``--count`` did)."""
    tr, src = recording(tmp_path, t0=0.0)  # times on the clock exactly as the spline's
    by_count = tmp_path / "count.csv"
    argv = [command, str(src), "--derivatives"] + (
        ["--smoothing", "1e-4"] if command == "fit" else []
    )
    assert main([*argv, "--count", "9", "-o", str(by_count)]) == 0
    counted = qio.read(by_count)
    at = at_file(tmp_path, "times", counted.times)
    by_at = tmp_path / "at.csv"
    assert main([*argv, "--at", str(at), "-o", str(by_at)]) == 0
    assert by_at.read_text().splitlines()[0] == by_count.read_text().splitlines()[0]
    assert by_at.read_bytes() == by_count.read_bytes()


@pytest.mark.parametrize("command", ["sample", "fit"])
def test_at_honours_max_samples_in_one_wording(tmp_path, capsys, command):
    """``sample --at`` ignored ``--max-samples`` (17 samples written with a bound of 3); ``fit``
    worded the bound differently: one check, one message, exit 2, nothing written."""
    tr, src = recording(tmp_path)
    at = at_file(tmp_path, "times", tr.times[3:20])
    out = tmp_path / "o.csv"
    assert main([command, str(src), "-o", str(out), "--at", str(at), "--max-samples", "3"]) == 2
    err = capsys.readouterr().err
    assert err == "quatspline: error: --at: 17 samples is more than --max-samples = 3\n"
    assert not out.exists()


def test_sample_and_fit_word_out_of_range_times_alike(tmp_path, capsys):
    tr, src = recording(tmp_path)
    at = at_file(tmp_path, "tum", np.r_[tr.times[3:6], tr.times[-1] + 1.0])
    errors = []
    for command in ("sample", "fit"):
        assert main([command, str(src), "-o", str(tmp_path / "o.csv"), "--at", str(at)]) == 1
        errors.append(capsys.readouterr().err)
    assert errors[0] == errors[1]
    last = float(tr.times[-1])
    assert errors[0].startswith(
        f"quatspline: error: --at: times[3] = {last + 1.0!r} is after the trajectory's "
        f"last time {last!r}"
    )
    # and the library's resample says the same
    with pytest.raises(ValueError) as e:
        tr.resample(qio.read(at))
    assert errors[0] == f"quatspline: error: --at{str(e.value)[len('times') :]}\n"


def test_fit_at_a_tum_file_uses_its_times_not_every_number(tmp_path):
    """``fit … --at sub.txt``, a TUM file that ``sample --at`` accepts, read every number in it
    as a time: both commands sample at the file's 17 times."""
    sub = tmp_path / "sub.txt"
    lines = TUM.read_text().splitlines()
    sub.write_text("\n".join(lines[:3] + lines[100:117]) + "\n")
    want = qio.read(sub).times
    assert len(want) == 17
    for command in ("sample", "fit"):
        out = tmp_path / f"{command}.csv"
        assert main([command, str(TUM), "-o", str(out), "--at", str(sub)]) == 0
        np.testing.assert_array_equal(qio.read(out).times, want)


def test_fit_extrapolate_clamp_holds_the_end_pose(tmp_path, capsys):
    tr, src = recording(tmp_path)
    at = at_file(tmp_path, "times", np.r_[tr.times[-2], tr.times[-1] + 0.5])
    out = tmp_path / "o.csv"
    argv = ["fit", str(src), "-o", str(out), "--at", str(at), "--smoothing", "1e-4"]
    assert main([*argv, "--extrapolate", "clamp", "--derivatives"]) == 0
    got = qio.read(out)
    _, f = ops.fit_trajectory(tr, times=[tr.times[-1]], smoothing=1e-4)
    end = f.orientation(np.array([tr.times[-1] - tr.times[0]]))
    assert abs(np.sum(got.quats[1] * end[0])) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(got.positions[1], f.position(tr.times[-1] - tr.times[0]))
    omega = np.loadtxt(out, delimiter=",", skiprows=1)[:, 8:11]
    np.testing.assert_array_equal(omega[1], 0.0)
    with pytest.raises(SystemExit) as e:  # a fit has no linear or periodic extrapolation
        main([*argv, "--extrapolate", "linear"])
    assert e.value.code == 2
    assert "--extrapolate: invalid choice: 'linear'" in capsys.readouterr().err


def test_fit_prints_the_rms_residual_of_the_one_function(tmp_path, capsys, monkeypatch):
    """The CLI and batch each computed the RMS residual (one guarded an empty array)."""
    _, src = recording(tmp_path)
    monkeypatch.setattr(ops, "rms_residual_deg", lambda f: 12.3456)
    assert main(["fit", str(src), "-o", str(tmp_path / "o.csv"), "--count", "5"]) == 0
    assert "RMS residual 12.346°" in capsys.readouterr().out
