"""``quatspline batch imu-simulate``: ``quatspline imu simulate`` over many files — per file the
bytes the single-file command writes, skipped when up to date, redone when the noise file
changes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="the dask extra is not installed")
import quatspline.io as qio  # noqa: E402
from dask.distributed import Client  # noqa: E402
from quatspline import batch  # noqa: E402
from quatspline.cli import main  # noqa: E402
from quatspline.cli._commands import build_parser  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
REPO = DATA / "repoimu" / "repoIMU_first30s.csv"

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]

NOISE = """accelerometer_noise_density: 0.02
accelerometer_random_walk: 0.001
gyroscope_noise_density: {gyro}
gyroscope_random_walk: 0.0001
update_rate: 100.0
"""


@pytest.fixture(scope="module")
def client():
    with batch.local_cluster(1) as cluster, Client(cluster) as c:
        yield c


def _inputs(root: Path) -> list[Path]:
    src = qio.read(TUM)
    a = root / "in" / "a.txt"
    b = root / "in" / "sub" / "b.csv"
    a.parent.mkdir(parents=True)
    b.parent.mkdir(parents=True)
    qio.write(a, qio.Trajectory(src.times[:200], src.quats[:200], src.positions[:200]))
    qio.write(b, _repo(500))
    return [a, b]


def _repo(n: int):
    r = qio.read(REPO)
    return qio.Trajectory(r.times[:n], r.quats[:n])


def _batch(client, inputs, out: Path, options: list[str]):
    args = build_parser().parse_args(
        ["batch", "imu-simulate", *map(str, inputs), "-o", str(out), *options]
    )
    return batch.run(
        "imu-simulate",
        args.inputs,
        args.output,
        client=client,
        progress=False,
        **batch.cli_options(args),
    )


def test_batch_imu_simulate_matches_the_single_file_command(client, tmp_path):
    inputs = _inputs(tmp_path)
    noise = tmp_path / "imu.yaml"
    noise.write_text(NOISE.format(gyro=0.001))
    opts = ["--rate", "100", "--noise", str(noise), "--seed", "7"]
    table = _batch(client, [tmp_path / "in"], tmp_path / "out", opts)
    assert table["status"].tolist() == ["ok", "ok"]
    outs = {Path(o).name: Path(o) for o in table["output"]}
    assert set(outs) == {"a.csv", "b.csv"}
    for src, name in zip(inputs, ("a.csv", "b.csv")):
        single = tmp_path / f"single-{name}"
        assert main(["imu", "simulate", str(src), "-o", str(single), *opts]) == 0
        assert outs[name].read_bytes() == single.read_bytes()
    assert qio.read_imu(outs["a.csv"]).accel is not None  # TUM has positions
    assert qio.read_imu(outs["b.csv"]).accel is None  # RepoIMU: orientations only

    again = _batch(client, [tmp_path / "in"], tmp_path / "out", opts)
    assert again["status"].tolist() == ["skipped", "skipped"]
    noise.write_text(NOISE.format(gyro=0.002))  # new densities: the outputs are stale
    redo = _batch(client, [tmp_path / "in"], tmp_path / "out", opts)
    assert redo["status"].tolist() == ["ok", "ok"]
    old = qio.read_imu(tmp_path / "single-a.csv").gyro
    assert not np.array_equal(qio.read_imu(outs["a.csv"]).gyro, old)


def test_batch_imu_simulate_needs_a_rate_and_names_bad_files(client, tmp_path):
    with pytest.raises(ValueError, match="rate"):
        batch.run("imu-simulate", [TUM], tmp_path / "o", client=client, progress=False)
    bad = tmp_path / "in" / "bad.csv"
    bad.parent.mkdir()
    bad.write_text("not,a,trajectory\n")
    table = batch.run(
        "imu-simulate", [bad], tmp_path / "o2", client=client, progress=False, rate=100.0
    )
    assert table["status"].tolist() == ["error"] and "bad.csv" in table["error"][0]
