"""Regression tests for the readers' defects of issue 2.1 (hostile and special files).

Each failed on main: a traceback of the wrong kind, a silent wrong result, a hang or an
allocation of gigabytes. Each now is a one-line ValueError naming the file (or the argument).
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
import tracemalloc
import zipfile

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.io import npz_format


def _one_line(e: BaseException, path) -> str:
    msg = str(e)
    assert "\n" not in msg
    assert str(path) in msg
    return msg


def test_deeply_nested_json_is_a_value_error_naming_the_file(tmp_path):
    p = tmp_path / "deep.json"
    p.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "nested too deeply" in _one_line(e.value, p)


@pytest.mark.parametrize("digits", [401, 5000])
def test_huge_json_integer_is_a_value_error_not_overflow(tmp_path, digits):
    p = tmp_path / "big.json"
    p.write_text('{"times": [0, ' + "1" * digits + '], "quats": [[1,0,0,0],[1,0,0,0]]}')
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert f"integer of {digits} digits is out of range" in _one_line(e.value, p)


def _npz(path, **arrays):
    with open(path, "wb") as f:
        np.savez(f, **arrays)


@pytest.mark.parametrize(
    "times",
    [
        np.array([0.0, 1.0]) + 0j,
        np.array(["2020-01-01", "2020-01-02"], dtype="datetime64[D]"),
        np.array([0, 1], dtype="timedelta64[s]"),
        np.array(["0", "1"]),
    ],
    ids=["complex", "datetime64", "timedelta64", "str"],
)
def test_npz_times_of_a_non_real_dtype_are_refused(tmp_path, times):
    p = tmp_path / "t.npz"
    _npz(p, times=times, quats=np.array([[1.0, 0, 0, 0], [1, 0, 0, 0]]))
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "array 'times' has dtype" in _one_line(e.value, p)


def test_npz_header_declaring_1e13_elements_is_refused_before_allocating(tmp_path):
    p = tmp_path / "huge.npz"
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        buf, {"descr": "<f8", "fortran_order": False, "shape": (10**13,)}
    )
    buf.write(b"\0" * 64)
    with zipfile.ZipFile(p, "w") as zf:
        zf.writestr("times.npy", buf.getvalue())
        qb = io.BytesIO()
        np.save(qb, np.array([[1.0, 0, 0, 0]]))
        zf.writestr("quats.npy", qb.getvalue())
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "declares shape (10000000000000,)" in _one_line(e.value, p)


def test_npz_decompression_bomb_is_bounded_before_allocating(tmp_path, monkeypatch):
    """A 64 MiB array of zeros compresses to ~64 KiB; with the limit lowered to 1 MiB the
    reader refuses it having allocated far less than the array (main inflated it all)."""
    p = tmp_path / "bomb.npz"
    n = 8 << 20  # 8 Mi float64 = 64 MiB
    with zipfile.ZipFile(p, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        with zf.open("times.npy", "w", force_zip64=True) as f:
            np.lib.format.write_array_header_1_0(
                f, {"descr": "<f8", "fortran_order": False, "shape": (n,)}
            )
            chunk = bytes(1 << 20)
            for _ in range(n * 8 >> 20):
                f.write(chunk)
        qb = io.BytesIO()
        np.save(qb, np.zeros((n, 4)))
        zf.writestr("quats.npy", qb.getvalue()[:200])
    assert p.stat().st_size < 1 << 20
    monkeypatch.setattr(npz_format, "MAX_ARRAY_BYTES", 1 << 20)
    tracemalloc.start()
    try:
        with pytest.raises(ValueError) as e:
            qio.read(p)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert "more than the limit of 1048576" in _one_line(e.value, p)
    assert peak < 4 << 20


def test_npz_round_trip_still_works(tmp_path):
    p = tmp_path / "ok.npz"
    q = np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])
    pos = np.arange(9.0).reshape(3, 3)
    qio.write(p, qio.Trajectory([0.0, 1, 2], q, pos))
    t = qio.read(p)
    np.testing.assert_array_equal(t.quats, q)
    np.testing.assert_array_equal(t.positions, pos)
    _npz(p, times=np.array([0, 1], dtype=np.int32), quats=np.array([[2, 0, 0, 0], [0, 0, 0, 3]]))
    np.testing.assert_array_equal(qio.read(p).quats, [[1.0, 0, 0, 0], [0, 0, 0, 1]])


def test_negative_bvh_skip_frames_is_an_error_not_the_last_frames(tmp_path):
    from pathlib import Path

    bvh = Path(__file__).resolve().parents[2] / "data" / "mocapbank_bvh" / "test_mocapbank.bvh"
    with pytest.raises(ValueError) as e:
        qio.read(bvh, skip_frames=-3)
    assert "skip_frames must be ≥ 0, got -3" in _one_line(e.value, bvh)
    with pytest.raises(TypeError, match="^skip_frames: expected an integer"):
        qio.read(bvh, skip_frames=1.5)


def test_euroc_timestamp_of_400_digits_is_a_value_error(tmp_path):
    p = tmp_path / "e.csv"
    p.write_text(
        "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],"
        "q_RS_z []\n" + "1" * 400 + ",0,0,0,1,0,0,0\n"
    )
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "400-digit integer out of range" in _one_line(e.value, p)


def test_io_read_unknown_option_is_a_value_error_naming_it(tmp_path):
    p = tmp_path / "a.csv"
    qio.write(p, qio.Trajectory([0.0, 1.0], [[1.0, 0, 0, 0], [1, 0, 0, 0]]))
    with pytest.raises(ValueError, match=r"^foo: unknown option for format csv; valid: euler"):
        qio.read(p, foo=1)
    with pytest.raises(ValueError, match=r"^format: unknown format 'xlsx'"):
        qio.read(p, format="xlsx")


def test_symlink_to_dev_zero_is_refused_not_read_forever(tmp_path):
    p = tmp_path / "zero.csv"
    os.symlink("/dev/zero", p)
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "is a device; only regular files are read" in _one_line(e.value, p)
    with pytest.raises(ValueError, match="is a device"):
        qio.detect_format(p)


def test_directory_input_is_refused(tmp_path):
    d = tmp_path / "dir.csv"
    d.mkdir()
    with pytest.raises(ValueError, match="is a directory"):
        qio.read(d)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this platform")
def test_fifo_input_is_refused_not_blocking(tmp_path):
    """Run in a child process with a timeout: on main this blocked forever."""
    fifo = tmp_path / "in.csv"
    os.mkfifo(fifo)
    r = subprocess.run(
        [sys.executable, "-m", "quatspline.cli", "compare", str(fifo)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 1
    assert (
        r.stderr.strip()
        == f"quatspline: error: {fifo}: is a FIFO (named pipe); only regular files are read"
    )


def test_npz_with_a_corrupt_deflate_stream_is_a_value_error(tmp_path):
    """Found while probing the new NPZ reader: zlib.error escaped (main: the same via np.load)."""
    b = io.BytesIO()
    np.savez_compressed(b, times=np.arange(3.0), quats=np.tile([1.0, 0, 0, 0], (3, 1)))
    bad = bytearray(b.getvalue())
    i = bad.find(b"times.npy") + 30
    bad[i : i + 20] = b"\xff" * 20
    p = tmp_path / "corrupt.npz"
    p.write_bytes(bytes(bad))
    with pytest.raises(ValueError) as e:
        qio.read(p)
    assert "not a valid .npz file (error: " in _one_line(e.value, p)


def test_reader_normalises_quaternions_with_huge_components(tmp_path):
    """Found by the writers' property test: |q|² overflowed, so main divided by inf and read
    (0, 0, 0, 1e200) as the zero quaternion (with an overflow warning)."""
    p = tmp_path / "huge.csv"
    p.write_text("t,qw,qx,qy,qz\n0,0,0,3e300,1.7e308\n1,0,0,0,1e200\n")
    t = qio.read(p)
    np.testing.assert_allclose(t.quats[1], [0, 0, 0, 1])
    np.testing.assert_allclose(np.linalg.norm(t.quats, axis=1), 1.0)
    assert t.quats[0, 3] == pytest.approx(1.0) and t.quats[0, 2] == pytest.approx(3e300 / 1.7e308)
