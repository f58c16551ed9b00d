"""The viewer's HTTP server: a token-protected Starlette app on 127.0.0.1.

The module's constants are its limits: request bodies (:data:`MAX_BODY`, :data:`BODY_TIMEOUT`),
connections (:data:`HEADER_TIMEOUT`, :data:`MAX_CONNECTIONS`, :data:`WRITE_TIMEOUT`) and
computations (:data:`WORKERS`, :data:`MAX_QUEUED`, :data:`JOB_TIMEOUT`).
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import os
import pickle
import secrets
import socket
import struct
import sys
import webbrowser
from pathlib import Path

try:  # the open-files limit (not on Windows)
    import resource
except ImportError:  # pragma: no cover - Windows
    resource = None

import numpy as np

from .. import io as qio
from .._util.optional import hint, need
from ..core.algebra import normalize
from ..examples import BETA_EXAMPLE1_VERTICES
from ..ops import design
from ._worker import EXPORT_FORMATS as _EXPORT_FORMATS

FIRST = asyncio.FIRST_COMPLETED

#: What a missing web stack tells (each missing module's ImportError names it and the extra).
VIEWER_HINT = hint("its web stack", "viewer", "quatspline view")

STATIC = Path(__file__).resolve().parent / "static"
#: The only files the server sends: name → media type. Anything else is a 404.
ASSETS = {
    "app.js": "text/javascript",
    "app.css": "text/css",
    "vendor/three.module.js": "text/javascript",
    "vendor/three.core.js": "text/javascript",
    "vendor/OrbitControls.js": "text/javascript",
    "vendor/TransformControls.js": "text/javascript",
    "vendor/uPlot.iife.min.js": "text/javascript",
    "vendor/uPlot.min.css": "text/css",
}
#: Largest request body (bytes); a longer one is refused (413) before it is read.
MAX_BODY = 8 << 20
#: A connection that has not sent a complete request head this many seconds after it opened,
#: or after its previous response, is closed (idle keep-alive and slow-header clients).
HEADER_TIMEOUT = 5.0
#: A request body must arrive within this many seconds (408 otherwise).
BODY_TIMEOUT = 10.0
#: A client that reads none of a pending response for this many seconds is disconnected.
WRITE_TIMEOUT = 30.0
#: Open connections at most (lower when the process may open few files); beyond it the
#: longest-idle connection (else the oldest one stalled on its client) is closed to make
#: room, or the new one is refused with a 503.
MAX_CONNECTIONS = 256
#: Worker processes computing designs and exports, and requests that may wait for one.
WORKERS = 2
MAX_QUEUED = 8
#: A computation still running after this many seconds is stopped (503).
JOB_TIMEOUT = 60.0
#: Seconds the server waits for running requests after SIGTERM or Ctrl-C before it stops.
SHUTDOWN_TIMEOUT = 2
EXPORT_FORMATS = _EXPORT_FORMATS
_HEADER = struct.Struct(">Q")
#: Started in each worker process (the package root comes first on its path).
_WORKER_CODE = (
    "import sys; sys.path.insert(0, sys.argv[1]); "
    "from quatspline.viewer._worker import main; main(int(sys.argv[2]))"
)


class _Refused(Exception):
    """A request the server will not run: ``status`` and a one-line message."""

    def __init__(self, status: int, message: str):
        super().__init__(message)
        self.status = status


class WorkerPool:
    """Runs requests' computations in worker processes, off the server's event loop.

    At most ``workers`` jobs run at once and at most ``max_queued`` wait; one more is a
    503. A job whose client disconnects, or that runs longer than ``timeout`` seconds, is
    stopped by ending its process (a new one starts for the next job); a waiting job whose
    client disconnects never starts.
    """

    def __init__(
        self, workers: int = WORKERS, max_queued: int = MAX_QUEUED, timeout: float = JOB_TIMEOUT
    ):
        self.workers = int(workers)
        self.max_queued = int(max_queued)
        self.timeout = float(timeout)
        self.running = 0
        self._waiting: collections.deque = collections.deque()
        self._idle: list = []
        self._procs: set = set()
        self._reaping: set = set()
        self.started = 0  # worker processes started (for tests and diagnostics)

    @property
    def queued(self) -> int:
        """Jobs waiting for a worker."""
        return sum(1 for f in self._waiting if not f.done())

    async def _slot(self) -> None:
        if self.running < self.workers and not self.queued:
            self.running += 1
            return
        if self.queued >= self.max_queued:
            raise _Refused(503, "server busy: too many computations waiting; try again")
        fut = asyncio.get_running_loop().create_future()
        self._waiting.append(fut)
        try:
            await fut  # the slot is handed over by _release (running stays counted)
        except asyncio.CancelledError:
            if fut.done() and not fut.cancelled():
                self._release()  # handed over just as the client left: pass it on
            raise

    def _release(self) -> None:
        while self._waiting:
            fut = self._waiting.popleft()
            if not fut.done():
                fut.set_result(None)
                return
        self.running -= 1

    async def _spawn(self):
        root = str(Path(__file__).resolve().parent.parent.parent)
        proc = await asyncio.create_subprocess_exec(
            sys.executable,
            "-c",
            _WORKER_CODE,
            root,
            str(os.getpid()),
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
        )
        self.started += 1
        self._procs.add(proc)
        return proc

    def _kill(self, proc) -> None:
        self._procs.discard(proc)
        if proc in self._idle:
            self._idle.remove(proc)
        if proc.returncode is None:
            try:
                proc.kill()
            except ProcessLookupError:
                pass
        task = asyncio.ensure_future(proc.wait())  # reap it without blocking
        self._reaping.add(task)
        task.add_done_callback(self._reaping.discard)

    async def _job(self, kind: str, body: bytes):
        proc = None
        while self._idle and proc is None:
            proc = self._idle.pop()
            if proc.returncode is not None:  # ended since its last job
                self._kill(proc)
                proc = None
        if proc is None:
            proc = await self._spawn()
        try:
            payload = pickle.dumps((kind, body), protocol=pickle.HIGHEST_PROTOCOL)
            proc.stdin.write(_HEADER.pack(len(payload)) + payload)
            await proc.stdin.drain()
            n = _HEADER.unpack(await proc.stdout.readexactly(_HEADER.size))[0]
            answer = pickle.loads(await proc.stdout.readexactly(n))
        except BaseException:
            self._kill(proc)
            raise
        self._idle.append(proc)
        return answer

    async def run(self, kind: str, body: bytes, disconnected=None):
        """``_worker.handle(kind, body)`` in a worker process.

        ``disconnected`` is an awaitable that completes when the client goes away; the job
        is then dropped (not started, or stopped). Raises ``_Refused`` (503) when the queue
        is full or the job runs too long, ``ConnectionAbortedError`` when the client left.
        """
        watch = asyncio.ensure_future(disconnected) if disconnected is not None else None
        try:
            slot = asyncio.ensure_future(self._slot())
            try:
                await asyncio.wait({slot} | ({watch} if watch else set()), return_when=FIRST)
            finally:
                if not slot.done():
                    slot.cancel()
            if not slot.done() or slot.cancelled():
                raise ConnectionAbortedError("client disconnected while waiting")
            slot.result()  # _Refused when the queue is full
            try:
                job = asyncio.ensure_future(self._job(kind, body))
                done, _ = await asyncio.wait(
                    {job} | ({watch} if watch else set()), timeout=self.timeout, return_when=FIRST
                )
                if job in done:
                    return job.result()
                if watch is not None and watch in done:
                    raise ConnectionAbortedError("client disconnected during the computation")
                raise _Refused(
                    503,
                    f"computation stopped after {self.timeout:g} s (the viewer's limit); "
                    "use fewer keys or samples, or the Python API",
                )
            finally:
                if not job.done():
                    job.cancel()  # ends its worker process
                self._release()
        finally:
            if watch is not None and not watch.done():
                watch.cancel()

    async def close(self) -> None:
        """Ends every worker process."""
        for proc in list(self._procs):
            self._kill(proc)
        if self._reaping:
            await asyncio.wait(set(self._reaping), timeout=5)


_BUSY_TEXT = b"server busy: too many connections\n"
_BUSY = (
    b"HTTP/1.1 503 Service Unavailable\r\ncontent-type: text/plain; charset=utf-8\r\n"
    b"content-length: %d\r\nconnection: close\r\n\r\n%s" % (len(_BUSY_TEXT), _BUSY_TEXT)
)


def _protocol_class(max_connections: int, header_timeout: float, write_timeout: float):
    """uvicorn's h11 protocol with the connection limits uvicorn lacks.

    - a connection must send a complete request head within ``header_timeout`` seconds of
      opening or of its previous response (slow or idle clients are closed);
    - at most ``max_connections`` are open: a new one closes the longest-idle connection
      (one not in the middle of a request), else the oldest whose request waits on its
      client (a body still arriving, a response unread), else it is refused with a 503;
    - a client that leaves a response unread for ``write_timeout`` seconds is disconnected;
    - a request body the application did not read ends the connection after the response
      (it is not read and discarded).
    """
    h11 = _web("h11")
    H11Protocol = _web("uvicorn.protocols.http.h11_impl").H11Protocol

    class LimitedH11Protocol(H11Protocol):
        def connection_made(self, transport):
            super().connection_made(transport)
            self._deadline = None
            self._write_deadline = None
            self._dropped = False
            self._idle_since = self.loop.time()
            self._opened = self._idle_since
            live = [c for c in self.connections if c is not self and not c._dropped]
            if len(live) >= max_connections:
                idle = [c for c in live if c._is_idle()]
                stalled = [c for c in live if c._waits_for_client()]
                if idle:
                    min(idle, key=lambda c: c._idle_since)._drop()
                elif stalled:
                    min(stalled, key=lambda c: c._opened)._drop()
                else:
                    self._dropped = True
                    transport.write(_BUSY)
                    transport.close()
                    return
            self._arm()

        def _is_idle(self) -> bool:
            """No request running: before the first, between requests, or a head incomplete."""
            return self.cycle is None or self.cycle.response_complete

        def _waits_for_client(self) -> bool:
            """A request stalled on its client: its body still arriving, or its response
            unread."""
            return self.conn.their_state is h11.SEND_BODY or self.flow.write_paused

        def _drop(self) -> None:
            self._dropped = True
            self._disarm()
            if self.transport is not None and not self.transport.is_closing():
                self.transport.abort()

        def _arm(self) -> None:
            self._disarm()
            self._idle_since = self.loop.time()
            self._deadline = self.loop.call_later(header_timeout, self._on_deadline)

        def _disarm(self) -> None:
            if self._deadline is not None:
                self._deadline.cancel()
                self._deadline = None

        def _on_deadline(self) -> None:
            self._deadline = None
            if self._is_idle():  # no request running: idle, or a head still incomplete
                self._drop()

        def on_response_complete(self) -> None:
            if self.conn.their_state is h11.SEND_BODY:  # a body nobody reads: do not drain it
                self.server_state.total_requests += 1
                self._disarm()
                self.transport.close()
                return
            super().on_response_complete()
            if not self.transport.is_closing():
                self._arm()

        def connection_lost(self, exc):
            self._dropped = True
            self._disarm()
            if self._write_deadline is not None:
                self._write_deadline.cancel()
                self._write_deadline = None
            super().connection_lost(exc)

        def pause_writing(self) -> None:
            super().pause_writing()
            if self._write_deadline is None:
                self._write_deadline = self.loop.call_later(write_timeout, self._drop)

        def resume_writing(self) -> None:
            super().resume_writing()
            if self._write_deadline is not None:
                self._write_deadline.cancel()
                self._write_deadline = None

    return LimitedH11Protocol


def open_files_limit() -> int:
    """Raises this process's soft limit of open files to its hard limit; returns the soft limit."""
    if resource is None:  # not on Windows
        return 512
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    target = hard if hard != resource.RLIM_INFINITY else max(soft, 65536)
    if soft != resource.RLIM_INFINITY and soft < target:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (target, hard))
            soft = target
        except (ValueError, OSError):
            pass
    return soft if soft != resource.RLIM_INFINITY else 1 << 20


