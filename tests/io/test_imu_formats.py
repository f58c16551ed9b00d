"""IMU files: EuRoC imu0/data.csv, RepoIMU's IMU columns, sensor_msgs/Imu in ROS 1 / ROS 2 /
MCAP bags and Kalibr imu.yaml — round trips, independent oracles (numpy's text parser,
rosbags' own reader and writer, PyYAML), and hostile input answered by one-line errors naming
the file and line."""

from __future__ import annotations

import dataclasses
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest
import quatspline.io as qio
from hypothesis import given, settings
from hypothesis import strategies as st
from quatspline.io import ImuData
from quatspline.io._fast import table as fast_table

ROOT = Path(__file__).resolve().parents[2]
REPOIMU = ROOT / "data" / "repoimu" / "repoIMU_first30s.csv"
EUROC_HEADER = (
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
)
STAMP0 = 1_403_636_579_758_555_392  # EuRoC-sized: float64 seconds cannot hold it exactly


def record(n=40, seed=0, accel=True, stamps=True):
    rng = np.random.default_rng(seed)
    ns = STAMP0 + np.arange(n, dtype=np.int64) * 5_000_000 + rng.integers(0, 1000, n)
    return ImuData(
        ns * 1e-9,
        rng.normal(size=(n, 3)),
        rng.normal(size=(n, 3)) * 3 + [0, 0, 9.81] if accel else None,
        stamps_ns=ns if stamps else None,
    )


def one_line_error(exc_info, path, line=None):
    msg = str(exc_info.value)
    assert "\n" not in msg, msg
    prefix = f"{path}:{line}:" if line is not None else f"{path}:"
    assert msg.startswith(prefix), (msg, prefix)
    return msg


# ------------------------------------------------------------------------- EuRoC


def test_euroc_imu_round_trip_keeps_integer_stamps_and_bytes(tmp_path):
    d = record()
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    qio.write_imu(a, d)
    r = qio.read_imu(a)
    assert qio.detect_imu_format(a) == "euroc"
    np.testing.assert_array_equal(r.stamps_ns, d.stamps_ns)
    np.testing.assert_array_equal(r.gyro, d.gyro)
    np.testing.assert_array_equal(r.accel, d.accel)
    np.testing.assert_array_equal(r.times, d.stamps_ns * 1e-9)  # absolute seconds
    qio.write_imu(b, r)
    assert a.read_bytes() == b.read_bytes()
    # the independent oracle: numpy's parser on the written text
    ns = np.loadtxt(a, delimiter=",", comments="#", usecols=0, dtype=np.int64)
    vals = np.loadtxt(a, delimiter=",", comments="#", usecols=range(1, 7))
    np.testing.assert_array_equal(ns, d.stamps_ns)
    np.testing.assert_array_equal(vals, np.hstack([d.gyro, d.accel]))


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=6, max_size=60),
    # steps ≥ 1 µs: distinct as float64 seconds up to |t| ≈ 2.3e9 s (spacing 477 ns)
    st.lists(st.integers(1000, 10**12), min_size=1, max_size=10),
    st.integers(-(2**61), 2**61 - 10**14),
    st.booleans(),
)
def test_euroc_and_repoimu_round_trips_are_exact_for_any_finite_values(
    tmp_path_factory, values, steps, start, with_accel
):
    """Any finite doubles (subnormal, ±1e308, −0.0) and any int64 stamps come back bit-exact;
    writing what was read gives the same bytes."""
    n = len(values) // 6
    v = np.array(values[: 6 * n]).reshape(n, 6)
    ns = start + np.cumsum(np.resize(np.array(steps, dtype=np.int64), n))
    d = ImuData(ns * 1e-9, v[:, :3], v[:, 3:] if with_accel else None, stamps_ns=ns)
    folder = tmp_path_factory.mktemp("rt")
    for fmt in ("euroc", "repoimu"):
        if fmt == "repoimu":
            d = ImuData(d.times, d.gyro, d.accel)  # seconds as the file's time column
        a, b = folder / f"a_{fmt}.csv", folder / f"b_{fmt}.csv"
        qio.write_imu(a, d, format=fmt)
        r = qio.read_imu(a)
        np.testing.assert_array_equal(r.gyro, d.gyro)
        assert np.array_equal(np.signbit(r.gyro), np.signbit(d.gyro))
        assert (r.accel is None) == (d.accel is None)
        if d.accel is not None:
            np.testing.assert_array_equal(r.accel, d.accel)
        if fmt == "euroc":
            np.testing.assert_array_equal(r.stamps_ns, ns)
        else:
            np.testing.assert_array_equal(r.times, d.times)
        qio.write_imu(b, r, format=fmt)
        assert a.read_bytes() == b.read_bytes()


