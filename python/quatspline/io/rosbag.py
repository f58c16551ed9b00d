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

Only regular files are read: a bag directory's ``metadata.yaml`` and the storage files it
lists are checked before the bag is opened (a FIFO would block the reader forever). A message
whose fields differ from the standard type (a bag that embeds its own definition) is refused
naming the file, topic, message and field.

The writer replaces an existing ROS 2 bag directory only when it provably is a bag: its
``metadata.yaml`` parses as rosbag2 bag information and the directory holds nothing but that
file and the storage files it lists; anything else is refused and left untouched. The new bag
is built in a locked work directory ``.NAME.<12 hex>.bagtmp`` beside the target and swapped
in (atomically where the system can exchange two directories, else by two renames undone on
failure), keeping the directory's permission bits; the old bag's files are removed, and
nothing else is. A killed write's work directory is removed by the next write (restoring the
old bag first if the kill fell between the two renames).

Times are the messages' header stamps (``stamp="header"``, default) or the bag's receive
times (``stamp="bag"``), in seconds; the integer nanoseconds are kept exactly in
``Trajectory.stamps_ns``. ROS quaternions are (x, y, z, w); the trajectory's are (w, x, y, z).
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import numbers
import os
import shutil
import stat
import warnings
from pathlib import Path, PurePath

import numpy as np

from .._util.atomic import (
    adopt_mode,
    make_directories,
    make_work_directory,
    release_work_directory,
    remove_stale_temporaries,
    resolve_output,
    sigterm_unwinds,
)
from .._util.optional import need
from .._util.progress_bars import progress
from ._common import check_for_writing, check_regular_input, open_regular
from .trajectory import Trajectory, TrajectoryError, finish

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


def _rosbags(module: str = "highlevel"):
    """The rosbags module ``rosbags.{module}``; without rosbags, one ``ImportError`` naming
    the pip extra."""
    need("rosbags", extra="bag", what="ROS bag support")
    return need(f"rosbags.{module}", extra="bag", what="ROS bag support")


def is_bag(path) -> bool:
    """Whether ``path`` looks like a bag: a .bag/.mcap/.db3 file or a ROS 2 bag directory."""
    p = Path(path)
    return p.suffix.lower() in SUFFIXES or (p.is_dir() and os.path.lexists(p / "metadata.yaml"))


class _Where:
    """Where a message is, for messages: the file, topic and message number."""

    def __init__(self, path, topic):
        self.path, self.topic, self.index = path, topic, 0

    def __str__(self):
        return f"{self.path}: topic {self.topic!r}, message {self.index}"


def field(where, msg, dotted: str):
    """The field ``dotted`` of a decoded message; a bag whose embedded definition lacks or
    renames it is a one-line error naming the file, topic, message and field."""
    obj = msg
    for part in dotted.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise TrajectoryError(
                f"{where}: no field {dotted!r} (the bag's definition of "
                f"{_short(getattr(msg, '__msgtype__', type(msg).__name__))} differs from the "
                "standard one)"
            ) from None
    return obj


def number(where, msg, dotted: str, integer: bool = False):
    x = field(where, msg, dotted)
    kinds = numbers.Integral if integer else numbers.Real
    if isinstance(x, bool) or not isinstance(x, kinds):
        raise TrajectoryError(
            f"{where}: field {dotted!r} is {type(x).__name__}, expected "
            f"{'an integer' if integer else 'a number'} (the bag's definition differs from "
            "the standard one)"
        )
    return int(x) if integer else float(x)


def _short(msgtype: str) -> str:
    return msgtype.replace("/msg/", "/")


def topics(path) -> dict[str, str]:
    """Topic → message type (``pkg/Type``) of every topic in the bag."""
    with open_bag(path) as reader:
        return {c.topic: _short(c.msgtype) for c in reader.connections}


