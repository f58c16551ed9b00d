"""``quatspline fit`` (thin CLI over quatspline.fit_trajectory) and fit/min_energy in
``compare`` and ``sample``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
from quatspline.cli import main

TUM = Path(__file__).resolve().parent.parent / "data" / "tum_rgbd_fr1_xyz"
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
