"""Fitting splines on noisy real motion (issue 2.2): ``quatspline.fit`` against the best
interpolating method through the same noisy samples, the robust loss against outliers,
MinimumEnergySpline against NaturalSpline, and fit time/memory at scale.

Protocol, for each bundled recording: the ground truth is the natural spline through every
10th frame (times relative to the first frame); it is sampled at the recording's own times
(inside its domain) and rotation noise is added: a random axis, angle with the given RMS
(0.5°, 1°, 2°), and separately 1 % of the frames turned by 10°: on top of 0.5° noise
("outliers", the case recorded since the first run) and on the noise-free samples ("outliers
only", the case as the issue words it). For the outlier cases the floor is the plain fit with
the outlier frames given weight 0 (what a robust loss that knew them could reach). For the
noise cases the "truth space" columns fit with knots every 10 frames — where the truth has
its keys — i.e. what an estimator that knew the truth's model could reach.
A separate table: far tracking glitches (5–30 % of single frames at 170°–180°, bursts of 3–20
frames) on the tests' synthetic motion, plain and robust fits, error ratios to the clean fit.
Scored on a grid of 4 points per sample interval: RMS angle to the truth, RMS error of
the angular velocity, RMS jerk (‖d²ω/dt²‖). "Best interpolant" = the interpolating method
(slerp, squad, catmull_rom, natural, c3) with the smallest orientation error in that case.

    python benchmarks/fit.py                 # tables, figure, MinimumEnergySpline check
    python benchmarks/fit.py --scale 1000000 # also time 10⁶ samples (fixed λ and auto)
    python benchmarks/fit.py --scale 1000000 --scale-only --repeats 3  # the timing alone
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import quatspline as qs
import quatspline.io as qio
from _common import RECORDINGS, cpu_model

ROOT = Path(__file__).resolve().parent.parent
INTERPOLANTS = ["slerp", "squad", "catmull_rom", "natural", "c3"]


def angle(a, b):
    r = qs.multiply(qs.conjugate(qs.normalize(a)), qs.normalize(b))
    return 2 * np.arctan2(np.linalg.norm(r[..., 1:], axis=-1), np.abs(r[..., 0]))


def rms(x):
    return float(np.sqrt(np.mean(np.asarray(x) ** 2)))


def perturb(q, rms_deg, rng):
    """Rotation noise: random axis, angle |N(0, σ²I₃)| with RMS rms_deg."""
    v = rng.normal(size=(len(q), 3)) * np.deg2rad(rms_deg) / np.sqrt(3)
    return qs.multiply(q, qs.from_rotvec(v))


def outliers(q, frac, deg, rng):
    q = q.copy()
    k = max(1, int(round(frac * len(q))))
    idx = rng.choice(len(q), size=k, replace=False)
    axis = rng.normal(size=(k, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    q[idx] = qs.multiply(q[idx], qs.from_rotvec(axis * np.deg2rad(deg)))
    return q


def scores(s, truth, grid):
    return {
        "angle_deg": np.degrees(rms(angle(s(grid), truth(grid)))),
        "omega": rms(
            np.linalg.norm(s.angular_velocity(grid) - truth.angular_velocity(grid), axis=1)
        ),
        "jerk": rms(np.linalg.norm(s.jerk(grid), axis=1)),
    }


def case(truth, t, q):
    grid = np.linspace(t[0], t[-1], 4 * (len(t) - 1) + 1)
    best = None
    for m in INTERPOLANTS:
        sc = scores(qs.spline(m, q, t), truth, grid)
        if best is None or sc["angle_deg"] < best[1]["angle_deg"]:
            best = (m, sc)
    return grid, best


def truths(every: int = 10):
    """Per recording: (name, truth, t, clean, keys) — the truth is the natural spline through
    every `every`-th frame (times from the first frame; its key times are `keys`), t the
    recording's own times inside its domain, clean the truth at t."""
    for name, path, opts in RECORDINGS:
        traj = qio.read(path, **opts)
        t_all = traj.times - traj.times[0]
        keys = t_all[::every]
        truth = qs.NaturalSpline(traj.quats[::every], keys)
        a, b = truth.domain
        t = t_all[(t_all >= a) & (t_all <= b)]
        yield name, truth, t, truth(t), keys


def oracle(t, q, keys):
    """The oracle: least squares in the truth's own spline space — a cumulative cubic B-spline
    with its knots exactly at the truth's key times, and a negligible penalty (λ 10⁻⁸ of the
    λ whose equivalent-kernel bandwidth is one key interval: it only fixes the gauge, the fit
    is the least-squares one to ~10⁻⁸; tested against a dense least-squares solve in
    tests/fitting/test_fit_oracle.py). No estimator knows these knots on real data."""
    span = t[-1] - t[0]
    lam = 1e-8 * (len(t) / span) * float(np.median(np.diff(keys))) ** 4
    return qs.fit(t, q, knots=keys, smoothing=lam)


