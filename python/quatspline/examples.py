"""The papers' worked examples as data, and the recording that ships with the package."""

from __future__ import annotations

from importlib.resources import as_file, files

import numpy as np

from . import io
from .io import Trajectory

__all__ = ["BETA_EXAMPLE1_VERTICES", "BETA_EXAMPLE2_VERTICES", "RECORDING", "load_recording"]

#: File name of the bundled recording (inside the package's ``data`` folder).
RECORDING = "freiburg1_xyz-groundtruth.txt"


def load_recording() -> Trajectory:
    """The TUM RGB-D ``fr1/xyz`` ground truth that ships inside the package.

    A handheld camera tracked by motion capture: 3000 poses at 100 Hz over 30.1 s (one
    110 ms gap), published by TU Munich under CC BY 4.0 (Sturm et al., IROS 2012). Read
    with :func:`importlib.resources.files`, so it works from an installed wheel.

    Returns
    -------
    Trajectory
        ``times`` (3000,) in seconds (Unix time), ``quats`` (3000, 4) scalar first,
        ``positions`` (3000, 3) in metres.

    Examples
    --------
    >>> import quatspline as qs
    >>> rec = qs.examples.load_recording()
    >>> rec.quats.shape, rec.positions.shape
    ((3000, 4), (3000, 3))
    >>> round(float(rec.times[-1] - rec.times[0]), 2)
    30.1
    """
    with as_file(files("quatspline") / "data" / RECORDING) as path:
        return io.read(path, format="tum")


#: Beta paper, Example 1: auxiliary vertices P0..P4 as printed (normalise before use).
BETA_EXAMPLE1_VERTICES = np.array(
    [
        [-0.2011, -0.7478, 0.0791, 0.6278],
        [-0.1603, 0.6073, 0.3653, 0.6871],
        [-0.4696, 0.0554, -0.8480, -0.2394],
        [-0.5268, -0.5665, -0.4194, -0.4751],
        [0.6921, -0.2551, 0.1314, 0.6623],
    ]
)

#: Beta paper, Example 2 (shape-parameter demo, Fig. 4).
BETA_EXAMPLE2_VERTICES = np.array(
    [
        [0.6387, -0.6301, -0.3306, 0.2927],
        [0.4412, -0.7009, -0.5567, 0.0646],
        [-0.8180, 0.5011, 0.0249, 0.2813],
        [0.7494, -0.5340, -0.0433, -0.3891],
        [0.9914, 0.0398, 0.1179, -0.0393],
    ]
)
