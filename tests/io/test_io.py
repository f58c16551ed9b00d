"""File formats: round trips, the bundled real recordings, and malformed files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio

from ..splinekit import random_walk

DATA = Path(__file__).resolve().parents[2] / "data"
TUM = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
EUROC = DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv"
REPOIMU = DATA / "repoimu" / "repoIMU_first30s.csv"
BVH = DATA / "mocapbank_bvh" / "test_mocapbank.bvh"
BVH_HEAD = (
    "HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n}\nMOTION\n"
)


def traj(n=20, seed=0, positions=True):
    q = random_walk(n, seed)
    t = 1.5 + 0.01 * np.arange(n)
    p = np.random.default_rng(seed).normal(size=(n, 3)) if positions else None
    return qio.Trajectory(t, q, p)


def same_rotation(a, b, tol):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    assert np.max(d) <= tol


@pytest.mark.parametrize(
    ("name", "fmt", "tol_t"),
    [
        ("a.csv", None, 0),
        ("a.json", None, 0),
        ("a.npz", None, 0),
        ("a.txt", None, 0),
        ("a.csv", "euroc", 1e-6),
        ("a.csv", "repoimu", 0),
        ("a.bvh", None, 1e-12),
    ],
)
def test_round_trips(tmp_path, name, fmt, tol_t):
    src = traj(positions=fmt != "repoimu")
    path = tmp_path / name
    qio.write(path, src, format=fmt)
    back = qio.read(path, format=fmt)
    assert len(back) == len(src)
    if name.endswith(".bvh"):  # BVH stores a frame time, not a start time: frames start at 0
        np.testing.assert_allclose(back.times, src.times - src.times[0], atol=tol_t, rtol=0)
    else:
        np.testing.assert_allclose(back.times, src.times, atol=tol_t, rtol=0)
    same_rotation(back.quats, src.quats, 1e-12)
    if src.positions is not None:
        np.testing.assert_allclose(back.positions, src.positions, atol=1e-12)


def test_csv_scalar_last_header_and_euler_and_bom_crlf(tmp_path):
    q = random_walk(5, 1)
    p = tmp_path / "xyzw.csv"
    rows = "\r\n".join(
        f"{i},{a[1]:.17g},{a[2]:.17g},{a[3]:.17g},{a[0]:.17g}" for i, a in enumerate(q)
    )
    p.write_bytes(("\ufefftime,qx,qy,qz,qw\r\n" + rows + "\r\n").encode("utf-8"))
    np.testing.assert_allclose(qio.read(p).quats, q, atol=1e-15)
    e = tmp_path / "euler.csv"
    ang = qs.as_euler(q, "ZYX", degrees=True)
    e.write_text(
        "t;yaw;pitch;roll\n"
        if False
        else "t,roll,pitch,yaw\n"
        + "\n".join(f"{i},{a[0]:.17g},{a[1]:.17g},{a[2]:.17g}" for i, a in enumerate(ang))
    )
    got = qio.read(e, euler="ZYX", degrees=True)
    same_rotation(got.quats, q, 1e-13)


def test_real_tum_rgbd_spot_values():
    t = qio.read(TUM)
    assert len(t) == 3000
    # first data line: 1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986
    assert t.times[0] == 1305031098.6659
    np.testing.assert_allclose(t.positions[0], [1.3563, 0.6305, 1.6380])
    ref = np.array([-0.3986, 0.6132, 0.5962, -0.3311])
    np.testing.assert_allclose(t.quats[0], ref / np.linalg.norm(ref), atol=1e-15)


def test_real_euroc_spot_values():
    t = qio.read(EUROC)
    assert len(t) == 2000 and qio.detect_format(EUROC) == "euroc"
    # 1403715524907143168,0.515356,1.996773,0.971104,0.161996,0.789985,-0.205376,0.554528,…
    assert abs(t.times[0] - 1403715524.907143168) < 1e-6
    np.testing.assert_allclose(t.positions[0], [0.515356, 1.996773, 0.971104])
    ref = np.array([0.161996, 0.789985, -0.205376, 0.554528])
    np.testing.assert_allclose(t.quats[0], ref / np.linalg.norm(ref), atol=1e-15)
    assert np.all(np.diff(t.times) > 0.004)


def test_real_repoimu_spot_values():
    t = qio.read(REPOIMU)
    assert len(t) == 3000 and t.times[0] == 0.08 and t.positions is None
    np.testing.assert_allclose(t.quats[0], [1, 0, 1.6232e-35, 0], atol=1e-40)


def test_real_bvh_joints_and_channel_order():
    t = qio.read(BVH)
    assert len(t) == 455 and abs(t.times[1] - 0.033333) < 1e-12
    # root: Xposition Yposition Zposition Zrotation Xrotation Yrotation, first frame
    # -44.0003 93.5663 229.0256 -7.98 -20.33 -7.46
    np.testing.assert_allclose(t.positions[0], [-44.0003, 93.5663, 229.0256])
    np.testing.assert_allclose(
        t.quats[0], qs.from_euler("ZXY", [-7.98, -20.33, -7.46], degrees=True), atol=1e-15
    )
    wrist = qio.read(BVH, joint="LeftWrist", world=True)
    assert wrist.positions is not None and wrist.name == "LeftWrist"
    # world rotation = product of the local rotations down the chain
    chain = ["Hips", "Chest", "Chest2", "LeftCollar", "LeftShoulder", "LeftElbow", "LeftWrist"]
    r = np.array([1.0, 0, 0, 0])
    for j in chain:
        r = qs.multiply(r, qio.read(BVH, joint=j).quats[0])
    same_rotation(wrist.quats[:1], r[None], 1e-14)
    with pytest.raises(ValueError, match=r"no joint 'Tail'; joints: Hips, Chest"):
        qio.read(BVH, joint="Tail")


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        (
            "a.csv",
            "t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,x,0\n",
            r"a.csv:3: column 4 \('qy'\): not a number: 'x'",
        ),
        ("a.csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0\n", r"a.csv:3: expected 5 columns"),
        ("a.csv", "foo,qw,qx,qy,qz\n0,1,0,0,0\n", r"a.csv:1: bad header: no time column"),
        ("a.csv", "t,a,b,c,d\n0,1,0,0,0\n", r"a.csv:1: bad header: no quaternion columns"),
        ("a.csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n1,nan,0,0,0\n", r"a.csv:3: NaN or inf"),
        ("a.csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n1,0,0,0,0\n", r"a.csv:3: quaternion of zero norm"),
        ("a.csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n0,1,0,0,0\n", r"a.csv:3: duplicate timestamp"),
        ("a.csv", "t,qw,qx,qy,qz\n1,1,0,0,0\n0,1,0,0,0\n", r"a.csv:3: decreasing timestamp"),
        ("a.csv", "", r"a.csv:1: empty file"),
        ("a.csv", "t,qw,qx,qy,qz\n", r"a.csv: no data rows"),
        ("a.txt", "0 1 2 3 0 0 0 1\n1 1 2 3 0 0\n", r"a.txt:2: expected 8 columns"),
        (
            "a.json",
            '{"times": [0, 1], "quats": [[1, 0, 0, 0]]}',
            r"a.json: expected times \(N,\) and quats",
        ),
        ("a.json", '{"times": [0, 1], ', r"a.json:1: column \d+: invalid JSON"),
        (
            "a.bvh",
            BVH_HEAD + "Frames: 2\nFrame Time: 0.1\n0 0 0\n",
            r"a.bvh: truncated: 1 of 2 frames",
        ),
        (
            "a.bvh",
            BVH_HEAD + "Frames: 1\nFrame Time: 0.1\n0 0\n",
            r"a.bvh:10: expected 3 channel values, got 2",
        ),
        # found by fuzz/readers_fuzz.py: a .npy header with a broken descriptor, a joint
        # without CHANNELS and zero frames, repeated rotation axes
        (
            "a.bvh",
            "HIERARCHY\nROOT A\n{\n OFFSET 0 0 0\n}\nMOTION\nFrames: 0\nFrame Time: 0.1\n",
            r"a.bvh: no CHANNELS",
        ),
        ("a.bvh", BVH_HEAD + "Frames: 0\nFrame Time: 0.1\n", r"a.bvh:8: no frames"),
        (
            "a.bvh",
            BVH_HEAD.replace("Xrotation", "Zrotation") + "Frames: 1\nFrame Time: 0.1\n0 0 0\n",
            r"a.bvh: joint 'A': rotation channels ZZY repeat an axis",
        ),
    ],
)
def test_malformed_files_name_file_line_and_column(tmp_path, name, text, message):
    p = write(tmp_path, name, text)
    with pytest.raises(ValueError, match=message):
        qio.read(p)


def test_missing_file_and_sort_dedupe(tmp_path):
    with pytest.raises(ValueError, match=r"nope.csv: no such file"):
        qio.read(tmp_path / "nope.csv")
    p = write(tmp_path, "u.csv", "t,qw,qx,qy,qz\n1,1,0,0,0\n0,1,0,0,0\n0,1,0,0,0\n")
    t = qio.read(p, sort=True, dedupe=True)
    np.testing.assert_array_equal(t.times, [0.0, 1.0])


def test_failed_write_leaves_existing_output_untouched(tmp_path):
    out = tmp_path / "o.csv"
    out.write_text("precious\n")
    bad = qio.Trajectory(
        [0.0, 1.0], [[1, 0, 0, 0], [1, 0, 0, 0]], extra={"w": np.array([1.0, np.nan])}
    )
    with pytest.raises(ValueError, match="refusing to write NaN"):
        qio.write(out, bad)
    assert out.read_text() == "precious\n"
    assert [f.name for f in tmp_path.iterdir()] == ["o.csv"]  # no temporary left behind


def test_damaged_npy_header_found_by_fuzzing(tmp_path):
    p = tmp_path / "a.npz"
    p.write_bytes(b"\x93NUMPY\x01\x00\x03\x00\xca]0\x00\x00")  # numpy raised TokenError
    with pytest.raises(ValueError, match=r"a.npz: not a valid .npz file"):
        qio.read(p)