TARGET_ANGLE, TARGET_OMEGA = 1.10, 1.30  # fit / oracle


def noise_table(seed: int):
    rows = []
    figure = None
    for name, truth, t, clean, keys in truths():
        for level in (0.5, 1.0, 2.0, "outliers", "outliers only"):
            rng = np.random.default_rng(seed)
            if level == "outliers":
                q = outliers(perturb(clean, 0.5, rng), 0.01, 10.0, rng)
            elif level == "outliers only":
                q = outliers(clean, 0.01, 10.0, rng)
            else:
                q = perturb(clean, level, rng)
            grid, (bm, bs) = case(truth, t, q)
            nat_jerk = rms(np.linalg.norm(qs.NaturalSpline(q, t).jerk(grid), axis=1))
            t0 = time.perf_counter()
            f = qs.fit(t, q)
            dt_fit = time.perf_counter() - t0
            fs = scores(f, truth, grid)
            row = {
                "recording": name,
                "frames": len(t),
                "noise": level if isinstance(level, str) else f"{level}°",
                "best_interpolant": bm,
                "interp_angle_deg": bs["angle_deg"],
                "fit_angle_deg": fs["angle_deg"],
                "angle_ratio": fs["angle_deg"] / bs["angle_deg"],
                "interp_omega": bs["omega"],
                "fit_omega": fs["omega"],
                "omega_ratio": fs["omega"] / bs["omega"],
                "interp_jerk": bs["jerk"],
                "fit_jerk": fs["jerk"],
                "truth_jerk": rms(np.linalg.norm(truth.jerk(grid), axis=1)),
                "natural_jerk": nat_jerk,
                "lambda": f.smoothing,
                "adaptive": f.penalty_weights is not None,
                "edf_per_sample": f.effective_dof / (3 * len(t)),
                "fit_seconds": dt_fit,
            }
            if not isinstance(level, str):
                os_ = scores(oracle(t, q, keys), truth, grid)
                row["oracle_angle_deg"], row["oracle_omega"] = os_["angle_deg"], os_["omega"]
                row["angle_vs_oracle"] = fs["angle_deg"] / os_["angle_deg"]
                row["omega_vs_oracle"] = fs["omega"] / os_["omega"]
                row["oracle_vs_interp"] = os_["angle_deg"] / bs["angle_deg"]
                for mode in ("gcv", "adaptive"):
                    ms = scores(qs.fit(t, q, smoothing=mode), truth, grid)
                    row[f"{mode}_angle_vs_oracle"] = ms["angle_deg"] / os_["angle_deg"]
                    row[f"{mode}_omega_vs_oracle"] = ms["omega"] / os_["omega"]
                # The best global λ in hindsight on a grid around GCV's, and the jerk penalty.
                lams = f.smoothing * np.logspace(-1.5, 1.5, 13)
                orc = [scores(qs.fit(t, q, smoothing=float(lam)), truth, grid) for lam in lams]
                row["oracle_angle_ratio"] = min(o["angle_deg"] for o in orc) / bs["angle_deg"]
                row["oracle_omega_ratio"] = min(o["omega"] for o in orc) / bs["omega"]
                # The truth's own spline space: uniform knots every 10 frames from t[0] (the
                # truth's keys; exactly so on uniformly sampled recordings), plain least squares
                # (λ → 0) and GCV's λ — what an estimator that knew where the truth has knots
                # could reach; the first is the noise floor σ·√(p/n) of that space.
                k10 = float(np.median(np.diff(t))) * 10.0
                for tag, lam in (("truth_space", 1e-9), ("truth_space_gcv", "auto")):
                    ts = scores(qs.fit(t, q, knots=k10, smoothing=lam), truth, grid)
                    row[f"{tag}_angle_ratio"] = ts["angle_deg"] / bs["angle_deg"]
                    row[f"{tag}_omega_ratio"] = ts["omega"] / bs["omega"]
                jf = qs.fit(t, q, penalty="jerk")
                js = scores(jf, truth, grid)
                row["auto_penalty"] = "jerk" if jf.score < f.score else "acceleration"
                row["jerk_angle_ratio"] = js["angle_deg"] / bs["angle_deg"]
                row["jerk_omega_ratio"] = js["omega"] / bs["omega"]
                row["jerk_angle_vs_oracle"] = js["angle_deg"] / os_["angle_deg"]
                row["jerk_omega_vs_oracle"] = js["omega"] / os_["omega"]
            else:
                base = (
                    perturb(clean, 0.5, np.random.default_rng(seed))
                    if level == "outliers"
                    else clean
                )
                w = (angle(base, q) < np.deg2rad(1.0)).astype(float)
                row["floor_angle_deg"] = scores(qs.fit(t, q, weights=w), truth, grid)["angle_deg"]
                row["floor_ratio"] = row["floor_angle_deg"] / fs["angle_deg"]
                r = qs.fit(t, q, robust="huber")
                rs = scores(r, truth, grid)
                row["huber_angle_deg"] = rs["angle_deg"]
                row["huber_ratio"] = rs["angle_deg"] / fs["angle_deg"]
                row["huber_omega"] = rs["omega"]
                c = qs.fit(t, q, robust="cauchy")
                row["cauchy_angle_deg"] = scores(c, truth, grid)["angle_deg"]
                row["cauchy_ratio"] = row["cauchy_angle_deg"] / fs["angle_deg"]
            rows.append(row)
            if figure is None and level == 1.0:
                figure = (name, truth, qs.spline(bm, q, t), bm, f, grid)
    return rows, figure


