"""``quatspline batch`` on Dask: a LocalCluster and a separately started scheduler."""

from __future__ import annotations

import fcntl
import itertools
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="the dask extra is not installed")
import pandas as pd  # noqa: E402
import quatspline as qs  # noqa: E402
import quatspline.io as qio  # noqa: E402
from dask.distributed import Client  # noqa: E402
from quatspline import batch  # noqa: E402
from quatspline.cli import main  # noqa: E402
from quatspline.ops import ParameterError  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
EUROC = DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv"

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
    pytest.mark.filterwarnings("ignore::UserWarning"),
]


@pytest.fixture(scope="module")
def client():
    with batch.local_cluster(2) as cluster, Client(cluster) as c:
        yield c


def _recordings(root: Path, n: int = 4, rows: int = 240) -> list[Path]:
    """Small recordings made from the bundled TUM file: each a random rotation of a slice."""
    src = qio.read(TUM)
    rng = np.random.default_rng(7)
    paths = []
    for i in range(n):
        a = int(rng.integers(0, len(src) - rows))
        r = qs.from_rotvec(rng.normal(size=3))
        q = qs.multiply(r, src.quats[a : a + rows])
        p = root / ("sub" if i % 2 else "") / f"rec{i}.txt"
        p.parent.mkdir(parents=True, exist_ok=True)
        qio.write(p, qio.Trajectory(src.times[a : a + rows], q, src.positions[a : a + rows]))
        paths.append(p)
    return paths


def test_sample_equals_single_file_command_bit_for_bit(tmp_path, client):
    inputs = _recordings(tmp_path / "in")
    out = tmp_path / "out"
    table = batch.run(
        "sample", [tmp_path / "in"], out, client=client, method="natural", rate=50.0, to="csv"
    )
    assert list(table["status"]) == ["ok"] * 4
    for p in inputs:
        rel = p.relative_to(tmp_path / "in").with_suffix(".csv")
        single = tmp_path / "single" / rel
        single.parent.mkdir(parents=True, exist_ok=True)
        assert (
            main(["sample", str(p), "-o", str(single), "--method", "natural", "--rate", "50"]) == 0
        )
        assert (out / rel).read_bytes() == single.read_bytes()
    assert (table["samples"] > 0).all()
    assert (out / "summary.csv").is_file() and (out / "summary.md").is_file()


def test_fit_equals_single_file_command_bit_for_bit(tmp_path, client):
    inputs = _recordings(tmp_path / "in", n=2, rows=300)
    out = tmp_path / "out"
    table = batch.run("fit", [tmp_path / "in"], out, client=client, smoothing="auto", rate=40.0)
    assert list(table["status"]) == ["ok", "ok"], table["error"].tolist()
    assert (table["smoothing"] > 0).all() and (table["effective_dof"] > 0).all()
    for p in inputs:
        rel = p.relative_to(tmp_path / "in").with_suffix(".csv")
        single = tmp_path / "single" / rel
        single.parent.mkdir(parents=True, exist_ok=True)
        assert main(["fit", str(p), "-o", str(single), "--rate", "40"]) == 0
        assert (out / rel).read_bytes() == single.read_bytes()


def test_corrupt_file_fails_alone(tmp_path, client):
    _recordings(tmp_path / "in", n=3)
    bad = tmp_path / "in" / "broken.txt"
    bad.write_text("0.0 1 2 3 4 5 6 7\n0.1 1 2 3 oops 5 6 7\n")
    out = tmp_path / "out"
    table = batch.run("sample", [tmp_path / "in"], out, client=client, method="slerp", count=20)
    row = table.set_index("file").loc["broken.txt"]
    assert row["status"] == "error" and "broken.txt:2" in row["error"]
    assert (table["status"] == "ok").sum() == 3
    assert "broken.txt" in (out / "batch.log").read_text()
    assert not (out / "broken.csv").exists()
    # the command line: every good file written, exit code 1 at the end
    code = main(["batch", "sample", str(tmp_path / "in"), "-o", str(tmp_path / "o2"),
                 "--count", "20", "--method", "slerp", "--workers", "1"])  # fmt: skip
    assert code == 1
    assert len(list((tmp_path / "o2").rglob("rec*.csv"))) == 3