def test_euroc_imu_reads_text_written_by_another_tool(tmp_path):
    """Numbers as C's printf writes them (%.9e, %g), CRLF line ends, a BOM; the values
    against numpy's parser of the same text."""
    rng = np.random.default_rng(3)
    rows = [EUROC_HEADER.replace("\n", "\r\n")]
    for k in range(30):
        v = rng.normal(size=6)
        rows.append(
            f"{STAMP0 + k * 5_000_000},"
            + ",".join(f"{x:.9e}" if k % 2 else f"{x:g}" for x in v)
            + "\r\n"
        )
    path = tmp_path / "data.csv"
    path.write_bytes(b"\xef\xbb\xbf" + "".join(rows).encode())
    r = qio.read_imu(path)
    expected = np.array([[float(c) for c in row.split(",")[1:]] for row in rows[1:]])
    np.testing.assert_array_equal(np.hstack([r.gyro, r.accel]), expected)
    np.testing.assert_array_equal(r.stamps_ns, STAMP0 + np.arange(30) * 5_000_000)


def test_euroc_imu_fast_and_careful_paths_agree(tmp_path):
    """A file over the fast path's threshold (pandas) and the same rows read line by line
    (a file under it) give bit-identical records."""
    d = record(n=1500, seed=4)
    big = tmp_path / "big.csv"
    qio.write_imu(big, d)
    assert big.stat().st_size > 1 << 16
    pytest.importorskip("pandas")
    assert fast_table(big, ",", 7, skip=1, int_first=True) is not None  # the fast path reads it
    r = qio.read_imu(big)
    assert r.name == "big.csv"
    for k in range(0, 1500, 300):
        part = ImuData(d.times[k : k + 300], d.gyro[k : k + 300], d.accel[k : k + 300],
                       stamps_ns=d.stamps_ns[k : k + 300])  # fmt: skip
        small = tmp_path / f"small{k}.csv"
        qio.write_imu(small, part)
        assert small.stat().st_size < 1 << 16
        s = qio.read_imu(small)
        np.testing.assert_array_equal(s.gyro, r.gyro[k : k + 300])
        np.testing.assert_array_equal(s.accel, r.accel[k : k + 300])
        np.testing.assert_array_equal(s.times, r.times[k : k + 300])


def test_euroc_imu_gyroscope_only_round_trip(tmp_path):
    d = record(accel=False)
    path = tmp_path / "gyro.csv"
    qio.write_imu(path, d)
    assert path.read_text().splitlines()[1].endswith(",,,")
    r = qio.read_imu(path)
    assert r.accel is None
    np.testing.assert_array_equal(r.gyro, d.gyro)


def test_euroc_imu_writes_times_without_stamps_rounded_to_the_nanosecond(tmp_path):
    d = ImuData([0.0, 0.005, 0.01, 1.5e9], np.zeros((4, 3)), np.ones((4, 3)))
    path = tmp_path / "t.csv"
    qio.write_imu(path, d)
    ns = [int(line.split(",")[0]) for line in path.read_text().splitlines()[1:]]
    assert ns == [0, 5_000_000, 10_000_000, 1_500_000_000_000_000_000]


def test_euroc_imu_sort_and_dedupe(tmp_path):
    path = tmp_path / "d.csv"
    path.write_text(
        EUROC_HEADER + "30,1,1,1,0,0,9\n10,2,2,2,0,0,9\n10,3,3,3,0,0,9\n20,4,4,4,0,0,9\n"
    )
    with pytest.raises(ValueError) as e:
        qio.read_imu(path)
    assert "decreasing timestamp" in one_line_error(e, path, 3)
    r = qio.read_imu(path, sort=True, dedupe=True)
    np.testing.assert_array_equal(r.stamps_ns, [10, 20, 30])
    np.testing.assert_array_equal(r.gyro[:, 0], [2, 4, 1])  # the first of equal stamps kept


BAD_EUROC = {
    "truncated row": ("0,1,2,3,4,5,6\n5000000,1,2,3\n", 3, "expected 7 columns, got 4"),
    "long row": ("0,1,2,3,4,5,6,7\n", 2, "expected 7 columns, got 8"),
    "NaN": ("0,1,2,3,4,5,6\n5000000,1,nan,3,4,5,6\n", 3, "NaN or inf in this row"),
    "inf": ("0,1,2,3,4,5,inf\n", 2, "NaN or inf in this row"),
    "duplicate stamp": ("7,1,2,3,4,5,6\n7,1,2,3,4,5,6\n", 3, "duplicate timestamp"),
    "decreasing": ("9,1,2,3,4,5,6\n8,1,2,3,4,5,6\n", 3, "decreasing timestamp"),
    "float stamp": ("1.5,1,2,3,4,5,6\n", 2, "column 1 ('timestamp'): not an integer"),
    "huge stamp": ("9" * 30 + ",1,2,3,4,5,6\n", 2, "beyond 64-bit nanoseconds"),
    "word": ("0,1,x,3,4,5,6\n", 2, "column 3 ('w_RS_S_y'): not a number: 'x'"),
    "underscore": ("0,1_0,2,3,4,5,6\n", 2, "column 2 ('w_RS_S_x'): not a number"),
    "accel half empty": ("0,1,2,3,,5,6\n", 2, "column 5 ('a_RS_S_x'): not a number: ''"),
    "accel mixed": ("0,1,2,3,,,\n5,1,2,3,4,5,6\n", 3, "accelerometer columns are empty in some"),
}


