"""Figures people would rather look at than read (matplotlib, ``pip install 'quatspline[plot]'``).

- ``sphere``: the body axes' tips on the unit sphere along the motion, keys marked, arrows for
  the direction of travel (as the Beta paper's Fig. 2);
- ``body``: the path of the body (positions when given) with snapshots of a rigid box with
  coloured axes at round times since the start, each labelled, in an orthographic view with
  equal scales on the three axes (Fig. 3);
- ``rates``: angular speed, acceleration and jerk versus time, keys marked sparsely (Squad
  article Fig. 1.1);
- ``family``: one shape parameter swept, the body x-axis (solid) and z-axis (dashed) path for
  each value (Fig. 4), beside the angle of each member from the first versus time;
- ``fitted``: a fit against its data: the measured orientations (Euler angles) and the fitted
  curve, the residual angle of every sample with its RMS, the angular speed, and for a pose
  fit the positions and their residuals.

Every function takes ``ax=`` (an Axes, 3-D for sphere/body/family) or ``fig=`` (a Figure to
draw into) and returns the Figure. Without them a new ``matplotlib.figure.Figure`` is made
without pyplot, so the user's backend and pyplot state are never touched. Axes carry
quantities and units; legends explain colours and line styles; titles come from the data
(``name=`` e.g. the recording) unless ``title=`` is given. ``save(fig, path)`` writes a
figure atomically.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ._util.atomic import atomic_write
from ._util.optional import need
from .core.algebra import rotate
from .core.convert import as_euler
from .core.metrics import angle_between

AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # x red, y green, z blue
MAX_MARKERS = 40
_STYLES = ("-", "--", "-.", ":")


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
    for lim, ticks in (
        (ax.set_xlim, ax.set_xticks),
        (ax.set_ylim, ax.set_yticks),
        (ax.set_zlim, ax.set_zticks),
    ):
        lim(-1.05, 1.05)
        ticks([-1.0, -0.5, 0.0, 0.5, 1.0])
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


def _nice_step(span: float, count: int) -> float:
    """The smallest round step (1, 2, 2.5 or 5 × 10ᵏ) that puts at most ``count`` marks, ends
    included, on ``[0, span]``.

    Examples
    --------
    >>> _nice_step(30.2, 10), _nice_step(2.0, 8), _nice_step(0.07, 4)
    (5.0, 0.5, 0.025)
    """
    if not span > 0 or count < 2:
        return float(span) if span > 0 else 1.0
    raw = span / (count - 1)
    k = math.floor(math.log10(raw))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        step = float(f"{m}e{k}")
        if step >= raw * (1 - 1e-12):
            return step
    return float(f"1e{k + 1}")  # pragma: no cover (10 × 10ᵏ always qualifies)


def _decimals(step: float) -> int:
    """Decimal places that write every multiple of ``step`` exactly (at most 12).

    Examples
    --------
    >>> _decimals(5.0), _decimals(0.5), _decimals(0.025), _decimals(250.0)
    (0, 1, 3, 0)
    """
    for d in range(13):
        if abs(round(step, d) - step) <= 1e-9 * step:
            return d
    return 12


def _time_note(t0: float, unit: str) -> str:
    """How to read relative times: '' when the clock starts at 0."""
    return "" if t0 == 0 else f"times after t₀ = {t0:.15g} {unit}"


def _place_labels(ax, texts, anchors) -> None:
    """Keeps the time labels of a 3-D plot apart on the page: each label goes above its box,
    else below, right or left of it, else is hidden; the first and the last are placed first.
    ``anchors``: per label, the box's centre and its half height in data units. Judged on the
    figure as laid out now (one draw); labels keep their size relative to the axes when saved
    at another dpi."""
    proj3d = need("mpl_toolkits.mplot3d.proj3d", extra="plot", what="plots")
    transforms = need("matplotlib.transforms", extra="plot", what="plots")
    fig = ax.figure
    fig.draw_without_rendering()
    m = ax.get_proj()

    def display(p):
        x, y, _ = proj3d.proj_transform(*p, m)
        return ax.transData.transform((x, y))

    order = list(range(len(texts)))
    if len(order) > 1:
        order = [0, order[-1], *order[1:-1]]
    kept = []
    for i in order:
        text, (centre, half) = texts[i], anchors[i]
        box = text.get_window_extent()
        w, h = box.width, box.height
        up = np.array([0.0, 0.0, half])
        (xt, yt), (xb, yb), (x, y) = display(centre + up), display(centre - up), display(centre)
        reach = max(abs(yt - y), 4.0)
        options = [  # (where, horizontal and vertical alignment, page offset, rectangle)
            (centre + up, "center", "bottom", 0.0, (xt - w / 2, yt, xt + w / 2, yt + h)),
            (centre - up, "center", "top", 0.0, (xb - w / 2, yb - h, xb + w / 2, yb)),
            (centre, "left", "center", reach, (x + reach, y - h / 2, x + reach + w, y + h / 2)),
            (centre, "right", "center", -reach, (x - reach - w, y - h / 2, x - reach, y + h / 2)),
        ]
        for where, ha, va, dx, rect in options:
            if any(_overlap(rect, r) for r in kept):
                continue
            text.set_position_3d(where)
            text.set_horizontalalignment(ha)
            text.set_verticalalignment(va)
            if dx:
                text.set_transform(
                    transforms.offset_copy(
                        ax.transData, fig=fig, x=dx * 72 / fig.dpi, units="points"
                    )
                )
            kept.append(rect)
            break
        else:
            text.set_visible(False)


def _overlap(a, b, pad: float = 2.0) -> bool:
    return a[0] < b[2] + pad and b[0] < a[2] + pad and a[1] < b[3] + pad and b[1] < a[3] + pad


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
    with direction arrows, and at most ``snapshots`` boxes at round times since the start of
    the motion, each labelled with that time (a label that would collide with another on the
    page is moved below or beside its box, or left out). ``t0`` is the clock reading at the
    spline's time 0 (e.g. a recording's first stamp): when the motion starts at another
    reading, the title says so once (``times after t₀ = …``). The view is orthographic with
    equal scales on all three axes.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> s = qs.C3Spline(qs.from_axis_angle([0, 0, 1], [0.0, 1.0, 2.0]), [0.0, 15.0, 30.5])
    >>> ax = body(s, snapshots=10, t0=1.4e9).axes[0]
    >>> [t.get_text() for t in ax.texts][:3], ax.get_title().splitlines()[-1]
    (['0 s', '5 s', '10 s'], 'times after t₀ = 1400000000 s')
    """
    _, _, Line2D = _mpl()
    fig, ax = _axes(ax, fig, (8.0, 6.2), "3d")
    a, b = spline.domain
    step = _nice_step(b - a, max(int(snapshots), 2))
    # round times; a last mark within step/1000 of the end stands at the end
    rel = np.arange(int(np.floor((b - a) / step + 1e-3)) + 1) * step
    t = np.minimum(a + rel, b)
    count = len(t)
    q = spline(t)
    tt = np.linspace(a, b, 600)
    if positions is None:
        pos = np.column_stack([np.arange(count) * 1.6, np.zeros(count), np.zeros(count)])
        path = np.column_stack([np.linspace(0, pos[-1, 0], 600), np.zeros(600), np.zeros(600)])
        scale, unit = 1.0, "layout"
    else:
        pos = np.asarray(positions(t))
        path = np.asarray(positions(tt))
        span = max(float(np.ptp(path, axis=0).max()), 1e-9)
        scale, unit = span / max(count, 2), length_unit
    ax.set_proj_type("ortho")
    ax.plot(*path.T, color="0.35", lw=1.2, ls="-")
    _arrows(ax, path, "0.35", count=4, length=0.6 * scale)
    corners, edges = _box_edges()
    d = _decimals(step)
    texts, anchors = [], []
    for m in range(count):
        c = rotate(q[m], corners * scale) + pos[m]
        for i, j in edges:
            ax.plot(*zip(c[i], c[j]), color="0.55", lw=0.8)
        for k in range(3):
            tip = rotate(q[m], np.eye(3)[k] * 0.8 * scale) + pos[m]
            ax.plot(*zip(pos[m], tip), color=AXIS_COLOURS[k], lw=2)
        up = pos[m] + [0, 0, 0.75 * scale]
        texts.append(
            ax.text(
                *up,
                f"{rel[m]:.{d}f} {time_unit}",
                fontsize=8,
                ha="center",
                va="bottom",
                bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.8},
                in_layout=False,  # placed after the layout (see _place_labels)
            )
        )
        anchors.append((pos[m], 0.75 * scale))
    lo, hi = (
        np.minimum(path.min(0), pos.min(0)) - scale,
        np.maximum(path.max(0), pos.max(0)) + scale,
    )
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    aspect = np.maximum(hi - lo, 1e-9)
    ax.set_box_aspect(tuple(aspect))
    ticker = need("matplotlib.ticker", extra="plot", what="plots")
    for axis, share in zip((ax.xaxis, ax.yaxis, ax.zaxis), aspect / aspect.max()):
        axis.set_major_locator(ticker.MaxNLocator(nbins=max(2, round(7 * share))))
    ax.set_xlabel(f"x ({unit})")
    ax.set_ylabel(f"y ({unit})")
    ax.set_zlabel(f"z ({unit})")
    handles = [Line2D([], [], color="0.35", label="path (arrows: direction of travel)")]
    handles += [
        Line2D([], [], color=c, lw=2, label=f"body {'xyz'[k]} axis")
        for k, c in enumerate(AXIS_COLOURS)
    ]
    handles.append(
        Line2D(
            [],
            [],
            color="0.55",
            lw=0.8,
            label=f"body every {rel[1] if count > 1 else 0:.{d}f} {time_unit}",
        )
    )
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    note = _time_note(t0 + a, time_unit)
    head = title or _title("rigid body along the motion", spline, name)
    ax.set_title(f"{head}\n{note}" if note else head)
    _place_labels(ax, texts, anchors)
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


