"""Files: nothing lost, nothing wedged. The ROS 2 bag writer replaces only a directory that
provably is a bag (and keeps its mode); KITTI poses and times change together, even across a
kill; killed writes' temporaries are removed by the next write, and nothing else is; FIFOs
and devices are refused by every reader without blocking; a bag with a foreign message
definition, and any third-party parser error, is a one-line error naming the file."""

from __future__ import annotations

import fcntl
import importlib.util
import os
import signal
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline._util import atomic as _atomic
from quatspline.io import _common
from quatspline.io import rosbag as qbag
from scipy.spatial.transform import Rotation

from ..splinekit import random_walk

ENV = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}


def poses(n, seed=0, t0=0.0):
    q = random_walk(n, seed, step=0.2)
    p = np.random.default_rng(seed).normal(size=(n, 3))
    return qio.Trajectory(t0 + np.arange(n) * 0.1, q, p)


def run_python(code: str, timeout: float = 120.0) -> subprocess.CompletedProcess:
    """Runs ``code`` in a child Python; a hang fails the test (TimeoutExpired) instead of
    wedging the suite."""
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        env=ENV,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


# --- ROS 2 bag directories: replace only a provable bag ----------------------------------------

HAS_ROSBAGS = importlib.util.find_spec("rosbags") is not None
needs_rosbags = pytest.mark.skipif(
    not HAS_ROSBAGS, reason="bag extra: pip install 'quatspline[bag]'"
)


@needs_rosbags
def test_bag_writer_refuses_to_delete_a_directory_that_is_not_its_bag(tmp_path):
    tr = poses(5)
    project = tmp_path / "project"
    project.mkdir()
    (project / "metadata.yaml").write_text("name: my project\n")
    (project / "thesis.tex").write_text("\\documentclass{article}")
    with pytest.raises(ValueError, match=r"project: is a directory but not a ROS 2 bag"):
        qio.write(project, tr, format="rosbag")
    assert (project / "thesis.tex").read_text() == "\\documentclass{article}"
    # a real bag with a user's file put inside is not a bag we may delete either
    bag = tmp_path / "bag"
    qio.write(bag, tr, format="rosbag")
    (bag / "notes.txt").write_text("keep me")
    with pytest.raises(ValueError, match=r"bag: holds files that are not part of the bag"):
        qio.write(bag, poses(7, 1), format="rosbag")
    assert (bag / "notes.txt").read_text() == "keep me"
    assert len(qio.read(bag)) == 5
    # an empty directory, a directory without metadata, a regular file: refused, untouched
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match=r"empty: is a directory but not a ROS 2 bag"):
        qio.write(empty, tr, format="rosbag")
    plain = tmp_path / "plain"
    plain.write_text("data")
    with pytest.raises(ValueError, match=r"plain: exists and is not a ROS 2 bag directory"):
        qio.write(plain, tr, format="rosbag")
    assert plain.read_text() == "data" and empty.is_dir()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag", "empty", "plain", "project"]


@needs_rosbags
def test_bag_writer_replaces_its_own_bag_keeping_the_directory_mode(tmp_path):
    bag = tmp_path / "bag"
    qio.write(bag, poses(5), format="rosbag")
    os.chmod(bag, 0o700)
    new = poses(9, 3, t0=100.0)
    qio.write(bag, new, format="rosbag")
    assert stat.S_IMODE(bag.stat().st_mode) == 0o700
    back = qio.read(bag)
    np.testing.assert_allclose(back.times, new.times, atol=1e-9)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag"]  # no work directory left
    # a new bag directory gets the usual mode of a new directory (0777 less the umask)
    umask = os.umask(0o022)
    try:
        qio.write(tmp_path / "fresh", new, format="rosbag")
    finally:
        os.umask(umask)
    assert stat.S_IMODE((tmp_path / "fresh").stat().st_mode) == 0o755


@needs_rosbags
def test_bag_writer_restores_the_old_bag_when_the_swap_fails(tmp_path, monkeypatch):
    bag = tmp_path / "bag"
    old = poses(5)
    qio.write(bag, old, format="rosbag")
    monkeypatch.setattr(qbag, "_exchange", lambda a, b: False)  # the two-rename path
    real_rename = os.rename

    def failing_rename(src, dst):
        if Path(src).name == "bag" and Path(src).parent.name.endswith(".bagtmp"):
            raise OSError(28, "No space left on device")
        return real_rename(src, dst)

    monkeypatch.setattr(os, "rename", failing_rename)
    with pytest.raises(OSError, match="No space left"):
        qio.write(bag, poses(9, 2), format="rosbag")
    monkeypatch.setattr(os, "rename", real_rename)
    assert len(qio.read(bag)) == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bag"]


