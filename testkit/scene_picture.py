"""A painting's plane as a still the way the tests compare it with the numpy core: Cycles at
one sample a pixel, the camera framing the plane pixel for pixel (the add-on's own settings,
blender/scenes/painting_scene.py), written to an EXR and read back (y-up, linear RGBA)."""
import bpy

from dynpaint_addon.blender.scenes.painting_scene import (exact_camera, exact_render_settings,
                                                          output_settings)
from dynpaint_addon.inputs.imageio import read_image


def render_cycles(scene, plane, path):
    """`scene` rendered by Cycles to `path` (.exr) → its pixels; an orthographic camera is
    made to frame `plane` unless the scene has one."""
    if scene.camera is None or scene.camera.data.type != "ORTHO":
        exact_camera(scene, plane)
    exact_render_settings(scene, "cycles")
    output_settings(scene, path)
    bpy.context.view_layer.update()
    bpy.ops.render.render(write_still=True)
    return read_image(path).pixels
