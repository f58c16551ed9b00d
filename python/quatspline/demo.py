"""``quatspline demo``: the papers' examples and one bundled real recording through every
method, written to ``out/`` with figures, sample files, a comparison table and a report.

The recording ships inside the package (:func:`quatspline.examples.load_recording`), so the
demo runs from an installed wheel. Everything is written into a temporary directory beside
``out`` and moved into place only when the demo has finished: a failure leaves ``out`` as it
was. Without matplotlib the demo writes everything but the figures and says how to get them.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import time
from pathlib import Path

import numpy as np

from . import io as qio
from . import plot
from ._util.atomic import (
    atomic_write,
    make_directories,
    make_work_directory,
    release_work_directory,
    remove_stale_temporaries,
)
from .core.algebra import normalize
from .core.interpolate import slerp
from .examples import BETA_EXAMPLE1_VERTICES, BETA_EXAMPLE2_VERTICES, RECORDING, load_recording
from .io._common import open_regular
from .ops import compare, format_table
from .poses.pose_spline import PoseSpline
from .registry import interpolating_methods
from .registry import spline as make_spline
from .splines import BetaSpline, continuity

PLOT_HINT = "figures skipped: matplotlib is not installed (pip install 'quatspline[plot]')"


def _write_csv(path: Path, header: str, rows: np.ndarray) -> None:
    with atomic_write(path, newline="") as f:
        f.write(header + "\n")
        for r in rows:
            f.write(",".join(repr(float(v)) for v in r) + "\n")


def _have_matplotlib() -> bool:
    return importlib.util.find_spec("matplotlib") is not None


#: The demo's record of the files it wrote into its output directory (one path a line).
MANIFEST = ".quatspline-demo"
#: Suffix of the demo's locked work directory beside its output.
_WORK_SUFFIX = ".demotmp"


def run(out: Path, recording: Path | None = None) -> int:
    """Runs the demo into ``out`` (created if missing; files of a previous run are replaced
    only when this run has succeeded, and never a file the demo did not write there).
    ``recording``: any trajectory file instead of the bundled one. Returns the exit code (0).
    """
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{out}: exists and is not a directory")
    if recording is not None and not Path(recording).is_file():
        raise ValueError(f"{recording}: no such file")
    make_directories(out.parent, out)
    target = out.resolve()
    remove_stale_temporaries(target, suffixes=(_WORK_SUFFIX,))  # a killed run's work
    work = make_work_directory(target, _WORK_SUFFIX)
    try:
        tmp = work / "out"
        tmp.mkdir()
        figures = _have_matplotlib()
        summary = _run(tmp, recording, figures)
        _move_into(tmp, out)
    finally:
        shutil.rmtree(work, ignore_errors=True)
        release_work_directory(work)
    print(summary.replace("{out}", str(out)))
    if not figures:
        print(PLOT_HINT)
    return 0


def _umask() -> int:
    """The process umask (read by setting it and restoring it at once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _written_before(dst: Path) -> set[str]:
    """The files an earlier demo wrote into ``dst`` (its manifest), or none."""
    try:
        with open_regular(dst / MANIFEST, encoding="utf-8") as f:
            return {line.rstrip("\n") for line in f if line.strip()}
    except (OSError, ValueError):
        return set()


def _move_into(src: Path, dst: Path) -> None:
    """Moves the finished tree ``src`` to ``dst``: a rename when ``dst`` does not exist,
    otherwise file by file (each an atomic replace), keeping unrelated files in ``dst`` and
    refusing, before anything is moved, to replace a file the demo did not write there."""
    files = sorted(
        (Path(root) / name).relative_to(src).as_posix()
        for root, _dirs, names in os.walk(src)
        for name in names
    )
    (src / MANIFEST).write_text("".join(f"{f}\n" for f in files), encoding="utf-8")
    if not dst.exists():
        os.chmod(src, 0o777 & ~_umask())  # the directory this run creates: the usual mode
        os.rename(src, dst)
        return
    ours = _written_before(dst)
    for rel in files:
        if os.path.lexists(dst / rel) and rel not in ours:
            raise ValueError(
                f"{dst / rel}: exists and was not written by the demo; refusing to overwrite "
                "it (choose another output directory)"
            )
    for rel in [*files, MANIFEST]:
        (dst / rel).parent.mkdir(parents=True, exist_ok=True)
        os.replace(src / rel, dst / rel)


def _run(out: Path, recording: Path | None, figures: bool) -> str:
    start = time.perf_counter()
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
    if figures:
        plot.save(
            plot.sphere(
                beta, key_times=beta.joints, title="Beta spline, paper Example 1 (β₁=1, β₂=0.5)"
            ),
            out / "sphere.png",
        )
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
    if figures:
        plot.save(
            plot.family(fam, title="Beta spline, paper Example 2: β₂ at vertex 1"),
            out / "family.png",
        )

    # 3. A real recording through every interpolating method
    if recording is None:
        traj = load_recording()
        rec_name, rec_title = RECORDING, "TUM RGB-D fr1/xyz"
    else:
        traj = qio.read(recording)
        rec_name = rec_title = Path(recording).name
    stem = Path(rec_name).stem
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
        qio.write(out / "samples" / f"{stem}_{m}.csv", qio.Trajectory(ts + traj.times[0], s(ts)))
    short = idx[t_rel[idx] <= 3.0]
    c3 = make_spline("c3", traj.quats[short], t_rel[short])
    if figures:
        plot.save(
            plot.rates(
                c3,
                key_times=t_rel[short],
                title=f"C³ spline on {rec_title} (keys every 10th frame)",
            ),
            out / "rates.png",
        )
    pose = PoseSpline(traj.quats[idx], t_rel[idx], traj.positions[idx], rotation="c3")
    if figures:
        plot.save(
            plot.body(
                pose.rotation,
                positions=pose.position,
                snapshots=10,
                t0=float(traj.times[0]),
                title=f"{rec_title}: the camera as a rigid body (C³ pose spline)",
            ),
            out / "body.png",
        )
    else:
        lines.append(PLOT_HINT.replace("figures skipped", "Figures skipped") + ".")

    def fig(title: str, name: str) -> list[str]:
        return [f"![{title}]({name})", ""] if figures else []

    report = [
        "# quatspline demo",
        "",
        *lines,
        "",
        "## Beta spline, Example 1 (sphere)",
        "",
        *fig("sphere", "sphere.png"),
        "## Shape parameter family, Example 2",
        "",
        *fig("family", "family.png"),
        f"## {rec_title}: every 10th frame as a key, the rest held out",
        "",
        table,
        "",
        *fig("rates", "rates.png"),
        *fig("body", "body.png"),
    ]
    (out / "report.md").write_text("\n".join(report))
    print(table)
    what = "4 figures, " if figures else ""
    return (
        f"\nwrote {{out}}/ (report.md, {what}compare.md/json, samples/) "
        f"in {time.perf_counter() - start:.1f} s"
    )
