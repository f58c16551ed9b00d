"""IMU simulation and strapdown integration: speed at 10⁶ samples, integration error by rate.

Speed: a PoseSpline through one key per second (random orientations and positions), sampled
at 200 Hz for N samples (default 10⁶). Timed, best of ``--repeat`` runs, wall clock:
``simulate`` exact, ``simulate`` with noise and a mounted, displaced sensor, ``integrate``
(orientation, velocity, position); beside them what they are built on — the spline's own
evaluation of orientation, body rate and world acceleration for all samples at once
(``simulate`` makes the same calls in cache-sized blocks) and the Rust attitude-only step
(``quatspline.integrate(..., method="cubic")``), which ``integrate`` runs once before adding
the velocity and position quadrature in numpy.

The machine these were measured on may be shared: the load average is printed before and
after; CPU seconds (this process, all threads) are less sensitive to it than wall clock.

Accuracy: noise-free samples of a smooth 60 s motion integrated back, for rates 25 … 800 Hz:
the largest attitude error (rad) and position error (m) over the minute, and the observed
order log2(e(h) / e(h/2)). Two motions: a PoseSpline through random smooth keys every second
(C³ orientation, C² natural-cubic positions, whose acceleration kinks at the keys limit the
position to second order) and an order-6 PoseBSpline (C⁴ everything: the scheme's own fourth
order shows).

    python benchmarks/imu.py                  # both tables
    python benchmarks/imu.py --samples 200000 # a quicker speed table
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np
import quatspline as qs
from quatspline.imu import ImuNoise, SensorModel, integrate, simulate


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "unknown"


def best(fn, repeat: int) -> tuple[float, float]:
    """(best wall-clock seconds, best CPU seconds of this process) over ``repeat`` runs."""
    wall = cpu = float("inf")
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu


def smooth(rng, t, amp, n=4, fmax=0.3):
    out = np.zeros((t.size, 3))
    for _ in range(n):
        f, ph = rng.uniform(0.02, fmax, 3), rng.uniform(0, 2 * np.pi, 3)
        out += rng.normal(0, amp, 3) * np.sin(2 * np.pi * f * t[:, None] + ph)
    return out


def speed(samples: int, repeat: int) -> dict:
    rate = 200.0
    duration = (samples - 1) / rate
    rng = np.random.default_rng(0)
    tk = np.arange(0.0, np.ceil(duration) + 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(rng.normal(0, 0.5, (tk.size, 3))), tk, rng.normal(0, 1.0, (tk.size, 3))
    )
    times = np.arange(samples) / rate
    noise = ImuNoise(1.7e-4, 2e-5, 2e-3, 3e-3)
    sensor = SensorModel(
        rotation=qs.from_euler("xyz", [10, 20, 30], degrees=True), lever_arm=[0.1, 0.02, -0.05]
    )
    data = simulate(pose, times=times)
    q0, p0 = pose.orientation(0.0), pose.position(0.0)

    def evaluate():
        pose.orientation(times)
        pose.angular_velocity(times, frame="body")
        pose.linear_acceleration(times)

    rows = {
        "the spline's own evaluation, all at once": best(evaluate, repeat),
        "simulate, exact": best(lambda: simulate(pose, times=times), repeat),
        "simulate, noise + sensor": best(
            lambda: simulate(pose, times=times, noise=noise, sensor=sensor, seed=1), repeat
        ),
        "attitude only, Rust (integrate runs it first)": best(
            lambda: qs.integrate(times, data.gyro, q0, method="cubic"), repeat
        ),
        "integrate (attitude, velocity, position)": best(
            lambda: integrate(data, (q0, p0), initial_velocity=pose.linear_velocity(0.0)), repeat
        ),
    }
    return {"samples": samples, "seconds": rows}


def errors(motion, rate):
    d = simulate(motion, rate=rate)
    t0 = d.times[0]
    tr = integrate(
        d,
        (motion.orientation(t0), motion.position(t0)),
        initial_velocity=motion.linear_velocity(t0),
    )
    att = qs.angle_between(tr.quats, motion.orientation(d.times)).max()
    pos = np.abs(tr.positions - motion.position(d.times)).max()
    return float(att), float(pos)


def accuracy(rates) -> dict:
    rng = np.random.default_rng(1)
    tk = np.arange(0.0, 61.0, 1.0)
    pose = qs.PoseSpline(
        qs.from_rotvec(smooth(rng, tk, 0.5)), tk, smooth(rng, tk, 2.0), rotation="c3"
    )
    rng = np.random.default_rng(2)
    bspline = qs.PoseBSpline(
        qs.from_rotvec(rng.normal(0, 0.6, (65, 3))),
        rng.normal(0, 1.0, (65, 3)),
        dt=1.0,
        order=6,
        formulation="split",
    )
    out = {}
    for name, motion in [
        ("PoseSpline (C³ attitude, C² position), 60 s", pose),
        ("PoseBSpline order 6 (C⁴), 60 s", bspline),
    ]:
        out[name] = [(r, *errors(motion, r)) for r in rates]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()
    print(f"CPU: {cpu_model()} ({os.cpu_count()} logical cores); load before: {load()}")
    sp = speed(args.samples, args.repeat)
    print(f"\nSpeed, {sp['samples']:,} samples at 200 Hz (best of {args.repeat}):")
    print(f"  {'':42s} {'wall s':>7s} {'CPU s':>7s}")
    for name, (wall, cpu) in sp["seconds"].items():
        print(f"  {name:42s} {wall:7.3f} {cpu:7.3f}")
    acc = accuracy([25, 50, 100, 200, 400, 800])
    for name, rows in acc.items():
        print(f"\nIntegration error, noise-free samples: {name}")
        head = ("rate Hz", 8), ("attitude rad", 13), ("order", 6), ("position m", 11), ("order", 6)
        print("  " + " ".join(f"{h:>{w}s}" for h, w in head))
        prev = None
        for r, att, pos in rows:
            o1 = o2 = ""
            if prev is not None:
                o1 = f"{np.log2(prev[1] / att):6.2f}"
                o2 = f"{np.log2(prev[2] / pos):6.2f}"
            print(f"  {r:8d} {att:13.3e} {o1:>6s} {pos:11.3e} {o2:>6s}")
            prev = (r, att, pos)
    print(f"\nload after: {load()}")
    if args.json:
        Path(args.json).write_text(
            json.dumps({"cpu": cpu_model(), "speed": sp, "accuracy": acc}, indent=1)
        )


if __name__ == "__main__":
    main()
