"""Atomic output: write to a temporary file beside the target, rename on success.

Rules (docs/robustness.md): only regular files are written — an existing target that is a
device, FIFO, socket or directory is refused, never replaced; a symbolic link is followed and
its target replaced (the link stays); a replaced file keeps its permission bits and, where the
process may set them, its owner and group; the temporary file is removed on any error, on
Ctrl-C and on SIGTERM.

Temporaries left by a killed writer (SIGKILL, power loss) are removed by the next write to
the same target, and only they: a file named exactly ``.NAME.<12 hex digits>.tmp`` beside
``NAME`` (and, for ROS 2 bags, a directory ``.NAME.<12 hex digits>.bagtmp``). A live writer
holds an advisory lock (``flock``) on its temporary from the moment it creates it until it
renames or removes it; a temporary is stale when nobody holds that lock and it is not empty
(a writer locks before writing its first byte) or, when empty, when it has not been modified
for :data:`STALE_EMPTY_SECONDS` (the instant between creating and locking). Where ``flock``
does not exist (Windows), a temporary is stale when it has not been modified for
:data:`STALE_UNLOCKED_SECONDS`.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import secrets
import shutil
import signal
import stat
import threading
import time
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

#: An empty temporary nobody locks is stale after this many seconds without a change.
STALE_EMPTY_SECONDS = 10.0
#: Without ``flock`` (Windows), a temporary is stale after this many seconds without a change.
STALE_UNLOCKED_SECONDS = 24 * 3600.0


def file_kind(mode: int) -> str:
    """What a non-regular file is, for messages: 'a directory', 'a FIFO (named pipe)' …."""
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
    except (FileNotFoundError, NotADirectoryError):
        why = blocking_component(target.parent)  # a parent that is a file, a FIFO …
        if why is not None:
            raise ValueError(f"{path}: {why}") from None
        return target, None
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(
            f"{path}: is {file_kind(st.st_mode)}; refusing to replace it (only regular files are "
            "written)"
        )
    return target, st


def blocking_component(directory) -> str | None:
    """What keeps ``directory`` from being created: ``"P is a FIFO (named pipe), not a
    directory"`` for its first existing component P that is not a directory (a regular file,
    FIFO, socket, device, dangling symbolic link), else None. Creates nothing."""
    directory = Path(directory)
    for part in [*reversed(directory.parents), directory]:
        try:
            st = os.stat(part)
        except FileNotFoundError:
            if os.path.islink(part):
                return f"{part} is a symbolic link to a missing target"
            return None
        except NotADirectoryError:  # pragma: no cover - found at the component before
            return None
        except OSError:
            return None
        if not stat.S_ISDIR(st.st_mode):
            kind = "a regular file" if stat.S_ISREG(st.st_mode) else file_kind(st.st_mode)
            return f"{part} is {kind}, not a directory"
    return None


def make_directories(directory, path=None) -> None:
    """Creates ``directory`` and its missing parents (``mkdir -p``). A component that exists
    and is not a directory is a one-line ``ValueError`` naming ``path`` (default:
    ``directory``) and that component (see :func:`blocking_component`), instead of
    ``NotADirectoryError: [Errno 20]``."""
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        why = blocking_component(directory)
        if why is None:
            raise
        raise ValueError(f"{path or directory}: {why}") from None


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


def lock_descriptor(fd: int) -> bool:
    """Takes the advisory lock that marks a temporary as in use by a live writer (False
    where ``flock`` does not exist or is not supported by the file system)."""
    if fcntl is None:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return False
    return True


def _temporary_pattern(name: str, suffix: str) -> re.Pattern:
    return re.compile(re.escape(f".{name}.") + r"[0-9a-f]{12}" + re.escape(suffix) + r"\Z")


def _euid() -> int:
    return os.geteuid() if hasattr(os, "geteuid") else 0


def _is_stale(path: Path, fd: int, st: os.stat_result) -> bool:
    """Whether the temporary open as ``fd`` belongs to no live writer (see the module's
    rules); when True the lock is held by us until ``fd`` is closed."""
    age = time.time() - st.st_mtime
    if fcntl is None:
        return age > STALE_UNLOCKED_SECONDS
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return False  # a live writer holds it
    empty = st.st_size == 0 if stat.S_ISREG(st.st_mode) else not os.listdir(path)
    return not empty or age > STALE_EMPTY_SECONDS


def remove_stale_temporaries(target, suffixes=(".tmp",), remove=None) -> list[Path]:
    """Removes the stale temporaries a killed write to ``target`` left beside it (names
    ``.NAME.<12 hex>SUFFIX`` for each suffix; ``.tmp`` files, ``.bagtmp`` directories) and
    returns their paths. Anything else, however similar its name, is left alone: a wrong
    kind (a file where a directory is expected, a symbolic link), a live writer's temporary,
    another name. ``remove(path)`` removes a stale directory temporary (default: the whole
    tree). Errors are ignored (a temporary that cannot be removed stays)."""
    target = Path(target)
    removed: list[Path] = []
    try:
        names = os.listdir(target.parent)
    except OSError:
        return removed
    patterns = [(_temporary_pattern(target.name, sfx), sfx) for sfx in suffixes]
    for name in names:
        for pattern, sfx in patterns:
            if not pattern.match(name):
                continue
            path = target.parent / name
            want_dir = sfx != ".tmp"
            flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
            flags |= getattr(os, "O_CLOEXEC", 0)
            try:
                fd = os.open(path, flags)
            except OSError:
                continue  # a symbolic link (O_NOFOLLOW), gone, or unreadable: not ours
            try:
                st = os.fstat(fd)
                kind_ok = stat.S_ISDIR(st.st_mode) if want_dir else stat.S_ISREG(st.st_mode)
                if not kind_ok or st.st_uid != _euid() or not _is_stale(path, fd, st):
                    continue
                now = os.lstat(path)
                if (now.st_dev, now.st_ino) != (st.st_dev, st.st_ino):
                    continue  # replaced meanwhile
                if want_dir:
                    (remove or shutil.rmtree)(path)
                else:
                    os.unlink(path)
                removed.append(path)
            except OSError:
                continue
            finally:
                os.close(fd)
    return removed


_WORK_LOCKS: dict[Path, int] = {}


def make_work_directory(target, suffix: str) -> Path:
    """A new work directory ``.NAME.<12 hex>SUFFIX`` beside ``target`` (mode 0700), locked
    until :func:`release_work_directory`: a later :func:`remove_stale_temporaries` with the
    same suffix sees a live writer's directory as live and a killed writer's as stale."""
    target = Path(target)
    for _ in range(100):
        work = target.parent / f".{target.name}.{secrets.token_hex(6)}{suffix}"
        try:
            os.mkdir(work, 0o700)
        except FileExistsError:
            continue
        fd = os.open(work, os.O_RDONLY)
        if lock_descriptor(fd):
            _WORK_LOCKS[work] = fd
        else:
            os.close(fd)
        return work
    raise FileExistsError(f"{target}: cannot create a work directory beside it")


def release_work_directory(work) -> None:
    """Drops the lock of a work directory made by :func:`make_work_directory`."""
    fd = _WORK_LOCKS.pop(Path(work), None)
    if fd is not None:
        os.close(fd)


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
            fd = os.open(name, flags, 0o600)
        except FileExistsError:
            holder.pop()  # someone else's file: never ours to remove
            continue
        lock_descriptor(fd)  # marks it live until it is renamed or removed
        return fd
    raise FileExistsError(f"{target}: cannot create a temporary file beside it")


@contextlib.contextmanager
def atomic_write(path, mode: str = "w", **kwargs):
    """Yields a file object; on success it replaces ``path`` atomically, on failure the
    temporary file is removed and any existing ``path`` is left untouched."""
    target, old = resolve_output(path)
    make_directories(target.parent, path)
    remove_stale_temporaries(target)
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
                if fcntl is not None:  # renamed while still locked: never seen as stale
                    os.replace(tmp, target)
            if fcntl is None:  # pragma: no cover - Windows renames closed files only
                os.replace(tmp, target)
        except BaseException:
            if holder:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(holder[-1])
            raise


def _fsync_directory(directory: Path) -> None:
    """Makes renames in ``directory`` durable (where directories can be opened)."""
    try:
        fd = os.open(directory, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # pragma: no cover - Windows
        return
    try:
        with contextlib.suppress(OSError):
            os.fsync(fd)
    finally:
        os.close(fd)


def _journal_path(primary: Path) -> Path:
    return primary.parent / f".{primary.name}.pair"


def _read_journal(journal: Path, primary: Path) -> list[tuple[Path, Path]] | None:
    """The (temporary, final) renames a committed pair write of ``primary`` recorded, or
    None when ``journal`` is missing or is not such a record (then it is not ours and is
    ignored): each temporary must be named as ours beside its final file, and ``primary``
    must be one of the finals."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(journal, flags)  # a FIFO put there cannot block us
    except OSError:
        return None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        with os.fdopen(os.dup(fd), "rb") as f:
            doc = json.loads(f.read(1 << 16).decode("utf-8"))
        moves = [(Path(a), Path(b)) for a, b in doc["renames"]]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    finally:
        os.close(fd)
    for tmp, final in moves:
        if tmp.parent != final.parent or not _temporary_pattern(final.name, ".tmp").match(tmp.name):
            return None
    if primary not in {final for _, final in moves}:
        return None
    return moves


