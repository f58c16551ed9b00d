"""Whole datasets at once: one operation over many trajectory files, distributed with Dask.

``run(operation, paths, out_dir)`` expands ``paths`` (files, directories searched recursively,
glob patterns), runs the single-file library operation on every file as one Dask task — on a
``LocalCluster`` by default, or on any running scheduler (``client=`` or ``scheduler=``) — and
returns a table (a pandas ``DataFrame``) with one row per file: its status, duration, number of
samples, error message, and the operation's own figures.

Behaviour at scale:

- one bad file fails alone: its error goes into the table and ``OUTDIR/batch.log``; the others
  go on; a named input that gives no file (missing, an empty directory, a pattern that
  matches nothing) and a file that is not a regular file (FIFO, device, socket: never
  opened) is an error row too;
- inputs are never written over: a batch whose output, bookkeeping record or summary would
  be one of its inputs (by path, symbolic or hard link; ``-o`` an input directory) is
  refused before anything is written, and every input gets an output of its own (see
  :func:`plan`); nor are files the batch did not write: an existing output without the
  batch's record of it (in ``OUTDIR/.quatspline-batch``) is an error row, and summary files
  in a directory where no batch ran refuse the batch;
- directory searches and ``**`` visit each real directory once (symbolic-link loops are not
  followed again) and never read the output directory back as input;
- every output is written atomically (temporary file, then rename); a re-run removes the
  temporaries that killed writes left beside its own outputs (only those, and only when no
  live writer holds their lock);
- a re-run skips files whose output is up to date — same input file (size, modification
  and change times, inode), same options, same quatspline version — so an interrupted batch
  resumes where it stopped (``force=True`` redoes everything); the input's version is taken
  before it is read and checked after the work: a file rewritten meanwhile is an error row,
  never recorded as up to date;
- memory per task is bounded: files larger than ``max_file_bytes`` are refused with a message
  before they are read, and sampling is bounded by ``max_samples``;
- each file goes through exactly the code of the single-file command (``quatspline sample`` …),
  so its output is identical to that command's, bit for bit.

``OUTDIR/summary.csv`` holds the per-file table, ``OUTDIR/summary.md`` a readable summary
(for ``compare``: per method, the median over files of the per-file median held-out error and
how often the method was the best), and ``OUTDIR/summary.png`` a figure (with matplotlib).

Dask is an optional dependency: ``pip install "quatspline[dask]"``.
"""

from __future__ import annotations

import argparse
import contextlib
import fnmatch
import glob
import hashlib
import json
import math
import numbers
import os
import stat
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import io as qio
from . import ops
from ._core import __version__
from ._util.atomic import atomic_write, file_kind, make_directories, remove_stale_temporaries
from ._util.errors import ParameterError
from ._util.optional import MissingDependency, need
from ._util.options import parse_positive_int, parse_smoothing
from ._util.progress_bars import progress as progress_bar
from .arguments import (
    add_compare_options,
    add_export_options,
    add_fit_options,
    add_imu_simulate_options,
    add_input_options,
    add_method_options,
    add_sampling_options,
    compare_options,
    examples,
    export_options,
    fit_options,
    imu_simulate_options,
    method_options,
    read_input,
    read_options,
    sampling_options,
)
from .io._common import open_regular

__all__ = ["OPERATIONS", "expand_inputs", "local_cluster", "plan", "run", "summarize"]

#: The operations ``run`` knows, with the extension of their per-file output.
OPERATIONS = ("sample", "fit", "compare", "export", "imu-simulate")

_STATE_DIR = ".quatspline-batch"
_DEFAULT_MAX_FILE_BYTES = 1 << 30
_TRAJ_EXT = (".csv", ".txt", ".tum", ".json", ".npz", ".bvh", ".kitti", ".bag", ".mcap")


def _need_dask():
    """``dask.distributed``, or an ImportError naming the ``dask`` extra."""
    return need("dask.distributed", extra="dask", what="quatspline batch")


# ---- inputs -----------------------------------------------------------------------------------
def _identity(st: os.stat_result) -> tuple[int, int]:
    return (st.st_dev, st.st_ino)


