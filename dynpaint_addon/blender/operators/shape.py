"""Make Shape: the painting's shape image made by numpy from what it has (issue 16,
docs/shape-from-painting.md): its silhouette inflated, its normal map integrated into heights,
its height map's normals, or a normal map from lighting profiles or a red/green photograph.
The adjust-last-operation panel is the preview: change a setting and the painting is made
again, one undo step."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from ...core.inflate import PROFILES
from ...core.photometric import SIDES
from ...imageio import image_data_from_blender, read_image
from ...shape_maker import METHODS, make_shape, read_as_made, sprite_lamp_siblings
from ..images import made_shape_image
from ..settings import channel_images, params_to_settings, settings_to_params
from ..sync import batch, update
from .common import PaintingOperator, active_painting, run_and_report

PROFILE_HELP = {"round": "A disc becomes a hemisphere; any outline gets round cross-sections",
                "soft": "Gentle at the rim, pointed in the middle",
                "flat": "Rounded rims and a plateau (a coin, a cushion)"}


class DYNPAINT_OT_make_shape(PaintingOperator, bpy.types.Operator):
    """Make the painting's shape image from what it has: inflate its silhouette, integrate its
    normal map into a height map, or take its height map's normals"""
    bl_idname = "dynpaint.make_shape"
    bl_label = "Make Shape"
    bl_options = {"REGISTER", "UNDO"}

    method: EnumProperty(name="Method", items=[(k, v.split(":")[0], v)
                                               for k, v in METHODS.items()])
    profile: EnumProperty(name="Profile", items=[(k, k.title(), PROFILE_HELP[k])
                                                 for k in PROFILES])
    height: FloatProperty(name="Height", default=1.0, min=0.01, max=10.0,
                          description="Scale of the relief: 1 makes a disc's hemisphere as "
                          "tall as its radius")
    detail: FloatProperty(name="Detail", default=0.0, min=0.0, max=0.1, precision=3,
                          description="Emboss the painting's luminance: image widths of relief "
                          "per unit of luminance (0.005–0.02 is subtle)")
    detail_blur: FloatProperty(name="Detail Blur", default=0.002, min=0.0, max=0.05,
                               precision=4, description="Blur of the embossed luminance "
                               "(image widths)")
    use_mask: BoolProperty(name="Cut at the Alpha", default=True,
                           description="Integrate the figure (the normal map's alpha) apart "
                           "from its background")
    depth: FloatProperty(name="Depth", default=0.0, min=-1.0, max=1.0, precision=3,
                         description="How far the figure's rim stands above its background "
                         "(image widths); a normal map cannot see this wall")
    profile_left: StringProperty(name="Left", subtype="FILE_PATH",
                                 description="The picture lit from the left (Sprite Lamp's "
                                 "name_left.png: the other sides beside it are found)")
    profile_right: StringProperty(name="Right", subtype="FILE_PATH",
                                  description="The picture lit from the right")
    profile_top: StringProperty(name="Top", subtype="FILE_PATH",
                                description="The picture lit from the top")
    profile_bottom: StringProperty(name="Bottom", subtype="FILE_PATH",
                                   description="The picture lit from the bottom")
    profile_front: StringProperty(name="Front", subtype="FILE_PATH",
                                  description="The picture lit from the front (optional)")
    elevation: FloatProperty(name="Side Lights' Elevation", default=45.0, min=1.0, max=89.0,
                             description="How high the side lights were above the painting "
                             "(degrees)")
    photo: StringProperty(name="Photograph", subtype="FILE_PATH",
                          description="A photograph lit by a red light from one side and a "
                          "green light from the top")
    red_from: EnumProperty(name="Red From", items=[("right", "Right", ""), ("left", "Left", "")])
    green_from: EnumProperty(name="Green From", items=[("top", "Top", ""),
                                                       ("bottom", "Bottom", "")])

    def invoke(self, context, event):
        s = active_painting(context).dynamic_painting
        self.method = "integrate" if s.shape.kind == "normal" else "inflate"
        return context.window_manager.invoke_props_dialog(self, width=360)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "method")
        if self.method == "inflate":
            for name in ("profile", "height", "detail", "detail_blur"):
                layout.prop(self, name)
        elif self.method == "integrate":
            layout.prop(self, "use_mask")
            row = layout.row()
            row.active = self.use_mask
            row.prop(self, "depth")
        elif self.method == "profiles":
            for side in SIDES:
                layout.prop(self, f"profile_{side}")
            layout.prop(self, "elevation")
        elif self.method == "rg_photo":
            for name in ("photo", "red_from", "green_from"):
                layout.prop(self, name)

    def profile_paths(self):
        """{side: path} given, completed by Sprite Lamp names beside the first one."""
        given = {side: bpy.path.abspath(getattr(self, f"profile_{side}")) for side in SIDES
                 if getattr(self, f"profile_{side}")}
        for path in list(given.values())[:1]:
            for side, found in sprite_lamp_siblings(path).items():
                given.setdefault(side, found)
        return given

    def execute(self, context):
        mat = active_painting(context)
        s = mat.dynamic_painting

        def work(progress):
            images = {c: image_data_from_blender(img) for c, img in channel_images(s).items()
                      if c in ("shape", "dark", "bright")}
            profiles = {side: read_image(path) for side, path in self.profile_paths().items()} \
                if self.method == "profiles" else None
            photo = read_image(bpy.path.abspath(self.photo)) \
                if self.method == "rg_photo" and self.photo else None
            progress(0.2)
            p = settings_to_params(s)
            kind, rgba, lines = make_shape(
                self.method, images, p, self.profile, self.height,
                self.detail, self.detail_blur, self.depth, self.use_mask, profiles,
                self.elevation, photo, self.red_from, self.green_from)
            progress(0.7)
            img = made_shape_image(f"{mat.name} {'height' if kind == 'height' else 'normal'}"
                                   f" ({self.method})", rgba)
            with batch():
                params_to_settings(read_as_made(p, kind), s, sections=("shape",))
                s.image_shape = img
            update(mat, context.scene, rebake=True)
            return [("INFO", f"{lines[0]}; the shape image is now {img.name} (packed in "
                             f"the .blend)")]
        return run_and_report(self, context, work, progress=True, failure="Make Shape: ",
                              catch=(ValueError, MemoryError))    # ShapeError, ImageReadError


CLASSES = (DYNPAINT_OT_make_shape,)
