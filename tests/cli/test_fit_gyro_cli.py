"""``quatspline fit TRAJ --gyro IMU [--gyro-noise imu.yaml] [--estimate …]``: the CLI translates
its options for :func:`quatspline.ops.fit_trajectory`, which the result must equal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline.cli import main

DATA = Path(__file__).resolve().parents[2] / "data"
REPO = DATA / "repoimu" / "repoIMU_first30s.csv"

NOISE = """accelerometer_noise_density: 0.02
accelerometer_random_walk: 0.0
gyroscope_noise_density: 0.002
gyroscope_random_walk: 0.0
update_rate: 100.0
"""


def _keys(tmp_path: Path) -> Path:
    """The RepoIMU Vicon orientations at 2 Hz over the first 10 s, as a csv trajectory."""
    src = qio.read(REPO)
    keep = (np.arange(len(src)) % 50 == 0) & (src.times <= src.times[0] + 10.0)
    p = tmp_path / "keys.csv"
    qio.write(p, qio.Trajectory(src.times[keep], src.quats[keep]))
    return p


def test_fit_with_gyro_equals_the_operation(tmp_path, capsys):
    keys = _keys(tmp_path)
    yaml = tmp_path / "imu.yaml"
    yaml.write_text(NOISE)
    out = tmp_path / "fused.csv"
    argv = ["fit", str(keys), "--gyro", str(REPO), "--gyro-noise", str(yaml), "-o", str(out)]
    assert main([*argv, "--rate", "50", "--estimate", "bias,time_offset"]) == 0
    cap = capsys.readouterr()
    assert "lie outside the orientations' time range" in cap.err
    text = cap.out
    assert "gyro bias (°/s)" in text and "time offset (ms)" in text
    assert "sensor rotation" not in text
    got = qio.read(out)
    with pytest.warns(RuntimeWarning, match="outside"):
        want, f = qs.ops.fit_trajectory(
            qio.read(keys),
            rate=50,
            gyro=qio.read_imu(REPO),
            gyro_noise=str(yaml),
            estimate=("bias", "time_offset"),
        )
    np.testing.assert_allclose(got.times, want.times, atol=1e-9)
    assert qs.angle_between(got.quats, want.quats).max() < 1e-6
    assert f.gyro.estimated == ("bias", "time_offset")


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (["--estimate", "bias,nope"], "--estimate"),
        (["--gyro-noise", "x.yaml"], "--gyro-noise: only with --gyro"),
    ],
)
def test_fit_gyro_bad_options(tmp_path, capsys, extra, match):
    keys = _keys(tmp_path)
    argv = ["fit", str(keys), "-o", str(tmp_path / "o.csv"), "--rate", "10"]
    if extra[0] == "--estimate":
        argv += ["--gyro", str(REPO)]
    assert main([*argv, *extra]) == 2
    assert match in capsys.readouterr().err
