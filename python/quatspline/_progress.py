"""Progress bars (tqdm) for reading, sampling, fitting and exporting: shown on a terminal
only, and only once the work has taken more than a second."""

from __future__ import annotations

import contextlib
import sys


class _Null:
    def update(self, n: int = 1) -> None:
        pass


@contextlib.contextmanager
def progress(total: int | None = None, desc: str = "", enabled: bool = True, unit: str = "it"):
    """A tqdm bar on standard error (``disable=None``: hidden when it is not a terminal,
    ``delay=1``: hidden for work under a second), or a no-op."""
    if not enabled:
        yield _Null()
        return
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        yield _Null()
        return
    with tqdm(
        total=total, desc=desc, unit=unit, disable=None, delay=1.0, leave=False, file=sys.stderr
    ) as bar:
        yield bar
