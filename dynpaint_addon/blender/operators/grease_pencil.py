"""Add › Dynamic Painting › From Grease Pencil (issue 42, first step): the active Grease
Pencil drawing as a scene of lit layers, in its place.

Each layer that draws something is drawn by Blender's own Grease Pencil renderer into an
image (scenes/grease_pencil/drawing.py: the current frame, or each of the scene's range for an
animated drawing), and made a painting as a plain layer of a layered file is (a shaded dark
copy, or the shadow colours the artist named; its silhouette inflated by parts; sprite
sheets where it changes, §16); the layers are
built as Add › Layered… builds them (§15): a plane per layer at its depth — where the artist
moved layers toward the camera, there, else Spacing apart — the layers in front casting
shadows on those behind. The planes lie where the drawing is (its object's XZ plane,
seen from −Y), the drawing is hidden (unhide it to go on drawing: the lit copy follows its
changes, scenes/grease_pencil/live.py). Its images are packed in the .blend.
"""
import bpy
from bpy.props import BoolProperty, FloatProperty, IntProperty

from ...core.layers import MAX_LAYERS
from ...inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING
from ..bake.layers import group_materials
from ..bake.live_bake import rendering
from ..scenes.grease_pencil.lit_copy import (GREASE_PENCIL_RELIEF, GREASE_PENCIL_RESOLUTION,
                                              LAYER_EFFECTS, LIT_SETTINGS, light_drawing)
from ..scenes.grease_pencil.live import warm_first_draft
from ..state.shape_options import option_property
from .add import select_only
from .common import run_and_report


class DYNPAINT_OT_add_grease_pencil(bpy.types.Operator):
    """Light the active Grease Pencil drawing: each layer a Dynamic Painting at a depth, lit
    by the scene's lights, the layers in front casting shadows on those behind"""
    bl_idname = "dynpaint.add_grease_pencil"
    bl_label = "From Grease Pencil"
    bl_options = {"REGISTER", "UNDO"}

    resolution: IntProperty(name="Resolution", default=GREASE_PENCIL_RESOLUTION, min=16,
                            soft_max=4096,
                            description="Width in pixels each layer is drawn at")
    spacing: FloatProperty(
        name="Spacing", default=DEFAULT_SPACING, min=0.0, soft_max=0.5, precision=3,
        description="Depth between one layer and the next, in widths of the drawing")
    shade: FloatProperty(
        name="Dark Shade", default=DEFAULT_SHADE, min=0.0, max=1.0,
        description="Each layer's dark image: this share of its colour (linear), where no "
                    "shadow colours are named — a layer \"<name> shadow\" or a material "
                    "\"<material> shadow\" draws them")
    animation: BoolProperty(
        name="Animation", default=True,
        description="Light every frame of the scene's frame range where the drawing changes "
                    "over it (else the current frame alone)")
    merge: BoolProperty(
        name="Merge Back Layers", default=False,
        description=f"Where more than {MAX_LAYERS} layers draw (a scene's most), draw the back "
                    f"ones together as one lit layer (they no longer shadow each other)")
    relief: FloatProperty(
        name="Relief", default=GREASE_PENCIL_RELIEF, min=0.0, soft_max=1.0, precision=3,
        description="How round each layer's shapes are inflated: 1 makes a disc a hemisphere "
                    "as tall as its radius; a drawing's layers lie close (Spacing), so low")

    __annotations__.update({o.name: option_property(o) for o in LAYER_EFFECTS})  # (Paint Shape's)

    @classmethod
    def poll(cls, context):
        if context.object is None or context.object.type != "GREASEPENCIL":
            cls.poll_message_set("Select a Grease Pencil drawing")
            return False
        return True

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        for name in LIT_SETTINGS:
            if name == LAYER_EFFECTS[0].name:
                layout.label(text="Each layer's relief (as Paint Shape's):")
            layout.prop(self, name)

    def execute(self, context):
        obj = context.object
        settings = {name: getattr(self, name) for name in LIT_SETTINGS}

        def work(progress):
            # with a UI the group's shadows as a dragged light's: a draft now, the final in
            # a worker thread (seconds at 1024²: issue 61); a script waits for the final
            parent, lines = light_drawing(context, obj, settings, progress,
                                          bake="now" if rendering() else "live")
            if not rendering():        # the first stroke's draft made ready meanwhile
                warm_first_draft(context, parent)
            select_only(context, parent)
            return [("WARNING", m) for m in lines] + [
                ("INFO", f"Lit {obj.name}: {len(group_materials(parent))} layers as "
                         f"'{parent.name}' (the drawing is hidden: unhide it to draw on; the "
                         f"lit copy follows its changes)")]
        return run_and_report(self, context, work, progress=True, failure="From Grease Pencil: ",
                              catch=(ValueError, OSError, MemoryError, RuntimeError))


CLASSES = (DYNPAINT_OT_add_grease_pencil,)
