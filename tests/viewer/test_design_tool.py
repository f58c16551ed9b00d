"""The viewer as a design tool, driven in Chromium by real pointer and keyboard events.

Camera orbit, the rotation gizmo, the timeline (select, drag, add, delete), the graph editor,
shape parameters, undo/redo, 400 keys, the legend after a method switch and the export: each
edit is made with ``page.mouse``/``page.keyboard`` and its result is checked against the Python
API. The page's state is only read (``window.qsState``, cameras, chart scales), never driven.

With ``QUATSPLINE_SCREENSHOTS=1`` the tests write the documentation's screenshots
(``docs/_static/viewer-*.png``).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio

from .test_viewer import TUM, Server, _evaluations, _keys, _open, _wait_next, browser  # noqa: F401

DOCS_STATIC = Path(__file__).resolve().parents[2] / "docs" / "_static"


def _shot(page, name: str, selector: str | None = None) -> None:
    """The documentation's screenshot ``docs/_static/viewer-<name>.png`` of the page's viewport
    or of one element (when ``QUATSPLINE_SCREENSHOTS=1``)."""
    if os.environ.get("QUATSPLINE_SCREENSHOTS") != "1":
        return
    path = str(DOCS_STATIC / f"viewer-{name}.png")
    if selector is None:
        page.screenshot(path=path)
    else:
        page.locator(selector).screenshot(path=path)


@pytest.fixture
def example():
    """A server of the bundled example keys (a fresh one per test: edits do not leak)."""
    with Server() as s:
        yield s


def _result(page) -> dict:
    return page.evaluate(
        "({t: qsState.result.t, quats: qsState.result.quats, method: qsState.result.method,"
        " params: qsState.result.params})"
    )


def _design(page) -> dict:
    """Everything an edit changes: keys, times, method and parameters."""
    return page.evaluate(
        "({quats: qsState.quats, times: qsState.times, method: qsState.method,"
        " params: qsState.params})"
    )


def _same_design(a: dict, b: dict) -> bool:
    return (
        np.array_equal(a["quats"], b["quats"])
        and np.array_equal(a["times"], b["times"])
        and a["method"] == b["method"]
        and a["params"] == b["params"]
    )


def _agrees_with_python(page, atol=1e-12) -> None:
    """The curve the page shows is ``quatspline.spline`` of the page's keys and parameters."""
    r = _result(page)
    q, t = _keys(page)
    s = qs.spline(r["method"], q, t, **r["params"])
    np.testing.assert_allclose(r["quats"], s(np.array(r["t"])), atol=atol)


def _timeline_point(page, t: float) -> tuple[float, float]:
    """Where time ``t`` is on the timeline canvas (page coordinates)."""
    return tuple(
        page.evaluate(
            """(t) => {
            const c = document.getElementById("timeline"), b = c.getBoundingClientRect();
            const r = qsState.result, ts = qsState.times;
            const a = Math.min(ts[0], r.domain[0]), e = Math.max(ts[ts.length - 1], r.domain[1]);
            return [b.left + 12 + (t - a) / (e - a) * (b.width - 24), b.top + 28];
        }""",
            float(t),
        )
    )


def _drag(page, start, end, steps=8):
    page.mouse.move(*start)
    page.mouse.down()
    page.mouse.move(*end, steps=steps)
    page.mouse.up()


def _click_key_on_timeline(page, i: int) -> None:
    t = page.evaluate(f"qsState.times[{i}]")
    page.mouse.click(*_timeline_point(page, t))
    page.wait_for_function(f"qsState.selected === {i}")