@needs_rosbags
def test_bag_killed_mid_swap_gets_its_old_bag_back_on_the_next_write(tmp_path):
    """A kill between "old bag aside" and "new bag in" leaves the old bag inside the work
    directory and no target: the next write's clean-up puts it back first."""
    bag = tmp_path / "bag"
    qio.write(bag, poses(5), format="rosbag")
    work = tmp_path / ".bag.0123456789ab.bagtmp"
    work.mkdir()
    os.rename(bag, work / "old")
    qio.write(tmp_path / "other", poses(3), format="rosbag")  # another target: not touched
    assert work.is_dir() and not bag.exists()
    removed = _atomic.remove_stale_temporaries(
        bag, suffixes=(".bagtmp",), remove=qbag._remove_work_dir
    )
    assert removed == [work] and not work.exists()
    assert len(qio.read(bag)) == 5  # the old bag is back
    # and a full re-run of the write: restored, then replaced by the new bag
    work.mkdir()
    os.rename(bag, work / "old")
    qio.write(bag, poses(7, 1), format="rosbag")
    assert len(qio.read(bag)) == 7 and sorted(p.name for p in tmp_path.iterdir()) == [
        "bag",
        "other",
    ]


# --- KITTI: the pair changes together; refuse what the format cannot hold -----------------------

KILL_BETWEEN = """
    import os, signal, sys
    import numpy as np
    import quatspline.io as qio
    from quatspline._util import atomic as _atomic
    from tests.io.test_io_dataloss import poses

    d = sys.argv[1] if len(sys.argv) > 1 else {d!r}
    real = os.replace
    calls = []

    def replace(src, dst):
        calls.append(dst)
        if {when!r} == "before-commit" and str(dst).endswith(".pair"):
            os.kill(os.getpid(), signal.SIGKILL)
        real(src, dst)
        if {when!r} == "between" and str(dst).endswith("times.txt"):
            os.kill(os.getpid(), signal.SIGKILL)
        if {when!r} == "between" and str(dst).endswith("poses.txt") and len(calls) == 1:
            os.kill(os.getpid(), signal.SIGKILL)  # the old scheme renames the poses first

    os.replace = replace
    qio.write(d + "/poses.txt", poses(30, 1), format="kitti", times_path=d + "/times.txt")
"""


@pytest.mark.parametrize("when", ["between", "before-commit"])
def test_kitti_pair_killed_mid_write_reads_both_old_or_both_new(tmp_path, when):
    old = poses(10)
    qio.write(tmp_path / "poses.txt", old, format="kitti", times_path=tmp_path / "times.txt")
    root = Path(__file__).resolve().parents[2]
    r = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(KILL_BETWEEN.format(d=str(tmp_path), when=when))],
        env=ENV,
        cwd=root,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == -signal.SIGKILL, r.stderr
    back = qio.read(tmp_path / "poses.txt", times=tmp_path / "times.txt")
    want = poses(30, 1) if when == "between" else old
    np.testing.assert_array_equal(back.times, want.times)
    np.testing.assert_allclose(back.positions, want.positions, atol=1e-12)
    # the next write completes or discards the interrupted one and leaves nothing behind
    newest = poses(4, 2)
    qio.write(tmp_path / "poses.txt", newest, format="kitti", times_path=tmp_path / "times.txt")
    back = qio.read(tmp_path / "poses.txt", times=tmp_path / "times.txt")
    np.testing.assert_array_equal(back.times, newest.times)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["poses.txt", "times.txt"]


