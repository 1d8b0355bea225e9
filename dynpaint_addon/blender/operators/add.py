"""Add › Dynamic Painting: from images or a recipe, a sample, a recipe import; the Add menu."""
import os

import numpy as np

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       IntProperty, StringProperty)
from bpy.utils import previews
from bpy_extras.io_utils import ImportHelper

from ... import params
from ...core.input_rules import ImageData, green_of, relief_guess
from ...core.frames import is_pattern
from ...inputs.channel_names import IMAGE_EXTENSIONS, common_name, guess_channels
from ...inputs.painting_folder import painting_channels
from ...inputs.sprite_files import depth_in_alpha
from ...inputs.imageio import image_data_from_blender
from ...inputs.recipe import DEFAULT_SUN_NOTE, RecipeError, load_recipe
from ...inputs.samples import list_samples
from ...shapes.maker import looks_like_height, read_as_made
from ...shapes.methods import make_shape
from ..scenes.grease_pencil.lit_copy import light_recipe_drawing
from ..scenes.layered_build import add_camera, add_layered, animate_scene
from ..scenes.painting_scene import create_painting, unchanged_images_on_failure
from ..scenes.turntable import turn_first_sun
from ..state.frames import moves, painting_frames
from ..state.images import load_image, made_shape_image
from .common import run_and_report


SHAPE_KINDS = (("AUTO", "Detect", "Grey images are height maps, coloured ones normal maps"),
               ("NORMAL", "Normal Map", "RGB normal map"),
               ("HEIGHT", "Height Map", "Grey height map, lighter = nearer"))


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
    shape_kind: EnumProperty(name="Shape Image", default="AUTO", items=SHAPE_KINDS)
    size: FloatProperty(name="Width", default=2.0, min=0.001, unit="LENGTH",
                        description="Width of the painting's plane in the scene")
    add_lights: BoolProperty(name="Recipe Lights", default=True,
                             description="Create the lights a recipe describes")
    confirm: BoolProperty(name="Confirm Channels", default=True, options={"SKIP_SAVE"},
                          description="Show which channel each picked image becomes, to check "
                                      "or change it, before the painting is made")
    max_size: IntProperty(name="Max Size", default=0, min=0, subtype="PIXEL",
                          description="Downsample images whose longest side is larger than "
                          "this as they are added (copies packed with the .blend; the files "
                          "are unchanged): less memory and faster bakes for huge scans. 0 "
                          "keeps every image as it is")

    def confirmation(self, images):
        """The confirm dialog's properties for the picked images."""
        channels, _ = proposed_channels(images)
        by_file = {path: channel for channel, path in channels.items()}
        return {"directory": os.path.dirname(images[0]), "shape_kind": self.shape_kind,
                "size": self.size, "max_size": self.max_size,
                "choices": [{"name": os.path.basename(p), "channel": by_file.get(p, NOT_USED)}
                            for p in images]}

    def execute(self, context):
        paths = [os.path.join(self.directory, f.name) for f in self.files if f.name] \
            or ([self.filepath] if self.filepath else [])
        if not paths:
            self.report({"ERROR"}, "Pick a painting.toml recipe or the painting's images")
            return {"CANCELLED"}

        images = [p for p in paths if not p.lower().endswith(".toml")]
        if images == paths and not bpy.app.background and self.confirm:
            # show the proposed channels before anything is made (the artist may change them)
            return bpy.ops.dynpaint.add_images("INVOKE_DEFAULT", **self.confirmation(images))

        def work(progress):     # a large painting's first bake takes a while: progress
            with unchanged_images_on_failure():
                plane, messages = self._create(context, paths, progress)
            select_only(context, plane)
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
            if recipe.layered:                  # a scene of layers (§15): one plane each
                return add_layered(context, recipes[0], size=self.size, rotation=rotation,
                                   progress=progress, lights=self.add_lights)
            # a recipe that names no light gets the add-on's own default: a Sun only where
            # the scene has no light (said by create_painting)
            named = self.add_lights and not recipe.default_lights
            plane, _, messages = create_painting(
                context, recipe.images, recipe.params, recipe.lights if named else None,
                name=recipe.name or "Dynamic Painting", size=self.size, location=location,
                rotation=rotation, progress=progress, frames=recipe.frames,
                max_size=self.max_size)
            return plane, [n for n in recipe.notes if n != DEFAULT_SUN_NOTE] + messages
        bad = [p for p in paths if os.path.splitext(p)[1].lower() not in IMAGE_EXTENSIONS]
        if bad:
            raise ValueError(f"{os.path.basename(bad[0])}: not an image or a .toml recipe")
        channels, rest = proposed_channels(paths)
        return painting_from_images(context, channels, rest, self.shape_kind, self.size,
                                    location, rotation, progress, self.max_size)

    @staticmethod
    def _view_rotation(context):
        """With no camera to face, face the 3D view the operator was called from."""
        if context.scene.camera is not None:
            return None
        space = context.space_data
        if space is None or space.type != "VIEW_3D" or space.region_3d is None:
            return None
        return space.region_3d.view_rotation.to_euler()


