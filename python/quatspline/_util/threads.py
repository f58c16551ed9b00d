"""The worker-thread count for batch work (evaluation, conversions, interpolation)."""

from __future__ import annotations

import inspect

from .. import _core
from .checks import integer

__all__ = ["get_num_threads", "set_num_threads"]

get_num_threads = _core.get_num_threads


def set_num_threads(n: int) -> None:
    """Sets the number of worker threads for batch work.

    Parameters
    ----------
    n : int
        Threads to use; 0 means one per core (the default). Results do not depend on it.

    Raises
    ------
    TypeError
        ``n`` is not an integer (e.g. 2.5).
    ValueError
        ``n`` is negative or above 1024.

    Examples
    --------
    >>> import quatspline as qs
    >>> qs.set_num_threads(2)
    >>> qs.get_num_threads()
    2
    >>> qs.set_num_threads(0)
    """
    _core.set_num_threads(integer(n, "n", 0, 1024))


# Like the compiled functions' docstrings: no leading indentation (tests/test_package.py).
set_num_threads.__doc__ = inspect.cleandoc(set_num_threads.__doc__ or "")
