"""Figures: ax=/fig=, no backend switching, labelled axes with units, legends, thinned key
markers, curve pixels in the saved image, titles from the data."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
from quatspline import plot

from ..splinekit import random_walk

matplotlib = pytest.importorskip("matplotlib")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.text as mtext  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


def dense(n=500, seed=0):
    t = np.arange(n) * 0.01
    return qs.C3Spline(random_walk(n, seed, step=0.1), t), t


def labelled(ax):
    labels = [ax.get_xlabel(), ax.get_ylabel()]
    if hasattr(ax, "get_zlabel"):
        labels.append(ax.get_zlabel())
    assert all(s.strip() for s in labels), labels
    return labels


def coloured_pixels(path) -> int:
    """Saturated pixels: the curves and axes (the sphere, grid and text are grey)."""
    img = mpimg.imread(path)[..., :3]
    return int(np.sum(img.max(axis=-1) - img.min(axis=-1) > 0.3))


def test_no_backend_switch_and_no_pyplot(tmp_path):
    """In a fresh interpreter with an interactive backend chosen by the user: drawing and
    saving leave the backend alone and never import pyplot."""
    code = (
        "import sys, matplotlib; matplotlib.use('TkAgg', force=False)\n"
        "before = matplotlib.get_backend()\n"
        "import numpy as np, quatspline as qs; from quatspline import plot\n"
        "s = qs.C3Spline(qs.from_axis_angle([0, 0, 1], [0.0, 1.0, 2.0]))\n"
        f"plot.save(plot.rates(s, key_times=[0, 1, 2]), {str(tmp_path / 'r.png')!r})\n"
        "plot.sphere(s); plot.body(s); plot.family({'a': s})\n"
        "assert matplotlib.get_backend() == before, (before, matplotlib.get_backend())\n"
        "assert 'matplotlib.pyplot' not in sys.modules\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    assert (tmp_path / "r.png").stat().st_size > 1000


@pytest.mark.parametrize("kind", ["sphere", "body", "family"])
def test_3d_plots_into_given_axes(tmp_path, kind):
    s, t = dense()
    fig = Figure()
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    if kind == "sphere":
        out = plot.sphere(s, key_times=t, ax=ax, name="walk")
    elif kind == "body":
        ps = qs.PoseSpline(s.params["quats"], t, np.cumsum(np.ones((len(t), 3)), 0) * 0.01)
        out = plot.body(s, positions=ps.position, ax=ax, name="walk", t0=100.0)
        texts = [x.get_text() for x in ax.texts]
        assert texts[0] == "0 s" and texts[-1].endswith(" s")
        assert ax.get_title().endswith("times after t₀ = 100 s")
        assert ax.get_xlabel() == "x (m)"
    else:
        fam = {f"α = {a}": qs.C3Spline(random_walk(6, 1), alpha=a) for a in (0, 0.3)}
        out = plot.family(fam, ax=ax, name="walk")
        legend = [x.get_text() for x in ax.get_legend().get_texts()]
        assert legend == ["α = 0", "α = 0.3", "body x axis", "body z axis"]
    assert out is fig and len(fig.axes) == 1
    labelled(ax)
    assert ax.get_legend() is not None
    assert "walk" in ax.get_title()
    plot.save(fig, tmp_path / "f.png")
    assert coloured_pixels(tmp_path / "f.png") > 300  # the curves are drawn


def test_sphere_thins_dense_key_markers():
    s, t = dense(2000)
    fig = plot.sphere(s, key_times=t)
    ax = fig.axes[0]
    sizes = [len(c.get_offsets()) for c in ax.collections if hasattr(c, "get_offsets")]
    assert max(sizes) <= plot.MAX_MARKERS
    legend = [x.get_text() for x in ax.get_legend().get_texts()]
    assert "keys (40 of 2000 shown)" in legend
    assert "c3 spline" in ax.get_title()


def test_rates_shows_omega_alpha_jerk_with_units(tmp_path):
    s, t = dense(300)
    fig = plot.rates(s, key_times=t, show=("omega", "alpha", "jerk"), name="rec.csv")
    axes = fig.axes
    assert [a.get_ylabel() for a in axes] == ["|ω| (rad/s)", "|α| (rad/s²)", "|dα/dt| (rad/s³)"]
    assert axes[-1].get_xlabel() == "time (s)"
    assert "rec.csv" in fig.get_suptitle()
    for a in axes:
        assert a.get_legend() is not None
        assert len(a.lines) - 1 <= plot.MAX_MARKERS + 1  # curve + markers; vlines are thinned
    plot.save(fig, tmp_path / "r.png")
    img = mpimg.imread(tmp_path / "r.png")[..., :3]
    blue = np.sum((img[..., 2] > 0.6) & (img[..., 0] < 0.3))
    assert blue > 500


def test_rates_into_given_axes_and_bad_arguments():
    s, _ = dense(50)
    fig = Figure()
    a1, a2 = fig.subplots(2, 1)
    assert plot.rates(s, ax=[a1, a2]) is fig
    assert a1.get_ylabel().startswith("|ω|")
    with pytest.raises(ValueError, match=r"ax: expected 2 axes"):
        plot.rates(s, ax=a1)
    with pytest.raises(ValueError, match=r"show: expected some of omega, alpha, jerk"):
        plot.rates(s, show=("speed",))
    with pytest.raises(ValueError, match=r"ax: expected 3-D axes"):
        plot.sphere(s, ax=a1)
    with pytest.raises(TypeError, match=r"fig: expected a matplotlib Figure"):
        plot.sphere(s, fig="figure")


def test_thin():
    assert plot.thin(3).tolist() == [0, 1, 2]
    k = plot.thin(1001, 11)
    assert k.tolist() == list(range(0, 1001, 100))


# ---- figures people read: content checked on the artists --------------------------------------
def drawn(fig):
    """The figure laid out and drawn by Agg (window extents are then the saved image's)."""
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig


def visible_labels(ax):
    return [x for x in ax.texts if x.get_visible() and x.get_text()]


def drawn_extents(fig, texts, monkeypatch) -> list:
    """The page rectangles of ``texts`` as Agg draws them (a 3-D text has its page position
    only while it is drawn, so each is measured inside its own draw)."""
    seen = {}
    draw = mtext.Text.draw

    def spy(self, renderer):
        if any(self is x for x in texts):
            seen[id(self)] = self.get_window_extent(renderer)
        return draw(self, renderer)

    monkeypatch.setattr(mtext.Text, "draw", spy)
    drawn(fig)
    monkeypatch.undo()
    return [seen[id(x)] for x in texts]


def overlapping(texts, boxes) -> list:
    return [
        (texts[i].get_text(), texts[j].get_text())
        for i in range(len(boxes))
        for j in range(i + 1, len(boxes))
        if boxes[i].overlaps(boxes[j])
    ]


def looping(laps=5, duration=30.0, n=301):
    """A body that goes round the same circle ``laps`` times: its snapshots fall on top of
    one another on the page, so labels must be kept apart by the plot."""
    t = np.linspace(0.0, duration, n)
    s = qs.C3Spline(random_walk(n, 3, step=0.05), t)
    w = 2 * np.pi * laps / duration

    def positions(tt):
        tt = np.asarray(tt, dtype=float)
        return np.column_stack([np.cos(w * tt), np.sin(w * tt), 0.1 * np.sin(3 * w * tt)])

    return s, positions


@pytest.mark.parametrize("snapshots", [5, 8, 12, 20])
def test_body_labels_are_short_times_since_the_start_and_never_overlap(snapshots, monkeypatch):
    s, positions = looping()
    fig = plot.body(s, positions=positions, snapshots=snapshots, t0=1.4e9, name="loop")
    ax = fig.axes[0]
    labels = visible_labels(ax)
    texts = [x.get_text() for x in labels]
    assert texts[0] == "0 s", texts  # the start is always labelled
    values = []
    for text in texts:
        m = re.fullmatch(r"(\d+(?:\.\d+)?) s", text)
        assert m and len(m.group(1).replace(".", "")) <= 4, text  # relative, few digits
        values.append(float(m.group(1)))
    # round times: multiples of one step of 1, 2, 2.5 or 5 × 10ᵏ, within the motion
    every = [float(re.fullmatch(r"(\S+) s", x.get_text()).group(1)) for x in ax.texts]
    step = every[1] - every[0]
    mantissa = step / 10 ** np.floor(np.log10(step))
    assert min(abs(mantissa - m) for m in (1, 2, 2.5, 5)) < 1e-9, step
    assert np.allclose(every, step * np.arange(len(every)), atol=1e-9)
    assert len(every) <= snapshots and every[-1] <= 30.0 + step / 1000
    assert ax.get_title().splitlines()[-1] == "times after t₀ = 1400000000 s"  # t₀ once
    assert (
        sum("1400000000" in x.get_text() for x in fig.findobj(lambda a: hasattr(a, "get_text")))
        == 1
    )
    boxes = drawn_extents(fig, labels, monkeypatch)
    page = fig.bbox
    assert all(
        page.x0 <= b.x0 and b.x1 <= page.x1 and page.y0 <= b.y0 and b.y1 <= page.y1 for b in boxes
    )
    assert overlapping(labels, boxes) == []
    # the laps put the snapshots on top of one another: labels were moved beside their
    # boxes (each within reach of its box) and only the rest left out
    assert len(labels) >= min(len(ax.texts), 8)
    proj3d = pytest.importorskip("mpl_toolkits.mplot3d.proj3d")
    for value, box in zip(values, boxes):
        x, y, _ = proj3d.proj_transform(*positions([value])[0], ax.get_proj())
        cx, cy = ax.transData.transform((x, y))
        gap = np.hypot(max(box.x0 - cx, 0, cx - box.x1), max(box.y0 - cy, 0, cy - box.y1))
        # from the body's centre to its label: within a box's reach (a box's half height is
        # 3/4 of the path's extent over the number of boxes; the extent is within the axes)
        reach = 0.75 * np.hypot(ax.bbox.width, ax.bbox.height) / len(ax.texts)
        assert gap < reach + 4, (value, gap, reach)


def test_body_labels_all_stand_when_there_is_room():
    t = np.linspace(0.0, 8.0, 81)
    s = qs.C3Spline(random_walk(81, 2, step=0.05), t)
    fig = drawn(
        plot.body(s, positions=lambda tt: np.outer(np.asarray(tt), [1.0, 0.0, 0.0]), snapshots=5)
    )
    ax = fig.axes[0]
    assert [x.get_text() for x in visible_labels(ax)] == ["0 s", "2 s", "4 s", "6 s", "8 s"]
    assert "t₀" not in ax.get_title()  # a clock that starts at 0 needs no note


def test_body_axes_have_equal_scales_and_an_orthographic_view():
    """Metres are metres on all three axes: the limits' spans are proportional to the box's
    aspect, and the view is orthographic (a metre along an axis is as long on the page near
    the viewer as far from it)."""
    proj3d = pytest.importorskip("mpl_toolkits.mplot3d.proj3d")
    s, positions = looping()
    stretched = lambda tt: positions(tt) * [3.0, 0.5, 0.2]  # noqa: E731
    fig = drawn(plot.body(s, positions=stretched, snapshots=8))
    ax = fig.axes[0]
    spans = np.array([np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim()), np.ptp(ax.get_zlim())])
    aspect = np.array(ax.get_box_aspect())
    assert np.allclose(spans / spans[0], aspect / aspect[0], rtol=1e-9)
    m = ax.get_proj()
    lo = np.array([ax.get_xlim()[0], ax.get_ylim()[0], ax.get_zlim()[0]])
    hi = lo + spans

    def page(p):
        x, y, _ = proj3d.proj_transform(*p, m)
        return ax.transData.transform((x, y))

    for k in range(3):
        e = np.eye(3)[k] * 0.1
        near = page(lo + e) - page(lo)
        far = page(hi - e) - page(hi)
        assert np.allclose(near, -far, atol=1e-6), (k, near, far)


