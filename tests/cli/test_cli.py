"""The command line end to end in a temporary directory."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import matplotlib.image as mpimg
import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline._util.options import DEFAULT_METHOD
from quatspline.cli import main
from quatspline.registry import METHODS

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
BVH = DATA / "mocapbank_bvh" / "test_mocapbank.bvh"


@pytest.fixture
def small_tum(tmp_path):
    t = qio.read(TUM)
    p = tmp_path / "small.txt"
    qio.write(p, qio.Trajectory(t.times[:300], t.quats[:300], t.positions[:300]))
    return p


def test_help_and_version(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    for cmd in ("sample", "compare", "plot", "demo"):
        assert cmd in out
    with pytest.raises(SystemExit):
        main(["--version"])
    assert qs.__version__ in capsys.readouterr().out


def test_no_command_is_usage_error():
    assert main([]) == 2


def test_sample_with_derivatives(tmp_path, small_tum):
    out = tmp_path / "s.csv"
    assert (
        main(
            [
                "sample",
                str(small_tum),
                "-o",
                str(out),
                "--method",
                "squad",
                "--rate",
                "200",
                "--derivatives",
            ]
        )
        == 0
    )
    t = qio.read(out)
    keys = qio.read(small_tum)
    assert abs(t.times[0] - keys.times[0]) < 1e-6 and len(t) > 500
    header = out.read_text().splitlines()[0].split(",")
    assert (
        header[:5] == ["t", "qw", "qx", "qy", "qz"] and "omega_x" in header and "jerk_z" in header
    )
    s = qs.Squad(keys.quats, keys.times - keys.times[0])
    np.testing.assert_allclose(t.quats[:50], s(t.times[:50] - keys.times[0]), atol=1e-12)
    np.testing.assert_allclose(t.positions[0], keys.positions[0], atol=1e-12)


def test_sample_count_at_and_params(tmp_path, small_tum):
    out = tmp_path / "c.json"
    assert (
        main(
            [
                "sample",
                str(small_tum),
                "-o",
                str(out),
                "--method",
                "c3",
                "--param",
                "alpha=0.5",
                "--count",
                "7",
            ]
        )
        == 0
    )
    assert len(qio.read(out)) == 7
    at = tmp_path / "at.txt"
    k = qio.read(small_tum)
    np.savetxt(at, k.times[[3, 10, 20]])
    out2 = tmp_path / "at.npz"
    assert main(["sample", str(small_tum), "-o", str(out2), "--at", str(at)]) == 0
    np.testing.assert_allclose(
        np.abs(np.sum(qio.read(out2).quats * k.quats[[3, 10, 20]], axis=1)), 1, atol=1e-12
    )


def test_compare_holdout_json(capsys, small_tum):
    assert (
        main(
            [
                "compare",
                str(small_tum),
                "--methods",
                "slerp,natural,c3",
                "--holdout",
                "10",
                "--json",
            ]
        )
        == 0
    )
    rows = json.loads(capsys.readouterr().out)
    assert [r["method"] for r in rows] == ["slerp", "natural", "c3"]
    keys = {
        "method",
        "max_speed",
        "rms_speed",
        "rms_acceleration",
        "rms_jerk",
        "path_length",
        "continuity_order",
        "holdout_median_deg",
        "holdout_p95_deg",
        "holdout_max_deg",
    }
    for r in rows:
        assert set(r) == keys
        assert 0 < r["holdout_median_deg"] <= r["holdout_p95_deg"] <= r["holdout_max_deg"] < 5
    assert [r["continuity_order"] for r in rows] == [0, 2, 3]


def test_compare_table_all_interpolating_methods(capsys, small_tum):
    assert main(["compare", str(small_tum)]) == 0
    out = capsys.readouterr().out
    for m in ("slerp", "nlerp", "lin_euler", "lin_mat", "squad", "catmull_rom", "natural", "c3"):
        assert f"| {m} |" in out


def curve_pixels(path):
    img = mpimg.imread(path)
    rgb = img[..., :3]
    coloured = (rgb.max(axis=-1) - rgb.min(axis=-1)) > 0.3  # saturated pixels: the curves
    return img.shape, int(coloured.sum())


def test_plot_family_of_a_method_without_shape_parameters_says_what_to_give(tmp_path, capsys):
    src = tmp_path / "keys.csv"
    qio.write(src, qio.Trajectory(np.arange(5.0), qs.from_rotvec(np.eye(3)[[0, 1, 2, 0, 1]])))
    out = tmp_path / "family.png"
    assert main(["plot", str(src), "-o", str(out), "--kind", "family", "--method", "natural"]) == 2
    err = capsys.readouterr().err
    assert "--family PARAM=V1,V2" in err and "--method c3" in err and not out.exists()


@pytest.mark.parametrize("kind", ["sphere", "body", "rates", "family"])
def test_plot_kinds_draw_curves(tmp_path, kind):
    from ..splinekit import random_walk

    src = tmp_path / "spin.csv"
    q = random_walk(12, 3, step=0.6)
    qio.write(src, qio.Trajectory(np.arange(12.0), q, np.cumsum(np.ones((12, 3)), axis=0)))
    out = tmp_path / f"{kind}.png"
    shaped = ["--method", "c3"] if kind == "family" else []  # a method with α to sweep
    assert main(["plot", str(src), "-o", str(out), "--kind", kind, *shaped]) == 0
    shape, n = curve_pixels(out)
    assert shape[0] > 300 and shape[1] > 300
    assert n > 500, n


def test_plot_svg_and_pdf(tmp_path, small_tum):
    for ext, magic in (("svg", b"<?xml"), ("pdf", b"%PDF")):
        out = tmp_path / f"f.{ext}"
        assert main(["plot", str(small_tum), "-o", str(out), "--kind", "rates"]) == 0
        assert out.read_bytes()[:5].startswith(magic)


def test_bvh_joint_option(capsys, tmp_path):
    out = tmp_path / "wrist.csv"
    assert (
        main(
            ["sample", str(BVH), "--joint", "LeftWrist", "--world", "-o", str(out), "--count", "50"]
        )
        == 0
    )
    assert main(["sample", str(BVH), "--joint", "Nope", "-o", str(out), "--count", "5"]) == 1
    assert "no joint 'Nope'; joints: Hips" in capsys.readouterr().err


def test_bad_usage_and_bad_data_exit_codes(capsys, tmp_path, small_tum):
    out = tmp_path / "x.csv"
    assert (
        main(["sample", str(small_tum), "-o", str(out), "--method", "spline9", "--count", "5"]) == 2
    )
    assert "valid: slerp" in capsys.readouterr().err
    assert (
        main(
            [
                "sample",
                str(small_tum),
                "-o",
                str(out),
                "--method",
                "c3",
                "--param",
                "gamma=1",
                "--count",
                "5",
            ]
        )
        == 2
    )
    assert "valid: alpha, beta, variant" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        main(["sample", str(small_tum), "-o", str(out)])  # no --rate/--count/--at
    assert e.value.code == 2
    assert main(["sample", str(tmp_path / "missing.csv"), "-o", str(out), "--count", "5"]) == 1
    bad = tmp_path / "bad.csv"
    bad.write_text("t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,oops,0\n")
    assert main(["compare", str(bad)]) == 1
    assert "bad.csv:3: column 4 ('qy'): not a number: 'oops'" in capsys.readouterr().err
    assert not out.exists()


def test_never_overwrites_the_input_without_force(tmp_path, small_tum):
    before = small_tum.read_bytes()
    assert main(["sample", str(small_tum), "-o", str(small_tum), "--count", "5"]) == 2
    assert small_tum.read_bytes() == before
    assert main(["sample", str(small_tum), "-o", str(small_tum), "--count", "5", "--force"]) == 0


def test_demo_writes_everything(tmp_path):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    for name in (
        "sphere.png",
        "body.png",
        "rates.png",
        "family.png",
        "report.md",
        "compare.json",
        "compare.md",
    ):
        assert (tmp_path / name).stat().st_size > 0, name
    data = np.loadtxt(tmp_path / "beta_example1_slerp.csv", delimiter=",", skiprows=1)
    assert data.shape == (201, 5)
    keys = qs.normalize(qs.examples.BETA_EXAMPLE1_VERTICES)
    np.testing.assert_allclose(data[::50, 1:], keys, atol=1e-16)
    cp = np.loadtxt(tmp_path / "beta_example1_control_points.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(cp[0, 2:], [-0.3796, 0.4589, 0.1106, 0.7956], atol=5e-5)
    rows = json.loads((tmp_path / "compare.json").read_text())
    n_methods = len(qs.registry.interpolating_methods())
    assert len(rows) == n_methods and all("holdout_median_deg" in r for r in rows)
    report = (tmp_path / "report.md").read_text()
    assert "![sphere](sphere.png)" in report and "| c3 |" in report
    assert len(list((tmp_path / "samples").glob("*.csv"))) == n_methods + 1


def test_console_script_runs():
    r = subprocess.run(
        [sys.executable, "-m", "quatspline.cli", "--version"], capture_output=True, text=True
    )
    assert r.returncode == 0 and "quatspline" in r.stdout


def test_python_dash_m_package_runs_the_cli(tmp_path):
    # `python -m quatspline` is the same command line as the console script, exit codes too
    r = subprocess.run(
        [sys.executable, "-m", "quatspline", "--version"], capture_output=True, text=True
    )
    assert r.returncode == 0 and "quatspline" in r.stdout
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "quatspline",
            "fit",
            str(tmp_path / "missing.csv"),
            "-o",
            "x.csv",
            "--rate",
            "10",
        ],
        capture_output=True,
        text=True,
    )
    assert (
        r.returncode == 1 and "missing.csv" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    )


@pytest.mark.parametrize("command", ["export", "sample"])
@pytest.mark.parametrize("name", ["node", "mesh", "samples", "nonsense"])
def test_param_that_is_not_a_parameter_of_the_method_is_a_one_line_usage_error(
    tmp_path, capsys, command, name
):
    # `export --param node=x` reached to_gltf as a second `node` keyword: a TypeError about
    # keyword arguments. Any name the method does not declare is refused up front.
    src = tmp_path / "keys.csv"
    qio.write(src, qio.Trajectory(np.arange(5.0), qs.from_rotvec(np.eye(3)[[0, 1, 2, 0, 1]])))
    out = tmp_path / ("out.glb" if command == "export" else "out.csv")
    extra = [] if command == "export" else ["--count", "5"]
    code = main([command, str(src), "-o", str(out), "--param", f"{name}=x", *extra])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    valid = ", ".join(METHODS[DEFAULT_METHOD].params)  # the default method's parameters
    assert f"--param {name}" in err and f"valid: {valid}" in err
    assert not out.exists()


@pytest.mark.parametrize("command", ["sample", "fit"])
def test_at_an_empty_file_is_a_one_line_error_naming_the_file(tmp_path, capsys, command):
    src = tmp_path / "keys.csv"
    qio.write(
        src, qio.Trajectory(np.arange(6.0), qs.from_rotvec(0.1 * np.arange(18.0).reshape(6, 3)))
    )
    empty = tmp_path / "times.txt"
    empty.write_text("# no times here\n")
    code = main([command, str(src), "-o", str(tmp_path / "out.csv"), "--at", str(empty)])
    err = capsys.readouterr().err
    assert code == 1 and len(err.strip().splitlines()) == 1, err
    assert str(empty) in err and "no times" in err and "UserWarning" not in err


def test_demo_creates_its_output_directory_with_the_usual_mode(tmp_path):
    # the demo built its tree in a mkdtemp directory (0700) and renamed it into place
    out = tmp_path / "demo_out"
    old = os.umask(0o022)
    try:
        assert main(["demo", "--out", str(out)]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE(out.stat().st_mode) == 0o755


def test_demo_never_replaces_a_file_it_did_not_write_and_cleans_a_killed_runs_work(
    tmp_path, capsys
):
    """``demo -o DIR`` into a directory holding the user's own ``report.md`` replaced it; a
    killed run's work directory was left beside DIR for ever. Now the user's file is refused
    (nothing moved), a re-run replaces only the demo's own files (its manifest), and a stale
    work directory (unlocked) is removed while a look-alike user directory is kept."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.md").write_text("my notes")
    (out / "mine.txt").write_text("keep")
    assert main(["demo", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "report.md: exists and was not written by the demo" in err and err.count("\n") == 1
    assert (out / "report.md").read_text() == "my notes" and sorted(os.listdir(out)) == [
        "mine.txt",
        "report.md",
    ]
    (out / "report.md").unlink()
    stale = tmp_path / ".out.0123456789ab.demotmp"
    (stale / "out").mkdir(parents=True)
    (stale / "out" / "partial.csv").write_text("x")
    lookalike = tmp_path / ".out.notours.demotmp"
    lookalike.mkdir()
    assert main(["demo", "--out", str(out)]) == 0
    first = (out / "report.md").read_text()
    assert main(["demo", "--out", str(out)]) == 0  # its own files: replaced
    assert (out / "report.md").read_text() == first and (out / "mine.txt").read_text() == "keep"
    assert not stale.exists() and lookalike.is_dir()
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".demotmp")] == [lookalike.name]
