"""ROS 1 bags (``.bag``), ROS 2 bags (a directory with ``metadata.yaml``, or a bare ``.db3``)
and MCAP files (``.mcap``), read and written with the ``rosbags`` library
(``pip install 'quatspline[bag]'``).

Messages with an orientation, by type:

- ``geometry_msgs/PoseStamped``: ``pose.orientation``, ``pose.position``;
- ``geometry_msgs/PoseWithCovarianceStamped``, ``nav_msgs/Odometry``: ``pose.pose``;
- ``geometry_msgs/TransformStamped``: ``transform.rotation``, ``transform.translation``;
- ``tf2_msgs/TFMessage`` (``/tf``): the transforms whose ``child_frame_id`` is ``frame``
  (needed when the topic carries more than one child frame);
- ``sensor_msgs/Imu``: ``orientation`` only (no positions);
- ``geometry_msgs/QuaternionStamped``: ``quaternion`` (no positions).

Times are the messages' header stamps (``stamp="header"``, default) or the bag's receive
times (``stamp="bag"``), in seconds; the integer nanoseconds are kept exactly in
``Trajectory.stamps_ns``. ROS quaternions are (x, y, z, w); the trajectory's are (w, x, y, z).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .._atomic import adopt_mode, resolve_output, sigterm_unwinds
from .._progress import progress
from ._common import Trajectory, TrajectoryError, finish

HINT = "ROS bags need the rosbags library: pip install 'quatspline[bag]'"

#: message type → (path to the quaternion, path to the position or None)
TYPES = {
    "geometry_msgs/msg/PoseStamped": ("pose.orientation", "pose.position"),
    "geometry_msgs/msg/PoseWithCovarianceStamped": ("pose.pose.orientation", "pose.pose.position"),
    "nav_msgs/msg/Odometry": ("pose.pose.orientation", "pose.pose.position"),
    "geometry_msgs/msg/TransformStamped": ("transform.rotation", "transform.translation"),
    "tf2_msgs/msg/TFMessage": ("transform.rotation", "transform.translation"),
    "sensor_msgs/msg/Imu": ("orientation", None),
    "geometry_msgs/msg/QuaternionStamped": ("quaternion", None),
}
SUFFIXES = (".bag", ".mcap", ".db3")


def _rosbags():
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError as e:
        raise ImportError(HINT) from e
    return AnyReader, Stores, get_typestore


def is_bag(path) -> bool:
    """Whether ``path`` looks like a bag: a .bag/.mcap/.db3 file or a ROS 2 bag directory."""
    p = Path(path)
    return p.suffix.lower() in SUFFIXES or (p.is_dir() and (p / "metadata.yaml").is_file())


def _get(msg, dotted: str):
    for part in dotted.split("."):
        msg = getattr(msg, part)
    return msg


def _short(msgtype: str) -> str:
    return msgtype.replace("/msg/", "/")


def topics(path) -> dict[str, str]:
    """Topic → message type (``pkg/Type``) of every topic in the bag."""
    AnyReader, _, _ = _rosbags()
    with _open(path, AnyReader) as reader:
        return {c.topic: _short(c.msgtype) for c in reader.connections}


@contextlib.contextmanager
def _open(path, AnyReader):
    from rosbags.highlevel import AnyReaderError

    p = Path(path)
    reader = None
    try:
        reader = AnyReader([p])
        reader.open()
    except (AnyReaderError, OSError, ValueError, KeyError) as e:
        raise TrajectoryError(f"{path}: not a readable ROS bag or MCAP file ({e})") from None
    except Exception as e:  # rosbags raises its own error types per storage backend
        raise TrajectoryError(
            f"{path}: not a readable ROS bag or MCAP file ({type(e).__name__}: {e})"
        ) from None
    try:
        yield reader
    finally:
        reader.close()


def _guarded(path, messages):
    """The bag's messages; a damaged chunk or index (rosbags raises assorted errors, even
    AssertionError) becomes one ValueError naming the file."""
    it = iter(messages)
    while True:
        try:
            item = next(it)
        except StopIteration:
            return
        except Exception as e:
            raise TrajectoryError(
                f"{path}: damaged bag, cannot read its messages ({type(e).__name__}: {e})"
            ) from None
        yield item


def _listing(conns) -> str:
    return ", ".join(f"{c.topic} ({_short(c.msgtype)})" for c in conns) or "none"


def read(
    path,
    topic: str | None = None,
    frame: str | None = None,
    stamp: str = "header",
    sort: bool = False,
    dedupe: bool = False,
) -> Trajectory:
    """Reads the orientations (and positions) on ``topic``.

    Parameters
    ----------
    path : path-like
        A ``.bag`` (ROS 1), a ROS 2 bag directory, a ``.db3`` or an ``.mcap`` file.
    topic : str, optional
        The topic; may be left out when exactly one topic has a usable type. A missing or
        unknown topic raises ``ValueError`` listing the bag's topics and their types.
    frame : str, optional
        For ``tf2_msgs/TFMessage`` topics: the ``child_frame_id`` to follow.
    stamp : {"header", "bag"}
        The message header stamps (default; ``sensor_msgs/Imu`` and poses) or the bag's
        receive times.
    sort, dedupe : bool
        Sort by time / drop repeated stamps instead of failing.

    Returns
    -------
    Trajectory
        Times in seconds, exact stamps in ``stamps_ns``, ``name`` = the topic.

    Raises
    ------
    ValueError
        A file that is not a bag, a missing topic, a type we cannot use, no messages.
    ImportError
        When ``rosbags`` is not installed (with the install hint).
    """
    if stamp not in ("header", "bag"):
        raise ValueError(f"stamp: expected 'header' or 'bag', got {stamp!r}")
    AnyReader, _, _ = _rosbags()
    with _open(path, AnyReader) as reader:
        conns = list(reader.connections)
        usable = [c for c in conns if c.msgtype in TYPES]
        if topic is None:
            names = sorted({c.topic for c in usable})
            if len(names) != 1:
                why = "no topic given" if names else "no topic of a usable type"
                raise TrajectoryError(
                    f"{path}: {why}; topics: {_listing(conns)} "
                    f"(usable types: {', '.join(_short(t) for t in TYPES)})"
                )
            topic = names[0]
        chosen = [c for c in conns if c.topic == topic]
        if not chosen:
            raise TrajectoryError(f"{path}: no topic {topic!r}; topics: {_listing(conns)}")
        msgtype = chosen[0].msgtype
        if msgtype not in TYPES:
            raise TrajectoryError(
                f"{path}: topic {topic!r} has type {_short(msgtype)}, which carries no "
                f"orientation we can use (usable: {', '.join(_short(t) for t in TYPES)})"
            )
        qpath, ppath = TYPES[msgtype]
        is_tf = msgtype == "tf2_msgs/msg/TFMessage"
        ns, quats, pos, children = [], [], [], set()
        total = sum(int(getattr(c, "msgcount", 0) or 0) for c in chosen) or None
        with progress(total=total, desc=f"reading {topic}", unit="msg") as bar:
            for conn, bag_ns, raw in _guarded(path, reader.messages(connections=chosen)):
                bar.update(1)
                try:
                    msg = reader.deserialize(raw, conn.msgtype)
                except Exception as e:  # a corrupt message: name where it is
                    raise TrajectoryError(
                        f"{path}: topic {topic!r}, message {len(ns) + 1}: cannot decode ({e})"
                    ) from None
                items = msg.transforms if is_tf else [msg]
                for item in items:
                    if is_tf or msgtype == "geometry_msgs/msg/TransformStamped":
                        children.add(item.child_frame_id)
                        if frame is not None and item.child_frame_id != frame:
                            continue
                        if is_tf and frame is None and len(children) > 1:
                            raise TrajectoryError(
                                f"{path}: topic {topic!r} carries several child frames "
                                f"({', '.join(sorted(children))}); choose one with frame= "
                                "(--frame)"
                            )
                    if stamp == "header":
                        st = item.header.stamp
                        ns.append(int(st.sec) * 1_000_000_000 + int(st.nanosec))
                    else:
                        ns.append(int(bag_ns))
                    q = _get(item, qpath)
                    quats.append((q.w, q.x, q.y, q.z))
                    if ppath is not None:
                        p = _get(item, ppath)
                        pos.append((p.x, p.y, p.z))
    if not ns:
        extra = f" with child frame {frame!r} (frames: {', '.join(sorted(children)) or 'none'})"
        raise TrajectoryError(
            f"{path}: no messages on topic {topic!r}" + (extra if frame is not None else "")
        )
    stamps = np.array(ns, dtype=np.int64)
    return finish(
        path,
        stamps * 1e-9,
        np.array(quats),
        np.array(pos) if ppath is not None else None,
        np.arange(1, len(ns) + 1),
        sort,
        dedupe,
        name=topic,
        stamps_ns=stamps,
    )


def _stamps(traj: Trajectory) -> np.ndarray:
    if traj.stamps_ns is not None:
        return traj.stamps_ns
    t = np.asarray(traj.times, dtype=float)
    if np.any(t < 0) or np.any(t > 9.2e9):
        raise ValueError("bag: times must be seconds in [0, 9.2e9] (ROS stamps are unsigned)")
    return np.round(t * 1e9).astype(np.int64)


def write(
    path, traj: Trajectory, topic: str = "/pose", frame_id: str = "world", ros: int | None = None
) -> None:
    """Writes ``geometry_msgs/PoseStamped`` messages on ``topic`` — or
    ``geometry_msgs/QuaternionStamped`` when the trajectory has no positions, so that a round
    trip keeps "no positions": ``.bag`` → ROS 1, ``.mcap`` → a ROS 2 MCAP file, any other
    path → a ROS 2 bag directory (sqlite3). The bag is built beside the target and renamed
    into place. A file target follows every writer's rules (only a regular file is replaced,
    a symbolic link is followed, the replaced file keeps its mode); a directory target is
    replaced only if it is a bag."""
    from ._common import check_for_writing

    _rosbags()  # the one-line install hint before anything else
    path = Path(path)
    suffix = path.suffix.lower()
    ros = ros or (1 if suffix == ".bag" else 2)
    check_for_writing(path, traj)  # NaN, no rows, repeated times: what the reader rejects
    stamps = _stamps(traj)
    has_pos = traj.positions is not None
    pos = traj.positions if has_pos else np.zeros((len(traj), 3))
    if not (np.all(np.isfinite(traj.quats)) and np.all(np.isfinite(pos))):
        raise ValueError(f"{path}: refusing to write NaN or inf")
    as_file = ros == 1 or suffix == ".mcap"
    if as_file:
        target, old = resolve_output(path)  # regular files only; symbolic links followed
    else:
        target, old = (Path(os.path.realpath(path)) if path.is_symlink() else path), None
        if target.exists() and not (target.is_file() or is_bag(target)):
            raise ValueError(f"{path}: exists and is not a bag; refusing to replace it")
    target.parent.mkdir(parents=True, exist_ok=True)
    with sigterm_unwinds():
        tmpdir = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
        try:
            out = _write_bag(tmpdir, ros, suffix, traj.quats, stamps, pos, has_pos, topic, frame_id)
            if as_file:
                adopt_mode(out, old)
            elif target.is_dir():
                shutil.rmtree(target)
            os.replace(out, target)
        finally:
            shutil.rmtree(tmpdir, ignore_errors=True)


def _write_bag(tmpdir: Path, ros, suffix, quats, stamps, pos, has_pos, topic, frame_id) -> Path:
    """Writes the messages into a new bag inside ``tmpdir``; returns the bag's path."""
    _, Stores, get_typestore = _rosbags()
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    store = get_typestore(Stores.ROS1_NOETIC if ros == 1 else Stores.ROS2_HUMBLE)
    types = store.types
    Header, Time = types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    Point, Quat = types["geometry_msgs/msg/Point"], types["geometry_msgs/msg/Quaternion"]
    Pose = types["geometry_msgs/msg/Pose"]
    Msg = types[
        "geometry_msgs/msg/PoseStamped" if has_pos else "geometry_msgs/msg/QuaternionStamped"
    ]
    serialize = store.serialize_ros1 if ros == 1 else store.serialize_cdr
    out = tmpdir / ("bag.bag" if ros == 1 else "bag")
    if ros == 1:
        writer = Writer1(out)
    else:
        plugin = StoragePlugin.MCAP if suffix == ".mcap" else StoragePlugin.SQLITE3
        writer = Writer2(out, version=9, storage_plugin=plugin)
    with writer, progress(total=len(quats), desc="writing bag", unit="msg") as bar:
        conn = writer.add_connection(topic, Msg.__msgtype__, typestore=store)
        for k, (ns, p, q) in enumerate(zip(stamps, pos, quats)):
            sec, nsec = divmod(int(ns), 1_000_000_000)
            header = Header(
                stamp=Time(sec=sec, nanosec=nsec),
                frame_id=frame_id,
                **({"seq": k} if ros == 1 else {}),
            )
            rot = Quat(x=float(q[1]), y=float(q[2]), z=float(q[3]), w=float(q[0]))
            if has_pos:
                point = Point(x=float(p[0]), y=float(p[1]), z=float(p[2]))
                msg = Msg(header=header, pose=Pose(position=point, orientation=rot))
            else:
                msg = Msg(header=header, quaternion=rot)
            writer.write(conn, int(ns), serialize(msg, Msg.__msgtype__))
            bar.update(1)
    if ros == 2 and suffix == ".mcap":
        out = next(out.glob("*.mcap"))
    return out