def _not_regular(path) -> str | None:
    """Why ``path`` is not a regular file to read (symbolic links followed), or None. Only
    ``stat`` is used: nothing is opened, so a FIFO or a device cannot block or flood."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return "broken symbolic link" if os.path.islink(path) else "no such file"
    except OSError as e:
        return f"cannot read ({e.strerror or e})"
    if not stat.S_ISREG(st.st_mode):
        return f"is {file_kind(st.st_mode)}; only regular files are read"
    return None


def _subdirs_and_files(d: Path, problems: list, seen: set, exclude: set, cache=None):
    """The entries of ``d``: subdirectories not yet seen (each real directory once, whatever
    the symbolic links: no loop is followed twice) and the other names. ``cache`` (a dict)
    keeps listings by real directory, so that a pattern's later parts, or a link back to a
    directory already listed, do not list it again."""
    dirs: list[Path] = []
    files: list[Path] = []
    key: object = str(d)
    if cache is not None:
        with contextlib.suppress(OSError):
            key = _identity(d.stat())
    if cache is not None and key in cache:
        entries = cache[key]
    else:
        try:
            with os.scandir(d) as it:
                entries = sorted(it, key=lambda e: e.name)
        except OSError as e:
            problems.append((str(d), f"{d}: cannot list this directory ({e.strerror or e})"))
            entries = []
        if cache is not None:
            cache[key] = entries
    for e in entries:
        try:
            is_dir = e.is_dir()  # follows links: a linked directory is searched once
        except OSError:
            is_dir = False
        if not is_dir:
            files.append(Path(e.path))
            continue
        try:
            ident = _identity(e.stat())
        except OSError:
            continue
        if ident in seen or ident in exclude or e.name == _STATE_DIR:
            continue
        seen.add(ident)
        dirs.append(Path(e.path))
    return dirs, files


def _walk(root: Path, problems: list, exclude: set) -> list[Path]:
    """Every non-directory under ``root``, each real directory listed once."""
    seen = {_identity(root.stat())}
    out: list[Path] = []
    stack = [root]
    while stack:
        dirs, files = _subdirs_and_files(stack.pop(), problems, seen, exclude)
        out += files
        stack += reversed(dirs)
    return out


def _hidden(name: str, part: str) -> bool:
    return name.startswith(".") and not part.startswith(".")


def _glob(pattern: str, problems: list, exclude: set) -> list[Path]:
    """``glob.glob(pattern, recursive=True)`` without following a directory loop: ``**``
    lists each real directory once, and the output directory is never searched. Like glob,
    wildcards do not match hidden names (those starting with a dot) unless the part of the
    pattern starts with a dot; directories are not returned."""
    parts = Path(pattern).parts
    i = next(k for k, part in enumerate(parts) if glob.has_magic(part))
    base = Path(*parts[:i]) if i else Path(".")
    try:
        if not base.is_dir():
            return []
    except OSError:
        return []
    out: list[Path] = []
    level = [base]
    cache: dict = {}
    for k in range(i, len(parts)):
        part, last = parts[k], k == len(parts) - 1
        nxt: list[Path] = []
        for d in level:
            if part == "**":
                seen = {_identity(d.stat())}
                stack, found = [d], [d]
                while stack:
                    dirs, files = _subdirs_and_files(stack.pop(), problems, seen, exclude, cache)
                    dirs = [s for s in dirs if not s.name.startswith(".")]
                    found += dirs
                    stack += reversed(dirs)
                    if last:
                        out += [f for f in files if not f.name.startswith(".")]
                nxt += found
            elif glob.has_magic(part):
                dirs, files = _subdirs_and_files(d, problems, set(), exclude, cache)
                if last:
                    out += [
                        f
                        for f in files
                        if fnmatch.fnmatch(f.name, part) and not _hidden(f.name, part)
                    ]
                nxt += [
                    s for s in dirs if fnmatch.fnmatch(s.name, part) and not _hidden(s.name, part)
                ]
            else:
                p = d / part
                if last:
                    if os.path.lexists(p) and not p.is_dir():
                        out.append(p)
                elif p.is_dir():
                    nxt.append(p)
        level = []
        idents: set = set()
        for d in nxt:  # each real directory once
            with contextlib.suppress(OSError):
                ident = _identity(d.stat())
                if ident not in idents:
                    idents.add(ident)
                    level.append(d)
    return out


def _expand(patterns, extensions=_TRAJ_EXT, out_dir=None):
    """The regular files named by ``patterns`` and, for each named input that yields none or
    names something that is not a regular file, ``(name, one-line message)``."""
    if isinstance(patterns, (str, os.PathLike)):
        patterns = [patterns]
    exclude: set = set()
    out_ident = None
    if out_dir is not None:
        for d in (Path(out_dir), Path(out_dir) / _STATE_DIR):
            with contextlib.suppress(OSError):
                if d.is_dir():
                    exclude.add(_identity(d.stat()))
        with contextlib.suppress(OSError):
            out_ident = _identity(Path(out_dir).stat())
    found: dict[str, Path] = {}
    problems: list[tuple[str, str]] = []
    for pat in patterns:
        s = os.fspath(pat) if isinstance(pat, os.PathLike) else pat
        if not isinstance(s, str):
            raise TypeError(f"paths: expected file names, got {type(pat).__name__}")
        if not s:
            problems.append(("''", "'': an empty input name"))
            continue
        p = Path(s)
        try:
            st = os.stat(s)
        except OSError:
            st = None
        if st is not None and stat.S_ISDIR(st.st_mode):
            if out_ident is not None and _identity(st) == out_ident:
                raise ParameterError(
                    f"{s}: the output directory is this input directory; its outputs would "
                    "be read back as inputs (use a separate or a sub-directory)"
                )
            walked = [f for f in _walk(p, problems, exclude) if f.suffix.lower() in extensions]
            if not walked:
                problems.append(
                    (
                        s,
                        f"{s}: no trajectory files in this directory (searched for "
                        f"{', '.join(extensions)})",
                    )
                )
            hits = walked
        elif st is not None or os.path.lexists(s) or not glob.has_magic(s):
            hits = [p]
        else:
            hits = _glob(s, problems, exclude)
            if not hits:
                problems.append((s, f"no files matched {s!r}"))
        for h in hits:
            why = _not_regular(h)
            if why is not None:
                problems.append((str(h), f"{h}: {why}"))
                continue
            found.setdefault(str(h.resolve()), h)
    unique = {name: msg for name, msg in problems}
    return sorted(found.values(), key=str), sorted(unique.items())


def expand_inputs(patterns, extensions=_TRAJ_EXT, *, out_dir=None) -> list[Path]:
    """The files named by ``patterns``, sorted, each once.

    Directory searches and ``**`` list every real directory once (a symbolic link that
    loops back is not followed again) and never enter ``out_dir`` or the batch's state
    directory. Nothing is opened: every input is checked with ``stat`` to be a regular file.

    Parameters
    ----------
    patterns : str, path or sequence of them
        Files, directories (searched recursively for files whose extension is one of
        ``extensions``) and glob patterns (``*``, ``?``, ``[…]``, ``**`` for any depth).
    extensions : tuple of str
        Extensions (lower case, with the dot) a directory search keeps.
    out_dir : str or pathlib.Path, optional
        The batch's output directory: not searched (a named directory that is ``out_dir``
        is refused).

    Returns
    -------
    list of pathlib.Path
        Regular files, sorted by path, duplicates removed.

    Raises
    ------
    ValueError
        When a named input yields no file (a missing file, an empty directory, a pattern
        that matches nothing) or a file found is not a regular file (a FIFO, a device, a
        socket, a broken link); the one-line message names each.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> for name in ("a.csv", "sub/b.tum", "sub/notes.md"):
    ...     (d / name).parent.mkdir(exist_ok=True)
    ...     _ = (d / name).write_text("")
    >>> [p.name for p in expand_inputs([d])]
    ['a.csv', 'b.tum']
    """
    files, problems = _expand(patterns, extensions, out_dir)
    if problems:
        raise ValueError("inputs: " + "; ".join(msg for _, msg in problems))
    return files


@dataclass(frozen=True)
class Task:
    """One file's work: where it comes from, where its output goes, and its bookkeeping."""

    input: Path
    output: Path
    record: Path
    name: str


