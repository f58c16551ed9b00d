"""The ``quatspline`` command line: argument parsing and one library call per command."""

from __future__ import annotations

from ._commands import main

__all__ = ["main"]
