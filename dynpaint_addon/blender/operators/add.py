"""Add › Dynamic Painting: from images or a recipe, a sample, a recipe import; the Add menu."""
import os

import numpy as np

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, FloatProperty, StringProperty
from bpy.utils import previews
from bpy_extras.io_utils import ImportHelper

from ... import params
from ...channel_names import IMAGE_EXTENSIONS, common_name, guess_channels
from ...imageio import image_data_from_blender
from ...recipe import RecipeError, load_recipe
from ...samples import list_samples
from ..images import load_image
from ..scene import create_painting, unchanged_images_on_failure
from .common import run_and_report


def looks_like_height(img):
    """A shape image is a height map if it is grey (R = G = B), else a normal map."""
    px = image_data_from_blender(img).pixels
    if px.shape[2] < 3:
        return True
    return bool(np.allclose(px[..., 0], px[..., 1], atol=2e-3)
                and np.allclose(px[..., 1], px[..., 2], atol=2e-3))


class DYNPAINT_OT_add(bpy.types.Operator, ImportHelper):
    """Add a Dynamic Painting: pick a recipe (painting.toml) or its images (shape, dark, bright,
    and optionally specular colour, gloss, environment, background, transparency)"""
    bl_idname = "dynpaint.add"
    bl_label = "Dynamic Painting"
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: StringProperty(default="*.toml;" + ";".join("*" + e for e in IMAGE_EXTENSIONS),
                                options={"HIDDEN"})
    files: CollectionProperty(type=bpy.types.OperatorFileListElement, options={"HIDDEN", "SKIP_SAVE"})
    directory: StringProperty(subtype="DIR_PATH", options={"HIDDEN", "SKIP_SAVE"})
    shape_kind: EnumProperty(name="Shape Image", default="AUTO", items=(
        ("AUTO", "Detect", "Grey images are height maps, coloured ones normal maps"),
        ("NORMAL", "Normal Map", "RGB normal map"),
        ("HEIGHT", "Height Map", "Grey height map, lighter = nearer")))
    size: FloatProperty(name="Width", default=2.0, min=0.001, unit="LENGTH",
                        description="Width of the painting's plane in the scene")
    add_lights: BoolProperty(name="Recipe Lights", default=True,
                             description="Create the lights a recipe describes")

    def execute(self, context):
        paths = [os.path.join(self.directory, f.name) for f in self.files if f.name] \
            or ([self.filepath] if self.filepath else [])
        if not paths:
            self.report({"ERROR"}, "Pick a painting.toml recipe or the painting's images")
            return {"CANCELLED"}

        def work(progress):     # a large painting's first bake takes a while: progress
            with unchanged_images_on_failure():
                plane, messages = self._create(context, paths, progress)
            for obj in context.selected_objects:
                obj.select_set(False)
            plane.select_set(True)
            context.view_layer.objects.active = plane
            return [("WARNING", m) for m in messages] + \
                [("INFO", f"Added Dynamic Painting '{plane.name}'")]
        return run_and_report(self, context, work, progress=True,
                              catch=(RecipeError, ValueError, OSError, MemoryError))

    def _create(self, context, paths, progress=None):
        recipes = [p for p in paths if p.lower().endswith(".toml")]
        location = tuple(context.scene.cursor.location)
        rotation = self._view_rotation(context)
        if recipes:
            recipe = load_recipe(recipes[0])
            plane, _, messages = create_painting(
                context, recipe.images, recipe.params,
                recipe.lights if self.add_lights else None, name=recipe.name or "Dynamic Painting",
                size=self.size, location=location, rotation=rotation, progress=progress)
            return plane, messages
        bad = [p for p in paths if os.path.splitext(p)[1].lower() not in IMAGE_EXTENSIONS]
        if bad:
            raise ValueError(f"{os.path.basename(bad[0])}: not an image or a .toml recipe")
        channels, rest = guess_channels(paths)
        if not channels:        # no file named after a channel: they are the basics, in order
            channels = dict(zip(("shape", "dark", "bright"), rest))
            rest = rest[len(channels):]
        if "shape" not in channels or ("dark" not in channels and "bright" not in channels):
            raise ValueError("pick at least a shape image (name it '…normal…' or '…height…') and "
                             "a dark and/or bright image")
        p = params.defaults()
        shape = load_image(channels["shape"], "shape")
        kind = self.shape_kind.lower() if self.shape_kind != "AUTO" else \
            ("height" if looks_like_height(shape) else "normal")
        p.shape.kind = kind
        name = common_name(channels.values()) or \
            os.path.splitext(os.path.basename(channels.get("dark") or channels["bright"]))[0]
        plane, _, messages = create_painting(context, {**channels, "shape": shape}, p, None,
                                             name=name, size=self.size, location=location,
                                             rotation=rotation, progress=progress)
        if rest:
            messages.append(f"not used (name them after a channel): "
                            f"{', '.join(os.path.basename(r) for r in rest)}")
        messages.append(f"shape image read as a {kind} map")
        return plane, messages

    @staticmethod
    def _view_rotation(context):
        """With no camera to face, face the 3D view the operator was called from."""
        if context.scene.camera is not None:
            return None
        space = context.space_data
        if space is None or space.type != "VIEW_3D" or space.region_3d is None:
            return None
        return space.region_3d.view_rotation.to_euler()


