"""Operators: Add › Dynamic Painting, Bake Shadows, looks, image slots, recipe import/export.

Every operator is undoable and reports one clear line; a failure leaves the scene as it was.
"""
import os

import numpy as np

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       StringProperty)
from bpy_extras.io_utils import ExportHelper, ImportHelper

from .. import params as P
from ..recipe import RecipeError, Recipe, load_recipe, recipe_to_toml
from . import material as M
from . import scene as S
from .properties import channel_images, settings_to_params

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".bmp", ".tga", ".webp",
                    ".hdr")
# File-name words → channel, checked in this order ("specular" before "light", …).
CHANNEL_WORDS = (
    ("specular_color", ("specular", "spec")),
    ("gloss", ("gloss", "rough")),
    ("environment", ("environment", "env", "reflect")),
    ("background", ("background", "backdrop", "bg")),
    ("transparency", ("transparency", "transp", "opacity")),
    ("shape", ("normal", "nrm", "height", "depth", "disp", "bump", "shape")),
    ("dark", ("dark", "shadow", "c0")),
    ("bright", ("bright", "lit", "light", "c1")),
)

LOOKS = {
    "CLASSIC": ("Classic", "Dark image in shadow, bright in full light (t0 = 0, t1 = 1)",
                {"diffuse.t0": 0.0, "diffuse.t1": 1.0, "diffuse.curve": "linear"}),
    "GOOCH": ("Gooch", "Soft wrap-around light from −1 to 1 (technical-illustration look)",
              {"diffuse.t0": -1.0, "diffuse.t1": 1.0, "diffuse.curve": "smoothstep"}),
    "CARTOON": ("Cartoon", "Hard light/shadow step and a crisp highlight",
                {"diffuse.t0": 0.3, "diffuse.t1": 0.3, "specular.enabled": True,
                 "specular.s0": 0.94, "specular.s1": 0.94}),
    "GLASS": ("Glass", "Transparent: refracts the background, reflects the environment",
              {"transparency.amount_auto": False, "transparency.amount": 1.0,
               "refraction.mode": "physical", "refraction.ior": 1.5, "fresnel.mode": "physical",
               "specular.enabled": True, "specular.s0": 0.92, "specular.s1": 1.0}),
    "MIRROR": ("Mirror", "Reflects the environment everywhere (art Fresnel at total reflection)",
               {"transparency.amount_auto": False, "transparency.amount": 1.0,
                "fresnel.mode": "art", "fresnel.kappa": 1.0, "reflection.distance": 0.05}),
}


def active_painting(context):
    """The active object's Dynamic Painting material, or None."""
    obj = context.object
    mat = obj.active_material if obj is not None else None
    return mat if mat is not None and mat.dynamic_painting.is_painting else None


class PaintingOperator:
    @classmethod
    def poll(cls, context):
        return active_painting(context) is not None


def guess_channels(paths):
    """Assign image files to channels by their names → ({channel: path}, [unassigned])."""
    found, rest = {}, []
    for path in paths:
        stem = os.path.splitext(os.path.basename(path))[0].lower()
        channel = next((c for c, words in CHANNEL_WORDS if c not in found
                        and any(w in stem for w in words)), None)
        if channel is None:
            rest.append(path)
        else:
            found[channel] = path
    return found, rest