#: Output formats of sample/fit: ``to`` → (extension, format given to the writer).
OUTPUT_FORMATS = {
    "csv": (".csv", None),
    "json": (".json", None),
    "npz": (".npz", None),
    "tum": (".txt", "tum"),
    "euroc": (".csv", "euroc"),
}


def _output_ext(operation: str, options: dict) -> str:
    if operation in ("sample", "fit"):
        to = str(options.get("to") or "csv").lower()
        if to not in OUTPUT_FORMATS:
            raise ValueError(
                f"to: unknown output format {to!r}; valid: {', '.join(OUTPUT_FORMATS)}"
            )
        return OUTPUT_FORMATS[to][0]
    if operation == "compare":
        return ".compare.json"
    if operation == "imu-simulate":
        return ".csv"
    return ".glb"


def plan(operation: str, inputs: list[Path], out_dir, options: dict | None = None) -> list[Task]:
    """Where each input's output and bookkeeping record go.

    Outputs mirror the inputs' paths relative to their deepest common directory, so files of
    the same name in different folders do not collide: ``data/a/x.tum`` and ``data/b/x.tum``
    become ``OUTDIR/a/x.csv`` and ``OUTDIR/b/x.csv``.

    Output names are unique, so that no result is lost: an output is named after its input's
    stem (``x.tum`` gives ``x.csv``), except when two inputs of one directory share a stem
    (``x.tum`` and ``x.txt``; names compared ignoring case, as on case-insensitive file
    systems) or the name is one the batch itself writes (``summary.csv``, ``batch.log``):
    each of those keeps its source extension (``x.tum.csv``, ``x.txt.csv``), and should that
    still collide, ``~2``, ``~3``, … is added (``x.tum~2.csv``) in the order of the inputs.

    Parameters
    ----------
    operation : {"sample", "fit", "compare", "export", "imu-simulate"}
    inputs : list of pathlib.Path
        The files (from :func:`expand_inputs`).
    out_dir : str or pathlib.Path
        The output directory.
    options : dict, optional
        The operation's options (``to`` picks the output format of sample/fit).

    Returns
    -------
    list of Task

    Raises
    ------
    ValueError
        (:class:`quatspline.ops.ParameterError`) When a file the batch would write (an
        output, a bookkeeping record, the summary) is one of the inputs — the same path, or
        the same file through a symbolic or hard link. Nothing is written.

    Examples
    --------
    >>> from pathlib import Path
    >>> from quatspline.batch import plan
    >>> tasks = plan("sample", [Path("data/a/x.tum"), Path("data/b/x.tum")], "out")
    >>> [str(t.output) for t in tasks]
    ['out/a/x.csv', 'out/b/x.csv']
    >>> tasks = plan("sample", [Path("data/x.tum"), Path("data/x.txt")], "out")
    >>> [str(t.output) for t in tasks]
    ['out/x.tum.csv', 'out/x.txt.csv']
    """
    options = options or {}
    out = Path(out_dir)
    ext = _output_ext(operation, options)
    absolute = [Path(os.path.abspath(p)) for p in inputs]
    root = Path(os.path.commonpath([str(p.parent) for p in absolute])) if absolute else out
    rels = [p.relative_to(root) for p in absolute]
    names = _output_names(rels, ext)
    tasks = [
        Task(
            input=src,
            output=out / rel.parent / name,
            record=out / _STATE_DIR / rel.parent / (name + ".json"),
            name=str(rel),
        )
        for src, rel, name in zip(inputs, rels, names)
    ]
    _refuse_overwriting_inputs(tasks, out)
    return tasks


#: Files a batch writes at the top of its output directory besides the per-file outputs.
_SUMMARY_FILES = ("summary.csv", "summary.md", "summary.png", "batch.log")


def _output_names(rels: list[Path], ext: str) -> list[str]:
    """Unique output file names for inputs at relative paths ``rels`` (see :func:`plan`)."""

    def key(parent: Path, name: str) -> tuple[str, str]:
        return (str(parent).casefold(), name.casefold())

    taken = {key(Path("."), n) for n in (*_SUMMARY_FILES, _STATE_DIR)}
    for rel in rels:  # the directories deeper outputs go into
        for a in list(rel.parents)[:-1]:
            taken.add(key(a.parent, a.name))
    first = [rel.stem + ext for rel in rels]
    counts: dict = {}
    for rel, name in zip(rels, first):
        k = key(rel.parent, name)
        counts[k] = counts.get(k, 0) + 1
    names: list = [None] * len(rels)
    for i, (rel, name) in enumerate(zip(rels, first)):
        k = key(rel.parent, name)
        if counts[k] == 1 and k not in taken:
            names[i] = name
    taken |= {key(rel.parent, n) for rel, n in zip(rels, names) if n is not None}
    for i in sorted((i for i, n in enumerate(names) if n is None), key=lambda i: str(rels[i])):
        rel = rels[i]
        name, n = rel.name + ext, 2
        while key(rel.parent, name) in taken:
            name, n = f"{rel.name}~{n}{ext}", n + 1
        taken.add(key(rel.parent, name))
        names[i] = name
    return names


def _refuse_overwriting_inputs(tasks: list[Task], out: Path) -> None:
    """A ParameterError if any file the batch would write is one of its inputs: the same
    real path, or the same file (device and inode: a hard link)."""
    by_id: dict = {}
    by_path: dict = {}
    for t in tasks:
        with contextlib.suppress(OSError):
            by_id[_identity(os.stat(t.input))] = t.input
        by_path[os.path.realpath(t.input)] = t.input
    writes = [(t.output, f"the output of {t.input}") for t in tasks]
    writes += [(t.record, f"the record of {t.input}") for t in tasks]
    writes += [(out / n, "the batch's summary") for n in _SUMMARY_FILES]
    for path, what in writes:
        hit = by_path.get(os.path.realpath(path))
        if hit is None:
            with contextlib.suppress(OSError):
                hit = by_id.get(_identity(os.stat(path)))
        if hit is not None:
            raise ParameterError(
                f"{path}: refusing to overwrite the input file {hit} ({what}); choose an "
                "output directory that holds no inputs"
            )


