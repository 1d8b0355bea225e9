"""Add › Dynamic Painting › From Grease Pencil (issue 42, first step): the active Grease
Pencil drawing as a scene of lit layers, in its place.

Each layer that draws something is drawn by Blender's own Grease Pencil renderer into an
image (scenes/grease_pencil.py: the current frame, or each of the scene's range for an
animated drawing), and made a painting as a plain layer of a layered file is (a shaded dark
copy, its silhouette inflated by parts; sprite sheets where it changes, §16); the layers are
built as Add › Layered… builds them (§15): a plane per layer at its depth — where the artist
moved layers toward the camera, there, else Spacing apart — the layers in front casting
shadows on those behind. The planes lie where the drawing is (its object's XZ plane,
seen from −Y), the drawing is hidden (unhide it to go on drawing; From Grease Pencil again
makes the painting anew). Its images are packed in the .blend.
"""
import math
import os
import shutil
import tempfile

import bpy
from bpy.props import BoolProperty, FloatProperty, IntProperty
from mathutils import Matrix

from ...core.lights import default_sun
from ...inputs.imageio import read_image
from ...inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING, painting_of_frames
from ..scenes.grease_pencil import animated, drawn_layers, layer_depths, render_layers
from ..scenes.layered_build import build_layered
from ..scenes.painting_scene import FACE_CAMERA, NO_CAMERA, unchanged_images_on_failure
from ..state.images import packed_image
from .add import select_only
from .common import run_and_report


# A drawing's layers lie a Spacing apart (0.05 image widths): inflated as a file's layers are
# (a disc a hemisphere), a large card would reach through the layers in front of it
GREASE_PENCIL_RELIEF = 0.1


class DYNPAINT_OT_add_grease_pencil(bpy.types.Operator):
    """Light the active Grease Pencil drawing: each layer a Dynamic Painting at a depth, lit
    by the scene's lights, the layers in front casting shadows on those behind"""
    bl_idname = "dynpaint.add_grease_pencil"
    bl_label = "From Grease Pencil"
    bl_options = {"REGISTER", "UNDO"}

    resolution: IntProperty(name="Resolution", default=1024, min=16, soft_max=4096,
                            description="Width in pixels each layer is drawn at")
    spacing: FloatProperty(
        name="Spacing", default=DEFAULT_SPACING, min=0.0, soft_max=0.5, precision=3,
        description="Depth between one layer and the next, in widths of the drawing")
    shade: FloatProperty(
        name="Dark Shade", default=DEFAULT_SHADE, min=0.0, max=1.0,
        description="Each layer's dark image: this share of its colour (linear)")
    animation: BoolProperty(
        name="Animation", default=True,
        description="Light every frame of the scene's frame range where the drawing changes "
                    "over it (else the current frame alone)")
    relief: FloatProperty(
        name="Relief", default=GREASE_PENCIL_RELIEF, min=0.0, soft_max=1.0, precision=3,
        description="How round each layer's shapes are inflated: 1 makes a disc a hemisphere "
                    "as tall as its radius; a drawing's layers lie close (Spacing), so low")

    @classmethod
    def poll(cls, context):
        if context.object is None or context.object.type != "GREASEPENCIL":
            cls.poll_message_set("Select a Grease Pencil drawing")
            return False
        return True

    def execute(self, context):
        obj = context.object

        def work(progress):
            scene = context.scene
            frames = list(range(scene.frame_start, scene.frame_end + 1)) \
                if self.animation and animated(obj) else None
            folder = tempfile.mkdtemp(prefix="dynpaint-grease-pencil-")
            try:
                paths, (x0, x1, z0, z1), notes = render_layers(
                    obj, folder, self.resolution, frames, lambda f: progress(0.4 * f))
                depths = layer_depths(drawn_layers(obj)[0], x1 - x0, self.spacing)
                with unchanged_images_on_failure():     # (its images are packed copies)
                    parent, messages = self.build(context, obj, paths, depths, frames,
                                                  x1 - x0, progress)
            finally:
                shutil.rmtree(folder, ignore_errors=True)
            parent.name = f"{obj.name} (lit)"
            if FACE_CAMERA in parent.constraints:      # it lies where the drawing does
                parent.constraints.remove(parent.constraints[FACE_CAMERA])
            parent.matrix_world = obj.matrix_world @ \
                Matrix.Translation(((x0 + x1) / 2, 0.0, (z0 + z1) / 2)) @ \
                Matrix.Rotation(math.pi / 2, 4, "X")
            obj.hide_render = True
            obj.hide_set(True)
            select_only(context, parent)
            said = [m for m in messages if NO_CAMERA not in m]   # (it lies where the drawing is)
            return [("WARNING", m) for m in notes + said] + [
                ("INFO", f"Lit {obj.name}: {len(paths)} layers as '{parent.name}' (the "
                         f"drawing is hidden: unhide it to draw on)")]
        return run_and_report(self, context, work, progress=True, failure="From Grease Pencil: ",
                              catch=(ValueError, OSError, MemoryError, RuntimeError))

    def build(self, context, obj, paths, depths, frames, size, progress):
        """The drawing's layers as a scene of paintings (§15) at `depths`: a layer whose
        drawing changes over `frames` a painting of sprite sheets following the scene's
        frames (§16), one that does not a still painting → (parent, messages)."""
        layers, tables, messages = [], {}, []
        for i, (layer_paths, depth) in enumerate(zip(paths, depths)):
            name = os.path.splitext(os.path.basename(layer_paths[0]))[0]
            name = name if frames is None else name.rsplit("_", 1)[0]
            images, p, notes, table = painting_of_frames(
                name, [read_image(path) for path in layer_paths], self.shade, self.relief)
            if table is not None:
                tables[name] = {"": {**table, "start": frames[0]}}
            messages += [f"{name}: {n}" for n in notes]
            layers.append((name, depth, (0.0, 0.0), 1.0, None,
                           {c: packed_image(f"{obj.name} {name} {c}", img, c)
                            for c, img in images.items()}, p))
            progress(0.4 + 0.3 * (i + 1) / len(paths))
        return build_layered(context, obj.name, layers, [default_sun()], messages, size,
                             parallax=False, add_lights=True, frames=tables)


CLASSES = (DYNPAINT_OT_add_grease_pencil,)