def proposed_channels(paths):
    """The channels Add proposes for picked image files → ({channel: path}, [not used])."""
    channels, rest, _ = painting_channels(paths)
    if any(is_pattern(path) for path in channels.values()):     # frames: From Recipe's
        channels, rest = guess_channels(paths)
    if not channels:        # no file named after a channel: they are the basics, in order;
        # the painting alone is the bright image (its silhouette is inflated into a shape)
        channels = dict(zip(("shape", "dark", "bright") if len(rest) > 1 else ("bright",),
                            rest))
        rest = rest[len(channels):]
    return channels, rest


def inflated_shape(channels, name, p):
    """No shape image: inflate the painting's silhouette (its alpha) into one (Make Shape's
    inflate, round) → (packed height image, report line); shapes.maker.ShapeError (a
    ValueError) without a silhouette."""
    images = {c: image_data_from_blender(load_image(channels[c], c))
              for c in ("dark", "bright") if c in channels}
    kind, rgba, lines = make_shape("inflate", images, p)
    read_as_made(p, kind)
    return made_shape_image(f"{name} height (inflate)", rgba), \
        f"no shape image: {lines[0]} (Make Shape changes it)"


def painting_from_images(context, channels, rest, shape_kind, size, location, rotation,
                         progress=None, max_size=0):
    """A painting from image files assigned to channels → (plane, messages). Without a shape
    image, the painting's silhouette is inflated into one."""
    if "dark" not in channels and "bright" not in channels:
        raise ValueError("pick at least a dark and/or bright image (and a shape image, "
                         "'…normal…' or '…height…', unless the painting has a transparent "
                         "background to inflate)")
    p = params.defaults()
    p.shadows.enabled = True        # a painting with a shape casts shadows, as `new` starts it
    name = common_name(channels.values()) or \
        os.path.splitext(os.path.basename(channels.get("dark") or channels["bright"]))[0]
    notes = []
    if "shape" in channels:
        shape = load_image(channels["shape"], "shape")
        pixels = image_data_from_blender(shape)
        if pixels.has_alpha and depth_in_alpha(channels["shape"]):     # its RGB is the map
            loaded, rgb = shape, pixels.rgb()
            rgba = np.dstack([rgb, np.ones(rgb.shape[:2], np.float32)])
            shape = made_shape_image(f"{name} normal map", rgba)
            pixels = ImageData(rgba, 32, shape.name)      # (what the packed float image holds)
            if not loaded.users:                          # the file's image: shown by nothing
                bpy.data.images.remove(loaded)
            notes.append(f"{os.path.basename(channels['shape'])}: its alpha is the depth "
                         f"(Sprite Lamp's NormalDepth), not the figure: its colour alone is "
                         f"the normal map (packed)")
        p.shape.kind = shape_kind.lower() if shape_kind != "AUTO" else \
            ("height" if looks_like_height(pixels) else "normal")
        notes.append(f"shape image read as a {p.shape.kind} map")
        if p.shape.kind == "normal":        # which way its green points, read from it (§2)
            green = green_of(pixels, p)
            p.shape.flip_green = green.flip
            notes.append(green.describe(os.path.basename(channels["shape"])))
            relief, why = relief_guess(pixels, os.path.basename(channels["shape"]))
            if relief:
                p.shadows.relief = relief
                notes.append(why)
    else:
        shape, note = inflated_shape(channels, name, p)
        notes.append(note)
    plane, _, messages = create_painting(context, {**channels, "shape": shape}, p, None,
                                         name=name, size=size, location=location,
                                         rotation=rotation, progress=progress,
                                         max_size=max_size)
    if rest:
        messages.append(f"not used: {', '.join(os.path.basename(r) for r in rest)}")
    return plane, messages + notes


NOT_USED = "NONE"


class DYNPAINT_PG_image_choice(bpy.types.PropertyGroup):
    """One picked image file and the channel it will be (Add › From Images)."""
    channel: EnumProperty(name="Channel", items=[(NOT_USED, "Not used", "Leave this file out")]
                          + [(c, c.replace("_", " ").title(), params.CHANNELS[c][0])
                             for c in params.CHANNELS])


