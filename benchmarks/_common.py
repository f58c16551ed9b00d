"""What every benchmark script shares: the machine's name and the bundled recordings.

The scripts run as ``python benchmarks/<name>.py``, which puts this directory on ``sys.path``;
a test that loads a script by file path prepends it too.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

DATA = Path(__file__).resolve().parent.parent / "data"

#: The bundled real recordings: (label, path, reader options).
RECORDINGS = [
    ("TUM RGB-D fr1/xyz", DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt", {}),
    ("EuRoC V1_02 (10 s)", DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv", {}),
    ("RepoIMU (30 s)", DATA / "repoimu" / "repoIMU_first30s.csv", {}),
    ("MocapBank LeftElbow", DATA / "mocapbank_bvh" / "test_mocapbank.bvh", {"joint": "LeftElbow"}),
]


def cpu_model() -> str:
    """The CPU's model name, family/model/stepping and the vector extensions that matter here."""
    name, fam, model, step, flags = "unknown", "?", "?", "?", set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                k, _, v = line.partition(":")
                k, v = k.strip(), v.strip()
                if k == "model name":
                    name = v
                elif k == "cpu family":
                    fam = v
                elif k == "model":
                    model = v
                elif k == "stepping":
                    step = v
                elif k == "flags":
                    flags = set(v.split())
                    break
    except OSError:
        return platform.processor() or platform.machine()
    simd = "+".join(f for f in ("avx2", "fma", "avx512f", "avx512dq") if f in flags) or "no avx2"
    cores = os.cpu_count()
    return f"{name} (family {fam}, model {model}, stepping {step}; {simd}; {cores} logical cores)"


def load() -> str:
    """The 1-, 5- and 15-minute load averages (the machine may be shared)."""
    try:
        return "/".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "unknown"
