"""Fuzz the trajectory file readers with atheris: arbitrary bytes as every supported format
(KITTI, glTF/GLB, ROS 1 bags and MCAP included).

The invariant lives in ``readers_check.py`` (shared with tests/test_fuzz_regressions.py, which
replays every input in ``fuzz/regressions/readers``). Pass that folder as a second corpus
directory so past findings seed each run:

    python fuzz/readers_fuzz.py fuzz/corpus/readers fuzz/regressions/readers -max_total_time=600
"""

from __future__ import annotations

import os
import sys
import tempfile

import atheris

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

with atheris.instrument_imports():
    import readers_check

DIR = tempfile.mkdtemp(prefix="qs-fuzz-")
NAMES = ["a.csv", "a.txt", "a.json", "a.npz", "a.bvh", "a.csv", "k.txt", "a.glb", "a.gltf"]
NAMES += ["a.bag", "a.mcap"]
FORMATS = [None, None, None, None, None, "euroc", "kitti", None, None, None, None]


def one_input(data: bytes) -> None:
    readers_check.check_one(data, DIR)


if __name__ == "__main__":
    atheris.Setup(sys.argv, one_input)
    atheris.Fuzz()