def _member_colour(cmap, k: int, count: int):
    """A sequential colour per member, dark to light, never the pale end of the map."""
    return cmap(0.8 * k / max(count - 1, 1))


def family(
    splines: dict,
    n: int = 600,
    title: str = "",
    name: str = "",
    ax=None,
    fig=None,
    *,
    angle_ax=None,
    reference=None,
    time_unit: str = "s",
):
    """``splines``: label → Spline (one shape parameter swept). Two panels: the body x axis
    (solid) and z axis (dashed) of each member on the unit sphere, and the angle (degrees)
    between each member's orientation and the ``reference`` member's (a label; default the
    first) versus time — versus normalised time when the members' domains differ. Members
    differ by colour on both panels and by line style on the second.

    ``ax`` (3-D) takes the sphere and ``angle_ax`` (2-D) the angles: with ``ax`` alone only
    the sphere is drawn; without either, a new two-panel figure (or two panels added to
    ``fig``).

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> keys = qs.from_axis_angle([[0, 0, 1], [0, 1, 0], [1, 0, 0]], [0.0, 1.0, 2.0])
    >>> fam = {f"α = {a}": qs.C3Spline(keys, alpha=a) for a in (0.0, 0.5)}
    >>> fig = family(fam)
    >>> [line.get_label() for line in fig.axes[1].lines]
    ['α = 0.0 (reference)', 'α = 0.5']
    """
    matplotlib, Figure, Line2D = _mpl()
    splines = dict(splines)
    if reference is None:
        reference = next(iter(splines), None)
    elif reference not in splines:
        raise ValueError(
            f"reference: expected one of the labels {list(splines)}, got {reference!r}"
        )
    own = ax is None
    if not own:
        fig, ax = _axes(ax, None, None, "3d")
    else:
        if angle_ax is not None:
            raise ValueError("angle_ax: only with ax (the sphere's 3-D axes)")
        if fig is None:
            fig = Figure(figsize=(12.0, 5.6), layout="constrained")
        elif not hasattr(fig, "add_subplot"):
            raise TypeError(f"fig: expected a matplotlib Figure, got {type(fig).__name__}")
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        angle_ax = fig.add_subplot(1, 2, 2)
    _sphere_wire(ax)
    cmap = matplotlib.colormaps["plasma"]
    styles = {0: "-", 2: "--"}
    handles = []
    for k, (label, s) in enumerate(splines.items()):
        _, q = s.sample(n=n)
        colour = _member_colour(cmap, k, len(splines))
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
    head = title or default
    if angle_ax is not None:
        _family_angles(angle_ax, splines, reference, n, cmap, time_unit)
    if own:
        fig.suptitle(head)
        ax.set_title("body axes on the unit sphere")
    else:
        ax.set_title(head)
    return fig