def test_atomic_write_pair_keeps_both_modes_and_refuses_one_file_twice(tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("old a")
    b.write_text("old b")
    os.chmod(a, 0o600)
    os.chmod(b, 0o640)
    with _atomic.atomic_write_pair(a, b) as (f, g):
        f.write("new a")
        g.write("new b")
    assert (a.read_text(), b.read_text()) == ("new a", "new b")
    assert stat.S_IMODE(a.stat().st_mode) == 0o600 and stat.S_IMODE(b.stat().st_mode) == 0o640
    with pytest.raises(ValueError, match="is the same file as"):
        with _atomic.atomic_write_pair(a, a):
            pass
    with pytest.raises(KeyboardInterrupt):  # an error before the commit point: nothing changes
        with _atomic.atomic_write_pair(a, b) as (f, g):
            f.write("newer a")
            raise KeyboardInterrupt
    assert (a.read_text(), b.read_text()) == ("new a", "new b")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


def test_kitti_writer_refuses_times_it_cannot_hold(tmp_path):
    tr = poses(6)  # times 0, 0.1, …: not the frame numbers a KITTI file without times means
    path = tmp_path / "k.txt"
    with pytest.raises(ValueError, match=r"k.txt: KITTI poses hold no times .* times_path="):
        qio.write(path, tr, format="kitti")
    assert not path.exists()
    frames = qio.Trajectory(np.arange(6.0), tr.quats, tr.positions)
    qio.write(path, frames, format="kitti")  # exactly what the reader assumes: lossless
    np.testing.assert_array_equal(qio.read(path).times, np.arange(6.0))


def test_kitti_writer_refuses_extra_columns_instead_of_dropping_them(tmp_path):
    tr = qio.Trajectory(np.arange(4.0), poses(4).quats, poses(4).positions)
    tr.extra["gyro"] = np.zeros((4, 3))
    with pytest.raises(ValueError, match=r"k.txt: the KITTI format has no columns for gyro"):
        qio.write(tmp_path / "k.txt", tr, format="kitti", times_path=tmp_path / "t.txt")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "block",
    [
        [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]],  # a shear (determinant 1)
        [[2, 0, 0], [0, 2, 0], [0, 0, 2]],  # 2·I
        [[0.9, 0, 0], [0, 0.9, 0], [0, 0, 1.2]],  # det ≈ 0.97, not orthonormal
        [[1, 0, 0], [0, 1, 0], [0, 0, -1]],  # orthonormal but a reflection
    ],
)
def test_kitti_refuses_blocks_that_are_not_rotations(tmp_path, block):
    good = Rotation.random(3, random_state=1).as_matrix()
    mats = np.concatenate([good, np.array(block, dtype=float)[None]])
    rows = np.concatenate([mats, np.ones((4, 3, 1))], axis=2).reshape(4, 12)
    np.savetxt(tmp_path / "k.txt", rows, fmt="%.9e")
    with pytest.raises(ValueError, match=r"k.txt:4: the 3×3 block is not a rotation"):
        qio.read(tmp_path / "k.txt")


def test_kitti_accepts_rotations_printed_with_few_digits(tmp_path):
    r = Rotation.random(200, random_state=4)
    rows = np.concatenate([r.as_matrix(), np.zeros((200, 3, 1))], axis=2).reshape(200, 12)
    for fmt in ("%.4f", "%e", "%.9e"):  # 4 decimals, KITTI's own 6 digits, 9 digits
        np.savetxt(tmp_path / "k.txt", rows, fmt=fmt)
        back = qio.read(tmp_path / "k.txt")
        assert np.max(qs.angle_between(back.quats, r.as_quat()[:, [3, 0, 1, 2]])) < 1e-3


# --- temporaries of killed writes ---------------------------------------------------------------

KILLED_WRITER = """
    import sys, time
    from quatspline._util.atomic import atomic_write
    with atomic_write(sys.argv[1]) as f:
        f.write("x" * 100000)
        f.flush()
        print("writing", flush=True)
        time.sleep(600)
"""


def test_a_rerun_removes_the_temporaries_of_a_killed_write_and_only_those(tmp_path):
    out = tmp_path / "out.csv"
    child = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(KILLED_WRITER), str(out)],
        env=ENV,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout.readline().strip() == "writing"
        child.send_signal(signal.SIGKILL)
    finally:
        child.wait(timeout=60)
        child.stdout.close()
    stale = [p for p in tmp_path.iterdir() if p.name.startswith(".out.csv.")]
    assert len(stale) == 1 and stale[0].stat().st_size == 100000
    # look-alikes a user may own, and a live writer's temporary (locked): they stay
    keep = [
        ".out.csv.notmine.tmp",
        ".out.csv.0123456789ab.tmp.bak",
        ".out.csv.0123456789AB.tmp",
        ".other.csv.0123456789ab.tmp",
        "out.csv.0123456789ab.tmp",
    ]
    for name in keep:
        (tmp_path / name).write_text("user data")
    (tmp_path / ".out.csv.aaaaaaaaaaaa.tmp").mkdir()  # a directory: not a file temporary
    (tmp_path / "precious").write_text("user data")
    (tmp_path / ".out.csv.dddddddddddd.tmp").symlink_to(tmp_path / "precious")  # a link
    live = tmp_path / ".out.csv.bbbbbbbbbbbb.tmp"
    live.write_text("in progress")
    fd = os.open(live, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)
    empty_new = tmp_path / ".out.csv.cccccccccccc.tmp"  # just created: may be a writer's
    empty_new.touch()
    try:
        qio.write(out, poses(3), format="csv")
        assert not stale[0].exists()
        for name in keep:
            assert (tmp_path / name).read_text() == "user data"
        assert live.exists() and empty_new.exists()
        assert (tmp_path / ".out.csv.aaaaaaaaaaaa.tmp").is_dir()
        assert (tmp_path / ".out.csv.dddddddddddd.tmp").is_symlink()
        assert (tmp_path / "precious").read_text() == "user data"
        # an empty one nobody locks, unchanged for longer than a writer needs to lock it
        old = time.time() - 10 * _atomic.STALE_EMPTY_SECONDS
        os.utime(empty_new, (old, old))
        qio.write(out, poses(3), format="csv")
        assert not empty_new.exists() and live.exists()
    finally:
        os.close(fd)
    qio.write(out, poses(3), format="csv")  # the live writer is gone: its temporary is stale
    assert not live.exists()


