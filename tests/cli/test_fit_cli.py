"""``quatspline fit`` (thin CLI over quatspline.fit_trajectory) and fit/min_energy in
``compare`` and ``sample``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
from quatspline.cli import main

TUM = Path(__file__).resolve().parents[2] / "data" / "tum_rgbd_fr1_xyz"
TUM = TUM / "freiburg1_xyz-groundtruth.txt"


def test_fit_command_writes_samples_with_derivatives_and_positions(tmp_path, capsys):
    out = tmp_path / "fit.csv"
    argv = ["fit", str(TUM), "-o", str(out), "--rate", "50", "--derivatives", "--robust", "huber"]
    assert main(argv) == 0
    msg = capsys.readouterr().out
    assert "λ =" in msg and "effective dof" in msg
    traj = qs.io.read(TUM)
    got = qs.io.read(out)
    header = out.read_text().splitlines()[0].split(",")
    assert got.positions is not None and "omega_x" in header and "jerk_z" in header
    assert got.times[0] == traj.times[0]
    f = qs.fit(traj.times - traj.times[0], traj.quats, robust="huber")
    assert np.allclose(np.abs(np.sum(got.quats * f(got.times - traj.times[0]), 1)), 1, atol=1e-9)


def test_fit_command_at_times_and_fixed_smoothing(tmp_path):
    traj = qs.io.read(TUM)
    at = tmp_path / "at.txt"
    np.savetxt(at, traj.times[10:20])
    out = tmp_path / "o.npz"
    argv = ["fit", str(TUM), "-o", str(out), "--at", str(at), "--smoothing", "1e-4"]
    assert main([*argv, "--penalty", "jerk"]) == 0
    assert len(qs.io.read(out)) == 10


def test_fit_command_huge_smoothing_warns_in_one_line(tmp_path, capsys):
    """λ beyond what double precision resolves: fitted at the bound; the library's
    RuntimeWarning reaches the terminal as one line, like the errors."""
    t = np.linspace(0.0, 2.0, 50)
    src = tmp_path / "in.csv"
    qs.io.write(src, qs.io.Trajectory(t, qs.from_rotvec(np.stack([t, 0 * t, 0.2 * t**2], 1))))
    argv = ["fit", str(src), "-o", str(tmp_path / "o.csv"), "--count", "10"]
    assert main([*argv, "--smoothing", "1e20"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("quatspline: warning: smoothing: λ = 1e+20 is beyond what double")


def test_fit_command_takes_a_file_of_uneven_knots_on_the_recordings_clock(tmp_path):
    traj = qs.io.read(TUM)
    t = traj.times
    # denser knots in the first half: every sample interval there, every third after
    half = len(t) // 2
    knots = np.r_[t[:half], t[half:-1:3], t[-1]]
    kf = tmp_path / "knots.txt"
    np.savetxt(kf, knots, fmt="%.6f", header="knot times")
    knots = np.loadtxt(kf)
    knots[0], knots[-1] = t[0], t[-1]  # the file's rounding is within the fit's 1e-9 span rule
    out = tmp_path / "o.csv"
    argv = ["fit", str(TUM), "-o", str(out), "--count", "7", "--smoothing", "1e-4"]
    assert main([*argv, "--knots", str(kf)]) == 0
    f = qs.fit(t - t[0], traj.quats, positions=traj.positions, smoothing=1e-4, knots=knots - t[0])
    got = qs.io.read(out)
    ref = f.orientation(got.times - t[0])
    assert np.allclose(np.abs(np.sum(got.quats * ref, 1)), 1, atol=1e-9)
    assert np.allclose(got.positions, f.position(got.times - t[0]), atol=1e-9)
    # and a spacing is still a number
    assert main([*argv, "--knots", "0.1"]) == 0


def test_fit_command_bad_knot_file_is_one_line(tmp_path, capsys):
    kf = tmp_path / "k.txt"
    kf.write_text("0 1\n2 3\n")
    code = main(
        ["fit", str(TUM), "-o", str(tmp_path / "x.csv"), "--count", "5", "--knots", str(kf)]
    )
    err = capsys.readouterr().err
    assert code == 1 and "--knots" in err and f"{kf}:1: expected one time, got 2" in err
    assert err.count("\n") == 1
    code = main(["fit", str(TUM), "-o", str(tmp_path / "x.csv"), "--count", "5", "--knots", "nope"])
    err = capsys.readouterr().err
    assert code == 1 and "nope" in err and err.count("\n") == 1


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (["--smoothing", "lots", "--count", "5"], "--smoothing"),
        (["--smoothing", "-1", "--count", "5"], "smoothing"),
    ],
)
def test_fit_command_bad_options_exit_2_with_one_line(tmp_path, capsys, extra, match):
    code = main(["fit", str(TUM), "-o", str(tmp_path / "x.csv"), *extra])
    err = capsys.readouterr().err
    assert code in (1, 2) and match in err and err.count("\n") == 1


def test_compare_and_sample_select_fit_and_min_energy(tmp_path, capsys):
    assert main(["compare", str(TUM), "--methods", "natural,min_energy,fit", "--holdout", "4"]) == 0
    table = capsys.readouterr().out
    assert "min_energy" in table and "fit" in table
    out = tmp_path / "s.csv"
    assert (
        main(
            [
                "sample",
                str(TUM),
                "-o",
                str(out),
                "--method",
                "fit",
                "--count",
                "7",
                "--param",
                "smoothing=auto",
                "--param",
                "robust=huber",
            ]
        )
        == 0
    )
    assert len(qs.io.read(out)) == 7


@pytest.mark.parametrize(
    "args",
    [
        ["--robust", "cauchy"],
        ["--robust", "huber", "--penalty", "jerk"],
        ["--robust", "huber", "--penalty", "auto"],
    ],
)
def test_robust_pose_fits_of_the_bundled_tum_recording_converge(tmp_path, args, capsys):
    """Robust fits of the bundled TUM poses exited 1 after 30–54 s: the positions' IRLS ran
    out of its 1000 rounds while the orientations converged. The whole recording (3000 poses)."""
    out = tmp_path / "fit.csv"
    assert main(["fit", str(TUM), "-o", str(out), "--count", "20", *args]) == 0
    assert "wrote" in capsys.readouterr().out
    got = qs.io.read(out)
    ref = qs.io.read(TUM)
    assert len(got.times) == 20 and got.positions is not None
    # the samples follow the recording: within 5 cm of the nearest measured position
    nearest = np.abs(ref.times[None, :] - got.times[:, None]).argmin(axis=1)
    assert np.max(np.linalg.norm(got.positions - ref.positions[nearest], axis=1)) < 0.05
