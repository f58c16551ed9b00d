"""glTF export key counts.

1. The adaptive key reduction against a uniform resampling that meets the same bound, on the
   bundled TUM RGB-D fr1/xyz recording (3,000 poses, 30 s) through the default spline, with
   no key limit (``max_keys=None``). The playback error is measured by the exporter on a grid
   4× denser than its candidate keys (tests/ops/test_gltf.py re-measures it with pygltflib +
   scipy on random times; tests/blender plays the files in Blender).
2. The defaults on recordings: the bundled one and a dense noisy one (10⁴ samples at 100 Hz,
   σ = 1 mrad and 1 mm on a smooth motion), exported with the default bounds (0.01°,
   0.1 mm) and the default key limit (the sample count), by the default spline and by
   ``method="fit"``: keys, the bound met, the file against the samples as float32.

    python benchmarks/gltf_keys.py [--defaults-only]
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import quatspline as qs
from quatspline.examples import load_recording
from quatspline.ops import to_gltf


def noisy(n=10_000, rate=100.0, noise=1e-3, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    rv = np.column_stack([np.sin(0.5 * t), np.cos(0.3 * t), 0.2 * t])
    p = np.column_stack([np.sin(t), np.cos(0.7 * t), 0.1 * t])
    q = qs.from_rotvec(rv + rng.normal(0, noise, rv.shape))
    return qs.io.Trajectory(t, q, p + rng.normal(0, noise, p.shape), name="noisy")


def adaptive_vs_uniform(d: Path) -> None:
    traj = load_recording()
    print(f"{len(traj)} poses over {traj.times[-1] - traj.times[0]:.1f} s (natural pose spline)")
    print(
        "| interpolation | bound (rotation / position) | rotation keys | uniform needs | "
        "measured max error | translation keys | uniform needs | file size | time (s) |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for interp in ("linear", "cubicspline"):
        for rot, pos in (("0.01deg", "0.1mm"), ("0.1deg", "1mm")):
            path = d / "m.glb"
            t0 = time.perf_counter()
            r = to_gltf(traj, path, max_error=rot, max_position_error=pos, interpolation=interp,
                        uniform=True, max_keys=None, progress=False)  # fmt: skip
            dt = time.perf_counter() - t0
            u = r.rotation_uniform_keys
            print(
                f"| {interp.upper()} | {rot} / {pos} | {r.rotation_keys} | "
                f"{u if u > 0 else '> 8×'} | {np.degrees(r.rotation_error):.4g}° / "
                f"{r.translation_error * 1e3:.3g} mm | {r.translation_keys} | "
                f"{r.translation_uniform_keys if r.translation_uniform_keys > 0 else '> 8×'} | "
                f"{path.stat().st_size / 1024:.0f} KiB | {dt:.1f} |"
            )


def defaults(d: Path) -> None:
    print(
        "| recording | samples | method | rotation keys | bound met | translation keys | "
        "bound met | .glb | samples as float32 | time (s) |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, traj in (("fr1/xyz", load_recording()), ("noisy 10⁴", noisy())):
        for method in (None, "fit"):
            path = d / "m.glb"
            t0 = time.perf_counter()
            r = to_gltf(traj, path, method=method, progress=False)
            dt = time.perf_counter() - t0
            print(
                f"| {name} | {len(traj)} | {method or 'default (natural)'} | {r.rotation_keys} | "
                f"{np.degrees(r.rotation_bound):.3g}° | {r.translation_keys} | "
                f"{r.translation_bound * 1e3:.3g} mm | {path.stat().st_size / 1024:.0f} KiB | "
                f"{len(traj) * 8 * 4 / 1024:.0f} KiB | {dt:.1f} |"
            )


def main() -> None:
    with tempfile.TemporaryDirectory() as d:
        if "--defaults-only" not in sys.argv:
            adaptive_vs_uniform(Path(d))
            print()
        defaults(Path(d))


if __name__ == "__main__":
    main()