def _family_angles(ax, splines: dict, reference, n: int, cmap, time_unit: str) -> None:
    """Per member, the angle from the reference member versus (normalised) time."""
    if not splines:
        return
    domains = [tuple(s.domain) for s in splines.values()]
    same = all(np.allclose(d, domains[0], rtol=0, atol=1e-12 * (1 + abs(d[1]))) for d in domains)
    # every segment sampled (4 points each, up to 20,000), so dense keys are not aliased
    segments = max(len(getattr(s, "joints", ())) for s in splines.values())
    u = np.linspace(0.0, 1.0, max(n, min(4 * segments, 20_000)))
    ref = splines[reference]
    ra, rb = ref.domain
    q_ref = ref(ra + u * (rb - ra))
    for k, (label, s) in enumerate(splines.items()):
        a, b = s.domain
        angle = angle_between(q_ref, s(a + u * (b - a)), degrees=True)
        x = ra + u * (rb - ra) if same else u
        text = f"{label} (reference)" if label == reference else str(label)
        ax.plot(
            x,
            angle,
            _STYLES[k % len(_STYLES)],
            color=_member_colour(cmap, k, len(splines)),
            lw=1.4,
            label=text,
            zorder=3 + len(splines) - k,  # the first members (the smaller sweeps) on top
        )
    ax.set_xlabel(f"time ({time_unit})" if same else "normalised time (start 0, end 1)")
    ax.set_ylabel(f"angle from {reference} (°)")
    ax.set_title("how far each member turns from the reference")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)


