"""Progress bars: tqdm on standard error, hidden off a terminal (disable=None) and for work
under a second (delay=1); used by resampling, the glTF export and the bag reader."""

from __future__ import annotations

import numpy as np
import quatspline as qs
import quatspline.io as qio
import tqdm as tqdm_mod
from quatspline import _progress
from quatspline.export import to_gltf
from quatspline.resampling import resample


class Recorder:
    made: list = []

    def __init__(self, **kw):
        Recorder.made.append(kw)
        self.n = 0

    def update(self, n=1):
        self.n += n

    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False


def test_bars_are_terminal_only_and_delayed(monkeypatch, tmp_path, capsys):
    Recorder.made = []
    monkeypatch.setattr(tqdm_mod, "tqdm", Recorder)
    tr = qio.Trajectory(np.arange(5.0), qs.from_axis_angle([0, 0, 1], np.arange(5.0) * 0.3))
    resample(tr, np.linspace(0, 4, 100))
    to_gltf(tr, tmp_path / "m.glb")
    descs = [kw["desc"] for kw in Recorder.made]
    assert descs == ["sampling", "export glTF"]
    for kw in Recorder.made:
        assert kw["disable"] is None and kw["delay"] == 1.0 and kw["leave"] is False
    with _progress.progress(total=3, enabled=False) as bar:
        bar.update(3)
    assert len(Recorder.made) == 2  # disabled: no tqdm at all


def test_no_output_off_a_terminal(capsys):
    with _progress.progress(total=10, desc="x") as bar:
        for _ in range(10):
            bar.update(1)
    assert capsys.readouterr().err == ""
