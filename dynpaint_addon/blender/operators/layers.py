"""Add › Dynamic Painting › Layered…: a scene of layers (pipeline.md §15) from an .ora file,
a folder of layer images or a layered recipe (built by blender/scenes/layered_build.py)."""
import os

import bpy
from bpy.props import BoolProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from ...inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING
from ..scenes.layered_build import add_layered
from ..scenes.painting_scene import unchanged_images_on_failure
from .add import DYNPAINT_OT_add, select_only
from .common import run_and_report


class DYNPAINT_OT_add_layered(bpy.types.Operator, ImportHelper):
    """Add a layered Dynamic Painting: an OpenRaster file (.ora, from Krita, GIMP or MyPaint),
    a folder of layer images (Photoshop's Export Layers to Files) or a layered recipe — one
    plane per layer at its depth, the layers in front casting shadows on those behind"""
    bl_idname = "dynpaint.add_layered"
    bl_label = "Add Layered Painting"
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: StringProperty(default="*.ora;*.toml", options={"HIDDEN"})
    spacing: FloatProperty(
        name="Spacing", default=DEFAULT_SPACING, min=0.0, soft_max=0.5, precision=3,
        description="Depth between one layer and the next, in widths of the back layer "
                    "(.ora files and folders; a recipe gives its own depths)")
    shade: FloatProperty(
        name="Dark Shade", default=DEFAULT_SHADE, min=0.0, max=1.0,
        description="A plain painted layer's dark image: this share of its colour (linear)")
    size: FloatProperty(name="Size", default=1.0, min=0.001, unit="LENGTH",
                        description="Width of the back layer in scene units")
    parallax: BoolProperty(
        name="Keep the Composition", default=True,
        description="With a perspective camera, scale each layer by (D − z)/D about the "
                    "camera's axis so the camera sees the painting as composed; moving the "
                    "camera then shows true parallax (pipeline.md §15)")

    def execute(self, context):
        path = self.filepath
        if not os.path.exists(path) and os.path.isdir(self.directory):
            path = self.directory               # a folder was picked, no file in it
        path = path.rstrip(os.sep) if os.path.isdir(path) else path

        def work(progress):
            with unchanged_images_on_failure():
                parent, messages = add_layered(
                    context, path, self.spacing, self.shade, self.size, self.parallax,
                    DYNPAINT_OT_add._view_rotation(context), progress)
            select_only(context, parent)
            return [("WARNING", m) for m in messages] + \
                [("INFO", f"Added layered painting '{parent.name}' "
                          f"({len(parent.children)} layers)")]
        return run_and_report(self, context, work, progress=True,
                              catch=(ValueError, OSError, MemoryError))


CLASSES = (DYNPAINT_OT_add_layered,)
