"""The readers' fast path (pandas) against their careful parser: bit-identical results, the
careful parser's file:line:column errors, exact EuRoC nanoseconds through a round trip."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.io import _fast

from ..splinekit import random_walk

pytest.importorskip("pandas", reason="the fast path needs pandas: pip install 'quatspline[pandas]'")

N = 4000  # > 64 KiB of text: the fast path is used
EUROC = Path(__file__).resolve().parents[2] / "data" / "euroc_v1_02_medium"


def table(n=N, seed=0):
    rng = np.random.default_rng(seed)
    t = 1305031102.175304 + np.cumsum(rng.uniform(0.001, 0.02, n))
    return t, random_walk(n, seed, step=0.1), rng.normal(size=(n, 3))


def write_file(path: Path, fmt: str, seed=0, bad_line=None, bad_text=None):
    t, q, p = table(seed=seed)
    lines = []
    if fmt == "tum":
        lines.append("# timestamp tx ty tz qx qy qz qw")
        rows = np.column_stack([t, p, q[:, [1, 2, 3, 0]]])
        lines += [" ".join(repr(float(v)) for v in r) for r in rows]
    elif fmt == "csv":
        lines.append("t,qx,qy,qz,qw,x,y,z")
        rows = np.column_stack([t, q[:, [1, 2, 3, 0]], p])
        lines += [",".join(repr(float(v)) for v in r) for r in rows]
    elif fmt == "kitti":
        from quatspline.core.convert import as_matrix

        rows = np.concatenate([as_matrix(q), p[:, :, None]], axis=2).reshape(-1, 12)
        lines += [" ".join(repr(float(v)) for v in r) for r in rows]
    elif fmt == "euroc":
        lines.append(
            "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],"
            "q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []"
        )
        ns = 1403715523912143143 + np.cumsum(np.random.default_rng(seed).integers(10**6, 10**7, N))
        lines += [
            f"{k}," + ",".join(repr(float(v)) for v in (*pp, *qq)) for k, pp, qq in zip(ns, p, q)
        ]  # noqa: E501
    if bad_line is not None:
        lines[bad_line - 1] = bad_text
    path.write_text("\n".join(lines) + "\n")
    return path


READERS = ("csv_format", "euroc", "kitti", "tum")  # the readers with a fast path


def careful(path, monkeypatch, **kw):
    with monkeypatch.context() as m:
        for reader in READERS:
            m.setattr(f"quatspline.io.{reader}.fast_table", lambda *a, **k: None)
        return qio.read(path, **kw)


def same(a, b):
    np.testing.assert_array_equal(a.times, b.times)
    np.testing.assert_array_equal(a.quats, b.quats)
    if a.positions is None:
        assert b.positions is None
    else:
        np.testing.assert_array_equal(a.positions, b.positions)
    if a.stamps_ns is not None:
        np.testing.assert_array_equal(a.stamps_ns, b.stamps_ns)


FILES = {"tum": "a.txt", "csv": "a.csv", "kitti": "k.txt", "euroc": "data.csv"}


@pytest.mark.parametrize("fmt", list(FILES))
def test_fast_equals_careful_bit_for_bit(tmp_path, monkeypatch, fmt):
    path = write_file(tmp_path / FILES[fmt], fmt)
    assert qio.detect_format(path) == fmt
    results = []
    orig = _fast.table
    for reader in READERS:
        monkeypatch.setattr(
            f"quatspline.io.{reader}.fast_table",
            lambda *a, **k: results.append(orig(*a, **k)) or results[-1],
        )
    fast = qio.read(path)
    assert results and results[0] is not None  # the fast path was taken
    same(fast, careful(path, monkeypatch))


@pytest.mark.parametrize(
    ("fmt", "line", "text", "match"),
    [
        ("tum", 3001, "1 2 3 4 5 x 7 8", r"a.txt:3001: column 6 \('qy'\): not a number: 'x'"),
        ("tum", 2500, "1 2 3", r"a.txt:2500: expected 8 columns"),
        ("csv", 1234, "1,2,3", r"a.csv:1234: expected 8 columns \(as the header\), got 3"),
        ("csv", 77, "1,nan,0,0,1,0,0,0", r"a.csv:77: NaN or inf in this row"),
        ("kitti", 3999, "1 0 0 0 0 1 0 0 0 0 1", r"k.txt:3999: expected 12 values .* got 11"),
        (
            "euroc",
            4000,
            "12.5,0,0,0,1,0,0,0",
            r"data.csv:4000: column 1 \('timestamp'\): not an integer",
        ),  # noqa: E501
        ("tum", 1800, "1305031102.2 0 0 0 0 0 0 1", r"a.txt:1800: decreasing timestamp"),
    ],
)
def test_errors_come_from_the_careful_parser(tmp_path, fmt, line, text, match):
    path = write_file(tmp_path / FILES[fmt], fmt, bad_line=line, bad_text=text)
    with pytest.raises(ValueError, match=match):
        qio.read(path, format=fmt)


def test_comment_inside_and_odd_whitespace(tmp_path, monkeypatch):
    path = write_file(tmp_path / "a.txt", "tum")
    text = path.read_text().splitlines()
    text.insert(2000, "# a comment in the middle")
    (tmp_path / "c.txt").write_text("\n".join(text) + "\n")
    same(qio.read(tmp_path / "c.txt"), qio.read(path))
    (tmp_path / "tabs.txt").write_text("\r\n".join(x.replace(" ", "\t  ") for x in text) + "\r\n")
    got = qio.read(tmp_path / "tabs.txt", format="tum")
    same(got, qio.read(path))
    same(got, careful(tmp_path / "tabs.txt", monkeypatch, format="tum"))


def test_sort_and_dedupe_on_the_fast_path(tmp_path, monkeypatch):
    path = write_file(
        tmp_path / "a.txt", "tum", bad_line=1800, bad_text="1305031102.2 0 0 0 0 0 0 1"
    )
    same(qio.read(path, sort=True), careful(path, monkeypatch, sort=True))


def test_without_pandas_the_careful_parser_reads(tmp_path, monkeypatch):
    path = write_file(tmp_path / "a.csv", "csv")
    fast = qio.read(path)
    monkeypatch.setitem(sys.modules, "pandas", None)
    assert _fast.table(path, ",", 8, skip=1) is None
    same(qio.read(path), fast)


def test_euroc_nanoseconds_survive_a_round_trip(tmp_path):
    src = write_file(tmp_path / "data.csv", "euroc")
    tr = qio.read(src)
    assert tr.stamps_ns.dtype == np.int64
    qio.write(tmp_path / "out.csv", tr, format="euroc")
    col = [line.split(",")[0] for line in src.read_text().splitlines()]
    out = [line.split(",")[0] for line in (tmp_path / "out.csv").read_text().splitlines()]
    assert out[1:] == col[1:]  # the integer stamps, character for character
    back = qio.read(tmp_path / "out.csv")
    np.testing.assert_array_equal(back.stamps_ns, tr.stamps_ns)
    # float64 seconds could not have carried them
    assert np.any(np.round(tr.times * 1e9).astype(np.int64) != tr.stamps_ns)


def test_real_euroc_file_round_trip(tmp_path, monkeypatch):
    (src,) = EUROC.glob("*.csv")
    tr = qio.read(src)
    same(tr, careful(src, monkeypatch))
    qio.write(tmp_path / "o.csv", tr, format="euroc")
    np.testing.assert_array_equal(qio.read(tmp_path / "o.csv").stamps_ns, tr.stamps_ns)


def test_stamps_closer_than_float_seconds_resolve(tmp_path):
    text = (
        "#timestamp [ns],p_x,p_y,p_z,q_w,q_x,q_y,q_z\n"
        "1403715523912143143,0,0,0,1,0,0,0\n"
        "1403715523912143144,0,0,0,1,0,0,0\n"
    )
    (tmp_path / "d.csv").write_text(text)
    with pytest.raises(
        ValueError, match=r"d.csv:3: stamps 1403715523912143143 and .*144 ns are 1 ns apart"
    ):  # noqa: E501
        qio.read(tmp_path / "d.csv", format="euroc")
    assert len(qio.read(tmp_path / "d.csv", format="euroc", dedupe=True)) == 1