@contextlib.contextmanager
def open_bag(path):
    highlevel = _rosbags("highlevel")

    p = Path(path)
    check_bag_files(p)
    reader = None
    try:
        reader = highlevel.AnyReader([p])
        reader.open()
    except (highlevel.AnyReaderError, OSError, ValueError, KeyError) as e:
        raise TrajectoryError(f"{path}: not a readable ROS bag or MCAP file ({e})") from None
    except Exception as e:  # rosbags raises its own error types per storage backend
        raise TrajectoryError(
            f"{path}: not a readable ROS bag or MCAP file ({type(e).__name__}: {e})"
        ) from None
    try:
        yield reader
    finally:
        reader.close()


def _load_yaml(path, f):
    """``metadata.yaml`` as Python objects (None when it is not YAML)."""
    yaml = need("ruamel.yaml", extra="bag", what="ROS bag support")
    errors = need("ruamel.yaml.error", extra="bag", what="ROS bag support")
    try:
        return yaml.YAML(typ="safe").load(f.read(1 << 24))
    except (errors.YAMLError, UnicodeDecodeError, ValueError, RecursionError):
        return None


def _bag_info(directory: Path):
    """The ``rosbag2_bagfile_information`` mapping of a bag directory's metadata.yaml (read
    through the regular-file check), or None when it is not one."""
    meta = directory / "metadata.yaml"
    with open_regular(meta, "rb") as f:
        doc = _load_yaml(meta, f)
    info = doc.get("rosbag2_bagfile_information") if isinstance(doc, dict) else None
    if not isinstance(info, dict):
        return None
    files = info.get("relative_file_paths")
    if not isinstance(files, list) or not all(isinstance(x, str) and x for x in files):
        return None
    return info


def check_bag_files(path) -> None:
    """The regular-file check for every file the bag reader will open: a bag file, or a
    bag directory's metadata.yaml and each storage file it lists."""
    p = Path(path)
    if not p.is_dir():
        check_regular_input(p)
        return
    info = _bag_info(p)
    if info is None:
        return  # rosbags reports what is wrong with it
    for name in info["relative_file_paths"]:
        storage = p / PurePath(name).name  # as rosbags resolves it
        if os.path.lexists(storage):
            check_regular_input(storage)


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


def check_stamp(stamp) -> None:
    """Refuses a ``stamp=`` option other than ``"header"`` or ``"bag"``."""
    if stamp not in ("header", "bag"):
        raise ValueError(f"stamp: expected 'header' or 'bag', got {stamp!r}")


def choose_topic(path, reader, topic, types, why: str):
    """The topic to read (``topic``, or the one topic whose type is in ``types``), its
    connections and message type; a missing, ambiguous or unusable topic is a one-line error
    listing the bag's topics (``why``: what an unusable type lacks)."""
    conns = list(reader.connections)
    usable = [c for c in conns if c.msgtype in types]
    if topic is None:
        names = sorted({c.topic for c in usable})
        if len(names) != 1:
            what = "no topic given" if names else "no topic of a usable type"
            raise TrajectoryError(
                f"{path}: {what}; topics: {_listing(conns)} "
                f"(usable types: {', '.join(_short(t) for t in types)})"
            )
        topic = names[0]
    chosen = [c for c in conns if c.topic == topic]
    if not chosen:
        raise TrajectoryError(f"{path}: no topic {topic!r}; topics: {_listing(conns)}")
    msgtype = chosen[0].msgtype
    if msgtype not in types:
        raise TrajectoryError(
            f"{path}: topic {topic!r} has type {_short(msgtype)}, which {why} "
            f"(usable: {', '.join(_short(t) for t in types)})"
        )
    return topic, chosen, msgtype


def messages(path, reader, topic, chosen):
    """The decoded messages of the connections ``chosen``, with a progress bar: yields
    (where, bag receive time in ns, message); a damaged chunk or message is a one-line
    error naming the file, topic and message."""
    total = sum(int(getattr(c, "msgcount", 0) or 0) for c in chosen) or None
    where = _Where(path, topic)
    with progress(total=total, desc=f"reading {topic}", unit="msg") as bar:
        for conn, bag_ns, raw in _guarded(path, reader.messages(connections=chosen)):
            bar.update(1)
            where.index += 1
            try:
                msg = reader.deserialize(raw, conn.msgtype)
            except Exception as e:  # a corrupt message: name where it is
                raise TrajectoryError(f"{where}: cannot decode ({e})") from None
            yield where, bag_ns, msg