#: At most this many measured samples are marked per curve of :func:`fitted` (evenly spread).
MAX_DATA_MARKERS = 400
#: Z-Y′-X″ angles in order, coloured like the axis each turns about.
_EULER = (("yaw", AXIS_COLOURS[2]), ("pitch", AXIS_COLOURS[1]), ("roll", AXIS_COLOURS[0]))


def _time_axis(t0: float, unit: str) -> str:
    return f"time ({unit})" if t0 == 0 else f"time ({unit}) after t₀ = {t0:.15g} {unit}"


def _shown(n_all: int, n_shown: int) -> str:
    return (
        f"measured ({n_all:,})"
        if n_all == n_shown
        else f"measured ({n_shown:,} of {n_all:,} shown)"
    )


def _euler_curves(spline, tt: np.ndarray, times: np.ndarray, quats: np.ndarray):
    """Z-Y-X (yaw, pitch, roll) angles in degrees of the spline at ``tt`` and at ``times``
    (one continuous branch through both, whole turns unwrapped) and of the samples, each
    moved by whole turns to the branch nearest the spline's value at its time."""
    both = np.concatenate([tt, times])
    order = np.argsort(both, kind="stable")
    e = np.empty((len(both), 3))
    e[order] = np.unwrap(as_euler(spline(both[order]), "ZYX", degrees=True), period=360.0, axis=0)
    curve, at_samples = e[: len(tt)], e[len(tt) :]
    data = as_euler(quats, "ZYX", degrees=True)
    return curve, data + 360.0 * np.round((at_samples - data) / 360.0)


