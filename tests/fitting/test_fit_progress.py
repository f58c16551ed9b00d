"""The progress of a fit counts its real work: a callable gets (stage, done, total) with a
total estimated from the step's rate of decrease (never ``max_iter``), a bar shows the same,
and the position fit is reported as a stage of its own."""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
from quatspline.fitting import smoothing

T = np.linspace(0.0, 8.0, 401)


def noisy(t, deg, seed=0):
    rng = np.random.default_rng(seed)
    rv = np.stack([0.6 * np.sin(0.9 * t), 0.4 * np.cos(0.6 * t) - 0.4, 0.3 * t], axis=1)
    return qs.multiply(
        qs.from_rotvec(rv), qs.from_rotvec(rng.normal(size=(len(t), 3)) * deg / 57.3)
    )


def check_reports(calls, iterations, max_iter):
    """The fit's reports: done counts 1 … iterations, then a last report with done == total;
    every known total lies between done and max_iter."""
    fit_calls = [c for c in calls if c[0] == "fit"]
    assert [c[1] for c in fit_calls] == [*range(1, iterations + 1), iterations]
    for _, done, total in fit_calls:
        assert total is None or (isinstance(total, int) and done <= total <= max_iter)
    assert fit_calls[-1][2] == iterations


@pytest.mark.parametrize(
    "kw",
    [
        {"smoothing": 1e-3},
        {"smoothing": "auto"},
        {"smoothing": "auto", "robust": "huber"},
        {"smoothing": 1e-3, "penalty": "jerk"},
    ],
)
def test_a_callable_gets_consistent_stage_done_total(kw):
    calls = []
    f = qs.fit(T, noisy(T, 1.0), progress=lambda *a: calls.append(a), **kw)
    check_reports(calls, f.iterations, 1000)


def test_the_total_of_a_short_fit_is_near_its_iterations_not_max_iter():
    # a fit of a few Gauss–Newton iterations: once the rate is known the total is within two
    # iterations of the truth (the old bar said 1/1000 here)
    calls = []
    f = qs.fit(T, noisy(T, 1.0), smoothing=1e-3, progress=lambda *a: calls.append(a))
    assert f.iterations <= 10
    known = [total for _, done, total in calls if total is not None]
    assert known and all(abs(total - f.iterations) <= 2 for total in known)


def test_positions_are_a_stage_of_their_own():
    calls = []
    pos = np.column_stack([np.sin(T), np.cos(T), T])
    f = qs.fit(T, noisy(T, 1.0), positions=pos, smoothing=1e-3, progress=lambda *a: calls.append(a))
    assert calls[-2:] == [("positions", 0, 1), ("positions", 1, 1)]
    check_reports(calls[:-2], f.iterations, 1000)


def test_remaining_iterations_is_exact_on_a_geometric_sequence():
    # steps s_k = s₀ r^k reach tol at the first k with s₀ r^k ≤ tol; from any two steps on,
    # done + remaining is that k
    for s0, r, tol in [(0.03, 1e-2, 1e-10), (0.5, 0.3, 1e-8), (1.0, 0.9, 1e-6)]:
        steps = [s0 * r**k for k in range(1, 400)]
        last = next(k for k, s in enumerate(steps, 1) if s <= tol)
        for done in range(2, last + 1):
            rem = smoothing.remaining_iterations(steps[:done], tol)
            assert done + rem == last, (s0, r, done, rem, last)


def test_remaining_iterations_is_unknown_without_a_rate():
    assert smoothing.remaining_iterations([0.1], 1e-10) is None
    assert smoothing.remaining_iterations([1e-3, 1e-2], 1e-10) is None  # the step grew
    assert smoothing.remaining_iterations([1e-3, 1e-12], 1e-10) == 0


class Bar:
    made: list = []

    def __init__(self, **kw):
        self.kw, self.n, self.total, self.seen = kw, 0, kw.get("total"), []
        Bar.made.append(self)

    def set_description_str(self, s, refresh=True):
        self.desc = s

    def set_postfix_str(self, s, refresh=True):
        pass

    def refresh(self):
        self.seen.append((self.n, self.total))

    def close(self):
        self.closed = True


def test_the_bar_shows_the_estimate_and_ends_full(monkeypatch):
    Bar.made = []
    monkeypatch.setattr(smoothing, "tqdm", Bar)
    f = qs.fit(T, noisy(T, 1.0), smoothing=1e-3, progress=True)
    (bar,) = Bar.made
    assert bar.closed and bar.seen[-1] == (f.iterations, f.iterations)
    assert all(total is None or n <= total <= 2 + f.iterations for n, total in bar.seen)


def test_a_wrong_kind_of_progress_is_a_type_error():
    with pytest.raises(TypeError, match="progress"):
        qs.fit(T, noisy(T, 1.0), smoothing=1e-3, progress="yes")
