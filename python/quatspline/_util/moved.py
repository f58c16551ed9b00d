"""Old module paths, kept importable for one release with a :class:`DeprecationWarning`.

The package was laid out by concern (``core``, ``splines``, ``io``, ``fitting``, ``poses``,
``ops``). ``import quatspline.algebra`` and ``from quatspline.keyframe import bessel_rates``
still work: a finder on :data:`sys.meta_path` answers for each old path with a module whose
attributes are looked up in the new modules, in order, and warns once per import. The public
API (``quatspline.slerp``, ``quatspline.fit``, …) never moved and needs none of this.

``quatspline.fit``, ``.spline``, ``.continuity``, ``.integrate``, ``.mean`` and ``.retime`` are
functions, not modules, so those six old module paths have no alias.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

__all__ = ["MOVED", "install"]

#: Old dotted path → the new modules that hold its names, searched in order.
MOVED: dict[str, tuple[str, ...]] = {
    "quatspline.algebra": ("quatspline.core.algebra",),
    "quatspline.convert": ("quatspline.core.convert",),
    "quatspline.interpolate": ("quatspline.core.interpolate",),
    "quatspline.dualquat": ("quatspline.core.dualquat",),
    "quatspline.metrics": ("quatspline.core.metrics",),
    "quatspline.rigid": ("quatspline.core.rigid",),
    "quatspline.threads": ("quatspline._util.threads",),
    "quatspline.simd": ("quatspline._util.simd",),
    "quatspline.bspline": ("quatspline.splines.knots",),
    "quatspline.keyframe": (
        "quatspline.splines",
        "quatspline.splines.hermite",
        "quatspline.splines.catmull_rom",
        "quatspline.splines.keys",
    ),
    "quatspline.se3": ("quatspline.splines.se3",),
    "quatspline.screw": ("quatspline.splines.screw",),
    "quatspline.pose_bspline": ("quatspline.splines.pose_bspline",),
    "quatspline.pose": ("quatspline.poses.pose_spline",),
    "quatspline.resampling": ("quatspline.ops._resample",),
    "quatspline.export": ("quatspline.ops._export",),
    "quatspline.design": ("quatspline.ops._design",),
    "quatspline.io.pandas_bridge": ("quatspline.io.trajectory",),
}


class _Alias(types.ModuleType):
    """A module that finds each attribute in the new modules (imported when first needed)."""

    def __init__(self, name: str, targets: tuple[str, ...]) -> None:
        super().__init__(name, f"Moved: use {' or '.join(targets)}.")
        self.__targets = targets

    def __getattr__(self, attr: str) -> object:
        for target in self.__targets:
            module = importlib.import_module(target)
            if hasattr(module, attr):
                return getattr(module, attr)
        raise AttributeError(f"module {self.__name__!r} has no attribute {attr!r}")

    def __dir__(self) -> list[str]:
        names: set[str] = set()
        for target in self.__targets:
            names.update(dir(importlib.import_module(target)))
        return sorted(names)


class _Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    def find_spec(self, fullname, path=None, target=None):  # noqa: ARG002 - the finder protocol
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec):
        targets = MOVED[spec.name]
        warnings.warn(
            f"{spec.name} is deprecated and will be removed in the next release: "
            f"import from {targets[0]} (or the public names of quatspline) instead",
            DeprecationWarning,
            stacklevel=2,
        )
        return _Alias(spec.name, targets)

    def exec_module(self, module) -> None:
        pass


def install() -> None:
    """Put the finder on :data:`sys.meta_path` (once)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())
