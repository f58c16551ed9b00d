"""The viewer's HTTP server: a token-protected Starlette app on 127.0.0.1."""

from __future__ import annotations

import json
import secrets
import socket
import webbrowser
from pathlib import Path

import numpy as np

from .. import design
from .. import io as qio

VIEWER_HINT = 'quatspline view needs its web stack: pip install "quatspline[viewer]"'

STATIC = Path(__file__).resolve().parent / "static"
#: The only files the server sends: name → media type. Anything else is a 404.
ASSETS = {
    "app.js": "text/javascript",
    "app.css": "text/css",
    "vendor/three.module.js": "text/javascript",
    "vendor/three.core.js": "text/javascript",
    "vendor/uPlot.iife.min.js": "text/javascript",
    "vendor/uPlot.min.css": "text/css",
}
MAX_BODY = 8 << 20
EXPORT_FORMATS = {
    "csv": "text/csv",
    "json": "application/json",
    "glb": "model/gltf-binary",
    "keys": "application/json",
}


def _web():
    try:
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError:
        raise ImportError(VIEWER_HINT) from None


def missing_assets() -> list[str]:
    """The vendored JavaScript files that are not installed (empty when the page can run)."""
    return [n for n in ASSETS if not (STATIC / n).is_file()]


def example_keys() -> tuple[np.ndarray, np.ndarray, str]:
    """The keys shown without a file: the Beta paper's Example 1 rotations at unit times."""
    from ..algebra import normalize
    from ..examples import BETA_EXAMPLE1_VERTICES

    q = normalize(BETA_EXAMPLE1_VERTICES)
    return q, np.arange(len(q), dtype=float), "Beta spline paper, Example 1"


def load_keys(path: Path | None, max_keys: int = 400) -> tuple[np.ndarray, np.ndarray, str]:
    """Keys from a file (every k-th frame of a long recording, at most ``max_keys``)."""
    if path is None:
        return example_keys()
    traj = qio.read(path)
    idx = np.arange(len(traj))
    if len(idx) > max_keys:
        idx = np.unique(np.linspace(0, len(traj) - 1, max_keys).round().astype(int))
    t = traj.times[idx] - traj.times[0]
    return traj.quats[idx], t, Path(path).name


