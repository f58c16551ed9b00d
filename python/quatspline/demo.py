"""``quatspline demo``: the papers' examples and one bundled real recording through every
method, written to ``out/`` with figures, sample files, a comparison table and a report."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from . import io as qio
from ._atomic import atomic_write
from .algebra import normalize
from .examples import BETA_EXAMPLE1_VERTICES, BETA_EXAMPLE2_VERTICES
from .interpolate import slerp
from .registry import interpolating_methods
from .registry import spline as make_spline
from .spline import BetaSpline

DATA = Path(__file__).resolve().parents[2] / "data"
RECORDING = DATA / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"


def _write_csv(path: Path, header: str, rows: np.ndarray) -> None:
    with atomic_write(path, newline="") as f:
        f.write(header + "\n")
        for r in rows:
            f.write(",".join(repr(float(v)) for v in r) + "\n")


def run(out: Path, recording: Path | None = None) -> int:
    from . import plot
    from .cli import compare, format_table

    start = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    (out / "samples").mkdir(exist_ok=True)
    lines = []

    # 1. Beta paper, Example 1: piecewise slerp through the vertices and the Beta spline
    keys = normalize(BETA_EXAMPLE1_VERTICES)
    u = np.linspace(0.0, 1.0, 50, endpoint=False)
    t = np.concatenate([i + u for i in range(len(keys) - 1)] + [[len(keys) - 1.0]])
    q = np.vstack([slerp(keys[i], keys[i + 1], u) for i in range(len(keys) - 1)] + [keys[-1:]])
    _write_csv(out / "beta_example1_slerp.csv", "t,qw,qx,qy,qz", np.column_stack([t, q]))
    beta = BetaSpline(BETA_EXAMPLE1_VERTICES, beta1=1.0, beta2=0.5, canonicalize=False)
    cp = beta.control_points()
    rows = [[i + 1, j, *cp[i, j]] for i in range(cp.shape[0]) for j in range(4)]
    _write_csv(out / "beta_example1_control_points.csv", "segment,j,qw,qx,qy,qz", np.array(rows))
    tb, qb = beta.sample(n=201)
    _write_csv(out / "samples" / "beta_example1.csv", "t,qw,qx,qy,qz", np.column_stack([tb, qb]))
    plot.save(
        plot.sphere(
            beta, key_times=beta.joints, title="Beta spline, paper Example 1 (β₁=1, β₂=0.5)"
        ),
        out / "sphere.png",
    )
    from .continuity import continuity

    (j1,) = continuity(beta)
    lines.append(
        f"Beta Example 1: G¹ residual {j1.beta_g1_residual:.1e}, G² residual "
        f"{j1.beta_g2_residual:.4f} (|s''| = {j1.second_derivative:.3f}): G¹, not G²."
    )

    # 2. Example 2: β₂ at vertex 1 swept (paper Fig. 4)
    fam = {}
    for b12 in (0.5, 2.0, 4.0):
        b2 = np.full(len(BETA_EXAMPLE2_VERTICES), 0.5)
        b2[1] = b12
        fam[f"β₁,₂ = {b12}"] = BetaSpline(
            BETA_EXAMPLE2_VERTICES, beta1=1.0, beta2=b2, canonicalize=False
        )
    plot.save(
        plot.family(fam, title="Beta spline, paper Example 2: β₂ at vertex 1"), out / "family.png"
    )

    # 3. A real recording through every interpolating method
    rec = recording or RECORDING
    if not rec.is_file():
        raise ValueError(f"{rec}: demo recording not found (run from a source checkout)")
    traj = qio.read(rec)
    t_rel = traj.times - traj.times[0]
    rows = compare(traj, interpolating_methods(), holdout=10)
    table = format_table(rows)
    (out / "compare.md").write_text(table + "\n")
    with atomic_write(out / "compare.json") as f:
        json.dump(rows, f, indent=1)
    idx = np.arange(0, len(t_rel), 10)
    for m in interpolating_methods():
        s = make_spline(m, traj.quats[idx], t_rel[idx])
        ts = np.arange(0.0, t_rel[idx[-1]], 0.01)
        qio.write(
            out / "samples" / f"{rec.stem}_{m}.csv", qio.Trajectory(ts + traj.times[0], s(ts))
        )
    short = idx[t_rel[idx] <= 3.0]
    c3 = make_spline("c3", traj.quats[short], t_rel[short])
    plot.save(
        plot.rates(
            c3, key_times=t_rel[short], title=f"C³ spline on {rec.name} (every 10th frame a key)"
        ),
        out / "rates.png",
    )
    from .pose import PoseSpline

    pose = PoseSpline(t_rel[idx], traj.quats[idx], traj.positions[idx], rotation="c3")
    plot.save(
        plot.body(
            pose.rotation,
            positions=pose.position,
            snapshots=10,
            title=f"{rec.name}: the body along the motion (C³ pose spline)",
        ),
        out / "body.png",
    )

    report = [
        "# quatspline demo",
        "",
        *lines,
        "",
        "## Beta spline, Example 1 (sphere)",
        "![sphere](sphere.png)",
        "",
        "## Shape parameter family, Example 2",
        "![family](family.png)",
        "",
        f"## {rec.name}: every 10th frame as a key, the rest held out",
        "",
        table,
        "",
        "![rates](rates.png)",
        "",
        "![body](body.png)",
        "",
    ]
    (out / "report.md").write_text("\n".join(report))
    print(table)
    print(
        f"\nwrote {out}/ (report.md, 4 figures, compare.md/json, samples/) "
        f"in {time.perf_counter() - start:.1f} s"
    )
    return 0
