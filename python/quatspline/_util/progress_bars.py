"""Progress bars (tqdm) for reading, sampling, fitting and exporting: shown on a terminal
only, and only once the work has taken more than a second."""

from __future__ import annotations

import contextlib
import io
import os
import sys
from collections.abc import Iterable, Iterator

from tqdm import tqdm


class _Null:
    def update(self, n: int = 1) -> None:
        pass

    def reset(self, total: int | None = None) -> None:
        pass


@contextlib.contextmanager
def progress(
    total: int | None = None, desc: str = "", enabled: bool = True, unit: str = "it", **kw
):
    """A tqdm bar on standard error (``disable=None``: hidden when it is not a terminal,
    ``delay=1``: hidden for work under a second), or a no-op. Extra keywords go to tqdm."""
    if not enabled:
        yield _Null()
        return
    with tqdm(
        total=total,
        desc=desc,
        unit=unit,
        disable=None,
        delay=1.0,
        leave=False,
        file=sys.stderr,
        **kw,
    ) as bar:
        yield bar


def on_terminal() -> bool:
    """Whether a bar would show: standard error is a terminal (tqdm's ``disable=None``)."""
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError):  # replaced or closed stream
        return False


#: files below this size are read without a bar (a fraction of a second either way)
READ_BAR_BYTES = 1 << 20


@contextlib.contextmanager
def reading(path):
    """A bar in bytes for reading the text file ``path`` (no-op for small files)."""
    try:
        size = os.stat(path).st_size
    except (OSError, TypeError, ValueError):
        size = 0
    name = os.path.basename(os.fspath(path)) if size else ""
    with progress(
        total=size,
        desc=f"reading {name}",
        enabled=size >= READ_BAR_BYTES,
        unit="B",
        unit_scale=True,
        unit_divisor=1024,
    ) as bar:
        yield bar


class CountingReader(io.RawIOBase):
    """A binary file that reports the bytes read to a bar (for parsers, such as pandas', that
    pull the file in large blocks); wrap it in ``io.BufferedReader``."""

    def __init__(self, f, bar) -> None:
        self._f = f
        self._bar = bar

    def readable(self) -> bool:
        return True

    def readinto(self, buf) -> int:
        n = self._f.readinto(buf)
        self._bar.update(n or 0)
        return n


def counting(f, bar) -> io.BufferedReader:
    """``f`` (a binary file) read through a buffer that reports progress to ``bar``."""
    return io.BufferedReader(CountingReader(f, bar), buffer_size=1 << 20)


def lines(f: Iterable[str], bar, already: int = 0, every: int = 8192) -> Iterator[str]:
    """The lines of a text file, reporting their length to ``bar`` every ``every`` lines
    (characters: bytes for the ASCII that these formats are); ``already``: characters read
    before (a header line)."""
    done = already
    k = 0
    for text in f:
        done += len(text)
        k += 1
        if k == every:
            bar.update(done)
            done = k = 0
        yield text
    bar.update(done)