def test_resume_after_deleting_half_the_outputs(tmp_path, client):
    _recordings(tmp_path / "in", n=4)
    out = tmp_path / "out"
    first = batch.run("sample", [tmp_path / "in"], out, client=client, method="squad", count=30)
    assert (first["status"] == "ok").all()
    outputs = sorted(out.rglob("rec*.csv"))
    before = {p: p.read_bytes() for p in outputs}
    for p in outputs[:2]:
        p.unlink()
    second = batch.run("sample", [tmp_path / "in"], out, client=client, method="squad", count=30)
    status = dict(zip(second["file"], second["status"]))
    assert sorted(status.values()) == ["ok", "ok", "skipped", "skipped"]
    assert {p: p.read_bytes() for p in outputs} == before
    # changed options redo everything; so does force
    third = batch.run("sample", [tmp_path / "in"], out, client=client, method="squad", count=31)
    assert (third["status"] == "ok").all()
    forced = batch.run(
        "sample", [tmp_path / "in"], out, client=client, method="squad", count=31, force=True
    )
    assert (forced["status"] == "ok").all()
    # a touched input is redone
    src = sorted((tmp_path / "in").rglob("rec*.txt"))[0]
    os.utime(src, ns=(time.time_ns(), time.time_ns() + 10**9))
    fourth = batch.run("sample", [tmp_path / "in"], out, client=client, method="squad", count=31)
    assert sorted(fourth["status"]) == ["ok", "skipped", "skipped", "skipped"]


def test_compare_summary_recomputed_from_the_table(tmp_path, client):
    _recordings(tmp_path / "in", n=4, rows=400)
    out = tmp_path / "out"
    methods = ["slerp", "squad", "natural"]
    table = batch.run("compare", [tmp_path / "in"], out, client=client, methods=methods, holdout=4)
    assert (table["status"] == "ok").all()
    summary = {r["method"]: r for r in batch.method_summary(table)}
    per_file = table[[f"holdout_median_deg[{m}]" for m in methods]].to_numpy()
    best = per_file.min(axis=1, keepdims=True)
    for j, m in enumerate(methods):
        assert summary[m]["median_of_medians_deg"] == pytest.approx(np.median(per_file[:, j]))
        assert summary[m]["wins"] == int(np.sum(per_file[:, j] == best[:, 0]))
    # the per-file figures are those of the library's compare on the same file
    one = sorted((tmp_path / "in").rglob("rec*.txt"))[0]
    rows = qs.ops.compare(qio.read(one), methods, holdout=4)
    name = str(one.relative_to(tmp_path / "in"))
    got = table.set_index("file").loc[name]
    for r in rows:
        assert got[f"holdout_median_deg[{r['method']}]"] == r["holdout_median_deg"]
    md = (out / "summary.md").read_text()
    assert "median of per-file medians" in md and "| natural |" in md
    on_disk = pd.read_csv(out / "summary.csv")
    assert len(on_disk) == len(table)
    assert (out / "summary.png").stat().st_size > 1000


def test_mixed_formats_in_one_directory(tmp_path, client):
    d = tmp_path / "in"
    d.mkdir()
    src = qio.read(EUROC)
    shutil.copy(EUROC, d / "euroc.csv")
    qio.write(d / "traj.json", qio.Trajectory(src.times[:200], src.quats[:200]))
    qio.write(d / "traj.txt", qio.Trajectory(src.times[:200], src.quats[:200], src.positions[:200]))
    table = batch.run("sample", [d], tmp_path / "out", client=client, method="slerp", count=25)
    assert (table["status"] == "ok").all(), table["error"].tolist()
    assert len(table) == 3


