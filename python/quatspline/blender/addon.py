"""The add-on inside Blender: operators and a panel that translate Blender's data into the
library's operations (:func:`quatspline.ops.keyframes`, :func:`quatspline.ops.sample`,
:func:`quatspline.io.read`) and write the results back as F-curves.

``bpy`` exists only inside Blender: it is imported when the add-on registers, never at import
time, so this module imports anywhere.

Operators (F3 search, and the *quatspline* tab of the 3D view's sidebar):

- ``quatspline.resample`` — the active object's rotation (quaternion or Euler) and location
  curves, through a quatspline method (any row of :data:`quatspline.METHODS`, parameters as
  ``name=value, …``), rewritten as LINEAR quaternion and location keys that Blender's
  playback keeps within the bounds;
- ``quatspline.fit`` — the same with the smoothing fit (rotation and location);
- ``quatspline.import_trajectory`` — a trajectory file (every format of
  :func:`quatspline.io.read`) as an animated empty: its samples as keys (exact), or a method's
  spline keyed within the bounds;
- ``quatspline.kinematics`` — |ω|, |α| and |jerk| of the active object's motion (world frame),
  written as curves of custom properties (``qs_omega``, ``qs_alpha``, ``qs_jerk``: the Graph
  Editor shows them) and their maxima in the panel.
"""

from __future__ import annotations

import threading

import numpy as np

from .._util.optional import MissingDependency, need
from ..io import read as read_trajectory
from ..io.gltf import sign_continuous
from ..io.trajectory import Trajectory
from ..ops import keyframes, sample
from .actions import (
    curve_frames,
    frames_to_times,
    method_items,
    parse_params,
    times_to_frames,
    trajectory_from_samples,
)

__all__ = ["register", "unregister", "write_keys"]

_CLASSES: list = []
_MENU: list = []


def _bpy():
    try:
        return need("bpy", extra="blender", what="the Blender add-on")
    except MissingDependency:
        raise MissingDependency(
            "the quatspline add-on runs inside Blender (no bpy here); install it with "
            "python -m quatspline.blender install"
        ) from None


def _fps(scene) -> float:
    return scene.render.fps / scene.render.fps_base


def write_keys(action, data_path: str, frames, values, group: str) -> None:
    """Replaces the F-curves ``data_path`` of ``action`` by LINEAR keys (frames, values (N, k))."""
    bpy = _bpy()
    for fc in [fc for fc in action.fcurves if fc.data_path == data_path]:
        action.fcurves.remove(fc)
    frames = np.asarray(frames, dtype=float)
    values = np.asarray(values, dtype=float)
    linear = bpy.types.Keyframe.bl_rna.properties["interpolation"].enum_items["LINEAR"].value
    co = np.empty(2 * len(frames))
    co[0::2] = frames
    for i in range(values.shape[1]):
        fc = action.fcurves.new(data_path=data_path, index=i, action_group=group)
        fc.keyframe_points.add(len(frames))
        co[1::2] = values[:, i]
        fc.keyframe_points.foreach_set("co", co.astype(np.float32))
        fc.keyframe_points.foreach_set("interpolation", [linear] * len(frames))
        fc.update()


def _object_motion(obj, fps: float) -> Trajectory:
    """The active object's motion at its key frames, as Blender evaluates its curves."""
    ad = obj.animation_data
    if ad is None or ad.action is None:
        raise ValueError(f"{obj.name}: no action (animate its rotation or location first)")
    mode = obj.rotation_mode
    if mode == "AXIS_ANGLE":
        raise ValueError(
            f"{obj.name}: rotation mode AXIS_ANGLE is not read; use QUATERNION or an Euler mode"
        )
    rot_path = "rotation_quaternion" if mode == "QUATERNION" else "rotation_euler"
    curves = {(fc.data_path, fc.array_index): fc for fc in ad.action.fcurves}
    n_rot = 4 if mode == "QUATERNION" else 3
    keyed = [fc for (p, _), fc in curves.items() if p in (rot_path, "location")]
    frames = curve_frames([[k.co[0] for k in fc.keyframe_points] for fc in keyed])
    base_rot = list(getattr(obj, rot_path))
    rot = np.array(
        [
            [
                curves[rot_path, i].evaluate(f) if (rot_path, i) in curves else base_rot[i]
                for i in range(n_rot)
            ]
            for f in frames
        ]
    )
    loc = None
    if any(("location", i) in curves for i in range(3)):
        loc = np.array(
            [
                [
                    curves["location", i].evaluate(f)
                    if ("location", i) in curves
                    else obj.location[i]
                    for i in range(3)
                ]
                for f in frames
            ]
        )
    return trajectory_from_samples(frames, fps, 0.0, mode, rot, loc, name=obj.name)


