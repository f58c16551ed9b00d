"""Gyroscope calibration (``quatspline.imu.calibrate``) against its targets.

1. Synthetic, at realistic noise: a smooth 60 s motion exciting all three axes, a 200 Hz IMU
   mounted at a planted rotation (about 10°), bias (about 0.5 °/s), scale (±1 %) and time
   offset (7.3 ms), with a consumer MEMS ``imu.yaml`` (gyroscope noise density
   3e-4 rad/s/√Hz, bias random walk 2e-5 rad/s²/√Hz). Two references: the exact motion
   spline, and motion capture (100 Hz orientations with 0.1° RMS noise, the Trajectory route:
   a GCV smoothing fit). Over 20 seeds: the worst and RMS errors of the offset, the bias (the
   estimand is a constant: compared with the true, drifting bias averaged over the record,
   and with its initial value) and the rotation; targets 0.5 ms, 0.01 °/s, 0.05°. The floor is
   the stated standard error (from the residuals; the estimator is unbiased, so the errors
   scatter at that scale).
2. RepoIMU (bundled, 30 s, 100 Hz): calibration on the two halves of the recording; the
   differences of offset and bias against the targets 1 ms and 0.05 °/s, with the standard
   error of each difference (√(σ₁² + σ₂²)) — the floor a constant-parameter model reaches on
   this data — and the gain of the measured against the Vicon-derived rate per frequency band.
3. Time of a calibration: 60 s and 10 min at 200 Hz.

    python benchmarks/imu_calibration.py [--seeds 20] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import time
import warnings
from pathlib import Path

import numpy as np
import quatspline as qs
import quatspline.io as qio
from quatspline.imu import SensorModel, calibrate, simulate
from quatspline.io import ImuNoise, Trajectory

DATA = Path(__file__).resolve().parents[1] / "data"
REPO = DATA / "repoimu" / "repoIMU_first30s.csv"
MEMS = ImuNoise(gyroscope_noise_density=3e-4, gyroscope_random_walk=2e-5)
ROT = qs.from_rotvec(np.radians([6.0, -5.0, 7.0]))
BIAS = np.radians([0.5, -0.3, 0.4])
SCALE = np.array([1.01, 0.99, 1.005])
OFFSET = 0.0073


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def motion(duration: float, seed: int = 0):
    """A smooth C³ motion exciting all axes with rates up to about 2 rad/s."""
    rng = np.random.default_rng(1000 + seed)
    tk = np.arange(0.0, duration + 0.25, 0.25)
    f = rng.uniform(0.3, 1.2, 3)
    p = rng.uniform(0, 2 * np.pi, 3)
    rv = np.stack([0.9 * np.sin(f[i] * tk + p[i]) for i in range(3)], axis=1)
    return qs.spline("c3", qs.from_rotvec(rv), tk)


def rotation_error_deg(q_est, q_true) -> float:
    d = abs(float(np.dot(q_est, q_true)))
    return math.degrees(2.0 * math.acos(min(1.0, d)))


def synthetic(seeds: int) -> dict:
    out = {}
    for ref in ("exact spline", "mocap 100 Hz, 0.1° noise"):
        errs, ses = [], []
        for seed in range(seeds):
            m = motion(60.0, seed)
            sensor = SensorModel(
                rotation=ROT, time_offset=OFFSET, gyro_matrix=SCALE, gyro_bias=BIAS
            )
            a, b = m.domain
            data = simulate(
                m, times=np.arange(a + 0.5, b - 0.5, 0.005), sensor=sensor, noise=MEMS, seed=seed
            )
            if ref.startswith("mocap"):
                rng = np.random.default_rng(seed + 77)
                tk = np.arange(a, b, 0.01)
                noise = qs.from_rotvec(
                    rng.normal(0, math.radians(0.1) / math.sqrt(3), (tk.size, 3))
                )
                reference = Trajectory(tk, qs.multiply(m(tk), noise))
            else:
                reference = m
            cal = calibrate(reference, data)
            se = cal.standard_errors
            # the estimand is the constant bias that best stands for the drifting one: the
            # true bias averaged over the samples used (also against the initial bias)
            used = np.isin(data.times, cal.times)
            mean_bias = data.gyro_bias[used].mean(0)
            errs.append(
                [
                    abs(cal.time_offset - OFFSET) * 1e3,
                    float(np.max(np.abs(np.degrees(cal.gyro_bias - mean_bias)))),
                    rotation_error_deg(cal.rotation, ROT),
                    float(np.max(np.abs(np.degrees(cal.gyro_bias - BIAS)))),
                ]
            )
            ses.append(
                [
                    se["time_offset"] * 1e3,
                    float(np.max(np.degrees(se["gyro_bias"]))),
                    float(np.degrees(np.linalg.norm(se["rotation"]))),
                ]
            )
        e, s = np.array(errs), np.array(ses)
        out[ref] = {
            "worst": e.max(0).tolist(),
            "rms": np.sqrt((e**2).mean(0)).tolist(),
            "stated_se_median": np.median(s, 0).tolist(),
        }
    return out


def repoimu() -> dict:
    traj = qio.read(REPO)
    imu = qio.read_imu(REPO)
    n = len(traj) // 2
    res = {}
    for robust in (None, "huber"):
        halves = []
        for sl in (slice(0, n), slice(n, None)):
            t = Trajectory(traj.times[sl], traj.quats[sl])
            d = qio.ImuData(imu.times[sl], imu.gyro[sl])
            halves.append(calibrate(t, d, robust=robust))
        c1, c2 = halves
        d_off = abs(c1.time_offset - c2.time_offset) * 1e3
        se_off = math.hypot(c1.standard_errors["time_offset"], c2.standard_errors["time_offset"])
        d_bias = np.degrees(np.abs(c1.gyro_bias - c2.gyro_bias))
        se_bias = np.degrees(
            np.hypot(c1.standard_errors["gyro_bias"], c2.standard_errors["gyro_bias"])
        )
        res[robust or "plain"] = {
            "offset_ms": [c1.time_offset * 1e3, c2.time_offset * 1e3],
            "offset_diff_ms": d_off,
            "offset_diff_se_ms": se_off * 1e3,
            "bias_deg_s": [np.degrees(c1.gyro_bias).tolist(), np.degrees(c2.gyro_bias).tolist()],
            "bias_diff_deg_s": d_bias.tolist(),
            "bias_diff_se_deg_s": se_bias.tolist(),
            "rms_deg_s": [np.degrees(c1.rms).tolist(), np.degrees(c2.rms).tolist()],
        }
    whole = calibrate(traj, imu)
    m = whole.measured[:, 0] - whole.gyro_bias[0]
    p = whole.predicted[:, 0] - whole.gyro_bias[0]
    fm, fp = np.fft.rfft(m), np.fft.rfft(p)
    f = np.fft.rfftfreq(m.size, float(np.median(np.diff(whole.times))))
    gains = {}
    for lo, hi in ((0, 1), (1, 2), (2, 4), (4, 8), (8, 16)):
        s = (f >= lo) & (f < hi)
        gains[f"{lo}-{hi} Hz"] = float(np.sqrt(np.sum(abs(fm[s]) ** 2) / np.sum(abs(fp[s]) ** 2)))
    res["gain_x_measured_over_vicon"] = gains
    res["whole"] = whole.to_dict()
    return res


def timing() -> dict:
    out = {}
    for duration in (60.0, 600.0):
        m = motion(duration)
        a, b = m.domain
        data = simulate(m, times=np.arange(a + 0.5, b - 0.5, 0.005), noise=MEMS, seed=0)
        best = math.inf
        for _ in range(3):
            t0 = time.perf_counter()
            calibrate(m, data)
            best = min(best, time.perf_counter() - t0)
        out[f"{duration:g} s at 200 Hz ({len(data)} samples)"] = best
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--json", help="write all results here")
    args = ap.parse_args()
    warnings.simplefilter("ignore", RuntimeWarning)
    calibrate(motion(5.0), simulate(motion(5.0), rate=100.0))  # imports, first calls
    print(f"CPU: {cpu_model()}, {os.cpu_count()} cores; load {os.getloadavg()[0]:.1f} (shared)")
    syn = synthetic(args.seeds)
    print(f"\n## Synthetic, consumer MEMS noise, {args.seeds} seeds")
    print("(targets: offset 0.5 ms, bias 0.01 °/s, rotation 0.05°)\n")
    print(
        "| reference | offset worst / RMS (ms) | bias − mean true bias, worst / RMS (°/s) "
        "| rotation worst / RMS (°) | bias − initial bias, worst (°/s) "
        "| stated SE: offset, bias, rotation |"
    )
    print("|---|---|---|---|---|---|")
    for ref, r in syn.items():
        w, q, s = r["worst"], r["rms"], r["stated_se_median"]
        print(
            f"| {ref} | {w[0]:.3f} / {q[0]:.3f} | {w[1]:.4f} / {q[1]:.4f} | "
            f"{w[2]:.4f} / {q[2]:.4f} | {w[3]:.4f} | "
            f"{s[0]:.3f} ms, {s[1]:.4f} °/s, {s[2]:.4f}° |"
        )
    rep = repoimu()
    print("\n## RepoIMU, the two halves (targets: offset within 1 ms, bias within 0.05 °/s)\n")
    print(
        "| loss | offsets (ms) | Δ offset (ms) ± SE | Δ bias x, y, z (°/s) | SE of Δ bias (°/s) |"
    )
    print("|---|---|---|---|---|")
    for k in ("plain", "huber"):
        r = rep[k]
        print(
            f"| {k} | {r['offset_ms'][0]:.2f}, {r['offset_ms'][1]:.2f} | "
            f"{r['offset_diff_ms']:.2f} ± {r['offset_diff_se_ms']:.2f} | "
            + ", ".join(f"{x:.3f}" for x in r["bias_diff_deg_s"])
            + " | "
            + ", ".join(f"{x:.3f}" for x in r["bias_diff_se_deg_s"])
            + " |"
        )
    print(
        "\nGain |measured| / |Vicon-derived| of the x rate per band:",
        ", ".join(f"{k}: {v:.2f}" for k, v in rep["gain_x_measured_over_vicon"].items()),
    )
    tim = timing()
    print("\n## Time of one calibration (best of 3)\n")
    for k, v in tim.items():
        print(f"- {k}: {v:.2f} s")
    if args.json:
        Path(args.json).write_text(
            json.dumps({"synthetic": syn, "repoimu": rep, "timing": tim}, indent=1, default=float)
        )


if __name__ == "__main__":
    main()
