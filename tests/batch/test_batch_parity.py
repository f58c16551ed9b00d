"""``quatspline batch OP`` is ``quatspline OP`` over many files: the same options (parsed by the
same groups), the same defaults, and per file the bytes the single-file command writes.

Each case parses ``quatspline batch …`` with the command line's own parser and runs it on one
module-scoped local cluster (``batch.run(…, client=…, **batch.cli_options(args))``, the call
``quatspline batch`` makes), then runs the single-file command on each input and compares.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="the dask extra is not installed")
import quatspline as qs  # noqa: E402
import quatspline.io as qio  # noqa: E402
from dask.distributed import Client  # noqa: E402
from quatspline import batch  # noqa: E402
from quatspline.cli import main  # noqa: E402
from quatspline.cli._commands import build_parser  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]


@pytest.fixture(scope="module")
def client():
    with batch.local_cluster(2) as cluster, Client(cluster) as c:
        yield c


def _recordings(root: Path, n: int = 2, rows: int = 200) -> list[Path]:
    """Slices of the bundled TUM recording, each turned by a random rotation."""
    src = qio.read(TUM)
    rng = np.random.default_rng(11)
    paths = []
    for i in range(n):
        a = int(rng.integers(0, len(src) - rows))
        q = qs.multiply(qs.from_rotvec(rng.normal(size=3)), src.quats[a : a + rows])
        p = root / ("sub" if i % 2 else "") / f"rec{i}.txt"
        p.parent.mkdir(parents=True, exist_ok=True)
        qio.write(p, qio.Trajectory(src.times[a : a + rows], q, src.positions[a : a + rows]))
        paths.append(p)
    return paths


def _batch(client, operation: str, inputs, out: Path, options: list[str]):
    """``quatspline batch OPERATION INPUTS -o OUT OPTIONS`` on the shared cluster."""
    args = build_parser().parse_args(
        ["batch", operation, *map(str, inputs), "-o", str(out), *options]
    )
    table = batch.run(
        args.operation, args.inputs, args.output, client=client, **batch.cli_options(args)
    )
    assert (table["status"] == "ok").all(), table["error"].tolist()
    return table


def _at_file(path: Path, src: Path) -> Path:
    """Times past both ends of ``src``'s keys and between them: extrapolation is exercised."""
    t = qio.read(src).times
    times = np.concatenate([[t[0] - 0.05], np.linspace(t[0], t[-1], 23), [t[-1] + 0.07]])
    path.write_text("".join(f"{float(x)!r}\n" for x in times))
    return path


@pytest.mark.parametrize(
    "options",
    [
        ["--method", "squad", "--param", "ends=closed", "--rate", "50", "--derivatives"],
        ["--method", "kochanek_bartels", "--param", "tension=0.3", "--count", "41"],
        ["--method", "slerp", "--at", "AT", "--extrapolate", "clamp", "--derivatives"],
        ["--method", "natural", "--at", "AT", "--extrapolate", "linear", "--max-samples", "30"],
    ],
    ids=["squad-closed-rate", "kb-tension-count", "at-clamp", "at-linear"],
)
def test_batch_sample_writes_the_bytes_of_sample_with_non_default_options(
    tmp_path, client, options
):
    inputs = _recordings(tmp_path / "in")
    if "AT" in options:  # one times file for every input: times inside the first one's range
        options = [
            str(_at_file(tmp_path / "at.txt", inputs[0])) if o == "AT" else o for o in options
        ]
    out = tmp_path / "out"
    table = _batch(client, "sample", [tmp_path / "in"], out, options)
    for p in inputs:
        rel = p.relative_to(tmp_path / "in").with_suffix(".csv")
        single = tmp_path / "single" / rel
        single.parent.mkdir(parents=True, exist_ok=True)
        assert main(["sample", str(p), "-o", str(single), *options]) == 0
        assert (out / rel).read_bytes() == single.read_bytes(), options
    if "--derivatives" in options:
        assert "omega" in (out / inputs[0].with_suffix(".csv").name).read_text().splitlines()[0]
    assert (table["samples"] > 0).all()


