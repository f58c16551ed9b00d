"""The C³ spline's default shape (α, β) = (5/16, 0) against alpha="auto" = (1/2, −3):
speed ripple on a constant-speed great circle (max/min |ω| over the interior segments,
uniform and non-uniform keys) and held-out accuracy (every K-th frame a key) with RMS jerk on
the bundled recordings.

    python benchmarks/c3_auto.py [--k 10]
"""

from __future__ import annotations

import argparse

import numpy as np
import quatspline as qs
import quatspline.io as qio
from accuracy import BUNDLED
from quatspline import angle_between

SHAPES = {"default (5/16, 0)": {}, "auto (1/2, -3)": {"alpha": "auto"}}


def ripple(kind: str, shape: dict) -> float:
    axis = np.array([0.2, 0.9, -0.4]) / np.linalg.norm([0.2, 0.9, -0.4])
    if kind == "uniform":
        t = np.arange(12.0)
    else:
        t = np.cumsum(np.r_[0, np.random.default_rng(1).uniform(0.5, 1.5, 11)])
    q = qs.from_rotvec(0.9 * t[:, None] * axis)
    s = qs.C3Spline(q, t, **shape)
    x = np.linspace(t[2], t[-3], 4001)
    w = np.linalg.norm(s.angular_velocity(x), axis=1)
    return float(w.max() / w.min())


def accuracy(path, opts, k: int, shape: dict) -> tuple[float, float, float, float]:
    traj = qio.read(path, **opts)
    t = traj.times - traj.times[0]
    idx = np.arange(0, len(t), k)
    rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
    s = qs.C3Spline(traj.quats[idx], t[idx], **shape)
    err = angle_between(s(t[rest]), traj.quats[rest], degrees=True)
    x = np.linspace(t[idx][0], t[idx][-1], 20000)
    jerk = float(np.sqrt(np.mean(np.sum(s.jerk(x) ** 2, axis=1))))
    return float(np.median(err)), float(np.percentile(err, 95)), float(err.max()), jerk


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, default=10)
    args = ap.parse_args()
    print("| shape | ripple, uniform keys | ripple, non-uniform keys |")
    print("|---|---:|---:|")
    for name, shape in SHAPES.items():
        print(f"| {name} | {ripple('uniform', shape):.4f} | {ripple('nonuniform', shape):.4f} |")
    print(f"\nHeld-out accuracy, every {args.k}th frame a key (degrees) and RMS jerk:\n")
    print("| recording | shape | median | p95 | max | rms jerk |")
    print("|---|---|---:|---:|---:|---:|")
    for label, path, opts in BUNDLED:
        for name, shape in SHAPES.items():
            med, p95, mx, j = accuracy(path, opts, args.k, shape)
            print(f"| {label} | {name} | {med:.4f} | {p95:.4f} | {mx:.3f} | {j:.3g} |")


if __name__ == "__main__":
    main()
