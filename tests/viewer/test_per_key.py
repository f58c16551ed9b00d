"""Per-key shape parameters in the viewer, driven in Chromium by real pointer events.

A key is selected on the timeline, its own slider (Beta β₂, the C³ spline's α per segment,
Kochanek–Bartels tension) is dragged, and the page's curve is checked against
``quatspline.spline`` called with the arrays; undo, redo, adding and deleting keys keep the
arrays one per key (segment), and the Python call the page shows rebuilds its samples.

With ``QUATSPLINE_SCREENSHOTS=1`` the Kochanek–Bartels case writes
``docs/_static/viewer-per-key.png``.
"""

from __future__ import annotations

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio

from .test_design_tool import (
    _click_key_on_timeline,
    _design,
    _drag,
    _result,
    _same_design,
    _shot,
    _timeline_point,
)
from .test_viewer import Server, _evaluations, _keys, _open, _wait_next, browser  # noqa: F401


@pytest.fixture
def example():
    with Server() as s:
        yield s


def _settled(page, name: str) -> None:
    """Waits until the page's last evaluation used the parameter array it holds now."""
    page.wait_for_function(
        f"Array.isArray(qsState.params.{name}) && qsState.result && JSON.stringify("
        f"qsState.result.params.{name}) === JSON.stringify(qsState.params.{name})",
        timeout=60_000,
    )
    page.wait_for_timeout(400)  # the slider's last evaluations
    page.wait_for_function(
        f"JSON.stringify(qsState.result.params.{name}) === JSON.stringify(qsState.params.{name})",
        timeout=60_000,
    )


def _agrees(page, atol=1e-12) -> dict:
    """The page's curve is ``quatspline.spline`` of its keys and (array) parameters."""
    r = _result(page)
    q, t = _keys(page)
    assert r["params"] == page.evaluate("qsState.params")
    s = qs.spline(r["method"], q, t, **r["params"])
    np.testing.assert_allclose(r["quats"], s(np.array(r["t"])), atol=atol)
    return r


def _runs_the_python_call(page) -> None:
    r = _result(page)
    ns: dict = {}
    exec(page.inner_text("#python"), ns)
    np.testing.assert_allclose(ns["s"](np.array(r["t"])), r["quats"], atol=1e-12)


CASES = [
    # method, extra settings, per-key parameter, its scalar default, values per key or segment
    ("beta", {}, "beta2", 0.0, "key"),
    ("c3", {"variant": "patent"}, "alpha", 5 / 16, "segment"),
    ("kochanek_bartels", {}, "tension", 0.0, "key"),
]


@pytest.mark.parametrize(("method", "settings", "name", "default", "unit"), CASES)
def test_a_keys_own_slider_dragged_gives_the_python_apis_curve(
    browser,  # noqa: F811
    example,
    method,
    settings,
    name,
    default,
    unit,
):
    page, errors = _open(browser, example)
    n = _evaluations(page)
    page.select_option("#method", method)
    _wait_next(page, n)
    for k, v in settings.items():
        n = _evaluations(page)
        page.select_option(f"#params select[name={k}]", v)
        _wait_next(page, n)
    before = _design(page)
    before_curve = _result(page)["quats"]
    _click_key_on_timeline(page, 2)
    head = page.inner_text("#key-shapes-head")
    assert head.startswith("key 2" if unit == "key" else "segment 2"), head
    # drag the selected key's own slider from its thumb to the right
    slider = page.locator(f"#key-shapes input[type=range][data-perkey={name}]")
    box = slider.bounding_box()
    lo, hi = (float(slider.get_attribute(a)) for a in ("min", "max"))
    v = float(slider.input_value())
    assert abs(v - default) <= (hi - lo) / 1000  # the slider's step
    assert float(page.input_value(f"#key-shapes input[type=number][data-perkey={name}]")) == default
    y = box["y"] + box["height"] / 2
    x0 = box["x"] + 8 + (v - lo) / (hi - lo) * (box["width"] - 16)
    n = _evaluations(page)
    _drag(page, (x0, y), (x0 + 0.2 * box["width"], y), steps=6)
    _wait_next(page, n)
    _settled(page, name)
    values = page.evaluate(f"qsState.params.{name}")
    q, t = _keys(page)
    count = len(t) if unit == "key" else len(t) - 1
    assert len(values) == count
    assert values[2] > default + 0.05 * (hi - lo)  # moved right by about a fifth of the range
    assert [x for i, x in enumerate(values) if i != 2] == [default] * (count - 1)
    r = _agrees(page)
    scalar = qs.spline(method, q, t, **{**settings, name: default})
    assert np.abs(np.array(r["quats"]) - scalar(np.array(r["t"]))).max() > 1e-4
    _runs_the_python_call(page)
    # the global control still sets every key at once: its number is the selected key's value
    assert float(page.input_value(f"#params input[type=number][name={name}]")) == values[2]
    edited = _design(page)
    # undo restores the design and the curve bit for bit; redo the per-key values
    page.mouse.click(5, 5)
    n = _evaluations(page)
    page.keyboard.press("Control+z")
    _wait_next(page, n)
    assert _same_design(_design(page), before)
    assert _result(page)["quats"] == before_curve
    n = _evaluations(page)
    page.keyboard.press("Control+Shift+z")
    _wait_next(page, n)
    assert _same_design(_design(page), edited)
    # a key added between keys 0 and 1 splits that interval: its value is key (segment) 0's
    page.mouse.click(*_timeline_point(page, 0.5 * (t[0] + t[1])))
    n = _evaluations(page)
    page.click("#add-key")
    _wait_next(page, n)
    grown = page.evaluate(f"qsState.params.{name}")
    assert grown == [values[0], *values]
    assert len(page.evaluate("qsState.times")) == len(t) + 1
    _agrees(page)
    _runs_the_python_call(page)
    if method == "kochanek_bartels":
        _click_key_on_timeline(page, 3)  # the edited key, moved up by one
        assert page.input_value(f"#key-shapes input[type=number][data-perkey={name}]") == str(
            values[2]
        )
        _shot(page, "per-key")
    # deleting key 1 again gives the edited design back
    _click_key_on_timeline(page, 1)
    n = _evaluations(page)
    page.keyboard.press("Delete")
    _wait_next(page, n)
    assert _same_design(_design(page), edited)
    _agrees(page)
    # "→ all keys": one number for every key again
    _click_key_on_timeline(page, 2)
    n = _evaluations(page)
    page.click(f"#key-shapes button[data-perkey-all={name}]")
    _wait_next(page, n)
    assert page.evaluate(f"qsState.params.{name}") == values[2]
    _agrees(page)
    assert not errors, errors