class DYNPAINT_OT_import_recipe(bpy.types.Operator, ImportHelper):
    """Import a Dynamic Painting recipe (painting.toml) as a new painting"""
    bl_idname = "dynpaint.import_recipe"
    bl_label = "Import Dynamic Painting Recipe"
    bl_options = {"REGISTER", "UNDO"}
    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})

    def execute(self, context):
        return bpy.ops.dynpaint.add(filepath=self.filepath, directory=os.path.dirname(self.filepath),
                                    files=[{"name": os.path.basename(self.filepath)}])


def _sample(sample_id):
    return next((s for s in list_samples() if s.id == sample_id), None)


class DYNPAINT_OT_add_sample(bpy.types.Operator):
    """Add one of the sample paintings that come with the extension"""
    bl_idname = "dynpaint.add_sample"
    bl_label = "Add Sample Painting"
    bl_options = {"REGISTER", "UNDO"}

    sample: StringProperty(name="Sample", description="Folder name of the sample in sample_scenes")

    @classmethod
    def description(cls, context, props):
        found = _sample(props.sample) if props is not None else None
        return found.description if found is not None and found.description else cls.__doc__

    def execute(self, context):
        found = _sample(self.sample)
        if found is None:
            self.report({"ERROR"}, f"No sample painting named '{self.sample}'")
            return {"CANCELLED"}
        folder, name = os.path.split(found.recipe)
        return bpy.ops.dynpaint.add("EXEC_DEFAULT", filepath=found.recipe, directory=folder,
                                    files=[{"name": name}])


class VIEW3D_MT_dynpaint_add(bpy.types.Menu):
    """Add › Dynamic Painting: from your images or recipe, or one of the samples"""
    bl_idname = "VIEW3D_MT_dynpaint_add"
    bl_label = "Dynamic Painting"

    def draw(self, context):
        draw_add_menu(self.layout)


def draw_add_menu(layout):
    layout.operator(DYNPAINT_OT_add.bl_idname, text="From Images or Recipe…",
                    icon="FILEBROWSER")
    samples = list_samples()
    if samples:
        layout.separator()
        layout.label(text="Samples")
    for sample in samples:
        layout.operator(DYNPAINT_OT_add_sample.bl_idname, text=sample.name,
                        icon_value=sample_icon(sample)).sample = sample.id


_PREVIEWS = {}


def sample_icon(sample):
    """The sample's thumbnail as a UI icon (0 = none, e.g. in background mode)."""
    if not sample.thumbnail or bpy.app.background:
        return 0
    try:
        pcoll = _PREVIEWS.get("samples") or _PREVIEWS.setdefault("samples", previews.new())
        item = pcoll.get(sample.id) or pcoll.load(sample.id, sample.thumbnail, "IMAGE")
        return item.icon_id
    except (RuntimeError, KeyError, OSError):
        return 0


def forget_previews():
    if "samples" in _PREVIEWS:
        previews.remove(_PREVIEWS.pop("samples"))


CLASSES = (DYNPAINT_OT_add, DYNPAINT_OT_add_sample, DYNPAINT_OT_import_recipe,
           VIEW3D_MT_dynpaint_add)
