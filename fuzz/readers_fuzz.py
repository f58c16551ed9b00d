"""Fuzz the trajectory file readers with atheris: arbitrary bytes as every supported format
(KITTI, glTF/GLB, ROS 1 bags and MCAP included).

A reader must return a valid trajectory (finite times strictly increasing, unit quaternions)
or raise ValueError with a message naming the file; any other exception is a bug.

    python fuzz/readers_fuzz.py -max_total_time=600
"""

from __future__ import annotations

import os
import sys
import tempfile

import atheris

with atheris.instrument_imports():
    import numpy as np
    import quatspline.io as qio

DIR = tempfile.mkdtemp(prefix="qs-fuzz-")
NAMES = ["a.csv", "a.txt", "a.json", "a.npz", "a.bvh", "a.csv", "k.txt", "a.glb", "a.gltf"]
NAMES += ["a.bag", "a.mcap"]
FORMATS = [None, None, None, None, None, "euroc", "kitti", None, None, None, None]


def one_input(data: bytes) -> None:
    if not data:
        return
    k = data[0] % len(NAMES)
    path = os.path.join(DIR, NAMES[k])
    with open(path, "wb") as f:
        f.write(data[1:])
    fmt = FORMATS[k]
    try:
        t = qio.read(path, format=fmt)
    except ValueError as e:
        assert path in str(e) or "format" in str(e), f"error does not name the file: {e}"
        return
    assert len(t) > 0
    assert np.all(np.isfinite(t.times)) and np.all(np.diff(t.times) > 0)
    assert np.all(np.abs(np.linalg.norm(t.quats, axis=1) - 1) < 1e-12)


if __name__ == "__main__":
    atheris.Setup(sys.argv, one_input)
    atheris.Fuzz()
