"""Evaluation cost at the corners: every registry method at its documented limits, and
arc-length splines of every family (the tabulated inverse of the arc-length map).

Keys: a random walk with steps of about 0.3 rad (``bench.random_walk``, seed 4) at times 0, 1,
…; ``--keys`` keys for the spline methods. Each row: ns per sample of ``s(t)`` (values) and of
``s.angular_velocity(t)`` (ω) at ``--n`` sorted times over the domain, one thread and both,
the best of ``--repeat`` runs (the machine may be shared: the minimum is the least disturbed
run). The CPU is named from /proc/cpuinfo.

The spherical Bézier curve costs n(n − 1)/2 slerps per sample for n control points (de
Casteljau): its rows also give the cost per slerp (the floor of the algorithm is that count
times the vector slerp's cost), and ``--only bezier`` sweeps the number of points to find the
most that stay within 1 µs per sample.

Run: ``python benchmarks/corners.py [--n 100000] [--keys 1000] [--repeat 5]
[--only arc|corners|bezier]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import quatspline as qs
from _common import cpu_model
from bench import random_walk
from engine_bench import best_ns, best_ns_interleaved


def corners(keys: int) -> list[tuple[str, qs.Spline]]:
    """Every registry method at its limits (most points, highest order, closed ends, holds)."""
    q = random_walk(keys, 4, 0.3)
    t = np.arange(keys, dtype=float)
    held = q.copy()
    held[1::7] = held[0::7][: len(held[1::7])]  # a hold every 7 keys
    dom = (0.0, keys - 1.0)
    rows = [
        ("slerp", qs.spline("slerp", q, t)),
        ("nlerp", qs.spline("nlerp", q, t)),
        ("lin_euler", qs.spline("lin_euler", q, t)),
        ("lin_mat", qs.spline("lin_mat", q, t)),
        ("squad (closed)", qs.spline("squad", q, t, ends="closed")),
        ("squad (rest, holds)", qs.spline("squad", held, t, ends="rest", holds=True)),
        ("catmull_rom (closed, holds)", qs.spline("catmull_rom", held, t, ends="closed")),
        (
            "kochanek_bartels (T, C, B)",
            qs.spline("kochanek_bartels", q, t, tension=0.3, continuity=0.2, bias=-0.2),
        ),
        ("natural (closed)", qs.spline("natural", q, t, ends="closed")),
        ("natural (holds)", qs.spline("natural", held, t)),
        ("c3 (closed)", qs.spline("c3", q, t, ends="closed")),
        ("c3 (holds)", qs.spline("c3", held, t, holds=True)),
        ("hermite (bessel rates)", qs.spline("hermite", q, t)),
        ("bspline (order 12)", qs.CumulativeBSpline(q, order=12)),
        ("bspline (closed)", qs.CumulativeBSpline(q, ends="closed")),
        ("bspline (rest, holds)", qs.CumulativeBSpline(held, ends="rest", holds=True)),
        ("beta", qs.BetaSpline(q, beta1=1.5, beta2=0.5)),
    ]
    for n in (64, 256, 1024, 4096):
        c = random_walk(n, 4, 0.3)
        rows.append((f"cumulative_bezier ({n} points)", qs.CumulativeBezier(c, domain=dom)))
    for n in (16, 17, 33, 65):
        rows.append((f"bezier ({n} points)", qs.SphericalBezier(q[:n], domain=dom)))
    return rows


def bernstein_window(degree: int) -> float:
    """Mean number of Bernstein terms of degree ``degree`` at least 2⁻⁶⁰ times the row's
    largest (the cumulative Bézier curve's window: its factors per sample) over u ∈ [0, 1]."""
    i = np.arange(degree + 1)
    ln_c = np.array(
        [math.lgamma(degree + 1) - math.lgamma(k + 1) - math.lgamma(degree - k + 1) for k in i]
    )
    counts = []
    for u in np.linspace(0.0, 1.0, 2001)[1:-1]:
        ln_b = ln_c + i * math.log(u) + (degree - i) * math.log1p(-u)
        counts.append(np.count_nonzero(ln_b >= ln_b.max() - 60 * math.log(2)))
    return float(np.mean(counts))


def arc_families(keys: int) -> list[tuple[str, qs.Spline]]:
    """Arc-length splines of every family."""
    q = random_walk(keys, 4, 0.3)
    t = np.arange(keys, dtype=float)
    inner = [
        ("slerp", qs.PiecewiseSlerp(q, t)),
        ("squad", qs.Squad(q, t)),
        ("catmull_rom", qs.CatmullRom(q, t)),
        ("natural", qs.NaturalSpline(q, t)),
        ("c3", qs.C3Spline(q, t)),
        ("bspline", qs.CumulativeBSpline(q)),
        ("beta", qs.BetaSpline(q, beta1=1.5, beta2=0.5)),
        ("bezier (8 points)", qs.SphericalBezier(q[:8], domain=(0.0, keys - 1.0))),
    ]
    return [(name, s, qs.arc_length(s)) for name, s in inner]


def build_us(s: qs.Spline, repeat: int) -> float:
    """Best construction time of ``qs.arc_length(s)``, µs per segment of ``s``."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter_ns()
        qs.arc_length(s)
        best = min(best, time.perf_counter_ns() - t0)
    return best / 1e3 / (len(s.joints) - 1)


def arc_table(rows, n: int, repeat: int) -> None:
    """Arc-length splines against their floor, the original spline's own evaluation at the
    same number of samples (the batch path maps every time through the tabulated inverse, then
    evaluates the original's kernel on the mapped times: the difference is the inverse); and
    the per-sample path the arc-length spline took before (forced ``reference`` kernels), and
    the construction of the arc-length spline, µs per segment."""
    mode = qs.simd_status()[0]
    print(
        "| spline | values | original's values | ω | original's ω | values, per-sample path "
        "| values, 2 threads | construction (µs/segment) |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, s, r in rows:
        ts = np.linspace(*s.domain, n)
        build = build_us(s, repeat)
        qs.set_num_threads(1)
        val, orig, om, orig_om = best_ns_interleaved(
            [
                lambda r=r, ts=ts: r(ts),
                lambda s=s, ts=ts: s(ts),
                lambda r=r, ts=ts: r.angular_velocity(ts),
                lambda s=s, ts=ts: s.angular_velocity(ts),
            ],
            n,
            repeat,
        )
        qs.set_simd("reference")
        few = ts[::20]  # the per-sample path is slow: every 20th time
        per_sample = best_ns(lambda r=r, few=few: r(few), len(few), min(repeat, 3))
        qs.set_simd(mode)
        qs.set_num_threads(0)
        two = best_ns(lambda r=r, ts=ts: r(ts), n, repeat)
        print(
            f"| arc_length({name}) | {val:,.1f} | {orig:,.1f} | {om:,.1f} | {orig_om:,.1f} "
            f"| {per_sample:,.1f} | {two:,.1f} | {build:,.1f} |",
            flush=True,
        )


def table(rows: list[tuple[str, qs.Spline]], n: int, repeat: int) -> None:
    print("| spline | values, 1 thread | values, 2 threads | ω, 1 thread | ω, 2 threads |")
    print("|---|---:|---:|---:|---:|")
    floors = []
    for name, s in rows:
        ts = np.linspace(*s.domain, n)
        cells = []
        for fn in (lambda s=s, ts=ts: s(ts), lambda s=s, ts=ts: s.angular_velocity(ts)):
            for threads in (1, 0):
                qs.set_num_threads(threads)
                cells.append(best_ns(fn, n, repeat))
        qs.set_num_threads(0)
        print(f"| {name} | " + " | ".join(f"{c:,.1f}" for c in cells) + " |", flush=True)
        if name.startswith("bezier"):
            # the floor of de Casteljau: n(n − 1)/2 slerps per sample for n points
            points = int(name.split("(")[1].split()[0])
            slerps = points * (points - 1) // 2
            floors.append(f"{name}: {slerps:,} slerps per sample, {cells[0] / slerps:.2f} ns each")
        elif name.startswith("cumulative_bezier"):
            w = bernstein_window(int(name.split("(")[1].split()[0]) - 1)
            floors.append(
                f"{name}: {w:,.1f} factors per sample in the Bernstein window (mean over u), "
                f"{cells[0] / w:.1f} ns each (values), {cells[2] / w:.1f} ns (ω)"
            )
    for line in floors:
        print(f"- {line}")


def bezier_sweep(n: int, repeat: int) -> None:
    """Values of the spherical Bézier curve by number of control points (one thread): ns per
    sample and per slerp, and the most points measured within 1 µs per sample."""
    q = random_walk(65, 4, 0.3)
    print("| points | slerps per sample | ns per sample | ns per slerp |")
    print("|---:|---:|---:|---:|")
    qs.set_num_threads(1)
    within = 0
    for points in (8, 16, 24, 32, 36, 40, 44, 48, 56, 65):
        s = qs.SphericalBezier(q[:points], domain=(0.0, 1.0))
        ts = np.linspace(0.0, 1.0, n)
        ns = best_ns(lambda s=s, ts=ts: s(ts), n, repeat)
        slerps = points * (points - 1) // 2
        if ns <= 1000.0:
            within = points
        print(f"| {points} | {slerps:,} | {ns:,.1f} | {ns / slerps:.2f} |", flush=True)
    qs.set_num_threads(0)
    print(f"\nWithin 1 µs per sample: up to {within} points (of those measured).")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000, help="samples per row")
    ap.add_argument("--keys", type=int, default=1000, help="keys of the spline methods")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--only", choices=("arc", "corners", "bezier"), default=None)
    a = ap.parse_args()
    print(f"CPU: {cpu_model()}; ns per sample, best of {a.repeat} runs, {a.n:,} sorted samples\n")
    if a.only in (None, "arc"):
        print(f"## Arc-length splines ({a.keys:,} keys)\n")
        arc_table(arc_families(a.keys), a.n, a.repeat)
    if a.only in (None, "corners"):
        print(f"\n## Registry methods at their limits ({a.keys:,} keys)\n")
        table(corners(a.keys), a.n, a.repeat)
    if a.only in (None, "bezier"):
        print("\n## Spherical Bézier: points within 1 µs per sample (values, 1 thread)\n")
        bezier_sweep(a.n, a.repeat)


if __name__ == "__main__":
    main()
