"""File › Export › Dynamic Painting Recipe: the painting as a recipe the command line renders."""
import os

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ...inputs.recipe import Recipe, recipe_to_toml
from ..state.frames import sequence_pattern
from ..state.lights import painting_lights
from ..state.painted import is_painted
from ..state.settings import channel_images, frames_table, settings_to_params
from .common import PaintingOperator, active_painting, run_and_report


def _on_disk(img, folder, stem):
    """The image's file, or its pixels written beside the recipe as `stem` (.exr for float
    images) where it has none on disk (packed, generated, made)."""
    src = bpy.path.abspath(img.filepath, library=img.library) if img.filepath else ""
    if not src or img.packed_file is not None or not os.path.isfile(src):
        src = os.path.join(folder, stem + (".exr" if img.is_float else ".png"))
        img.save(filepath=src)  # writes the pixels; the image keeps its own source
    return os.path.abspath(src)


def export_recipe(mat, scene, path, only_changed=True):
    """The painting as recipe text; images without a file on disk are written beside it — a
    painted shape's made image as the shape, and its layers (Paint Shape), so the painting
    can be painted on elsewhere."""
    s = mat.dynamic_painting
    folder = os.path.dirname(os.path.abspath(path))
    name = bpy.path.clean_name(mat.name)
    images = {}
    for channel, img in channel_images(s).items():
        pattern = sequence_pattern(img)      # §16: an image sequence is named by its pattern
        images[channel] = pattern if pattern is not None else \
            _on_disk(img, folder, f"{name}_{channel}")
    if is_painted(s):
        for role, img in (("mask", s.painted.mask), ("height_layer", s.painted.height_layer)):
            if img is not None:
                _on_disk(img, folder, f"{name}_painted_{role}")
    recipe = Recipe(settings_to_params(s), painting_lights(mat, scene), images, mat.name, path,
                    frames=frames_table(s))
    return recipe_to_toml(recipe, folder, only_changed)


class DYNPAINT_OT_export_recipe(PaintingOperator, bpy.types.Operator, ExportHelper):
    """Export the painting as a recipe (painting.toml) for the command line or another machine;
    packed or generated images are saved next to it"""
    bl_idname = "dynpaint.export_recipe"
    bl_label = "Export Dynamic Painting Recipe"
    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})
    only_changed: BoolProperty(name="Only Changed Settings", default=True,
                               description="Leave settings at their defaults out of the file")

    def execute(self, context):
        mat = active_painting(context)

        def work():
            os.makedirs(os.path.dirname(os.path.abspath(self.filepath)), exist_ok=True)
            text = export_recipe(mat, context.scene, self.filepath, self.only_changed)
            with open(self.filepath, "w", encoding="utf-8") as fh:
                fh.write(text)
            return [("INFO", f"Wrote {self.filepath}")]
        return run_and_report(self, context, work, failure="Could not export the recipe: ",
                              catch=(OSError, ValueError, RuntimeError))


CLASSES = (DYNPAINT_OT_export_recipe,)
