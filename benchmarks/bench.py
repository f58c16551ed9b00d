"""Peer benchmark: quatspline against scipy, numpy-quaternion and pytransform3d, same data,
same run. Prints ns per sample (best of --repeat runs) and the ratio to each peer, then the
evaluation engine's tables (benchmarks/engine_bench.py).

    make bench                # builds in release mode, then runs this
    python benchmarks/bench.py --n 1000000 --repeat 5
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
from collections.abc import Callable

import engine_bench
import numpy as np
import quatspline as qs
from quatspline.splines import bessel_rates


def median_ns(fn: Callable[[], object], n: int, repeat: int) -> float:
    """Best (minimum) of ``repeat`` runs after a warm-up, ns per item: the machine is shared,
    the least disturbed run is the one closest to the code's cost. (Name kept for the callers.)
    """
    fn()  # warm up (page faults, lazy imports)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter_ns()
        fn()
        times.append(time.perf_counter_ns() - t0)
    return min(times) / n


def random_quats(n: int, seed: int) -> np.ndarray:
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def slerp_pairs(n: int, repeat: int) -> list[tuple[str, str, float]]:
    """1,000,000 independent slerp pairs (issue 1/6)."""
    a, b = random_quats(n, 1), random_quats(n, 2)
    b = qs.canonicalize(b, reference=a)
    t = np.random.default_rng(3).uniform(0, 1, n)
    rows = [("quatspline", "slerp (pairs)", median_ns(lambda: qs.slerp(a, b, t), n, repeat))]
    try:
        import quaternion

        qa, qb = quaternion.as_quat_array(a), quaternion.as_quat_array(b)
        rows.append(
            (
                "numpy-quaternion",
                "np.slerp_vectorized (ufunc)",
                median_ns(lambda: np.slerp_vectorized(qa, qb, t), n, repeat),
            )
        )
    except ImportError:
        print("numpy-quaternion not installed: skipped")
    try:
        from scipy.spatial.transform import Rotation

        ra, rb = Rotation.from_quat(qs.as_xyzw(a)), Rotation.from_quat(qs.as_xyzw(b))

        def scipy_slerp():
            return ra * Rotation.from_rotvec((ra.inv() * rb).as_rotvec() * t[:, None])

        rows.append(("scipy", "r0 * exp(t log(r0⁻¹ r1))", median_ns(scipy_slerp, n, repeat)))
    except ImportError:
        print("scipy not installed: skipped")
    try:
        import pytransform3d.batch_rotations as pbr

        # pytransform3d has no batch of pairs; its batch form is one pair, many t (its best case)
        rows.append(
            (
                "pytransform3d",
                "quaternion_slerp_batch (1 pair, n t)",
                median_ns(lambda: pbr.quaternion_slerp_batch(a[0], b[0], t), n, repeat),
            )
        )
    except ImportError:
        print("pytransform3d not installed: skipped")
    return rows


def random_walk(n: int, seed: int, step: float = 0.3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3))
    v *= (rng.uniform(0.05, step, n) / np.linalg.norm(v, axis=1))[:, None]
    rel = qs.exp(np.concatenate([np.zeros((n, 1)), v], axis=1))
    q = np.empty((n, 4))
    q[0] = qs.normalize(rng.normal(size=4))
    for i in range(1, n):
        q[i] = qs.multiply(q[i - 1], rel[i])
    return q


def spline_methods(n: int, keys: int, repeat: int) -> list[tuple[str, str, float]]:
    """1,000 keys, n sorted samples (issues 2/6 and 3/6)."""
    q = random_walk(keys, 4)
    times = np.arange(keys, dtype=float)
    t = np.linspace(0.0, keys - 1.0, n)
    tb = np.linspace(0.0, keys - 3.0, n)  # the cubic B-spline's domain is 3 knots shorter
    rows = []
    cases = [
        ("PiecewiseSlerp", qs.PiecewiseSlerp(q, times), t),
        ("Squad", qs.Squad(q, times), t),
        ("CatmullRom", qs.CatmullRom(q, times), t),
        ("NaturalSpline", qs.NaturalSpline(q, times), t),
        ("CumulativeBSpline", qs.CumulativeBSpline(q), tb),
        ("BetaSpline (β₁=1.5, β₂=0.5)", qs.BetaSpline(q, beta1=1.5, beta2=0.5), tb),
        ("C3Spline (knot)", qs.C3Spline(q, times), t),
        ("C3Spline (patent)", qs.C3Spline(q, times, variant="patent"), t),
        ("Hermite (cubic)", qs.Hermite(q, times, bessel_rates(q, times), frame="body"), t),
        ("KochanekBartels (T=0.3)", qs.KochanekBartels(q, times, tension=0.3), t),
        ("CumulativeBezier (8 points)", qs.CumulativeBezier(q[:8], domain=(0.0, keys - 1.0)), t),
        ("SphericalBezier (8 points)", qs.SphericalBezier(q[:8], domain=(0.0, keys - 1.0)), t),
    ]
    for name, s, tt in cases:
        rows.append(("quatspline", name, median_ns(lambda s=s, tt=tt: s(tt), n, repeat)))
    nat = cases[3][1]
    c3 = cases[6][1]
    rows.append(
        ("quatspline", "C3Spline ω (world)", median_ns(lambda: c3.angular_velocity(t), n, repeat))
    )
    rows.append(
        (
            "quatspline",
            "NaturalSpline ω (world)",
            median_ns(lambda: nat.angular_velocity(t), n, repeat),
        )
    )
    rows.append(
        (
            "quatspline",
            "NaturalSpline ω (body)",
            median_ns(lambda: nat.angular_velocity(t, frame="body"), n, repeat),
        )
    )
    try:
        from scipy.spatial.transform import Rotation, RotationSpline, Slerp

        r = Rotation.from_quat(qs.as_xyzw(q))
        rs = RotationSpline(times, r)
        sl = Slerp(times, r)
        build = median_ns(lambda: RotationSpline(times, r), 1, repeat) * 1e-6
        ours = median_ns(lambda: qs.NaturalSpline(q, times, ends="clamped"), 1, repeat) * 1e-6
        print(
            f"\nconstruction, 1,000 keys: scipy RotationSpline {build:.2f} ms, "
            f"quatspline NaturalSpline (same construction) {ours:.2f} ms, "
            f"C3Spline {median_ns(lambda: qs.C3Spline(q, times), 1, repeat) * 1e-6:.2f} ms"
        )
        rows.append(("scipy", "RotationSpline (evaluate)", median_ns(lambda: rs(t), n, repeat)))
        rows.append(("scipy", "RotationSpline(t, 1) (ω)", median_ns(lambda: rs(t, 1), n, repeat)))
        rows.append(("scipy", "Slerp", median_ns(lambda: sl(t), n, repeat)))
    except ImportError:
        print("scipy not installed: skipped")
    try:
        import splines.quaternion as sq

        uq = [sq.UnitQuaternion.from_unit_xyzw(v) for v in qs.as_xyzw(q)]
        kb = sq.KochanekBartels(uq, times.tolist(), tcb=(0.3, 0.0, 0.0))
        ts = t[:: max(1, n // 200)]  # pure Python: 200 samples suffice
        rows.append(
            (
                "splines",
                "KochanekBartels (T=0.3)",
                median_ns(lambda: [kb.evaluate(x) for x in ts], len(ts), repeat),
            )
        )
    except ImportError:
        print("splines not installed: skipped")
    try:
        import quaternion

        qa = quaternion.as_quat_array(q)
        rows.append(
            (
                "numpy-quaternion",
                "squad",
                median_ns(lambda: quaternion.squad(qa, times, t), n, repeat),
            )
        )
    except ImportError:
        print("numpy-quaternion not installed: skipped")
    return rows


def print_matrix(title: str, rows: list[tuple[str, str, float]]) -> None:
    ours = [r for r in rows if r[0] == "quatspline"]
    peers = [r for r in rows if r[0] != "quatspline"]
    print(f"\n## {title}\n")
    head = " | ".join(f"vs {lib} {m}" for lib, m, _ in peers)
    print(f"| method | ns/sample | {head} |")
    print("|---|---:|" + "---:|" * len(peers))
    for _, m, ns in ours:
        ratios = " | ".join(f"{p / ns:.1f}×" for _, _, p in peers)
        print(f"| {m} | {ns:.1f} | {ratios} |")
    for lib, m, ns in peers:
        print(f"| {lib} {m} | {ns:.1f} |" + " |" * len(peers))


def sclerp_pairs(n: int, repeat: int) -> list[tuple[str, str, float]]:
    """Screw interpolation of pose pairs against pytransform3d."""
    a = qs.dq_from_pose(random_quats(n, 5), np.random.default_rng(6).normal(size=(n, 3)))
    b = qs.dq_from_pose(random_quats(n, 7), np.random.default_rng(8).normal(size=(n, 3)))
    t = np.random.default_rng(9).uniform(0, 1, n)
    rows = [("quatspline", "sclerp (pairs)", median_ns(lambda: qs.sclerp(a, b, t), n, repeat))]
    try:
        import pytransform3d.trajectories as ptr

        rows.append(
            (
                "pytransform3d",
                "dual_quaternions_sclerp (batch)",
                median_ns(lambda: ptr.dual_quaternions_sclerp(a, b, t), n, repeat),
            )
        )
    except ImportError:
        print("pytransform3d not installed: skipped")
    return rows


def scaling(repeat: int) -> None:
    """ns/sample of C3Spline evaluation over sample counts, key counts and thread counts."""
    print("\n## Scaling: C3Spline evaluation, ns/sample (median)\n")
    print("| keys | samples | 1 thread | 2 threads |")
    print("|---:|---:|---:|---:|")
    cases = [(1000, m) for m in (10**3, 10**4, 10**5, 10**6, 10**7)]
    cases += [(k, 10**6) for k in (10, 100, 10**4, 10**5, 10**6)]
    for keys, m in cases:
        q = random_quats(keys, 11) if keys > 1000 else random_walk(keys, 11)
        s = qs.C3Spline(q)
        t = np.linspace(0.0, keys - 1.0, m)
        row = []
        for threads in (1, 2):
            qs.set_num_threads(threads)
            r = max(1, repeat if m <= 10**6 else 3)
            row.append(median_ns(lambda s=s, t=t: s(t), m, r))
        qs.set_num_threads(0)
        print(f"| {keys:,} | {m:,} | {row[0]:.1f} | {row[1]:.1f} |")


def construction(repeat: int) -> None:
    q = random_quats(1_000_000, 12)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        qs.C3Spline(q)
        times.append(time.perf_counter() - t0)
    print(f"\nConstruction of a 1,000,000-key C3Spline: {statistics.median(times):.3f} s (median)")
    # the natural spline's global solve (Newton, linear in the keys; target ≤ 2 s)
    for n in (100_000, 1_000_000):
        qn = q[:n]
        times = []
        for _ in range(max(1, min(repeat, 3))):
            t0 = time.perf_counter()
            qs.NaturalSpline(qn)
            times.append(time.perf_counter() - t0)
        print(f"Construction of a {n:,}-key NaturalSpline (random keys): {min(times):.3f} s (best)")


def memory() -> None:
    """Peak resident memory of evaluating 10,000,000 samples, in a fresh process."""
    import subprocess
    import sys

    # VmHWM, not ru_maxrss: the latter keeps the parent's peak across fork/exec.
    code = (
        "import numpy as np, quatspline as qs\n"
        "def hwm():\n"
        "    lines = open('/proc/self/status').read().splitlines()\n"
        "    return next(int(x.split()[1]) for x in lines if x.startswith('VmHWM'))\n"
        "q = qs.normalize(np.random.default_rng(0).normal(size=(1000, 4)))\n"
        "s = qs.C3Spline(q); t = np.linspace(0, 999, 10_000_000)\n"
        "s(t[:10])\n"
        "base = hwm()\n"
        "out = s(t)\n"
        "print(base, hwm(), out.nbytes)\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    base, peak, nbytes = (int(v) for v in r.stdout.split())
    extra = (peak - base) * 1024 - nbytes
    print(
        f"Peak memory for 10,000,000 samples: +{(peak - base) / 1024:.0f} MB over the process "
        f"before the call; output {nbytes / 2**20:.0f} MB; overhead {extra / 2**20:.0f} MB"
    )


def print_table(title: str, rows: list[tuple[str, str, float]]) -> None:
    ours = rows[0][2]
    print(f"\n## {title}\n")
    print(f"| {'library':<18} | {'method':<38} | {'ns/sample':>10} | {'quatspline is':>14} |")
    print(f"|{'-' * 20}|{'-' * 40}|{'-' * 12}:|{'-' * 15}:|")
    for lib, method, ns in rows:
        ratio = "—" if lib == "quatspline" else f"{ns / ours:.1f}× faster"
        print(f"| {lib:<18} | {method:<38} | {ns:>10.1f} | {ratio:>14} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000, help="samples / pairs")
    ap.add_argument("--repeat", type=int, default=5, help="runs per measurement (best of)")
    ap.add_argument("--quick", action="store_true", help="skip scaling, construction, memory")
    args = ap.parse_args()
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.python_implementation()}"
        f" {platform.python_version()}, numpy {np.__version__}, quatspline {qs.__version__}"
    )
    print(f"CPU: {engine_bench.cpu_model()}; kernels: {qs.simd_status()[1]}")
    print_table(f"{args.n:,} independent slerp pairs", slerp_pairs(args.n, args.repeat))
    print_table(f"{args.n:,} screw interpolations (pose pairs)", sclerp_pairs(args.n, args.repeat))
    print_matrix(
        f"1,000 keys, {args.n:,} sorted samples (ratios: how many times faster quatspline is)",
        spline_methods(args.n, 1000, args.repeat),
    )
    engine_bench.engine(args.n, args.repeat)
    if not args.quick:
        scaling(args.repeat)
        construction(args.repeat)
        memory()


if __name__ == "__main__":
    main()