def committed_pair(primary) -> dict[Path, Path]:
    """For a reader of a file pair: the files to read in place of the pair's final names
    while an interrupted :func:`atomic_write_pair` has not been completed yet (final →
    committed temporary), so that a reader sees both new files; empty when there is nothing
    to complete (then the final names hold a consistent pair)."""
    primary = Path(os.path.realpath(primary))
    moves = _read_journal(_journal_path(primary), primary)
    if not moves:
        return {}
    return {final: tmp for tmp, final in moves if tmp.is_file()}


def complete_pair(primary) -> None:
    """Completes an :func:`atomic_write_pair` that a kill interrupted after its commit point
    (renames its remaining temporaries into place, removes the journal). A journal locked by
    a live writer is a ``ValueError`` (two writes of one pair at once)."""
    primary = Path(os.path.realpath(primary))
    journal = _journal_path(primary)
    try:
        flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
        fd = os.open(journal, flags)
    except OSError:
        return
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return
        if fcntl is not None:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                raise ValueError(
                    f"{primary}: another write of this file pair is in progress"
                ) from None
        moves = _read_journal(journal, primary)
        if moves is None:
            return
        for tmp, final in moves:
            if os.path.isfile(tmp) and not os.path.islink(tmp):
                os.replace(tmp, final)
        for directory in {final.parent for _, final in moves}:
            _fsync_directory(directory)
        os.unlink(journal)
        _fsync_directory(journal.parent)
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_write_pair(primary, secondary, mode: str = "w", **kwargs):
    """Yields two file objects ``(f_primary, f_secondary)`` and replaces both files so that
    they change together: after a kill at any point, a reader that resolves the pair through
    :func:`committed_pair` sees either both old files or both new ones.

    The scheme (a journal, as databases do): both temporaries (``.NAME.<hex>.tmp``, each
    beside its file, each kept locked) are written in full and fsynced; then a journal
    ``.PRIMARY.pair`` beside the primary file, listing the two renames, is written, fsynced
    and renamed into place — the commit point; then the secondary temporary is renamed onto
    the secondary file, the primary onto the primary, the directories are fsynced and the
    journal is removed. The guarantee, precisely:

    - killed before the commit point: both files are untouched (old); the temporaries are
      removed by the next write (see the module's rules for stale temporaries);
    - killed after it: the journal names the new files; :func:`committed_pair` lets a reader
      read them (both new) and the next write of the pair completes the renames first
      (:func:`complete_pair`);
    - a program that reads the final names without this library may, between such a kill and
      the next write of the pair, see the new secondary beside the old primary (POSIX has no
      rename of two files at once); the primary (e.g. KITTI poses) is always renamed last.

    On an error or Ctrl-C before the commit point, nothing is changed and the temporaries
    are removed. Each replaced file keeps its mode; both targets follow :func:`atomic_write`'s
    rules (regular files only, symbolic links followed). The two must be different files.
    """
    first, old_first = resolve_output(primary)
    second, old_second = resolve_output(secondary)
    first = Path(os.path.realpath(first))
    second = Path(os.path.realpath(second))
    if first == second:
        raise ValueError(f"{secondary}: is the same file as {primary}; a pair needs two files")
    for target, given in ((first, primary), (second, secondary)):
        make_directories(target.parent, given)
    complete_pair(first)
    remove_stale_temporaries(first)
    remove_stale_temporaries(second)
    journal = _journal_path(first)
    with sigterm_unwinds():
        holder: list[Path] = []
        files = []
        committed = False
        try:
            for target, old in ((first, old_first), (second, old_second)):
                fd = _create_temporary(target, holder)
                files.append(os.fdopen(fd, mode, **kwargs))
                adopt_mode(holder[-1], old)
            tmp_first, tmp_second = holder[0], holder[1]
            yield files[0], files[1]
            for f in files:
                f.flush()
                os.fsync(f.fileno())
            record = {"renames": [[str(tmp_second), str(second)], [str(tmp_first), str(first)]]}
            with atomic_write(journal) as j:
                json.dump(record, j)
            _fsync_directory(journal.parent)
            committed = True  # from here on the new pair is what readers get
            os.replace(tmp_second, second)
            os.replace(tmp_first, first)
            for directory in {first.parent, second.parent}:
                _fsync_directory(directory)
            os.unlink(journal)
        except BaseException:
            if not committed:
                for name in holder:
                    with contextlib.suppress(FileNotFoundError):
                        os.unlink(name)
            raise
        finally:
            for f in files:
                with contextlib.suppress(OSError):
                    f.close()