def draws_table(first_seed: int, draws: int):
    """The noise columns over `draws` independent noise draws (seeds first_seed, …): mean,
    smallest and largest angle and ω ratio of the fit (default and jerk penalty) to the best
    interpolant of the same draw. One draw decides nothing near a target: on the bundled
    recordings the angle ratios move by ±0.01–0.03 from draw to draw."""
    rows = []
    for name, truth, t, clean, _ in truths():
        for level in (0.5, 1.0, 2.0):
            ratios = {k: [] for k in ("angle", "omega", "jerk_angle", "jerk_omega")}
            for seed in range(first_seed, first_seed + draws):
                q = perturb(clean, level, np.random.default_rng(seed))
                grid, (_, bs) = case(truth, t, q)
                for tag, pen in (("", "acceleration"), ("jerk_", "jerk")):
                    fs = scores(qs.fit(t, q, penalty=pen), truth, grid)
                    ratios[tag + "angle"].append(fs["angle_deg"] / bs["angle_deg"])
                    ratios[tag + "omega"].append(fs["omega"] / bs["omega"])
            row = {"recording": name, "noise": f"{level}°", "draws": draws}
            for k, v in ratios.items():
                row[k] = (float(np.mean(v)), float(np.min(v)), float(np.max(v)))
            rows.append(row)
    return rows


def synthetic_motions(rate: float = 100.0, seconds: float = 20.0):
    """Motions whose smoothness varies along time (and one whose does not), sampled at
    `rate` Hz: (name, times, rotation vectors)."""
    t = np.arange(0.0, seconds, 1.0 / rate)
    s = 1.0 / (1.0 + np.exp(-(t - seconds / 2) / 0.3))  # slow → fast, a smooth switch
    phase_sf = 2 * np.pi * (0.15 * t + (1.2 - 0.15) * np.cumsum(s) / rate)
    phase_chirp = 2 * np.pi * 0.1 * seconds / 3 * (np.exp(3 * t / seconds) - 1)  # 0.1 → 2 Hz
    out = []
    for name, ph, amp in (
        ("slow then fast", phase_sf, 0.6),
        ("chirp 0.1→2 Hz", phase_chirp, 0.5),
        ("fast then rest", phase_sf[::-1] * (1 - s), 0.6),
        ("uniform 0.7 Hz", 2 * np.pi * 0.7 * t, 0.5),
    ):
        rv = amp * np.stack([np.sin(ph), 0.6 * np.cos(0.8 * ph), 0.3 * np.sin(1.3 * ph + 1)], 1)
        out.append((name, t, rv))
    return out


def extra_table(seed: int):
    """The oracle targets off the bundled protocol: the recordings' truths with keys every 5th
    and 20th frame (1° noise), and synthetic motions whose smoothness varies along time (the
    natural spline through every 10th sample of each; 0.5°, 1°, 2° noise). Each row: fit
    (smoothing auto, gcv, adaptive) / oracle, angle and ω."""
    cases = []
    for every in (5, 20):
        for name, truth, t, clean, keys in truths(every):
            cases.append((f"{name}, keys every {every}", 1.0, truth, t, clean, keys))
    for name, t, rv in synthetic_motions():
        q = qs.from_rotvec(rv)
        truth = qs.NaturalSpline(q[::10], t[::10])
        a, b = truth.domain
        tt = t[(t >= a) & (t <= b)]
        for level in (0.5, 1.0, 2.0):
            cases.append((f"synthetic: {name}", level, truth, tt, truth(tt), t[::10]))
    rows = []
    for name, level, truth, t, clean, keys in cases:
        q = perturb(clean, level, np.random.default_rng(seed))
        grid = np.linspace(t[0], t[-1], 4 * (len(t) - 1) + 1)
        os_ = scores(oracle(t, q, keys), truth, grid)
        row = {"case": name, "noise": f"{level}°"}
        for mode in ("auto", "gcv", "adaptive"):
            f = qs.fit(t, q, smoothing=mode)
            fs = scores(f, truth, grid)
            row[mode] = (fs["angle_deg"] / os_["angle_deg"], fs["omega"] / os_["omega"])
            if mode == "auto":
                row["adaptive_chosen"] = f.penalty_weights is not None
        rows.append(row)
    return rows