def angle_deg(a, b):
    """The angle between rotations, written independently of quatspline.angle_between."""
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    return np.degrees(2 * np.arccos(np.clip(np.abs(np.sum(a * b, axis=-1)), 0.0, 1.0)))


def test_family_has_the_angle_from_the_reference_of_every_member():
    keys = random_walk(7, 4)
    fam = {f"α = {a}": qs.C3Spline(keys, alpha=a) for a in (0.0, 0.2, 0.4, 0.6)}
    fig = drawn(plot.family(fam, name="walk"))
    sphere, panel = fig.axes
    assert sphere.name == "3d" and panel.name != "3d"
    lines = panel.lines
    assert [x.get_label() for x in lines] == [
        "α = 0.0 (reference)",
        "α = 0.2",
        "α = 0.4",
        "α = 0.6",
    ]
    for line, spline in zip(lines, fam.values()):
        t = line.get_xdata()
        assert np.allclose(angle_deg(fam["α = 0.0"](t), spline(t)), line.get_ydata(), atol=1e-5)
    assert np.max(lines[0].get_ydata()) < 1e-6
    assert all(np.max(x.get_ydata()) > 0.1 for x in lines[1:])  # the sweep is visible
    assert len({x.get_color() for x in lines}) == 4  # distinct colours
    assert len({x.get_linestyle() for x in lines}) == 4  # and line styles
    assert panel.get_ylabel() == "angle from α = 0.0 (°)" and panel.get_xlabel() == "time (s)"
    assert [x.get_text() for x in panel.get_legend().get_texts()][1:] == [
        "α = 0.2",
        "α = 0.4",
        "α = 0.6",
    ]
    assert "walk" in fig.get_suptitle()


