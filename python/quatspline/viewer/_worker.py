"""The viewer's computations, run in a separate worker process.

The server never computes a design on its event loop: it streams a request's body (bounded),
hands the bytes to a worker process through a pipe and answers with what comes back. A job
whose client went away, or that runs past its deadline, is stopped by ending the process.

Protocol on the worker's stdin/stdout: each message is an 8-byte big-endian length followed by
a pickle. A job is ``(kind, body)``; the answer is ``(status, media_type, content, headers)``.

An evaluation's answer is JSON whose float arrays travel as their bytes (see :func:`packed`):
writing 2,000 samples' numbers as decimal text took most of a slider's latency.
"""

from __future__ import annotations

import base64
import ctypes
import json
import os
import pickle
import signal
import struct
import sys

import numpy as np

from ..ops import design

#: Fields a request body may hold, per endpoint (anything else is refused, naming it).
FIELDS = {
    "evaluate": ("method", "params", "quats", "times", "samples"),
    "export": ("format", "method", "params", "quats", "times", "samples", "options"),
}
EXPORT_FORMATS = {
    "csv": "text/csv",
    "json": "application/json",
    "glb": "model/gltf-binary",
    "keys": "application/json",
}
_HEADER = struct.Struct(">Q")


def _request(kind: str, body: bytes) -> dict:
    try:
        data = json.loads(body or b"{}")
    except (ValueError, RecursionError) as e:
        raise ValueError(f"request: not JSON ({e})") from None
    if not isinstance(data, dict):
        raise ValueError("request: expected a JSON object")
    unknown = sorted(k for k in data if k not in FIELDS[kind])
    if unknown:
        raise ValueError(
            f"request: unknown field{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(map(repr, unknown))} (valid: {', '.join(FIELDS[kind])})"
        )
    return data


def _kind(value) -> str:
    """The JSON kind of a parsed value, for messages."""
    if value is None:
        return "null"
    return {bool: "a boolean", str: "a string", list: "an array", dict: "an object"}.get(
        type(value), "a number"
    )


def _design_args(data: dict):
    method = data.get("method", "c3")
    if not isinstance(method, str):
        raise TypeError(f"method: expected a string, got {_kind(method)}")
    params = data.get("params")
    if params is None:
        params = {}
    if not isinstance(params, dict):
        raise TypeError(f"params: expected an object, got {_kind(params)}")
    samples = data.get("samples", 2000)
    return method, data.get("quats"), data.get("times"), params, samples


def packed(d: dict) -> dict:
    """``d`` for JSON, each finite float array as ``{"shape": [...], "f8": base64}``: its
    float64 values, little-endian, row-major (exact, and far faster to write and read than
    decimal text); other values as :func:`quatspline.ops.design.to_json` writes them.

    Examples
    --------
    >>> import numpy as np
    >>> from quatspline.viewer._worker import packed
    >>> packed({"t": np.array([0.0, 0.5]), "n": 2})
    {'t': {'shape': [2], 'f8': 'AAAAAAAAAAAAAAAAAADgPw=='}, 'n': 2}
    """
    out = {}
    for k, v in d.items():
        if isinstance(v, np.ndarray) and v.dtype.kind == "f" and np.all(np.isfinite(v)):
            raw = np.ascontiguousarray(v, dtype="<f8").tobytes()
            out[k] = {"shape": list(v.shape), "f8": base64.b64encode(raw).decode("ascii")}
        else:
            out[k] = design.to_json(v)
    return out


def _error(e: BaseException) -> tuple:
    if isinstance(e, (ValueError, TypeError)):
        msg = (str(e).splitlines() or [type(e).__name__])[0]
    else:  # the server never dies of a design; the page shows why
        msg = f"{type(e).__name__}: {(str(e).splitlines() or [''])[0]}"
    return 400, "application/json", json.dumps({"error": msg}).encode(), {}


def _filename(fmt: str) -> str:
    return "keys.json" if fmt == "keys" else f"design.{fmt}"


def handle(kind: str, body: bytes) -> tuple[int, str, bytes, dict]:
    """One request: ``kind`` is ``"evaluate"`` or ``"export"``, ``body`` the request's JSON.

    Returns ``(status, media_type, content, headers)``; bad input is a 400 whose JSON names
    what is wrong.
    """
    try:
        data = _request(kind, body)
        if kind == "evaluate":
            method, q, t, params, samples = _design_args(data)
            out = design.evaluate(method, q, t, params, samples)
            blob = json.dumps(packed(out), allow_nan=False).encode()
            return 200, "application/json", blob, {}
        fmt = data.get("format")
        if not isinstance(fmt, str):
            raise TypeError(f"format: expected a string ({', '.join(EXPORT_FORMATS)})")
        if fmt not in EXPORT_FORMATS:
            raise ValueError(f"format: expected one of {', '.join(EXPORT_FORMATS)}")
        method, q, t, params, samples = _design_args(data)
        blob = design.export_bytes(fmt, method, q, t, params, samples, data.get("options"))
        disposition = {"Content-Disposition": f'attachment; filename="{_filename(fmt)}"'}
        return 200, EXPORT_FORMATS[fmt], blob, disposition
    except Exception as e:
        return _error(e)


def _read_exact(fd: int, n: int) -> bytes | None:
    chunks = []
    while n:
        b = os.read(fd, min(n, 1 << 20))
        if not b:
            return None
        chunks.append(b)
        n -= len(b)
    return b"".join(chunks)


def _end_with_parent(parent: int) -> None:
    """On Linux, the kernel ends this worker when the server process dies, even mid-job."""
    if not sys.platform.startswith("linux"):
        return
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # the server died before prctl took effect
        os._exit(0)


def main(parent: int) -> None:
    """The worker loop: jobs from stdin, answers to stdout, until stdin closes.

    ``parent`` is the server's process id.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    _end_with_parent(parent)
    out = os.dup(1)
    os.dup2(2, 1)  # stray prints must not corrupt the answers
    sys.stdout = sys.stderr
    while True:
        head = _read_exact(0, _HEADER.size)
        if head is None:
            return
        payload = _read_exact(0, _HEADER.unpack(head)[0])
        if payload is None:
            return
        kind, body = pickle.loads(payload)
        answer = pickle.dumps(handle(kind, body), protocol=pickle.HIGHEST_PROTOCOL)
        try:
            os.write(out, _HEADER.pack(len(answer)))
            view = memoryview(answer)
            while view:
                view = view[os.write(out, view) :]
        except OSError:  # the server is gone
            return


if __name__ == "__main__":
    main(os.getppid())
