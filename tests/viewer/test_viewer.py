"""``quatspline view``: the design functions, the server's security, and the page in Chromium."""

from __future__ import annotations

import contextlib
import http.client
import json
import os
import re
import resource
import select
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import quatspline as qs
import quatspline.io as qio
from quatspline.ops import design

ROOT = Path(__file__).resolve().parents[2]
TUM = ROOT / "data" / "tum_rgbd_fr1_xyz" / "freiburg1_xyz-groundtruth.txt"
SHOTS = ROOT / "out" / "viewer-test"


# ---- design: the library functions the page calls -------------------------------------------
def test_evaluate_equals_the_spline_api():
    keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [90, 0, 90], [90, 45, 0]], degrees=True)
    t = [0.0, 1.0, 2.5, 3.0]
    d = design.evaluate("c3", keys, t, {"alpha": 0.2, "beta": 0.1}, samples=101)
    s = qs.spline("c3", keys, t, alpha=0.2, beta=0.1)
    np.testing.assert_allclose(d["quats"], s(d["t"]), atol=1e-15)
    np.testing.assert_allclose(d["jerk"], np.linalg.norm(s.jerk(d["t"]), axis=1), rtol=1e-14)
    np.testing.assert_allclose(d["omega"], s.angular_velocity(d["t"]), rtol=1e-14, atol=1e-15)
    assert [j["order"] for j in d["joints"]] == [j.order for j in qs.continuity(s)]
    ns: dict = {}
    exec(d["python"], ns)
    np.testing.assert_allclose(ns["s"](d["t"]), d["quats"], atol=1e-15)
    json.dumps(design.to_json(d))  # valid JSON, no NaN


def test_an_evaluation_travels_as_exact_float64_bytes():
    import base64

    from quatspline.viewer import _worker

    keys = qs.from_euler("xyz", [[0, 0, 0], [0, 0, 90], [90, 0, 90]], degrees=True)
    body = {"method": "c3", "quats": keys.tolist(), "times": [0, 1, 2.5], "samples": 301}
    status, media, blob, _ = _worker.handle("evaluate", json.dumps(body).encode())
    assert status == 200 and media == "application/json"
    got = json.loads(blob)
    ref = design.evaluate("c3", keys, [0, 1, 2.5], samples=301)
    for name in ("t", "quats", "omega", "speed", "acceleration", "jerk", "key_quats"):
        packed = got[name]
        # independent decoding: little-endian float64, row-major, the stated shape
        raw = np.frombuffer(base64.b64decode(packed["f8"]), dtype="<f8")
        np.testing.assert_array_equal(raw.reshape(packed["shape"]), ref[name])
    assert got["python"] == ref["python"] and got["joints"] == design.to_json(ref)["joints"]


def test_method_specs_cover_the_registry():
    names = [m["name"] for m in design.method_specs()]
    assert names == list(qs.METHODS)
    c3 = next(m for m in design.method_specs() if m["name"] == "c3")
    assert next(p for p in c3["params"] if p["name"] == "variant")["choices"] == ["knot", "patent"]


@pytest.mark.parametrize(
    ("quats", "times", "match"),
    [
        ([[1, 0, 0, 0]], [0.0], "2 … 5000 keys"),
        ([[1, 0, 0, 0], [np.nan, 0, 0, 1]], [0.0, 1.0], r"quats\[1\]: not finite"),
        ([[1, 0, 0, 0], [0, 0, 0, 1]], [1.0, 0.5], r"times\[1\]: key times must increase"),
        ([[1, 0, 0, 0], [0, 0, 0, 1]], [0.0, np.inf], r"times\[1\]: not finite"),
        ([[1, 0, 0], [0, 0, 1]], [0.0, 1.0], r"quats: expected shape \(N, 4\)"),
    ],
)
def test_bad_designs_are_value_errors_naming_the_argument(quats, times, match):
    with pytest.raises(ValueError, match=match):
        design.evaluate("c3", quats, times)


def test_bad_samples_and_parameters():
    k = [[1, 0, 0, 0], [0, 0, 0, 1]]
    with pytest.raises(ValueError, match="samples: expected 2"):
        design.evaluate("slerp", k, [0, 1], samples=10**7)
    with pytest.raises(TypeError, match="samples: expected an integer"):
        design.evaluate("slerp", k, [0, 1], samples=2.5)
    with pytest.raises(ValueError, match="unknown parameter"):
        design.evaluate("slerp", k, [0, 1], {"alpha": 1.0})


KEYS3 = [[1, 0, 0, 0], [0, 0, 0, 1], [0, 1, 0, 0]]


