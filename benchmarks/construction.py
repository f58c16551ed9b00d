"""Construction cost per key of the interpolating and B-spline families.

Keys: a random walk of small rotations (steps of about 0.05 rad, seed 0) at times 0, 1, …,
N − 1 (default N = 10⁶). For each method, in a fresh process: the best of ``--repeat``
constructions (wall time per key) and memory per key of the first construction, read from
/proc/self/status — *kept*, the resident set held by the live spline over the process before it
(keys and times already made), after a first evaluation (some tables are built on first use),
and *peak*, the high-water mark during construction over the same
base (VmHWM, reset through /proc/self/clear_refs). *fill* is the floor that memory sets: the
processor time numpy takes to allocate and fill as many bytes as the spline keeps
(``numpy.ones``, one thread, best of the same runs; numpy backs large arrays with huge pages),
per key. *CPU* is the construction's processor time (all
threads; wall time × threads on an idle machine, and what a loaded shared machine inflates
least). The CPU is named from /proc/cpuinfo.

``--save FILE`` stores each spline's orientations and angular velocities at 10⁴ times;
``--compare FILE`` checks them for bit-identity against a stored run (construction changes
must not change results).

Run: ``python benchmarks/construction.py [--n 1000000] [--save a.npz | --compare a.npz]``.
"""

from __future__ import annotations

import argparse
import gc
import json
import subprocess
import sys
import time

import numpy as np
import quatspline as qs
from _common import cpu_model

METHODS = {
    "PiecewiseSlerp": lambda q, t: qs.PiecewiseSlerp(q, t),
    "Squad": lambda q, t: qs.Squad(q, t),
    "CatmullRom": lambda q, t: qs.CatmullRom(q, t),
    "KochanekBartels": lambda q, t: qs.KochanekBartels(q, t),
    "CumulativeBSpline": lambda q, t: qs.CumulativeBSpline(q, dt=1.0),
    "NaturalSpline": lambda q, t: qs.NaturalSpline(q, t),
    "C3Spline": lambda q, t: qs.C3Spline(q, t),
}
# every registry method by name (its default parameters), for the memory column of the README
METHODS.update({m: (lambda q, t, m=m: qs.spline(m, q, t)) for m in qs.METHODS})


def status_kb(field: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    raise KeyError(field)


def reset_peak() -> None:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def keys(n: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    # a random walk of small rotations: rotation vectors summed step by step (smooth path)
    v = np.cumsum(rng.normal(scale=0.05 / np.sqrt(3), size=(n, 3)), axis=0)
    return qs.from_rotvec(v), np.arange(n, dtype=float)


def one(name: str, n: int, repeat: int, sample_to: str | None) -> dict:
    q, t = keys(n)
    make = METHODS[name]
    make(q[:16].copy(), t[:16].copy())  # warm up imports and the thread pool
    gc.collect()
    # memory first, on a heap that has not yet held a large spline (freed blocks of earlier
    # constructions would otherwise be reused and hide what the spline keeps)
    base = status_kb("VmRSS")
    reset_peak()
    s = make(q, t)
    a, b = s.domain
    s(np.linspace(a, b, 1000))  # tables some methods build on first evaluation count as kept
    peak = status_kb("VmHWM") - base
    kept = status_kb("VmRSS") - base
    if sample_to:
        a, b = s.domain
        ts = np.linspace(a, b, 10_000)
        np.savez(sample_to, q=s(ts), w=s.angular_velocity(ts))
    del s
    best = cpu = float("inf")
    for _ in range(repeat):
        gc.collect()
        t0, c0 = time.perf_counter(), time.process_time()
        s = make(q, t)
        best = min(best, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
        del s
    # the memory floor: writing as many fresh bytes as the spline keeps (page faults and
    # zeroing included), one thread, best of the same number of runs
    fill = float("inf")
    words = max(1, int(kept * 1024 / 8))
    for _ in range(repeat):
        gc.collect()
        c0 = time.process_time()
        buf = np.ones(words)
        fill = min(fill, time.process_time() - c0)
        del buf
    out = {
        "method": name,
        "fill_ns_per_key": fill / n * 1e9,
        "ns_per_key": best / n * 1e9,
        "cpu_ns_per_key": cpu / n * 1e9,
        "kept_bytes_per_key": kept * 1024 / n,
        "peak_bytes_per_key": peak * 1024 / n,
    }
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n", type=int, default=1_000_000)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument(
        "--methods",
        nargs="*",
        default=list(METHODS)[:7],
        help="names (default: the classes; registry names too)",
    )
    p.add_argument("--save")
    p.add_argument("--compare")
    p.add_argument("--one", help=argparse.SUPPRESS)
    p.add_argument("--sample-to", help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.one:
        print(json.dumps(one(a.one, a.n, a.repeat, a.sample_to)))
        return
    print(f"CPU: {cpu_model()}; N = {a.n} keys, best of {a.repeat}")
    print(
        f"{'method':<18} {'ns/key':>9} {'CPU ns/key':>11} {'kept B/key':>11} {'peak B/key':>11} "
        f"{'fill ns/key':>12}"
    )
    samples, failed = {}, []
    for name in a.methods:
        tmp = f"/tmp/construction_{name}.npz"
        cmd = [sys.executable, __file__, "--one", name, "--n", str(a.n), "--repeat", str(a.repeat)]
        if a.save or a.compare:
            cmd += ["--sample-to", tmp]
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode:  # a method that refuses this many keys says why
            print(f"{name:<18} refused: {(run.stderr.strip().splitlines() or ['?'])[-1][:150]}")
            continue
        r = json.loads(run.stdout)
        print(
            f"{name:<18} {r['ns_per_key']:>9.1f} {r['cpu_ns_per_key']:>11.1f} "
            f"{r['kept_bytes_per_key']:>11.0f} "
            f"{r['peak_bytes_per_key']:>11.0f} {r['fill_ns_per_key']:>12.1f}"
        )
        if a.save or a.compare:
            with np.load(tmp) as z:
                samples[name + "/q"], samples[name + "/w"] = z["q"], z["w"]
    if a.save:
        np.savez(a.save, **samples)
    if a.compare:
        with np.load(a.compare) as ref:
            for k, v in samples.items():
                if k in ref and not np.array_equal(ref[k], v):
                    failed.append(k)
        print("bit-identical samples" if not failed else f"CHANGED: {', '.join(failed)}")
        if failed:
            sys.exit(1)


if __name__ == "__main__":
    main()