# ---- one file ---------------------------------------------------------------------------------
def _fingerprint(path: Path) -> dict:
    """The input's identity and version, from ``stat`` (nothing is opened): taken before it
    is read and compared after the work, so a file rewritten meanwhile is noticed."""
    st = os.stat(path)
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"{path}: is {file_kind(st.st_mode)}; only regular files are read")
    return {
        "size": st.st_size,
        "mtime_ns": st.st_mtime_ns,
        "ctime_ns": st.st_ctime_ns,
        "inode": st.st_ino,
    }


def _options_key(operation: str, options: dict) -> str:
    blob = json.dumps([operation, options, __version__], sort_keys=True, default=_jsonable)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _up_to_date(task: Task, key: str) -> dict | None:
    """The stored result row when ``task``'s output is current, else None."""
    try:
        rec = json.loads(task.record.read_text())
    except (OSError, ValueError):
        return None
    if not task.output.is_file() or rec.get("options_key") != key:
        return None
    try:
        if rec.get("input") != _fingerprint(task.input):
            return None
    except (OSError, ValueError):
        return None
    row = rec.get("row")
    return row if isinstance(row, dict) and row.get("status") == "ok" else None


def run_one(operation: str, task: Task, options: dict, force: bool = False) -> dict:
    """Runs ``operation`` on one file; never raises for a bad file (the row says what failed).

    This is the function each Dask task executes; it is also the plain-loop path used to
    measure Dask's overhead. The input's version (``stat``: size, times, inode) is taken
    before it is read and compared after the work: if it changed, the row is an error and
    no up-to-date record is kept.

    Returns
    -------
    dict
        ``file``, ``status`` ("ok", "skipped" or "error"), ``duration_s``, ``samples``,
        ``error``, ``output`` and the operation's figures.
    """
    key = _options_key(operation, options)
    if not force:
        row = _up_to_date(task, key)
        if row is not None:
            return {**row, "status": "skipped", "duration_s": 0.0}
    t0 = time.perf_counter()
    row: dict = {"file": task.name, "output": str(task.output), "error": ""}
    before = None
    try:
        # The input's version before it is read; the record of an earlier result goes first,
        # so that a failure (or a change found below) leaves nothing that claims up to date.
        before = _fingerprint(task.input)
        _claim_output(task)
        limit = int(options.get("max_file_bytes") or _DEFAULT_MAX_FILE_BYTES)
        if before["size"] > limit:
            raise ValueError(
                f"{task.input}: {before['size']} bytes is over the per-task limit of {limit} "
                "bytes (raise --max-file-size, or split the recording)"
            )
        figures = _OPERATION_FUNCS[operation](task, options)
        try:
            after = _fingerprint(task.input)
        except (OSError, ValueError):
            after = None
        if after != before:
            raise ValueError(
                f"{task.input}: changed while it was being processed, so its output may mix "
                "old and new content; run the batch again"
            )
        row.update(status="ok", **figures)
    except Exception as e:  # one bad file fails alone, whatever went wrong
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        row.update(status="error", error=f"{type(e).__name__}: {msg}", samples=0)
        row["_traceback"] = traceback.format_exc(limit=8)
    row["duration_s"] = time.perf_counter() - t0
    if row["status"] == "ok":
        rec = {
            "input": before,
            "options_key": key,
            "row": {k: v for k, v in row.items() if not k.startswith("_")},
        }
        with atomic_write(task.record) as f:
            json.dump(rec, f, default=_jsonable)
    return row


def _claim_output(task: Task) -> None:
    """Refuses to replace an existing output this batch did not write (no record of it in the
    state directory: a user's file), then replaces the task's record by a claim that is
    never up to date, so that a failure leaves no record of an earlier result but the output
    stays the batch's own to replace on the next run."""
    try:
        has_record = stat.S_ISREG(os.lstat(task.record).st_mode)
    except OSError:
        has_record = False
    if os.path.lexists(task.output) and not has_record:
        raise ValueError(
            f"{task.output}: exists and was not written by this batch (no record of it in "
            f"{task.record.parent}); refusing to overwrite it (move it away, or choose another "
            "output directory)"
        )
    with atomic_write(task.record) as f:
        json.dump({"output": str(task.output), "row": None}, f)


def _jsonable(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)


# ---- the operations: each file goes through the single-file command's library call ------------
#: The keyword arguments of each operation's library call that ``run`` passes on when given
#: (an option not given takes the library's default, which is the command's default too).
SAMPLE_OPTIONS = (
    "method",
    "params",
    "rate",
    "count",
    "times",
    "derivatives",
    "max_samples",
    "extrapolate",
)
FIT_OPTIONS = (
    "rate",
    "count",
    "times",
    "smoothing",
    "penalty",
    "robust",
    "knots",
    "uncertainty",
    "derivatives",
    "max_samples",
    "extrapolate",
)
COMPARE_OPTIONS = ("methods", "holdout")
IMU_SIMULATE_OPTIONS = ("rate", "method", "params", "fit", "noise", "seed", "max_samples")
EXPORT_OPTIONS = (
    "max_error",
    "max_position_error",
    "interpolation",
    "node",
    "mesh",
    "method",
    "fps",
)
#: The reading options (:func:`quatspline.arguments.read_options`).
READ_OPTIONS = (
    "format",
    "euler",
    "degrees",
    "joint",
    "world",
    "skip_frames",
    "topic",
    "frame",
    "node_in",
    "times_file",
    "sort",
    "dedupe",
)


def _given(options: dict, names) -> dict:
    return {k: options[k] for k in names if options.get(k) is not None}


def _read(task: Task, options: dict):
    return read_input(task.input, _given(options, READ_OPTIONS))


def _write(task: Task, traj, options: dict) -> None:
    to = str(options.get("to") or "csv").lower()
    qio.write(task.output, traj, format=OUTPUT_FORMATS[to][1])


def _op_sample(task: Task, options: dict) -> dict:
    """``quatspline sample IN -o OUT``: the same read, ``ops.sample`` and write."""
    traj = _read(task, options)
    out = ops.sample(traj, **_given(options, SAMPLE_OPTIONS))
    _write(task, out, options)
    return {"samples": len(out), "keys": len(traj)}


