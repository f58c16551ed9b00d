"""CLI for the new formats: export to glTF (validated) and BVH, sample --at another
trajectory with --extrapolate, bag topics, KITTI times."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline.io as qio
from quatspline._util.options import DEFAULT_METHOD
from quatspline.cli import main

from ..ops.test_gltf import measured_errors, validate
from ..splinekit import random_walk

T0 = 1_305_031_102.0


def est(tmp_path, n=60):
    q = random_walk(n, 0, step=0.15)
    t = T0 + 0.05 * np.arange(n)
    p = np.random.default_rng(0).normal(size=(n, 3)) * 0.1
    tr = qio.Trajectory(t, q, p)
    qio.write(tmp_path / "est.tum", tr)
    return tr, tmp_path / "est.tum"


def test_export_glb_within_bound_and_valid(tmp_path, capsys):
    tr, src = est(tmp_path)
    out = tmp_path / "motion.glb"
    args = ["export", str(src), "-o", str(out), "--max-error", "0.02deg", "--node", "body"]
    assert main([*args, "--interpolation", "cubicspline"]) == 0
    assert "keys (uniform needs" in capsys.readouterr().out
    assert validate(out)[0]["numErrors"] == 0
    import quatspline as qs

    ps = qs.PoseSpline(
        tr.quats, tr.times - T0, tr.positions, rotation=DEFAULT_METHOD
    )  # the export default
    e_rot, e_pos, _ = measured_errors(out, ps, 0.0)
    assert np.degrees(e_rot.max()) <= 0.02 * (1 + 1e-3)
    assert e_pos.max() <= 1e-4 * (1 + 1e-3)


def test_export_bvh(tmp_path):
    _, src = est(tmp_path)
    assert main(["export", str(src), "-o", str(tmp_path / "m.bvh")]) == 0
    assert len(qio.read(tmp_path / "m.bvh")) == 60


@pytest.mark.parametrize(
    ("value", "match"),
    [
        ("--max-error=0", "--max-error: expected a positive finite bound"),
        ("--max-error=-1deg", "--max-error: expected a positive finite bound"),
        ("--max-error=1parsec", "--max-error: cannot parse '1parsec'"),
        ("--max-position-error=2 feet", "--max-position-error: cannot parse '2 feet'"),
    ],
)
def test_export_bad_bounds(tmp_path, capsys, value, match):
    _, src = est(tmp_path)
    assert main(["export", str(src), "-o", str(tmp_path / "m.glb"), value]) == 2
    assert match in capsys.readouterr().err
    assert not (tmp_path / "m.glb").exists()


def test_sample_at_another_trajectory(tmp_path, capsys):
    tr, src = est(tmp_path)
    gt = qio.Trajectory(np.linspace(T0 + 0.01, T0 + 2.9, 33), random_walk(33, 2), np.zeros((33, 3)))
    qio.write(tmp_path / "gt.tum", gt)
    out = tmp_path / "on_gt.tum"
    assert main(["sample", str(src), "--at", str(tmp_path / "gt.tum"), "-o", str(out)]) == 0
    got = qio.read(out)
    np.testing.assert_array_equal(got.times, gt.times)
    np.testing.assert_allclose(got.quats, tr.resample(gt).quats, atol=1e-15)
    # a one-column file of times works as well
    np.savetxt(tmp_path / "t.txt", gt.times, fmt="%.17g")
    assert main(["sample", str(src), "--at", str(tmp_path / "t.txt"), "-o", str(out)]) == 0
    np.testing.assert_array_equal(qio.read(out).times, gt.times)


def test_sample_at_outside_names_the_first_time(tmp_path, capsys):
    _, src = est(tmp_path)
    gt = qio.Trajectory(T0 + np.array([5.0, 6.0]), random_walk(2, 2), np.zeros((2, 3)))
    qio.write(tmp_path / "gt.tum", gt)
    out = tmp_path / "x.tum"
    assert main(["sample", str(src), "--at", str(tmp_path / "gt.tum"), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    # the wording of every sampling route (ops.check_times): sample, fit and resample alike
    assert "--at: times[0] = 1305031107.0 is after the trajectory's last time" in err
    assert "(all of them are outside)" in err
    assert not out.exists()
    argv = ["sample", str(src), "--at", str(tmp_path / "gt.tum"), "-o", str(out)]
    assert main([*argv, "--extrapolate", "clamp"]) == 0
    with pytest.raises(SystemExit) as e:
        main([*argv, "--extrapolate", "sideways"])
    assert e.value.code == 2
    assert "--extrapolate: invalid choice: 'sideways'" in capsys.readouterr().err


def test_bag_topic_listing_through_cli(tmp_path, capsys):
    pytest.importorskip("rosbags")
    from ..io.test_rosbag import write_bag

    path = write_bag(tmp_path / "a.bag", "ros1", {"/a": "geometry_msgs/msg/PoseStamped"})
    out = tmp_path / "o.csv"
    assert main(["sample", str(path), "--topic", "/b", "--count", "5", "-o", str(out)]) == 1
    assert "no topic '/b'; topics: /a (geometry_msgs/PoseStamped)" in capsys.readouterr().err
    assert main(["sample", str(path), "--topic", "/a", "--count", "5", "-o", str(out)]) == 0


def test_kitti_times_through_cli(tmp_path):
    tr, _ = est(tmp_path)
    qio.write(tmp_path / "00.txt", tr, format="kitti", times_path=tmp_path / "times.txt")
    out = tmp_path / "o.tum"
    argv = ["sample", str(tmp_path / "00.txt"), "--times", str(tmp_path / "times.txt")]
    assert main([*argv, "--count", "7", "-o", str(out)]) == 0
    got = qio.read(out)
    assert got.times[0] == tr.times[0] and got.times[-1] == pytest.approx(tr.times[-1])


def test_plot_rates_with_jerk_and_title_from_the_file(tmp_path, monkeypatch, capsys):
    pytest.importorskip("matplotlib")
    from quatspline import plot

    _, src = est(tmp_path)
    figs = []
    orig = plot.save
    monkeypatch.setattr(plot, "save", lambda fig, path: figs.append(fig) or orig(fig, path))
    out = tmp_path / "r.png"
    argv = ["plot", str(src), "-o", str(out), "--kind", "rates", "--show", "omega,jerk"]
    assert main(argv) == 0
    (fig,) = figs
    assert [a.get_ylabel() for a in fig.axes] == ["|ω| (rad/s)", "|dα/dt| (rad/s³)"]
    assert fig.get_suptitle().startswith("est.tum: ")
    assert main([*argv[:-1], "omega,snap"]) == 2
    assert "--show: expected some of omega, alpha, jerk" in capsys.readouterr().err
    assert main(["plot", str(src), "-o", str(out), "--kind", "body", "--force"]) == 0
    assert figs[-1].axes[0].get_xlabel() == "x (m)"
    assert figs[-1].axes[0].get_title().startswith("est.tum: ")


@pytest.mark.parametrize("link", ["same", "symlink", "hardlink"])
def test_commands_refuse_to_overwrite_their_auxiliary_input_files(tmp_path, capsys, link):
    """The output of sample/fit may not be the KITTI --times file, the --at file or the --knots
    file (by any name), as it may not be the input: each is refused (exit 2) and unchanged."""
    tr, src = est(tmp_path)
    kitti, times = tmp_path / "00.txt", tmp_path / "times.txt"
    qio.write(kitti, tr, format="kitti", times_path=times)
    at = tmp_path / "at.txt"
    at.write_text("".join(f"{float(t)!r}\n" for t in tr.times[5:50:5]))
    knots = tmp_path / "knots.txt"
    knots.write_text("".join(f"{float(t)!r}\n" for t in np.linspace(tr.times[0], tr.times[-1], 9)))

    def named(path):
        if link == "same":
            return path
        other = tmp_path / f"other-{path.name}"
        other.unlink(missing_ok=True)
        (other.symlink_to if link == "symlink" else other.hardlink_to)(path)
        return other

    cases = [
        (["sample", str(kitti), "--times", str(times), "--count", "5", "--format", "kitti"], times),
        (["sample", str(src), "--at", str(at), "--format", "tum"], at),
        (["fit", str(src), "--at", str(at), "--format", "tum"], at),
        (["fit", str(src), "--knots", str(knots), "--count", "5", "--format", "tum"], knots),
    ]
    for argv, victim in cases:
        before = victim.read_bytes()
        capsys.readouterr()
        assert main([*argv, "-o", str(named(victim))]) == 2, argv
        err = capsys.readouterr().err
        assert "refusing to overwrite the --" in err and err.count("\n") == 1, err
        assert victim.read_bytes() == before, argv


def test_sample_at_honours_max_samples_and_derivatives(tmp_path, capsys):
    """``sample --at`` goes through the same route as ``--count``: the ω/α/jerk columns with
    ``--derivatives`` and the ``--max-samples`` bound (both were ignored with ``--at``)."""
    tr, src = est(tmp_path)
    at = tmp_path / "at.txt"
    at.write_text("".join(f"{float(t)!r}\n" for t in tr.times[3:20]))
    out = tmp_path / "s.csv"
    argv = ["sample", str(src), "--at", str(at), "-o", str(out)]
    assert main([*argv, "--derivatives"]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert len(qio.read(out)) == 17 and {"omega_x", "alpha_y", "jerk_z"} <= set(header)
    by_count = tmp_path / "c.csv"
    assert main(["sample", str(src), "--count", "17", "--derivatives", "-o", str(by_count)]) == 0
    assert by_count.read_text().splitlines()[0].split(",") == header
    out.unlink()
    assert main([*argv, "--max-samples", "3"]) == 2  # a bad option value, as with --count
    err = capsys.readouterr().err
    assert "max" in err and err.count("\n") == 1 and not out.exists()
    # a one-line file of three numbers is not three times
    at.write_text(" ".join(f"{float(t)!r}" for t in tr.times[3:6]) + "\n")
    assert main(argv) == 1
    assert not out.exists()
