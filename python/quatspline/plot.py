"""Figures people would rather look at than read (matplotlib, ``pip install 'quatspline[plot]'``).

- ``sphere``: the body axes' tips on the unit sphere along the motion, keys marked, arrows for
  the direction of travel (as the Beta paper's Fig. 2);
- ``body``: the path of the body (positions when given) with snapshots of a rigid box with
  coloured axes, each labelled with its time (Fig. 3);
- ``rates``: angular speed, acceleration and jerk versus time, keys marked sparsely (Squad
  article Fig. 1.1);
- ``family``: one shape parameter swept, the body x-axis (solid) and z-axis (dashed) path for
  each value (Fig. 4).

Every function takes ``ax=`` (an Axes, 3-D for sphere/body/family) or ``fig=`` (a Figure to
draw into) and returns the Figure. Without them a new ``matplotlib.figure.Figure`` is made
without pyplot, so the user's backend and pyplot state are never touched. Axes carry
quantities and units; legends explain colours and line styles; titles come from the data
(``name=`` e.g. the recording) unless ``title=`` is given. ``save(fig, path)`` writes a
figure atomically.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._util.atomic import atomic_write
from ._util.optional import need
from .core.algebra import rotate

AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # x red, y green, z blue
MAX_MARKERS = 40


def _mpl():
    matplotlib = need("matplotlib", extra="plot", what="plots")
    figure = need("matplotlib.figure", extra="plot", what="plots")
    lines = need("matplotlib.lines", extra="plot", what="plots")
    return matplotlib, figure.Figure, lines.Line2D


def _axes(ax, fig, figsize, projection=None):
    """(figure, axes): the given axes, a new subplot of the given figure, or a new Figure."""
    _, Figure, _ = _mpl()
    if ax is not None:
        if projection == "3d" and getattr(ax, "name", "") != "3d":
            raise ValueError("ax: expected 3-D axes (projection='3d') for this plot")
        return ax.figure, ax
    if fig is None:
        fig = Figure(figsize=figsize, layout="constrained")
    elif not hasattr(fig, "add_subplot"):
        raise TypeError(f"fig: expected a matplotlib Figure, got {type(fig).__name__}")
    return fig, fig.add_subplot(projection=projection)


def thin(n: int, max_markers: int = MAX_MARKERS) -> np.ndarray:
    """Indices of at most ``max_markers`` evenly spread items out of ``n`` (first and last
    kept): key markers stay readable on dense recordings.

    Examples
    --------
    >>> thin(5).tolist(), len(thin(10_000)), int(thin(10_000)[-1])
    ([0, 1, 2, 3, 4], 40, 9999)
    """
    if n <= max_markers:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, max_markers)).astype(int))


def _key_label(n_all: int, n_shown: int) -> str:
    return f"keys ({n_all})" if n_all == n_shown else f"keys ({n_shown} of {n_all} shown)"


def _title(kind: str, spline, name: str) -> str:
    what = f"{spline.method} spline"
    return f"{name}: {kind} ({what})" if name else f"{kind} ({what})"


def _sphere_wire(ax):
    u, v = np.mgrid[0 : 2 * np.pi : 40j, 0 : np.pi : 20j]
    ax.plot_wireframe(
        np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.88", linewidth=0.4
    )
    ax.set_box_aspect((1, 1, 1))
    for lim in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        lim(-1.05, 1.05)
    ax.set_xlabel("world x (unit vector)")
    ax.set_ylabel("world y (unit vector)")
    ax.set_zlabel("world z (unit vector)")


def _arrows(ax, p: np.ndarray, colour, count: int = 5, length: float = 0.12):
    """Arrowheads along a 3-D polyline, pointing in the direction of travel."""
    n = len(p)
    if n < 3:
        return
    for k in np.linspace(n * 0.1, n * 0.9, count).astype(int):
        d = p[min(k + 1, n - 1)] - p[max(k - 1, 0)]
        nd = np.linalg.norm(d)
        if nd > 0:
            ax.quiver(*p[k], *(d / nd * length), color=colour, arrow_length_ratio=0.6, lw=1.2)


def sphere(
    spline, key_times=None, n: int = 600, title: str = "", name: str = "", ax=None, fig=None
):
    """Body axes' tips on the unit sphere; keys (thinned to ≤ 40 markers), start and end,
    direction arrows."""
    _, _, Line2D = _mpl()
    fig, ax = _axes(ax, fig, (6.4, 6.0), "3d")
    t, q = spline.sample(n=n)
    _sphere_wire(ax)
    handles = []
    kt = None
    if key_times is not None:
        kt_all = np.clip(np.asarray(key_times, dtype=float), *spline.domain)
        kt = kt_all[thin(len(kt_all))]
    for k, (axis, colour) in enumerate(zip(np.eye(3), AXIS_COLOURS)):
        p = rotate(q, axis)
        (h,) = ax.plot(p[:, 0], p[:, 1], p[:, 2], color=colour, lw=2, label=f"body {'xyz'[k]} axis")
        handles.append(h)
        _arrows(ax, p, colour)
        ax.scatter(*p[0], color=colour, s=40, marker="o", edgecolor="k", zorder=6)
        ax.scatter(*p[-1], color=colour, s=50, marker="s", edgecolor="k", zorder=6)
        if kt is not None:
            pk = rotate(spline(kt), axis)
            ax.scatter(pk[:, 0], pk[:, 1], pk[:, 2], color=colour, s=14, edgecolor="k", zorder=5)
    if kt is not None:
        handles.append(
            Line2D(
                [],
                [],
                ls="",
                marker="o",
                mfc="w",
                mec="k",
                ms=4,
                label=_key_label(len(kt_all), len(kt)),
            )
        )
    handles.append(Line2D([], [], ls="", marker="o", mfc="0.6", mec="k", label="start"))
    handles.append(Line2D([], [], ls="", marker="s", mfc="0.6", mec="k", label="end"))
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    ax.set_title(title or _title("body axes on the unit sphere", spline, name))
    return fig


def _box_edges(size=(1.0, 0.6, 0.3)):
    sx, sy, sz = (s / 2 for s in size)
    corners = np.array([[x, y, z] for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)])
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    return corners, edges


def body(
    spline,
    positions=None,
    snapshots: int = 8,
    title: str = "",
    name: str = "",
    t0: float = 0.0,
    time_unit: str = "s",
    length_unit: str = "m",
    ax=None,
    fig=None,
):
    """The path (``positions``: a callable t → (M, 3), or None to lay the boxes out along x)
    with direction arrows, and ``snapshots`` boxes labelled with their times (``t0`` is added
    to the labels, e.g. a recording's first stamp)."""
    _, _, Line2D = _mpl()
    fig, ax = _axes(ax, fig, (8.0, 5.5), "3d")
    t = np.linspace(*spline.domain, snapshots)
    q = spline(t)
    tt = np.linspace(*spline.domain, 600)
    if positions is None:
        pos = np.column_stack(
            [np.arange(snapshots) * 1.6, np.zeros(snapshots), np.zeros(snapshots)]
        )
        path = np.column_stack([np.linspace(0, pos[-1, 0], 600), np.zeros(600), np.zeros(600)])
        scale, unit = 1.0, "layout"
    else:
        pos = np.asarray(positions(t))
        path = np.asarray(positions(tt))
        span = max(float(np.ptp(path, axis=0).max()), 1e-9)
        scale, unit = span / max(snapshots, 2), length_unit
    ax.plot(*path.T, color="0.35", lw=1.2, ls="-")
    _arrows(ax, path, "0.35", count=4, length=0.6 * scale)
    corners, edges = _box_edges()
    for m in range(snapshots):
        c = rotate(q[m], corners * scale) + pos[m]
        for a, b in edges:
            ax.plot(*zip(c[a], c[b]), color="0.55", lw=0.8)
        for k in range(3):
            tip = rotate(q[m], np.eye(3)[k] * 0.8 * scale) + pos[m]
            ax.plot(*zip(pos[m], tip), color=AXIS_COLOURS[k], lw=2)
        ax.text(*(pos[m] + [0, 0, 0.7 * scale]), f"{t[m] + t0:.6g} {time_unit}", fontsize=7)
    lo, hi = (
        np.minimum(path.min(0), pos.min(0)) - scale,
        np.maximum(path.max(0), pos.max(0)) + scale,
    )
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-9)))
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.set_zlabel(f"z ({unit})")
    handles = [Line2D([], [], color="0.35", label="path (arrows: direction of travel)")]
    handles += [
        Line2D([], [], color=c, lw=2, label=f"body {'xyz'[k]} axis")
        for k, c in enumerate(AXIS_COLOURS)
    ]
    handles.append(Line2D([], [], color="0.55", lw=0.8, label=f"body at {snapshots} times"))
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    ax.set_title(title or _title("rigid body along the motion", spline, name))
    return fig