def test_family_reference_and_members_on_different_times():
    fam = {
        "slow": qs.C3Spline(random_walk(5, 5), [0.0, 1.0, 2.0, 3.0, 4.0]),
        "fast": qs.C3Spline(random_walk(5, 5), [0.0, 0.5, 1.0, 1.5, 2.0]),
    }
    fig = plot.family(fam, reference="fast")
    panel = fig.axes[1]
    assert panel.get_xlabel() == "normalised time (start 0, end 1)"
    u = panel.lines[0].get_xdata()
    assert np.allclose(
        angle_deg(fam["fast"](2 * u), fam["slow"](4 * u)), panel.lines[0].get_ydata(), atol=1e-5
    )
    assert np.max(panel.lines[1].get_ydata()) < 1e-6
    with pytest.raises(ValueError, match=r"reference: expected one of the labels"):
        plot.family(fam, reference="medium")


def noisy_recording(n=1500, seed=0, positions=False):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 15.0, n)
    truth = qs.from_rotvec(np.column_stack([np.sin(t), 0.5 * np.cos(0.7 * t), 0.3 * t]))
    q = qs.multiply(truth, qs.from_rotvec(rng.normal(0, np.radians(1.0), (n, 3))))
    p = None
    if positions:
        p = np.column_stack([np.cos(t), np.sin(t), 0.1 * t]) + rng.normal(0, 0.01, (n, 3))
    return t, q, p