def fitted(
    spline,
    times,
    quats,
    positions=None,
    *,
    t0: float = 0.0,
    n: int = 2000,
    max_markers: int = MAX_DATA_MARKERS,
    time_unit: str = "s",
    length_unit: str = "m",
    title: str = "",
    name: str = "",
    fig=None,
):
    """A fit against its data on one time axis. Orientation (left column): yaw, pitch and roll
    (intrinsic z-y′-x″, degrees), one panel each, of the fitted curve (line) and of the
    measured samples (dots, at most ``max_markers``, evenly spread), then the residual — the
    angle between every sample and the curve at its time, in degrees — with its RMS in the
    legend. With ``positions``, a right column of x, y, z and the distance of every sample from
    the curve with its RMS. At the bottom the fit's angular speed |ω|.

    Parameters
    ----------
    spline : FittedSpline, FittedPose or Spline
        The curve (:func:`quatspline.fit`); any spline is compared with the samples alike.
    times, quats : array_like, shapes (N,) and (N, 4)
        The measured samples on the curve's clock.
    positions : array_like, shape (N, 3), optional
        Measured positions; the curve must have positions (a :class:`FittedPose`).
    t0 : float
        The clock reading at the curve's time 0 (a recording's first stamp), named once on
        the time axis.
    n : int
        Points of the drawn curves.

    Returns
    -------
    matplotlib.figure.Figure
        Its axes in order: yaw, pitch, roll, orientation residual, [x, y, z, position
        residual, speed |v|,] |ω|.

    Examples
    --------
    >>> import numpy as np, quatspline as qs
    >>> t = np.linspace(0.0, 2.0, 41)
    >>> f = qs.fit(t, qs.from_rotvec(np.outer(t, [0.0, 0.0, 1.0])), smoothing=1e-6)
    >>> fig = fitted(f, t, f(t))
    >>> [a.get_ylabel() for a in fig.axes]
    ['yaw (°)', 'pitch (°)', 'roll (°)', 'residual (°)', '|ω| (rad/s)']
    >>> [x.get_text() for x in fig.axes[3].get_legend().get_texts()]
    ['angle between sample and fit', 'RMS 0°']
    """
    _, Figure, Line2D = _mpl()
    times = np.asarray(times, dtype=float).reshape(-1)
    quats = np.asarray(quats, dtype=float)
    if len(times) == 0:
        raise ValueError("times: expected at least one sample")
    if quats.shape != (len(times), 4):
        raise ValueError(f"quats: expected shape ({len(times)}, 4), got {quats.shape}")
    pose = positions is not None
    if pose:
        positions = np.asarray(positions, dtype=float)
        if positions.shape != (len(times), 3):
            raise ValueError(f"positions: expected shape ({len(times)}, 3), got {positions.shape}")
        if not callable(getattr(spline, "position", None)):
            raise ValueError(
                f"positions: the curve has no positions ({type(spline).__name__}); "
                "fit them with quatspline.fit(..., positions=...)"
            )
    if fig is None:
        fig = Figure(figsize=(13.0 if pose else 8.5, 10.5), layout="constrained")
    elif not hasattr(fig, "add_gridspec"):
        raise TypeError(f"fig: expected a matplotlib Figure, got {type(fig).__name__}")
    grid = fig.add_gridspec(5, 2 if pose else 1, height_ratios=(1, 1, 1, 1.2, 1.2))
    left = [fig.add_subplot(grid[0, 0])]
    left += [fig.add_subplot(grid[i, 0], sharex=left[0]) for i in range(1, 4)]
    right = [fig.add_subplot(grid[i, 1], sharex=left[0]) for i in range(5)] if pose else []
    bottom = fig.add_subplot(grid[4, 0], sharex=left[0])

    rotation = getattr(spline, "orientation", spline)  # a pose's orientation part
    a, b = spline.domain
    tt = np.linspace(a, b, max(int(n), 2))
    shown = thin(len(times), max_markers)
    dots = {"ls": "", "marker": "o", "ms": 2.5, "alpha": 0.45, "mew": 0}
    curve, data = _euler_curves(rotation, tt, times, quats)
    for k, (angle, colour) in enumerate(_EULER):
        left[k].plot(times[shown], data[shown, k], color=colour, **dots)
        left[k].plot(tt, curve[:, k], color=colour, lw=1.5)
        left[k].set_ylabel(f"{angle} (°)")
    left[0].set_title("orientation: yaw about z, pitch about y′, roll about x″", fontsize=10)
    r = angle_between(rotation(times), quats, degrees=True)
    _residual(left[3], times, r, "angle between sample and fit", "°", "residual (°)")
    if pose:
        p_fit = np.asarray(spline.position(tt))
        for k, colour in enumerate(AXIS_COLOURS):
            right[k].plot(times[shown], positions[shown, k], color=colour, **dots)
            right[k].plot(tt, p_fit[:, k], color=colour, lw=1.5)
            right[k].set_ylabel(f"{'xyz'[k]} ({length_unit})")
        right[0].set_title("position", fontsize=10)
        d = np.linalg.norm(np.asarray(spline.position(times)) - positions, axis=1)
        _residual(
            right[3],
            times,
            d,
            "distance between sample and fit",
            f" {length_unit}",
            f"residual ({length_unit})",
        )
        speed = np.linalg.norm(spline.linear_velocity(tt), axis=1)
        right[4].plot(tt, speed, color="#8c564b", lw=1.5, label="|v| of the fit")
        right[4].set_ylabel(f"|v| ({length_unit}/{time_unit})")
        right[4].legend(loc="upper right", fontsize=8)
        right[4].set_xlabel(_time_axis(t0, time_unit))
    omega = np.linalg.norm(spline.angular_velocity(tt), axis=1)
    bottom.plot(tt, omega, color=_RATES["omega"][3], lw=1.5, label="|ω| of the fit")
    bottom.set_ylabel(f"|ω| (rad/{time_unit})")
    bottom.legend(loc="upper right", fontsize=8)
    bottom.set_xlabel(_time_axis(t0, time_unit))
    for ax in [*left, *right, bottom]:
        ax.grid(alpha=0.3)
    for ax in [*left, *right[:4]]:
        ax.tick_params(labelbottom=False)
    left[0].legend(
        handles=[
            Line2D([], [], color="0.3", lw=1.5, label="fit"),
            Line2D([], [], color="0.3", **dots, label=_shown(len(times), len(shown))),
        ],
        loc="best",
        fontsize=8,
    )
    what = f"fit to {len(times):,} samples"
    lam = getattr(spline, "smoothing", None)
    if lam is not None:
        what += f" (λ = {lam:.3g})"
    fig.suptitle(title or (f"{name}: {what}" if name else what))
    return fig