# ---- camera ----------------------------------------------------------------------------------
def test_orbit_drag_turns_the_camera_and_the_wheel_zooms(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    cam = "(c) => [c.position.x, c.position.y, c.position.z]"
    for view in ("body", "sphere"):
        before = np.array(page.evaluate(f"({cam})(qsCameras.{view})"))
        box = page.locator(f"#{view}3d").bounding_box()
        # a corner of the view, away from the body and any gizmo
        x, y = box["x"] + 30, box["y"] + box["height"] - 30
        _drag(page, (x, y), (x + 120, y - 40))
        after = np.array(page.evaluate(f"({cam})(qsCameras.{view})"))
        assert np.linalg.norm(after - before) > 0.3, view
        # an orbit keeps the distance to the target
        assert abs(np.linalg.norm(after) - np.linalg.norm(before)) < 1e-9, view
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        page.mouse.wheel(0, 400)
        page.wait_for_timeout(100)
        zoomed = np.array(page.evaluate(f"({cam})(qsCameras.{view})"))
        assert np.linalg.norm(zoomed) > np.linalg.norm(after) * 1.05, view
    assert not errors, errors


# ---- rotation gizmo --------------------------------------------------------------------------
@pytest.mark.parametrize("axis", ["X", "Y", "Z"])
def test_gizmo_drag_rotates_the_selected_key_as_the_python_api_does(browser, example, axis):  # noqa: F811
    page, errors = _open(browser, example)
    k = "XYZ".index(axis)
    _click_key_on_timeline(page, 2)
    page.wait_for_timeout(200)
    q_old = np.array(page.evaluate("qsState.quats[2]"))
    # aim at the ring of rotations about the world axis: hover until the gizmo names that ring
    start = None
    for deg in range(20, 360, 15):
        p = page.evaluate(f"qsGizmoRingPoint('{axis}', {deg})")
        page.mouse.move(*p)
        if page.evaluate("qsGizmo.axis") == axis:
            start, end = p, page.evaluate(f"qsGizmoRingPoint('{axis}', {deg + 35})")
            break
    assert start is not None, f"the {axis} ring of the gizmo was never under the pointer"
    n = _evaluations(page)
    _drag(page, start, end, steps=10)
    _wait_next(page, n)
    q_new = np.array(page.evaluate("qsState.quats[2]"))
    rel = qs.as_rotvec(qs.multiply(q_new, qs.conjugate(q_old)))
    assert np.all(np.abs(np.delete(rel, k)) < 1e-12), rel  # about that world axis only
    steps = rel[k] / np.radians(5.0)  # the gizmo turns in 5° steps
    assert abs(steps - round(steps)) < 1e-9 and round(steps) != 0, rel
    rotvec = np.zeros(3)
    rotvec[k] = np.radians(5.0) * round(steps)
    expected = qs.multiply(qs.from_rotvec(rotvec), q_old)
    np.testing.assert_allclose(q_new * np.sign(q_new @ expected), expected, atol=1e-12)
    _agrees_with_python(page)
    if axis == "Z":
        page.mouse.move(*start)  # the ring under the pointer is highlighted
        page.wait_for_timeout(200)
        _shot(page, "gizmo", ".views3d")
    assert not errors, errors


# ---- timeline --------------------------------------------------------------------------------
def test_timeline_drags_adds_and_deletes_keys(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    q0, t0 = _keys(page)
    # drag key 2 to the right by 40 px: later, still between its neighbours, value unchanged
    x, y = _timeline_point(page, t0[2])
    n = _evaluations(page)
    _drag(page, (x, y), (x + 40, y))
    _wait_next(page, n)
    q1, t1 = _keys(page)
    px = (t0[-1] - t0[0]) / (page.locator("#timeline").bounding_box()["width"] - 24)
    assert abs(t1[2] - (t0[2] + 40 * px)) < 1.5 * px, (t1[2], t0[2], px)
    np.testing.assert_array_equal(np.delete(t1, 2), np.delete(t0, 2))
    np.testing.assert_array_equal(q1, q0)
    _agrees_with_python(page)
    # drag it past key 3: refused, nothing changes (and nothing is evaluated)
    x, y = _timeline_point(page, t1[2])
    x3 = _timeline_point(page, t1[3])[0]
    n = _evaluations(page)
    undo = page.evaluate("qsState.undo.length")
    _drag(page, (x, y), (x3 + 80, y))
    page.wait_for_timeout(300)
    _, t2 = _keys(page)
    np.testing.assert_array_equal(t2, t1)
    assert "cannot pass key 3" in page.inner_text("#ed-msg")
    assert _evaluations(page) == n and page.evaluate("qsState.undo.length") == undo
    # a key at the playhead is the current curve's value there
    s_before = qs.spline("c3", *_keys(page))
    r = _result(page)
    x, y = _timeline_point(page, 0.5 * (t2[0] + t2[1]))
    page.mouse.click(x, y)  # no key there: moves the playhead
    tp = page.evaluate(
        "qsState.result.t[Math.round(qsState.phase * (qsState.result.t.length - 1))]"
    )
    assert tp in r["t"] and t2[0] < tp < t2[1]
    n = _evaluations(page)
    page.click("#add-key")
    _wait_next(page, n)
    q3, t3 = _keys(page)
    assert len(t3) == len(t2) + 1 and t3[1] == tp
    np.testing.assert_allclose(q3[1], s_before(tp), atol=1e-12)
    _agrees_with_python(page)
    _shot(page, "timeline")
    # delete it again (the Delete key, the new key selected)
    page.mouse.click(*_timeline_point(page, tp))  # selects the new key
    assert page.evaluate("qsState.selected") == 1
    n = _evaluations(page)
    page.keyboard.press("Delete")
    _wait_next(page, n)
    q4, t4 = _keys(page)
    np.testing.assert_array_equal(t4, t2)
    np.testing.assert_array_equal(q4, q3[[0, 2, 3, 4, 5]])
    _agrees_with_python(page)
    assert not errors, errors


# ---- shape parameters ------------------------------------------------------------------------
def test_a_shape_slider_dragged_gives_the_python_apis_curve(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    n = _evaluations(page)
    page.select_option("#method", "beta")
    _wait_next(page, n)
    assert "set every key at once" in page.inner_text("#shape-note")
    slider = page.locator("#params input[type=range][data-param=beta2]").bounding_box()
    y = slider["y"] + slider["height"] / 2
    n = _evaluations(page)
    _drag(page, (slider["x"] + slider["width"] / 2, y), (slider["x"] + slider["width"] * 0.8, y))
    page.wait_for_function(f"qsEvaluations > {n} && qsState.result.params.beta2 > 0")
    page.wait_for_timeout(500)  # the last of the slider's evaluations
    beta2 = page.evaluate("qsState.params.beta2")
    assert beta2 > 0 and page.evaluate("qsState.result.params.beta2") == beta2
    r = _result(page)
    q, t = _keys(page)
    s = qs.spline("beta", q, t, beta2=beta2)
    np.testing.assert_allclose(r["quats"], s(np.array(r["t"])), atol=1e-12)
    assert not errors, errors


# ---- graph editor ----------------------------------------------------------------------------
def _graph_point(page, i: int, axis: int) -> tuple[float, float]:
    return tuple(
        page.evaluate(
            f"""() => {{
            const u = qsGraph.euler, b = u.over.getBoundingClientRect();
            const e = qsState.quats[{i}];
            const [w, x, y, z] = e;
            const ang = [Math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)),
              Math.asin(Math.max(-1, Math.min(1, 2 * (w * y - z * x)))),
              Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))][{axis}] * 180 / Math.PI;
            return [b.left + u.valToPos(qsState.times[{i}], "x"), b.top + u.valToPos(ang, "y")];
        }}"""
        )
    )


def test_graph_editor_drag_changes_one_euler_angle_of_the_key(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    q0, t0 = _keys(page)
    e0 = qs.as_euler(q0[1], "xyz", degrees=True)
    x, y = _graph_point(page, 1, 0)
    expected = page.evaluate(
        f"qsGraph.euler.posToVal({y} - 30 - qsGraph.euler.over.getBoundingClientRect().top, 'y')"
    )
    n = _evaluations(page)
    _drag(page, (x, y), (x, y - 30))
    _wait_next(page, n)
    q1, t1 = _keys(page)
    e1 = qs.as_euler(q1[1], "xyz", degrees=True)
    deg_per_px = abs(expected - e0[0]) / 30
    wrapped = (e1[0] - expected + 180.0) % 360.0 - 180.0  # an Euler angle is modulo 360°
    assert abs(wrapped) < deg_per_px, (e1, expected)
    assert abs(e1[0] - e0[0]) > 5
    np.testing.assert_allclose(e1[1:], e0[1:], atol=1e-9)  # the other angles kept
    ref = qs.from_euler("xyz", e1, degrees=True)
    np.testing.assert_allclose(q1[1] * np.sign(q1[1] @ ref), ref, atol=1e-12)
    assert q1[1] @ q0[1] > 0  # the edited key stays in its hemisphere
    np.testing.assert_array_equal(np.delete(q1, 1, axis=0), np.delete(q0, 1, axis=0))
    np.testing.assert_array_equal(t1, t0)
    _agrees_with_python(page)
    _shot(page, "graph-editor", "#graph")
    assert not errors, errors


# ---- undo / redo -----------------------------------------------------------------------------
def test_undo_and_redo_restore_every_edit_exactly(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    designs, results = [_design(page)], [_result(page)["quats"]]

    def done(n):
        _wait_next(page, n)
        designs.append(_design(page))
        results.append(_result(page)["quats"])

    n = _evaluations(page)
    page.fill("#params input[name=alpha]", "0.2")
    done(n)
    t = page.evaluate("qsState.times")
    x, y = _timeline_point(page, t[1])
    n = _evaluations(page)
    _drag(page, (x, y), (x - 25, y))
    done(n)
    page.mouse.click(*_timeline_point(page, 0.5 * (t[2] + t[3])))
    n = _evaluations(page)
    page.click("#add-key")
    done(n)
    x, y = _graph_point(page, 4, 2)
    n = _evaluations(page)
    _drag(page, (x, y), (x, y + 25))
    done(n)
    _click_key_on_timeline(page, 0)
    n = _evaluations(page)
    page.keyboard.press("Delete")
    done(n)
    n = _evaluations(page)
    page.select_option("#method", "natural")
    done(n)
    for a, b in zip(designs, designs[1:]):
        assert not _same_design(a, b)
    page.mouse.click(5, 5)  # the page, not an input, has the focus
    for k in range(len(designs) - 2, -1, -1):
        n = _evaluations(page)
        page.keyboard.press("Control+z")
        _wait_next(page, n)
        assert _same_design(_design(page), designs[k]), k
        assert _result(page)["quats"] == results[k], k  # the same curve, bit for bit
    assert page.input_value("#method") == "c3"
    for k in range(1, len(designs)):
        n = _evaluations(page)
        if k == 1:
            page.click("#redo")
        else:
            page.keyboard.press("Control+Shift+z")
        _wait_next(page, n)
        assert _same_design(_design(page), designs[k]), k
        assert _result(page)["quats"] == results[k], k
    assert page.input_value("#method") == "natural"
    assert not errors, errors


# ---- large key counts ------------------------------------------------------------------------
def test_400_keys_render_thinned_with_a_folded_paged_certificate(browser, tmp_path):  # noqa: F811
    t = qio.read(TUM)
    idx = np.linspace(0, len(t) - 1, 400).round().astype(int)
    p = tmp_path / "tum_400_keys.json"
    qio.write(p, qio.Trajectory(t.times[idx], t.quats[idx]))
    with Server(p) as s:
        page, errors = _open(browser, s)
        assert len(page.evaluate("qsState.times")) == 400
        page.wait_for_timeout(300)
        _shot(page, "400-keys")
        sphere = page.evaluate("qsSphere")
        assert sphere["keyDots"] <= 60 and sphere["tracePoints"] <= 801
        assert page.evaluate("document.getElementById('cert-details').open") is False
        assert "398 joints" in page.inner_text("#cert-details summary")
        page.click("#cert-details summary")
        rows = page.locator("#cert-table tr")
        assert rows.count() == 51  # a header and one page of 50 joints
        page.click("#cert-next")
        assert page.locator("#cert-table tr").nth(1).locator("td").first.inner_text() == "51"
        assert "joints 51–100 of 398" in page.inner_text("#cert-pager")
        page.click("#cert-details summary")  # folded again
        # among 400 keys, a click below the keys' line moves the playhead, selects nothing
        page.locator("#timeline").scroll_into_view_if_needed()
        x, y = _timeline_point(page, 15.0)
        page.mouse.click(x, y + 18)
        phase = page.evaluate("qsState.phase")
        assert abs(phase - 15.0 / page.evaluate("qsState.result.domain[1]")) < 0.01
        assert page.evaluate("qsState.selected") == -1
        _agrees_with_python(page)
        assert not errors, errors


# ---- the legend --------------------------------------------------------------------------------
def test_the_legend_names_the_method_after_switching(browser, example):  # noqa: F811
    page, errors = _open(browser, example)
    legend = "#plot-speed .u-legend .u-series:nth-child(2)"
    assert "c3" in page.inner_text(legend)
    for method in ("natural", "squad"):
        n = _evaluations(page)
        page.select_option("#method", method)
        _wait_next(page, n)
        assert method in page.inner_text(legend)
        assert "c3" not in page.inner_text(legend)
    assert not errors, errors


# ---- export ------------------------------------------------------------------------------------
def test_the_exported_csv_and_python_call_are_the_viewers_curve(browser, example, tmp_path):  # noqa: F811
    page, errors = _open(browser, example)
    n = _evaluations(page)
    page.select_option("#method", "kochanek_bartels")
    _wait_next(page, n)
    n = _evaluations(page)
    page.fill("#params input[name=tension]", "0.4")
    _wait_next(page, n)
    page.mouse.click(*_timeline_point(page, 2.5))
    n = _evaluations(page)
    page.click("#add-key")
    _wait_next(page, n)
    r = _result(page)
    ns: dict = {}
    exec(page.inner_text("#python"), ns)
    s = ns["s"]
    assert s.method == "kochanek_bartels" and len(ns["times"]) == 6
    np.testing.assert_allclose(s(np.array(r["t"])), r["quats"], atol=1e-12)
    with page.expect_download() as dl:
        page.click("button[data-export=csv]")
    path = tmp_path / "design.csv"
    dl.value.save_as(path)
    got = qio.read(path)
    assert len(got.times) == len(r["t"])
    np.testing.assert_allclose(got.times, r["t"], rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(got.quats, r["quats"], atol=1e-12)
    np.testing.assert_allclose(got.quats, s(got.times), atol=1e-12)
    assert not errors, errors