def legend_texts(ax):
    return [x.get_text() for x in ax.get_legend().get_texts()]


@pytest.mark.parametrize("pose", [False, True])
def test_fitted_shows_the_data_the_fit_and_the_residuals(pose):
    from scipy.spatial.transform import Rotation

    t, q, p = noisy_recording(positions=pose)
    f = qs.fit(t, q, positions=p)
    fig = drawn(plot.fitted(f, t, q, p, t0=1.4e9, name="rec"))
    axes = fig.axes
    yaw, pitch, roll, res = axes[:4]
    assert [a.get_ylabel() for a in (yaw, pitch, roll, res)] == [
        "yaw (°)",
        "pitch (°)",
        "roll (°)",
        "residual (°)",
    ]
    # data (thinned markers) and the fit, as Euler angles: equal to scipy's modulo whole turns
    data_rot = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_euler("ZYX", degrees=True)
    for k, ax in enumerate((yaw, pitch, roll)):
        dots, curve = ax.lines
        assert dots.get_linestyle() == "None" and len(dots.get_xdata()) == plot.MAX_DATA_MARKERS
        idx = np.searchsorted(t, dots.get_xdata())
        assert np.allclose(t[idx], dots.get_xdata())
        wrap = (dots.get_ydata() - data_rot[idx, k] + 180) % 360 - 180
        assert np.allclose(wrap, 0, atol=1e-6)
        tt = curve.get_xdata()
        fq = f.orientation(tt) if pose else f(tt)
        ref = Rotation.from_quat(fq[:, [1, 2, 3, 0]]).as_euler("ZYX", degrees=True)[:, k]
        assert np.allclose((curve.get_ydata() - ref + 180) % 360 - 180, 0, atol=1e-6)
        assert np.max(np.abs(np.diff(curve.get_ydata()))) < 10  # continuous, no wrap jumps
    # residual: the angle between every sample and the fit, in degrees, and its RMS
    (r_line,) = [x for x in res.lines if len(x.get_xdata()) == len(t)]
    fq = f.orientation(t) if pose else f(t)
    expected = angle_deg(fq, q)
    assert np.allclose(r_line.get_xdata(), t)
    assert np.allclose(r_line.get_ydata(), expected, atol=1e-5)
    assert np.allclose(r_line.get_ydata(), np.degrees(f.residuals), atol=1e-6)  # the solver's
    rms = np.sqrt(np.mean(expected**2))
    assert legend_texts(res) == ["angle between sample and fit", f"RMS {rms:.3g}°"]
    assert 1.2 < rms < 2.0  # √3 × 1° of noise per axis, less what the fit absorbs
    texts = [x.get_text() for x in fig.findobj(lambda a: hasattr(a, "get_text"))]
    assert not any("keys" in x for x in texts)
    assert "measured (400 of 1,500 shown)" in texts
    assert axes[-1].get_ylabel() == "|ω| (rad/s)"
    assert axes[-1].get_xlabel() == "time (s) after t₀ = 1400000000 s"
    assert fig.get_suptitle().startswith("rec: fit to 1,500 samples (λ = ")
    if pose:
        x_ax, y_ax, z_ax, p_res, speed = axes[4:9]
        for k, ax in enumerate((x_ax, y_ax, z_ax)):
            dots, curve = ax.lines
            idx = np.searchsorted(t, dots.get_xdata())
            assert np.allclose(dots.get_ydata(), p[idx, k])
            assert np.allclose(curve.get_ydata(), f.position(curve.get_xdata())[:, k])
        (d_line,) = [x for x in p_res.lines if len(x.get_xdata()) == len(t)]
        d = np.linalg.norm(f.position(t) - p, axis=1)
        assert np.allclose(d_line.get_ydata(), d, atol=1e-12)
        assert np.allclose(d_line.get_ydata(), f.position_residuals, atol=1e-9)
        assert legend_texts(p_res)[1] == f"RMS {np.sqrt(np.mean(d**2)):.3g} m"
        assert speed.get_ylabel() == "|v| (m/s)"
        assert len(axes) == 10
    else:
        assert len(axes) == 5


