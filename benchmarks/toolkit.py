"""Toolkit benchmark: means, integration, non-uniform B-splines, arc-length
reparameterisation and screw splines, against peers where there is one (same data, same run).
Prints the best of --repeat runs in ns per sample and ratios.

    python benchmarks/toolkit.py --repeat 5
"""

from __future__ import annotations

import argparse

import numpy as np
import quatspline as qs
from _common import cpu_model
from engine_bench import best_ns


def walk(n, seed=0, step=0.3):
    rng = np.random.default_rng(seed)
    return qs.from_rotvec(np.cumsum(rng.normal(scale=step, size=(n, 3)), axis=0))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    r = args.repeat
    rows = []

    from scipy.spatial.transform import Rotation

    n = 100_000
    q = walk(n, 1, 0.01)
    ours = best_ns(lambda: qs.mean(q), n, r)
    rot = Rotation.from_quat(qs.as_xyzw(q))
    peer = best_ns(lambda: rot.mean(), n, r)
    rows.append(("chordal mean, 1e5 rotations", ours, f"scipy Rotation.mean ×{peer / ours:.2f}"))
    geo = best_ns(lambda: qs.mean(q, method="geodesic"), n, r)
    rows.append(("geodesic (Karcher) mean, 1e5", geo, ""))

    n = 1_000_000
    t = np.linspace(0.0, 100.0, n)
    w = np.random.default_rng(2).normal(size=(n, 3))
    for m in ("zoh", "linear", "cubic"):
        rows.append(
            (
                f"integrate {m}, 1e6 samples",
                best_ns(lambda m=m: qs.integrate(t, w, method=m), n, r),
                "",
            )
        )

    keys = walk(200, 3)
    knots = np.cumsum(np.random.default_rng(4).uniform(0.5, 1.5, 204))
    uni = qs.CumulativeBSpline(keys, dt=1.0)
    non = qs.CumulativeBSpline(keys, knots=knots)
    x_u = np.linspace(*uni.domain, n)
    x_n = np.linspace(*non.domain, n)
    a = best_ns(lambda: uni.derivatives(x_u, 3), n, r)
    b = best_ns(lambda: non.derivatives(x_n, 3), n, r)
    rows.append(("uniform cubic B-spline q…q''', 1e6", a, ""))
    rows.append(("non-uniform cubic B-spline q…q''', 1e6", b, f"×{b / a:.2f} of uniform"))

    s = qs.C3Spline(walk(50, 5), np.cumsum(np.r_[0, np.random.default_rng(6).uniform(0.5, 2, 49)]))
    build = best_ns(lambda: qs.arc_length(s), 1, r)
    arc = qs.arc_length(s)
    m = 100_000
    xs = np.linspace(*s.domain, m)
    inner = best_ns(lambda: s.angular_velocity(xs), m, r)
    outer = best_ns(lambda: arc.angular_velocity(xs), m, r)
    rows.append(("arc_length(C3, 50 keys) construction", build, "(ns per spline)"))
    rows.append(("arc-length spline ω, 1e5", outer, f"×{outer / inner:.1f} of the C3 spline"))

    import pytransform3d.batch_rotations  # noqa: F401
    from pytransform3d.trajectories import dual_quaternions_sclerp

    tt = np.linspace(0, 1, 2)
    pos = np.array([[0.0, 0, 0], [1.0, 2.0, -0.5]])
    qq = walk(2, 7, 0.8)
    screw = qs.ScrewSpline(qq, tt, pos)
    dq = qs.dq_from_pose(qq, pos)
    u = np.linspace(0, 1, m)
    ours = best_ns(lambda: screw.position(u), m, r)
    a0, b0 = np.tile(dq[0], (m, 1)), np.tile(dq[1], (m, 1))
    peer = best_ns(lambda: dual_quaternions_sclerp(a0, b0, u), m, r)
    rows.append(
        ("ScrewSpline (ScLerp) positions, 1e5", ours, f"pytransform3d sclerp ×{peer / ours:.2f}")
    )
    twist = best_ns(lambda: screw.twist(u, order=3), m, r)
    rows.append(("ScrewSpline body twist'' , 1e5", twist, ""))

    print(f"CPU: {cpu_model()}; best of {r} runs; ns per sample (ratio > 1: quatspline faster)")
    for name, ns, note in rows:
        print(f"{name:44s} {ns:12.1f}  {note}")


if __name__ == "__main__":
    main()
