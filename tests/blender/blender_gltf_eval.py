"""Run inside Blender: imports a glTF file with Blender's own importer and evaluates the
animated node's F-curves at the given frames (Blender's own F-curve evaluation).

    blender -b --factory-startup --python blender_gltf_eval.py -- in.glb frames.npy out.npz
"""

import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's Blender 3.4 uses the alias numpy 1.24–1.26 lack
    numpy.bool = bool

import addon_utils  # noqa: E402
import bpy  # noqa: E402

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
numpy.savez(
    out,
    fps=bpy.context.scene.render.fps,
    rotation=rot,
    location=loc if loc is not None else numpy.zeros((0, 3)),
    keys=numpy.array([len(curves["rotation_quaternion", 0].keyframe_points)]),
)
