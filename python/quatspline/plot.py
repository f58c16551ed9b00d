"""Figures people would rather look at than read (matplotlib, headless).

- ``sphere``: the body axes' tips on the unit sphere along the motion, keys marked (as the
  Beta paper's Fig. 2);
- ``body``: snapshots of a rigid box with coloured axes along the motion (Fig. 3);
- ``rates``: angular speed and acceleration versus time, keys marked (Squad article Fig. 1.1);
- ``family``: one shape parameter swept, the body x-axis path for each value (Fig. 4).

Each function returns a matplotlib Figure; ``save(fig, path)`` writes it atomically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._atomic import atomic_write
from .algebra import rotate
from .spline import Spline

AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # x red, y green, z blue


def _plt():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("plots need matplotlib: pip install 'quatspline[plot]'") from e
    return plt


def _sphere_wire(ax):
    u, v = np.mgrid[0 : 2 * np.pi : 40j, 0 : np.pi : 20j]
    ax.plot_wireframe(
        np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.85", linewidth=0.4
    )
    ax.set_box_aspect((1, 1, 1))
    for lim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        lim(-1.05, 1.05)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")


def sphere(spline: Spline, key_times=None, n: int = 600, title: str = ""):
    plt = _plt()
    t, q = spline.sample(n=n)
    fig = plt.figure(figsize=(6.4, 6.0))
    ax = fig.add_subplot(projection="3d")
    _sphere_wire(ax)
    for k, (axis, colour) in enumerate(zip(np.eye(3), AXIS_COLOURS)):
        p = rotate(q, axis)
        ax.plot(p[:, 0], p[:, 1], p[:, 2], color=colour, linewidth=2, label=f"body {'xyz'[k]} axis")
        if key_times is not None:
            kt = np.clip(np.asarray(key_times), *spline.domain)
            pk = rotate(spline(kt), axis)
            ax.scatter(pk[:, 0], pk[:, 1], pk[:, 2], color=colour, s=25, edgecolor="k", zorder=5)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title or f"{spline.method}: body axes on the unit sphere")
    return fig


def _box_edges(size=(1.0, 0.6, 0.3)):
    sx, sy, sz = (s / 2 for s in size)
    corners = np.array([[x, y, z] for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)])
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    return corners, edges


def body(spline: Spline, positions=None, snapshots: int = 8, title: str = ""):
    """Boxes at ``snapshots`` times; ``positions`` is a callable t → (M, 3) or None (the boxes
    are then laid out along x)."""
    plt = _plt()
    t = np.linspace(*spline.domain, snapshots)
    q = spline(t)
    if positions is None:
        pos = np.column_stack(
            [np.arange(snapshots) * 1.6, np.zeros(snapshots), np.zeros(snapshots)]
        )
        scale = 1.0
    else:
        pos = np.asarray(positions(t))
        span = np.ptp(pos, axis=0).max()
        scale = max(span / snapshots, 1e-9)
    corners, edges = _box_edges()
    fig = plt.figure(figsize=(8.0, 5.0))
    ax = fig.add_subplot(projection="3d")
    for m in range(snapshots):
        c = rotate(q[m], corners * scale) + pos[m]
        shade = str(0.15 + 0.6 * m / max(snapshots - 1, 1))
        for a, b in edges:
            ax.plot(*zip(c[a], c[b]), color=shade, linewidth=1)
        for k in range(3):
            tip = rotate(q[m], np.eye(3)[k] * 0.8 * scale) + pos[m]
            ax.plot(*zip(pos[m], tip), color=AXIS_COLOURS[k], linewidth=2)
    ax.set_box_aspect(
        (
            np.ptp(pos[:, 0]) + 2 * scale,
            np.ptp(pos[:, 1]) + 2 * scale,
            np.ptp(pos[:, 2]) + 2 * scale,
        )
    )
    ax.set_title(title or f"{spline.method}: rigid body along the motion")
    return fig


def rates(spline: Spline, key_times=None, n: int = 2000, title: str = ""):
    plt = _plt()
    t = np.linspace(*spline.domain, n)
    w = np.linalg.norm(spline.angular_velocity(t), axis=1)
    a = np.linalg.norm(spline.angular_acceleration(t), axis=1)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8.0, 5.5), sharex=True)
    ax1.plot(t, w, color="#1f77b4")
    ax1.set_ylabel("|ω| (rad / time unit)")
    ax2.plot(t, a, color="#ff7f0e")
    ax2.set_ylabel("|α| (rad / time unit²)")
    ax2.set_xlabel("time")
    if key_times is not None:
        for ax in (ax1, ax2):
            for k in key_times:
                ax.axvline(k, color="0.8", linewidth=0.6, zorder=0)
        kt = np.clip(np.asarray(key_times), *spline.domain)
        ax1.plot(kt, np.linalg.norm(spline.angular_velocity(kt), axis=1), "k.", markersize=4)
    fig.suptitle(title or f"{spline.method}: angular speed and acceleration")
    fig.tight_layout()
    return fig


def family(splines: dict, n: int = 600, title: str = ""):
    """``splines``: label → Spline (one shape parameter swept); the body x axis (solid) and
    z axis (dashed) of each."""
    plt = _plt()
    fig = plt.figure(figsize=(6.4, 6.0))
    ax = fig.add_subplot(projection="3d")
    _sphere_wire(ax)
    cmap = plt.get_cmap("viridis")
    styles = {0: "-", 2: "--"}
    for k, (label, s) in enumerate(splines.items()):
        _, q = s.sample(n=n)
        colour = cmap(k / max(len(splines) - 1, 1))
        for axis, style in styles.items():
            p = rotate(q, np.eye(3)[axis])
            ax.plot(
                p[:, 0],
                p[:, 1],
                p[:, 2],
                style,
                color=colour,
                linewidth=2,
                label=label if axis == 0 else None,
            )
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title or "shape parameter family: body x (solid) and z (dashed) axes")
    return fig


def save(fig, path) -> None:
    """Writes the figure atomically; the format follows the extension (png, svg, pdf)."""
    path = Path(path)
    ext = path.suffix.lower().lstrip(".")
    if ext not in ("png", "svg", "pdf"):
        raise ValueError(f"{path}: expected a .png, .svg or .pdf output")
    with atomic_write(path, mode="wb") as f:
        fig.savefig(f, format=ext, dpi=110)
    _plt().close(fig)
