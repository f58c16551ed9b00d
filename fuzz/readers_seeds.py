"""Writes one small valid input of every ``readers_check.ENTRIES`` entry into
``fuzz/corpus/readers`` as ``seed-<entry>-<format>-<name>`` (run again after changing the
entries): each reads back as a trajectory through ``readers_check.check_one``."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import quatspline.io as qio  # noqa: E402
import readers_check  # noqa: E402

HERE = Path(__file__).resolve().parent
OUT = HERE / "corpus" / "readers"


def _trajectory(positions: bool) -> qio.Trajectory:
    ang = np.array([0.0, 0.3, 0.7, 1.0])
    q = np.stack([np.cos(ang / 2), np.sin(ang / 2), 0 * ang, 0 * ang], axis=1)
    x = np.stack([ang, ang**2, 0 * ang], axis=1) if positions else None
    return qio.Trajectory([0.0, 0.5, 1.0, 1.5], q, positions=x)


def _ros2_dir(tmp: Path, storage: str, traj) -> tuple[bytes, bytes]:
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    T = store.types
    out = Path(tempfile.mkdtemp(dir=tmp)) / "bag"
    plugin = StoragePlugin.MCAP if storage.endswith(".mcap") else StoragePlugin.SQLITE3
    Msg = T["geometry_msgs/msg/QuaternionStamped"]
    with Writer2(out, version=9, storage_plugin=plugin) as w:
        conn = w.add_connection("/q", Msg.__msgtype__, typestore=store)
        for t, q in zip(traj.times, traj.quats):
            ns = int(round(t * 1e9))
            hdr = T["std_msgs/msg/Header"](
                stamp=T["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9),
                frame_id="w",
            )
            quat = T["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0])
            msg = Msg(header=hdr, quaternion=quat)
            w.write(conn, ns, store.serialize_cdr(msg, Msg.__msgtype__))
    meta = (out / "metadata.yaml").read_bytes()
    files = [p for p in out.iterdir() if p.name != "metadata.yaml"]
    assert len(files) == 1 and files[0].name == storage, files
    return meta, files[0].read_bytes()


def _file(tmp: Path, k: int, name: str, fmt: str | None) -> bytes:
    path = tmp / f"{k}-{name}"
    if fmt in ("euroc", "repoimu", "kitti") or name.endswith(".txt"):
        use = fmt or "tum"
    else:
        use = fmt or qio.detect_format_for_writing(name)
    opts = {}
    if use == "gltf":
        opts = {"mesh": None, "progress": False}
    if use == "kitti":
        path = path.with_suffix(".txt")
    try:
        qio.write(path, _trajectory(True), format=use, **opts)
    except ValueError:  # a format without positions
        qio.write(path, _trajectory(False), format=use, **opts)
    return path.read_bytes()


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob("seed-*"):
        old.unlink()
    with tempfile.TemporaryDirectory() as d, tempfile.TemporaryDirectory() as check:
        tmp = Path(d)
        for k, (name, fmt, storage) in enumerate(readers_check.ENTRIES):
            if storage is not None:
                data = readers_check.encode(k, *_ros2_dir(tmp, storage, _trajectory(False)))
            elif name.endswith(".db3"):  # a bare ROS 2 sqlite3 storage file
                data = readers_check.encode(k, _ros2_dir(tmp, "bag.db3", _trajectory(False))[1])
            else:
                data = readers_check.encode(k, _file(tmp, k, name, fmt))
            got = readers_check.check_one(data, check)
            assert isinstance(got, qio.Trajectory), (k, name, fmt, got)
            seed = OUT / f"seed-{k:02d}-{fmt or 'auto'}-{(storage or name).replace('.', '_')}"
            seed.write_bytes(data)
            print(f"{seed.name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