def test_batch_sample_reads_euler_columns_as_sample_does(tmp_path, client):
    """``batch`` had no ``--euler``/``--degrees``: a CSV of Euler angles could not be read."""
    t = np.linspace(0.0, 2.0, 21)
    angles = np.degrees(np.column_stack([np.sin(t), 0.5 * t, np.cos(2 * t) - 1]))
    src = tmp_path / "in" / "euler.csv"
    src.parent.mkdir()
    rows = np.column_stack([t, angles])
    src.write_text(
        "t,e1,e2,e3\n" + "".join(",".join(map(repr, map(float, r))) + "\n" for r in rows)
    )
    options = ["--euler", "ZYX", "--degrees", "--method", "natural", "--count", "17"]
    out = tmp_path / "out"
    _batch(client, "sample", [src], out, options)
    single = tmp_path / "single.csv"
    assert main(["sample", str(src), "-o", str(single), *options]) == 0
    assert (out / "euler.csv").read_bytes() == single.read_bytes()


@pytest.mark.parametrize(
    "options",
    [
        ["--smoothing", "1e-3", "--count", "40", "--max-samples", "40"],
        ["--smoothing", "1e-4", "--penalty", "jerk", "--knots", "0.5", "--rate", "20"],
        ["--smoothing", "AUTO", "--robust", "huber", "--at", "AT"],
    ],
    ids=["fixed-lambda", "jerk-knot-spacing", "auto-robust-at"],
)
def test_batch_fit_writes_the_bytes_of_fit_with_non_default_options(tmp_path, client, options):
    inputs = _recordings(tmp_path / "in", rows=240)
    if "AT" in options:
        t = qio.read(inputs[0]).times
        at = tmp_path / "at.txt"
        at.write_text("".join(f"{float(x)!r}\n" for x in np.linspace(t[0], t[-1], 9)))
        options = [str(at) if o == "AT" else o for o in options]
    out = tmp_path / "out"
    _batch(client, "fit", [inputs[0]], out, [*options, "--to", "tum"])
    single = tmp_path / "single.txt"
    assert main(["fit", str(inputs[0]), "-o", str(single), "--format", "tum", *options]) == 0
    assert (out / "rec0.txt").read_bytes() == single.read_bytes(), options


@pytest.mark.parametrize(
    "options",
    [[], ["--methods", "slerp,squad,natural", "--holdout", "3"]],
    ids=["defaults", "methods-holdout"],
)
def test_batch_compare_gives_the_rows_of_compare(tmp_path, client, capsys, options):
    """``batch compare`` held out every 4th key by default where ``compare`` holds out none:
    other figures for the same file (max speed 0.65 against 1.05 rad/s)."""
    (src,) = _recordings(tmp_path / "in", n=1, rows=300)
    out = tmp_path / "out"
    _batch(client, "compare", [src], out, options)
    capsys.readouterr()
    assert main(["compare", str(src), "--json", *options]) == 0
    printed = capsys.readouterr().out
    written = (out / "rec0.compare.json").read_text()
    assert json.loads(written) == json.loads(printed)
    assert written == printed  # the same JSON text, byte for byte


@pytest.mark.parametrize(
    "options",
    [
        ["--max-error", "0.05deg", "--max-position-error", "1mm"],
        ["--method", "squad", "--param", "ends=closed", "--max-error", "0.2deg",
         "--interpolation", "cubicspline", "--node", "camera", "--empty"],
    ],
    ids=["bounds", "squad-cubic-empty-node"],
)  # fmt: skip
def test_batch_export_writes_the_bytes_of_export_with_non_default_options(
    tmp_path, client, options
):
    (src,) = _recordings(tmp_path / "in", n=1, rows=120)
    out = tmp_path / "out"
    _batch(client, "export", [src], out, options)
    single = tmp_path / "single.glb"
    assert main(["export", str(src), "-o", str(single), *options]) == 0
    assert (out / "rec0.glb").read_bytes() == single.read_bytes()
