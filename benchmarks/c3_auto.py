"""The C³ spline's default shape (α, β) = (5/16, 0) against the two candidate "auto" rules —
the fixed pair (1/2, −3) and the per-key speed-matched α_k (β_k = −6 α_k,
``quatspline.splines.c3_speed_matched_alpha``): speed ripple on a constant-speed
great circle
(max/min |ω| over the interior segments, uniform and non-uniform keys; also on a great circle
whose speed varies) and held-out accuracy (every K-th frame a key) with RMS jerk on the bundled
recordings.

    python benchmarks/c3_auto.py [--k 10]
"""

from __future__ import annotations

import argparse

import numpy as np
import quatspline as qs
import quatspline.io as qio
from accuracy import BUNDLED
from quatspline import angle_between


def _per_key(q, t):
    a = qs.splines.c3_speed_matched_alpha(q, t)
    return {"alpha": a, "beta": -6 * a}


SHAPES = {
    "default (5/16, 0)": lambda q, t: {"alpha": 5 / 16, "beta": 0.0},
    "fixed pair (1/2, -3)": lambda q, t: {"alpha": 0.5, "beta": -3.0},
    "per-key speed-matched": _per_key,
}


def ripple(kind: str, shape) -> float:
    axis = np.array([0.2, 0.9, -0.4]) / np.linalg.norm([0.2, 0.9, -0.4])
    if kind == "uniform":
        t = np.arange(12.0)
    else:
        t = np.cumsum(np.r_[0, np.random.default_rng(1).uniform(0.5, 1.5, 11)])
    q = qs.from_rotvec(0.9 * t[:, None] * axis)
    s = qs.C3Spline(q, t, **shape(q, t))
    x = np.linspace(t[2], t[-3], 4001)
    w = np.linalg.norm(s.angular_velocity(x), axis=1)
    return float(w.max() / w.min())


def turning(shape) -> float:
    """Max/min of |ω| / (mean chord speed at the nearest key) on a path that turns at every key
    (keys on a circle of latitude, 30° apart): how far key speeds stray from the chords'."""
    t = np.arange(13.0)
    lat, lon = np.radians(40.0), np.radians(30.0) * t
    axes = np.c_[np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.full_like(t, np.sin(lat))]
    q = qs.from_rotvec(0.8 * axes)
    s = qs.C3Spline(q, t, **shape(q, t))
    w = np.linalg.norm(s.angular_velocity(t[2:-2], "body"), axis=1)
    chord = qs.angle_between(q[:-1], q[1:])
    mean = 0.5 * (chord[1:-2] + chord[2:-1])
    r = w / mean
    return float(r.max()), float(r.min())


def accuracy(path, opts, k: int, shape, uneven: bool = False) -> tuple[float, float, float, float]:
    traj = qio.read(path, **opts)
    t = traj.times - traj.times[0]
    if uneven:  # key gaps drawn from k/2 … 3k/2 frames (seeded): non-uniform key spacing
        gaps = np.random.default_rng(2).integers(max(1, k // 2), 3 * k // 2 + 1, len(t))
        idx = np.cumsum(np.r_[0, gaps])
        idx = idx[idx < len(t)]
    else:
        idx = np.arange(0, len(t), k)
    rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
    q = qs.canonicalize(traj.quats[idx])
    s = qs.C3Spline(q, t[idx], **shape(q, t[idx]))
    err = angle_between(s(t[rest]), traj.quats[rest], degrees=True)
    x = np.linspace(t[idx][0], t[idx][-1], 20000)
    jerk = float(np.sqrt(np.mean(np.sum(s.jerk(x) ** 2, axis=1))))
    return float(np.median(err)), float(np.percentile(err, 95)), float(err.max()), jerk


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=int, default=10)
    args = ap.parse_args()
    print("| shape | ripple, uniform keys | ripple, non-uniform keys | key speed / chords |")
    print("|---|---:|---:|---:|")
    for name, shape in SHAPES.items():
        hi, lo = turning(shape)
        print(
            f"| {name} | {ripple('uniform', shape):.4f} | {ripple('nonuniform', shape):.4f} "
            f"| {lo:.3f} … {hi:.3f} |"
        )
    for uneven in (False, True):
        which = (
            f"key gaps of {args.k // 2} … {3 * args.k // 2} frames"
            if uneven
            else f"every {args.k}th frame a key"
        )
        print(f"\nHeld-out accuracy, {which} (degrees) and RMS jerk:\n")
        print("| recording | shape | median | p95 | max | rms jerk |")
        print("|---|---|---:|---:|---:|---:|")
        for label, path, opts in BUNDLED:
            for name, shape in SHAPES.items():
                med, p95, mx, j = accuracy(path, opts, args.k, shape, uneven)
                print(f"| {label} | {name} | {med:.4f} | {p95:.4f} | {mx:.3f} | {j:.3g} |")


if __name__ == "__main__":
    main()
