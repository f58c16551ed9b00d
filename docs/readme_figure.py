"""The README's figure: a designed C³ motion on the unit sphere, and a recording's angular speed
through its noisy samples (natural spline) against the fit. ``python docs/readme_figure.py``
writes ``docs/_static/readme.png``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import quatspline as qs
from matplotlib.figure import Figure
from quatspline import plot

OUT = Path(__file__).resolve().parent / "_static" / "readme.png"


def main() -> None:
    fig = Figure(figsize=(11.0, 4.2), layout="constrained")
    left = fig.add_subplot(1, 2, 1, projection="3d")
    right = fig.add_subplot(1, 2, 2)

    keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [45, 0, 90], [45, 30, 120]], degrees=True)
    times = [0.0, 1.0, 2.5, 3.0]
    plot.sphere(qs.C3Spline(keys, times), times, title="designed keys: C³ spline", ax=left)

    rec = qs.examples.load_recording()
    t, q = rec.times[:400] - rec.times[0], rec.quats[:400]
    through = qs.NaturalSpline(q, t)
    fitted = qs.fit(t, q)
    grid = np.linspace(t[0], t[-1], 4000)
    for s, label, width in (
        (through, "natural spline through every sample", 0.6),
        (fitted, "qs.fit (smoothing by GCV)", 1.6),
    ):
        right.plot(grid, np.linalg.norm(s.angular_velocity(grid), axis=1), lw=width, label=label)
    right.set_xlabel("time (s)")
    right.set_ylabel("angular speed ‖ω‖ (rad/s)")
    right.set_title("TUM RGB-D fr1/xyz: 4 s of motion capture")
    right.legend(loc="upper right")
    fig.savefig(OUT, dpi=90)


if __name__ == "__main__":
    main()