def looks_like_height(img):
    """A shape image is a height map if it is grey (R = G = B), else a normal map."""
    from ..imageio import image_data_from_blender
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
        wm = context.window_manager
        wm.progress_begin(0, 1000)       # a large painting's first bake takes a while
        try:
            with S.unchanged_images_on_failure():
                plane, messages = self._create(context, paths,
                                               lambda f: wm.progress_update(int(1000 * f)))
        except (RecipeError, ValueError, OSError, MemoryError) as exc:
            self.report({"ERROR"}, str(exc) if not isinstance(exc, MemoryError) else
                        "not enough memory for this painting: use smaller images")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        for obj in context.selected_objects:
            obj.select_set(False)
        plane.select_set(True)
        context.view_layer.objects.active = plane
        for m in messages:
            self.report({"WARNING"}, m)
        self.report({"INFO"}, f"Added Dynamic Painting '{plane.name}'")
        return {"FINISHED"}

    def _create(self, context, paths, progress=None):
        recipes = [p for p in paths if p.lower().endswith(".toml")]
        location = tuple(context.scene.cursor.location)
        rotation = self._view_rotation(context)
        if recipes:
            recipe = load_recipe(recipes[0])
            plane, _, messages = S.create_painting(
                context, recipe.images, recipe.params,
                recipe.lights if self.add_lights else None, name=recipe.name or "Dynamic Painting",
                size=self.size, location=location, rotation=rotation, progress=progress)
            return plane, messages
        bad = [p for p in paths if os.path.splitext(p)[1].lower() not in IMAGE_EXTENSIONS]
        if bad:
            raise ValueError(f"{os.path.basename(bad[0])}: not an image or a .toml recipe")
        channels, rest = guess_channels(paths)
        for channel in ("shape", "dark", "bright"):     # unnamed files fill the basics in order
            if channel not in channels and rest:
                channels[channel] = rest.pop(0)
        if "shape" not in channels or ("dark" not in channels and "bright" not in channels):
            raise ValueError("pick at least a shape image (name it '…normal…' or '…height…') and "
                             "a dark and/or bright image")
        p = P.defaults()
        shape = S.load_image(channels["shape"], "shape")
        kind = self.shape_kind.lower() if self.shape_kind != "AUTO" else \
            ("height" if looks_like_height(shape) else "normal")
        p.shape.kind = kind
        name = os.path.splitext(os.path.basename(channels.get("dark") or channels["bright"]))[0]
        plane, _, messages = S.create_painting(context, {**channels, "shape": shape}, p, None,
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


class DYNPAINT_OT_bake_shadows(PaintingOperator, bpy.types.Operator):
    """Bake the cos-θ shadow term of every linked light (pipeline.md §6) with numpy"""
    bl_idname = "dynpaint.bake_shadows"
    bl_label = "Bake Shadows"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        mat = active_painting(context)
        if not mat.dynamic_painting.shadows.enabled:
            self.report({"WARNING"}, "Shadows are off: turn on Shadows first")
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0, 1000)      # the cursor shows it; long bakes report per band
        try:
            ms = M.bake_shadows(mat, context.scene, context.evaluated_depsgraph_get(),
                                progress=lambda f: wm.progress_update(int(1000 * f)))
            M.rebuild_tree(mat, context.scene)
        except Exception as exc:
            self.report({"ERROR"}, f"Bake failed, the previous shadows are kept: {exc}")
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        n = len(mat.dynamic_painting.lights)
        w, h = mat.dynamic_painting.image_shape.size
        self.report({"INFO"}, f"Baked shadows of {n} light{'s' * (n != 1)} at {w}×{h} "
                    f"in {ms:.0f} ms")
        return {"FINISHED"}


class DYNPAINT_OT_apply_look(PaintingOperator, bpy.types.Operator):
    """Apply a ready-made look to the painting's settings"""
    bl_idname = "dynpaint.apply_look"
    bl_label = "Apply Look"
    bl_options = {"REGISTER", "UNDO"}

    look: EnumProperty(name="Look", items=[(k, v[0], v[1]) for k, v in LOOKS.items()])

    def execute(self, context):
        mat = active_painting(context)
        s = mat.dynamic_painting
        with M.batch():
            for path, value in LOOKS[self.look][2].items():
                section, key = path.split(".")
                setattr(getattr(s, section), key, value)
        try:
            M.refresh(mat, structure=True, derived=True, shadows=s.shadows.enabled,
                      scene=context.scene)
        except ValueError as exc:
            self.report({"WARNING"}, str(exc))
        self.report({"INFO"}, f"Applied the {LOOKS[self.look][0]} look")
        return {"FINISHED"}


