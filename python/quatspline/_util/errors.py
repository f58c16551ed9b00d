"""The package's own exception types, defined once at the bottom layer so that the module
where a fault is known raises the typed error itself (nothing above classifies messages).

:class:`ParameterError` is public as ``quatspline.ops.ParameterError``.
"""

from __future__ import annotations

__all__ = ["ParameterError"]


class ParameterError(ValueError):
    """A bad option value chosen by the caller (method, parameter, rate, count, holdout), as
    opposed to bad data. The command line maps it to exit code 2.

    Examples
    --------
    >>> from quatspline.ops import ParameterError, sample_times
    >>> try:
    ...     sample_times((0.0, 1.0), rate=-1.0)
    ... except ParameterError as e:
    ...     print(isinstance(e, ValueError))
    True"""


# Shown (in tracebacks and documentation) and pickled under its public name.
ParameterError.__module__ = "quatspline.ops"