class DYNPAINT_OT_add_images(bpy.types.Operator):
    """Add a Dynamic Painting from image files: check the channel proposed for each file (by
    its name) and change it before the painting is made"""
    bl_idname = "dynpaint.add_images"
    bl_label = "Add Dynamic Painting"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(subtype="DIR_PATH", options={"HIDDEN", "SKIP_SAVE"})
    choices: CollectionProperty(type=DYNPAINT_PG_image_choice, options={"SKIP_SAVE"})
    shape_kind: EnumProperty(name="Shape Image", default="AUTO", items=SHAPE_KINDS)
    size: FloatProperty(name="Width", default=2.0, min=0.001, unit="LENGTH",
                        description="Width of the painting's plane in the scene")
    max_size: IntProperty(name="Max Size", default=0, min=0, subtype="PIXEL",
                          description="Downsample images whose longest side is larger than "
                          "this as they are added (copies packed with the .blend; the files "
                          "are unchanged): less memory and faster bakes for huge scans. 0 "
                          "keeps every image as it is")

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self, width=420,
                                                          title="Which image is which?")

    def draw(self, context):
        layout = self.layout
        col = layout.column(align=True)
        for item in self.choices:
            row = col.row(align=True)
            row.label(text=item.name, icon="IMAGE_DATA")
            row.prop(item, "channel", text="")
        if not any(i.channel == "shape" for i in self.choices):
            layout.label(text="No shape image: the painting's silhouette (alpha) will be "
                              "inflated into one", icon="INFO")
        layout.prop(self, "shape_kind")
        layout.prop(self, "size")
        layout.prop(self, "max_size")

    def execute(self, context):
        chosen = [(i.channel, os.path.join(self.directory, i.name)) for i in self.choices]
        used = [c for c, _ in chosen if c != NOT_USED]
        twice = sorted({c for c in used if used.count(c) > 1})
        if twice:
            self.report({"ERROR"}, f"one image per channel: {', '.join(twice)} is chosen twice")
            return {"CANCELLED"}
        channels = {c: path for c, path in chosen if c != NOT_USED}
        rest = [path for c, path in chosen if c == NOT_USED]

        def work(progress):
            with unchanged_images_on_failure():
                plane, messages = painting_from_images(
                    context, channels, rest, self.shape_kind, self.size,
                    tuple(context.scene.cursor.location),
                    DYNPAINT_OT_add._view_rotation(context), progress, self.max_size)
            select_only(context, plane)
            return [("WARNING", m) for m in messages] + \
                [("INFO", f"Added Dynamic Painting '{plane.name}'")]
        return run_and_report(self, context, work, progress=True,
                              catch=(ValueError, OSError, MemoryError))


def select_only(context, obj):
    for other in context.selected_objects:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj


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


def turn_with_painting(context, mat, loops=2):
    """A painting that moves (§16): the scene's frame range set to `loops` of the painting's
    own and its first Sun turned once over it (a light turntable) → report lines."""
    scene = context.scene
    scene.frame_start, scene.frame_end = 1, loops * painting_frames(mat).loop()
    lines = [f"frames 1–{scene.frame_end}: the painting comes round {loops} times"]
    lines += turn_first_sun(context, mat, 1, scene.frame_end)
    scene.frame_set(1)
    return lines


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
        recipe = load_recipe(found.recipe)
        if recipe.drawing:           # a Grease Pencil drawing: built, lit, its light turning
            parent, notes = light_recipe_drawing(context, recipe, context.scene.cursor.location)
            select_only(context, parent)
            for line in notes + animate_scene(context, parent):
                self.report({"INFO"}, line)
            return {"FINISHED"}
        layered = recipe.layered
        if layered and context.scene.camera is None:      # the layers face it, composed
            add_camera(context)
        result = bpy.ops.dynpaint.add("EXEC_DEFAULT", filepath=found.recipe, directory=folder,
                                      files=[{"name": name}])
        if layered and result == {"FINISHED"}:           # its showpiece: parallax and light
            for line in animate_scene(context, context.object):
                self.report({"INFO"}, line)
        elif result == {"FINISHED"} and moves(context.object.active_material):
            for line in turn_with_painting(context, context.object.active_material):
                self.report({"INFO"}, line)       # its showpiece: it moves as the light turns
        return result


class VIEW3D_MT_dynpaint_add(bpy.types.Menu):
    """Add › Dynamic Painting: from your images or recipe, or one of the samples"""
    bl_idname = "VIEW3D_MT_dynpaint_add"
    bl_label = "Dynamic Painting"

    def draw(self, context):
        draw_add_menu(self.layout)


def draw_add_menu(layout):
    layout.operator(DYNPAINT_OT_add.bl_idname, text="From Images or Recipe…",
                    icon="FILEBROWSER")
    layout.operator("dynpaint.add_layered", text="Layered…", icon="RENDERLAYERS")
    layout.operator("dynpaint.add_grease_pencil", icon="OUTLINER_OB_GREASEPENCIL")
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


CLASSES = (DYNPAINT_PG_image_choice, DYNPAINT_OT_add, DYNPAINT_OT_add_images,
           DYNPAINT_OT_add_sample, DYNPAINT_OT_import_recipe, VIEW3D_MT_dynpaint_add)
