"""MinimumEnergySpline construction time per key: the discrete form (default, resolution 4)
and the exact Riemannian cubic (``mode="exact"``), on keys of a smooth random motion at
uneven times.

    python benchmarks/min_energy.py            # 100, 1000, 4000, 10000 keys (exact);
                                               # the discrete form up to --discrete-max keys
    python benchmarks/min_energy.py --repeat 3 --discrete-max 1000

Prints µs per key (best of --repeat runs), Newton / descent iterations, and the CPU. For the
discrete form also its Jacobian passes (the descent's dominant cost), the cost of one pass
(its time beyond the exact curve it starts from, per pass) and the floor of the method: the
exact start plus one pass. Times on a shared machine are inflated by its load (printed with
each row).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import quatspline as qs
from _common import cpu_model, load


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
    ap.add_argument("--discrete-max", type=int, default=4000)
    a = ap.parse_args()
    print(f"CPU: {cpu_model()}; load {load()}\n")
    print(
        "| keys | mode | µs/key | iterations | Jacobian passes | µs/key per pass | "
        "floor µs/key | energy / natural | load |"
    )
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for n in a.sizes:
        q, t = random_keys(n)
        exact = None
        for mode in ("exact", "discrete"):
            if mode == "discrete" and n > a.discrete_max:
                continue
            try:
                secs, s = best_time(q, t, mode, a.repeat)
            except RuntimeError as e:
                print(f"| {n} | {mode} | failed: {e} | | | | | | |")
                continue
            us = secs / n * 1e6
            passes = per_pass = floor = ""
            if mode == "exact":
                exact = us
            elif exact is not None and s.jacobian_passes:
                # The discrete form = its start (the exact curve, projected) + the descent,
                # whose cost is its Jacobian passes over every quadrature node. The floor of
                # this method: the start plus one pass (the gradient that certifies the
                # optimum), the descent's other costs (energies, banded solves) taken as free.
                passes = str(s.jacobian_passes)
                pp = max(us - exact, 0.0) / s.jacobian_passes
                per_pass, floor = f"{pp:.0f}", f"{exact + pp:.0f}"
            print(
                f"| {n} | {mode} | {us:.0f} | {s.iterations} | {passes} | {per_pass} | {floor} | "
                f"{s.energy / s.natural_energy:.6f} | {os.getloadavg()[0]:.1f} |"
            )


if __name__ == "__main__":
    main()
