"""``quatspline imu simulate`` and ``quatspline imu calibrate``: thin commands over
quatspline.ops.simulate_imu / calibrate_imu, checked against independent computations."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline._util.options import DEFAULT_METHOD
from quatspline.cli import main

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
REPO = DATA / "repoimu" / "repoIMU_first30s.csv"
G = np.array([0.0, 0.0, -9.80665])

NOISE = """accelerometer_noise_density: 0.02
accelerometer_random_walk: 0.0
gyroscope_noise_density: 0.002
gyroscope_random_walk: 0.0
update_rate: 100.0
"""


def _short_tum(tmp_path: Path, rows: int = 300) -> Path:
    src = qio.read(TUM)
    p = tmp_path / "poses.txt"
    qio.write(p, qio.Trajectory(src.times[:rows], src.quats[:rows], src.positions[:rows]))
    return p


def test_simulate_writes_exact_gyro_and_specific_force(tmp_path, capsys):
    """The EuRoC file holds ω_body and Rᵀ(p̈ − g) of the default pose spline through the keys,
    computed here from the spline's own derivatives, at first key + k / rate."""
    src = _short_tum(tmp_path)
    out = tmp_path / "imu.csv"
    assert main(["imu", "simulate", str(src), "-o", str(out), "--rate", "100"]) == 0
    assert "gyroscope and accelerometer" in capsys.readouterr().out
    traj = qio.read(src)
    got = qio.read_imu(out)
    rel = traj.times - traj.times[0]
    pose = qs.PoseSpline(traj.quats, rel, traj.positions, rotation=DEFAULT_METHOD)
    t = np.arange(got.times.size) / 100.0
    np.testing.assert_allclose(got.times, traj.times[0] + t, atol=1e-9)  # ns stamps
    np.testing.assert_allclose(got.gyro, pose.angular_velocity(t, frame="body"), atol=1e-9)
    q = pose.orientation(t)
    f = qs.rotate(qs.conjugate(q), pose.linear_acceleration(t) - G)
    np.testing.assert_allclose(got.accel, f, atol=1e-8)


def test_simulate_noise_is_seeded_and_has_the_density(tmp_path):
    src = _short_tum(tmp_path, 600)
    (tmp_path / "imu.yaml").write_text(NOISE)
    runs = {}
    for name, seed in (("a", "1"), ("b", "1"), ("c", "2"), ("exact", None)):
        out = tmp_path / f"{name}.csv"
        argv = ["imu", "simulate", str(src), "-o", str(out), "--rate", "100"]
        if seed is not None:
            argv += ["--noise", str(tmp_path / "imu.yaml"), "--seed", seed]
        assert main(argv) == 0
        runs[name] = qio.read_imu(out)
    assert np.array_equal(runs["a"].gyro, runs["b"].gyro)
    assert not np.array_equal(runs["a"].gyro, runs["c"].gyro)
    # white noise per sample: σ √rate = 0.002 √100 = 0.02 rad/s (within 10 %)
    std = np.std(runs["a"].gyro - runs["exact"].gyro)
    assert abs(std / (0.002 * math.sqrt(100.0)) - 1.0) < 0.1


def test_simulate_with_fit_uses_the_smoothing_fit(tmp_path):
    src = _short_tum(tmp_path)
    out = tmp_path / "imu.csv"
    assert main(["imu", "simulate", str(src), "-o", str(out), "--rate", "50", "--fit"]) == 0
    traj = qio.read(src)
    rel = traj.times - traj.times[0]
    f = qs.fit(rel, traj.quats, positions=traj.positions)
    got = qio.read_imu(out)
    t = np.arange(got.times.size) / 50.0
    np.testing.assert_allclose(got.gyro, f.angular_velocity(t, frame="body"), atol=1e-9)


@pytest.mark.parametrize(
    ("extra", "code", "match"),
    [
        (["--rate", "0"], 2, "--rate"),
        (["--rate", "100", "--method", "nope"], 2, "nope"),
        (["--rate", "1e9"], 2, "more than --max-samples"),
    ],
)
def test_simulate_bad_options(tmp_path, capsys, extra, code, match):
    src = _short_tum(tmp_path)
    assert main(["imu", "simulate", str(src), "-o", str(tmp_path / "o.csv"), *extra]) == code
    assert match in capsys.readouterr().err


