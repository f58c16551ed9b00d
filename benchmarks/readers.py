"""Reader benchmark: 500k-row TUM, CSV, EuRoC and KITTI files read by quatspline's fast path
(pandas' C parser), by its careful line-by-line parser (the only path before 2.7, and the
fallback that gives file:line:column errors), and by the peers pandas.read_csv and
numpy.loadtxt alone — same files, same run, best of --repeat runs, ratios printed.

    make bench
    python benchmarks/readers.py --rows 500000 --repeat 3
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

import numpy as np
import quatspline.io as qio
from quatspline.core.convert import as_matrix
from quatspline.io import _fast


def cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def make_files(d: Path, n: int) -> dict:
    rng = np.random.default_rng(0)
    t = 1305031102.175304 + np.cumsum(rng.uniform(0.001, 0.02, n))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    p = rng.normal(size=(n, 3))
    ns = 1403715523912143143 + np.cumsum(rng.integers(10**6, 10**7, n))
    files = {}
    with open(d / "a.tum", "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        np.savetxt(f, np.column_stack([t, p, q[:, [1, 2, 3, 0]]]), fmt="%.17g")
    files["TUM"] = (d / "a.tum", " ", 1)
    with open(d / "a.csv", "w") as f:
        f.write("t,qw,qx,qy,qz,x,y,z\n")
        np.savetxt(f, np.column_stack([t, q, p]), fmt="%.17g", delimiter=",")
    files["CSV"] = (d / "a.csv", ",", 1)
    with open(d / "data.csv", "w") as f:
        f.write("#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],")
        f.write("q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n")
        body = np.column_stack([p, q])
        for k in range(0, n, 50_000):
            lines = [
                f"{s}," + ",".join(f"{v:.17g}" for v in row)
                for s, row in zip(ns[k : k + 50_000], body[k : k + 50_000])
            ]
            f.write("\n".join(lines) + "\n")
    files["EuRoC"] = (d / "data.csv", ",", 1)
    with open(d / "k.txt", "w") as f:
        rows = np.concatenate([as_matrix(q), p[:, :, None]], axis=2).reshape(-1, 12)
        np.savetxt(f, rows, fmt="%.17g")
    files["KITTI"] = (d / "k.txt", " ", 0)
    return files


def best(fn, repeat: int) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def careful_read(path):
    orig = _fast.table
    _fast.table = lambda *a, **k: None
    try:
        return qio.read(path)
    finally:
        _fast.table = orig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=500_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    import pandas as pd

    print(f"{args.rows} rows, best of {args.repeat}, {cpu()}, pandas {pd.__version__}")
    print("| format | careful parser (s) | fast path (s) | speed-up | pandas.read_csv (s) | "
          "numpy.loadtxt (s) |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (path, sep, skip) in make_files(Path(tmp), args.rows).items():
            qio.read(path)  # warm up (imports, page cache)
            fast = best(lambda path=path: qio.read(path), args.repeat)
            slow = best(lambda path=path: careful_read(path), max(1, args.repeat - 1))
            pdt = best(
                lambda path=path, sep=sep, skip=skip: pd.read_csv(
                    path, sep=sep, header=None, skiprows=skip
                ),
                args.repeat,
            )
            npt = best(
                lambda path=path, sep=sep, skip=skip: np.loadtxt(
                    path, delimiter=None if sep == " " else sep, skiprows=skip, comments=None
                ),
                1,
            )
            a, b = qio.read(path), careful_read(path)
            same = np.array_equal(a.times, b.times) and np.array_equal(a.quats, b.quats)
            print(
                f"| {name} | {slow:.2f} | {fast:.2f} | {slow / fast:.1f}× | {pdt:.2f} | "
                f"{npt:.2f} |" + ("" if same else " (results differ!)")
            )


if __name__ == "__main__":
    main()
