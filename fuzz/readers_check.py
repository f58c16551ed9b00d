"""The readers' fuzz invariant, shared by the atheris target and the regression replay test.

A reader must return a valid trajectory (finite times strictly increasing, unit quaternions)
or raise ValueError with a message naming the file; any other exception is a bug. The first
byte of an input picks the file name (hence the format), the rest is the file's content.
"""

from __future__ import annotations

import os

import numpy as np
import quatspline.io as qio

NAMES = ["a.csv", "a.txt", "a.json", "a.npz", "a.bvh", "a.csv"]
FORMATS = [None, None, None, None, None, "euroc"]


def check_one(data: bytes, directory: str) -> None:
    """Writes ``data`` as a file in ``directory``, reads it and asserts the invariant."""
    if not data:
        return
    k = data[0] % len(NAMES)
    path = os.path.join(directory, NAMES[k])
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
