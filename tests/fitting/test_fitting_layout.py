"""The fitting package: smoothing (fit) and min_energy (MinimumEnergySpline) behind one face,
importing the splines through theirs, at the top of each file."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import quatspline as qs
import quatspline.fitting as fitting

PKG = Path(__file__).resolve().parents[2] / "python" / "quatspline" / "fitting"


def test_minimum_energy_spline_has_its_own_module_beside_the_smoothing_fit():
    assert qs.MinimumEnergySpline.__module__ == "quatspline.fitting.min_energy"
    assert qs.fit.__module__ == "quatspline.fitting.smoothing"
    for name in ("FittedPose", "FittedSpline", "MinimumEnergySpline", "fit"):
        assert name in fitting.__all__ and getattr(fitting, name) is getattr(qs, name)


def test_fitting_imports_our_modules_at_the_top_except_in_fit_trajectory():
    for path in sorted(PKG.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        top = {id(n) for n in tree.body}
        allowed = {
            id(n)
            for f in tree.body
            if isinstance(f, ast.FunctionDef) and f.name == "fit_trajectory"
            for n in ast.walk(f)
        }
        for node in ast.walk(tree):
            if not isinstance(node, ast.ImportFrom) or node.level == 0:
                continue
            assert id(node) in top or id(node) in allowed, f"{path.name}:{node.lineno}"
            assert node.module != "splines._families", f"{path.name}:{node.lineno}"


def test_minimum_energy_jerk_energy_is_measured_against_the_natural_spline():
    # the jerk variant builds its NaturalSpline from the splines face (imported inside
    # __init__ before the split): its reported natural energy is that spline's ∫|ω̈|²
    q = qs.from_rotvec([[0, 0, 0], [0.5, 0, 0], [0.5, 0.5, 0], [0, 0.5, 0.3]])
    s = qs.MinimumEnergySpline(q, penalty="jerk", resolution=2)
    natural = qs.NaturalSpline(q, np.arange(4.0))
    edges = np.unique(np.r_[s.joints, natural.joints])
    x, w = np.polynomial.legendre.leggauss(8)
    a, b = edges[:-1, None], edges[1:, None]
    t = 0.5 * (b - a) * x + 0.5 * (a + b)
    jerk = natural.jerk(t.reshape(-1), "body").reshape(*t.shape, 3)
    expected = float(np.sum(0.5 * (b - a) * w * np.sum(jerk**2, -1)))
    assert np.isclose(s.natural_energy, expected, rtol=1e-12)
    assert s.energy <= s.natural_energy
