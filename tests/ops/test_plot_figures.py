"""Figures: ax=/fig=, no backend switching, labelled axes with units, legends, thinned key
markers, curve pixels in the saved image, titles from the data."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import quatspline as qs
from quatspline import plot

from ..splinekit import random_walk

matplotlib = pytest.importorskip("matplotlib")
import matplotlib.image as mpimg  # noqa: E402
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
        assert texts[0] == "100 s" and texts[-1].endswith(" s")
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
