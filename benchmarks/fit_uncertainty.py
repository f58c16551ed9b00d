"""Coverage of the fit's posterior intervals (``FittedSpline.covariance``/``std``): how often the
nominal 95 % intervals contain the truth, per noise level and penalty.

Coverage measured: Nychka's across-the-function coverage — the fraction of (time, axis) pairs
whose error lies within ±1.96 std, over the sample times of each draw, averaged over draws
(pointwise intervals, averaged over the curve; the target is 90–98 %). Columns:

- ``orient``: orientation, per body axis: |Log(q̂(t)⁻¹ q(t))_c| ≤ 1.96 std_c(t);
- ``ellipsoid``: the 3-D orientation error inside the 95 % ellipsoid of the covariance
  (eᵀ C⁻¹ e ≤ χ²₃(0.95) = 7.815);
- ``omega``: world angular velocity per axis, ±1.96 ``angular_velocity_std``;
- ``pos``: positions per coordinate, ±1.96 ``position_std`` (synthetic table only);
- ``σ̂/σ``: the noise the posterior estimates over the noise added.

Synthetic table: a smooth motion with random phases on 6 s, 300 samples at jittered times
(±30 % of the spacing), isotropic Gaussian noise of σ per axis (σ = RMS angle / √3), λ by GCV.
Recordings table: the protocol of ``benchmarks/fit.py`` — the truth is the natural spline
through every 10th frame of each bundled recording, sampled at its own times, noise of the
given RMS angle; ω of the truth from that spline. Both: ``--draws`` draws per row (default 40).
The last table times building the posterior (assembly, banded factor, selected inversion)
and evaluating std at every sample, for growing sample counts.

    python benchmarks/fit_uncertainty.py [--draws 40] [--scale 100000]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import quatspline as qs
import quatspline.io as qio

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "data"
RECORDINGS = [
    ("TUM RGB-D fr1/xyz", DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt", {}),
    ("EuRoC V1_02 (10 s)", DATA / "euroc_v1_02_medium" / "V102_groundtruth_first10s.csv", {}),
    ("RepoIMU (30 s)", DATA / "repoimu" / "repoIMU_first30s.csv", {}),
    ("MocapBank LeftElbow", DATA / "mocapbank_bvh" / "test_mocapbank.bvh", {"joint": "LeftElbow"}),
]
CHI2_3_95 = 7.814727903251178


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def errors(a, b):
    """Log(a⁻¹ b): the rotation vector from a to b in a's body frame."""
    return 2 * qs.log(qs.multiply(qs.conjugate(a), b))[:, 1:]


def coverage(f, t, q_true, omega_true=None, x_true=None) -> dict:
    e = errors(f.orientation(t) if hasattr(f, "rotation") else f(t), q_true)
    cov = f.covariance(t)
    m = np.einsum("ni,nij,nj->n", e, np.linalg.inv(cov), e)
    out = {
        "orient": np.mean(np.abs(e) <= 1.96 * f.std(t)),
        "ellipsoid": np.mean(m <= CHI2_3_95),
    }
    if omega_true is not None:
        d = f.angular_velocity(t) - omega_true
        out["omega"] = np.mean(np.abs(d) <= 1.96 * f.angular_velocity_std(t))
    if x_true is not None:
        out["pos"] = np.mean(np.abs(f.position(t) - x_true) <= 1.96 * f.position_std(t))
    return out


def synthetic_truth(t, ph):
    rv = np.column_stack(
        [
            0.8 * np.sin(1.1 * t + ph[0]),
            0.5 * np.cos(0.7 * t + ph[1]),
            0.3 * t + 0.2 * np.sin(2.3 * t + ph[2]),
        ]
    )
    x = np.column_stack([np.sin(t + ph[0]), np.cos(0.5 * t + ph[1]), 0.2 * t**2])
    return rv, x


def synthetic_omega(t, ph, h=1e-5):
    """World angular velocity of the synthetic truth, 2 q̇ q* by central differences."""
    q0 = qs.from_rotvec(synthetic_truth(t, ph)[0])
    qp = qs.from_rotvec(synthetic_truth(t + h, ph)[0])
    qm = qs.from_rotvec(synthetic_truth(t - h, ph)[0])
    qp *= np.sign(np.sum(qp * q0, axis=1))[:, None]
    qm *= np.sign(np.sum(qm * q0, axis=1))[:, None]
    return 2 * qs.multiply((qp - qm) / (2 * h), qs.conjugate(q0))[:, 1:]