_RATES = {
    "omega": ("angular_velocity", "|ω|", "rad/{u}", "#1f77b4"),
    "alpha": ("angular_acceleration", "|α|", "rad/{u}²", "#ff7f0e"),
    "jerk": ("jerk", "|dα/dt|", "rad/{u}³", "#9467bd"),
}


def rates(
    spline,
    key_times=None,
    n: int = 2000,
    title: str = "",
    name: str = "",
    show=("omega", "alpha"),
    time_unit: str = "s",
    t0: float = 0.0,
    fig=None,
    ax=None,
    band: bool = False,
):
    """Angular speed |ω|, acceleration |α| and jerk |dα/dt| (any of ``show``) versus time,
    one panel each; keys as thin vertical lines and markers (at most 40). ``ax`` may be one
    Axes (with one quantity) or a sequence with one Axes per quantity.

    ``band=True`` (a fit with a posterior, :func:`quatspline.fit` with λ > 0) shades
    |ω| ± 2σ on the angular-speed panel: σ² = ûᵀ Cov(ω) û, û = ω/|ω|, the first-order
    variance of |ω| from :meth:`quatspline.FittedSpline.angular_velocity_covariance`
    (reliable where |ω| is well above σ; the band is clipped at 0)."""
    _, Figure, Line2D = _mpl()
    show = tuple(show)
    bad = [s for s in show if s not in _RATES]
    if bad or not show:
        raise ValueError(f"show: expected some of {', '.join(_RATES)}, got {show!r}")
    if not isinstance(band, (bool, np.bool_)):
        raise TypeError(f"band: expected a bool, got {type(band).__name__}")
    if band and not hasattr(spline, "angular_velocity_covariance"):
        raise TypeError(
            f"band: needs a fitted spline (quatspline.fit), got {type(spline).__name__}"
        )
    if ax is not None:
        axes = list(np.atleast_1d(ax))
        if len(axes) != len(show):
            raise ValueError(f"ax: expected {len(show)} axes (one per quantity), got {len(axes)}")
        fig = axes[0].figure
    else:
        if fig is None:
            fig = Figure(figsize=(8.0, 2.2 + 1.8 * len(show)), layout="constrained")
        axes = list(np.atleast_1d(fig.subplots(len(show), 1, sharex=True)))
    t = np.linspace(*spline.domain, n)
    kt = None
    if key_times is not None:
        kt_all = np.clip(np.asarray(key_times, dtype=float), *spline.domain)
        kt = kt_all[thin(len(kt_all))]
    for a, what in zip(axes, show):
        fn, sym, unit, colour = _RATES[what]
        f = getattr(spline, fn)
        v = f(t)
        y = np.linalg.norm(v, axis=1)
        a.plot(t + t0, y, color=colour, lw=1.5, label=sym)
        handles = [Line2D([], [], color=colour, lw=1.5, label=f"{sym} of the spline")]
        if band and what == "omega":
            patch = need("matplotlib.patches", extra="plot", what="plots").Patch
            u = v / np.maximum(y, 1e-300)[:, None]
            sd = np.sqrt(np.einsum("ni,nij,nj->n", u, spline.angular_velocity_covariance(t), u))
            a.fill_between(t + t0, np.maximum(y - 2 * sd, 0), y + 2 * sd, color=colour, alpha=0.25)
            handles.append(patch(color=colour, alpha=0.25, label="± 2σ (posterior)"))
        if kt is not None:
            for k in kt:
                a.axvline(k + t0, color="0.85", lw=0.6, zorder=0)
            a.plot(kt + t0, np.linalg.norm(f(kt), axis=1), "k.", ms=4)
            handles.append(
                Line2D([], [], color="k", marker=".", ls="", label=_key_label(len(kt_all), len(kt)))
            )
        a.set_ylabel(f"{sym} ({unit.format(u=time_unit)})")
        a.legend(handles=handles, loc="upper right", fontsize=8)
        a.grid(alpha=0.3)
    axes[-1].set_xlabel(f"time ({time_unit})")
    names = {"omega": "angular speed", "alpha": "acceleration", "jerk": "jerk"}
    kind = ", ".join(names[s] for s in show)
    if ax is not None:
        axes[0].set_title(title or _title(kind, spline, name))
    else:
        fig.suptitle(title or _title(kind, spline, name))
    return fig


