"""The papers' worked examples as data (MATH.md §7)."""

from __future__ import annotations

import numpy as np

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
