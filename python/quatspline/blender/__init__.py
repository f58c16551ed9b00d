"""quatspline inside Blender: an add-on whose operators resample or fit an object's rotation
and location curves with any quatspline method, import trajectory files as animated objects,
and show the angular velocity, acceleration and jerk of an action.

``python -m quatspline.blender install [--blender PATH]`` installs and enables it (see
:mod:`quatspline.blender.installer`); the operators are in :mod:`quatspline.blender.addon`,
the translation between Blender's curves and the library's arrays in
:mod:`quatspline.blender.actions` (no Blender needed). The keys the operators write are
LINEAR and placed by :func:`quatspline.ops.keyframes`, so Blender's own playback stays within
the bounds given (0.01° and 0.1 mm by default).
"""

from __future__ import annotations

from .addon import register, unregister
from .installer import BL_INFO

#: What Blender's add-on list shows (the installed stub add-on carries a copy).
bl_info = BL_INFO

__all__ = ["bl_info", "register", "unregister"]
