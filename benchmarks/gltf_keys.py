"""glTF export key counts: the adaptive key reduction against a uniform resampling that meets
the same bound, on the bundled TUM RGB-D fr1/xyz recording (3,000 poses, 30 s), through the
C³ pose spline. The playback error is measured by the exporter on a grid 4× denser than its
candidate keys (tests/test_gltf.py re-measures it with pygltflib + scipy on random times).

    python benchmarks/gltf_keys.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np
from quatspline.examples import load_recording
from quatspline.ops import to_gltf


def main() -> None:
    traj = load_recording()
    print(f"{len(traj)} poses over {traj.times[-1] - traj.times[0]:.1f} s (c3 pose spline)")
    print(
        "| interpolation | bound (rotation / position) | rotation keys | uniform needs | "
        "measured max error | translation keys | uniform needs | file size | time (s) |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as d:
        for interp in ("linear", "cubicspline"):
            for rot, pos in (("0.01deg", "0.1mm"), ("0.1deg", "1mm")):
                path = Path(d) / "m.glb"
                t0 = time.perf_counter()
                r = to_gltf(traj, path, max_error=rot, max_position_error=pos,
                            interpolation=interp, progress=False)  # fmt: skip
                dt = time.perf_counter() - t0
                u = r.rotation_uniform_keys
                print(
                    f"| {interp.upper()} | {rot} / {pos} | {r.rotation_keys} | "
                    f"{u if u > 0 else '> 8×'} | {np.degrees(r.rotation_error):.4g}° / "
                    f"{r.translation_error * 1e3:.3g} mm | {r.translation_keys} | "
                    f"{r.translation_uniform_keys if r.translation_uniform_keys > 0 else '> 8×'} | "
                    f"{path.stat().st_size / 1024:.0f} KiB | {dt:.1f} |"
                )


if __name__ == "__main__":
    main()