def verdict(a, w):
    return "PASS" if a <= TARGET_ANGLE and w <= TARGET_OMEGA else "MISS"


def min_energy_table():
    """MinimumEnergySpline vs NaturalSpline on every 10th frame: energy and held-out error."""

    def energy(s, sub=8):
        x, w = np.polynomial.legendre.leggauss(10)
        j = s.joints
        pieces = [np.linspace(a, b, sub + 1)[:-1] for a, b in zip(j[:-1], j[1:])]
        e = np.r_[np.concatenate(pieces), j[-1]]
        lo, hi = e[:-1, None], e[1:, None]
        tt = (0.5 * (hi - lo) * x + 0.5 * (lo + hi)).ravel()
        v = np.sum(s.angular_acceleration(tt, "body") ** 2, axis=1).reshape(lo.shape[0], -1)
        return float(np.sum(0.5 * (hi - lo) * v * w))

    rows = []
    for name, path, opts in RECORDINGS:
        traj = qio.read(path, **opts)
        t = traj.times - traj.times[0]
        idx = np.arange(0, len(t), 10)
        rest = np.setdiff1d(np.arange(idx[0], idx[-1] + 1), idx)
        nat = qs.NaturalSpline(traj.quats[idx], t[idx])
        t0 = time.perf_counter()
        me = qs.MinimumEnergySpline(traj.quats[idx], t[idx])
        secs = time.perf_counter() - t0
        en, em = energy(nat), energy(me)
        hn = np.degrees(rms(angle(nat(t[rest]), traj.quats[rest])))
        hm = np.degrees(rms(angle(me(t[rest]), traj.quats[rest])))
        rows.append(
            {
                "recording": name,
                "keys": len(idx),
                "energy_natural": en,
                "energy_min": em,
                "energy_ratio": em / en,
                "holdout_natural_deg": hn,
                "holdout_min_deg": hm,
                "holdout_ratio": hm / hn,
                "seconds": secs,
            }
        )
    return rows