@pytest.mark.parametrize(
    ("method", "params", "error", "match"),
    [
        ("c3", {"holds": []}, TypeError, "params.holds: expected true or false"),
        ("c3", {"holds": "maybe"}, TypeError, "params.holds: expected true or false"),
        ("c3", {"variant": 5}, TypeError, "params.variant: expected a string"),
        ("c3", {"ends": {}}, TypeError, "params.ends: expected a string"),
        ("c3", {"alpha": "0.3"}, TypeError, "params.alpha: expected a number or 'auto'"),
        # one per key: each element a number
        ("c3", {"alpha": [1, "x", 0]}, TypeError, r"params.alpha\[1\]: expected a real number"),
        ("c3", {"beta": float("nan")}, ValueError, "params.beta: expected a finite number"),
        ("kochanek_bartels", {"tension": "1"}, TypeError, "params.tension: expected a real"),
        ("bspline", {"order": "4"}, TypeError, "params.order: expected an integer"),
        ("min_energy", {"resolution": 4.5}, TypeError, "params.resolution: expected an integer"),
        ("min_energy", {"resolution": 1e308}, TypeError, "params.resolution: expected an int"),
        ("min_energy", {"resolution": 2**70}, ValueError, "params.resolution: expected an int"),
        ("fit", {"smoothing": "x"}, ValueError, "params.smoothing: expected 'auto', 'gcv', 'adap"),
        ("fit", {"smoothing": True}, TypeError, "params.smoothing: expected a number or 'auto'"),
        ("fit", {"robust": 5}, TypeError, "params.robust: expected a string"),
        ("hermite", {"rates": [0, 0, 0]}, ValueError, r"params.rates: expected an \(N, 3\)"),
    ],
)
def test_a_design_refuses_params_of_the_wrong_kind_naming_them(method, params, error, match):
    with pytest.raises(error, match=f"^{match}"):
        design.evaluate(method, KEYS3, [0, 1, 2], params, samples=5)


def test_a_design_accepts_every_kind_of_parameter_the_page_sends():
    for method, params in [
        ("c3", {"alpha": "auto", "holds": False, "variant": "patent", "ends": "open"}),
        ("c3", {"alpha": 0, "beta": None}),
        ("fit", {"smoothing": "0.5", "robust": "none", "penalty": "jerk", "knots": None}),
        ("hermite", {"rates": "zero", "frame": "world"}),
        ("hermite", {"rates": [[0, 0, 0], [0, 0, 1], [0, 0, 0]], "frame": "world"}),
        ("min_energy", {"resolution": 2}),
    ]:
        assert len(design.evaluate(method, KEYS3, [0, 1, 2], params, samples=5)["t"]) == 5


def test_a_design_never_reads_a_file_named_in_its_parameters(tmp_path):
    hermite = next(m for m in design.method_specs() if m["name"] == "hermite")
    rates = next(p for p in hermite["params"] if p["name"] == "rates")
    assert rates["choices"] == ["bessel", "zero"]  # the page offers no file name field
    rates = tmp_path / "rates.txt"
    rates.write_text("0 0 0\n0 0 1\n0 0 0\n")
    for name in (str(rates), "/dev/zero"):
        with pytest.raises(ValueError, match=r"^params.rates: .*\(a design reads no files\)"):
            design.evaluate("hermite", KEYS3, [0, 1, 2], {"rates": name}, samples=5)
        with pytest.raises(ValueError, match=r"^params.rates: .*\(a design reads no files\)"):
            design.export_bytes("csv", "hermite", KEYS3, [0, 1, 2], {"rates": name}, samples=5)


def test_hermite_rates_from_a_fifo_or_a_device_are_refused_not_read(tmp_path):
    fifo = tmp_path / "rates.fifo"
    os.mkfifo(fifo)
    for name in (str(fifo), "/dev/zero"):
        with pytest.raises(ValueError, match="^rates: "):
            qs.spline("hermite", KEYS3, [0, 1, 2], rates=name)


@pytest.mark.parametrize(
    ("quats", "times", "error", "match"),
    [
        (KEYS3, ["0", "1", "2"], TypeError, "times: expected real numbers"),
        (KEYS3, None, TypeError, r"times: missing \(expected N increasing numbers\)"),
        (None, [0, 1, 2], TypeError, r"quats: missing \(expected an \(N, 4\) array"),
        ([[1, 0, 0, 0], [0, 0, 0, 1], [0, 1, 0, "a"]], [0, 1, 2], TypeError, "quats: expected"),
        ([[1, 0, 0, 0], [0, 0, 0, 1], [0, 1, 0, {}]], [0, 1, 2], TypeError, "quats: expected"),
        ([[1, 0, 0, 0], [0, 0, 0, 1], [1, 2]], [0, 1, 2], ValueError, "quats: not an array"),
        ([[1, 0, 0, 0], [0, 0, 0, 0], [0, 1, 0, 0]], [0, 1, 2], ValueError, r"quats\[1\]: zero"),
        (KEYS3, [0, 1e-300, 1], ValueError, "times: keys at index 0 and 1"),
    ],
)
def test_design_keys_of_the_wrong_kind_or_value_are_errors_naming_them(quats, times, error, match):
    with pytest.raises(error, match=f"^{match}"):
        design.evaluate("slerp", quats, times, samples=5)
    with pytest.raises(error, match=f"^{match}"):
        design.export_bytes("keys", "slerp", quats, times)


def test_the_keys_export_holds_the_keys_the_design_uses(tmp_path):
    tiny = [[1e-300, 0, 0, 0], [0, 0, 0, 1e-300]]
    path = tmp_path / "keys.json"
    path.write_bytes(design.export_bytes("keys", "slerp", tiny, [0, 1]))
    np.testing.assert_array_equal(qio.read(path).quats, [[1, 0, 0, 0], [0, 0, 0, 1]])


