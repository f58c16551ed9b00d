"""Regression tests for the command line defects of issue 2.1 (each failed on main)."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline.io as qio
from quatspline.cli import main

from .conftest import random_quats


@pytest.fixture
def keys_csv(tmp_path):
    t = np.linspace(0.0, 3.9, 40)
    p = tmp_path / "keys.csv"
    qio.write(p, qio.Trajectory(t, random_quats(40, seed=7), np.column_stack([t, t, t])))
    return p


def test_compare_holdout_zero_is_a_usage_error(keys_csv, capsys):
    assert main(["compare", str(keys_csv), "--holdout", "0", "--methods", "slerp"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--holdout: expected an integer ≥ 2, got 0" in err
