"""The evaluation engine's rows of ``make bench``: which kernel ran, 1 vs 2
threads, sorted vs unsorted times, derivative orders and angular rates, per-call cost of small
calls, AVX-512 against AVX2 (both forced), the batch kernels against the forced scalar kernels
and the per-sample reference path — with scipy's ``RotationSpline`` timed in the same run for
the ratios. ``python benchmarks/engine_bench.py --isa [--n N] [--repeat R]`` prints the
AVX-512 / AVX2 table alone.

Every figure is the best of ``repeat`` runs (the machine is shared; the minimum is the least
disturbed run), in ns per sample unless stated; the figures of a ratio (sorted and unsorted;
ω, α and jerk) take turns run by run.
"""

from __future__ import annotations

import subprocess
import time
from collections.abc import Callable

import numpy as np
import quatspline as qs
from _common import cpu_model


def best_ns(fn: Callable[[], object], n: int, repeat: int) -> float:
    """Best (minimum) wall time of ``repeat`` runs after one warm-up, per item, in ns."""
    fn()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter_ns()
        fn()
        best = min(best, time.perf_counter_ns() - t0)
    return best / n


def best_ns_interleaved(fns: list[Callable[[], object]], n: int, repeat: int) -> list[float]:
    """Best of ``repeat`` runs per function, the functions taking turns (f₀, f₁, …, f₀, …), so
    that a burst of load on the shared machine spoils one run of each rather than every run
    of one: the figures a ratio compares come from the same stretch of time."""
    for fn in fns:
        fn()
    best = [float("inf")] * len(fns)
    for _ in range(repeat):
        for i, fn in enumerate(fns):
            t0 = time.perf_counter_ns()
            fn()
            best[i] = min(best[i], time.perf_counter_ns() - t0)
    return [b / n for b in best]


def _keys(n: int, seed: int, step: float = 0.3) -> np.ndarray:
    from bench import random_walk

    return random_walk(n, seed, step)


def _methods(keys: int):
    q = _keys(keys, 4)
    times = np.arange(keys, dtype=float)
    return [
        ("PiecewiseSlerp", qs.PiecewiseSlerp(q, times)),
        ("CumulativeBSpline", qs.CumulativeBSpline(q)),
        ("BetaSpline", qs.BetaSpline(q, beta1=1.5, beta2=0.5)),
        ("C3Spline (knot)", qs.C3Spline(q, times)),
        ("NaturalSpline", qs.NaturalSpline(q, times)),
        ("Squad", qs.Squad(q, times)),
        ("CatmullRom", qs.CatmullRom(q, times)),
        ("KochanekBartels (T=0.3)", qs.KochanekBartels(q, times, tension=0.3)),
        ("CumulativeBezier (8 points)", qs.CumulativeBezier(q[:8], domain=(0.0, keys - 1.0))),
        ("SphericalBezier (8 points)", qs.SphericalBezier(q[:8], domain=(0.0, keys - 1.0))),
        # control points a few degrees apart (half-angles ≤ 0.15), as dense keys are: the
        # shortest series tier
        (
            "SphericalBezier (8 dense points)",
            qs.SphericalBezier(_keys(8, 4, 0.15), domain=(0.0, keys - 1.0)),
        ),
    ]


def _scipy(keys: int, t: np.ndarray, n: int, repeat: int) -> tuple[float, float]:
    try:
        from scipy.spatial.transform import Rotation, RotationSpline
    except ImportError:
        return float("nan"), float("nan")
    q = _keys(keys, 4)
    rs = RotationSpline(np.arange(keys, dtype=float), Rotation.from_quat(qs.as_xyzw(q)))
    return best_ns(lambda: rs(t), n, repeat), best_ns(lambda: rs(t, 1), n, repeat)


