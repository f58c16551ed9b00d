"""The fast path of the text readers: pandas' C parser over the whole table.

``table(path, sep, ncols, skip)`` returns the data rows as a float64 array (the first column
int64 with ``int_first=True``), or None whenever anything is unusual — pandas missing, a
non-numeric cell, a short or long row, a comment inside the data, NaN or inf — so the caller
falls back to its careful line-by-line parser, which gives the same result or the exact
file:line:column error. Both paths give bit-identical values (tested).
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from .._util import progress_bars as _progress
from .._util.optional import need
from ._common import MAX_LINE, open_regular

#: below this size the careful parser is fast enough and pandas' import is not worth it
MIN_BYTES = 1 << 16


def table(path, sep: str, ncols: int | None, skip: int = 0, int_first: bool = False, min_cols=None):
    """Rows after ``skip`` header lines; ``sep`` one character or ``"ws"`` (any whitespace);
    ``ncols`` the exact column count (``min_cols``: at least that many, extra ignored)."""
    try:
        with open_regular(path, "rb") as f:
            head = f.read(MIN_BYTES)
    except (OSError, ValueError):
        return None  # the caller's careful parser opens it again and names what is wrong
    if len(head) < MIN_BYTES:
        return None
    if not _lines_within_limit(path):
        return None  # the careful parser reads at most MAX_LINE of a line and names it
    try:
        pd = need("pandas", extra="pandas", what="the fast text reader")
    except ImportError:
        return None  # the careful parser reads without pandas
    # header lines, then comment lines at the top; a comment further down makes a ragged or
    # non-numeric row, which sends the caller to the careful parser
    lines = head.split(b"\n")
    top = skip
    while top < len(lines) - 1 and lines[top].lstrip(b"\xef\xbb\xbf").startswith(b"#"):
        top += 1
    if top >= len(lines) - 1:
        return None
    if sep == "ws":
        # single spaces (the common case) parse twice as fast as the general whitespace rule
        body = b"\n".join(lines[top:-1])
        simple = not any(x in body for x in (b"\t", b"  ", b" \n", b"\n ", b"\r"))
        seps = [" ", r"\s+"] if simple and not body.startswith(b" ") else [r"\s+"]
    else:
        seps = [sep]
    for k, sp in enumerate(seps):
        df = _read(pd, path, sp, top)
        if df is not None and (ncols is None or df.shape[1] == ncols):
            break
        if k == len(seps) - 1:
            return None
    if min_cols is not None and df.shape[1] < min_cols:
        return None
    kinds = [dt.kind for dt in df.dtypes]
    first = 1 if int_first else 0
    if int_first and kinds[0] not in "i":
        return None
    if not all(k in "fi" for k in kinds[first:]):
        return None
    vals = df.iloc[:, first:].to_numpy(dtype=np.float64)
    if not np.all(np.isfinite(vals)):
        return None
    if int_first:
        return df.iloc[:, 0].to_numpy(dtype=np.int64), vals
    return vals


def _lines_within_limit(path) -> bool:
    """Whether every line of the file is shorter than :data:`MAX_LINE` bytes (so shorter in
    characters too). pandas' tokenizer holds a whole line and its cells (several times the
    line's size), so a file with a longer line is left to the careful parser, which refuses it
    after reading :data:`MAX_LINE` characters. Every aligned block of ``MAX_LINE // 2`` bytes
    must hold a line end (then no line spans ``MAX_LINE`` bytes): one pass over the file in
    blocks read into one buffer (not a memory map, which a file truncated meanwhile would
    turn into SIGBUS)."""
    block = MAX_LINE // 2
    buf = bytearray(block)
    view = memoryview(buf)
    try:
        with open_regular(path, "rb") as f:
            while True:
                n = 0
                while n < block:  # a whole block (a read may return less)
                    k = f.readinto(view[n:])
                    if not k:
                        break
                    n += k
                if n < block:
                    # the end: the last line started in a block that held a line end
                    return True
                if buf.find(b"\n") < 0:
                    return False
    except (OSError, ValueError):
        return False


#: From this size on, and only when a progress bar can show (standard error is a terminal),
#: pandas reads through a byte-counting file handle that drives the bar. Given a path, pandas
#: parses faster (about 2.5x here, in parallel) but reports no progress; below this size that
#: takes under about a second, so no bar would show anyway.
BAR_BYTES = 512 << 20


def _read(pd, path, sep: str, top: int):
    kw = dict(
        encoding="utf-8-sig", header=None, engine="c", skip_blank_lines=True, skiprows=top, sep=sep
    )
    try:
        # the open file, not the path: pandas must read what open_regular checked
        with open_regular(path, "rb") as raw:
            # a column of mixed types (a bad cell far down) is a DtypeWarning on standard
            # error; the caller's careful parser names the cell instead
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", pd.errors.DtypeWarning)
                if _progress.on_terminal() and os.fstat(raw.fileno()).st_size >= BAR_BYTES:
                    with _progress.reading(path) as bar:
                        return pd.read_csv(_progress.counting(raw, bar), **kw)
                return pd.read_csv(raw, **kw)
    except Exception:  # ParserError (ragged rows), EmptyDataError, UnicodeDecodeError, …
        return None
