"""Hostile files for the readers: declarations and line lengths that would make a reader
allocate far beyond what the file holds, and values of the wrong kind read as numbers."""

from __future__ import annotations

import json
import tracemalloc
import warnings
import zipfile

import numpy as np
import pytest
import quatspline.io as qio

#: The documented longest line (characters) of the text readers.
MAX_LINE = 1 << 20

#: A line three times the limit: split into cells it would cost over 100 MB.
WIDE = "0 " * (3 * MAX_LINE // 2)

ROT = "1 0 0 0 0 1 0 0 0 0 1 0\n"
BVH_HEAD = (
    "HIERARCHY\nROOT r\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "  End Site\n  {\n    OFFSET 0 0 0\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n"
)

#: (file name, format, content, number of the long line, the read's keyword arguments)
LONG_LINES = [
    ("a.csv", "csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n" + WIDE.replace(" ", ",") + "\n", 3, {}),
    ("a.tum", "tum", "0 0 0 0 0 0 0 1\n" + WIDE + "\n", 2, {}),
    ("k.txt", "kitti", ROT + ROT + WIDE + "\n", 3, {}),
    ("e.csv", "euroc", "#timestamp [ns],x,y,z,w,x,y,z\n" + WIDE.replace(" ", ",") + "\n", 2, {}),
    ("e2.csv", "euroc", "#timestamp [ns]" + ",c" * MAX_LINE + "\n", 1, {}),
    ("r.csv", "repoimu", "Time (s);Vicon Orientation;;;\n" + ";" * (2 * MAX_LINE) + "\n", 2, {}),
    ("b.bvh", "bvh", BVH_HEAD + "0 0 0\n" + WIDE + "\n", 15, {}),
    ("h.bvh", "bvh", BVH_HEAD.replace("CHANNELS 3", "CHANNELS 3 " + WIDE), 5, {}),
]


@pytest.mark.parametrize(
    "name, fmt, content, line, kwargs", LONG_LINES, ids=[c[0] for c in LONG_LINES]
)
def test_text_readers_refuse_an_overlong_line_before_splitting_it(
    tmp_path, name, fmt, content, line, kwargs
):
    """A line of 3 MiB of ``0 0 0 …`` was read whole and split into 1.5 million cells (about
    ten times the file's size in memory; a 2 GB line would need tens of GB) before its column
    count was checked; now at most :data:`MAX_LINE` characters of a line are read."""
    p = tmp_path / name
    p.write_text(content)
    tracemalloc.start()
    try:
        with pytest.raises(qio.TrajectoryError) as err:
            qio.read(p, format=fmt, **kwargs)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    msg = str(err.value)
    assert msg.startswith(f"{p}:{line}: ") and "line longer than 1048576 characters" in msg
    assert "\n" not in msg
    assert peak < 16 * MAX_LINE  # the old readers peaked above 100 MB here


def test_kitti_times_file_refuses_an_overlong_line(tmp_path):
    poses = tmp_path / "k.txt"
    poses.write_text(ROT)
    times = tmp_path / "times.txt"
    times.write_text("0\n" + WIDE + "\n")
    with pytest.raises(qio.TrajectoryError, match=r"times.txt:2: line longer than 1048576"):
        qio.read(poses, format="kitti", times=times)


def test_text_readers_accept_a_line_just_under_the_limit(tmp_path):
    """Valid input is never refused: a long comment line within the limit is read."""
    p = tmp_path / "a.tum"
    p.write_text("#" + "c" * (MAX_LINE - 1) + "\r\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n")
    assert len(qio.read(p)) == 2


@pytest.mark.parametrize(
    "field, value, kind",
    [
        ("quats", [[1, 0, 0, "1"], [1, 0, 0, 0]], "a string"),
        ("quats", [[True, 0, 0, 0], [1, 0, 0, 0]], "a boolean"),
        ("quats", [[1, 0, 0, None], [1, 0, 0, 0]], "null"),
        ("times", ["0", 1], "a string"),
        ("times", [False, True], "a boolean"),
        ("positions", [[0, 0, {}], [0, 0, 0]], "an object"),
    ],
)
def test_json_reader_refuses_strings_booleans_and_null_as_numbers(tmp_path, field, value, kind):
    """``"1"`` and ``true`` were read as 1.0 (numpy converts them), ``null`` became NaN."""
    doc = {"times": [0, 1], "quats": [[1, 0, 0, 0], [1, 0, 0, 0]], "positions": [[0, 0, 0]] * 2}
    doc[field] = value
    p = tmp_path / "a.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(qio.TrajectoryError) as err:
        qio.read(p)
    assert str(err.value).startswith(f'{p}: "{field}" holds {kind} ')


def test_json_reader_still_reads_null_positions_as_none(tmp_path):
    p = tmp_path / "a.json"
    p.write_text('{"times": [0, 1], "quats": [[1, 0, 0, 0], [0, 1, 0, 0]], "positions": null}')
    t = qio.read(p)
    assert t.positions is None and np.array_equal(t.quats[1], [0, 1, 0, 0])


@pytest.mark.parametrize("shape", ["(-1,)", "(-2, -2)", "(2, -4)"])
def test_npz_negative_declared_dimensions_are_refused_naming_them(tmp_path, shape):
    """A .npy header declaring shape (-1,) gave `expected -8 bytes of data`; (-2, -2) passed
    the size checks (the product is positive) and reached numpy."""
    header = f"{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}".encode()
    header += b" " * (-(len(header) + 11) % 64) + b"\n"
    member = b"\x93NUMPY\x01\x00" + len(header).to_bytes(2, "little") + header + bytes(64)
    p = tmp_path / "a.npz"
    with zipfile.ZipFile(p, "w") as z:
        z.writestr("times.npy", member)
        z.writestr("quats.npy", member)
    with pytest.raises(qio.TrajectoryError) as err:
        qio.read(p)
    assert str(err.value).startswith(f"{p}: array 'times' declares shape ")
    assert "dimensions must be integers ≥ 0" in str(err.value)


def _bad_last_row(fmt: str, n: int) -> tuple[str, str, int]:
    """(file name, content of n good rows and a bad last one, values per row)."""
    if fmt == "tum":
        body = "".join(f"{i} 0 0 0 0 0 0 1\n" for i in range(n))
        return "a.tum", body + "x 0 0 0 0 0 0 1\n", 8
    if fmt == "kitti":
        return "k.txt", ROT * n + "x" + ROT[1:], 12
    if fmt == "csv":
        body = "".join(f"{i},1,0,0,0,0,0,0\n" for i in range(n))
        return "a.csv", "t,qw,qx,qy,qz,x,y,z\n" + body + "x,1,0,0,0,0,0,0\n", 8
    if fmt == "euroc":
        body = "".join(f"{i},0,0,0,1,0,0,0\n" for i in range(n))
        return "e.csv", "#timestamp [ns],x,y,z,w,x,y,z\n" + body + "x,0,0,0,1,0,0,0\n", 8
    if fmt == "repoimu":
        body = "".join(f"{i};1;0;0;0\n" for i in range(n))
        return "r.csv", "Time (s);Vicon Orientation;;;\n;W;X;Y;Z\n" + body + "x;1;0;0;0\n", 5
    head = BVH_HEAD.replace("Frames: 2", f"Frames: {n + 1}")
    return "b.bvh", head + "0 0 0\n" * n + "x 0 0\n", 3


@pytest.mark.parametrize("fmt", ["tum", "kitti", "csv", "euroc", "repoimu", "bvh"])
def test_careful_parsers_keep_rows_compact_until_a_bad_last_row(tmp_path, monkeypatch, fmt):
    """The line-by-line parsers (used when the fast path declines, e.g. for one bad cell)
    kept every value as a Python float in a list per row: about ten times the values' size
    (a 1 GB file with a bad last row needed tens of GB before its error). Now 8 bytes a
    value (``array('d')``)."""
    for reader in ("csv_format", "euroc", "kitti", "tum"):
        monkeypatch.setattr(f"quatspline.io.{reader}.fast_table", lambda *args, **kwargs: None)
    n = 20_000
    name, content, width = _bad_last_row(fmt, n)
    p = tmp_path / name
    p.write_text(content)
    tracemalloc.start()
    try:
        with pytest.raises(qio.TrajectoryError, match=rf"{name}:\d+: column 1 .*'x'"):
            qio.read(p, format=fmt)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 4 * n * width * 8  # was 5 to 10 times


def test_fast_path_prints_no_pandas_warning_for_a_bad_cell_far_down(tmp_path):
    """A TUM file past the fast path's size with a non-numeric cell far down printed pandas'
    `DtypeWarning: Columns (0) have mixed types …` before the reader's own error."""
    name, content, _ = _bad_last_row("tum", 100_000)
    p = tmp_path / name
    p.write_text(content)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with pytest.raises(qio.TrajectoryError, match=r"a.tum:100001: column 1"):
            qio.read(p)
    assert [str(w.message) for w in seen] == []


def test_bvh_reader_does_not_hold_the_file_as_a_list_of_lines(tmp_path):
    """The BVH reader split the whole file into a list of line strings first (about 50 bytes
    a line: 600 kB of `ab` lines took 12 MB before the error on the first of them); it now
    reads line by line as it parses."""
    head = BVH_HEAD.split("MOTION")[0]
    p = tmp_path / "a.bvh"
    p.write_text(head + "ab\n" * 200_000 + "MOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n")
    size = p.stat().st_size
    tracemalloc.start()
    try:
        with pytest.raises(qio.TrajectoryError, match=r"a.bvh:11: unexpected 'ab' in HIERARCHY"):
            qio.read(p)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < size


#: (file name, format, content with the odd number, its line)
ODD_NUMBERS = [
    ("a.csv", "csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n1_0,1,0,0,0\n", 3),
    ("b.csv", "csv", "t,qw,qx,qy,qz\n0,1,0,0,0\n\u0661,1,0,0,0\n", 3),
    ("a.tum", "tum", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 \uff11\n", 2),
    ("k.txt", "kitti", ROT + "1 0 0 1_0 0 1 0 0 0 0 1 0\n", 2),
    ("e.csv", "euroc", "#timestamp [ns],x,y,z,w,x,y,z\n0,0,0,0,1,0,0,0\n1_000,0,0,0,1,0,0,0\n", 3),
    ("r.csv", "repoimu", "Time (s);Vicon Orientation;;;\n;W;X;Y;Z\n0;1;0;0;0\n1;1_0;0;0;0\n", 4),
    ("b.bvh", "bvh", BVH_HEAD + "0 0 0\n0 1_5 0\n", 15),
    ("f.bvh", "bvh", BVH_HEAD.replace("Frames: 2", "Frames: 1_0") + "0 0 0\n0 0 0\n", 12),
]


@pytest.mark.parametrize("name, fmt, content, line", ODD_NUMBERS, ids=[c[0] for c in ODD_NUMBERS])
def test_text_readers_refuse_underscores_and_non_ascii_digits_as_numbers(
    tmp_path, name, fmt, content, line
):
    """Python's float() and int() read `1_0` as 10 and Arabic-Indic or full-width digits
    as numbers; the careful parsers passed cells to them unchecked, so `1_0` became 10."""
    p = tmp_path / name
    p.write_text(content, encoding="utf-8")
    with pytest.raises(qio.TrajectoryError) as err:
        qio.read(p, format=fmt)
    assert str(err.value).startswith(f"{p}:{line}")


def test_times_file_refuses_an_underscore_in_a_time(tmp_path):
    poses = tmp_path / "k.txt"
    poses.write_text(ROT + ROT)
    times = tmp_path / "times.txt"
    times.write_text("0\n1_0\n")
    with pytest.raises(qio.TrajectoryError, match=r"times.txt:2: column 1 .*not a number"):
        qio.read(poses, format="kitti", times=times)
