"""Optional third-party packages, imported where they are needed, with the pip extra named.

The package's own modules import one another at the top of each file. A function-level import
is for an optional third-party package only, and goes through :func:`need`, so that a missing
package is one :class:`ImportError` naming the extra that provides it::

    pd = need("pandas", extra="pandas", what="DataFrames")
    # ImportError: DataFrames needs pandas: pip install "quatspline[pandas]"
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["MissingDependency", "hint", "need"]


class MissingDependency(ImportError):
    """An optional package is not installed; the message names the pip extra to install."""


def hint(module: str, extra: str, what: str) -> str:
    """The one-line hint for a missing package: ``{what} needs {module}: pip install …``."""
    return f'{what} needs {module}: pip install "quatspline[{extra}]"'


def need(module: str, *, extra: str, what: str | None = None) -> ModuleType:
    """Import the optional third-party ``module`` or raise :class:`MissingDependency`.

    Parameters
    ----------
    module : str
        The dotted module name (``"pandas"``, ``"dask.distributed"``).
    extra : str
        The extra of ``pyproject.toml`` that installs it (``"pandas"``, ``"dask"``).
    what : str, optional
        What needs it, for the message (``"quatspline batch"``, ``"DataFrames"``).

    Examples
    --------
    >>> need("json", extra="none").dumps([1])
    '[1]'
    >>> need("no_such_module", extra="plot", what="plots")
    Traceback (most recent call last):
    ...
    quatspline._util.optional.MissingDependency: plots needs no_such_module: pip install ...
    """
    try:
        return importlib.import_module(module)
    except ImportError as e:
        if e.name is not None and module != e.name and not module.startswith(e.name + "."):
            raise  # the package is installed but one of its own imports failed: show that
        raise MissingDependency(hint(module, extra, what or "this")) from e
