"""Paint Shape (issue 41): paint the painting's shape in Blender, lit as you paint.

One click sets the painting up (the first time) and enters Texture Paint on its plane: a
figure mask and a height layer, packed images of the painting's size (state/painted.py);
the painting's shape image becomes the shape made from them, its own kept as the base
(shapes/painted.py). Texture Paint paints the layer the panel's *Paint On* names while the
material shows the painting lit, with Blender's own brushes (Paint Soft to start: a soft
falloff). Each stroke remakes the shape and the shadows live — a draft while strokes come,
final when they stop — by the Image update a stroke sends, or where none comes by watching
the painted layer's pixels while Texture Paint is on (_watch). *Done* leaves Texture Paint.
"""
import bpy
import numpy as np

from ...core.either_relief import image_casts_either
from ...core.input_rules import relief_of
from ...core.shape import default_preblur_px
from ...core.strokes import changed_box
from ...inputs.imageio import image_data_from_blender
from ...shapes.maker import read_as_made
from ..material.sync import batch, update
from ..state.edits import note_edited, version
from ..state.frames import moves, painting_size
from ..state.images import made_shape_image
from ..state.painted import base_reads, is_painted, new_layers, show_layer, watched_images
from ..state.settings import params_to_settings, settings_to_params
from ..state.status import report
from .common import PaintingOperator, active_painting, run_and_report

SOFT_BRUSH = "brushes/essentials_brushes-mesh_texture.blend/Brush/Paint Soft"
WATCH_S = 0.1          # how often the painted layer is looked at while Texture Paint is on


def set_up(mat, scene):
    """Give the painting its layers and make its shape from them → report lines. The shape
    image before is kept as the base (its §2 settings are the base's: a height map's relief
    is the made shape's floor, a normal map's slopes are added to the painted relief's); a
    painting with no shape image starts from its silhouette (the bright or dark image's
    alpha)."""
    s = mat.dynamic_painting
    p = settings_to_params(s)
    if moves(mat):
        raise ValueError("Paint Shape paints a still painting; this one moves (§16)")
    base = s.image_shape
    over_normals = base is not None and p.shape.kind == "normal"
    source = base or s.image_bright or s.image_dark
    if source is None:
        raise ValueError("the painting has no image to paint over")
    size = tuple(source.size) if base is None else painting_size(mat)
    figure = None
    if base is None:                 # no shape: the figure is the painting's silhouette
        alpha = image_data_from_blender(source).alpha()
        figure = None if alpha is None or alpha.min() >= 0.5 else np.clip(alpha, 0, 1)
    mask, layer = new_layers(mat, size, figure)
    w, h = size
    made = made_shape_image(f"{mat.name} painted shape", np.zeros((h, w, 4), np.float32))
    pt = s.painted
    with batch():
        pt.made, pt.mask, pt.height_layer, pt.base, pt.key = made, mask, layer, base, ""
        pt.base_reads = base_reads(p) if over_normals else ""
        if base is not None and not over_normals:
            preblur = p.shape.preblur
            pt.base_scale = p.shape.height_scale
            pt.base_preblur = default_preblur_px(image_data_from_blender(base).bits) \
                if preblur == "auto" else float(preblur)
        if over_normals:
            # its shadows fall from the relief the base's did (an alpha or not); a map that
            # casts the shadow of either relief keeps auto: its final shadows are the base's
            base_data = image_data_from_blender(base)
            if not image_casts_either(base_data, p):
                p.shadows.relief = relief_of(p.shadows.relief, base_data.has_alpha)
        params_to_settings(read_as_made(p, "normal" if over_normals else "height"), s,
                           sections=("shape", "shadows"))
        s.image_shape = made
    update(mat, scene, rebake=True)
    what = f"the shape image {base.name} is its base" if base is not None else \
        ("its silhouette is the figure mask" if figure is not None else
         "paint the figure mask where the figure is")
    return [f"Paint Shape: {mat.name} is painted in layers ({what}; packed in the .blend)"]


def enter_texture_paint(context, mat):
    """Texture Paint on the painting's plane, painting its chosen layer with a soft brush."""
    plane = mat.dynamic_painting.plane
    view_layer = context.view_layer
    if view_layer.objects.active is not plane:
        if context.object is not None and context.object.mode != "OBJECT":
            bpy.ops.object.mode_set(mode="OBJECT")
        plane.select_set(True)
        view_layer.objects.active = plane
    show_layer(mat, context.scene)
    if plane.mode != "TEXTURE_PAINT":
        bpy.ops.object.mode_set(mode="TEXTURE_PAINT")
        try:       # a soft falloff to start (the artist's brush choice is kept after)
            bpy.ops.brush.asset_activate(asset_library_type="ESSENTIALS",
                                         relative_asset_identifier=SOFT_BRUSH)
        except (RuntimeError, TypeError):
            pass
    if not bpy.app.timers.is_registered(_watch):
        bpy.app.timers.register(_watch, first_interval=WATCH_S)


class DYNPAINT_OT_paint_shape(PaintingOperator, bpy.types.Operator):
    """Paint the painting's shape in Blender, lit as you paint: a figure mask (inflated) and a
    height layer, in Texture Paint"""
    bl_idname = "dynpaint.paint_shape"
    bl_label = "Paint Shape"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        mat = active_painting(context)

        def work():
            lines = [] if is_painted(mat.dynamic_painting) else set_up(mat, context.scene)
            enter_texture_paint(context, mat)
            layer = mat.dynamic_painting.painted.layer.replace("_", " ")
            return [("INFO", line) for line in lines] + [
                ("INFO", f"Texture Paint on the {layer}: lighter raises, darker lowers")]
        return run_and_report(self, context, work, failure="Paint Shape: ",
                              catch=(ValueError, RuntimeError, MemoryError))


class DYNPAINT_OT_paint_shape_done(PaintingOperator, bpy.types.Operator):
    """Leave Texture Paint (the painted shape and its layers stay; Paint Shape goes on)"""
    bl_idname = "dynpaint.paint_shape_done"
    bl_label = "Done Painting"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        if context.object is not None and context.object.mode == "TEXTURE_PAINT":
            bpy.ops.object.mode_set(mode="OBJECT")
        return {"FINISHED"}


# painted layer's name → (its edit version, its pixels) when _watch last looked
_SEEN = {}


def _watch():
    """While Texture Paint paints a painted shape's layer: a change of its pixels that no
    Image update announced (state/edits.py: its version did not move) is an edit — noted,
    and the painting updated live. Stops when Texture Paint is left."""
    try:
        context = bpy.context
        mat = active_painting(context)
        obj = context.object
        if mat is None or obj is None or obj.mode != "TEXTURE_PAINT" or \
                not is_painted(mat.dynamic_painting):
            _SEEN.clear()
            return None
        img = context.scene.tool_settings.image_paint.canvas
        if img is None or img not in watched_images(mat.dynamic_painting).values():
            return WATCH_S
        w, h = img.size
        px = np.empty((h, w, img.channels), np.float32)
        img.pixels.foreach_get(px.ravel())
        seen = _SEEN.get(img.name)
        _SEEN[img.name] = (version(img), px)
        if seen is not None and seen[0] == version(img) and \
                changed_box(seen[1], px) is not None:
            note_edited([img.name])
            _SEEN[img.name] = (version(img), px)
            update(mat, context.scene, bake="live")
    except Exception as exc:          # a timer must never raise into Blender
        report("Paint Shape", exc)
    return WATCH_S


CLASSES = (DYNPAINT_OT_paint_shape, DYNPAINT_OT_paint_shape_done)