def test_switching_the_c3_variant_keeps_one_value_per_key_or_segment(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    _click_key_on_timeline(page, 1)
    slider = page.locator("#key-shapes input[type=range][data-perkey=beta]")
    box = slider.bounding_box()
    y = box["y"] + box["height"] / 2
    n = _evaluations(page)
    _drag(page, (box["x"] + box["width"] / 2, y), (box["x"] + box["width"] * 0.75, y), steps=4)
    _wait_next(page, n)
    _settled(page, "beta")
    knot = page.evaluate("qsState.params.beta")
    assert len(knot) == len(page.evaluate("qsState.times"))
    n = _evaluations(page)
    page.select_option("#params select[name=variant]", "patent")
    _wait_next(page, n)
    assert page.evaluate("qsState.params.beta") == knot[:-1]
    _agrees(page)
    n = _evaluations(page)
    page.select_option("#params select[name=ends]", "closed")
    _wait_next(page, n)
    assert page.evaluate("qsState.params.beta") == [*knot[:-1], knot[-2]]
    _agrees(page)
    assert not errors, errors


@pytest.mark.parametrize("variant", ["knot", "patent"])
def test_a_c3_loop_with_a_closing_key_has_one_value_per_key_or_segment_of_the_loop(
    browser,  # noqa: F811
    tmp_path,
    variant,
):
    """Round a closed loop whose last key repeats the first, the closing key has no value
    of its own: N − 1 keys and N − 1 segments, as :func:`quatspline.spline` counts them."""
    keys = qs.from_euler(
        "xyz", [[0, 0, 0], [0, 0, 90], [60, 0, 90], [60, 40, 150], [0, 0, 0]], True
    )
    path = tmp_path / "loop.json"
    qio.write(path, qio.Trajectory(np.arange(5.0), keys))
    with Server(path) as s:
        page, errors = _open(browser, s)
        for k, v in (("variant", variant), ("ends", "closed")):
            n = _evaluations(page)
            page.select_option(f"#params select[name={k}]", v)
            _wait_next(page, n)
        _click_key_on_timeline(page, 1)
        slider = page.locator("#key-shapes input[type=range][data-perkey=alpha]")
        box = slider.bounding_box()
        y = box["y"] + box["height"] / 2
        n = _evaluations(page)
        _drag(page, (box["x"] + box["width"] / 3, y), (box["x"] + box["width"] * 0.6, y), steps=4)
        _wait_next(page, n)
        _settled(page, "alpha")
        assert len(page.evaluate("qsState.params.alpha")) == 4
        _agrees(page)
        _runs_the_python_call(page)
        assert "error" not in page.inner_text("#status")
        assert not errors, errors