@pytest.mark.parametrize("case", list(BAD_EUROC))
def test_euroc_imu_bad_rows_name_file_and_line(tmp_path, case):
    body, line, text = BAD_EUROC[case]
    path = tmp_path / "imu.csv"
    path.write_text(EUROC_HEADER + body)
    with pytest.raises(ValueError) as e:
        qio.read_imu(path)
    assert text in one_line_error(e, path, line)


def test_euroc_imu_bad_headers_and_empty_files(tmp_path):
    path = tmp_path / "imu.csv"
    for text, line, message in [
        ("timestamp,wx,wy,wz,ax,ay,az\n0,1,2,3,4,5,6\n", 1, "bad header"),
        ("#timestamp [ns],w_RS_S_x,w_RS_S_y,w_RS_S_z,a_RS_S_x,a_RS_S_y,a_RS_S_z,temp\n", 1,
         "the header names 8 columns"),
        ("#timestamp [ns],a_RS_S_x,a_RS_S_y,a_RS_S_z,w_RS_S_x,w_RS_S_y,w_RS_S_z\n", 1,
         "column 2 is 'a_RS_S_x'"),
        (EUROC_HEADER, None, "no data rows"),
    ]:  # fmt: skip
        path.write_text(text)
        with pytest.raises(ValueError) as e:
            qio.read_imu(path, format="euroc")
        assert message in one_line_error(e, path, line)


def test_euroc_imu_overlong_line_is_refused_after_a_bounded_read(tmp_path):
    from quatspline.io._common import MAX_LINE

    path = tmp_path / "imu.csv"
    with open(path, "w") as f:
        f.write(EUROC_HEADER + "0,1,2,3,4,5,6\n" + "1" * (3 * MAX_LINE) + "\n")
    with pytest.raises(ValueError) as e:
        qio.read_imu(path)
    assert "line longer than" in one_line_error(e, path, 3)


def test_imu_readers_refuse_directories_fifos_and_symlink_loops(tmp_path):
    folder = tmp_path / "dir.csv"
    folder.mkdir()
    loop = tmp_path / "loop.csv"
    loop.symlink_to(tmp_path / "loop.csv")
    fifo = tmp_path / "fifo.csv"
    os.mkfifo(fifo)
    for fmt in (None, "euroc", "repoimu"):
        for path, text in [
            (folder, "is a directory; only regular files are read"),
            (fifo, "is a FIFO"),
            (loop, "cannot read"),
            (tmp_path / "missing.csv", "no such file"),
        ]:
            with pytest.raises(ValueError) as e:
                qio.read_imu(path, format=fmt)
            assert text in one_line_error(e, path)
    yaml_dir = tmp_path / "imu.yaml"
    yaml_dir.mkdir()
    with pytest.raises(ValueError) as e:
        qio.read_imu_noise(yaml_dir)
    assert "is a directory" in one_line_error(e, yaml_dir)
    with pytest.raises(ValueError) as e:
        qio.read_imu_noise(loop)
    assert "cannot read" in one_line_error(e, loop)


# ------------------------------------------------------------------------ RepoIMU


def test_repoimu_imu_columns_match_numpy_on_the_bundled_recording():
    d = qio.read_imu(REPOIMU)
    assert qio.detect_imu_format(REPOIMU) == "repoimu"
    a = np.genfromtxt(REPOIMU, delimiter=";", skip_header=2)
    assert a.shape == (3000, 14) and len(d) == 3000
    np.testing.assert_array_equal(d.times, a[:, 0])
    np.testing.assert_array_equal(d.extra["orientation"], a[:, 1:5])
    np.testing.assert_array_equal(d.accel, a[:, 5:8])
    np.testing.assert_array_equal(d.gyro, a[:, 8:11])
    np.testing.assert_array_equal(d.extra["mag"], a[:, 11:14])
    # at rest at the start: gravity on the accelerometer, a small rate on the gyroscope
    assert abs(np.linalg.norm(d.accel[0]) - 9.8) < 0.1 and np.linalg.norm(d.gyro[0]) < 0.05