@pytest.mark.parametrize(
    ("kind", "body", "match"),
    [
        ("evaluate", {"params": []}, "^params: expected an object, got an array"),
        ("evaluate", {"params": ""}, "^params: expected an object, got a string"),
        ("evaluate", {"method": ["c3"]}, "^method: expected a string, got an array"),
        ("export", {"format": []}, "^format: expected a string"),
        ("export", {"format": {}}, "^format: expected a string"),
    ],
)
def test_a_request_field_of_the_wrong_kind_is_400_naming_it(kind, body, match):
    from quatspline.viewer import _worker

    keys = {"quats": KEYS3, "times": [0, 1, 2], "samples": 5}
    status, _, blob, _ = _worker.handle(kind, json.dumps({**keys, **body}).encode())
    assert status == 400
    assert re.search(match, json.loads(blob)["error"]), blob


# ---- the server --------------------------------------------------------------------------------
pytest.importorskip("starlette", reason="the viewer extra is not installed")
pytest.importorskip("uvicorn", reason="the viewer extra is not installed")


class Server:
    def __init__(self, path=None, token="test-token"):
        import uvicorn
        from quatspline.viewer.server import _free_port, create_app, server_config

        self.port = _free_port("127.0.0.1")
        self.token = token
        self.app = create_app(path, token, self.port)
        self.server = uvicorn.Server(server_config(self.app, host="127.0.0.1", port=self.port))
        self.thread = threading.Thread(target=self.server.run, daemon=True)

    def __enter__(self):
        self.thread.start()
        for _ in range(200):
            if self.server.started:
                return self
            time.sleep(0.05)
        raise RuntimeError("the viewer server did not start")

    def __exit__(self, *exc):
        self.server.should_exit = True
        self.thread.join(timeout=10)

    @property
    def url(self):
        return f"http://127.0.0.1:{self.port}/?token={self.token}"

    def request(self, method, path, body=None, headers=None):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        data = r.read()
        c.close()
        return r.status, data


@pytest.fixture(scope="module")
def server():
    with Server() as s:
        yield s


def test_no_token_is_403(server):
    for path in ("/", "/api/state", "/static/app.js", "/?token=wrong"):
        assert server.request("GET", path)[0] == 403, path
    status, _ = server.request("POST", "/api/evaluate", b"{}")
    assert status == 403


def test_other_origin_and_foreign_host_are_403(server):
    tok = {"X-Quatspline-Token": server.token}
    evil = {**tok, "Origin": "http://evil.example"}
    assert server.request("GET", "/api/state", headers=evil)[0] == 403
    assert server.request("POST", "/api/evaluate", b"{}", headers=evil)[0] == 403
    rebinding = {**tok, "Host": f"evil.example:{server.port}"}
    assert server.request("GET", "/api/state", headers=rebinding)[0] == 403
    same = {**tok, "Origin": f"http://127.0.0.1:{server.port}"}
    assert server.request("GET", "/api/state", headers=same)[0] == 200


@pytest.mark.parametrize(
    "path",
    [
        "/static/../server.py",
        "/static/%2e%2e/server.py",
        "/static/..%2fserver.py",
        "/static/vendor/../../server.py",
        "/static//etc/passwd",
        "/etc/passwd",
        "/static/index.html.bak",
        "/api/../../../../etc/passwd",
    ],
)
def test_path_traversal_is_404(server, path):
    status, body = server.request("GET", path, headers={"X-Quatspline-Token": server.token})
    assert status == 404, (path, body[:80])


