"""The example of docs/imu.rst runs and says what the page says it does."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import numpy as np

PAGE = Path(__file__).resolve().parents[2] / "docs" / "imu.rst"


def _python_blocks(text: str) -> list[str]:
    blocks = re.findall(r"\.\. code-block:: python\n\n((?:   .*\n|\n)+)", text)
    return ["\n".join(line[3:] for line in b.splitlines()) for b in blocks]


def test_the_worked_example_runs():
    blocks = _python_blocks(PAGE.read_text(encoding="utf-8"))
    assert blocks
    out = io.StringIO()
    scope: dict = {}
    with contextlib.redirect_stdout(out):
        for b in blocks:
            exec(compile(b, str(PAGE), "exec"), scope)
    first = out.getvalue().splitlines()[0]
    assert float(first) < 1e-3  # "well below a millimetre"
    assert scope["noisy"].gyro.shape == (4001, 3)
    assert np.all(scope["noisy"].gyro_bias[-1] != 0)