def family(splines: dict, n: int = 600, title: str = "", name: str = "", ax=None, fig=None):
    """``splines``: label → Spline (one shape parameter swept); the body x axis (solid) and
    z axis (dashed) of each, colour by label."""
    matplotlib, _, Line2D = _mpl()
    fig, ax = _axes(ax, fig, (6.4, 6.0), "3d")
    _sphere_wire(ax)
    cmap = matplotlib.colormaps["viridis"]
    styles = {0: "-", 2: "--"}
    handles = []
    for k, (label, s) in enumerate(splines.items()):
        _, q = s.sample(n=n)
        colour = cmap(k / max(len(splines) - 1, 1))
        for axis, style in styles.items():
            p = rotate(q, np.eye(3)[axis])
            ax.plot(p[:, 0], p[:, 1], p[:, 2], style, color=colour, lw=2)
            if axis == 0:
                _arrows(ax, p, colour, count=2)
        handles.append(Line2D([], [], color=colour, lw=2, label=str(label)))
    handles.append(Line2D([], [], color="0.3", ls="-", label="body x axis"))
    handles.append(Line2D([], [], color="0.3", ls="--", label="body z axis"))
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    method = next(iter(splines.values())).method if splines else ""
    default = f"{method} shape parameter family" + (f" ({name})" if name else "")
    ax.set_title(title or default)
    return fig


def save(fig, path) -> None:
    """Writes the figure atomically; the format follows the extension (png, svg, pdf)."""
    path = Path(path)
    ext = path.suffix.lower().lstrip(".")
    if ext not in ("png", "svg", "pdf"):
        raise ValueError(f"{path}: expected a .png, .svg or .pdf output")
    with atomic_write(path, mode="wb") as f:
        fig.savefig(f, format=ext, dpi=110)
