"""`quatspline batch --scheduler FILE` with files that are not Dask scheduler files."""

from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest
import quatspline.io as qio
from quatspline import batch
from quatspline.cli import main

pytestmark = [
    pytest.mark.filterwarnings("ignore::DeprecationWarning"),
    pytest.mark.filterwarnings("ignore::ResourceWarning"),
]


def _input(tmp_path):
    src = tmp_path / "in.csv"
    q = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    qio.write(src, qio.Trajectory(np.arange(4.0), q))
    return src


@pytest.mark.parametrize(
    "content, why",
    [
        (b"not json", "not a Dask scheduler file (not JSON)"),
        (b'{"address": 5}', 'not a Dask scheduler file (no "address" string'),
        (b"[]", 'not a Dask scheduler file (no "address" string'),
        (b'{"type": "Scheduler"}', 'not a Dask scheduler file (no "address" string'),
        (b"\xff\xfe", "not a Dask scheduler file (not JSON)"),
    ],
)
def test_batch_scheduler_file_that_is_not_dasks_is_a_one_line_error_naming_it(
    tmp_path, capsys, content, why
):
    """Dask raised a bare `AssertionError`, `TypeError: expected str, got 'int'` or `list
    indices must be integers` out of `quatspline batch --scheduler s.json`."""
    src = _input(tmp_path)
    sched = tmp_path / "s.json"
    sched.write_bytes(content)
    with pytest.raises(ValueError) as err:
        batch.run("sample", [src], tmp_path / "out", scheduler=str(sched), count=5)
    assert str(err.value).startswith(f"scheduler: {sched}: {why}")
    code = main(["batch", "sample", str(src), "-o", str(tmp_path / "o2"), "--count", "5",
                 "--scheduler", str(sched)])  # fmt: skip
    err_text = capsys.readouterr().err.strip()
    assert code != 0 and len(err_text.splitlines()) == 1 and why in err_text


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_batch_scheduler_file_that_is_a_fifo_or_device_is_refused(tmp_path, kind):
    """A FIFO named `s.json` was taken for an address (`missing port number in address`),
    a link to /dev/zero likewise; both are now refused as files, without blocking."""
    src = _input(tmp_path)
    sched = tmp_path / "s.json"
    if kind == "fifo":
        os.mkfifo(sched)
    else:
        os.symlink("/dev/zero", sched)
    what = "a FIFO (named pipe)" if kind == "fifo" else "a device"
    expected = f"^scheduler: {re.escape(str(sched))}: is {re.escape(what)}; only regular files"
    with pytest.raises(ValueError, match=expected):
        batch.run("sample", [src], tmp_path / "out", scheduler=str(sched), count=5)


def test_batch_scheduler_file_gives_its_address(tmp_path, capsys):
    """A real scheduler file's address is used (here unreachable, so named in the error)."""
    src = _input(tmp_path)
    sched = tmp_path / "scheduler.json"
    sched.write_text(json.dumps({"type": "Scheduler", "address": "tcp://127.0.0.1:9"}))
    code = main(["batch", "sample", str(src), "-o", str(tmp_path / "o"), "--count", "5",
                 "--scheduler", str(sched)])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert code == 1 and "cannot reach tcp://127.0.0.1:9" in err, err
