"""The example of docs/imu_calibration.rst runs, and recovers what it planted."""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
from pathlib import Path

import numpy as np

PAGE = Path(__file__).resolve().parents[2] / "docs" / "imu_calibration.rst"


def _python_blocks(text: str) -> list[str]:
    blocks = re.findall(r"\.\. code-block:: python\n\n((?:   .*\n|\n)+)", text)
    return ["\n".join(line[3:] for line in b.splitlines()) for b in blocks]


def test_the_example_runs_and_recovers_the_planted_sensor(tmp_path):
    blocks = _python_blocks(PAGE.read_text(encoding="utf-8"))
    assert blocks
    scope: dict = {}
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with contextlib.redirect_stdout(out):
            for b in blocks:
                exec(compile(b, str(PAGE), "exec"), scope)
    finally:
        os.chdir(cwd)
    assert "time offset (ms)" in out.getvalue()
    assert (tmp_path / "calibration.png").stat().st_size > 0
    cal, sensor = scope["cal"], scope["sensor"]
    se = cal.standard_errors
    assert abs(cal.time_offset - sensor.time_offset) < 4 * se["time_offset"]
    assert np.all(np.abs(cal.gyro_bias - sensor.gyro_bias) < 4 * se["gyro_bias"])
    d = abs(float(np.dot(cal.rotation, sensor.rotation)))
    assert 2 * math.acos(min(1.0, d)) < 4 * np.linalg.norm(se["rotation"])