def stamp_of(where, msg, stamp: str, bag_ns) -> int:
    """The message's time in integer ns: its header stamp or the bag's receive time."""
    if stamp == "header":
        sec = number(where, msg, "header.stamp.sec", integer=True)
        nsec = number(where, msg, "header.stamp.nanosec", integer=True)
        return sec * 1_000_000_000 + nsec
    return int(bag_ns)


def int64_stamps(path, topic, ns) -> np.ndarray:
    """The stamps as int64; one beyond 64-bit nanoseconds is a one-line error."""
    out_of_range = [k for k, v in enumerate(ns) if not -(2**63) <= v < 2**63]
    if out_of_range:
        k = out_of_range[0]
        raise TrajectoryError(
            f"{path}: topic {topic!r}, stamp {k + 1}: {ns[k]} ns is beyond 64-bit nanoseconds"
        )
    return np.array(ns, dtype=np.int64)


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
    check_stamp(stamp)
    with open_bag(path) as reader:
        topic, chosen, msgtype = choose_topic(
            path, reader, topic, TYPES, "carries no orientation we can use"
        )
        qpath, ppath = TYPES[msgtype]
        is_tf = msgtype == "tf2_msgs/msg/TFMessage"
        ns, quats, pos, children = [], [], [], set()
        for where, bag_ns, msg in messages(path, reader, topic, chosen):
            items = field(where, msg, "transforms") if is_tf else [msg]
            if is_tf and not isinstance(items, (list, tuple)):
                raise TrajectoryError(f"{where}: field 'transforms' is not a list")
            for item in items:
                if is_tf or msgtype == "geometry_msgs/msg/TransformStamped":
                    child = field(where, item, "child_frame_id")
                    if not isinstance(child, str):
                        raise TrajectoryError(f"{where}: field 'child_frame_id' is not text")
                    children.add(child)
                    if frame is not None and child != frame:
                        continue
                    if is_tf and frame is None and len(children) > 1:
                        raise TrajectoryError(
                            f"{path}: topic {topic!r} carries several child frames "
                            f"({', '.join(sorted(children))}); choose one with frame= "
                            "(--frame)"
                        )
                ns.append(stamp_of(where, item, stamp, bag_ns))
                quats.append(tuple(number(where, item, f"{qpath}.{c}") for c in "wxyz"))
                if ppath is not None:
                    pos.append(tuple(number(where, item, f"{ppath}.{c}") for c in "xyz"))
    if not ns:
        extra = f" with child frame {frame!r} (frames: {', '.join(sorted(children)) or 'none'})"
        raise TrajectoryError(
            f"{path}: no messages on topic {topic!r}" + (extra if frame is not None else "")
        )
    stamps = int64_stamps(path, topic, ns)
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
    path → a ROS 2 bag directory (sqlite3). The bag is built in a work directory beside the
    target and renamed into place. A file target follows every writer's rules (only a
    regular file is replaced, a symbolic link is followed, the replaced file keeps its mode);
    a directory target is replaced only if it provably is a ROS 2 bag (see the module's
    rules), keeping its mode; anything else is refused and left untouched."""

    _rosbags()  # the one-line install hint before anything else
    check_for_writing(path, traj)  # NaN, no rows, repeated times: what the reader rejects
    stamps = _stamps(traj)
    has_pos = traj.positions is not None
    pos = traj.positions if has_pos else np.zeros((len(traj), 3))
    if not (np.all(np.isfinite(traj.quats)) and np.all(np.isfinite(pos))):
        raise ValueError(f"{path}: refusing to write NaN or inf")
    quats = traj.quats
    msgtype = "geometry_msgs/msg/PoseStamped" if has_pos else "geometry_msgs/msg/QuaternionStamped"

    def make(types, k, header):
        q = quats[k]
        rot = types["geometry_msgs/msg/Quaternion"](
            x=float(q[1]), y=float(q[2]), z=float(q[3]), w=float(q[0])
        )
        if not has_pos:
            return types[msgtype](header=header, quaternion=rot)
        p = pos[k]
        point = types["geometry_msgs/msg/Point"](x=float(p[0]), y=float(p[1]), z=float(p[2]))
        pose = types["geometry_msgs/msg/Pose"](position=point, orientation=rot)
        return types[msgtype](header=header, pose=pose)

    write_bag(path, ros, topic, msgtype, stamps, frame_id, make)


def write_bag(path, ros, topic: str, msgtype: str, stamps, frame_id: str, make) -> None:
    """Writes ``len(stamps)`` messages of type ``msgtype`` on ``topic`` into a new bag at
    ``path`` by the rules of :func:`write`: ``.bag`` → ROS 1 (unless ``ros`` says), ``.mcap``
    → ROS 2 MCAP, any other path → a ROS 2 bag directory. ``make(types, k, header)`` builds
    message ``k`` from the type store's classes and its header (stamp ``stamps[k]`` ns,
    ``frame_id``); the receive time is the stamp."""
    _rosbags()
    path = Path(path)
    suffix = path.suffix.lower()
    ros = ros or (1 if suffix == ".bag" else 2)
    as_file = ros == 1 or suffix == ".mcap"
    old_files = None
    if as_file:
        target, old = resolve_output(path)  # regular files only; symbolic links followed
    else:
        target, old = (Path(os.path.realpath(path)) if path.is_symlink() else path), None
        # first: a killed write's old bag is put back before the target is judged
        remove_stale_temporaries(target, suffixes=(".bagtmp",), remove=_remove_work_dir)
        if os.path.lexists(target):
            old_files = proven_bag_files(path, target)
            old = os.stat(target)
    make_directories(target.parent, path)
    if as_file:
        remove_stale_temporaries(target, suffixes=(".bagtmp",), remove=_remove_work_dir)
    with sigterm_unwinds():
        work = make_work_directory(target, ".bagtmp")
        try:
            out = _write_bag(work, ros, suffix, topic, msgtype, stamps, frame_id, make)
            if as_file:
                adopt_mode(out, old)
                os.replace(out, target)
            else:
                os.chmod(out, stat.S_IMODE(old.st_mode) if old is not None else _new_dir_mode())
                _swap_in(out, target, work, old_files)
        finally:
            with contextlib.suppress(OSError):  # what cannot be removed stays, named by rules
                _remove_work_dir(work)


def _new_dir_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o777 & ~umask


def proven_bag_files(path, directory: Path) -> list[str]:
    """The names of the files of the ROS 2 bag ``directory`` (metadata.yaml and the storage
    files it lists), or a one-line ValueError when it is not provably a bag: not a directory,
    metadata.yaml missing or not rosbag2 bag information, or any other entry inside."""
    st = os.lstat(directory)
    if not stat.S_ISDIR(st.st_mode):
        raise ValueError(
            f"{path}: exists and is not a ROS 2 bag directory; refusing to replace it "
            "(a .bag or .mcap name writes a single file)"
        )
    try:
        info = _bag_info(directory)
    except ValueError:
        info = None
    if info is None:
        raise ValueError(
            f"{path}: is a directory but not a ROS 2 bag (no metadata.yaml holding rosbag2 bag "
            "information); refusing to replace it"
        )
    names = {"metadata.yaml"} | {PurePath(x).name for x in info["relative_file_paths"]}
    entries = os.listdir(directory)
    others = sorted(e for e in entries if e not in names)
    if others:
        shown = ", ".join(others[:3]) + (", …" if len(others) > 3 else "")
        raise ValueError(
            f"{path}: holds files that are not part of the bag ({shown}); refusing to replace it"
        )
    for e in entries:
        if not stat.S_ISREG(os.lstat(directory / e).st_mode):
            raise ValueError(
                f"{path}: {e} is not a regular file, so this is not a bag this library "
                "writes; refusing to replace it"
            )
    return entries


#: the old bag, set aside inside the work directory during the swap
_OLD = "old"


def _remove_work_dir(work: Path) -> None:
    """Removes a work directory: what we wrote into it, and an old bag set aside in it
    (which a kill between the two renames leaves there: put back if the target is missing)."""
    target = work.parent / work.name[1:].rsplit(".", 2)[0]
    old = work / _OLD
    if old.is_dir() and not old.is_symlink():
        if not os.path.lexists(target):
            os.rename(old, target)  # a write killed mid-swap: the old bag comes back
        else:
            try:
                names = proven_bag_files(old, old)
            except ValueError:
                warnings.warn(
                    f"{old}: the replaced bag now holds other files; left in place",
                    RuntimeWarning,
                    stacklevel=3,
                )
                return
            for name in names:
                os.unlink(old / name)
            os.rmdir(old)
    bag = work / "bag"
    if bag.is_dir() and not bag.is_symlink():
        shutil.rmtree(bag)
    for entry in os.listdir(work):  # only what _write_bag makes: bag.bag, bag/
        if entry == "bag.bag":
            os.unlink(work / entry)
    try:
        os.rmdir(work)
    finally:
        release_work_directory(work)


def _swap_in(new: Path, target: Path, work: Path, old_files) -> None:
    """Puts the bag directory ``new`` at ``target``; an existing bag there (``old_files``
    not None) ends up as ``work/old`` for removal."""
    if old_files is None:
        os.rename(new, target)  # fails if something appeared there meanwhile: nothing lost
        return
    if _exchange(new, target):  # one atomic step: target is the new bag, new the old one
        os.rename(new, work / _OLD)
        return
    os.rename(target, work / _OLD)
    try:
        os.rename(new, target)
    except BaseException:
        os.rename(work / _OLD, target)
        raise


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Atomically exchanges two paths (Linux renameat2 RENAME_EXCHANGE); False where the
    system or file system cannot."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    return rc == 0


def _write_bag(tmpdir: Path, ros, suffix, topic, msgtype, stamps, frame_id, make) -> Path:
    """Writes the messages into a new bag inside ``tmpdir``; returns the bag's path."""
    typesys, rosbag1, rosbag2 = _rosbags("typesys"), _rosbags("rosbag1"), _rosbags("rosbag2")

    stores = typesys.Stores
    store = typesys.get_typestore(stores.ROS1_NOETIC if ros == 1 else stores.ROS2_HUMBLE)
    types = store.types
    Header, Time = types["std_msgs/msg/Header"], types["builtin_interfaces/msg/Time"]
    serialize = store.serialize_ros1 if ros == 1 else store.serialize_cdr
    out = tmpdir / ("bag.bag" if ros == 1 else "bag")
    if ros == 1:
        writer = rosbag1.Writer(out)
    else:
        plugin = rosbag2.StoragePlugin
        plugin = plugin.MCAP if suffix == ".mcap" else plugin.SQLITE3
        writer = rosbag2.Writer(out, version=9, storage_plugin=plugin)
    with writer, progress(total=len(stamps), desc="writing bag", unit="msg") as bar:
        conn = writer.add_connection(topic, msgtype, typestore=store)
        for k, ns in enumerate(stamps):
            sec, nsec = divmod(int(ns), 1_000_000_000)
            header = Header(
                stamp=Time(sec=sec, nanosec=nsec),
                frame_id=frame_id,
                **({"seq": k} if ros == 1 else {}),
            )
            writer.write(conn, int(ns), serialize(make(types, k, header), msgtype))
            bar.update(1)
    if ros == 2 and suffix == ".mcap":
        out = next(out.glob("*.mcap"))
    return out
