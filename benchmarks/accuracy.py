"""Real-data accuracy: every interpolating method, and scipy's RotationSpline on the same keys,
predicting held-out frames (every K-th frame is a key). Prints one table per recording and a
summary: the best method's median error against piecewise slerp and against scipy.

    python benchmarks/accuracy.py            # the bundled recordings, K = 10
    python benchmarks/accuracy.py --k 10 FILE[:joint] ...
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import quatspline.io as qio
from quatspline import angle_between
from quatspline.ops import compare, format_table
from quatspline.registry import interpolating_methods

DATA = Path(__file__).resolve().parent.parent / "data"
BUNDLED = [
    ("TUM RGB-D fr1/xyz", DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt", {}),
    ("EuRoC V1_02 (first 10 s)", DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv", {}),
    ("RepoIMU (first 30 s)", DATA / "repoimu" / "repoIMU_first30s.csv", {}),
    (
        "MocapBank BVH, LeftElbow (local)",
        DATA / "mocapbank_bvh" / "test_mocapbank.bvh",
        {"joint": "LeftElbow"},
    ),
]


def scipy_row(traj, k):
    from scipy.spatial.transform import Rotation, RotationSpline

    t = traj.times - traj.times[0]
    idx = np.arange(0, len(t), k)
    rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
    q = traj.quats[[*idx]]
    s = RotationSpline(t[idx], Rotation.from_quat(q[:, [1, 2, 3, 0]]))
    pred = s(t[rest]).as_quat()[:, [3, 0, 1, 2]]
    err = angle_between(pred, traj.quats[rest], degrees=True)
    return float(np.median(err)), float(np.percentile(err, 95)), float(err.max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, default=10)
    ap.add_argument("files", nargs="*", help="FILE or FILE:joint (BVH)")
    args = ap.parse_args()
    cases = BUNDLED
    if args.files:
        cases = []
        for f in args.files:
            path, _, joint = f.partition(":")
            cases.append((f, Path(path), {"joint": joint} if joint else {}))
    for name, path, opts in cases:
        traj = qio.read(path, **opts)
        rows = compare(traj, interpolating_methods(), holdout=args.k)
        print(f"\n## {name} ({len(traj)} frames, keys every {args.k}th)\n")
        print(format_table(rows))
        med, p95, mx = scipy_row(traj, args.k)
        print(f"| scipy RotationSpline | | | | | | | {med:.4f} | {p95:.4f} | {mx:.4f} |")
        best = min(rows, key=lambda r: r["holdout_median_deg"])
        slerp = next(r for r in rows if r["method"] == "slerp")
        print(
            f"\nbest: {best['method']} {best['holdout_median_deg']:.4f}° median = "
            f"{best['holdout_median_deg'] / slerp['holdout_median_deg']:.3f} × slerp, "
            f"{best['holdout_median_deg'] / med:.3f} × scipy RotationSpline "
            f"(RotationSpline/slerp = {med / slerp['holdout_median_deg']:.3f})"
        )


if __name__ == "__main__":
    main()
