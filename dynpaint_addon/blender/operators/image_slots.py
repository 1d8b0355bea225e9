"""Operators on a painting's image slots: open (assign or replace) and remove."""
import os

import bpy
from bpy.props import EnumProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from ... import params
from ...inputs.channel_names import IMAGE_EXTENSIONS
from ..state.images import load_image
from ..state.settings import channel_images
from .common import PaintingOperator, active_painting, run_and_report


class DYNPAINT_OT_image_open(PaintingOperator, bpy.types.Operator, ImportHelper):
    """Assign or replace the image of one of the painting's channels"""
    bl_idname = "dynpaint.image_open"
    bl_label = "Open Image"
    bl_options = {"REGISTER", "UNDO"}

    channel: EnumProperty(items=[(c, c.replace("_", " ").title(), params.CHANNELS[c][0])
                                 for c in params.CHANNELS], options={"HIDDEN"})
    filter_glob: StringProperty(default=";".join("*" + e for e in IMAGE_EXTENSIONS),
                                options={"HIDDEN"})

    def execute(self, context):
        mat = active_painting(context)

        def work():
            img = load_image(self.filepath, self.channel)
            setattr(mat.dynamic_painting, f"image_{self.channel}", img)   # updates (sync.py)
            return [("INFO", f"{self.channel}: {os.path.basename(self.filepath)}")]
        return run_and_report(self, context, work, catch=(ValueError, OSError))


class DYNPAINT_OT_image_remove(PaintingOperator, bpy.types.Operator):
    """Remove the image of this channel (its branch leaves the material)"""
    bl_idname = "dynpaint.image_remove"
    bl_label = "Remove Image"
    bl_options = {"REGISTER", "UNDO"}

    channel: EnumProperty(items=[(c, c, "") for c in params.CHANNELS], options={"HIDDEN"})

    def execute(self, context):
        s = active_painting(context).dynamic_painting
        imgs = channel_images(s)
        if self.channel == "shape" or (self.channel in ("dark", "bright")
                                       and not ({"dark", "bright"} - {self.channel}) & imgs.keys()):
            self.report({"ERROR"}, f"the painting needs its {self.channel} image: replace it instead")
            return {"CANCELLED"}
        setattr(s, f"image_{self.channel}", None)
        return {"FINISHED"}


CLASSES = (DYNPAINT_OT_image_open, DYNPAINT_OT_image_remove)
