"""Run by test_blender_screenshot.py in Blender with its interface (under Xvfb): keys an empty's
quaternion rotation at four frames, resamples it with the add-on's operator (C³ spline) and
takes a screenshot of the graph editor showing the resampled F-curves."""

import math
import sys

import bpy

OUT = sys.argv[sys.argv.index("--") + 1]


def setup():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.object.empty_add(type="ARROWS")
    obj = bpy.context.active_object
    obj.name = "body"
    obj.rotation_mode = "QUATERNION"
    keys = ((1, (1, 0, 0), 0.0), (25, (0, 0, 1), 1.2), (49, (0, 1, 0), 0.9), (73, (1, 1, 0), 2.0))
    for frame, axis, angle in keys:
        n = math.sqrt(sum(c * c for c in axis))
        half = angle / 2
        obj.rotation_quaternion = (math.cos(half), *(math.sin(half) * c / n for c in axis))
        obj.keyframe_insert("rotation_quaternion", frame=frame)
    bpy.context.scene.frame_end = 73
    assert bpy.ops.quatspline.resample(method="c3") == {"FINISHED"}
    win = bpy.context.window
    big = max(win.screen.areas, key=lambda a: a.width * a.height)
    big.ui_type = "FCURVES"
    bpy.context.scene.frame_set(37)

    def shoot():
        region = [r for r in big.regions if r.type == "WINDOW"][0]
        with bpy.context.temp_override(window=win, area=big, region=region):
            bpy.ops.graph.view_all()
        with bpy.context.temp_override(window=win, area=big):
            bpy.ops.screen.screenshot(filepath=OUT)
        bpy.ops.wm.quit_blender()

    bpy.app.timers.register(shoot, first_interval=1.0)


bpy.app.timers.register(setup, first_interval=1.0)
