"""Progress bars: tqdm on standard error, hidden off a terminal (disable=None) and for work
under a second (delay=1); used by resampling, the glTF export and the bag reader."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline._util import progress_bars as _progress
from quatspline.io import _fast
from quatspline.ops._export import to_gltf
from quatspline.ops._resample import resample


class Recorder:
    made: list = []

    last = None

    def __init__(self, **kw):
        Recorder.made.append(kw)
        Recorder.last = self
        self.n = 0

    def update(self, n=1):
        self.n += n

    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False


def test_bars_are_terminal_only_and_delayed(monkeypatch, tmp_path, capsys):
    Recorder.made = []
    monkeypatch.setattr(_progress, "tqdm", Recorder)
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


def _big_trajectory(n: int = 40_000) -> qio.Trajectory:
    t = np.arange(n) * 0.01
    rng = np.random.default_rng(3)
    return qio.Trajectory(t, qs.from_axis_angle([0, 0, 1], t * 0.1), rng.normal(size=(n, 3)))


def _careful_only(path, line_no: int = 5):
    """Put a comment line inside the data: the fast path gives up, the careful parser reads."""
    lines = path.read_text().splitlines(keepends=True)
    comment = "# a note inside the data\n" if path.suffix != ".csv" else "\n"
    lines.insert(line_no, comment)
    path.write_text("".join(lines))


@pytest.mark.parametrize("fmt", ["tum", "csv", "euroc", "kitti", "repoimu"])
def test_careful_parser_reports_every_byte_to_a_reading_bar(monkeypatch, tmp_path, fmt):
    tr = _big_trajectory()
    if fmt == "repoimu":  # orientations only
        tr = qio.Trajectory(tr.times, tr.quats)
    if fmt == "kitti":  # no times column: the frame numbers the reader assumes
        tr = qio.Trajectory(np.arange(len(tr), dtype=float), tr.quats, tr.positions)
    ext = {"euroc": "csv", "kitti": "txt", "repoimu": "csv"}.get(fmt, fmt)
    p = tmp_path / f"big.{ext}"
    qio.write(p, tr, format=fmt)
    if fmt != "csv":
        _careful_only(p)
    Recorder.made = []
    monkeypatch.setattr(_progress, "tqdm", Recorder)
    for reader in ("csv_format", "euroc", "kitti", "tum"):  # the careful parser only
        monkeypatch.setattr(f"quatspline.io.{reader}.fast_table", lambda *a, **k: None)
    got = qio.read(p, format=fmt)
    assert np.max(qs.angle_between(got.quats, tr.quats)) < 1e-9
    (kw,) = [kw for kw in Recorder.made if kw["desc"].startswith("reading")]
    size = p.stat().st_size
    assert size > _progress.READ_BAR_BYTES
    assert kw["total"] == size and kw["unit"] == "B" and kw["desc"] == f"reading {p.name}"
    assert kw["disable"] is None and kw["delay"] == 1.0
    assert Recorder.last.n == size  # ASCII files: characters == bytes


def test_fast_path_on_a_terminal_reads_large_files_through_the_bar(monkeypatch, tmp_path):
    tr = _big_trajectory()
    p = tmp_path / "big.tum"
    qio.write(p, tr)
    plain = _fast.table(p, "ws", 8)  # by path: pandas' own (parallel) reader, no bar
    Recorder.made = []
    monkeypatch.setattr(_progress, "tqdm", Recorder)
    monkeypatch.setattr(_progress, "on_terminal", lambda: True)
    monkeypatch.setattr(_fast, "BAR_BYTES", 1 << 20)
    barred = _fast.table(p, "ws", 8)
    np.testing.assert_array_equal(barred, plain)
    (kw,) = Recorder.made
    assert kw["total"] == p.stat().st_size and kw["desc"] == "reading big.tum"
    assert Recorder.last.n == p.stat().st_size


def test_small_files_and_non_terminals_get_no_reading_bar(monkeypatch, tmp_path):
    tr = _big_trajectory(200)
    p = tmp_path / "small.tum"
    qio.write(p, tr)
    _careful_only(p)
    Recorder.made = []
    monkeypatch.setattr(_progress, "tqdm", Recorder)
    qio.read(p)
    assert Recorder.made == []
    big = tmp_path / "big.tum"
    qio.write(big, _big_trajectory())
    monkeypatch.setattr(_fast, "BAR_BYTES", 1 << 20)  # large, but not on a terminal
    qio.read(big)
    assert Recorder.made == []