def test_fitted_bad_input():
    t, q, p = noisy_recording(200)
    f = qs.fit(t, q)
    with pytest.raises(ValueError, match=r"quats: expected shape \(200, 4\)"):
        plot.fitted(f, t, q[:10])
    with pytest.raises(ValueError, match=r"positions: the curve has no positions"):
        plot.fitted(f, t, q, np.zeros((200, 3)))
    with pytest.raises(ValueError, match=r"positions: expected shape \(200, 3\)"):
        plot.fitted(f, t, q, np.zeros((200, 2)))
    with pytest.raises(TypeError, match=r"fig: expected a matplotlib Figure"):
        plot.fitted(f, t, q, fig="figure")


# ---- the command line draws through the same functions ------------------------------------------
def noisy_file(tmp_path, n=600, start=1.4e9):
    """A TUM recording with 1° of orientation and 1 cm of position noise, on a clock that starts
    at ``start``."""
    import quatspline.io as qio

    t, q, p = noisy_recording(n, positions=True)
    path = tmp_path / "noisy.tum"
    qio.write(path, qio.Trajectory(t + start, q, p))
    return path


@pytest.fixture
def saved(monkeypatch):
    """The figures the command line hands to ``plot.save``."""
    figs = []
    orig = plot.save
    monkeypatch.setattr(plot, "save", lambda fig, path: figs.append(fig) or orig(fig, path))
    return figs


def test_cli_fit_figure_is_the_data_against_the_fit(tmp_path, capsys, saved):
    from quatspline.cli import main

    src = noisy_file(tmp_path)
    out, fig_path = tmp_path / "smooth.csv", tmp_path / "fit.png"
    assert main(["fit", str(src), "-o", str(out), "--count", "50", "--figure", str(fig_path)]) == 0
    printed = capsys.readouterr().out
    assert f"wrote {fig_path}" in printed and fig_path.stat().st_size > 10_000
    (fig,) = saved
    assert len(fig.axes) == 10  # orientation and position columns: the file has positions
    rms = float(re.search(r"RMS residual ([\d.]+)°", printed).group(1))
    legend = [x.get_text() for x in fig.axes[3].get_legend().get_texts()]
    assert legend[1].startswith("RMS ") and float(legend[1][4:-1]) == pytest.approx(rms, rel=5e-3)
    assert fig.axes[-1].get_xlabel() == "time (s) after t₀ = 1400000000 s"
    assert fig.get_suptitle().startswith("noisy.tum: fit to 600 samples")


def test_cli_fit_refuses_a_figure_that_is_not_an_image_before_any_work(tmp_path, capsys):
    from quatspline.cli import main

    src = noisy_file(tmp_path, n=50)
    out = tmp_path / "smooth.csv"
    assert main(["fit", str(src), "-o", str(out), "--count", "5", "--figure", "f.txt"]) == 2
    assert "--figure f.txt: expected a .png, .svg, .pdf file" in capsys.readouterr().err
    assert not out.exists()


