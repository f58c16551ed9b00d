"""One definition per option: ``quatspline batch OP`` takes the options of ``quatspline OP``
with the same defaults, and batch reaches the command line only through its option groups."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline import batch
from quatspline.cli import main
from quatspline.cli._commands import build_parser

ROOT = Path(__file__).resolve().parents[2]
TUM = ROOT / "data" / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"

#: Options only the single-file commands have (one output file, the JSON switch of compare).
SINGLE_ONLY = {
    "command", "func", "debug", "input", "output", "format", "force", "json", "imu_command",
    # a gyroscope record belongs to one recording (``fit --gyro``), not to a batch of them
    "gyro", "gyro_noise", "estimate",
    # one figure file, like the one output file (``fit --figure``)
    "figure",
}  # fmt: skip
#: Options only the batch has (many inputs, an output directory, Dask, resuming).
BATCH_ONLY = {"command", "func", "debug", "operation", "inputs", "output", "scheduler",
              "workers", "force", "max_file_size", "to"}  # fmt: skip
#: The least each operation needs on the command line.
REQUIRED = {
    "sample": ["--count", "5"],
    "fit": ["--count", "5"],
    "compare": [],
    "export": [],
    "imu-simulate": ["--rate", "100"],
}
#: The single-file command of each batch operation (the operation's name unless listed).
SINGLE_COMMAND = {"imu-simulate": ["imu", "simulate"]}


def _single(op: str, extra=()) -> dict:
    output = [] if op == "compare" else ["-o", "out.x"]  # compare prints
    cmd = SINGLE_COMMAND.get(op, [op])
    return vars(build_parser().parse_args([*cmd, "in.txt", *output, *REQUIRED[op], *extra]))


def _batch(op: str, extra=()) -> dict:
    argv = ["batch", op, "in.txt", "-o", "out", *REQUIRED[op], *extra]
    return vars(build_parser().parse_args(argv))


@pytest.mark.parametrize("op", batch.OPERATIONS)
def test_batch_operations_take_every_option_of_their_single_file_command(op):
    """``batch`` lacked ``--knots``, ``--euler/--degrees``, ``--topic/--frame``, ``--node-in``,
    ``--times``, ``--at``, ``--extrapolate``, ``--max-samples``, ``--max-position-error``, … and
    had its own defaults."""
    single = {k: v for k, v in _single(op).items() if k not in SINGLE_ONLY}
    many = {k: v for k, v in _batch(op).items() if k not in BATCH_ONLY}
    assert sorted(many) == sorted(single)
    assert many == single  # the same defaults


def test_batch_compare_holds_out_nothing_by_default_as_compare():
    """``batch compare`` held out every 4th key by default, ``compare`` none: other figures
    for the same file (max speed 0.65 against 1.05 rad/s)."""
    assert _single("compare")["holdout"] is None
    args = build_parser().parse_args(["batch", "compare", "in.txt", "-o", "out"])
    assert batch.cli_options(args).get("holdout") is None


@pytest.mark.parametrize(
    ("op", "extra", "key", "value"),
    [
        ("sample", ["--at", "AT"], "times", None),
        ("sample", ["--extrapolate", "periodic"], "extrapolate", "periodic"),
        ("sample", ["--max-samples", "9"], "max_samples", 9),
        ("fit", ["--knots", "0.25"], "knots", 0.25),
        ("fit", ["--smoothing", " Auto "], "smoothing", "auto"),
        ("fit", ["--smoothing", "2e-3"], "smoothing", 2e-3),
        ("sample", ["--euler", "ZYX", "--degrees"], "euler", "ZYX"),
        ("sample", ["--topic", "/pose", "--frame", "base"], "topic", "/pose"),
        ("export", ["--node-in", "arm"], "node_in", "arm"),
        ("export", ["--empty", "--node", "cam"], "mesh", None),
        ("export", ["--max-position-error", "2mm"], "max_position_error", "2mm"),
    ],
)
def test_batch_passes_each_option_on_to_the_operation(tmp_path, op, extra, key, value):
    if "AT" in extra:
        at = tmp_path / "at.txt"
        at.write_text("0.5\n1.5\n")
        extra = [str(at) if x == "AT" else x for x in extra]
    where = [] if "--at" in extra else REQUIRED[op]
    args = build_parser().parse_args(["batch", op, "a.txt", "-o", "o", *where, *extra])
    opts = batch.cli_options(args)
    assert key in opts
    if key == "times":
        assert opts[key].tolist() == [0.5, 1.5]
    else:
        assert opts[key] == value


def test_batch_imports_no_private_name_of_the_cli_and_nothing_inside_functions():
    """batch imported the command line's private ``_params`` inside a function (an import
    cycle cli ↔ batch) and our own modules inside six functions."""
    path = ROOT / "python" / "quatspline" / "batch.py"
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(n) for n in tree.body}
    bad = []
    for node in ast.walk(tree):
        if not isinstance(node, (ast.Import, ast.ImportFrom)):
            continue
        ours = isinstance(node, ast.ImportFrom) and (
            node.level > 0 or (node.module or "").startswith("quatspline")
        )
        if isinstance(node, ast.Import):
            ours = any(a.name.startswith("quatspline") for a in node.names)
        if not ours:
            continue
        module = node.module or "" if isinstance(node, ast.ImportFrom) else ""
        if id(node) not in top:
            bad.append(f"line {node.lineno}: a function-level import of {module}")
        if module.startswith("cli"):
            bad.append(f"line {node.lineno}: imports {module} (the command line lies above batch)")
        for a in node.names:
            if a.name.startswith("_") and not a.name.startswith("__"):
                bad.append(f"line {node.lineno}: imports the private name {a.name}")
    assert not bad, bad


def test_batch_and_the_command_line_import_neither_dask_nor_pandas():
    code = (
        "import sys, quatspline.batch, quatspline.cli\n"
        "print(','.join(m for m in ('dask', 'distributed', 'pandas') if m in sys.modules))\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert r.stdout.strip() == ""


def test_batch_without_dask_names_the_extra_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(
        ImportError, match=r'quatspline batch needs .*pip install "quatspline\[dask\]"'
    ):
        batch.run("sample", [tmp_path], tmp_path / "out", count=5)


@pytest.mark.parametrize("spelling", ["AUTO", " auto ", "Auto"])
def test_fit_smoothing_accepts_the_spellings_of_the_fit_method_parameter(tmp_path, spelling):
    """λ was parsed in four places: ``sample --method fit --param smoothing=AUTO`` worked,
    ``fit --smoothing AUTO`` was a usage error."""
    src = tmp_path / "keys.csv"
    full = qio.read(TUM)
    qio.write(src, qio.Trajectory(full.times[:120], full.quats[:120]))
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert main(["fit", str(src), "-o", str(a), "--count", "9", "--smoothing", spelling]) == 0
    assert main(["sample", str(src), "-o", str(b), "--count", "9", "--method", "fit",
                 "--param", f"smoothing={spelling}"]) == 0  # fmt: skip
    np.testing.assert_array_equal(qio.read(a).times, qio.read(b).times)
    assert qs.ops.ParameterError is not None
