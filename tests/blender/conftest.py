"""The scripts here run inside Blender, not under pytest."""

collect_ignore = ["blender_addon_driver.py", "blender_gltf_eval.py", "blender_screenshot.py"]