def _write_motion(obj, keys: dict, start: float, fps: float) -> int:
    """LINEAR quaternion and location keys on the object's action (Euler curves removed,
    the rotation mode set to QUATERNION); returns the number of rotation keys."""
    action = obj.animation_data.action
    for fc in [fc for fc in action.fcurves if fc.data_path == "rotation_euler"]:
        action.fcurves.remove(fc)
    obj.rotation_mode = "QUATERNION"
    t, q = keys["rotation"]
    write_keys(action, "rotation_quaternion", times_to_frames(start + t, fps), q, "Rotation")
    if "translation" in keys:
        t, p = keys["translation"]
        write_keys(action, "location", times_to_frames(start + t, fps), p, "Location")
    return len(keys["rotation"][0])


def _bounds(op) -> dict:
    return {
        "max_error": f"{op.max_error}deg",
        "max_position_error": f"{op.max_position_error}mm",
        "max_keys": None if op.max_keys == 0 else int(op.max_keys),
    }


def _summary(rep) -> str:
    s = f"{rep.rotation_keys} rotation keys, error ≤ {np.degrees(rep.rotation_bound):.3g}°"
    if rep.translation_keys:
        s += f"; {rep.translation_keys} location keys, error ≤ {rep.translation_bound * 1e3:.3g} mm"
    return s


def _resample(op, context):
    obj = context.active_object
    if obj is None:
        raise ValueError("no active object")
    fps = _fps(context.scene)
    traj = _object_motion(obj, fps)
    params = parse_params(op.method, op.params)
    keys, rep = keyframes(traj, method=op.method, **_bounds(op), **params)
    _write_motion(obj, keys, rep.start, fps)
    return f"{obj.name}: {op.method}: " + _summary(rep)


def _import(op, context):
    bpy = _bpy()
    traj = read_trajectory(op.filepath, op.format or None)
    scene = context.scene
    fps = _fps(scene)
    name = traj.name or "trajectory"
    obj = bpy.data.objects.new(name, None)
    obj.empty_display_type = "ARROWS"
    obj.empty_display_size = op.size
    context.collection.objects.link(obj)
    obj.rotation_mode = "QUATERNION"
    obj.animation_data_create().action = bpy.data.actions.new(name)
    if op.method == "keys":  # the samples themselves, exactly (as float32 F-curve keys)
        t = traj.times - traj.times[0]
        keys = {"rotation": (t, sign_continuous(traj.quats))}
        if traj.positions is not None:
            keys["translation"] = (t, traj.positions)
        start, what = 0.0, f"{len(t)} samples as keys"
    else:
        shifted = Trajectory(traj.times - traj.times[0], traj.quats, traj.positions, name=name)
        params = parse_params(op.method, op.params)
        keys, rep = keyframes(shifted, method=op.method, **_bounds(op), **params)
        start, what = rep.start, f"{op.method}: " + _summary(rep)
    _write_motion(obj, keys, start, fps)
    frames = times_to_frames(start + keys["rotation"][0], fps)
    scene.frame_start, scene.frame_end = int(np.floor(frames[0])), int(np.ceil(frames[-1]))
    for o in context.selected_objects:
        o.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return f"{obj.name}: {what}"


def _kinematics(op, context):
    obj = context.active_object
    if obj is None:
        raise ValueError("no active object")
    fps = _fps(context.scene)
    traj = _object_motion(obj, fps)
    at = frames_to_times(
        np.arange(np.ceil(traj.times[0] * fps), np.floor(traj.times[-1] * fps) + 1), fps
    )
    out = sample(
        traj, op.method, times=at, params=parse_params(op.method, op.params), derivatives=True
    )
    action = obj.animation_data.action
    frames = times_to_frames(out.times, fps)
    maxima = {}
    for col, prop in (("omega", "qs_omega"), ("alpha", "qs_alpha"), ("jerk", "qs_jerk")):
        mag = np.linalg.norm(out.extra[col], axis=1)
        obj[prop] = float(mag[0])
        write_keys(action, f'["{prop}"]', frames, mag[:, None], "quatspline kinematics")
        maxima[col] = float(mag.max())
    obj["qs_kinematics"] = (
        f"max |ω| {maxima['omega']:.4g} rad/s, |α| {maxima['alpha']:.4g} rad/s², "
        f"|jerk| {maxima['jerk']:.4g} rad/s³ ({op.method})"
    )
    return f"{obj.name}: " + obj["qs_kinematics"]


