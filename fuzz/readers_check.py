"""The readers' fuzz invariant, shared by the atheris target and the regression replay test.

A reader must return a valid trajectory (finite times strictly increasing, unit quaternions)
or raise ValueError with a message naming the file; any other exception is a bug.

An input is one byte that picks an entry of :data:`ENTRIES` (a file name and the format it is
read as), then the file's content. A ROS 2 bag is a directory: its entries take a 4-byte
little-endian length, that many bytes of ``metadata.yaml``, and the storage file (``bag.db3``
or ``bag.mcap``) as the rest. :data:`ENTRIES` is built from ``quatspline.io.FORMATS``, so a
format added to the library is fuzzed without editing this file.
"""

from __future__ import annotations

import os
import shutil
import struct

import numpy as np
import quatspline.io as qio

#: (file name, format passed to io.read; None: detected from the name and content, storage
#: file name inside a ROS 2 bag directory or None for a plain file). The first six keep the
#: indices of the earlier fuzzer so that old findings keep their meaning.
_KNOWN = [
    ("a.csv", None, None),
    ("a.txt", None, None),
    ("a.json", None, None),
    ("a.npz", None, None),
    ("a.bvh", None, None),
    ("a.csv", "euroc", None),
    ("k.txt", "kitti", None),
    ("a.glb", "gltf", None),
    ("a.gltf", "gltf", None),
    ("a.bag", "rosbag", None),
    ("a.mcap", "rosbag", None),
    ("a.db3", "rosbag", None),
    ("bag", "rosbag", "bag.db3"),
    ("bag", "rosbag", "bag.mcap"),
    ("a.tum", "tum", None),
    ("r.csv", "repoimu", None),
    ("e.csv", "csv", None),
    ("j.json", "json", None),
    ("n.npz", "npz", None),
    ("b.bvh", "bvh", None),
]
#: Every format the library reads, each read explicitly at least once (a format missing
#: from ``_KNOWN`` is appended as ``a.<format>`` read with ``format=``).
ENTRIES = _KNOWN + [(f"a.{f}", f, None) for f in qio.FORMATS if f not in {e[1] for e in _KNOWN}]
FORMATS = sorted({f for _, f, _ in ENTRIES if f is not None})


def encode(entry: int, content: bytes, storage: bytes = b"") -> bytes:
    """The fuzz input for ``ENTRIES[entry]``: a file's content, or for a bag directory the
    ``metadata.yaml`` content and the storage file."""
    if ENTRIES[entry][2] is None:
        return bytes([entry]) + content
    return bytes([entry]) + struct.pack("<I", len(content)) + content + storage


def materialise(data: bytes, directory: str) -> tuple[str, str | None] | None:
    """Writes the input's file (or bag directory) in ``directory``; (path, format)."""
    if not data:
        return None
    name, fmt, storage = ENTRIES[data[0] % len(ENTRIES)]
    path = os.path.join(directory, name)
    body = data[1:]
    if storage is None:
        if os.path.isdir(path):
            shutil.rmtree(path)
        with open(path, "wb") as f:
            f.write(body)
        return path, fmt
    n = struct.unpack("<I", body[:4])[0] if len(body) >= 4 else 0
    meta, rest = body[4 : 4 + n], body[4 + n :]
    if os.path.lexists(path) and not os.path.isdir(path):
        os.remove(path)
    if os.path.isdir(path):
        shutil.rmtree(path)
    os.mkdir(path)
    with open(os.path.join(path, "metadata.yaml"), "wb") as f:
        f.write(meta)
    with open(os.path.join(path, storage), "wb") as f:
        f.write(rest)
    return path, fmt


def check_one(data: bytes, directory: str):
    """Writes ``data`` as a file in ``directory``, reads it and asserts the invariant;
    returns the trajectory, or the ValueError the reader raised (None for an empty input)."""
    made = materialise(data, directory)
    if made is None:
        return None
    path, fmt = made
    try:
        t = qio.read(path, format=fmt)
    except ValueError as e:
        msg = str(e)
        assert path in msg, f"error does not name the file: {msg}"
        assert "\n" not in msg, f"error is not one line: {msg!r}"
        return e
    assert len(t) > 0
    assert np.all(np.isfinite(t.times)) and np.all(np.diff(t.times) > 0)
    assert np.all(np.abs(np.linalg.norm(t.quats, axis=1) - 1) < 1e-12)
    if t.positions is not None:
        assert t.positions.shape == (len(t), 3) and np.all(np.isfinite(t.positions))
    return t
