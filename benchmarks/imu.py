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

Gyro-aided fitting (``quatspline.fit(..., gyro=...)``), real data: the bundled RepoIMU
recording (30 s, Vicon orientation and the IMU's 100 Hz gyroscope), the Vicon orientations
decimated to 2 Hz and 4 Hz as keys, the full 100 Hz Vicon orientation as the truth: the RMS
angle error of the gyro-aided fit (defaults: bias, time offset and rotation estimated, noise
levels estimated) against the best interpolant through the same keys (slerp, squad,
catmull_rom, natural, c3); targets 0.3× at 2 Hz and 0.5× at 4 Hz. The floor: the gyroscope
itself integrated between consecutive keys, forward from one and backward from the next,
blended linearly, with the sensor's rotation, bias, scale and offset from
``quatspline.imu.calibrate`` against the full 100 Hz Vicon (what the gyroscope can give at
best, given its own error against Vicon). Synthetic: random smooth motions, a consumer MEMS
gyroscope (3e-4 rad/s/√Hz at 200 Hz) with a planted bias, offset and rotation, 100 Hz keys of
0.1° noise: the worst errors over the seeds against 0.01 °/s, 0.5 ms, 0.05°.

    python benchmarks/imu.py                  # all tables
    python benchmarks/imu.py --samples 200000 # a quicker speed table
    python benchmarks/imu.py --gyro-only      # only the gyro-aided fitting tables
"""

from __future__ import annotations

import argparse
import json
import os
import time
import warnings
from pathlib import Path

import numpy as np
import quatspline as qs
from _common import cpu_model, load
from quatspline.imu import ImuNoise, SensorModel, calibrate, integrate, simulate

REPO = Path(__file__).resolve().parents[1] / "data" / "repoimu" / "repoIMU_first30s.csv"
INTERPOLANTS = ("slerp", "squad", "catmull_rom", "natural", "c3")


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


def _repoimu():
    a = np.loadtxt(REPO, delimiter=";", skiprows=2)
    return a[:, 0], a[:, 1:5], a[:, 8:11]


def _rms_deg(q, truth) -> float:
    return float(np.degrees(np.sqrt(np.mean(qs.angle_between(q, truth) ** 2))))


def _floor(t, q, g, idx, cal) -> float:
    """The gyroscope integrated between consecutive keys (forward from one, backward from the
    next, blended linearly in time), corrected by a calibration against the full Vicon."""
    k = np.asarray(cal.scale_matrix)
    rb = qs.as_matrix(cal.rotation)
    wb = np.linalg.solve(k, (g - cal.gyro_bias).T).T @ rb.T  # body-frame rates
    w = np.stack([np.interp(t, t + cal.time_offset, wb[:, i]) for i in range(3)], axis=1)
    est = np.empty((idx[-1] + 1, 4))
    for a, b in zip(idx[:-1], idx[1:]):
        dts = np.diff(t[a : b + 1])[:, None]
        inc = qs.from_rotvec(0.5 * (w[a:b] + w[a + 1 : b + 1]) * dts)
        fwd = [q[a]]
        for d in inc:
            fwd.append(qs.multiply(fwd[-1], d))
        bwd = [q[b]]
        for d in inc[::-1]:
            bwd.append(qs.multiply(bwd[-1], qs.conjugate(d)))
        bwd = bwd[::-1]
        for j in range(b - a + 1):
            est[a + j] = qs.slerp(np.asarray(fwd[j]), np.asarray(bwd[j]), j / (b - a))
    return _rms_deg(est, q[: idx[-1] + 1])


def gyro_repoimu() -> list:
    t, q, g = _repoimu()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        cal = calibrate(qs.fit(t, q), (t, g), estimate=("rotation", "bias", "scale", "time_offset"))
    rows = []
    for hz in (2, 4):
        idx = np.arange(0, t.size, int(round(100 / hz)))
        tk, qk = t[idx], q[idx]
        inside = t <= tk[-1]
        tt, truth = t[inside], q[inside]
        interp = {m: _rms_deg(qs.spline(m, qk, tk)(tt), truth) for m in INTERPOLANTS}
        best = min(interp, key=interp.get)
        row = {"keys Hz": hz, "best interpolant": best, "interpolant °": interp[best]}
        for name, kw in (
            ("gyro fit °", {}),
            ("gyro fit, σ_q 0.1° °", {"noise_std": np.radians(0.1)}),
        ):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                t0 = time.perf_counter()
                f = qs.fit(tk, qk, gyro=(t, g), **kw)
                sec = time.perf_counter() - t0
            row[name] = _rms_deg(f(tt), truth)
            row[name.replace("°", "s")] = sec
        row["floor °"] = _floor(t, q, g, idx, cal)
        row["target ×"] = 0.3 if hz == 2 else 0.5
        rows.append(row)
    return rows


def gyro_synthetic(seeds: int) -> dict:
    mems = ImuNoise(gyroscope_noise_density=3e-4, gyroscope_random_walk=0.0)
    worst = {"bias °/s": 0.0, "offset ms": 0.0, "rotation °": 0.0}
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        tk = np.arange(0.0, 30.5, 0.5)
        rv = np.cumsum(np.random.default_rng(500 + seed).normal(0.0, 0.35, (tk.size, 3)), axis=0)
        m = qs.spline("c3", qs.from_rotvec(rv), tk)
        bias = rng.normal(0.0, np.radians(0.5), 3)
        rot = qs.from_rotvec(rng.normal(0.0, np.radians(6.0), 3))
        offset = float(rng.uniform(-0.01, 0.01))
        sensor = SensorModel(rotation=rot, time_offset=offset, gyro_bias=bias)
        imu = simulate(
            m, times=np.arange(0.05, 29.95, 1 / 200), sensor=sensor, noise=mems, seed=seed
        )
        sq = np.radians(0.1)
        t = np.arange(0.0, 30.0 + 1e-9, 0.01)
        q = qs.multiply(m(t), qs.from_rotvec(rng.normal(0.0, sq, (t.size, 3))))
        gf = qs.fit(t, q, gyro=imu, gyro_noise=mems, noise_std=sq).gyro
        worst["bias °/s"] = max(worst["bias °/s"], float(np.abs(np.degrees(gf.bias - bias)).max()))
        worst["offset ms"] = max(worst["offset ms"], 1e3 * abs(gf.time_offset - offset))
        ang = float(np.degrees(qs.angle_between(gf.rotation, rot)))
        worst["rotation °"] = max(worst["rotation °"], ang)
    return {
        "seeds": seeds,
        "worst": worst,
        "targets": {"bias °/s": 0.01, "offset ms": 0.5, "rotation °": 0.05},
    }


def print_gyro(rows, syn) -> None:
    print("\nGyro-aided fit, RepoIMU (30 s): RMS angle error against the 100 Hz Vicon")
    print(
        "| keys | best interpolant | interp ° | gyro fit ° (s) | ratio | σ_q = 0.1° given ° | "
        "ratio | floor ° | floor ratio | target |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        i, gq = r["interpolant °"], r["gyro fit, σ_q 0.1° °"]
        print(
            f"| {r['keys Hz']} Hz | {r['best interpolant']} | {i:.3f} | {r['gyro fit °']:.3f} "
            f"({r['gyro fit s']:.2f}) | {r['gyro fit °'] / i:.2f} | {gq:.3f} | "
            f"{gq / i:.2f} | {r['floor °']:.3f} | {r['floor °'] / i:.2f} | "
            f"{r['target ×']} |"
        )
    w, tg = syn["worst"], syn["targets"]
    print(f"\nGyro-aided fit, synthetic ({syn['seeds']} seeds): worst error (target)")
    for k in w:
        print(f"  {k:12s} {w[k]:.4f} ({tg[k]})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--gyro-only", action="store_true", help="only the gyro-aided fitting tables")
    ap.add_argument("--seeds", type=int, default=5, help="synthetic gyro-aided fits")
    args = ap.parse_args()
    print(f"CPU: {cpu_model()} ({os.cpu_count()} logical cores); load before: {load()}")
    gyro_rows, syn = gyro_repoimu(), gyro_synthetic(args.seeds)
    print_gyro(gyro_rows, syn)
    if args.gyro_only:
        if args.json:
            Path(args.json).write_text(json.dumps({"gyro": gyro_rows, "synthetic": syn}, indent=1))
        return
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
            json.dumps(
                {
                    "cpu": cpu_model(),
                    "speed": sp,
                    "accuracy": acc,
                    "gyro": gyro_rows,
                    "gyro synthetic": syn,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
