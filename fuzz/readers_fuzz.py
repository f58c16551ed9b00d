"""Fuzz the trajectory file readers with atheris: arbitrary bytes as every format
``quatspline.io`` reads (the list is ``readers_check.ENTRIES``, derived from
``quatspline.io.FORMATS``; ROS 2 bag directories included).

The invariant lives in ``readers_check.py`` (shared with tests/test_fuzz_regressions.py, which
replays every input in ``fuzz/regressions/readers``). ``fuzz/corpus/readers`` holds one small
valid file of every format (``seed-*``, written by ``python fuzz/readers_seeds.py``); pass the
regressions folder as a second corpus directory so past findings seed each run:

    python fuzz/readers_fuzz.py fuzz/corpus/readers fuzz/regressions/readers -max_total_time=600

A failure stops the run (libFuzzer writes ``crash-*``). With ``QS_FUZZ_FINDINGS=DIR`` set, a
failure is instead saved in DIR, once per distinct place it was raised (exception type and the
innermost file:line, or the broken invariant), and fuzzing goes on: one long run then collects
every distinct finding.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import traceback

import atheris

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

with atheris.instrument_imports():
    import readers_check

#: The scratch directory the inputs are written to. libFuzzer ends the process from C, so no
#: Python clean-up runs in it: a parent process makes the directory, runs the fuzzer in a
#: child and removes the directory when the child ends (however it ends).
DIR = os.environ.get("QS_FUZZ_SCRATCH", "")


FINDINGS = os.environ.get("QS_FUZZ_FINDINGS")
SEEN: set[str] = set()


def _signature(e: BaseException) -> str:
    frames = traceback.extract_tb(e.__traceback__)
    where = frames[-1] if frames else None
    if isinstance(e, AssertionError):  # the invariant that broke, without the file's name
        return "AssertionError: " + str(e).split(":")[0]
    return f"{type(e).__name__} at {where.filename}:{where.lineno}" if where else type(e).__name__


def one_input(data: bytes) -> None:
    if FINDINGS is None:
        readers_check.check_one(data, DIR)
        return
    try:
        readers_check.check_one(data, DIR)
    except Exception as e:
        sig = _signature(e)
        if sig not in SEEN:
            SEEN.add(sig)
            name = "finding-" + hashlib.sha1(data).hexdigest()
            with open(os.path.join(FINDINGS, name), "wb") as f:
                f.write(data)
            with open(os.path.join(FINDINGS, "findings.txt"), "a") as f:
                f.write(f"{name}\t{sig}\t{str(e)[:300]!r}\n")


def _parent() -> int:
    scratch = tempfile.mkdtemp(prefix="qs-fuzz-")
    try:
        env = {**os.environ, "QS_FUZZ_SCRATCH": scratch}
        return subprocess.run([sys.executable, *sys.argv], env=env).returncode
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == "__main__":
    if not DIR:
        sys.exit(_parent())
    atheris.Setup(sys.argv, one_input)
    atheris.Fuzz()
