"""Atomic output: write to a temporary file beside the target, rename on success.

Rules (docs/robustness.md): only regular files are written — an existing target that is a
device, FIFO, socket or directory is refused, never replaced; a symbolic link is followed and
its target replaced (the link stays); a replaced file keeps its permission bits and, where the
process may set them, its owner and group; the temporary file is removed on any error, on
Ctrl-C and on SIGTERM.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import signal
import stat
import threading
from pathlib import Path


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def resolve_output(path) -> tuple[Path, os.stat_result | None]:
    """The file to replace for ``path`` (symbolic links followed) and its current status, or
    a ValueError if it exists and is not a regular file."""
    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    try:
        st = os.stat(target)
    except FileNotFoundError:
        return target, None
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(
            f"{path}: is {_kind(st.st_mode)}; refusing to replace it (only regular files are "
            "written)"
        )
    return target, st


def adopt_mode(tmp, old: os.stat_result | None) -> None:
    """Gives the new file ``tmp`` the replaced file's permission bits (and owner and group
    where the process may set them), or a new file's usual mode (0666 less the umask)."""
    if old is not None:
        os.chmod(tmp, stat.S_IMODE(old.st_mode))
        with contextlib.suppress(OSError):  # only root (or the owner, for the group)
            os.chown(tmp, old.st_uid, old.st_gid)
        os.chmod(tmp, stat.S_IMODE(old.st_mode))  # chown may clear setuid bits
    else:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)


class _Terminated(SystemExit):
    """SIGTERM during a write: unwinds like Ctrl-C so the temporary file is removed."""


def _on_sigterm(signum, frame):
    raise _Terminated(128 + signal.SIGTERM)


@contextlib.contextmanager
def sigterm_unwinds():
    """While writing, SIGTERM raises (exit status 143) instead of killing the process at once,
    so cleanup runs. Only in the main thread, and only if nobody else handles SIGTERM."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    try:
        previous = signal.getsignal(signal.SIGTERM)
    except (ValueError, AttributeError):  # pragma: no cover - no SIGTERM on this platform
        yield
        return
    if previous is not signal.SIG_DFL:
        yield
        return
    signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _create_temporary(target: Path, holder: list) -> int:
    """Creates ``.NAME.XXXXXXXXXXXX.tmp`` beside ``target`` (mode 0600, O_EXCL) and returns its
    descriptor. The name is put in ``holder`` *before* the file is created, so an interrupt
    (SIGINT, SIGTERM) that lands at any point after the creation finds the name to remove;
    tempfile.mkstemp only reveals it after returning (found by the SIGTERM test under load)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    flags |= getattr(os, "O_BINARY", 0)
    for _ in range(100):
        name = target.parent / f".{target.name}.{secrets.token_hex(6)}.tmp"
        holder.append(name)
        try:
            return os.open(name, flags, 0o600)
        except FileExistsError:
            holder.pop()  # someone else's file: never ours to remove
    raise FileExistsError(f"{target}: cannot create a temporary file beside it")


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", **kwargs):
    """Yields a file object; on success it replaces ``path`` atomically, on failure the
    temporary file is removed and any existing ``path`` is left untouched."""
    target, old = resolve_output(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    with sigterm_unwinds():
        holder: list[Path] = []
        try:
            fd = _create_temporary(target, holder)
            tmp = holder[-1]
            with os.fdopen(fd, mode, **kwargs) as f:
                adopt_mode(tmp, old)
                yield f
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, target)
        except BaseException:
            if holder:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(holder[-1])
            raise
