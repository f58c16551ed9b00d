"""``quatspline fit --uncertainty`` (and ``batch fit --uncertainty``): the fit's posterior
standard deviations as extra columns of formats that hold them, a clear error before any work
for those that do not, and the input never overwritten."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
from quatspline.cli import main

TUM = Path(__file__).resolve().parents[2] / "data" / "tum_rgbd_fr1_xyz"
TUM = TUM / "freiburg1_xyz-groundtruth.txt"


def test_uncertainty_adds_std_columns_equal_to_the_fits(tmp_path, capsys):
    out = tmp_path / "fit.csv"
    argv = ["fit", str(TUM), "-o", str(out), "--count", "40", "--uncertainty", "--derivatives"]
    assert main(argv) == 0
    assert "noise σ̂" in capsys.readouterr().out
    header = out.read_text().splitlines()[0].split(",")
    for name in ("orientation_std", "position_std", "omega_std"):
        assert [f"{name}_{a}" for a in "xyz"] == [h for h in header if h.startswith(name)]
    traj = qs.io.read(TUM)
    got = np.genfromtxt(out, delimiter=",", names=True)
    f = qs.fit(traj.times - traj.times[0], traj.quats, positions=traj.positions)
    t = got["t"] - traj.times[0]
    want = f.std(t)
    np.testing.assert_allclose(
        got["orientation_std_y"], want[:, 1], rtol=1e-5
    )  # the CSV writer's digits
    np.testing.assert_allclose(
        got["position_std_z"], f.position_std(t)[:, 2], rtol=1e-5
    )  # the CSV writer's digits
    np.testing.assert_allclose(
        got["omega_std_x"], f.angular_velocity_std(t)[:, 0], rtol=1e-5
    )  # the CSV writer's digits
    assert np.all(got["orientation_std_x"] > 0)


def test_uncertainty_in_npz_and_batch(tmp_path):
    out = tmp_path / "fit.npz"
    assert main(["fit", str(TUM), "-o", str(out), "--count", "7", "--uncertainty"]) == 0
    with np.load(out) as z:
        assert z["orientation_std"].shape == (7, 3) and "omega_std" not in z
    d = tmp_path / "b"
    assert main(["batch", "fit", str(TUM), "-o", str(d), "--count", "7", "--uncertainty"]) == 0
    header = next(d.glob("*.csv")).read_text().splitlines()[0]
    assert "orientation_std_x" in header and "position_std_x" in header


@pytest.mark.parametrize("name", ["out.txt", "out.bvh", "out.gltf"])
def test_uncertainty_is_refused_for_formats_without_extra_columns(tmp_path, capsys, name):
    out = tmp_path / name
    assert main(["fit", str(TUM), "-o", str(out), "--count", "5", "--uncertainty"]) != 0
    err = capsys.readouterr().err
    assert "--uncertainty" in err and "no columns" in err and "csv, json, npz" in err
    assert not out.exists()


def test_uncertainty_of_an_interpolating_fit_is_an_error_and_the_input_is_kept(tmp_path, capsys):
    t = np.linspace(0.0, 1.0, 20)
    src = tmp_path / "in.csv"
    qs.io.write(src, qs.io.Trajectory(t, qs.from_rotvec(np.outer(t, [0, 0, 1.0]))))
    before = src.read_bytes()
    argv = ["fit", str(src), "-o", str(tmp_path / "o.csv"), "--count", "5", "--uncertainty"]
    assert main([*argv, "--smoothing", "0"]) != 0
    assert "smoothing" in capsys.readouterr().err
    assert not (tmp_path / "o.csv").exists()
    assert main(["fit", str(src), "-o", str(src), "--count", "5", "--uncertainty"]) != 0
    assert src.read_bytes() == before