def test_repoimu_gyroscope_is_in_rad_per_second_as_the_vicon_orientation_turns():
    """The units: over 0.1 s windows where the Vicon orientation turns faster than 0.5 rad/s,
    the mean gyroscope magnitude matches the rotation rate of the reference (deg/s would be
    57 times too large)."""
    d = qio.read_imu(REPOIMU)
    q = d.extra["orientation"] / np.linalg.norm(d.extra["orientation"], axis=1, keepdims=True)
    k = 10
    angle = 2 * np.arccos(np.abs(np.sum(q[:-k] * q[k:], axis=1)).clip(0, 1))
    rate = angle / (d.times[k:] - d.times[:-k])
    gyro = np.convolve(np.linalg.norm(d.gyro, axis=1), np.ones(k) / k, mode="valid")[: len(rate)]
    turning = rate > 0.5
    assert turning.sum() > 100
    assert 0.8 < np.median(gyro[turning] / rate[turning]) < 1.25


def test_repoimu_imu_round_trip_and_the_pose_reader_reads_the_written_file(tmp_path):
    d = qio.read_imu(REPOIMU)
    out = tmp_path / "out.csv"
    qio.write_imu(out, d, format="repoimu")
    r = qio.read_imu(out)
    for name in ("times", "gyro", "accel"):
        np.testing.assert_array_equal(getattr(r, name), getattr(d, name))
    for name in ("orientation", "mag"):
        np.testing.assert_array_equal(r.extra[name], d.extra[name])
    np.testing.assert_array_equal(qio.read(out).quats, qio.read(REPOIMU).quats)
    # the careful line-by-line path (a file under the fast path's threshold) agrees
    head = tmp_path / "head.csv"
    head.write_text("".join(REPOIMU.read_text().splitlines(keepends=True)[:302]))
    h = qio.read_imu(head)
    np.testing.assert_array_equal(h.gyro, d.gyro[:300])
    np.testing.assert_array_equal(h.extra["orientation"], d.extra["orientation"][:300])


def test_repoimu_imu_without_orientation_accel_and_mag(tmp_path):
    d = record(accel=False, stamps=False)
    out = tmp_path / "g.csv"
    qio.write_imu(out, d, format="repoimu")
    r = qio.read_imu(out)
    assert r.accel is None and r.extra == {}
    np.testing.assert_array_equal(r.gyro, d.gyro)
    np.testing.assert_array_equal(r.times, d.times)
    with pytest.raises(ValueError) as e:  # the pose reader needs the orientation
        qio.read(out)
    assert "column 2 ('W'): not a number" in one_line_error(e, out, 3)


REPO_HEAD = (
    "Time (s);Vicon Orientation;;;;IMU Acceleration;;;IMU Gyroscope;;;IMU Magnetometer;;;\n"
    ";W;X;Y;Z;X;Y;Z;X;Y;Z;X;Y;Z;\n"
)
ROW = "0.08;1;0;0;0;0.1;0.2;9.8;0.01;0.02;0.03;-0.3;0.2;-0.9"
BAD_REPO = {
    "truncated": (ROW + "\n0.09;1;0;0;0;0.1", 4, "expected 14 columns"),
    "long": (ROW + ";1;2\n", 3, "expected 14 columns"),
    "NaN gyro": (ROW.replace("0.02", "nan") + "\n", 3, "NaN or inf in this row"),
    "duplicate": (ROW + "\n" + ROW + "\n", 4, "duplicate timestamp"),
    "decreasing": (ROW + "\n" + ROW.replace("0.08", "0.07") + "\n", 4, "decreasing timestamp"),
    "gyro empty": (ROW.replace(";0.01;0.02;0.03;", ";;;;") + "\n", 3, "column 9 ('gyro X')"),
    "mag mixed": (ROW + "\n0.09;1;0;0;0;0.1;0.2;9.8;0.01;0.02;0.03;;;\n", 4,
                  "magnetometer columns are empty in some rows"),
}  # fmt: skip


@pytest.mark.parametrize("case", list(BAD_REPO))
def test_repoimu_imu_bad_rows_name_file_and_line(tmp_path, case):
    body, line, text = BAD_REPO[case]
    path = tmp_path / "r.csv"
    path.write_text(REPO_HEAD + body)
    with pytest.raises(ValueError) as e:
        qio.read_imu(path)
    assert text in one_line_error(e, path, line)


# -------------------------------------------------------------------------- bags

rosbags = pytest.importorskip("rosbags", reason="bag extra: pip install 'quatspline[bag]'")
from rosbags.highlevel import AnyReader  # noqa: E402
from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

BAGS = {"ros1": "imu.bag", "mcap": "imu.mcap", "ros2": "imu_ros2"}


