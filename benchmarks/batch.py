"""Scaling of ``quatspline batch`` on Dask: 1 and 2 workers against a plain loop.

Generates recordings from the bundled ones (random rotations, random time warps, 10⁴–10⁵
samples by default), then times the same operation over all files three ways, each best of
``--repeat`` runs with ``force=True`` (every file redone):

- a plain Python loop over :func:`quatspline.batch.run_one` (no Dask), then the same summary
  files,
- Dask ``LocalCluster`` with 1 worker process,
- Dask ``LocalCluster`` with 2 worker processes.

The clusters are started before the clock starts (as a user's cluster would be running).
Prints a Markdown table, the per-file overhead of the Dask path and an estimate for a
64-worker cluster with 100,000 files.

    python benchmarks/batch.py --files 100 --min-samples 10000 --max-samples 100000
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import quatspline as qs
import quatspline.io as qio
from _common import cpu_model
from dask.distributed import Client
from quatspline import batch

DATA = Path(__file__).resolve().parent.parent / "data"
SOURCES = [
    DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt",
    DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv",
    DATA / "repoimu" / "repoIMU_first30s.csv",
]


def generate(root: Path, files: int, lo: int, hi: int, seed: int = 1) -> list[Path]:
    """Recordings of lo…hi samples: a natural spline through a bundled recording, sampled on a
    randomly warped clock, rotated by a random rotation, written as TUM files (CSV when the
    source has no positions)."""
    rng = np.random.default_rng(seed)
    bases = []
    for src in SOURCES:
        tr = qio.read(src)
        t = tr.times - tr.times[0]
        s = qs.spline("natural", tr.quats, t)
        bases.append((s, t, tr.positions))
    root.mkdir(parents=True, exist_ok=True)
    paths = []
    for i in range(files):
        s, t, pos = bases[i % len(bases)]
        n = int(rng.integers(lo, hi + 1))
        u = np.linspace(0.0, 1.0, n)
        k = int(rng.integers(1, 5))
        a = rng.uniform(-0.8, 0.8)
        warp = u + a * np.sin(2 * np.pi * k * u) / (2 * np.pi * k)  # monotone: |a| < 1
        tau = t[-1] * np.clip(warp, 0.0, 1.0)
        q = qs.multiply(qs.from_rotvec(rng.normal(size=3)), s(tau))
        p = None
        if pos is not None:
            p = np.column_stack([np.interp(tau, t, pos[:, j]) for j in range(3)])
        duration = t[-1] * rng.uniform(0.5, 2.0)
        path = root / (f"rec{i:04d}.txt" if p is not None else f"rec{i:04d}.csv")
        qio.write(path, qio.Trajectory(1000.0 + u * duration, q, p))
        paths.append(path)
    return paths


def best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=100)
    ap.add_argument("--min-samples", type=int, default=10_000)
    ap.add_argument("--max-samples", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--operation", default="sample", choices=("sample", "compare"))
    args = ap.parse_args()
    options = (
        {"method": "natural", "rate": 100.0}
        if args.operation == "sample"
        else {"methods": ["slerp", "natural", "c3"], "holdout": 4}
    )
    with tempfile.TemporaryDirectory() as d:
        root = Path(d)
        t0 = time.perf_counter()
        inputs = generate(root / "in", args.files, args.min_samples, args.max_samples)
        gen = time.perf_counter() - t0
        samples = sum(len(qio.read(p)) for p in inputs[:10]) / min(10, len(inputs))
        tasks = batch.plan(args.operation, inputs, root / "out", options)

        def loop():
            # the same work as batch.run without Dask: every file, then the summary files
            rows = []
            for task in tasks:
                row = batch.run_one(args.operation, task, options, force=True)
                assert row["status"] == "ok", row["error"]
                rows.append(row)
            table = pd.DataFrame(rows).sort_values("file").reset_index(drop=True)
            batch.summarize(table, root / "out", args.operation)

        t_loop = best(loop, args.repeat)
        results = {}
        for n in (1, 2):
            with batch.local_cluster(n) as cluster, Client(cluster) as c:

                def dask_run(c=c):
                    table = batch.run(
                        args.operation, [root / "in"], root / "out", client=c, force=True,
                        progress=False, **options,
                    )  # fmt: skip
                    assert (table["status"] == "ok").all()

                results[n] = best(dask_run, args.repeat)
    per_file = t_loop / args.files
    overhead = results[1] / t_loop - 1
    speedup = results[1] / results[2]
    est = 100_000 * per_file * (1 + max(overhead, 0)) / 64
    print(f"CPU: {cpu_model()} ({platform.machine()}), quatspline {qs.__version__}")
    print(
        f"{args.files} generated recordings of ~{samples:,.0f} samples (mean of the first 10), "
        f"operation `{args.operation}` {options}; generation took {gen:.1f} s; "
        f"best of {args.repeat}."
    )
    print()
    print("| path | wall time (s) | per file (ms) |")
    print("|---|---:|---:|")
    print(f"| plain loop (no Dask) | {t_loop:.2f} | {1e3 * per_file:.1f} |")
    for n, t in results.items():
        print(f"| Dask LocalCluster, {n} worker{'s' if n > 1 else ''} | {t:.2f} | "
              f"{1e3 * t / args.files:.1f} |")  # fmt: skip
    print()
    print(f"speed-up 1 → 2 workers: {speedup:.2f}× (target ≥ 1.7×)")
    print(f"Dask overhead per file (1 worker vs plain loop): {100 * overhead:+.1f}% (target ≤ 10%)")
    print(
        f"estimate, 64 workers, 100,000 such files: {est / 60:.1f} min "
        f"(100,000 × {1e3 * per_file:.0f} ms × {1 + max(overhead, 0):.2f} / 64, if input reading "
        "scales with the workers)"
    )


if __name__ == "__main__":
    main()
