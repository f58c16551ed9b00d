"""ROS 1 / ROS 2 bags and MCAP files written here by rosbags' own writers, read back by
quatspline.io; round trips through quatspline's bag writer; bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import quatspline.io as qio

from ..splinekit import random_walk

pytest.importorskip("rosbags", reason="bag extra: pip install 'quatspline[bag]'")
from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

N = 25
STAMP0 = 1_700_000_000_123_456_789  # ns: float64 seconds cannot hold this exactly


def data(seed=0):
    q = random_walk(N, seed, step=0.3)
    p = np.random.default_rng(seed).normal(size=(N, 3))
    ns = STAMP0 + np.arange(N, dtype=np.int64) * 33_333_333 + seed
    return ns, q, p


def make_msg(store, msgtype, ns, q, p, child="base_link", ros=2):
    T = store.types
    sec, nsec = divmod(int(ns), 1_000_000_000)
    header = T["std_msgs/msg/Header"](
        stamp=T["builtin_interfaces/msg/Time"](sec=sec, nanosec=nsec),
        frame_id="map",
        **({"seq": 0} if ros == 1 else {}),
    )
    quat = T["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0])
    point = T["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2])
    vec = T["geometry_msgs/msg/Vector3"](x=p[0], y=p[1], z=p[2])
    pose = T["geometry_msgs/msg/Pose"](position=point, orientation=quat)
    cov = np.zeros(36)
    if msgtype == "std_msgs/msg/String":
        return T[msgtype](data="hello")
    if msgtype == "geometry_msgs/msg/PoseStamped":
        return T[msgtype](header=header, pose=pose)
    if msgtype == "geometry_msgs/msg/PoseWithCovarianceStamped":
        pwc = T["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=cov)
        return T[msgtype](header=header, pose=pwc)
    if msgtype == "nav_msgs/msg/Odometry":
        pwc = T["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=cov)
        z = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)
        tw = T["geometry_msgs/msg/TwistWithCovariance"](
            twist=T["geometry_msgs/msg/Twist"](linear=z, angular=z), covariance=cov
        )
        return T[msgtype](header=header, child_frame_id="base", pose=pwc, twist=tw)
    if msgtype in ("geometry_msgs/msg/TransformStamped", "tf2_msgs/msg/TFMessage"):
        tr = T["geometry_msgs/msg/Transform"](translation=vec, rotation=quat)
        ts = T["geometry_msgs/msg/TransformStamped"](
            header=header, child_frame_id=child, transform=tr
        )
        if msgtype == "geometry_msgs/msg/TransformStamped":
            return ts
        other = T["geometry_msgs/msg/TransformStamped"](
            header=header,
            child_frame_id="camera",
            transform=T["geometry_msgs/msg/Transform"](
                translation=vec, rotation=T["geometry_msgs/msg/Quaternion"](x=0, y=0, z=0, w=1.0)
            ),
        )
        return T[msgtype](transforms=[ts, other])
    if msgtype == "geometry_msgs/msg/QuaternionStamped":
        return T[msgtype](header=header, quaternion=quat)
    if msgtype == "sensor_msgs/msg/Imu":
        z = T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=9.81)
        return T[msgtype](
            header=header,
            orientation=quat,
            orientation_covariance=np.zeros(9),
            angular_velocity=z,
            angular_velocity_covariance=np.zeros(9),
            linear_acceleration=z,
            linear_acceleration_covariance=np.zeros(9),
        )
    raise AssertionError(msgtype)


def write_bag(path: Path, kind: str, topics: dict, seed=0):
    """topics: name → message type; every topic gets the same N messages."""
    ros = 1 if kind == "ros1" else 2
    store = get_typestore(Stores.ROS1_NOETIC if ros == 1 else Stores.ROS2_HUMBLE)
    if "tf2_msgs/msg/TFMessage" not in store.types:  # ROS 1 store: /tf's type, as ROS defines it
        store.register(
            get_types_from_msg(
                "geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"
            )
        )
    if ros == 1:
        writer = Writer1(path)
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(path, version=9, storage_plugin=plugin)
    ns, q, p = data(seed)
    with writer:
        for topic, msgtype in topics.items():
            conn = writer.add_connection(topic, msgtype, typestore=store)
            for k in range(N):
                msg = make_msg(store, msgtype, ns[k], q[k], p[k], ros=ros)
                raw = (
                    store.serialize_ros1(msg, msgtype)
                    if ros == 1
                    else store.serialize_cdr(msg, msgtype)
                )
                # receive time 5 ms after the header stamp
                writer.write(conn, int(ns[k]) + 5_000_000, raw)
    if kind == "mcap":  # the bare .mcap file inside the bag directory
        return next(path.glob("*.mcap"))
    return path


KINDS = {"ros1": "x.bag", "ros2": "x_ros2", "mcap": "x_mcap"}
TYPES = [
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "nav_msgs/msg/Odometry",
    "geometry_msgs/msg/TransformStamped",
    "tf2_msgs/msg/TFMessage",
    "sensor_msgs/msg/Imu",
    "geometry_msgs/msg/QuaternionStamped",
]


def same_rotation(a, b, tol=1e-12):
    d = np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))
    assert np.max(d) <= tol


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("msgtype", TYPES)
def test_reads_every_type_from_every_container(tmp_path, kind, msgtype):
    path = write_bag(
        tmp_path / KINDS[kind], kind, {"/est": msgtype, "/chatter": "std_msgs/msg/String"}
    )
    frame = "base_link" if msgtype.startswith("tf2") else None
    tr = qio.read(path, topic="/est", frame=frame)
    ns, q, p = data()
    np.testing.assert_array_equal(tr.stamps_ns, ns)  # exact integer nanoseconds
    np.testing.assert_allclose(tr.times, ns * 1e-9, rtol=0, atol=1e-6)
    same_rotation(tr.quats, q)
    if msgtype.endswith(("Imu", "QuaternionStamped")):
        assert tr.positions is None
    else:
        np.testing.assert_array_equal(tr.positions, p)
    assert tr.name == "/est"
    # bag receive times instead of header stamps
    tb = qio.read(path, topic="/est", frame=frame, stamp="bag")
    np.testing.assert_array_equal(tb.stamps_ns, ns + 5_000_000)


@pytest.mark.parametrize("kind", list(KINDS))
def test_single_usable_topic_needs_no_name(tmp_path, kind):
    path = write_bag(tmp_path / KINDS[kind], kind, {"/pose": TYPES[0], "/s": "std_msgs/msg/String"})
    assert qio.detect_format(path) == "rosbag"
    assert qio.read(path).name == "/pose"


@pytest.mark.parametrize("target", ["r.bag", "r.mcap", "r_dir"])
def test_round_trip_through_our_writer(tmp_path, target):
    ns, q, p = data(3)
    tr = qio.Trajectory(ns * 1e-9, q, p, stamps_ns=ns)
    out = tmp_path / target
    qio.write(out, tr, format="rosbag")
    back = qio.read(out)
    np.testing.assert_array_equal(back.stamps_ns, ns)
    same_rotation(back.quats, q)
    np.testing.assert_array_equal(back.positions, p)
    # replacing an existing bag works (the writer builds beside it and renames)
    qio.write(out, tr, format="rosbag")
    assert len(qio.read(out)) == N


def test_missing_topic_lists_topics(tmp_path):
    path = write_bag(tmp_path / "a.bag", "ros1", {"/a": TYPES[0], "/b": TYPES[5]})
    with pytest.raises(
        ValueError,
        match=r"a.bag: no topic '/c'; topics: /a \(geometry_msgs/PoseStamped\), "
        r"/b \(sensor_msgs/Imu\)",
    ):
        qio.read(path, topic="/c")
    with pytest.raises(ValueError, match=r"a.bag: no topic given; topics: /a .*, /b "):
        qio.read(path)


def test_unusable_type_is_named(tmp_path):
    path = write_bag(tmp_path / "s", "ros2", {"/chatter": "std_msgs/msg/String"})
    with pytest.raises(
        ValueError, match=r"topic '/chatter' has type std_msgs/String, which carries no orientation"
    ):  # noqa: E501
        qio.read(path, topic="/chatter")
    with pytest.raises(ValueError, match=r"no topic of a usable type; topics: /chatter"):
        qio.read(path)


def test_tf_with_several_frames_needs_a_frame(tmp_path):
    path = write_bag(tmp_path / "tf.bag", "ros1", {"/tf": "tf2_msgs/msg/TFMessage"})
    with pytest.raises(ValueError, match=r"several child frames \(base_link, camera\); choose one"):
        qio.read(path)
    with pytest.raises(ValueError, match=r"no messages on topic '/tf' with child frame 'arm'"):
        qio.read(path, frame="arm")
    cam = qio.read(path, frame="camera")
    np.testing.assert_array_equal(cam.quats, np.tile([1.0, 0, 0, 0], (N, 1)))


def test_not_a_bag(tmp_path):
    bad = tmp_path / "junk.bag"
    bad.write_bytes(b"#ROSBAG V2.0\nthis is not a bag")
    with pytest.raises(ValueError, match=r"junk.bag: not a readable ROS bag or MCAP file"):
        qio.read(bad)
    bad = tmp_path / "junk.mcap"
    bad.write_bytes(b"\x89MCAP0\r\n garbage")
    with pytest.raises(ValueError, match=r"junk.mcap: not a readable ROS bag or MCAP file"):
        qio.read(bad)
    with pytest.raises(ValueError, match=r"stamp: expected 'header' or 'bag'"):
        qio.read(bad, stamp="receive")


@pytest.mark.parametrize("target", ["o.bag", "o.mcap", "o_dir"])
def test_orientations_only_round_trip_as_quaternion_stamped(tmp_path, target):
    ns, q, _ = data(4)
    tr = qio.Trajectory(ns * 1e-9, q, stamps_ns=ns)
    out = tmp_path / target
    qio.write(out, tr, format="rosbag")
    from quatspline.io.rosbag import topics

    assert topics(out) == {"/pose": "geometry_msgs/QuaternionStamped"}
    back = qio.read(out)
    assert back.positions is None  # no positions stays no positions (not zeros)
    np.testing.assert_array_equal(back.stamps_ns, ns)
    same_rotation(back.quats, q)


@pytest.mark.parametrize("name", ["m.bag", "m.mcap"])
def test_bag_files_follow_the_writers_rules(tmp_path, name):
    import os
    import stat

    ns, q, p = data(5)
    tr = qio.Trajectory(ns * 1e-9, q, p, stamps_ns=ns)
    real = tmp_path / name
    real.write_bytes(b"old")
    os.chmod(real, 0o640)
    link = tmp_path / ("link" + Path(name).suffix)
    link.symlink_to(real)
    qio.write(link, tr, format="rosbag")
    assert link.is_symlink() and os.readlink(link) == str(real)  # the link stays
    assert stat.S_IMODE(real.stat().st_mode) == 0o640  # the replaced file keeps its mode
    np.testing.assert_array_equal(qio.read(real).stamps_ns, ns)
    assert [f.name for f in tmp_path.iterdir() if f.name.startswith(".")] == []
    fifo = tmp_path / ("fifo" + Path(name).suffix)
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match=r"is a FIFO \(named pipe\); refusing to replace it"):
        qio.write(fifo, tr, format="rosbag")
    folder = tmp_path / ("dir" + Path(name).suffix)
    folder.mkdir()
    with pytest.raises(ValueError, match=r"is a directory; refusing to replace it"):
        qio.write(folder, tr, format="rosbag")
    assert folder.is_dir() and stat.S_ISFIFO(fifo.stat().st_mode)