def _soft_files_limit() -> int:
    if resource is None:  # not on Windows
        return 512
    soft = resource.getrlimit(resource.RLIMIT_NOFILE)[0]
    return soft if soft != resource.RLIM_INFINITY else 1 << 20


def connection_limit(open_files: int) -> int:
    """Connections the server keeps open at most when the process may open ``open_files``
    files: :data:`MAX_CONNECTIONS`, less when needed to leave room for an accept burst, the
    workers' pipes and the files a request opens."""
    return max(8, min(MAX_CONNECTIONS, (open_files - 256) // 2))


def server_config(app, *, host: str = "127.0.0.1", port: int = 0, open_files: int | None = None):
    """The uvicorn configuration the viewer runs with: the connection limits of
    :func:`_protocol_class` for a process that may open ``open_files`` files (default: its
    current soft limit), and a bounded wait for running requests at shutdown."""
    uvicorn = _web("uvicorn")
    if open_files is None:
        open_files = _soft_files_limit()
    limit = connection_limit(open_files)
    return uvicorn.Config(
        app,
        host=host,
        port=port,
        http=_protocol_class(limit, HEADER_TIMEOUT, WRITE_TIMEOUT),
        ws="none",
        lifespan="on",
        log_level="warning",
        timeout_keep_alive=int(HEADER_TIMEOUT),
        timeout_graceful_shutdown=SHUTDOWN_TIMEOUT,
        h11_max_incomplete_event_size=16 << 10,
        backlog=128,
    )


def _web(module: str = "starlette"):
    """A module of the viewer's web stack (starlette, uvicorn, h11), or an ImportError naming
    the ``viewer`` extra."""
    return need(module, extra="viewer", what="quatspline view")


def missing_assets() -> list[str]:
    """The vendored JavaScript files that are not installed (empty when the page can run)."""
    return [n for n in ASSETS if not (STATIC / n).is_file()]


def example_keys() -> tuple[np.ndarray, np.ndarray, str]:
    """The keys shown without a file: the Beta paper's Example 1 rotations at unit times."""
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


def create_app(
    path: Path | None = None, token: str | None = None, port: int = 0, host: str = "127.0.0.1"
):
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
    host : str, default "127.0.0.1"
        The interface the server listens on: requests naming it (or 127.0.0.1 or localhost)
        in ``Host`` are served, any other name is refused (DNS rebinding).

    Returns
    -------
    starlette.applications.Starlette
        With ``app.state.token`` set.
    """
    _web("uvicorn")  # served by uvicorn: refused early without it
    Starlette = _web("starlette.applications").Starlette
    requests = _web("starlette.requests")
    ClientDisconnect, Request = requests.ClientDisconnect, requests.Request
    responses = _web("starlette.responses")
    HTMLResponse, JSONResponse = responses.HTMLResponse, responses.JSONResponse
    PlainTextResponse, Response = responses.PlainTextResponse, responses.Response
    Route = _web("starlette.routing").Route

    token = token or secrets.token_urlsafe(24)
    pool = WorkerPool()
    quats, times, name = load_keys(path)
    hosts = {"127.0.0.1", "localhost", host.strip("[]").lower()}

    def _host_ok(value: str | None) -> bool:
        """``value`` (a Host header, or an origin without its scheme) names this server."""
        if not value:
            return False
        if value.startswith("["):  # an IPv6 address: [::1]:8000
            name, _, rest = value[1:].partition("]")
            p = rest[1:] if rest.startswith(":") else None
            if rest and p is None:
                return False
        elif value.count(":") == 1:
            name, _, p = value.partition(":")
        else:
            name, p = value, None
        return name.lower() in hosts and (port == 0 or p == str(port))

    def _authorised(request: Request) -> bool:
        given = (
            request.query_params.get("token")
            or request.headers.get("x-quatspline-token")
            or request.cookies.get("quatspline_token")
        )
        if not given:
            return False
        # bytes: compare_digest refuses str with non-ASCII characters (a TypeError, a 500)
        raw = str(given).encode("utf-8", "surrogateescape")
        return secrets.compare_digest(raw, token.encode("utf-8", "surrogateescape"))

    def _bad(status: int, msg: str) -> Response:
        return PlainTextResponse(msg + "\n", status_code=status)

    async def _body(request: Request) -> bytes:
        """The request body, refused (413) before reading when it is declared or grows over
        MAX_BODY, and (408) when it does not arrive within BODY_TIMEOUT."""
        declared = request.headers.get("content-length")
        if declared is not None and (not declared.isdigit() or int(declared) > MAX_BODY):
            raise _Refused(413, f"request: body of {declared} bytes is over {MAX_BODY}")
        chunks: list[bytes] = []

        async def read() -> None:
            size = 0
            async for chunk in request.stream():
                size += len(chunk)
                if size > MAX_BODY:
                    raise _Refused(413, f"request: body is over {MAX_BODY} bytes")
                chunks.append(chunk)

        try:
            await asyncio.wait_for(read(), BODY_TIMEOUT)
        except asyncio.TimeoutError:
            raise _Refused(408, f"request: body not received within {BODY_TIMEOUT:g} s") from None
        return b"".join(chunks)

    async def _disconnected(receive) -> None:
        try:
            while (await receive())["type"] != "http.disconnect":
                pass
        except Exception:  # a broken connection is a gone client too
            return

    async def _compute(request: Request, kind: str) -> Response:
        try:
            body = await _body(request)
            status, media, blob, headers = await pool.run(
                kind, body, _disconnected(request.receive)
            )
        except _Refused as e:
            headers = {"Connection": "close"} if e.status in (408, 413) else {}
            return JSONResponse({"error": str(e)}, status_code=e.status, headers=headers)
        except (ClientDisconnect, ConnectionAbortedError):
            return Response(status_code=499)  # nobody reads it
        except asyncio.CancelledError:  # the server is stopping; its worker has been ended
            return JSONResponse({"error": "server stopping"}, status_code=503)
        except (asyncio.IncompleteReadError, OSError) as e:
            return JSONResponse(
                {"error": f"viewer worker stopped unexpectedly ({type(e).__name__})"},
                status_code=500,
            )
        return Response(blob, status_code=status, media_type=media, headers=headers)

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
        return await _compute(request, "evaluate")

    async def export(request: Request) -> Response:
        return await _compute(request, "export")

    @contextlib.asynccontextmanager
    async def lifespan(app):
        try:
            yield
        finally:
            await pool.close()

    app = Starlette(
        routes=[
            Route("/", index),
            Route("/static/{name:path}", static),
            Route("/api/state", state),
            Route("/api/evaluate", evaluate, methods=["POST"]),
            Route("/api/export", export, methods=["POST"]),
        ],
        lifespan=lifespan,
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
            elif origin is not None and not (
                origin.startswith("http://") and _host_ok(origin[len("http://") :])
            ):
                resp = _bad(403, "forbidden: cross-origin request")
            elif not _authorised(request):
                resp = _bad(403, "forbidden: missing or wrong token")
            else:
                return await self.inner(scope, receive, send)
            await resp(scope, receive, send)

    guarded = Guard(app)
    guarded.state = app.state  # type: ignore[attr-defined]
    app.state.token = token
    app.state.pool = pool
    return guarded


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
    _web("starlette")
    uvicorn = _web("uvicorn")
    missing = missing_assets()
    if missing:
        raise ValueError(
            f"viewer: the page's JavaScript is not installed ({missing[0]} missing); "
            "build the package with `make viewer-assets`"
        )
    p = Path(path) if path is not None else None
    # listen before the URL is printed, so a browser opened at once finds the server
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, int(port)))
    except OSError as e:
        sock.close()
        raise OSError(f"--port: cannot listen on {host}:{port} ({e.strerror or e})") from None
    sock.listen(128)
    port = int(sock.getsockname()[1])
    app = create_app(p, token, port, host)
    config = server_config(app, host=host, port=port, open_files=open_files_limit())
    url = f"http://{f'[{host}]' if ':' in host else host}:{port}/?token={app.state.token}"
    print(f"quatspline view: {url}  (Ctrl-C to stop)", flush=True)
    if open_browser:
        webbrowser.open(url)
    server = uvicorn.Server(config)
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