def _residual(ax, times, values, what: str, unit: str, ylabel: str) -> None:
    """A residual per sample (dots, every sample) and its RMS (a dashed line, in the legend)."""
    rms = float(np.sqrt(np.mean(values**2)))
    alpha = 0.5 * min(1.0, math.sqrt(5000 / len(values)))  # dense records: a density, not a blot
    ax.plot(times, values, ls="", marker="o", ms=2.0, color="0.25", alpha=max(alpha, 0.04), mew=0)
    ax.plot([], [], ls="", marker="o", ms=3.0, color="0.25", label=what)  # the legend's dot
    ax.axhline(rms, color="#d62728", lw=1.2, ls="--", label=f"RMS {rms:.3g}{unit}")
    ax.set_ylabel(ylabel)
    ax.set_ylim(bottom=0.0)
    ax.legend(loc="upper right", fontsize=8, ncol=2)


def save(fig, path) -> None:
    """Writes the figure atomically; the format follows the extension (png, svg, pdf)."""
    path = Path(path)
    ext = path.suffix.lower().lstrip(".")
    if ext not in ("png", "svg", "pdf"):
        raise ValueError(f"{path}: expected a .png, .svg or .pdf output")
    with atomic_write(path, mode="wb") as f:
        fig.savefig(f, format=ext, dpi=110)