def _operator(bpy, idname: str, label: str, run, props: dict, doc: str, extra: dict | None = None):
    def execute(self, context):
        try:
            msg = run(self, context)
        except (ValueError, TypeError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, msg)
        return {"FINISHED"}

    ns = {
        "bl_idname": idname,
        "bl_label": label,
        "bl_description": doc,
        "bl_options": {"REGISTER", "UNDO"},
        "__annotations__": props,
        "__doc__": doc,
        "execute": execute,
    }
    ns.update(extra or {})
    return type("QUATSPLINE_OT_" + idname.split(".")[1], (bpy.types.Operator,), ns)


def _classes(bpy):
    P = bpy.props
    methods = method_items()

    def bounds():
        return {
            "max_error": P.FloatProperty(
                name="Max rotation error (°)", default=0.01, min=1e-5, max=180.0, precision=4
            ),
            "max_position_error": P.FloatProperty(
                name="Max location error (mm)", default=0.1, min=1e-4, precision=4
            ),
            "max_keys": P.IntProperty(name="Max keys (0: no limit)", default=0, min=0),
            "params": P.StringProperty(name="Parameters", description="name=value, …"),
        }

    def method(default):
        return {"method": P.EnumProperty(name="Method", items=methods, default=default)}

    resample = _operator(
        bpy, "quatspline.resample", "Resample with quatspline", _resample,
        {**method("natural"), **bounds()},
        "Rewrite the active object's rotation and location curves through a quatspline "
        "method, as LINEAR keys that play within the bounds",
    )  # fmt: skip
    fit = _operator(
        bpy, "quatspline.fit", "Fit with quatspline", _resample,
        {**method("fit"), **bounds()},
        "Smooth the active object's rotation and location curves with the quatspline fit, "
        "as LINEAR keys that play within the bounds",
    )  # fmt: skip

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    imp = _operator(
        bpy, "quatspline.import_trajectory", "Trajectory (quatspline)", _import,
        {
            "filepath": P.StringProperty(subtype="FILE_PATH"),
            "format": P.StringProperty(name="Format", description="empty: from the extension"),
            "method": P.EnumProperty(
                name="Keys",
                items=[("keys", "samples", "every sample as a key (exact)")] + methods,
                default="keys",
            ),
            "size": P.FloatProperty(name="Axes size", default=0.1, min=1e-6),
            **bounds(),
        },
        "Import a trajectory file (TUM, EuRoC, CSV, BVH, ROS bag, …) as an animated empty",
        {"invoke": invoke},
    )  # fmt: skip
    kin = _operator(
        bpy, "quatspline.kinematics", "Kinematics (ω, α, jerk)", _kinematics,
        {**method("natural"), "params": P.StringProperty(name="Parameters")},
        "Angular velocity, acceleration and jerk of the active object's motion as curves of "
        "custom properties, and their maxima",
    )  # fmt: skip

    class QUATSPLINE_PT_panel(bpy.types.Panel):
        bl_label = "quatspline"
        bl_space_type = "VIEW_3D"
        bl_region_type = "UI"
        bl_category = "quatspline"

        def draw(self, context):
            col = self.layout.column()
            col.operator("quatspline.resample")
            col.operator("quatspline.fit")
            col.operator("quatspline.import_trajectory")
            col.operator("quatspline.kinematics")
            obj = context.active_object
            if obj is not None and "qs_kinematics" in obj:
                for part in str(obj["qs_kinematics"]).split(", "):
                    col.label(text=part)

    return [resample, fit, imp, kin, QUATSPLINE_PT_panel]


def _menu(self, context):
    self.layout.operator("quatspline.import_trajectory")


def register() -> None:
    """Registers the operators, the panel and the File › Import entry (inside Blender)."""
    bpy = _bpy()
    if _CLASSES:
        return
    # tqdm's default lock holds a multiprocessing semaphore whose clean-up crashes Blender
    # 3.4 on exit once any progress bar was made: a thread lock is enough inside Blender
    need("tqdm", extra="core").tqdm.set_lock(threading.RLock())
    _CLASSES.extend(_classes(bpy))
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(_menu)
    _MENU.append(_menu)


def unregister() -> None:
    """Removes what :func:`register` added."""
    bpy = _bpy()
    for fn in _MENU:
        bpy.types.TOPBAR_MT_file_import.remove(fn)
    _MENU.clear()
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
    _CLASSES.clear()