def synthetic_table(draws: int, seed: int):
    print("\nSynthetic motion, 300 jittered samples on 6 s, λ by GCV (coverage of nominal 95 %)")
    print(f"{'penalty':13s} {'RMS°':>5s} {'orient':>7s} {'ellips':>7s} {'omega':>7s} "
          f"{'pos':>7s} {'σ̂/σ':>6s}")  # fmt: skip
    n = 300
    for pen in ("acceleration", "jerk"):
        for rms_deg in (0.1, 0.5, 1.0, 2.0, 5.0):
            rng = np.random.default_rng(seed)
            sigma = np.deg2rad(rms_deg) / np.sqrt(3)
            rows = []
            for _ in range(draws):
                t = np.linspace(0.0, 6.0, n)
                t[1:-1] += rng.uniform(-0.3, 0.3, n - 2) * (t[1] - t[0])
                ph = rng.uniform(0, 2 * np.pi, 3)
                rv, x = synthetic_truth(t, ph)
                qt = qs.from_rotvec(rv)
                y = qs.multiply(qt, qs.from_rotvec(sigma * rng.normal(size=(n, 3))))
                f = qs.fit(t, y, positions=x + sigma * rng.normal(size=(n, 3)), penalty=pen)
                c = coverage(f, t, qt, synthetic_omega(t, ph), x)
                c["ratio"] = f.noise_std / sigma
                rows.append(c)
            m = {k: np.mean([r[k] for r in rows]) for k in rows[0]}
            cells = [100 * m[k] for k in ("orient", "ellipsoid", "omega", "pos")]
            print(f"{pen:13s} {rms_deg:5.1f} " + " ".join(f"{c:6.1f}%" for c in cells)
                  + f" {m['ratio']:6.3f}")  # fmt: skip


def recordings_table(draws: int, seed: int):
    print("\nBundled recordings (truth: natural spline through every 10th frame), λ by GCV")
    print(f"{'recording':22s} {'penalty':13s} {'RMS°':>5s} {'orient':>7s} {'ellips':>7s} "
          f"{'omega':>7s} {'σ̂/σ':>6s}")  # fmt: skip
    for name, path, opts in RECORDINGS:
        traj = qio.read(path, **opts)
        t_all = traj.times - traj.times[0]
        truth = qs.NaturalSpline(traj.quats[::10], t_all[::10])
        a, b = truth.domain
        t = t_all[(t_all >= a) & (t_all <= b)]
        qt, wt = truth(t), truth.angular_velocity(t)
        for pen in ("acceleration", "jerk"):
            for rms_deg in (0.5, 2.0):
                rng = np.random.default_rng(seed)
                sigma = np.deg2rad(rms_deg) / np.sqrt(3)
                rows = []
                for _ in range(max(1, draws // 4)):
                    y = qs.multiply(qt, qs.from_rotvec(sigma * rng.normal(size=(len(t), 3))))
                    f = qs.fit(t, y, penalty=pen)
                    c = coverage(f, t, qt, wt)
                    c["ratio"] = f.noise_std / sigma
                    rows.append(c)
                m = {k: np.mean([r[k] for r in rows]) for k in rows[0]}
                cells = [100 * m[k] for k in ("orient", "ellipsoid", "omega")]
                print(f"{name:22s} {pen:13s} {rms_deg:5.1f} "
                      + " ".join(f"{c:6.1f}%" for c in cells) + f" {m['ratio']:6.3f}")  # fmt: skip


def timing_table(max_n: int):
    print(f"\nPosterior cost (build once + std at every sample; best of 3; {cpu_model()})")
    print(f"{'samples':>9s} {'fit s':>8s} {'posterior s':>12s} {'std s':>8s}")
    rng = np.random.default_rng(0)
    n = 1000
    while n <= max_n:
        t = np.linspace(0.0, n / 100.0, n)
        rv = np.column_stack([np.sin(0.5 * t), np.cos(0.3 * t), 0.1 * t])
        y = qs.multiply(qs.from_rotvec(rv), qs.from_rotvec(0.005 * rng.normal(size=(n, 3))))
        best = [np.inf, np.inf, np.inf]
        for _ in range(3):
            t0 = time.perf_counter()
            f = qs.fit(t, y, smoothing=1e-5)
            t1 = time.perf_counter()
            f.covariance(t[:1])  # builds the posterior
            t2 = time.perf_counter()
            f.std(t)
            t3 = time.perf_counter()
            best = [min(b, x) for b, x in zip(best, (t1 - t0, t2 - t1, t3 - t2))]
        print(f"{n:9d} {best[0]:8.3f} {best[1]:12.3f} {best[2]:8.3f}")
        n *= 10


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=40, help="noise draws per row (default 40)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--scale", type=int, default=100_000, help="largest timing size")
    args = ap.parse_args()
    synthetic_table(args.draws, args.seed)
    recordings_table(args.draws, args.seed)
    timing_table(args.scale)


if __name__ == "__main__":
    main()