@pytest.mark.parametrize("kind", list(BAGS))
def test_bag_imu_written_here_is_read_by_rosbags_own_reader(tmp_path, kind):
    d = record(n=25, seed=1)
    path = tmp_path / BAGS[kind]
    qio.write_imu(path, d, format="rosbag", topic="/imu0", frame_id="imu_link")
    seen = []
    with AnyReader([path]) as reader:
        (conn,) = reader.connections
        assert conn.topic == "/imu0" and conn.msgtype == "sensor_msgs/msg/Imu"
        for c, bag_ns, raw in reader.messages():
            m = reader.deserialize(raw, c.msgtype)
            ns = m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec
            assert bag_ns == ns and m.header.frame_id == "imu_link"
            assert m.orientation_covariance[0] == -1  # no orientation estimate
            assert np.all(m.angular_velocity_covariance == 0)  # unknown
            assert np.all(m.linear_acceleration_covariance == 0)
            g, a = m.angular_velocity, m.linear_acceleration
            seen.append((ns, g.x, g.y, g.z, a.x, a.y, a.z))
    got = np.array(seen, dtype=object)
    np.testing.assert_array_equal(got[:, 0].astype(np.int64), d.stamps_ns)
    np.testing.assert_array_equal(got[:, 1:4].astype(float), d.gyro)
    np.testing.assert_array_equal(got[:, 4:7].astype(float), d.accel)
    r = qio.read_imu(path)
    assert r.name == "/imu0" and r.extra == {}
    np.testing.assert_array_equal(r.stamps_ns, d.stamps_ns)
    np.testing.assert_array_equal(r.gyro, d.gyro)
    np.testing.assert_array_equal(r.accel, d.accel)


@pytest.mark.parametrize("kind", list(BAGS))
def test_bag_imu_gyroscope_only_and_orientation_round_trip(tmp_path, kind):
    d = record(n=10, seed=2, accel=False)
    q = np.random.default_rng(0).normal(size=(10, 4))
    d.extra["orientation"] = q / np.linalg.norm(q, axis=1, keepdims=True)
    path = tmp_path / BAGS[kind]
    qio.write_imu(path, d, format="rosbag")
    with AnyReader([path]) as reader:
        for c, _, raw in reader.messages():
            m = reader.deserialize(raw, c.msgtype)
            assert m.linear_acceleration_covariance[0] == -1
            assert m.orientation_covariance[0] == 0
    r = qio.read_imu(path)
    assert r.accel is None
    np.testing.assert_array_equal(r.extra["orientation"], d.extra["orientation"])
    np.testing.assert_array_equal(r.gyro, d.gyro)


