"""Run inside Blender: imports a glTF file with Blender's own importer and evaluates the
animated node's F-curves at the given frames (Blender's own F-curve evaluation).

    blender -b --factory-startup --python blender_gltf_eval.py -- in.glb frames.npy out.npz
    python blender_gltf_eval.py -- in.glb frames.npy out.npz    (Blender as a module: bpy)
"""

import importlib
import os
import sys

import numpy

if "bool" not in vars(numpy):  # Debian's Blender 3.4 uses the alias numpy 1.24–1.26 lack
    numpy.bool = bool

import bpy  # noqa: E402

# after bpy: Blender as a Python module puts its scripts/modules on sys.path on import
addon_utils = importlib.import_module("addon_utils")

argv = sys.argv[sys.argv.index("--") + 1 :]
src, frames_path, out = argv
addon_utils.enable("io_scene_gltf2", default_set=True)
bpy.ops.import_scene.gltf(filepath=src)
obj = next(o for o in bpy.data.objects if o.animation_data and o.animation_data.action)
frames = numpy.load(frames_path)
curves = {(fc.data_path, fc.array_index): fc for fc in obj.animation_data.action.fcurves}
rot = numpy.array(
    [[curves["rotation_quaternion", i].evaluate(f) for i in range(4)] for f in frames]
)
loc = None
if ("location", 0) in curves:
    loc = numpy.array([[curves["location", i].evaluate(f) for i in range(3)] for f in frames])
# the first location curve's keys: frame, value, and the Bézier handles Blender set
fc = curves["location", 0]
handles = numpy.array(
    [[*k.co, *k.handle_left, *k.handle_right] for k in fc.keyframe_points], dtype=float
)
handle_types = sorted(
    {t for k in fc.keyframe_points for t in (k.handle_left_type, k.handle_right_type)}
)
numpy.savez(
    out,
    handles=handles,
    handle_types=numpy.array(handle_types),
    fps=bpy.context.scene.render.fps,
    blender=numpy.array(bpy.app.version),
    interpolation=numpy.array(
        sorted({k.interpolation for fc in curves.values() for k in fc.keyframe_points})
    ),
    rotation=rot,
    location=loc if loc is not None else numpy.zeros((0, 3)),
    keys=numpy.array([len(curves["rotation_quaternion", 0].keyframe_points)]),
)
if not bpy.app.binary_path:
    # Blender as a Python module (bpy 4.2) crashes on exit after its glTF importer ran: at
    # exit it frees the importer's Python classes after Python has finalised. The results are
    # written: leave at once.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
