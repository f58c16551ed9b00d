"""Run inside Blender: drives the quatspline add-on's operators on scenes described by a
JSON file (a list of jobs, each with its output .npz) and writes what Blender then plays (its
own F-curve evaluation). One Blender run serves every job (a fresh scene each).

    blender -b --factory-startup --python blender_addon_driver.py -- jobs.json
    python blender_addon_driver.py -- jobs.json     (Blender as a Python module: bpy)

The folders to import quatspline from come in the environment variable QS_PATHS
(os.pathsep-separated), as the installed stub add-on appends them.
"""

import json
import os
import sys

import numpy

if "bool" not in vars(numpy):  # Debian's Blender 3.4 uses the alias numpy 1.24–1.26 lack
    numpy.bool = bool

for _p in os.environ.get("QS_PATHS", "").split(os.pathsep):
    if _p and _p not in sys.path:
        sys.path.append(_p)

import bpy  # noqa: E402
import quatspline.blender  # noqa: E402

(job_path,) = sys.argv[sys.argv.index("--") + 1 :]
with open(job_path, encoding="utf-8") as f:
    jobs = json.load(f)
quatspline.blender.register()


def _keyed_object(spec):
    obj = bpy.data.objects.new("body", None)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.rotation_mode = spec["mode"]
    path = {"QUATERNION": "rotation_quaternion", "AXIS_ANGLE": "rotation_axis_angle"}.get(
        spec["mode"], "rotation_euler"
    )
    frames = spec["frames"]
    for f, rot in zip(frames, spec["rotation"]):
        setattr(obj, path, rot)
        obj.keyframe_insert(path, frame=f)
    for f, loc in zip(spec.get("location_frames", frames), spec.get("location", [])):
        obj.location = loc
        obj.keyframe_insert("location", frame=f)
    return obj


def _play(obj, frames):
    curves = {(fc.data_path, fc.array_index): fc for fc in obj.animation_data.action.fcurves}
    rot = numpy.array(
        [[curves["rotation_quaternion", i].evaluate(f) for i in range(4)] for f in frames]
    )
    loc = numpy.zeros((0, 3))
    if ("location", 0) in curves:
        loc = numpy.array([[curves["location", i].evaluate(f) for i in range(3)] for f in frames])
    interp = {k.interpolation for fc in curves.values() for k in fc.keyframe_points}
    return rot, loc, curves, interp


def _run(job):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    for a in list(bpy.data.actions):
        bpy.data.actions.remove(a)
    scene = bpy.context.scene
    scene.render.fps = job.get("fps", 24)
    scene.render.fps_base = 1.0
    result = {"blender": numpy.array(bpy.app.version)}
    kind = job["kind"]
    if kind in ("resample", "fit", "kinematics"):
        obj = _keyed_object(job["object"])
        op = getattr(bpy.ops.quatspline, kind)
        try:
            ret = op(**job.get("options", {}))
        except RuntimeError as e:  # an operator's ERROR report, raised by bpy.ops
            numpy.savez(job["out"], status=numpy.array(["ERROR"]), error=numpy.array(str(e)),
                        blender=numpy.array(bpy.app.version))  # fmt: skip
            return
        result["status"] = numpy.array(sorted(ret))
        if kind == "kinematics":
            curves = {fc.data_path: fc for fc in obj.animation_data.action.fcurves}
            for prop in ("qs_omega", "qs_alpha", "qs_jerk"):
                fc = curves[f'["{prop}"]']
                result[prop] = numpy.array([fc.evaluate(f) for f in job["frames"]])
            result["summary"] = numpy.array(obj["qs_kinematics"])
    elif kind == "import":
        ret = bpy.ops.quatspline.import_trajectory(filepath=job["file"], **job.get("options", {}))
        result["status"] = numpy.array(sorted(ret))
        obj = bpy.context.view_layer.objects.active
        result["range"] = numpy.array([scene.frame_start, scene.frame_end])
    else:
        raise SystemExit(f"unknown job kind {kind!r}")
    if kind != "kinematics":
        rot, loc, curves, interp = _play(obj, job["frames"])
        result.update(
            rotation=rot,
            location=loc,
            keys=numpy.array(len(curves["rotation_quaternion", 0].keyframe_points)),
            location_keys=numpy.array(
                len(curves["location", 0].keyframe_points) if ("location", 0) in curves else 0
            ),
            interpolation=numpy.array(sorted(interp)),
            mode=numpy.array(obj.rotation_mode),
            euler_curves=numpy.array(
                sum(fc.data_path == "rotation_euler" for fc in curves.values())
            ),
        )
    numpy.savez(job["out"], **result)


for job in jobs:
    _run(job)
quatspline.blender.unregister()
