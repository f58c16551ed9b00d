"""quatspline.ops: the library operations behind the CLI (sample, compare, tables), their
docstring examples, and the defects of issue 2.1 that lived in the CLI."""

from __future__ import annotations

import doctest

import numpy as np
import pytest
import quatspline.io as qio
import quatspline.metrics
import quatspline.ops
from quatspline.ops import ParameterError, compare

from .conftest import random_quats


@pytest.mark.parametrize("module", [quatspline.ops, quatspline.metrics], ids=lambda m: m.__name__)
def test_docstring_examples_run(module):
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0


def _traj(n=40, positions=True):
    t = np.linspace(0.0, 3.9, n)
    q = random_quats(n, seed=5)
    q = q * np.sign(np.cumsum(np.ones(n)))[:, None]
    pos = np.column_stack([np.sin(t), np.cos(t), t]) if positions else None
    return qio.Trajectory(t + 100.0, q, pos)


def test_compare_returns_plain_numbers():
    rows = compare(_traj(), ["slerp", "natural"], holdout=3)
    assert [r["method"] for r in rows] == ["slerp", "natural"]
    for r in rows:
        for k, v in r.items():
            assert type(v) in (str, float, int), (k, type(v))


def test_compare_holdout_zero_is_an_error_not_no_holdout():
    with pytest.raises(ParameterError, match=r"^holdout: expected an integer ≥ 2, got 0"):
        compare(_traj(), ["slerp"], holdout=0)
    with pytest.raises(TypeError, match="^holdout"):
        compare(_traj(), ["slerp"], holdout=2.5)