def _op_fit(task: Task, options: dict) -> dict:
    """``quatspline fit IN -o OUT``: the same read, ``fit_trajectory`` and write."""
    traj = _read(task, options)
    kwargs = _given(options, FIT_OPTIONS)
    if "smoothing" in kwargs:
        kwargs["smoothing"] = parse_smoothing(kwargs["smoothing"])
    out, f = ops.fit_trajectory(traj, **kwargs)
    _write(task, out, options)
    return {
        "samples": len(out),
        "keys": len(traj),
        "smoothing": float(f.smoothing),
        "effective_dof": float(f.effective_dof),
        "rms_residual_deg": ops.rms_residual_deg(f),
    }


def _op_compare(task: Task, options: dict) -> dict:
    """``quatspline compare IN --json``: the library's compare; the rows written as that
    command prints them."""
    traj = _read(task, options)
    rows = ops.compare(traj, **_given(options, COMPARE_OPTIONS))
    with atomic_write(task.output) as f:
        f.write(json.dumps(rows, indent=1) + "\n")
    figures: dict = {"samples": len(traj)}
    for r in rows:
        for k in ("holdout_median_deg", "holdout_p95_deg", "holdout_max_deg", "rms_jerk"):
            if r.get(k) is not None:
                figures[f"{k}[{r['method']}]"] = r[k]
    return figures


def _op_export(task: Task, options: dict) -> dict:
    """``quatspline export IN -o OUT.glb``: the library's export (glTF, error-bounded)."""
    traj = _read(task, options)
    kwargs = _given(options, EXPORT_OPTIONS)
    if "mesh" in options:  # None: an empty node (``--empty``)
        kwargs["mesh"] = options["mesh"]
    report = ops.export(
        traj, task.output, progress=False, **kwargs, **(options.get("params") or {})
    )
    return {
        "samples": len(traj),
        "rotation_keys": report.rotation_keys,
        "rotation_error_deg": float(np.degrees(report.rotation_error)),
        "translation_keys": report.translation_keys,
    }


def _op_imu_simulate(task: Task, options: dict) -> dict:
    """``quatspline imu simulate IN -o OUT.csv``: the same read, ``ops.simulate_imu`` and
    ``ops.write_simulated`` (EuRoC ``imu0/data.csv``)."""
    traj = _read(task, options)
    data = ops.simulate_imu(traj, **_given(options, IMU_SIMULATE_OPTIONS))
    ops.write_simulated(task.output, data, format="euroc")
    return {"samples": len(data), "keys": len(traj), "accelerometer": data.accel is not None}


_OPERATION_FUNCS = {
    "sample": _op_sample,
    "fit": _op_fit,
    "compare": _op_compare,
    "export": _op_export,
    "imu-simulate": _op_imu_simulate,
}


# ---- the batch --------------------------------------------------------------------------------
#: Largest scheduler file read (Dask writes a few hundred bytes).
MAX_SCHEDULER_FILE = 1 << 20


def _scheduler_address(scheduler) -> str:
    """The address to connect to: ``scheduler`` itself, or for a scheduler file (a name
    ending in ``.json``, or any existing path) its ``"address"``. The file is read through
    the regular-file check (a FIFO or device is refused, never opened to block) and checked,
    so that a file that is not Dask's is a one-line ``ValueError`` naming it (Dask raised a
    bare ``AssertionError`` or ``TypeError``)."""
    name = str(scheduler)
    if not (name.endswith(".json") or os.path.lexists(name)):
        return name
    try:
        with open_regular(name, "rb") as f:
            raw = f.read(MAX_SCHEDULER_FILE + 1)
    except ValueError as e:
        raise ValueError(f"scheduler: {e}") from None
    except OSError as e:
        raise ValueError(f"scheduler: {name}: cannot read ({e.strerror or e})") from None
    if len(raw) > MAX_SCHEDULER_FILE:
        raise ValueError(
            f"scheduler: {name}: larger than {MAX_SCHEDULER_FILE} bytes; not a Dask scheduler file"
        )
    try:
        doc = json.loads(raw.decode("utf-8"))
    except (ValueError, RecursionError):
        raise ValueError(f"scheduler: {name}: not a Dask scheduler file (not JSON)") from None
    address = doc.get("address") if isinstance(doc, dict) else None
    if not isinstance(address, str) or not address.strip():
        raise ValueError(
            f'scheduler: {name}: not a Dask scheduler file (no "address" string such as '
            '"tcp://127.0.0.1:8786")'
        )
    return address


@contextlib.contextmanager
def _client(
    client=None, scheduler: str | None = None, workers: int | None = None, timeout: float = 10.0
):
    """A Dask client: the one given, one connected to ``scheduler``, or a LocalCluster."""
    if client is not None:
        yield client
        return
    dd = _need_dask()
    if scheduler:
        address = _scheduler_address(scheduler)
        try:
            c = dd.Client(address, timeout=timeout)
        except (OSError, TimeoutError) as e:
            raise OSError(
                f"scheduler: cannot reach {address}"
                + (f" (from {scheduler})" if address != str(scheduler) else "")
                + f" within {timeout:g} s ({type(e).__name__})"
            ) from None
        with c:
            yield c
        return
    with local_cluster(workers) as cluster, dd.Client(cluster) as c:
        yield c


def local_cluster(workers: int | None = None):
    """A Dask ``LocalCluster`` of single-threaded worker processes, as ``run`` starts one.

    Dask's nannies export ``MALLOC_TRIM_THRESHOLD_=65536`` to their workers by default; with
    it, glibc returns freed memory to the system so eagerly that our numpy-heavy tasks ran
    about 20 % slower than the same code in a plain loop (measured in
    ``benchmarks/batch.py``). The cluster keeps Dask's one-thread settings for OpenMP, MKL and
    OpenBLAS and leaves malloc's trimming at glibc's default.

    Parameters
    ----------
    workers : int, optional
        Worker processes (default: the number of cores, at most 4).

    Returns
    -------
    dask.distributed.LocalCluster

    Examples
    --------
    >>> from dask.distributed import Client
    >>> from quatspline.batch import local_cluster
    >>> with local_cluster(1) as cluster, Client(cluster) as client:
    ...     print(len(client.scheduler_info()["workers"]))
    1
    """
    dd = _need_dask()
    dask = need("dask", extra="dask", what="quatspline batch")
    _check_workers(workers)
    n = int(workers) if workers is not None else min(os.cpu_count() or 1, 4)
    if n < 1:
        raise ValueError(f"workers: expected at least 1, got {workers}")
    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", default={}) or {})
    env.pop("MALLOC_TRIM_THRESHOLD_", None)
    with dask.config.set({"distributed.nanny.pre-spawn-environ": env}):
        return dd.LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=40,
        )