def test_cli_plot_marks_no_keys_for_a_fit_and_names_the_start_of_the_body(tmp_path, saved):
    from quatspline.cli import main

    src = noisy_file(tmp_path, n=300)
    out = tmp_path / "r.png"
    assert main(["plot", str(src), "-o", str(out), "--kind", "rates", "--method", "fit"]) == 0
    texts = [x.get_text() for x in saved[-1].findobj(lambda a: hasattr(a, "get_text"))]
    assert not any("keys" in x for x in texts)
    assert main(["plot", str(src), "-o", str(out), "--kind", "rates", "--force"]) == 0
    texts = [x.get_text() for x in saved[-1].findobj(lambda a: hasattr(a, "get_text"))]
    assert "keys (40 of 300 shown)" in texts  # an interpolating spline's keys still are
    assert main(["plot", str(src), "-o", str(out), "--kind", "body", "--force"]) == 0
    ax = saved[-1].axes[0]
    assert ax.get_title().endswith("times after t₀ = 1400000000 s")
    assert re.fullmatch(r"0(\.0+)? s", visible_labels(ax)[0].get_text())


# ---- the documentation's screenshots -------------------------------------------------------------
DOCS_STATIC = Path(__file__).resolve().parents[2] / "docs" / "_static"


@pytest.mark.skipif(
    os.environ.get("QUATSPLINE_SCREENSHOTS") != "1",
    reason="screenshots only with QUATSPLINE_SCREENSHOTS=1",
)
def test_screenshots_for_the_docs(tmp_path):
    """``docs/_static/figure-{body,family,fit}.png``, drawn by the routes users take:
    ``quatspline plot --kind body`` on the bundled recording, the demo's family figure and
    ``quatspline fit --figure`` on the bundled recording with noise added."""
    from importlib.resources import as_file, files

    import quatspline.io as qio
    from quatspline.cli import main
    from quatspline.examples import BETA_EXAMPLE2_VERTICES, RECORDING, load_recording
    from quatspline.splines import BetaSpline

    with as_file(files("quatspline") / "data" / RECORDING) as path:
        argv = ["plot", str(path), "-o", str(DOCS_STATIC / "figure-body.png"), "--kind", "body"]
        assert main(argv) == 0
    fam = {}
    for b12 in (0.5, 2.0, 4.0):
        b2 = np.full(len(BETA_EXAMPLE2_VERTICES), 0.5)
        b2[1] = b12
        fam[f"β₁,₂ = {b12}"] = BetaSpline(
            BETA_EXAMPLE2_VERTICES, beta1=1.0, beta2=b2, canonicalize=False
        )
    plot.save(
        plot.family(fam, title="Beta spline, paper Example 2: β₂ at vertex 1"),
        DOCS_STATIC / "figure-family.png",
    )
    traj = load_recording()
    rng = np.random.default_rng(0)
    noisy = qio.Trajectory(
        traj.times,
        qs.multiply(traj.quats, qs.from_rotvec(rng.normal(0, np.radians(1.0), (len(traj), 3)))),
        traj.positions + rng.normal(0, 0.005, traj.positions.shape),
    )
    src = tmp_path / "fr1_xyz_noisy.tum"
    qio.write(src, noisy)
    argv = ["fit", str(src), "-o", str(tmp_path / "smooth.csv"), "--rate", "100"]
    assert main([*argv, "--figure", str(DOCS_STATIC / "figure-fit.png")]) == 0


def test_family_into_given_axes_for_the_sphere_and_the_angles():
    fam = {f"α = {a}": qs.C3Spline(random_walk(6, 1), alpha=a) for a in (0, 0.3)}
    fig = Figure()
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    panel = fig.add_subplot(1, 2, 2)
    assert plot.family(fam, ax=ax, angle_ax=panel, name="walk") is fig
    assert len(fig.axes) == 2 and len(panel.lines) == 2 and "walk" in ax.get_title()
    with pytest.raises(ValueError, match=r"angle_ax: only with ax"):
        plot.family(fam, angle_ax=panel)


def test_cli_fit_figure_without_matplotlib_says_so_before_the_fit(tmp_path, capsys, monkeypatch):
    from quatspline.cli import main

    src = noisy_file(tmp_path, n=50)
    out = tmp_path / "smooth.csv"
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now fails
    argv = ["fit", str(src), "-o", str(out), "--count", "5", "--figure", str(tmp_path / "f.png")]
    assert main(argv) == 1
    assert "fit --figure needs matplotlib: pip install" in capsys.readouterr().err
    assert not out.exists()