def test_bad_edits_are_400_and_the_server_lives_on(server):
    tok = {"X-Quatspline-Token": server.token, "Content-Type": "application/json"}
    bad = [
        b"not json",
        b"[1, 2]",
        json.dumps({"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [1, 0]}).encode(),
        json.dumps({"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [0, 1], "method": 3}).encode(),
        json.dumps({"quats": "x", "times": [0, 1]}).encode(),
        json.dumps(
            {"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [0, 1], "samples": 1e9}
        ).encode(),
    ]
    for body in bad:
        status, data = server.request("POST", "/api/evaluate", body, headers=tok)
        assert status == 400, body
        assert json.loads(data)["error"]
    good = json.dumps({"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [0, 1], "samples": 3})
    status, data = server.request("POST", "/api/evaluate", good.encode(), headers=tok)
    assert status == 200 and json.loads(data)["t"]["shape"] == [3]


def test_only_the_given_file_is_served(tmp_path):
    t = qio.read(TUM)
    p = tmp_path / "keys.json"
    qio.write(p, qio.Trajectory(t.times[:50:5], t.quats[:50:5]))
    with Server(p) as s:
        status, data = s.request("GET", "/api/state", headers={"X-Quatspline-Token": s.token})
        state = json.loads(data)
        assert status == 200 and state["name"] == "keys.json" and len(state["times"]) == 10
        np.testing.assert_allclose(state["quats"], t.quats[:50:5], atol=1e-15)
        status, _ = s.request("GET", f"/static/{p}", headers={"X-Quatspline-Token": s.token})
        assert status == 404


# ---- the page in a real browser -----------------------------------------------------------------
def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def browser():
    exe = _chromium()
    if exe is None:
        pytest.skip(
            "no Chromium installed (Debian: apt-get install chromium); `make test` installs it"
        )
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    from quatspline.viewer.server import missing_assets

    assert not missing_assets(), "viewer JavaScript missing: run `make viewer-assets`"
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(
            executable_path=exe,
            args=["--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader"],
        )
        yield b
        b.close()


def _open(browser, server):
    page = browser.new_page(viewport={"width": 1400, "height": 1100}, accept_downloads=True)
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(server.url)
    page.wait_for_function("window.qsEvaluations >= 1", timeout=60_000)
    return page, errors


def _evaluations(page) -> int:
    return int(page.evaluate("window.qsEvaluations"))


def _wait_next(page, n: int):
    page.wait_for_function(f"window.qsEvaluations > {n}", timeout=60_000)
    page.wait_for_timeout(50)


def _canvas_pixels(page, selector: str) -> int:
    """Pixels of a canvas that differ from its background colour."""
    png = page.locator(selector).screenshot()
    import io as _io

    import matplotlib.image as mpimg

    img = mpimg.imread(_io.BytesIO(png))[..., :3]
    background = img[2, 2]
    return int(np.sum(np.any(np.abs(img - background) > 0.05, axis=-1)))


def test_page_renders_edits_exports_in_chromium(browser, server, tmp_path):
    SHOTS.mkdir(parents=True, exist_ok=True)
    page, errors = _open(browser, server)
    page.wait_for_timeout(300)
    assert _canvas_pixels(page, "#body3d") > 500, "the 3D body view is blank"
    assert _canvas_pixels(page, "#sphere3d") > 500, "the sphere view is blank"
    page.screenshot(path=str(SHOTS / "beta_example1.png"), full_page=True)

    # move the α slider: the jerk plot and the certificate change
    jerk0 = page.evaluate("Array.from(window.qsPlotData.jerk)")
    cert0 = page.inner_html("#certificate")
    n = _evaluations(page)
    page.fill("#params input[name=alpha]", "0.1")
    _wait_next(page, n)
    jerk1 = page.evaluate("Array.from(window.qsPlotData.jerk)")
    assert np.max(np.abs(np.subtract(jerk1, jerk0))) > 1e-3
    assert page.inner_html("#certificate") != cert0
    s = qs.spline("c3", *_keys(page), alpha=0.1)
    t = np.linspace(*s.domain, len(jerk1))
    np.testing.assert_allclose(jerk1, np.linalg.norm(s.jerk(t), axis=1), rtol=1e-9, atol=1e-9)

    # edit a key: a time past its neighbour is refused in the page; a good edit is applied
    page.click("#keytable tr.key[data-i='2']")
    page.fill("#ed-time", "99")
    page.click("#ed-apply-euler")
    assert "must be before key 3" in page.inner_text("#ed-msg")
    quats_before, times_before = _keys(page)
    page.fill("#ed-time", str(times_before[2]))
    page.fill("#ed-ex", "10")
    n = _evaluations(page)
    page.click("#ed-apply-euler")
    _wait_next(page, n)
    quats_after, _ = _keys(page)
    assert not np.allclose(quats_after[2], quats_before[2])
    np.testing.assert_allclose(quats_after[[0, 1, 3, 4]], quats_before[[0, 1, 3, 4]])
    n = _evaluations(page)
    page.click("#undo")
    _wait_next(page, n)
    np.testing.assert_allclose(_keys(page)[0], quats_before)
    n = _evaluations(page)
    page.click("#redo")
    _wait_next(page, n)
    np.testing.assert_allclose(_keys(page)[0], quats_after)

    # export CSV: the same numbers as the Python API with the same parameters
    with page.expect_download() as dl:
        page.click("button[data-export=csv]")
    path = tmp_path / "design.csv"
    dl.value.save_as(path)
    got = qio.read(path)
    q, t_keys = _keys(page)
    ref = qs.spline("c3", q, t_keys, alpha=0.1)
    np.testing.assert_allclose(got.quats, ref(got.times), atol=1e-12)
    code = page.inner_text("#python")
    ns: dict = {}
    exec(code, ns)
    np.testing.assert_allclose(ns["s"](got.times), got.quats, atol=1e-12)

    # comparison with a second method: three series per plot
    n = _evaluations(page)
    page.select_option("#compare", "natural")
    _wait_next(page, n)
    assert page.locator("#plot-jerk .u-legend .u-series").count() == 3
    page.screenshot(path=str(SHOTS / "compare_natural.png"), full_page=True)
    assert not errors, errors


def _keys(page):
    q = np.array(page.evaluate("window.qsState.quats"))
    t = np.array(page.evaluate("window.qsState.times"))
    return q, t


def test_latency_for_100_keys_and_2000_samples_on_a_real_recording(browser, tmp_path):
    t = qio.read(TUM)
    idx = np.linspace(0, len(t) - 1, 100).round().astype(int)
    p = tmp_path / "tum_100_keys.json"
    qio.write(p, qio.Trajectory(t.times[idx], t.quats[idx]))
    with Server(p) as s:
        page, errors = _open(browser, s)
        page.wait_for_timeout(300)
        lat = []
        for alpha in (0.2, 0.25, 0.3, 0.35, 0.4):
            n = _evaluations(page)
            page.fill("#params input[name=alpha]", str(alpha))
            _wait_next(page, n)
            lat.append(float(page.evaluate("window.qsLatency[window.qsLatency.length - 1]")))
        SHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SHOTS / "tum_fr1_xyz_100_keys.png"), full_page=True)
        (SHOTS / "latency.txt").write_text(
            f"slider → redrawn plots, 100 keys, 2000 samples, c3: {lat} ms "
            f"(median {np.median(lat):.0f} ms; CPU {os.cpu_count()} cores)\n"
        )
        print(f"viewer latency (ms): {lat}")
        assert len(lat) == 5 and all(x > 0 for x in lat)
        assert not errors, errors


def test_cli_view_prints_the_url_and_serves_with_the_token(tmp_path):
    from quatspline.viewer.server import _free_port

    port = _free_port("127.0.0.1")
    exe = Path(sys.executable).parent / "quatspline"
    with subprocess.Popen(
        [str(exe), "view", "--no-browser", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    ) as proc:
        try:
            line = proc.stdout.readline()
            assert line.startswith(f"quatspline view: http://127.0.0.1:{port}/?token="), line
            token = line.split("token=", 1)[1].split()[0]
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
            c.request("GET", f"/?token={token}")
            r = c.getresponse()
            assert r.status == 200 and b"quatspline view" in r.read()
            c.request("GET", "/")
            r = c.getresponse()
            r.read()
            assert r.status == 403
            c.close()
        finally:
            proc.terminate()
            proc.wait(timeout=20)


# ---- connections: floods, slow clients, shutdown ------------------------------------------------
def _raw(port: int, timeout: float = 30.0) -> socket.socket:
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return s


def _closed_by_server(s: socket.socket) -> bool:
    """Reads until the server closes the connection (True) or the socket's timeout (False)."""
    try:
        while True:
            if not s.recv(65536):
                return True
    except ConnectionResetError:
        return True
    except socket.timeout:
        return False


def _status_line(s: socket.socket) -> bytes:
    data = b""
    while b"\r\n" not in data:
        chunk = s.recv(4096)
        if not chunk:
            break
        data += chunk
    return data.split(b"\r\n", 1)[0]


def test_idle_and_slow_header_clients_are_dropped(server):
    idle = _raw(server.port)
    assert _closed_by_server(idle), "a connection that never sends a request stays open"
    idle.close()
    # a request head trickled a byte at a time never completes: the deadline still applies
    slow = _raw(server.port)
    slow.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n")
    slow.settimeout(0.5)
    dropped = False
    for _ in range(120):
        try:
            slow.sendall(b"X")
            if slow.recv(1) == b"":
                dropped = True
                break
        except socket.timeout:
            continue
        except (BrokenPipeError, ConnectionResetError):
            dropped = True
            break
    slow.close()
    assert dropped, "a client sending its request head slowly is never dropped"
    # a kept-alive connection that goes quiet after its response is closed too
    c = _raw(server.port)
    c.sendall(
        f"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
        f"X-Quatspline-Token: {server.token}\r\n\r\n".encode()
    )
    assert _status_line(c) == b"HTTP/1.1 200 OK"
    assert _closed_by_server(c)
    c.close()


def _nonblocking_connect(port: int) -> socket.socket:
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.setblocking(False)
    s.connect_ex(("127.0.0.1", port))
    return s


class _Flood:
    """``idle`` connections that send nothing and ``slow`` ones that trickle a request head."""

    def __init__(self, port: int, idle: int, slow: int):
        self.socks = [_nonblocking_connect(port) for _ in range(idle)]
        self.slow = [_nonblocking_connect(port) for _ in range(slow)]
        self.stop = threading.Event()
        self._wait_connected()
        self.thread = threading.Thread(target=self._trickle, daemon=True)
        self.thread.start()

    def _wait_connected(self, patience: float = 30.0):
        """Until every connection is established (the kernel retries a refused SYN after
        1 s, 3 s, …), or has failed; a server that accepts nothing more leaves them queued."""
        poller = select.poll()
        pending = {s.fileno(): s for s in self.socks + self.slow}
        for fd in pending:
            poller.register(fd, select.POLLOUT)
        deadline = time.monotonic() + patience
        while pending and time.monotonic() < deadline:
            for fd, _ in poller.poll(500):
                poller.unregister(fd)
                pending.pop(fd, None)

    def _trickle(self):
        head = b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Padding: "
        sent = [0] * len(self.slow)
        while not self.stop.wait(0.2):
            for i, s in enumerate(self.slow):
                with contextlib.suppress(OSError):
                    s.send(head[sent[i] : sent[i] + 1] if sent[i] < len(head) else b"a")
                    sent[i] += 1

    def close(self):
        self.stop.set()
        self.thread.join(timeout=10)
        for s in self.socks + self.slow:
            s.close()


def _get_page(port: int, token: str) -> tuple[int, bytes]:
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    try:
        c.request("GET", f"/?token={token}")
        r = c.getresponse()
        return r.status, r.read()
    finally:
        c.close()


@contextlib.contextmanager
def _viewer_process(max_files: int):
    """``quatspline view`` in a subprocess that may open ``max_files`` files (soft = hard)."""
    from quatspline.viewer.server import _free_port

    port = _free_port("127.0.0.1")
    exe = Path(sys.executable).parent / "quatspline"

    def limit():
        resource.setrlimit(resource.RLIMIT_NOFILE, (max_files, max_files))

    proc = subprocess.Popen(
        [str(exe), "view", "--no-browser", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        preexec_fn=limit,
    )
    try:
        line = proc.stdout.readline()
        assert line.startswith(f"quatspline view: http://127.0.0.1:{port}/?token="), line
        yield proc, port, line.split("token=", 1)[1].split()[0]
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait(timeout=30)
        proc.stdout.close()


@pytest.fixture
def many_files():
    """This test process may open enough sockets to flood a server limited to 1,024 files."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    want = 4096 if hard == resource.RLIM_INFINITY else min(hard, 4096)
    resource.setrlimit(resource.RLIMIT_NOFILE, (max(soft, want), hard))
    assert resource.getrlimit(resource.RLIMIT_NOFILE)[0] >= 1600, "RLIMIT_NOFILE hard < 1600"
    yield
    resource.setrlimit(resource.RLIMIT_NOFILE, (soft, hard))


def test_a_flood_of_idle_and_slow_connections_does_not_wedge_the_viewer(many_files):
    with _viewer_process(1024) as (proc, port, token):
        flood = _Flood(port, idle=1200, slow=60)
        try:
            status, page = _get_page(port, token)
            assert status == 200 and b"quatspline view" in page
        finally:
            flood.close()
        status, page = _get_page(port, token)
        assert status == 200 and b"quatspline view" in page
        assert proc.poll() is None


def test_the_viewer_raises_its_open_files_limit_to_the_hard_limit():
    def limit():
        resource.setrlimit(resource.RLIMIT_NOFILE, (256, 2048))

    code = (
        "import resource; from quatspline.viewer.server import open_files_limit, "
        "connection_limit; n = open_files_limit(); "
        "print(n, resource.getrlimit(resource.RLIMIT_NOFILE)[0], connection_limit(n))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, preexec_fn=limit, check=True
    ).stdout.split()
    assert out == ["2048", "2048", "256"]


def test_the_viewer_stops_on_sigterm_under_a_connection_flood(many_files):
    with _viewer_process(1024) as (proc, port, token):
        assert _get_page(port, token)[0] == 200
        # a request in the middle of its body: shutdown does not wait for it forever
        body = _raw(port)
        body.sendall(
            f"POST /api/evaluate HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
            f"Content-Length: 1000\r\nX-Quatspline-Token: {token}\r\n\r\n{{".encode()
        )
        flood = _Flood(port, idle=1200, slow=60)
        try:
            proc.send_signal(signal.SIGTERM)
            proc.wait(timeout=30)
        finally:
            flood.close()
            body.close()
        assert proc.returncode is not None


# ---- heavy requests and bodies ------------------------------------------------------------------
def _heavy_body() -> bytes:
    """min_energy through 5,000 random keys at 20,000 samples: a minute of work."""
    rng = np.random.default_rng(1)
    q = qs.normalize(rng.normal(size=(5000, 4)))
    return json.dumps(
        {"method": "min_energy", "quats": q.tolist(), "times": list(range(5000)), "samples": 20000}
    ).encode()


def _post(port: int, path: str, body: bytes, token: str) -> socket.socket:
    s = _raw(port, timeout=60)
    s.sendall(
        f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Quatspline-Token: {token}\r\n"
        f"Content-Type: application/json\r\nContent-Length: {len(body)}\r\n\r\n".encode()
        + body
    )
    return s


LIGHT = json.dumps({"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [0, 1], "samples": 3}).encode()


def _wait_for(predicate, what: str):
    for _ in range(600):
        if predicate():
            return
        time.sleep(0.05)
    raise AssertionError(f"never happened: {what}")


def test_a_heavy_request_does_not_block_the_page_or_light_requests():
    with Server() as s:
        heavy = _post(s.port, "/api/evaluate", _heavy_body(), s.token)
        answer: list = []
        reader = threading.Thread(target=lambda: answer.append(_status_line(heavy)), daemon=True)
        reader.start()
        time.sleep(1.0)  # the heavy request has arrived and is being computed
        status, page = _get_page(s.port, s.token)
        assert status == 200 and b"quatspline view" in page
        tok = {"X-Quatspline-Token": s.token}
        status, data = s.request("POST", "/api/evaluate", LIGHT, headers=tok)
        assert status == 200 and json.loads(data)["t"]["shape"] == [3]
        assert reader.is_alive() and not answer, "the heavy request was not running"
        heavy.shutdown(socket.SHUT_RDWR)  # abandoned: its computation is stopped
        reader.join(timeout=60)
        heavy.close()


def test_abandoned_computations_are_stopped_and_a_full_queue_is_503():
    with Server() as s:
        pool = s.app.state.pool
        body = _heavy_body()
        clients = [_post(s.port, "/api/evaluate", body, s.token) for _ in range(pool.workers)]
        _wait_for(lambda: pool.running == pool.workers, "every worker busy")
        waiting = [_post(s.port, "/api/evaluate", body, s.token) for _ in range(pool.max_queued)]
        _wait_for(lambda: pool.queued == pool.max_queued, "the queue full")
        one_more = _post(s.port, "/api/evaluate", LIGHT, s.token)
        assert _status_line(one_more) == b"HTTP/1.1 503 Service Unavailable"
        one_more.close()
        for c in waiting:  # their clients leave before their turn: they never start
            c.close()
        _wait_for(lambda: pool.queued == 0, "the queue emptied by disconnects")
        started = pool.started
        for c in clients:  # the running ones are stopped when their clients leave
            c.close()
        status, data = s.request(
            "POST", "/api/evaluate", LIGHT, headers={"X-Quatspline-Token": s.token}
        )
        assert status == 200 and json.loads(data)["t"]["shape"] == [3]
        assert pool.started == started + 1  # one new worker; no abandoned job ran


def test_a_computation_past_its_deadline_is_stopped_with_503():
    with Server() as s:
        s.app.state.pool.timeout = 1.0
        c = _post(s.port, "/api/evaluate", _heavy_body(), s.token)
        assert _status_line(c) == b"HTTP/1.1 503 Service Unavailable"
        c.close()
        # the next request starts a new worker: its start-up is not held to the 1 s deadline
        s.app.state.pool.timeout = 60.0
        status, _ = s.request(
            "POST", "/api/evaluate", LIGHT, headers={"X-Quatspline-Token": s.token}
        )
        assert status == 200


def test_a_client_that_does_not_read_its_response_is_disconnected(monkeypatch):
    from quatspline.viewer import server as viewer_server

    monkeypatch.setattr(viewer_server, "WRITE_TIMEOUT", 1.0)
    with Server() as s:
        rng = np.random.default_rng(2)
        q = qs.normalize(rng.normal(size=(200, 4)))
        body = json.dumps(
            {"format": "csv", "quats": q.tolist(), "times": list(range(200)), "samples": 20000}
        ).encode()
        c = socket.socket()
        c.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        c.settimeout(120)
        c.connect(("127.0.0.1", s.port))
        c.sendall(
            f"POST /api/export HTTP/1.1\r\nHost: 127.0.0.1:{s.port}\r\n"
            f"X-Quatspline-Token: {s.token}\r\nContent-Length: {len(body)}\r\n\r\n".encode()
            + body
        )
        # the server has computed and begun to answer (however long that takes on a loaded
        # machine); from then on the client reads nothing while the buffers fill and the
        # server's write timeout runs out
        c.recv(1, socket.MSG_PEEK)
        time.sleep(4.0)
        data = b""
        with contextlib.suppress(ConnectionResetError):
            while chunk := c.recv(1 << 16):
                data += chunk
        c.close()
        head, _, payload = data.partition(b"\r\n\r\n")
        assert head.startswith(b"HTTP/1.1 200"), head[:80]
        length = int(
            next(h for h in head.split(b"\r\n") if h.lower().startswith(b"content-length")).split(
                b":"
            )[1]
        )
        assert len(payload) < length, "the stalled response was kept for ever"


def test_oversize_bodies_are_refused_before_they_are_read(server):
    from quatspline.viewer.server import MAX_BODY

    head = (
        f"POST /api/evaluate HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
        f"X-Quatspline-Token: {server.token}\r\n"
    )
    # declared: refused from the header, after 1 KiB of the 400 MB
    c = _raw(server.port)
    c.sendall((head + "Content-Length: 400000000\r\n\r\n").encode() + b"[" * 1024)
    assert _status_line(c) == b"HTTP/1.1 413 Request Entity Too Large"
    c.close()
    # not declared (chunked): refused as soon as the count passes the limit, without the end
    c = _raw(server.port)
    c.sendall((head + "Transfer-Encoding: chunked\r\n\r\n").encode())
    chunk = b"[" * (1 << 20)
    for _ in range(MAX_BODY // len(chunk)):
        c.sendall(b"%x\r\n%s\r\n" % (len(chunk), chunk))
    c.sendall(b"1\r\n[\r\n")  # one byte over; the body never ends
    assert _status_line(c) == b"HTTP/1.1 413 Request Entity Too Large"
    c.close()
    assert (
        server.request("GET", "/api/state", headers={"X-Quatspline-Token": server.token})[0] == 200
    )


def test_a_body_sent_too_slowly_is_refused_with_408(server):
    c = _raw(server.port)
    c.sendall(
        f"POST /api/evaluate HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
        f"X-Quatspline-Token: {server.token}\r\nContent-Length: 100\r\n\r\n{{".encode()
    )
    assert _status_line(c) == b"HTTP/1.1 408 Request Timeout"
    assert _closed_by_server(c)
    c.close()


def test_export_refuses_keywords_it_does_not_know_naming_them(server):
    tok = {"X-Quatspline-Token": server.token, "Content-Type": "application/json"}
    keys = {"quats": [[1, 0, 0, 0], [0, 0, 0, 1]], "times": [0, 1], "format": "glb"}
    for extra, name in [
        ({"max_error": 0.5}, "max_error"),
        ({"params": {"samples": 5_000_000}}, "samples"),
        ({"params": {"uniform": True}}, "uniform"),
        ({"options": {"samples": 5_000_000}}, "samples"),
        ({"options": {"max_error": 1e-9}}, "max_error"),
        ({"options": {"interpolation": "step"}}, "interpolation"),
    ]:
        status, data = server.request(
            "POST", "/api/export", json.dumps({**keys, **extra}).encode(), headers=tok
        )
        assert status == 400, extra
        assert name in json.loads(data)["error"], (extra, data)
    good = {**keys, "options": {"max_error": 0.5, "interpolation": "cubicspline"}}
    status, blob = server.request("POST", "/api/export", json.dumps(good).encode(), headers=tok)
    assert status == 200 and blob[:4] == b"glTF"


def test_a_design_refuses_a_fit_knot_spacing_that_multiplies_its_work():
    rng = np.random.default_rng(0)
    q = qs.normalize(np.cumsum(rng.normal(size=(50, 4)) * 0.1, axis=0) + [3, 0, 0, 0])
    t = np.arange(50.0)
    with pytest.raises(ValueError, match="knots: spacing 0.005 gives 9800 knot intervals"):
        design.evaluate("fit", q, t, {"knots": 0.005}, samples=10)
    with pytest.raises(ValueError, match="knots: spacing"):
        design.export_bytes("csv", "fit", q, t, {"knots": 0.005}, samples=10)
    assert len(design.evaluate("fit", q, t, {"knots": 2.0}, samples=10)["t"]) == 10


def test_export_bytes_passes_no_foreign_keywords_to_gltf():
    k = [[1, 0, 0, 0], [0, 0, 0, 1]]
    with pytest.raises(ValueError, match="max_error"):
        design.export_bytes("glb", "c3", k, [0, 1], {"max_error": 0.5})
    with pytest.raises(ValueError, match="samples"):
        design.export_bytes("glb", "c3", k, [0, 1], {"samples": 5_000_000})
    with pytest.raises(ValueError, match="options"):
        design.export_bytes("csv", "c3", k, [0, 1], options={"max_error": 0.5})
    assert design.export_bytes("glb", "c3", k, [0, 1], options={"max_error": 0.5})[:4] == b"glTF"


# ---- further hostile inputs ---------------------------------------------------------------------
@pytest.mark.parametrize(
    "request_head",
    [
        b"GET /api/state HTTP/1.1\r\nX-Quatspline-Token: t\xf6k\r\n",
        b"GET /api/state?token=%FF%FE HTTP/1.1\r\n",
        b"GET /api/state?token=%C3%A9 HTTP/1.1\r\n",
        b"GET /?token=%C3%A9 HTTP/1.1\r\n",
        b"GET /api/state HTTP/1.1\r\nCookie: quatspline_token=\xc3\xa9\r\n",
    ],
)
def test_a_token_with_non_ascii_characters_is_403_not_500(server, request_head):
    c = _raw(server.port)
    c.sendall(request_head + f"Host: 127.0.0.1:{server.port}\r\n\r\n".encode())
    assert _status_line(c) == b"HTTP/1.1 403 Forbidden"
    c.close()


def test_an_origin_of_another_scheme_is_403(server):
    tok = {"X-Quatspline-Token": server.token}
    for origin in (f"https://127.0.0.1:{server.port}", f"ws://127.0.0.1:{server.port}"):
        assert server.request("GET", "/api/state", headers={**tok, "Origin": origin})[0] == 403


def test_the_viewer_serves_the_interface_it_was_asked_to_listen_on():
    from quatspline.viewer.server import _free_port

    host = "127.0.0.2"  # another loopback address: serve(host=…) is documented
    port = _free_port(host)
    code = (
        "import sys; from quatspline.viewer import serve; "
        f"serve(host={host!r}, port={port}, open_browser=False)"
    )
    with subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
    ) as proc:
        try:
            line = proc.stdout.readline()
            assert line.startswith(f"quatspline view: http://{host}:{port}/?token="), line
            token = line.split("token=", 1)[1].split()[0]
            c = http.client.HTTPConnection(host, port, timeout=30)
            c.request("GET", f"/?token={token}")  # Host: 127.0.0.2:PORT, as a browser sends
            r = c.getresponse()
            assert r.status == 200 and b"quatspline view" in r.read()
            c.request("GET", f"/?token={token}", headers={"Host": f"evil.example:{port}"})
            r = c.getresponse()
            r.read()
            assert r.status == 403
            c.close()
        finally:
            proc.terminate()
            proc.wait(timeout=20)
