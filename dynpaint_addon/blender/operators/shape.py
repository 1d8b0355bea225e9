"""Make Shape: the painting's shape image made by numpy from what it has (issue 16,
docs/shape-from-painting.md): its silhouette inflated, its normal map integrated into heights,
its height map's normals, or a normal map from lighting profiles or a red/green photograph.
The adjust-last-operation panel is the preview: change a setting and the painting is made
again, one undo step."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from ...core.photometric import SIDES
from ...imageio import image_data_from_blender, read_image
from ...shape_maker import read_as_made, sprite_lamp_siblings
from ...shape_methods import METHODS, OPTIONS, SHAPE_MAKERS, make_shape, options
from ..images import made_shape_image
from ..settings import channel_images, params_to_settings, settings_to_params
from ..sync import batch, update
from .common import PaintingOperator, active_painting, run_and_report


def blender_property(option):
    """One row of shape_methods.OPTIONS as an operator property."""
    kw = {"name": option.ui_label, "description": option.help}
    if option.kind is bool:
        return BoolProperty(default=option.default, **kw)
    if option.kind is float:
        return FloatProperty(default=option.default, min=option.min, max=option.max,
                             precision=option.precision, **kw)
    if isinstance(option.kind, tuple):
        return EnumProperty(items=[(c, c.replace("_", " ").title(), option.choice_help.get(c, ""))
                                   for c in option.kind], default=option.default, **kw)
    return StringProperty(subtype="FILE_PATH", **kw)


class DYNPAINT_OT_make_shape(PaintingOperator, bpy.types.Operator):
    """Make the painting's shape image from what it has: inflate its silhouette, integrate its
    normal map into a height map, or take its height map's normals"""
    bl_idname = "dynpaint.make_shape"
    bl_label = "Make Shape"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = {
        "method": EnumProperty(name="Method", items=[(k, METHODS[k].label, METHODS[k].help)
                                                     for k in SHAPE_MAKERS]),
        **{o.name: blender_property(o) for o in OPTIONS if o.where in ("both", "addon")},
    }

    def invoke(self, context, event):
        s = active_painting(context).dynamic_painting
        self.method = "integrate" if s.shape.kind == "normal" else "inflate"
        return context.window_manager.invoke_props_dialog(self, width=360)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "method")
        for option in options(self.method, "addon"):
            row = layout.row()
            row.active = not option.active_if or getattr(self, option.active_if)
            row.prop(self, option.name)

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
            values = {o.name: getattr(self, o.name) for o in options(self.method, "addon")}
            if self.method == "profiles":
                values.update({f"profile_{side}": profiles.get(side) for side in SIDES})
            elif self.method == "rg_photo":
                values["photo"] = photo
            kind, rgba, lines = make_shape(self.method, images, p, **values)
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