@needs_rosbags
def test_a_rerun_removes_a_killed_bag_writes_work_directory_and_only_that(tmp_path):
    stale = tmp_path / ".bag.0123456789ab.bagtmp"
    (stale / "bag").mkdir(parents=True)
    (stale / "bag" / "bag.db3").write_bytes(b"partial")
    similar = tmp_path / ".bag.0123456789ab.bagtmp.mine"
    similar.mkdir()
    (similar / "data").write_text("user data")
    other = tmp_path / ".other.0123456789ab.bagtmp"
    other.mkdir()
    qio.write(tmp_path / "bag", poses(4), format="rosbag")
    assert not stale.exists()
    assert (similar / "data").read_text() == "user data" and other.is_dir()


# --- special files: refused without blocking ----------------------------------------------------

SPECIAL = """
    import os, sys
    from pathlib import Path
    import numpy as np
    import quatspline.io as qio
    d = Path(sys.argv[1]) if len(sys.argv) > 1 else Path({d!r})
    cases = {{
        "csv": lambda: qio.read(d / "fifo.csv"),
        "tum": lambda: qio.read(d / "fifo.txt", format="tum"),
        "json": lambda: qio.read(d / "fifo.json"),
        "npz": lambda: qio.read(d / "fifo.npz"),
        "bvh": lambda: qio.read(d / "fifo.bvh"),
        "euroc": lambda: qio.read(d / "fifo.csv", format="euroc"),
        "repoimu": lambda: qio.read(d / "fifo.csv", format="repoimu"),
        "kitti": lambda: qio.read(d / "fifo.txt", format="kitti"),
        "kitti times fifo": lambda: qio.read(d / "k.txt", times=d / "fifo.txt"),
        "kitti times /dev/zero": lambda: qio.read(d / "k.txt", times=d / "zero.txt"),
        "bag db3 fifo": lambda: qio.read(d / "bag"),
        "bag metadata fifo": lambda: qio.read(d / "bag2", format="rosbag"),
    }}
    for name, fn in cases.items():
        try:
            fn()
            print(name, "| READ")
        except ValueError as e:
            print(name, "|", str(e).replace(chr(10), " "))
"""


def test_every_reader_refuses_fifos_and_devices_without_hanging(tmp_path):
    os.mkfifo(tmp_path / "fifo.csv")
    for ext in ("txt", "json", "npz", "bvh"):
        os.mkfifo(tmp_path / f"fifo.{ext}")
    (tmp_path / "zero.txt").symlink_to("/dev/zero")
    frames = qio.Trajectory(np.arange(3.0), poses(3).quats, poses(3).positions)
    qio.write(tmp_path / "k.txt", frames, format="kitti")
    if HAS_ROSBAGS:
        qio.write(tmp_path / "bag", poses(3), format="rosbag")
        (db3,) = (tmp_path / "bag").glob("*.db3")
        db3.unlink()
        os.mkfifo(db3)
        qio.write(tmp_path / "bag2", poses(3), format="rosbag")
        (tmp_path / "bag2" / "metadata.yaml").unlink()
        os.mkfifo(tmp_path / "bag2" / "metadata.yaml")
    r = run_python(SPECIAL.format(d=str(tmp_path)))
    assert r.returncode == 0, r.stderr
    got = dict(line.split(" | ", 1) for line in r.stdout.splitlines())
    for name, message in got.items():
        if name.startswith("bag") and not HAS_ROSBAGS:
            continue
        assert "is a FIFO (named pipe); only regular files are read" in message or (
            "is a device; only regular files are read" in message
        ), (name, message)
    assert "zero.txt: is a device" in got["kitti times /dev/zero"]
    assert "fifo.txt: is a FIFO" in got["kitti times fifo"]