def engine(n: int, repeat: int, keys: int = 1000) -> None:
    """Prints the engine tables."""
    mode, kernel = qs.simd_status()
    print(f"\n## Evaluation engine: {keys:,} keys, {n:,} samples\n")
    print(f"CPU: {cpu_model()}")
    print(f"engine mode {mode!r}, batch kernels run on: {kernel}; best of {repeat} runs\n")
    rng = np.random.default_rng(0)
    methods = _methods(keys)
    t_all = {}
    for name, s in methods:
        a, b = s.domain
        ts = np.linspace(a, b, n)
        t_all[name] = (ts, rng.permutation(ts))
    sc, scw = _scipy(keys, t_all["PiecewiseSlerp"][0], n, repeat)

    print(
        "| method | kernel | sorted, 1 thread | sorted, 2 threads | unsorted, 2 threads "
        "| unsorted / sorted | jets path, 2 threads | vs scipy RotationSpline (2 threads) |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name, s in methods:
        ts, tu = t_all[name]
        qs.set_num_threads(1)
        one = best_ns(lambda s=s, ts=ts: s(ts), n, repeat)
        qs.set_num_threads(0)
        two, uns = best_ns_interleaved(
            [lambda s=s, ts=ts: s(ts), lambda s=s, tu=tu: s(tu)], n, repeat
        )
        qs.set_simd("reference")
        ref = best_ns(lambda s=s, ts=ts: s(ts), n, max(1, repeat // 2))
        qs.set_simd(mode)
        print(
            f"| {name} | {s._core.kernel} | {one:.1f} | {two:.1f} | {uns:.1f} | "
            f"{uns / two:.2f}× | {ref:.1f} | {sc / two:.0f}× |"
        )
    print(f"| scipy RotationSpline | — | | {sc:.1f} | | | | 1× |")

    print(f"\n### Derivatives and angular rates (2 threads, sorted; scipy ω {scw:.1f} ns)\n")
    print(
        "| method | q | q, q' | …q'' | …q''' | ω world | ω body | α world | jerk world "
        "| α / ω | jerk / ω | ω vs scipy RotationSpline(t, 1) |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, s in methods:
        if name not in ("CumulativeBSpline", "C3Spline (knot)", "NaturalSpline", "BetaSpline"):
            continue
        ts = t_all[name][0]
        cells = [best_ns(lambda s=s, k=k, ts=ts: s.derivatives(ts, k), n, repeat) for k in range(4)]
        w, wb, al, jk = best_ns_interleaved(
            [
                lambda s=s, ts=ts: s.angular_velocity(ts),
                lambda s=s, ts=ts: s.angular_velocity(ts, frame="body"),
                lambda s=s, ts=ts: s.angular_acceleration(ts),
                lambda s=s, ts=ts: s.jerk(ts),
            ],
            n,
            repeat,
        )
        row = " | ".join(f"{v:.1f}" for v in (*cells, w, wb, al, jk))
        print(f"| {name} | {row} | {al / w:.2f} | {jk / w:.2f} | {scw / min(w, wb):.0f}× |")

    print("\n### Small calls: µs per call (1 thread)\n")
    print("| method | s(float) | 1 sample (array) | 10 samples | 100 samples |")
    print("|---|---:|---:|---:|---:|")
    qs.set_num_threads(1)
    for name, s in methods:
        if name not in ("CumulativeBSpline", "C3Spline (knot)", "PiecewiseSlerp", "Squad"):
            continue
        a, b = s.domain
        x = float(0.37 * a + 0.63 * b)
        cells = [best_ns(lambda s=s, x=x: s(x), 1, repeat * 200) * 1e-3]
        for m in (1, 10, 100):
            tm = np.linspace(a, b, m)
            cells.append(best_ns(lambda s=s, tm=tm: s(tm), 1, repeat * 200) * 1e-3)
        print(f"| {name} | " + " | ".join(f"{v:.2f}" for v in cells) + " |")
    qs.set_num_threads(0)

    print(f"\n### The batch kernels ({kernel}) against the forced scalar kernels (2 threads)\n")
    print("| method | auto | QUATSPLINE_SIMD=scalar | scalar / auto |")
    print("|---|---:|---:|---:|")
    for name, s in methods:
        if s._core.kernel == "jets":
            continue
        ts = t_all[name][0]
        auto = best_ns(lambda s=s, ts=ts: s(ts), n, repeat)
        qs.set_simd("scalar")
        scal = best_ns(lambda s=s, ts=ts: s(ts), n, repeat)
        qs.set_simd(mode)
        print(f"| {name} | {auto:.1f} | {scal:.1f} | {scal / auto:.2f}× |")

    isa_ratios(n, repeat, methods, t_all)
    pairs(n, repeat)


CUMULATIVE = ("CumulativeBSpline", "BetaSpline", "C3Spline (knot)", "CumulativeBezier (8 points)")


def isa_ratios(n: int, repeat: int, methods=None, t_all=None, keys: int = 1000) -> list[tuple]:
    """AVX-512 (8 lanes) against AVX2 (4 lanes), the two forced by ``set_simd`` and taking turns
    run by run (2 threads, sorted times): values of every kernel, ω (world) of the cumulative
    family and the natural spline, and the pairs kernels. Returns the rows (name, quantity,
    avx2 ns, avx512 ns, ratio); prints nothing but a note where the CPU lacks AVX-512."""
    mode = qs.simd_status()[0]
    have = []
    for isa in ("avx2", "avx512"):
        qs.set_simd(isa)
        have.append(qs.simd_status()[1] == isa)
    qs.set_simd(mode)
    print("\n### AVX-512 against AVX2 (2 threads, sorted; the two forced, taking turns)\n")
    if not all(have):
        print("(this CPU lacks AVX-512 F/DQ or AVX2: no comparison)")
        return []
    if methods is None:
        methods = _methods(keys)
    if t_all is None:
        t_all = {name: (np.linspace(*s.domain, n), None) for name, s in methods}

    def forced(isa, fn):
        def run():
            qs.set_simd(isa)
            fn()

        return run

    def compare(fn):
        return best_ns_interleaved([forced("avx2", fn), forced("avx512", fn)], n, repeat)

    rows = []
    for name, s in methods:
        if s._core.kernel == "jets":
            continue
        ts = t_all[name][0]
        rows.append((name, "q", *compare(lambda s=s, ts=ts: s(ts))))
        if name in CUMULATIVE or name == "NaturalSpline":
            rows.append((name, "ω world", *compare(lambda s=s, ts=ts: s.angular_velocity(ts))))
            # the same values into a preallocated array: the kernels without the fresh output
            # array's page faults, which cost the two instruction sets alike
            buf = np.empty((len(ts), 4))
            rows.append((name, "q (out=)", *compare(lambda s=s, ts=ts, b=buf: s(ts, out=b))))
    from bench import random_quats

    a, b = random_quats(n, 1), random_quats(n, 2)
    t = np.random.default_rng(3).uniform(0, 1, n)
    rows.append(("slerp pairs", "q", *compare(lambda: qs.slerp(a, b, t))))
    rng = np.random.default_rng(6)
    da = qs.dq_from_pose(random_quats(n, 5), rng.normal(size=(n, 3)))
    db = qs.dq_from_pose(random_quats(n, 7), rng.normal(size=(n, 3)))
    rows.append(("sclerp pairs", "dq", *compare(lambda: qs.sclerp(da, db, t))))
    qs.set_simd(mode)
    print("| method | quantity | avx2 ns | avx512 ns | avx2 / avx512 |")
    print("|---|---|---:|---:|---:|")
    out = []
    for name, what, x2, x5 in rows:
        print(f"| {name} | {what} | {x2:.2f} | {x5:.2f} | {x2 / x5:.2f}× |")
        out.append((name, what, x2, x5, x2 / x5))
    floor = best_ns(lambda: np.ones((n, 4)), n, repeat)
    print(
        f"\nFloor shared by both: allocating and writing a fresh (n, 4) float64 output "
        f"(np.ones, 1 thread) costs {floor:.2f} ns/sample; a call's ratio cannot exceed the "
        "kernels' own ratio once that part is added to both."
    )
    return out


def pairs(n: int, repeat: int) -> None:
    """Independent slerp / sclerp pairs through the SIMD pairs kernels."""
    from bench import random_quats

    mode = qs.simd_status()[0]
    a, b = random_quats(n, 1), random_quats(n, 2)
    b = qs.canonicalize(b, reference=a)
    t = np.random.default_rng(3).uniform(0, 1, n)
    rng = np.random.default_rng(6)
    da = qs.dq_from_pose(random_quats(n, 5), rng.normal(size=(n, 3)))
    db = qs.dq_from_pose(random_quats(n, 7), rng.normal(size=(n, 3)))
    print("\n### Independent pairs: ns per pair\n")
    print("| operation | auto, 1 thread | auto, 2 threads | scalar kernel | reference (per row) |")
    print("|---|---:|---:|---:|---:|")
    for name, fn in (
        ("slerp", lambda: qs.slerp(a, b, t)),
        ("sclerp", lambda: qs.sclerp(da, db, t)),
    ):
        qs.set_num_threads(1)
        one = best_ns(fn, n, repeat)
        qs.set_num_threads(0)
        two = best_ns(fn, n, repeat)
        cells = []
        for m in ("scalar", "reference"):
            qs.set_simd(m)
            cells.append(best_ns(fn, n, repeat))
        qs.set_simd(mode)
        print(f"| {name} | {one:.1f} | {two:.1f} | {cells[0]:.1f} | {cells[1]:.1f} |")


def lscpu() -> str:
    """``lscpu``'s model line, for the README."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return ""
    return next((ln for ln in out.splitlines() if ln.startswith("Model name")), "")


if __name__ == "__main__":
    import argparse

    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--isa", action="store_true", help="only the AVX-512 / AVX2 table")
    p.add_argument("--n", type=int, default=1_000_000, help="samples per call")
    p.add_argument("--repeat", type=int, default=5, help="runs per figure (the best is kept)")
    args = p.parse_args()
    print(f"CPU: {cpu_model()}")
    if args.isa:
        isa_ratios(args.n, args.repeat)
    else:
        engine(args.n, args.repeat)
