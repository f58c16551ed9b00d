"""MinimumEnergySpline construction time per key: the discrete form (default, resolution 4)
and the exact Riemannian cubic (``mode="exact"``), on keys of a smooth random motion at
uneven times.

    python benchmarks/min_energy.py            # 100, 1000, 4000, 10000 keys (exact);
                                               # the discrete form up to --discrete-max keys
    python benchmarks/min_energy.py --repeat 3 --discrete-max 1000

Prints µs per key (best of --repeat runs), Newton / descent iterations, and the CPU. Times on
a shared machine are inflated by its load (printed with each row).
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
import quatspline as qs


def cpu_name() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def random_keys(n: int, seed: int = 1000):
    """Keys of a smooth random motion (three sinusoids per axis, 0.2–1 rad/s) at uneven times
    0.5–1.5 apart."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, n))
    f, ph, amp = (
        rng.uniform(0.2, 1.0, (3, 3)),
        rng.uniform(0, 6.3, (3, 3)),
        rng.uniform(0.3, 1, (3, 3)),
    )
    rv = np.sum(amp * np.sin(f * t[:, None, None] + ph), axis=2)
    return qs.from_rotvec(rv), t


def best_time(q, t, mode: str, repeat: int):
    best, s = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        s = qs.MinimumEnergySpline(q, t, mode=mode)
        best = min(best, time.perf_counter() - t0)
    return best, s


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100, 1000, 4000, 10000])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--discrete-max", type=int, default=1000)
    a = ap.parse_args()
    print(f"CPU: {cpu_name()} ({os.cpu_count()} logical cores)\n")
    print("| keys | mode | µs/key | iterations | energy / natural | load |")
    print("|---:|---|---:|---:|---:|---:|")
    for n in a.sizes:
        q, t = random_keys(n)
        for mode in ("exact", "discrete"):
            if mode == "discrete" and n > a.discrete_max:
                continue
            try:
                secs, s = best_time(q, t, mode, a.repeat)
            except RuntimeError as e:
                print(f"| {n} | {mode} | failed: {e} | | | |")
                continue
            load = os.getloadavg()[0]
            print(
                f"| {n} | {mode} | {secs / n * 1e6:.0f} | {s.iterations} | "
                f"{s.energy / s.natural_energy:.6f} | {load:.1f} |"
            )


if __name__ == "__main__":
    main()