def create_app(path: Path | None = None, token: str | None = None, port: int = 0):
    """The Starlette application.

    Parameters
    ----------
    path : pathlib.Path, optional
        Keys file, recording or trajectory to start from (default: the bundled example).
    token : str, optional
        The access token (default: a new random one); every request must carry it as
        ``?token=`` (the page), the ``X-Quatspline-Token`` header (the API) or the cookie the
        page sets.
    port : int
        The port the server listens on (for the ``Host``/``Origin`` checks; 0 accepts any
        port on 127.0.0.1/localhost, for tests).

    Returns
    -------
    starlette.applications.Starlette
        With ``app.state.token`` set.
    """
    _web()
    from starlette.applications import Starlette
    from starlette.requests import Request
    from starlette.responses import HTMLResponse, JSONResponse, PlainTextResponse, Response
    from starlette.routing import Route

    token = token or secrets.token_urlsafe(24)
    quats, times, name = load_keys(path)
    hosts = {"127.0.0.1", "localhost"}

    def _host_ok(value: str | None) -> bool:
        if not value:
            return False
        host, _, p = value.rpartition(":") if value.count(":") == 1 else (value, "", "")
        return host in hosts and (port == 0 or p == str(port))

    def _authorised(request: Request) -> bool:
        given = (
            request.query_params.get("token")
            or request.headers.get("x-quatspline-token")
            or request.cookies.get("quatspline_token")
        )
        return bool(given) and secrets.compare_digest(str(given), token)

    def _bad(status: int, msg: str) -> Response:
        return PlainTextResponse(msg + "\n", status_code=status)

    async def _json(request: Request) -> dict:
        body = await request.body()
        if len(body) > MAX_BODY:
            raise ValueError(f"request: body of {len(body)} bytes is over {MAX_BODY}")
        try:
            data = json.loads(body or b"{}")
        except ValueError as e:
            raise ValueError(f"request: not JSON ({e})") from None
        if not isinstance(data, dict):
            raise ValueError("request: expected a JSON object")
        return data

    def _design_args(data: dict):
        method = data.get("method", "c3")
        if not isinstance(method, str):
            raise TypeError("method: expected a string")
        params = data.get("params") or {}
        if not isinstance(params, dict):
            raise TypeError("params: expected an object")
        samples = data.get("samples", 2000)
        return method, data.get("quats"), data.get("times"), params, samples

    async def index(request: Request) -> Response:
        html = (STATIC / "index.html").read_text(encoding="utf-8")
        resp = HTMLResponse(html.replace("__TOKEN__", token))
        resp.set_cookie("quatspline_token", token, httponly=True, samesite="strict")
        return resp

    async def static(request: Request) -> Response:
        rel = request.path_params["name"]
        if rel not in ASSETS or not (STATIC / rel).is_file():
            return _bad(404, "not found")
        return Response((STATIC / rel).read_bytes(), media_type=ASSETS[rel])

    async def state(request: Request) -> Response:
        return JSONResponse(
            design.to_json(
                {
                    "name": name,
                    "quats": quats,
                    "times": times,
                    "methods": design.method_specs(),
                    "missing_assets": missing_assets(),
                }
            )
        )

    async def evaluate(request: Request) -> Response:
        try:
            data = await _json(request)
            method, q, t, params, samples = _design_args(data)
            out = design.evaluate(method, q, t, params, samples)
        except (ValueError, TypeError) as e:
            return JSONResponse({"error": str(e).splitlines()[0]}, status_code=400)
        except Exception as e:  # the server never dies of a design; the page shows why
            return JSONResponse({"error": f"{type(e).__name__}: {e}"}, status_code=400)
        return JSONResponse(design.to_json(out))

    async def export(request: Request) -> Response:
        try:
            data = await _json(request)
            fmt = data.get("format")
            if fmt not in EXPORT_FORMATS:
                raise ValueError(f"format: expected one of {', '.join(EXPORT_FORMATS)}")
            method, q, t, params, samples = _design_args(data)
            blob = design.export_bytes(fmt, method, q, t, params, samples)
        except (ValueError, TypeError) as e:
            return JSONResponse({"error": str(e).splitlines()[0]}, status_code=400)
        except Exception as e:
            return JSONResponse({"error": f"{type(e).__name__}: {e}"}, status_code=400)
        return Response(
            blob,
            media_type=EXPORT_FORMATS[fmt],
            headers={"Content-Disposition": f'attachment; filename="{_filename(fmt)}"'},
        )

    app = Starlette(
        routes=[
            Route("/", index),
            Route("/static/{name:path}", static),
            Route("/api/state", state),
            Route("/api/evaluate", evaluate, methods=["POST"]),
            Route("/api/export", export, methods=["POST"]),
        ]
    )

    class Guard:
        """Host, origin and token checks before any route (403), unknown paths 404."""

        def __init__(self, inner):
            self.inner = inner

        async def __call__(self, scope, receive, send):
            if scope["type"] not in ("http", "websocket"):
                return await self.inner(scope, receive, send)
            request = Request(scope)
            origin = request.headers.get("origin")
            if not _host_ok(request.headers.get("host")):
                resp = _bad(403, "forbidden: unknown host")
            elif origin is not None and not _host_ok(origin.split("://", 1)[-1]):
                resp = _bad(403, "forbidden: cross-origin request")
            elif not _authorised(request):
                resp = _bad(403, "forbidden: missing or wrong token")
            else:
                return await self.inner(scope, receive, send)
            await resp(scope, receive, send)

    guarded = Guard(app)
    guarded.state = app.state  # type: ignore[attr-defined]
    app.state.token = token
    return guarded


def _filename(fmt: str) -> str:
    return "keys.json" if fmt == "keys" else f"design.{fmt}"


def _free_port(host: str) -> int:
    with socket.socket() as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def serve(
    path=None,
    *,
    host: str = "127.0.0.1",
    port: int = 0,
    open_browser: bool = True,
    token: str | None = None,
) -> None:
    """Runs the viewer until interrupted.

    Parameters
    ----------
    path : str or pathlib.Path, optional
        Keys file, recording or trajectory (default: the bundled example).
    host : str, default "127.0.0.1"
        Interface to bind (the default keeps the viewer on this machine).
    port : int, default 0
        Port (0: a free one).
    open_browser : bool, default True
        Open the page in the default browser.
    token : str, optional
        Access token (default: random).

    Raises
    ------
    ImportError
        Without the ``viewer`` extra (starlette, uvicorn).
    ValueError
        If ``path`` cannot be read, or the page's JavaScript is not installed.
    """
    _web()
    import uvicorn

    missing = missing_assets()
    if missing:
        raise ValueError(
            f"viewer: the page's JavaScript is not installed ({missing[0]} missing); "
            "build the package with `make viewer-assets`"
        )
    p = Path(path) if path is not None else None
    # listen before the URL is printed, so a browser opened at once finds the server
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, int(port)))
    except OSError as e:
        sock.close()
        raise OSError(f"--port: cannot listen on {host}:{port} ({e.strerror or e})") from None
    sock.listen(128)
    port = int(sock.getsockname()[1])
    app = create_app(p, token, port)
    url = f"http://{host}:{port}/?token={app.state.token}"
    print(f"quatspline view: {url}  (Ctrl-C to stop)", flush=True)
    if open_browser:
        webbrowser.open(url)
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning"))
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