def test_external_scheduler_and_workers(tmp_path):
    """A scheduler and a worker started as separate processes, addresses on 127.0.0.1."""
    if shutil.which("dask", path=str(Path(sys.executable).parent)) is None:
        pytest.fail("the dask command line is missing from the environment")
    dask_cmd = str(Path(sys.executable).parent / "dask")
    sched_file = tmp_path / "scheduler.json"
    env = {**os.environ, "DASK_DISTRIBUTED__LOGGING__DISTRIBUTED": "error"}
    sched = subprocess.Popen(
        [dask_cmd, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
         "--scheduler-file", str(sched_file)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
    )  # fmt: skip
    worker = None
    try:
        for _ in range(300):
            if sched_file.is_file() and sched_file.stat().st_size > 0:
                break
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        worker = subprocess.Popen(
            [dask_cmd, "worker", address, "--nworkers", "1", "--nthreads", "1",
             "--no-dashboard", "--host", "127.0.0.1"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
        )  # fmt: skip
        _recordings(tmp_path / "in", n=2)
        with Client(address, timeout=30) as c:
            c.wait_for_workers(1, timeout=60)
        table = batch.run(
            "sample", [tmp_path / "in"], tmp_path / "out", scheduler=address, method="c3", count=40
        )
        assert (table["status"] == "ok").all()
        assert len(list((tmp_path / "out").rglob("rec*.csv"))) == 2
    finally:
        for p in (worker, sched):
            if p is not None:
                p.terminate()
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    p.kill()


# ---- bad input --------------------------------------------------------------------------------
def test_no_inputs_matched_names_the_patterns(tmp_path):
    with pytest.raises(ValueError, match=r"no files matched .*nothing\*\.tum"):
        batch.run("sample", [str(tmp_path / "nothing*.tum")], tmp_path / "out", count=5)
    code = main(["batch", "sample", str(tmp_path / "x*.csv"), "-o", str(tmp_path / "o"),
                 "--count", "5"])  # fmt: skip
    assert code == 1


def test_unreachable_scheduler_is_one_line_within_a_timeout(tmp_path, capsys):
    _recordings(tmp_path / "in", n=1)
    t0 = time.monotonic()
    code = main(["batch", "sample", str(tmp_path / "in"), "-o", str(tmp_path / "o"), "--count",
                 "5", "--scheduler", "tcp://127.0.0.1:9"])  # fmt: skip
    assert code == 1 and time.monotonic() - t0 < 60
    err = capsys.readouterr().err.strip()
    assert "cannot reach tcp://127.0.0.1:9" in err and len(err.splitlines()) == 1


def test_output_directory_that_is_a_file(tmp_path):
    _recordings(tmp_path / "in", n=1)
    f = tmp_path / "out"
    f.write_text("x")
    with pytest.raises(ValueError, match="not a directory"):
        batch.run("sample", [tmp_path / "in"], f, count=5)


def test_unknown_operation_and_missing_rate(tmp_path):
    with pytest.raises(ValueError, match="operation: unknown 'resample'"):
        batch.run("resample", [tmp_path], tmp_path / "o")
    _recordings(tmp_path / "in", n=1)
    with pytest.raises(ValueError, match="give rate="):
        batch.run("sample", [tmp_path / "in"], tmp_path / "o")
    # the command line: a usage error, as `quatspline sample` without --rate, --count or --at
    with pytest.raises(SystemExit) as e:
        main(["batch", "sample", str(tmp_path / "in"), "-o", str(tmp_path / "o")])
    assert e.value.code == 2
    assert not (tmp_path / "o").exists()


def test_too_large_file_is_refused_before_reading(tmp_path, client):
    _recordings(tmp_path / "in", n=2)
    table = batch.run(
        "sample", [tmp_path / "in"], tmp_path / "o", client=client, count=5, max_file_bytes=100
    )
    assert (table["status"] == "error").all()
    assert table["error"].str.contains("over the per-task limit of 100 bytes").all()


def test_expand_inputs_globs_and_duplicates(tmp_path):
    paths = _recordings(tmp_path / "in", n=4)
    got = batch.expand_inputs([str(tmp_path / "in" / "**" / "*.txt"), paths[0], tmp_path / "in"])
    assert sorted(map(str, got)) == sorted(map(str, paths))


# ---- inputs and outputs: never written over, never lost, never read back ----------------------
def _tree(root: Path) -> dict:
    return {p: p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def test_batch_refuses_to_overwrite_its_inputs(tmp_path, capsys):
    d = tmp_path / "d"
    (rec,) = _recordings(d, n=1)
    qio.write(d / "keys.csv", qio.read(rec))
    qio.write(d / "summary.csv", qio.read(rec))
    before = _tree(d)
    for argv in (
        ["sample", str(d), "-o", str(d)],  # the output directory is the input directory
        ["sample", str(d / "*.csv"), "-o", str(d)],  # d/keys.csv would be its own output
        ["fit", str(d / "keys.csv"), "-o", str(d)],
        ["sample", str(d / "summary.csv"), "-o", str(d)],  # the summary table over an input
    ):
        assert main(["batch", *argv, "--count", "5", "--workers", "1"]) == 2, argv
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and str(d) in err, err
        assert _tree(d) == before  # nothing written, not even a summary


@pytest.mark.parametrize("link", ["symbolic", "hard"])
@pytest.mark.parametrize("operation", batch.OPERATIONS)
def test_batch_refuses_outputs_that_are_an_input_through_a_link(tmp_path, operation, link):
    src = tmp_path / "in" / "a.txt"
    src.parent.mkdir()
    src.write_bytes(b"precious\n")
    out = tmp_path / "out"
    opts = {"count": 5} if operation in ("sample", "fit") else {}
    if operation == "imu-simulate":
        opts = {"rate": 100.0}
    (task,) = batch.plan(operation, [src], out, opts)
    task.output.parent.mkdir(parents=True)
    (os.symlink if link == "symbolic" else os.link)(src, task.output)
    with pytest.raises(ParameterError, match="refusing to overwrite the input file"):
        batch.run(operation, [src], out, workers=1, **opts)
    assert src.read_bytes() == b"precious\n"
    assert sorted(p.name for p in out.iterdir()) == [task.output.name]


#: Every extension a batch input may have (those a directory search keeps, and glTF).
_INPUT_EXTENSIONS = (*batch._TRAJ_EXT, ".gltf", ".glb")


@pytest.mark.parametrize("a, b", list(itertools.combinations(_INPUT_EXTENSIONS, 2)))
def test_outputs_of_inputs_sharing_a_stem_do_not_collide(tmp_path, a, b):
    inputs = [
        tmp_path / "in" / f"x{a}",
        tmp_path / "in" / f"X{b}",  # a case-insensitive file system would mix them too
        tmp_path / "in" / "sub" / f"x{a}",
        tmp_path / "other" / f"x{a}",  # same relative name, another directory
        tmp_path / "other" / f"summary{b}",  # named like the batch's own summary
    ]
    for p in inputs:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text("")
    cases = [("sample", {"count": 5}), ("fit", {"to": "tum"}), ("compare", {}), ("export", {})]
    for operation, opts in cases:
        tasks = batch.plan(operation, inputs, tmp_path / "out", opts)
        written = [t.output for t in tasks] + [t.record for t in tasks]
        written += [tmp_path / "out" / n for n in ("summary.csv", "summary.md", "batch.log")]
        assert len({str(p).casefold() for p in written}) == len(written), written


def test_both_results_are_kept_when_two_inputs_share_a_stem(tmp_path):
    a, b = _recordings(tmp_path / "in", n=2)
    (tmp_path / "in" / "x.tum").write_bytes(a.read_bytes())
    (tmp_path / "in" / "x.txt").write_bytes(b.read_bytes())
    inputs = [tmp_path / "in" / "x.tum", tmp_path / "in" / "x.txt"]
    tasks = batch.plan("sample", inputs, tmp_path / "out", {"count": 7})
    for t in tasks:
        row = batch.run_one("sample", t, {"method": "slerp", "count": 7})
        assert row["status"] == "ok", row["error"]
    for t, src in zip(tasks, (a, b)):
        single = tmp_path / "single" / (src.stem + ".csv")
        assert (
            main(["sample", str(src), "-o", str(single), "--method", "slerp", "--count", "7"]) == 0
        )
        assert t.output.read_bytes() == single.read_bytes()


def test_input_rewritten_during_its_run_is_not_skipped_as_up_to_date(tmp_path, monkeypatch):
    (src,) = _recordings(tmp_path / "in", n=1)
    opts = {"method": "slerp", "count": 5}
    (task,) = batch.plan("sample", [src], tmp_path / "out", opts)
    real = batch._OPERATION_FUNCS["sample"]

    def rewritten_meanwhile(task, options):
        figures = real(task, options)
        with open(task.input, "a") as f:
            f.write("# a line added while the batch ran\n")
        return figures

    monkeypatch.setitem(batch._OPERATION_FUNCS, "sample", rewritten_meanwhile)
    row = batch.run_one("sample", task, opts)
    assert row["status"] == "error" and "changed while it was being processed" in row["error"]
    monkeypatch.setitem(batch._OPERATION_FUNCS, "sample", real)
    assert batch.run_one("sample", task, opts)["status"] == "ok"  # redone, not skipped
    assert batch.run_one("sample", task, opts)["status"] == "skipped"


def test_rerun_removes_its_own_stale_temporaries_and_nothing_else(tmp_path, client):
    _recordings(tmp_path / "in", n=1)
    out = tmp_path / "out"
    args = ("sample", [tmp_path / "in"], out)
    assert (batch.run(*args, client=client, method="slerp", count=5)["status"] == "ok").all()
    (task,) = batch.plan("sample", [tmp_path / "in" / "rec0.txt"], out, {"count": 5})
    state = task.record.parent
    stale = [
        out / ".rec0.csv.0123456789ab.tmp",
        state / f".{task.record.name}.a1b2c3d4e5f6.tmp",
        out / ".summary.csv.00112233aabb.tmp",
    ]
    kept = [
        out / ".rec0.csv.notes.tmp",  # not the atomic writer's pattern
        out / ".other.csv.0123456789ab.tmp",  # not a file this batch writes
        out / "rec0.csv.0123456789ab.tmp",
        state / ".rec0.csv.0123456789ab.tmp",  # rec0.csv is not written in the state dir
    ]
    live = out / ".rec0.csv.fedcba987654.tmp"  # a live writer holds a lock on its temporary
    hour_ago = time.time() - 3600
    for p in [*stale, *kept, live]:
        p.write_text("partial")
    for p in [*stale, *kept]:
        os.utime(p, (hour_ago, hour_ago))
    user = tmp_path / "mine.txt"
    user.write_text("mine")
    link = out / ".rec0.csv.abcdefabcdef.tmp"
    os.symlink(user, link)
    os.utime(link, (hour_ago, hour_ago), follow_symlinks=False)
    with open(live, "rb") as held:
        fcntl.flock(held.fileno(), fcntl.LOCK_EX)
        again = batch.run(*args, client=client, method="slerp", count=5)
    assert (again["status"] == "skipped").all()
    assert [p for p in stale if os.path.lexists(p)] == []
    assert all(p.exists() for p in [*kept, live])
    assert link.is_symlink() and user.read_text() == "mine"


def test_recursive_globs_and_walks_list_each_real_directory_once(tmp_path, monkeypatch):
    d = tmp_path / "d"
    (d / "a" / "b").mkdir(parents=True)
    x = d / "a" / "b" / "x.csv"
    x.write_text("")
    os.symlink("../..", d / "a" / "b" / "up")  # loops back to d
    listed = []
    scandir = os.scandir

    def counting_scandir(path="."):
        listed.append(os.path.realpath(path))
        return scandir(path)

    monkeypatch.setattr(os, "scandir", counting_scandir)
    patterns = (str(d / "**" / "*.csv"), str(d / "**"), str(d / "*" / "**" / "*.csv"), d)
    for pattern in patterns:
        listed.clear()
        assert batch.expand_inputs([pattern]) == [x]
        assert sorted(listed) == sorted(set(listed)), pattern
    # more loops: a search following them would take 2**40 steps (the kernel's link limit)
    os.symlink(".", d / "a" / "self")
    os.symlink("..", d / "a" / "b" / "parent")
    for pattern in patterns:
        listed.clear()
        assert batch.expand_inputs([pattern]) == [x]
        assert sorted(listed) == sorted(set(listed)), pattern


def test_named_inputs_that_give_nothing_are_error_rows(tmp_path, client, capsys):
    (good,) = _recordings(tmp_path / "in", n=1)
    os.mkfifo(tmp_path / "in" / "pipe.txt")  # found by the directory search
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    os.mkfifo(tmp_path / "glob.tum")
    (tmp_path / "empty").mkdir()
    named = {
        "missing": tmp_path / "missing.csv",
        "fifo": fifo,
        "empty": tmp_path / "empty",
        "pattern": tmp_path / "none*.tum",
        "walked fifo": tmp_path / "in" / "pipe.txt",
        "globbed fifo": tmp_path / "glob.tum",
    }
    paths = [tmp_path / "in", named["missing"], fifo, named["empty"], str(named["pattern"])]
    paths.append(str(tmp_path / "g*.tum"))
    table = batch.run("sample", paths, tmp_path / "out", client=client, method="slerp", count=5)
    rows = table.set_index("file")
    assert list(rows.loc[rows["status"] == "ok"].index) == [good.name]
    for what, p in named.items():
        err = rows.loc[str(p), "error"]
        assert rows.loc[str(p), "status"] == "error" and str(p) in err, what
        assert "\n" not in err
    assert str(named["missing"]) in (tmp_path / "out" / "batch.log").read_text()
    argv = [str(good), str(named["missing"]), str(fifo), str(named["empty"])]
    code = main(["batch", "sample", *argv, "-o", str(tmp_path / "o2"), "--count", "5",
                 "--workers", "1"])  # fmt: skip
    assert code == 1
    assert (tmp_path / "o2" / "rec0.csv").is_file()


def test_output_directory_inside_the_input_directory_is_not_read_back(tmp_path, client):
    _recordings(tmp_path / "in", n=2)
    out = tmp_path / "in" / "out"
    kw = dict(client=client, method="slerp", count=5)
    first = batch.run("sample", [tmp_path / "in"], out, **kw)
    assert sorted(first["status"]) == ["ok", "ok"]
    for pattern in (
        tmp_path / "in",
        str(tmp_path / "in" / "**" / "*"),
        str(tmp_path / "*" / "**" / "*.*"),
    ):
        again = batch.run("sample", [pattern], out, **kw)
        assert sorted(again["file"]) == sorted(first["file"]), pattern
        assert (again["status"] == "skipped").all()


def test_zero_or_negative_workers_are_refused(tmp_path, capsys):
    _recordings(tmp_path / "in", n=1)
    for workers in (0, -2):
        with pytest.raises(ParameterError, match="workers: expected at least 1"):
            batch.run("sample", [tmp_path / "in"], tmp_path / "out", workers=workers, count=5)
        code = main(["batch", "sample", str(tmp_path / "in"), "-o", str(tmp_path / "out"),
                     "--count", "5", "--workers", str(workers)])  # fmt: skip
        err = capsys.readouterr().err.strip()
        assert code == 2 and len(err.splitlines()) == 1 and "--workers" in err, err
    assert not (tmp_path / "out").exists()


def test_batch_never_overwrites_files_it_did_not_write(tmp_path, client):
    d = tmp_path / "d"
    (rec,) = _recordings(d, n=1)
    tum = d / "walk.tum"
    tum.write_bytes(rec.read_bytes())
    user = d / "walk.csv"  # the user's own file, where the batch's output would go
    user.write_text("the user's notes\n")
    table = batch.run("sample", [str(d / "*.tum")], d, client=client, method="slerp", count=5)
    (err,) = table["error"]
    assert "walk.csv: exists and was not written by this batch" in err
    assert user.read_text() == "the user's notes\n"
    user.unlink()  # once moved away, the batch writes it, and may rewrite its own output
    for count in (5, 6):
        table = batch.run("sample", [str(d / "*.tum")], d, client=client, count=count)
        assert list(table["status"]) == ["ok"] and len(qio.read(user)) == count
    # summary files in a directory where no batch ran are a user's too
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.md").write_text("# my summary\n")
    with pytest.raises(ParameterError, match="summary.md: exists and was not written"):
        batch.run("sample", [tum], out, client=client, count=5)
    assert [p.name for p in out.iterdir()] == ["summary.md"]