def test_simulate_refuses_outputs(tmp_path, capsys):
    src = _short_tum(tmp_path)
    csv = tmp_path / "in.csv"
    qio.write(csv, qio.read(src))
    assert main(["imu", "simulate", str(csv), "-o", str(csv), "--rate", "10"]) == 2
    assert "refusing to overwrite the input file" in capsys.readouterr().err
    assert main(["imu", "simulate", str(src), "-o", str(tmp_path / "o.json"), "--rate", "10"]) == 2
    assert ".csv (EuRoC" in capsys.readouterr().err
    (tmp_path / "imu.yaml").write_text("gyroscope_noise_density: 0.1\n")
    argv = ["imu", "simulate", str(src), "-o", str(tmp_path / "o.csv"), "--rate", "10"]
    assert main([*argv, "--noise", str(tmp_path / "imu.yaml")]) == 1
    assert "accelerometer_noise_density" in capsys.readouterr().err
    assert not (tmp_path / "o.csv").exists()


def test_calibrate_repoimu_prints_table_json_and_figure(tmp_path, capsys):
    fig, js = tmp_path / "cal.png", tmp_path / "cal.json"
    argv = ["imu", "calibrate", str(REPO), str(REPO), "--figure", str(fig), "--json", str(js)]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert "quatspline: warning: calibrate: the motion excites" in err  # one line
    for row in ("rotation R_bs", "gyro bias", "scale", "time offset (ms)", "RMS residual"):
        assert row in out
    doc = json.loads(js.read_text())
    assert doc["samples"] > 2900 and len(doc["standard_errors"]["gyro_bias"]) == 3
    assert abs(doc["time_offset"]) < 1.0 and fig.stat().st_size > 0
    # the JSON is the library's result, not a second computation
    with pytest.warns(RuntimeWarning, match="weakly"):
        cal = qs.imu.calibrate(qio.read(REPO), qio.read_imu(REPO))
    assert doc["time_offset"] == cal.time_offset
    assert doc["rms"] == cal.rms.tolist()


@pytest.mark.parametrize(
    ("extra", "code", "match"),
    [
        (["--estimate", "rotation,offset"], 2, "--estimate"),
        (["--max-offset", "-1"], 2, "--max-offset"),
        (["--max-offset", "soon"], 2, "--max-offset"),
        (["--smoothing", "lots"], 2, "--smoothing"),
        (["--figure", "x.txt"], 2, "--figure"),
    ],
)
def test_calibrate_bad_options(capsys, extra, code, match):
    assert main(["imu", "calibrate", str(REPO), str(REPO), *extra]) == code
    assert match in capsys.readouterr().err


def test_calibrate_refuses_to_write_over_an_input(tmp_path, capsys):
    imu = tmp_path / "imu.csv"
    qio.write_imu(imu, qio.ImuData(*_gyro_only()))
    argv = ["imu", "calibrate", str(REPO), str(imu), "--json", str(imu)]
    assert main(argv) == 2
    assert "--json" in capsys.readouterr().err  # .csv is not .json
    traj = tmp_path / "t.json"
    qio.write(traj, qio.read(REPO))
    assert main(["imu", "calibrate", str(traj), str(imu), "--json", str(traj)]) == 2
    assert "refusing to overwrite the input file" in capsys.readouterr().err


def _gyro_only():
    d = qio.read_imu(REPO)
    return d.times, d.gyro


def test_calibrate_disjoint_times_is_bad_data(tmp_path, capsys):
    t, g = _gyro_only()
    imu = tmp_path / "late.csv"
    qio.write_imu(imu, qio.ImuData(t + 1000.0, g))
    assert main(["imu", "calibrate", str(REPO), str(imu)]) == 1
    assert "do not overlap" in capsys.readouterr().err


def test_help_ends_with_examples_and_runs_as_a_program(tmp_path):
    for cmd in ("simulate", "calibrate"):
        r = subprocess.run(
            [sys.executable, "-m", "quatspline", "imu", cmd, "--help"],
            capture_output=True,
            text=True,
            check=True,
        )
        tail = r.stdout.rstrip().splitlines()
        assert "examples:" in tail[-4:] or any(x.startswith("examples:") for x in tail[-5:])
        assert tail[-1].lstrip().startswith(f"quatspline imu {cmd}")
    src = _short_tum(tmp_path, 100)
    out = tmp_path / "imu.csv"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "quatspline",
            "imu",
            "simulate",
            str(src),
            "-o",
            str(out),
            "--rate",
            "30",
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    assert len(qio.read_imu(out)) > 0
