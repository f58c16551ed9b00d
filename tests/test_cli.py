"""The command line: --help, --version, demo."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import quatspline as qs
from quatspline.cli import main


def test_help_and_version(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--help"])
    assert e.value.code == 0
    assert "demo" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["--version"])
    assert qs.__version__ in capsys.readouterr().out


def test_no_command_is_usage_error(capsys):
    assert main([]) == 2


def test_demo_writes_samples(tmp_path):
    assert main(["demo", "--out", str(tmp_path)]) == 0
    data = np.loadtxt(tmp_path / "beta_example1_slerp.csv", delimiter=",", skiprows=1)
    assert data.shape == (201, 5)
    np.testing.assert_allclose(np.linalg.norm(data[:, 1:], axis=1), 1.0, atol=1e-15)
    keys = qs.normalize(qs.examples.BETA_EXAMPLE1_VERTICES)
    np.testing.assert_allclose(data[::50, 1:], keys, atol=1e-16)


def test_console_script_runs():
    r = subprocess.run(
        [sys.executable, "-m", "quatspline.cli", "--version"], capture_output=True, text=True
    )
    assert r.returncode == 0 and "quatspline" in r.stdout