def run(
    operation: str,
    paths,
    out_dir,
    client=None,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    force: bool = False,
    progress: bool | None = None,
    **options,
):
    """Runs one operation over many trajectory files on Dask and returns the per-file table.

    Parameters
    ----------
    operation : {"sample", "fit", "compare", "export", "imu-simulate"}
        The single-file operation: ``sample`` (resample through a method), ``fit`` (a
        smoothing fit, then sampled), ``compare`` (held-out comparison of methods), ``export``
        (glTF), ``imu-simulate`` (the IMU samples of the motion, EuRoC ``.csv``).
    paths : str, path or sequence of them
        Files, directories (recursive) and glob patterns; see :func:`expand_inputs`.
    out_dir : str or pathlib.Path
        Output directory (created); outputs mirror the inputs' relative paths.
    client : dask.distributed.Client, optional
        A client to use. Without one, ``scheduler`` (an address such as
        ``"tcp://127.0.0.1:8786"`` or a scheduler file) is connected to, or else a
        ``LocalCluster`` with ``workers`` single-threaded worker processes is started.
    scheduler : str, optional
        Scheduler address or scheduler-file path.
    workers : int, optional
        Worker processes of the local cluster, at least 1 (default: the number of cores, at
        most 4).
    force : bool
        Redo files whose outputs are up to date.
    progress : bool, optional
        ``False`` hides the progress bar over files; otherwise it shows on a terminal once
        the batch has run for a second (the package's shared progress helper).
    **options
        The keyword arguments of the operation's library call, as the single-file command
        gives them (:mod:`quatspline.arguments` translates ``quatspline batch``'s arguments
        into these): sample — those of :func:`quatspline.ops.sample_trajectory`
        (:data:`SAMPLE_OPTIONS`); fit — those of :func:`quatspline.fit_trajectory`
        (:data:`FIT_OPTIONS`); compare — ``methods``, ``holdout`` (default: none, as
        ``quatspline compare``); export — those of :func:`quatspline.ops.export` and the
        method's ``params`` (:data:`EXPORT_OPTIONS`; ``fps`` is for BVH, unused in glTF);
        imu-simulate — those of :func:`quatspline.ops.simulate_imu`
        (:data:`IMU_SIMULATE_OPTIONS`; ``noise`` an imu.yaml path is read once). An
        option not given takes the library's default, which is the command's. Also the
        reading options of
        :func:`quatspline.arguments.read_input` (``format``, ``euler``, ``degrees``,
        ``joint``, ``world``, ``skip_frames``, ``topic``, ``frame``, ``node_in``,
        ``times_file``, ``sort``, ``dedupe``), ``to`` (output format of sample/fit, default
        ``"csv"``) and ``max_file_bytes`` (per-task input size limit, default 1 GiB).

    Returns
    -------
    pandas.DataFrame
        One row per file, sorted by file, and an error row for each named input that gave no
        file (missing, an empty directory, a pattern that matched nothing) and for each file
        found that is not a regular file (a FIFO, a device, a socket: never opened). Columns:
        ``file``, ``status``, ``duration_s``, ``samples``, ``error``, ``output`` and the
        operation's figures. Also written to
        ``OUTDIR/summary.csv`` with ``summary.md`` and, with matplotlib, ``summary.png``.

    Raises
    ------
    ValueError
        Unknown operation, no named input gave a file, ``out_dir`` is not a directory;
        :class:`quatspline.ops.ParameterError` (a ``ValueError``) for ``workers`` < 1 and
        when a file the batch would write is one of its inputs (``out_dir`` is an input
        directory, or an output, record or summary is an input by path or link), or when
        ``out_dir`` holds a ``summary.csv``, ``summary.md``, ``summary.png`` or ``batch.log``
        but no batch ran there. Nothing is written then.
    TypeError
        ``workers`` is not an integer, or ``paths`` holds something other than file names.
    OSError
        The scheduler cannot be reached within the timeout.
    ImportError
        Dask (or pandas) is not installed.

    See Also
    --------
    expand_inputs, summarize, local_cluster

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import quatspline as qs, quatspline.io as qio
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> keys = qs.from_rotvec([[0, 0, 0], [0, 0, 0.5], [0, 0.3, 1.0]])
    >>> qio.write(d / "in" / "a.json", qio.Trajectory([0.0, 1.0, 2.0], keys))
    >>> table = run("sample", d / "in", d / "out", workers=1, method="c3", count=5, progress=False)
    >>> table[["file", "status", "samples"]].values.tolist()
    [['a.json', 'ok', 5]]
    """
    if operation not in OPERATIONS:
        raise ValueError(f"operation: unknown {operation!r}; valid: {', '.join(OPERATIONS)}")
    dd = _need_dask()
    pd = need("pandas", extra="dask", what="quatspline batch")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out_dir: {out} exists and is not a directory")
    if (
        operation in ("sample", "fit")
        and options.get("rate") is None
        and options.get("count") is None
        and options.get("times") is None
    ):
        raise ValueError(f"{operation}: give rate= (samples per time unit), count= or times=")
    if operation == "imu-simulate":
        if options.get("rate") is None:
            raise ValueError("imu-simulate: give rate= (IMU samples per second)")
        if isinstance(options.get("noise"), (str, os.PathLike)):
            # read once, before the batch: every task gets the densities, and a changed
            # file changes the options' key (so outputs made with the old one are redone)
            options["noise"] = qio.ImuNoise.from_dict(qio.read_imu_noise(options["noise"]))
        if isinstance(options.get("noise"), qio.ImuNoise):
            options["noise"] = options["noise"].as_dict()
    _check_workers(workers)
    inputs, problems = _expand(paths, out_dir=out)
    if not inputs:
        raise ValueError("inputs: nothing to process: " + "; ".join(m for _, m in problems))
    tasks = plan(operation, inputs, out, options)
    if not (out / _STATE_DIR).is_dir():  # no batch ran here: a summary there is a user's
        for n in _SUMMARY_FILES:
            if os.path.lexists(out / n):
                raise ParameterError(
                    f"{out / n}: exists and was not written by a batch; refusing to overwrite "
                    "it (choose another output directory)"
                )
    make_directories(out / _STATE_DIR, f"out_dir: {out}")
    targets = [p for t in tasks for p in (t.output, t.record)]
    for target in [*targets, *(out / n for n in _SUMMARY_FILES)]:
        remove_stale_temporaries(target)
    rows: list[dict] = [
        {
            "file": name,
            "status": "error",
            "samples": 0,
            "duration_s": float("nan"),
            "output": "",
            "error": f"ValueError: {msg}",
        }
        for name, msg in problems
    ]
    with _client(client, scheduler, workers) as c:
        futures = c.map(
            run_one,
            [operation] * len(tasks),
            tasks,
            [options] * len(tasks),
            [force] * len(tasks),
            pure=False,
        )
        with progress_bar(
            len(tasks), f"batch {operation}", enabled=progress is not False, unit="file"
        ) as bar:
            for fut in dd.as_completed(futures):
                try:
                    rows.append(fut.result())
                except Exception as e:  # a worker lost mid-task, a task that cannot unpickle
                    i = futures.index(fut)
                    rows.append(
                        {
                            "file": tasks[i].name,
                            "status": "error",
                            "samples": 0,
                            "duration_s": float("nan"),
                            "output": str(tasks[i].output),
                            "error": f"{type(e).__name__}: {e}",
                        }
                    )
                bar.update(1)
    _log_errors(out, rows)
    rows = [{k: v for k, v in r.items() if not k.startswith("_")} for r in rows]
    table = pd.DataFrame(rows).sort_values("file", kind="stable").reset_index(drop=True)
    summarize(table, out, operation)
    return table