def imu_bag(path, kind, msgs, topic="/imu", extra_topic=None):
    """A bag written by rosbags' own writer: ``msgs`` are (ns, gyro, accel, q, covariances
    element 0 for orientation, angular velocity, linear acceleration)."""
    ros = 1 if kind == "ros1" else 2
    store = get_typestore(Stores.ROS1_NOETIC if ros == 1 else Stores.ROS2_HUMBLE)
    T = store.types
    if ros == 1:
        writer = Writer1(path)
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(path, version=9, storage_plugin=plugin)
    ser = store.serialize_ros1 if ros == 1 else store.serialize_cdr
    with writer:
        conn = writer.add_connection(topic, "sensor_msgs/msg/Imu", typestore=store)
        if extra_topic:
            other = writer.add_connection(extra_topic, "std_msgs/msg/String", typestore=store)
            writer.write(other, 1, ser(T["std_msgs/msg/String"](data="hi"), "std_msgs/msg/String"))
        for ns, g, a, q, covs in msgs:
            sec, nsec = divmod(ns, 1_000_000_000)
            header = T["std_msgs/msg/Header"](
                stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=nsec),
                frame_id="imu",
                **({"seq": 0} if ros == 1 else {}),
            )
            V = T["geometry_msgs/msg/Vector3"]
            cov = [np.full(9, 0.01) for _ in range(3)]
            for k in range(3):
                cov[k][0] = covs[k]
            msg = T["sensor_msgs/msg/Imu"](
                header=header,
                orientation=T["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0]),
                orientation_covariance=cov[0],
                angular_velocity=V(x=g[0], y=g[1], z=g[2]),
                angular_velocity_covariance=cov[1],
                linear_acceleration=V(x=a[0], y=a[1], z=a[2]),
                linear_acceleration_covariance=cov[2],
            )
            writer.write(conn, ns + 1000, ser(msg, "sensor_msgs/msg/Imu"))
    return next(path.glob("*.mcap")) if kind == "mcap" else path


@pytest.mark.parametrize("kind", list(BAGS))
def test_bag_imu_written_by_rosbags_is_read(tmp_path, kind):
    rng = np.random.default_rng(7)
    msgs = [
        (STAMP0 + k * 2_500_000, rng.normal(size=3), rng.normal(size=3), (1.0, 0.0, 0.0, 0.0),
         (0.01, 0.01, 0.01))
        for k in range(12)
    ]  # fmt: skip
    path = imu_bag(tmp_path / BAGS[kind], kind, msgs, extra_topic="/chatter")
    r = qio.read_imu(path)  # the one IMU topic is chosen
    np.testing.assert_array_equal(r.stamps_ns, [m[0] for m in msgs])
    np.testing.assert_array_equal(r.gyro, [m[1] for m in msgs])
    np.testing.assert_array_equal(r.accel, [m[2] for m in msgs])
    np.testing.assert_array_equal(r.extra["orientation"], [m[3] for m in msgs])
    b = qio.read_imu(path, stamp="bag")
    np.testing.assert_array_equal(b.stamps_ns, [m[0] + 1000 for m in msgs])


def test_bag_imu_bad_content_is_one_line_naming_the_file(tmp_path):
    g, a, q = (0.1, 0.2, 0.3), (0.0, 0.0, 9.8), (1.0, 0.0, 0.0, 0.0)
    cases = [
        ([(10, g, a, q, (0, -1, 0))], "angular_velocity_covariance[0] is -1"),
        ([(10, g, a, q, (0, 0, -1)), (20, g, a, q, (0, 0, 0))],
         "linear_acceleration_covariance[0] is not -1, unlike the earlier"),
        ([(10, g, a, q, (0, 0, 0)), (10, g, a, q, (0, 0, 0))], "duplicate timestamp"),
        ([(10, (math.nan, 0, 0), a, q, (0, 0, 0))], "NaN or inf"),
    ]  # fmt: skip
    for k, (msgs, text) in enumerate(cases):
        path = imu_bag(tmp_path / f"b{k}.bag", "ros1", msgs)
        with pytest.raises(ValueError) as e:
            qio.read_imu(path)
        assert text in one_line_error(e, path), str(e.value)
    path = imu_bag(tmp_path / "t.bag", "ros1", [(10, g, a, q, (0, 0, 0))], extra_topic="/chat")
    with pytest.raises(ValueError) as e:
        qio.read_imu(path, topic="/chat")
    assert "has type std_msgs/String, which carries no inertial measurements" in one_line_error(
        e, path
    )
    with pytest.raises(ValueError) as e:
        qio.read_imu(path, topic="/nope")
    assert "no topic '/nope'; topics: /imu (sensor_msgs/Imu), /chat (std_msgs/String)" in (
        one_line_error(e, path)
    )
    junk = tmp_path / "junk.bag"
    junk.write_bytes(b"#ROSBAG V2.0\n" + b"\x00" * 100)
    with pytest.raises(ValueError) as e:
        qio.read_imu(junk)
    one_line_error(e, junk)


def test_bag_imu_writer_follows_the_writers_rules(tmp_path):
    d = record(n=5)
    real = tmp_path / "real.bag"
    real.write_bytes(b"old")
    os.chmod(real, 0o640)
    link = tmp_path / "link.bag"
    link.symlink_to(real)
    qio.write_imu(link, d)
    assert link.is_symlink() and stat.S_IMODE(real.stat().st_mode) == 0o640
    np.testing.assert_array_equal(qio.read_imu(real).gyro, d.gyro)
    folder = tmp_path / "dir.bag"
    folder.mkdir()
    with pytest.raises(ValueError, match="is a directory; refusing to replace it"):
        qio.write_imu(folder, d)
    with pytest.raises(ValueError, match="times before 0 s"):
        qio.write_imu(tmp_path / "neg.bag", ImuData([-1.0, 0.0], np.zeros((2, 3))))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dir.bag", "link.bag", "real.bag"]


# ----------------------------------------------------------------------- writers


@pytest.mark.parametrize(
    "fmt,name", [("euroc", "w.csv"), ("repoimu", "w.csv"), ("rosbag", "w.bag")]
)
def test_imu_writers_refuse_what_they_cannot_hold_and_leave_the_target(tmp_path, fmt, name):
    path = tmp_path / name
    path.write_bytes(b"keep")
    os.chmod(path, 0o600)
    d = record(n=6)
    bad = []
    nan = record(n=6)
    nan.gyro[3, 1] = np.nan  # changed after construction
    bad.append((nan, "refusing to write NaN or inf (gyro, row 3)"))
    bias = record(n=6)
    bias.gyro_bias = np.zeros((6, 3))
    bad.append((bias, "no columns for gyro_bias"))
    extra = record(n=6)
    extra.extra["temperature"] = np.zeros(6)
    bad.append((extra, "no columns for extra 'temperature'"))
    close = ImuData([1.0, 1.0 + 1e-10], np.zeros((2, 3)), np.zeros((2, 3)))
    if fmt != "repoimu":  # integer nanoseconds
        bad.append((close, "round to the same nanosecond"))
    for data, text in bad:
        with pytest.raises(ValueError) as e:
            qio.write_imu(path, data, format=fmt)
        assert text in one_line_error(e, path)
    with pytest.raises(TypeError, match="data: expected a quatspline.io.ImuData, got dict"):
        qio.write_imu(path, {"times": [0]}, format=fmt)
    assert path.read_bytes() == b"keep"
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no temporary left
    qio.write_imu(path, d, format=fmt)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600  # the replaced file keeps its mode
    np.testing.assert_array_equal(qio.read_imu(path).gyro, d.gyro)


def test_imu_format_and_option_errors(tmp_path):
    d = record(n=3)
    with pytest.raises(ValueError, match=r"unknown IMU output extension '\.txt'"):
        qio.write_imu(tmp_path / "x.txt", d)
    with pytest.raises(ValueError, match="format: unknown IMU format 'tum'; valid: euroc"):
        qio.write_imu(tmp_path / "x.csv", d, format="tum")
    with pytest.raises(ValueError, match="topic: unknown option for format euroc"):
        qio.write_imu(tmp_path / "x.csv", d, topic="/imu")
    qio.write_imu(tmp_path / "x.csv", d)
    with pytest.raises(ValueError, match="frame: unknown option for format euroc; valid: sort"):
        qio.read_imu(tmp_path / "x.csv", frame="a")
    other = tmp_path / "poses.csv"
    other.write_text("t,qw,qx,qy,qz\n0,1,0,0,0\n")
    with pytest.raises(ValueError) as e:
        qio.read_imu(other)
    assert "cannot tell the IMU format" in one_line_error(e, other)


# ------------------------------------------------------------------ Kalibr yaml

KALIBR_EXAMPLE = """#Accelerometers
accelerometer_noise_density: 1.86e-03   #Noise density (continuous-time)
accelerometer_random_walk:   4.33e-04   #Bias random walk

#Gyroscopes
gyroscope_noise_density:     1.87e-04   #Noise density (continuous-time)
gyroscope_random_walk:       2.66e-05   #Bias random walk

rostopic:                    /imu0      #the IMU ROS topic
update_rate:                 200.0      #Hz (for discretization of the values above)
"""
CHAIN = """%YAML:1.0 # need to specify the file type at the top!

imu0:
  T_i_b:
    - [1.0, 0.0, 0.0, 0.0]
    - [0.0, 1.0, 0.0, 0.0]
  accelerometer_noise_density: 0.01
  accelerometer_random_walk: 2e-4
  gyroscope_noise_density: 0.005
  gyroscope_random_walk: 4.0e-06
  rostopic: /snappy_imu
  time_offset: 0.0
  update_rate: 1000
"""


def test_kalibr_yaml_reads_kalibrs_example_and_an_imu_chain(tmp_path):
    path = tmp_path / "imu.yaml"
    path.write_text(KALIBR_EXAMPLE)
    assert qio.read_imu_noise(path) == {
        "accelerometer_noise_density": 1.86e-3,
        "accelerometer_random_walk": 4.33e-4,
        "gyroscope_noise_density": 1.87e-4,
        "gyroscope_random_walk": 2.66e-5,
        "update_rate": 200.0,
        "rostopic": "/imu0",
    }
    chain = tmp_path / "chain.yaml"
    chain.write_text(CHAIN)
    n = qio.read_imu_noise(chain)
    assert n["accelerometer_random_walk"] == 2e-4  # written 2e-4: text to PyYAML, read as a number
    assert n["update_rate"] == 1000.0 and n["rostopic"] == "/snappy_imu"
    chain.write_text(CHAIN + CHAIN.split("\n", 2)[2].replace("imu0", "imu1"))
    with pytest.raises(ValueError, match="holds several IMUs .imu0, imu1.; choose one with imu="):
        qio.read_imu_noise(chain)
    assert qio.read_imu_noise(chain, imu="imu1")["gyroscope_noise_density"] == 0.005


def test_kalibr_yaml_round_trip_is_exact_and_readable_by_pyyaml(tmp_path):
    yaml = pytest.importorskip("yaml")
    path = tmp_path / "imu.yaml"
    rng = np.random.default_rng(0)
    values = [0.0, 1e-5, 5e-324, 1e300, 0.1 + 0.2, 2.0, *map(float, rng.lognormal(-8, 3, 20))]
    for k, x in enumerate(values):
        noise = {
            "accelerometer_noise_density": x,
            "accelerometer_random_walk": values[-k],
            "gyroscope_noise_density": float(k),
            "gyroscope_random_walk": x / 3,
            "update_rate": 1.0 + x,
            "rostopic": f"/imu{k}" if k % 2 else 'odd "name" \\ ü',
        }
        qio.write_imu_noise(path, noise)
        assert qio.read_imu_noise(path) == noise
        plain = yaml.safe_load(path.read_text())  # what Kalibr's own loader sees
        for key, v in noise.items():
            assert plain[key] == v and type(plain[key]) is type(v), (key, plain[key])


def test_kalibr_yaml_writer_takes_an_object_and_checks_it(tmp_path):
    class Noise:
        gyroscope_noise_density = 1.7e-4
        gyroscope_random_walk = 2e-5
        accelerometer_noise_density = 2e-3
        accelerometer_random_walk = 3e-3
        update_rate = 400

    path = tmp_path / "imu.yaml"
    qio.write_imu_noise(path, Noise(), rostopic="/mti")
    got = qio.read_imu_noise(path)
    assert got["update_rate"] == 400.0 and got["rostopic"] == "/mti"
    good = dict(qio.read_imu_noise(path))
    for change, error, text in [
        ({"gyroscope_random_walk": -1e-5}, ValueError, "cannot be negative"),
        ({"update_rate": 0.0}, ValueError, "expected a rate > 0 Hz"),
        ({"accelerometer_noise_density": math.nan}, ValueError, "not finite"),
        ({"gyroscope_noise_density": "1e-3"}, TypeError, "expected a number, got str"),
        ({"gyroscope_noise_density": True}, TypeError, "expected a number, got bool"),
    ]:
        with pytest.raises(error, match=text):
            qio.write_imu_noise(path, {**good, **change})
    missing = {k: v for k, v in good.items() if k != "accelerometer_random_walk"}
    with pytest.raises(ValueError, match="noise: missing 'accelerometer_random_walk'"):
        qio.write_imu_noise(path, missing)
    with pytest.raises(TypeError, match="noise: missing 'accelerometer_noise_density'"):
        qio.write_imu_noise(path, object())
    assert qio.read_imu_noise(path)["rostopic"] == "/mti"  # untouched by the refusals

    @dataclasses.dataclass(frozen=True)
    class Densities:  # a noise model without a rate: the rate is given when writing
        gyroscope_noise_density: float = 1.6968e-04
        gyroscope_random_walk: float = 1.9393e-05
        accelerometer_noise_density: float = 2.0e-3
        accelerometer_random_walk: float = 3.0e-3

    with pytest.raises(ValueError, match="update_rate: needed"):
        qio.write_imu_noise(path, Densities())
    qio.write_imu_noise(path, Densities(), update_rate=200)
    back = qio.read_imu_noise(path)
    assert Densities(**{k: back[k] for k in dataclasses.asdict(Densities())}) == Densities()
    assert back["update_rate"] == 200.0 and back["rostopic"] == "/imu0"


BAD_YAML = {
    "missing": (KALIBR_EXAMPLE.replace("gyroscope_random_walk", "gyro_rw"), None,
                "missing gyroscope_random_walk"),
    "negative": (KALIBR_EXAMPLE.replace("1.87e-04", "-1.87e-04"), "6:30",
                 "gyroscope_noise_density: a noise density cannot be negative"),
    "nan": (KALIBR_EXAMPLE.replace("4.33e-04", ".nan"), "3:30", "not finite"),
    "text": (KALIBR_EXAMPLE.replace("4.33e-04", "low"), "3:30", "not a number: 'low'"),
    "list": (KALIBR_EXAMPLE.replace("4.33e-04", "[1, 2]"), "3:30", "expected a number, got list"),
    "bool": (KALIBR_EXAMPLE.replace("200.0", "yes"), "10:30", "expected a number, got bool"),
    "rate": (KALIBR_EXAMPLE.replace("200.0", "0"), "10:30", "expected a rate > 0 Hz"),
    "topic": (KALIBR_EXAMPLE.replace("/imu0", "7"), "9:30", "rostopic: expected text, got int"),
    "syntax": ("a: [1, 2\nb: 3\n", "2:", "not YAML"),
    "scalar": ("42\n", None, "expected a mapping of noise parameters, got int"),
    "nested": ("[" * 10000 + "]" * 10000, None, "not an imu.yaml (nested too deeply)"),
    "no imu": ("camera: 1\n", None, "missing accelerometer_noise_density"),
}  # fmt: skip


@pytest.mark.parametrize("case", list(BAD_YAML))
def test_kalibr_yaml_bad_files_are_one_line_errors_naming_file_and_line(tmp_path, case):
    text, where, message = BAD_YAML[case]
    path = tmp_path / "imu.yaml"
    path.write_text(text)
    with pytest.raises(ValueError) as e:
        qio.read_imu_noise(path)
    msg = one_line_error(e, path)
    if where is not None:
        assert msg.startswith(f"{path}:{where}"), msg
    assert message in msg


def test_kalibr_yaml_huge_and_binary_files_are_refused_after_a_bounded_read(tmp_path):
    from quatspline.io.kalibr_yaml import MAX_BYTES

    path = tmp_path / "imu.yaml"
    with open(path, "w") as f:
        f.write(KALIBR_EXAMPLE + "#" * (4 * MAX_BYTES) + "\n")
    with pytest.raises(ValueError) as e:
        qio.read_imu_noise(path)
    assert f"larger than {MAX_BYTES} bytes" in one_line_error(e, path)
    path.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(ValueError) as e:
        qio.read_imu_noise(path)
    assert "not a text file" in one_line_error(e, path)