def test_a_fifo_swapped_in_after_the_check_does_not_block_the_open(tmp_path, monkeypatch):
    """The race: the path passes the check, then becomes a FIFO before it is opened. The
    open does not block (O_NONBLOCK) and the descriptor's own check refuses it."""
    fifo = tmp_path / "late.csv"
    os.mkfifo(fifo)
    monkeypatch.setattr(_common, "check_regular_input", lambda path: None)
    with pytest.raises(ValueError, match=r"late.csv: is a FIFO \(named pipe\)"):
        _common.open_regular(fifo)


# --- foreign message definitions, third-party parser errors -------------------------------------


@needs_rosbags
@pytest.mark.parametrize(
    ("definition", "field"),
    [
        ("std_msgs/Header header\ngeometry_msgs/Pose posture\n", "pose.orientation"),
        ("std_msgs/Header head\ngeometry_msgs/Pose pose\n", "header.stamp.sec"),
        ("std_msgs/Header header\nstring pose\n", "pose.orientation"),
    ],
)
def test_bag_with_a_renamed_field_is_a_one_line_error_naming_the_file(tmp_path, definition, field):
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    name = "geometry_msgs/msg/PoseStamped"
    # a store where PoseStamped has the foreign definition, embedded in the bag as is
    foreign = get_typestore(Stores.ROS1_NOETIC)
    foreign.fielddefs.pop(name, None)
    foreign.types.pop(name, None)
    foreign.register(get_types_from_msg(definition, name))
    T = foreign.types
    Msg = T[name]
    header = T["std_msgs/msg/Header"](
        seq=0, stamp=T["builtin_interfaces/msg/Time"](sec=1, nanosec=0), frame_id="m"
    )
    pose = T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=0.0),
        orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
    )
    values = {"header": header, "head": header, "pose": pose, "posture": pose}
    if "string pose" in definition:
        values["pose"] = "text"
    msg = Msg(**{f: values[f] for f in Msg.__dataclass_fields__ if not f.startswith("__")})
    path = tmp_path / "foreign.bag"
    with Writer(path) as w:
        conn = w.add_connection("/pose", name, typestore=foreign)
        w.write(conn, 1_000_000_000, foreign.serialize_ros1(msg, name))
    with pytest.raises(qio.TrajectoryError) as e:
        qio.read(path)
    text = str(e.value)
    assert f"foreign.bag: topic '/pose', message 1: no field '{field}" in text, text
    assert "\n" not in text


def test_any_third_party_parser_error_becomes_a_one_line_error_naming_the_file(
    tmp_path, monkeypatch
):
    path = tmp_path / "a.json"
    path.write_text("{}")

    def parser(p, **options):  # a third-party parser (outside the package) failing on bytes
        return {"a": 1}["missing\nkey"]

    from quatspline.io import json_format

    monkeypatch.setattr(json_format, "read", parser)
    with pytest.raises(qio.TrajectoryError, match=r"a.json: not a readable json file \(KeyError"):
        qio.read(path)
    try:
        qio.read(path)
    except qio.TrajectoryError as e:
        assert "\n" not in str(e)


def test_a_wrong_option_kind_inside_the_package_stays_a_type_error(tmp_path):
    frames = qio.Trajectory(np.arange(3.0), poses(3).quats, poses(3).positions)
    qio.write(tmp_path / "k.txt", frames, format="kitti")
    with pytest.raises(TypeError):
        qio.read(tmp_path / "k.txt", format="kitti", times=object())


@needs_rosbags
def test_bag_with_a_retyped_field_is_refused_not_converted(tmp_path):
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    name, qn = "geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/Quaternion"
    foreign = get_typestore(Stores.ROS1_NOETIC)
    foreign.fielddefs.pop(qn)
    foreign.types.pop(qn)
    foreign.register(get_types_from_msg("float64 x\nfloat64 y\nfloat64 z\nstring w\n", qn))
    T = foreign.types
    header = T["std_msgs/msg/Header"](
        seq=0, stamp=T["builtin_interfaces/msg/Time"](sec=1, nanosec=0), frame_id="m"
    )
    pose = T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=0.0, y=0.0, z=0.0),
        orientation=T[qn](x=0.0, y=0.0, z=0.0, w="1.0"),
    )
    path = tmp_path / "retyped.bag"
    with Writer(path) as w:
        conn = w.add_connection("/pose", name, typestore=foreign)
        raw = foreign.serialize_ros1(T[name](header=header, pose=pose), name)
        w.write(conn, 1_000_000_000, raw)
    with pytest.raises(
        qio.TrajectoryError,
        match=r"retyped.bag: topic '/pose', message 1: field 'pose.orientation.w' is str",
    ):
        qio.read(path)