def _check_workers(workers) -> None:
    if workers is None:
        return
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
        raise TypeError(f"workers: expected an integer, got {type(workers).__name__}")
    if workers < 1:
        raise ParameterError(f"workers: expected at least 1 worker process, got {workers}")


def _log_errors(out: Path, rows: list[dict]) -> None:
    bad = [r for r in rows if r.get("status") == "error"]
    lines = [f"{time.strftime('%Y-%m-%dT%H:%M:%S')} {len(rows)} files, {len(bad)} failed"]
    for r in sorted(bad, key=lambda r: r["file"]):
        lines.append(f"{r['file']}: {r['error']}")
        if r.get("_traceback"):
            lines.append("    " + r["_traceback"].rstrip().replace("\n", "\n    "))
    with atomic_write(out / "batch.log") as f:
        f.write("\n".join(lines) + "\n")


# ---- summary ----------------------------------------------------------------------------------
def _md_cell(x) -> str:
    """A Markdown table cell: floats to 4 digits (NaN empty); ``|`` and backslashes escaped,
    newlines flattened."""
    if isinstance(x, float):
        return "" if math.isnan(x) else f"{x:.4g}"
    return ops.markdown_cell(x)


def _md_table(header: list[str], rows: list[list]) -> str:
    head = "| " + " | ".join(_md_cell(h) for h in header) + " |"
    sep = "|" + "|".join("---" for _ in header) + "|"
    return "\n".join([head, sep] + ["| " + " | ".join(_md_cell(c) for c in r) + " |" for r in rows])


def method_summary(table) -> list[dict]:
    """Per method, over the files of a ``compare`` batch that succeeded: the median of the
    per-file median held-out errors (degrees), their maximum, and how many files the method
    won (lowest per-file median error; ties go to every tied method).

    Parameters
    ----------
    table : pandas.DataFrame
        The table ``run("compare", …)`` returned (columns ``holdout_median_deg[METHOD]``).

    Returns
    -------
    list of dict
        ``method``, ``files``, ``median_of_medians_deg``, ``worst_median_deg``, ``wins``,
        sorted by ``median_of_medians_deg``.
    """
    ok = table[table["status"].isin(["ok", "skipped"])]
    cols = [c for c in table.columns if c.startswith("holdout_median_deg[")]
    if not cols or ok.empty:
        return []
    vals = ok[cols].to_numpy(dtype=float)
    best = np.nanmin(vals, axis=1, keepdims=True)
    wins = np.sum(vals == best, axis=0)
    out = []
    for j, c in enumerate(cols):
        v = vals[:, j][np.isfinite(vals[:, j])]
        out.append(
            {
                "method": c[len("holdout_median_deg[") : -1],
                "files": int(v.size),
                "median_of_medians_deg": float(np.median(v)) if v.size else float("nan"),
                "worst_median_deg": float(np.max(v)) if v.size else float("nan"),
                "wins": int(wins[j]),
            }
        )
    return sorted(out, key=lambda r: r["median_of_medians_deg"])