class DYNPAINT_OT_image_open(PaintingOperator, bpy.types.Operator, ImportHelper):
    """Assign or replace the image of one of the painting's channels"""
    bl_idname = "dynpaint.image_open"
    bl_label = "Open Image"
    bl_options = {"REGISTER", "UNDO"}

    channel: EnumProperty(items=[(c, c.replace("_", " ").title(), P.CHANNELS[c][0])
                                 for c in P.CHANNELS], options={"HIDDEN"})
    filter_glob: StringProperty(default=";".join("*" + e for e in IMAGE_EXTENSIONS),
                                options={"HIDDEN"})

    def execute(self, context):
        mat = active_painting(context)
        try:
            img = S.load_image(self.filepath, self.channel)
        except (ValueError, OSError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        setattr(mat.dynamic_painting, f"image_{self.channel}", img)   # refreshes (update)
        self.report({"INFO"}, f"{self.channel}: {os.path.basename(self.filepath)}")
        return {"FINISHED"}


class DYNPAINT_OT_image_remove(PaintingOperator, bpy.types.Operator):
    """Remove the image of this channel (its branch leaves the material)"""
    bl_idname = "dynpaint.image_remove"
    bl_label = "Remove Image"
    bl_options = {"REGISTER", "UNDO"}

    channel: EnumProperty(items=[(c, c, "") for c in P.CHANNELS], options={"HIDDEN"})

    def execute(self, context):
        mat = active_painting(context)
        s = mat.dynamic_painting
        imgs = channel_images(s)
        if self.channel == "shape" or (self.channel in ("dark", "bright")
                                       and not ({"dark", "bright"} - {self.channel}) & imgs.keys()):
            self.report({"ERROR"}, f"the painting needs its {self.channel} image: replace it instead")
            return {"CANCELLED"}
        setattr(s, f"image_{self.channel}", None)
        return {"FINISHED"}


class DYNPAINT_OT_face_camera(PaintingOperator, bpy.types.Operator):
    """Keep the painting facing the scene camera"""
    bl_idname = "dynpaint.face_camera"
    bl_label = "Face Camera"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        if context.scene.camera is None:
            self.report({"ERROR"}, "The scene has no camera")
            return {"CANCELLED"}
        plane = active_painting(context).dynamic_painting.plane or context.object
        S.face_camera(plane, context.scene.camera)
        return {"FINISHED"}


class DYNPAINT_OT_rebuild(PaintingOperator, bpy.types.Operator):
    """Rebuild the painting's material, derived images and shadows from its settings"""
    bl_idname = "dynpaint.rebuild"
    bl_label = "Rebuild Material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        mat = active_painting(context)
        try:
            M.refresh(mat, structure=True, derived=True, shadows=mat.dynamic_painting.shadows.enabled,
                      scene=context.scene)
            M.rebuild_tree(mat, context.scene, force=True)
        except Exception as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        return {"FINISHED"}


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
        try:
            os.makedirs(os.path.dirname(os.path.abspath(self.filepath)), exist_ok=True)
            text = export_recipe(mat, context.scene, self.filepath, self.only_changed)
            with open(self.filepath, "w", encoding="utf-8") as fh:
                fh.write(text)
        except (OSError, ValueError, RuntimeError) as exc:
            self.report({"ERROR"}, f"Could not export the recipe: {exc}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Wrote {self.filepath}")
        return {"FINISHED"}


def export_recipe(mat, scene, path, only_changed=True):
    """The painting as recipe text; images without a file on disk are written beside it."""
    s = mat.dynamic_painting
    folder = os.path.dirname(os.path.abspath(path))
    images = {}
    for channel, img in channel_images(s).items():
        src = bpy.path.abspath(img.filepath, library=img.library) if img.filepath else ""
        if not src or img.packed_file is not None or not os.path.isfile(src):
            ext = ".exr" if img.is_float else ".png"
            src = os.path.join(folder, f"{bpy.path.clean_name(mat.name)}_{channel}{ext}")
            img.save(filepath=src)  # writes the pixels; the image keeps its own source
        images[channel] = os.path.abspath(src)
    plane = s.plane
    lights = [M.painting_frame_light(o, plane.matrix_world) for o in M.linked_lights(mat, scene)]
    recipe = Recipe(settings_to_params(s), lights, images, mat.name, path)
    return recipe_to_toml(recipe, folder, only_changed)


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


def _sample(sample_id):
    from ..samples import list_samples
    return next((s for s in list_samples() if s.id == sample_id), None)


class DYNPAINT_OT_add_light_turntable(PaintingOperator, bpy.types.Operator):
    """Make a light orbit the painting in a seamless loop over a frame range (keyframed, linear,
    cyclic), and optionally set the render output to a video file"""
    bl_idname = "dynpaint.add_light_turntable"
    bl_label = "Add Light Turntable"
    bl_options = {"REGISTER", "UNDO"}

    def _light_items(self, context):
        mat = active_painting(context)
        items = [("NEW_SUN", "New Sun", "Add a Sun that orbits"),
                 ("NEW_POINT", "New Point Light", "Add a Point light that orbits")]
        if mat is not None:
            items = [(o.name, o.name, f"Orbit the {o.data.type.title()} '{o.name}'")
                     for o in M.linked_lights(mat, context.scene)] + items
        _ITEMS_KEEPALIVE[:] = items      # Blender needs the strings kept alive
        return items

    light: EnumProperty(name="Light", items=_light_items,
                        description="The light that orbits (its own location/rotation keys "
                                    "are replaced)")
    frame_start: bpy.props.IntProperty(name="Start Frame", default=1, min=0)
    frame_end: bpy.props.IntProperty(name="End Frame", default=96, min=0,
                                     description="Last frame of one orbit (the loop is seamless: "
                                                 "the frame after it is the start frame again)")
    elevation: FloatProperty(name="Elevation", subtype="ANGLE", default=0.61, min=-1.5708,
                             max=1.5708, description="Height of the orbit above the painting "
                                                     "(90° = straight in front of it)")
    radius: FloatProperty(name="Radius", default=1.0, min=0.01, soft_max=10.0,
                          description="Orbit radius in image widths (where a Point light "
                                      "is; a Sun only uses the direction)")
    start_angle: FloatProperty(name="Start Angle", subtype="ANGLE", default=2.356,
                               description="Where the light starts, counter-clockwise from "
                                           "the painting's right (135° = upper left)")
    direction: EnumProperty(name="Direction", items=(
        ("CCW", "Counter-clockwise", "As seen from the front"),
        ("CW", "Clockwise", "As seen from the front")))
    set_output: BoolProperty(name="Video Output", default=True,
                             description="Set the render output to an H.264 MP4 video and "
                                         "the scene's frame range to the orbit")
    filepath: StringProperty(name="Video File", default="//turntable.mp4", subtype="FILE_PATH")

    def invoke(self, context, event):
        self.frame_start, self.frame_end = context.scene.frame_start, context.scene.frame_end
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        from . import turntable as T
        mat = active_painting(context)
        light = None if self.light.startswith("NEW_") else context.scene.objects.get(self.light)
        kind = "POINT" if self.light == "NEW_POINT" else "SUN"
        try:
            _, light, messages = T.add_light_turntable(
                context, mat, light, kind if light is None else light.data.type,
                self.frame_start, self.frame_end, self.elevation, self.radius, self.start_angle,
                self.direction == "CW")
            if self.set_output:
                T.video_output(context.scene, self.filepath)
        except (ValueError, TypeError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for m in messages:
            self.report({"WARNING"} if "not" in m else {"INFO"}, m)
        frames = self.frame_end - self.frame_start + 1
        self.report({"INFO"}, f"'{light.name}' orbits the painting every {frames} frames"
                    + (f"; output: {self.filepath}" if self.set_output else ""))
        return {"FINISHED"}


_ITEMS_KEEPALIVE = []


class DYNPAINT_OT_add_compositor_group(bpy.types.Operator):
    """Add the Dynamic Painting node group to the scene's compositor: relight images (a render's
    normal pass, painted maps, image sequences) without a 3D scene"""
    bl_idname = "dynpaint.add_compositor_group"
    bl_label = "Dynamic Painting Group"
    bl_options = {"REGISTER", "UNDO"}

    match_painting: BoolProperty(name="Match Active Painting", default=True,
                                 description="Build the group for the active painting and wire "
                                             "its images, settings and lights")
    shape_kind: EnumProperty(name="Shape", items=(("normal", "Normal Map", ""),
                                                  ("height", "Height Map", "")))
    suns: bpy.props.IntProperty(name="Suns", default=1, min=0, max=8)
    points: bpy.props.IntProperty(name="Point Lights", default=0, min=0, max=8)
    shadows: BoolProperty(name="Shadows", description="cos-θ shadow image inputs, one per light")
    specular: BoolProperty(name="Highlights")
    environment: BoolProperty(name="Environment (reflection)")
    background: BoolProperty(name="Background (refraction)")
    transparency: BoolProperty(name="Transparency Map")

    def execute(self, context):
        from . import compositor as C
        mat = active_painting(context) if self.match_painting else None
        try:
            if mat is not None:
                features, _ = M.features_for(mat, context.scene)
            else:
                chans = [c for c in ("environment", "background", "transparency") if getattr(self, c)]
                features = C.features_for_options(self.shape_kind, self.suns, self.points,
                                                  self.shadows, self.specular, chans, "")
            group = C.build_group(features)
            node = C.add_group_node(context.scene, group)
            if mat is not None:
                C.wire_painting(context.scene, node, mat)
        except (ValueError, KeyError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Added '{group.name}' to the compositor"
                    + (f" for {mat.name}" if mat is not None else ""))
        return {"FINISHED"}


CLASSES = (DYNPAINT_OT_add, DYNPAINT_OT_add_sample, DYNPAINT_OT_add_light_turntable,
           DYNPAINT_OT_add_compositor_group, DYNPAINT_OT_bake_shadows, DYNPAINT_OT_apply_look, DYNPAINT_OT_image_open,
           DYNPAINT_OT_image_remove, DYNPAINT_OT_face_camera, DYNPAINT_OT_rebuild,
           DYNPAINT_OT_import_recipe, DYNPAINT_OT_export_recipe)


class VIEW3D_MT_dynpaint_add(bpy.types.Menu):
    """Add › Dynamic Painting: from your images or recipe, or one of the samples"""
    bl_idname = "VIEW3D_MT_dynpaint_add"
    bl_label = "Dynamic Painting"

    def draw(self, context):
        draw_add_menu(self.layout)


def draw_add_menu(layout):
    from ..samples import list_samples
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
        from bpy.utils import previews
        pcoll = _PREVIEWS.get("samples") or _PREVIEWS.setdefault("samples", previews.new())
        item = pcoll.get(sample.id) or pcoll.load(sample.id, sample.thumbnail, "IMAGE")
        return item.icon_id
    except (RuntimeError, KeyError, OSError):
        return 0


def menu_add(self, context):
    self.layout.menu(VIEW3D_MT_dynpaint_add.bl_idname, icon="IMAGE_RGB_ALPHA")


def menu_add_image(self, context):
    self.layout.operator(DYNPAINT_OT_add.bl_idname, text="Dynamic Painting", icon="IMAGE_RGB_ALPHA")


def menu_import(self, context):
    self.layout.operator(DYNPAINT_OT_import_recipe.bl_idname, text="Dynamic Painting Recipe (.toml)")


def menu_export(self, context):
    self.layout.operator(DYNPAINT_OT_export_recipe.bl_idname, text="Dynamic Painting Recipe (.toml)")


def menu_compositor(self, context):
    space = context.space_data
    if getattr(space, "tree_type", "") == "CompositorNodeTree":
        self.layout.operator(DYNPAINT_OT_add_compositor_group.bl_idname, icon="NODETREE")


MENUS = (("VIEW3D_MT_add", menu_add), ("VIEW3D_MT_image_add", menu_add_image), ("NODE_MT_add", menu_compositor),
         ("TOPBAR_MT_file_import", menu_import), ("TOPBAR_MT_file_export", menu_export))


def register():
    for cls in CLASSES + (VIEW3D_MT_dynpaint_add,):
        bpy.utils.register_class(cls)
    for menu, fn in MENUS:
        getattr(bpy.types, menu).append(fn)


def unregister():
    for menu, fn in MENUS:
        getattr(bpy.types, menu).remove(fn)
    for cls in reversed(CLASSES + (VIEW3D_MT_dynpaint_add,)):
        bpy.utils.unregister_class(cls)
    if "samples" in _PREVIEWS:
        from bpy.utils import previews
        previews.remove(_PREVIEWS.pop("samples"))