def glitch_table(seed: int, draws: int = 3):
    """Tracking glitches far from the motion (the tests' 8 s motion, 801 samples, 0.3° noise
    per axis): 5 %, 20 % and 30 % of single frames turned by 170°–180° about random axes, 5 %
    of exact half turns, and bursts of 3, 8 and 20 consecutive frames turned by one rotation
    (30°, 90°, 170°–180°; bursts apart from each other). Plain, Huber and Cauchy fits with the
    default max_iter, over `draws` draws: the largest iteration count and the mean and largest
    ratio of the RMS angle to the clean motion to that of the plain fit of the same draw
    without glitches (None: an error in some draw)."""
    t = np.linspace(0.0, 8.0, 801)
    rv = np.stack([0.6 * np.sin(0.9 * t), 0.4 * np.cos(0.6 * t) - 0.4, 0.3 * t], axis=1)
    clean = qs.from_rotvec(rv)
    cases = [("single", (170.0, 180.0), f, 1) for f in (0.05, 0.2, 0.3)]
    cases += [("single", (180.0, 180.0), 0.05, 1)]
    cases += [("burst", (d, d), 0.05, n) for d in (30.0, 90.0) for n in (3, 8, 20)]
    cases += [("burst", (170.0, 180.0), f, n) for f in (0.05, 0.2) for n in (3, 8, 20)]
    rows = []
    for kind, (lo, hi), frac, burst in cases:
        row = {"kind": kind, "deg": (lo, hi), "fraction": frac, "burst": burst}
        cells = {str(loss): [] for loss in (None, "huber", "cauchy")}
        for d in range(draws):
            rng = np.random.default_rng([seed, d, int(lo), int(frac * 100), burst])
            q = qs.multiply(clean, qs.from_rotvec(rng.normal(size=(len(t), 3)) * np.deg2rad(0.3)))
            ref = rms(angle(qs.fit(t, q)(t), clean))
            count = int(round(frac * len(t) / burst))
            if burst == 1:
                starts = rng.choice(len(t), size=count, replace=False)
            else:
                slots = rng.choice(len(t) // (2 * burst), size=count, replace=False)
                starts = slots * 2 * burst + rng.integers(0, burst, size=count)
            for s0 in starts:
                axis = rng.normal(size=3)
                axis /= np.linalg.norm(axis)
                turn = qs.from_rotvec(axis * np.deg2rad(rng.uniform(lo, hi)))
                q[s0 : s0 + burst] = qs.multiply(q[s0 : s0 + burst], turn)
            for loss in (None, "huber", "cauchy"):
                try:
                    f = qs.fit(t, q, robust=loss)
                    cells[str(loss)].append((f.iterations, rms(angle(f(t), clean)) / ref))
                except (RuntimeError, ValueError):
                    cells[str(loss)].append(None)
        for k, v in cells.items():
            ok = [x for x in v if x is not None]
            row[k] = (
                None
                if len(ok) < len(v)
                else (
                    max(x[0] for x in ok),
                    float(np.mean([x[1] for x in ok])),
                    max(x[1] for x in ok),
                )
            )
        rows.append(row)
    return rows


def outlier_rows(seed: int, draws: int = 3):
    """1 % of frames turned by 10° about random axes on 0.5° noise: the plain, Huber and
    Cauchy fits and the floor (the plain fit with the outlier frames given weight 0), RMS angle
    to the truth: per bundled recording (its own truth, one draw) and on random synthetic
    motions (`draws` draws, random outlier placement). Ratios to the floor."""
    out = []

    def row(name, t, truth_q, q, bad):
        err = {}
        for key, kw in (
            ("plain", {}),
            ("floor", {"weights": (~bad).astype(float)}),
            ("huber", {"robust": "huber"}),
            ("cauchy", {"robust": "cauchy"}),
        ):
            err[key] = rms(angle(qs.fit(t, q, **kw)(t), truth_q))
        return {"case": name, **{k: err[k] / err["floor"] for k in ("plain", "huber", "cauchy")}}

    def draw(q, rng):
        q = perturb(q, 0.5, rng)
        bad = np.zeros(len(q), bool)
        bad[rng.choice(len(q), size=max(1, int(round(0.01 * len(q)))), replace=False)] = True
        axis = rng.normal(size=(bad.sum(), 3))
        axis /= np.linalg.norm(axis, axis=1, keepdims=True)
        q[bad] = qs.multiply(q[bad], qs.from_rotvec(axis * np.deg2rad(10.0)))
        return q, bad

    for name, _, t, clean, _ in truths():
        q, bad = draw(clean, np.random.default_rng(seed))
        out.append(row(name, t, clean, q, bad))
    for d in range(draws):
        rng = np.random.default_rng([seed, d, 10])
        t, clean = random_motion(rng)
        q, bad = draw(clean, rng)
        out.append(row(f"random motion, draw {d}", t, clean, q, bad))
    return out


def random_motion(rng, n: int = 801):
    """A random smooth motion: 8 s, n samples, each rotation-vector axis a sum of four
    sinusoids of random frequency (0.1–1.5 Hz), amplitude and phase."""
    t = np.linspace(0.0, 8.0, n)
    f = rng.uniform(0.1, 1.5, (3, 4))
    a = rng.uniform(0.1, 0.6, (3, 4)) / f
    ph = rng.uniform(0, 2 * np.pi, (3, 4))
    rv = np.stack(
        [(a[i] * np.sin(2 * np.pi * f[i] * t[:, None] + ph[i])).sum(1) for i in range(3)], 1
    )
    return t, qs.from_rotvec(rv)


def print_robust_tables(seed: int):
    """The robust losses' tables (`--robust`): outliers against the floor, far glitches."""
    print("\n## 1 % outliers of 10° on 0.5° noise: error / floor (outlier frames weighted 0)\n")
    print("| case | plain / floor | huber / floor | cauchy / floor |")
    print("|---|---|---|---|")
    orows = outlier_rows(seed)
    for r in orows:
        print(f"| {r['case']} | {r['plain']:.3f} | {r['huber']:.3f} | {r['cauchy']:.3f} |")
    gl = glitch_table(seed)
    print_glitch_table(gl)
    return {"outliers": orows, "glitches": gl}


def print_glitch_table(gl):
    print(
        "\n## Far glitches (3 draws): largest iteration count; error ratio to the clean fit "
        "of the same draw, mean (largest)\n"
    )
    print("| glitches | plain | huber | cauchy |")
    print("|---|---|---|---|")
    for r in gl:
        lo, hi = r["deg"]
        deg = f"{lo:g}°" if lo == hi else f"{lo:g}°–{hi:g}°"
        what = (
            f"{r['fraction']:.0%} single frames of {deg}"
            if r["kind"] == "single"
            else f"{r['fraction']:.0%} in bursts of {r['burst']} frames, {deg}"
        )
        cells = [
            "error" if r[k] is None else f"{r[k][0]} it, {r[k][1]:.2f} ({r[k][2]:.2f})"
            for k in ("None", "huber", "cauchy")
        ]
        print(f"| {what} | " + " | ".join(cells) + " |")


def plot(figure, out: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name, truth, interp, bm, f, grid = figure
    sel = grid <= grid[0] + min(6.0, grid[-1] - grid[0])
    g = grid[sel]
    fig, ax = plt.subplots(figsize=(9, 3.6), dpi=120)
    sp = lambda s: np.linalg.norm(s.angular_velocity(g), axis=1)  # noqa: E731
    ax.plot(g, sp(interp), color="0.7", lw=0.8, label=f"{bm} through the noisy samples")
    ax.plot(g, sp(truth), color="k", lw=1.6, label="truth")
    ax.plot(g, sp(f), color="C3", lw=1.4, label=f"fit (GCV λ = {f.smoothing:.3g})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("angular speed (rad/s)")
    ax.set_title(f"{name}: 1° RMS rotation noise")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


SCALE_SCRIPT = r"""
import json, os, resource, sys, time
import numpy as np, quatspline as qs
n, smoothing, with_pos = int(sys.argv[1]), sys.argv[2], sys.argv[3] == "1"
max_iter = int(sys.argv[4])
t = np.arange(n) / 300.0
rv = np.stack([0.8 * np.sin(0.5 * t), 0.6 * np.cos(0.37 * t), 0.2 * np.sin(0.05 * t)], 1)
rng = np.random.default_rng(0)
q = qs.multiply(qs.from_rotvec(rv), qs.from_rotvec(rng.normal(size=(n, 3)) * 0.01))
pos = np.column_stack([np.sin(t), np.cos(0.3 * t), 0.1 * t]) + rng.normal(size=(n, 3)) * 1e-3
lam = "auto" if smoothing == "auto" else float(smoothing)


def status(key):  # kB → GB, from /proc/self/status (None where unavailable)
    try:
        for line in open("/proc/self/status"):
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1e6
    except OSError:
        pass
    return None


try:  # reset the peak RSS to the current RSS (Linux): the fit's own peak is read after it
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")
except OSError:
    pass
before = status("VmRSS")
load = os.getloadavg()[0]
t0, c0 = time.perf_counter(), time.process_time()
stopped = False
try:
    f = qs.fit(t, q, smoothing=lam, positions=pos if with_pos else None, max_iter=max_iter)
except RuntimeError:  # the floor runs: stopped after max_iter iterations (not converged)
    f, stopped = None, True
dt, cpu = time.perf_counter() - t0, time.process_time() - c0
print(json.dumps({"n": n, "smoothing": smoothing, "positions": with_pos, "seconds": dt,
                  "cpu_seconds": cpu, "load": load, "max_iter": max_iter, "stopped": stopped,
                  "iterations": None if f is None else f.iterations,
                  "lambda": None if f is None else f.smoothing,
                  "rss_before_gb": before, "fit_peak_rss_gb": status("VmHWM"),
                  "peak_rss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6}))
"""

# The floor of a fit (the least work any Gauss–Newton fit of this size does): one iteration
# with a fixed λ — an assembly of the normal equations at the start and at the step, a banded
# factorisation, a solve, a retraction — and, for λ = "auto", two (the second one's
# linearisation is the first where λ is searched by GCV). Timed as the same fit stopped after
# `max_iter` = 1 or 2 iterations.
FLOOR_ITERATIONS = {"1e-6": 1, "auto": 2}


def scale(n: int, repeats: int):
    """Best of `repeats` runs (by wall time), each in a fresh process: wall and CPU (user +
    sys of all threads) seconds of the fit, peak RSS of the process (the data and the
    interpreter included) and of the fit (the peak reset when the fit starts; it includes the
    RSS before the fit), and the 1-minute load average when the run started (the machine
    may be shared: wall time above CPU time / threads means the fit waited for a core).
    Each orientation-only case is followed by its floor (see `FLOOR_ITERATIONS`)."""
    out = []
    cases = [("1e-6", False, 100), ("1e-6", False, FLOOR_ITERATIONS["1e-6"])]
    cases += [("auto", False, 100), ("auto", False, FLOOR_ITERATIONS["auto"])]
    cases += [("1e-6", True, 100), ("auto", True, 100)]
    for smoothing, with_pos, max_iter in cases:
        best = None
        for _ in range(repeats):
            r = subprocess.run(
                [
                    sys.executable,
                    "-c",
                    SCALE_SCRIPT,
                    str(n),
                    smoothing,
                    str(int(with_pos)),
                    str(max_iter),
                ],
                capture_output=True,
                text=True,
                check=True,
            )
            row = json.loads(r.stdout.strip().splitlines()[-1])
            if best is None or row["seconds"] < best["seconds"]:
                best = row
        out.append(best)
    return out


def print_scale(sc, repeats: int, cpu: str):
    print(f"\n## scale (best of {repeats}, fresh process each; CPU: {cpu})\n")
    print(
        "| samples | smoothing | positions | run | wall (s) | CPU user+sys (s) | load | "
        "iterations | λ | peak RSS: process, fit (GB) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    fmt = lambda v, f: "–" if v is None else format(v, f)  # noqa: E731
    for r in sc:
        run = f"floor ({r['max_iter']} it.)" if r.get("stopped") else "fit"
        print(
            f"| {r['n']:,} | {r['smoothing']} | {'yes' if r['positions'] else 'no'} | {run} | "
            f"{r['seconds']:.1f} | {r['cpu_seconds']:.1f} | {r['load']:.1f} | "
            f"{fmt(r['iterations'], 'd')} | {fmt(r['lambda'], '.3g')} | "
            f"{r['peak_rss_gb']:.2f}, {fmt(r.get('fit_peak_rss_gb'), '.2f')} |"
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--scale", type=int, nargs="*", default=[], help="sample counts to time")
    ap.add_argument(
        "--scale-only", action="store_true", help="only the --scale table (no quality tables)"
    )
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--draws", type=int, default=8, help="noise draws for the spread table")
    ap.add_argument("--figure", default=str(ROOT / "docs" / "_static" / "fit_speed.png"))
    ap.add_argument("--json", help="write all results here")
    ap.add_argument(
        "--robust", action="store_true", help="only the robust losses' tables (outliers, glitches)"
    )
    args = ap.parse_args()
    cpu = cpu_model()
    print(f"CPU: {cpu}")
    if args.scale_only:
        sc = [r for n in args.scale for r in scale(n, args.repeats)]
        print_scale(sc, args.repeats, cpu)
        if args.json:
            Path(args.json).write_text(json.dumps({"cpu": cpu, "scale": sc}, indent=1))
        return
    if args.robust:
        res = print_robust_tables(args.seed)
        if args.json:
            Path(args.json).write_text(json.dumps(res, indent=1, default=float))
        return
    rows, figure = noise_table(args.seed)
    print("\n## fit vs the best interpolant (ratios: fit / interpolant)\n")
    print(
        "| recording | noise | best interpolant | angle err (°) interp → fit | ratio | "
        "ω err (rad/s) interp → fit | ratio | RMS jerk: fit, natural spline, truth |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['recording']} | {r['noise']} | {r['best_interpolant']} | "
            f"{r['interp_angle_deg']:.3f} → {r['fit_angle_deg']:.3f} | {r['angle_ratio']:.2f} | "
            f"{r['interp_omega']:.3f} → {r['fit_omega']:.3f} | {r['omega_ratio']:.3f} | "
            f"{r['fit_jerk']:.3g}, {r['natural_jerk']:.3g}, {r['truth_jerk']:.3g} |"
        )
    print(
        "\n## The oracle: least squares in the truth's own spline space (knots at its keys)\n"
        '\nREADME table — fit = `fit(smoothing="auto")`; targets angle ≤ '
        f"{TARGET_ANGLE:.2f}× and ω ≤ {TARGET_OMEGA:.2f}× the oracle's\n"
    )
    print(
        "| recording | noise | angle fit/oracle | ω fit/oracle | angle fit/best interpolant | "
        "target |"
    )
    print("|---|---|---|---|---|---|")
    for r in rows:
        if "angle_vs_oracle" in r:
            print(
                f"| {r['recording']} | {r['noise']} | {r['angle_vs_oracle']:.3f} | "
                f"{r['omega_vs_oracle']:.3f} | {r['angle_ratio']:.3f} | "
                f"{verdict(r['angle_vs_oracle'], r['omega_vs_oracle'])} |"
            )
    print(
        "\n## Against the oracle: auto (adaptive chosen?), global GCV, adaptive forced, jerk "
        "penalty; the floor (oracle / best interpolant, truth-space GCV / oracle)\n"
    )
    print(
        "| recording | noise | auto: angle, ω (adaptive?) | gcv: angle, ω | adaptive: angle, ω | "
        "jerk: angle, ω | oracle/interp | truth-space GCV/oracle: angle, ω | "
        "best global λ in hindsight/interp: angle, ω | penalty='auto' keeps |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "angle_vs_oracle" in r:
            o = r["oracle_vs_interp"]
            print(
                f"| {r['recording']} | {r['noise']} | {r['angle_vs_oracle']:.3f}, "
                f"{r['omega_vs_oracle']:.3f} ({'yes' if r['adaptive'] else 'no'}) | "
                f"{r['gcv_angle_vs_oracle']:.3f}, {r['gcv_omega_vs_oracle']:.3f} | "
                f"{r['adaptive_angle_vs_oracle']:.3f}, {r['adaptive_omega_vs_oracle']:.3f} | "
                f"{r['jerk_angle_vs_oracle']:.3f}, {r['jerk_omega_vs_oracle']:.3f} | {o:.3f} | "
                f"{r['truth_space_gcv_angle_ratio'] / o:.3f}, "
                f"{r['truth_space_gcv_omega_ratio'] * r['interp_omega'] / r['oracle_omega']:.3f} | "
                f"{r['oracle_angle_ratio']:.3f}, {r['oracle_omega_ratio']:.3f} | "
                f"{r['auto_penalty']} |"
            )
    ex = extra_table(args.seed)
    print(
        "\n## Off the protocol: other key spacings, synthetic motions of varying smoothness "
        "(fit / oracle: angle, ω)\n"
    )
    print("| case | noise | auto (adaptive?) | gcv | adaptive | target (auto) |")
    print("|---|---|---|---|---|---|")
    for r in ex:
        a, g, d = r["auto"], r["gcv"], r["adaptive"]
        print(
            f"| {r['case']} | {r['noise']} | {a[0]:.3f}, {a[1]:.3f} "
            f"({'yes' if r['adaptive_chosen'] else 'no'}) | {g[0]:.3f}, {g[1]:.3f} | "
            f"{d[0]:.3f}, {d[1]:.3f} | {verdict(*a)} |"
        )
    n_rows = [r for r in rows if "angle_vs_oracle" in r]
    miss = [r for r in n_rows if verdict(r["angle_vs_oracle"], r["omega_vs_oracle"]) == "MISS"]
    print(
        f"\nsummary: {len(n_rows) - len(miss)}/{len(n_rows)} bundled rows within the targets; "
        f"off-protocol {sum(verdict(*r['auto']) == 'PASS' for r in ex)}/{len(ex)}"
    )
    for r in miss:
        print(
            f"  MISS {r['recording']} {r['noise']}: angle {r['angle_vs_oracle']:.3f}× "
            f"(target {TARGET_ANGLE}), ω {r['omega_vs_oracle']:.3f}× (target {TARGET_OMEGA})"
        )
    print("\n## 1 % outliers of 10°: Huber vs plain fit (floor: outlier frames weighted 0)\n")
    print(
        "| recording | case | plain fit angle err (°) | huber (°) | huber / plain | "
        "cauchy / plain | floor / plain | huber / floor |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "huber_ratio" in r:
            print(
                f"| {r['recording']} | {r['noise']} | {r['fit_angle_deg']:.3f} | "
                f"{r['huber_angle_deg']:.3f} | {r['huber_ratio']:.3f} | {r['cauchy_ratio']:.3f} | "
                f"{r['floor_ratio']:.3f} | {r['huber_ratio'] / r['floor_ratio']:.3f} |"
            )
    dr = draws_table(args.seed, args.draws) if args.draws > 0 else []
    if dr:
        print(
            f"\n## Over {args.draws} noise draws (seeds {args.seed}…{args.seed + args.draws - 1}): "
            "mean (smallest–largest) ratio to the best interpolant of the same draw\n"
        )
        print("| recording | noise | angle ratio | ω ratio | jerk penalty: angle | ω |")
        print("|---|---|---|---|---|---|")

        def cell(v):
            return f"{v[0]:.3f} ({v[1]:.3f}–{v[2]:.3f})"

        for r in dr:
            print(
                f"| {r['recording']} | {r['noise']} | {cell(r['angle'])} | {cell(r['omega'])} | "
                f"{cell(r['jerk_angle'])} | {cell(r['jerk_omega'])} |"
            )
    gl = glitch_table(args.seed)
    print_glitch_table(gl)
    me = min_energy_table()
    print("\n## MinimumEnergySpline vs NaturalSpline (keys: every 10th frame)\n")
    print(
        "| recording | keys | ∫|ω̇|² natural | min-energy / natural | held-out RMS (°) natural | "
        "min-energy / natural | seconds |"
    )
    print("|---|---|---|---|---|---|---|")
    for r in me:
        print(
            f"| {r['recording']} | {r['keys']} | {r['energy_natural']:.6g} | "
            f"{r['energy_ratio']:.10f} | {r['holdout_natural_deg']:.4f} | "
            f"{r['holdout_ratio']:.5f} | {r['seconds']:.2f} |"
        )
    if figure is not None:
        Path(args.figure).parent.mkdir(parents=True, exist_ok=True)
        plot(figure, Path(args.figure))
        print(f"\nfigure: {args.figure}")
    sc = []
    for n in args.scale:
        sc += scale(n, args.repeats)
    if sc:
        print_scale(sc, args.repeats, cpu)
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {
                    "cpu": cpu,
                    "noise": rows,
                    "off_protocol": ex,
                    "draws": dr,
                    "glitches": gl,
                    "min_energy": me,
                    "scale": sc,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