def summarize(table, out_dir, operation: str) -> None:
    """Writes ``summary.csv``, ``summary.md`` and (with matplotlib) ``summary.png``.

    Parameters
    ----------
    table : pandas.DataFrame
        The per-file table of :func:`run`.
    out_dir : str or pathlib.Path
        The batch's output directory.
    operation : str
        The operation that made the table.

    Returns
    -------
    None
        The files are written atomically into ``out_dir``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import pandas as pd
    >>> from quatspline.batch import summarize
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> row = {"file": "a.txt", "status": "ok", "duration_s": 0.1, "samples": 10, "error": ""}
    >>> table = pd.DataFrame([row])
    >>> summarize(table, d, "sample")
    >>> sorted(p.name for p in d.iterdir())
    ['summary.csv', 'summary.md', 'summary.png']
    """
    out = Path(out_dir)
    with atomic_write(out / "summary.csv", newline="") as f:
        table.to_csv(f, index=False)
    counts = table["status"].value_counts().to_dict()
    ok = table[table["status"].isin(["ok", "skipped"])]
    lines = [
        f"# quatspline batch {operation}",
        "",
        f"{len(table)} files: {counts.get('ok', 0)} done, {counts.get('skipped', 0)} up to date "
        f"(skipped), {counts.get('error', 0)} failed.",
        "",
    ]
    if len(ok):
        dur = table.loc[table["status"] == "ok", "duration_s"].to_numpy(dtype=float)
        samples = ok["samples"].to_numpy(dtype=float) if "samples" in ok else np.zeros(0)
        lines += [
            _md_table(
                ["files", "samples (total)", "median time per file (s)", "total time (s)"],
                [
                    [
                        len(ok),
                        int(np.nansum(samples)),
                        float(np.median(dur)) if dur.size else float("nan"),
                        float(np.sum(dur)),
                    ]
                ],
            ),
            "",
        ]
    per_method = method_summary(table) if operation == "compare" else []
    if per_method:
        lines += [
            "## Methods (held-out error, degrees)",
            "",
            _md_table(
                [
                    "method",
                    "files",
                    "median of per-file medians (°)",
                    "worst per-file median (°)",
                    "wins",
                ],
                [
                    [
                        r["method"],
                        r["files"],
                        r["median_of_medians_deg"],
                        r["worst_median_deg"],
                        r["wins"],
                    ]
                    for r in per_method
                ],
            ),
            "",
        ]
    bad = table[table["status"] == "error"]
    if len(bad):
        lines += [
            "## Failed files",
            "",
            _md_table(["file", "error"], [[r.file, r.error] for r in bad.itertuples()]),
            "",
        ]
    with atomic_write(out / "summary.md") as f:
        f.write("\n".join(lines))
    _figure(table, per_method, out, operation)


def _figure(table, per_method, out: Path, operation: str) -> None:
    try:
        figure = need("matplotlib.figure", extra="plot", what="the batch's summary figure")
    except MissingDependency:
        return
    fig = figure.Figure(figsize=(7, 4), layout="constrained")
    ax = fig.add_subplot()
    if per_method:
        cols = [f"holdout_median_deg[{r['method']}]" for r in per_method]
        ok = table[table["status"].isin(["ok", "skipped"])]
        data = [ok[c].dropna().to_numpy(dtype=float) for c in cols]
        ax.boxplot(data, tick_labels=[r["method"] for r in per_method], showfliers=True)
        ax.set_yscale("log")
        ax.set_ylabel("per-file median held-out error (°)")
        ax.set_xlabel("method")
        ax.set_title(f"compare over {len(ok)} files")
    else:
        dur = table.loc[table["status"] == "ok", "duration_s"].to_numpy(dtype=float)
        ax.hist(dur if dur.size else [0.0], bins=30)
        ax.set_xlabel("time per file (s)")
        ax.set_ylabel("files")
        ax.set_title(f"batch {operation}: {len(table)} files")
    with atomic_write(out / "summary.png", "wb") as f:
        fig.savefig(f, format="png", dpi=110)


# ---- the command line's part (``quatspline batch OPERATION``): arguments → options of :func:`run`
def add_arguments(p, parser_class=None) -> None:
    """Adds ``quatspline batch``'s operations to an argparse parser: one sub-command per
    operation, each with the option groups of the single-file command of that name
    (:mod:`quatspline.arguments`: the same options, choices and defaults) and the batch's
    own: ``-o OUTDIR``, ``--scheduler`` or ``--workers``, ``--force``, ``--max-file-size`` and
    (sample, fit) ``--to``."""
    kw = {} if parser_class is None else {"parser_class": parser_class}
    sub = p.add_subparsers(dest="operation", metavar="OPERATION", required=True, **kw)
    helps = {
        "sample": "sample a spline through each file's keys (as quatspline sample)",
        "fit": "fit a smooth spline to each file and sample it (as quatspline fit)",
        "compare": "compare methods on each file (as quatspline compare --json)",
        "export": "export each file to glTF (as quatspline export -o FILE.glb)",
        "imu-simulate": "simulate the IMU of each file's motion, EuRoC csv (as quatspline imu "
        "simulate -o FILE.csv; --seed gives every file the same seed, as that command would)",
    }
    for op in OPERATIONS:
        o = sub.add_parser(
            op,
            help=helps[op],
            description=helps[op],
            epilog=examples(f"batch {op}"),
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        add_input_options(o, many=True)
        o.add_argument("-o", "--output", required=True, help="output directory")
        where = o.add_mutually_exclusive_group()
        where.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address or file")
        where.add_argument("--workers", type=int, help="local worker processes (default: cores)")
        o.add_argument("--force", action="store_true", help="redo files whose output is up to date")
        o.add_argument("--max-file-size", type=int, metavar="BYTES", help="per-file size limit")
        if op in ("sample", "fit"):
            o.add_argument(
                "--to",
                default="csv",
                type=str.lower,
                choices=tuple(OUTPUT_FORMATS),
                help="output format of each file (default: csv)",
            )
        if op == "sample":
            add_method_options(o)
            add_sampling_options(o)
        elif op == "fit":
            add_sampling_options(o, extrapolate=ops.FIT_EXTRAPOLATE)
            add_fit_options(o)
        elif op == "compare":
            add_compare_options(o)
        elif op == "imu-simulate":
            add_imu_simulate_options(o)
        else:
            add_export_options(o)
            add_method_options(o, what="spline through the keys")


def cli_options(args) -> dict:
    """The options of :func:`run` that ``quatspline batch OPERATION``'s arguments give: the
    same translation as the single-file command's (:mod:`quatspline.arguments`), so each
    file's library call gets the same arguments."""
    opts: dict = {k: v for k, v in read_options(args).items() if v not in (None, False, 0)}
    if args.max_file_size is not None:
        opts["max_file_bytes"] = parse_positive_int(args.max_file_size, "--max-file-size")
    op = args.operation
    if op == "sample":
        opts.update(method_options(args), **sampling_options(args), to=args.to)
    elif op == "fit":
        opts.update(sampling_options(args), **fit_options(args), to=args.to)
    elif op == "compare":
        opts.update(compare_options(args))
    elif op == "imu-simulate":
        opts.update(imu_simulate_options(args))
    else:
        opts.update(export_options(args), **method_options(args))
    return {k: v for k, v in opts.items() if v is not None or k == "mesh"}
