"""The painting's settings as Blender properties, generated from params.py (one definition).

`Material.dynamic_painting` holds one PropertyGroup per params.py section (shape, diffuse, …),
the channel images, the linked lights and the bookkeeping of what was built. Every property
calls sync.on_setting_changed when it changes; what that redoes is decided by comparison
(sync.py), not by the property.
"""
import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty,
                       FloatVectorProperty, IntProperty, PointerProperty, StringProperty)

from .. import params
from ..shapes.painted import OPTIONS as PAINTED_OPTIONS
from .material.sync import on_setting_changed
from .state.painted import show_layer
from .state.shape_options import option_property

CHOICE_LABELS = {"baked": "Baked (numpy)", "osl": "In-shader (Cycles OSL)",
                 "art": "Art-directed", "cos": "1 − cos θ", "sin": "sin θ",
                 "smoothstep": "Smooth Step", "smootherstep": "Smoother Step"}


def _on_change(path):
    def update(self, context):
        on_setting_changed(self.id_data, path)
    return update


def _description(param):
    unit = f" ({param.unit})" if param.unit else ""
    spec = f". pipeline.md {param.spec}" if param.spec else ""
    return f"{param.help}{unit}{spec}"


def _property(param):
    kw = {"name": param.ui_label,
          "description": _description(param), "update": _on_change(param.path)}
    if param.kind is bool:
        return {param.key: BoolProperty(default=param.default, **kw)}
    if param.kind is int:
        return {param.key: IntProperty(default=param.default, min=int(param.min),
                                       soft_max=1024, max=int(param.max), **kw)}
    if param.kind == "auto_int":
        return {param.key: IntProperty(default=param.auto_value, min=int(param.min),
                                       max=int(param.max), **kw),
                param.key + "_auto": _auto_toggle(param)}
    if param.kind == "enum":
        items = [(c, CHOICE_LABELS.get(c, c.replace("_", " ").title()), "")
                 for c in param.choices]
        return {param.key: EnumProperty(items=items, default=param.default, **kw)}
    limits = {"min": param.min, "max": param.max}
    limits = {k: v for k, v in limits.items() if v is not None}
    if param.kind == "auto_float":
        auto = param.default == "auto"
        return {param.key: FloatProperty(default=param.auto_value if auto else param.default,
                                         precision=3, **limits, **kw),
                param.key + "_auto": _auto_toggle(param)}
    if param.kind == "vec2":
        return {param.key: FloatVectorProperty(default=param.default, size=2, subtype="XYZ",
                                               precision=3, step=1, **limits, **kw)}
    return {param.key: FloatProperty(default=param.default, precision=3, step=1, **limits, **kw)}


def _auto_toggle(param):
    return BoolProperty(default=param.default == "auto", name="Auto",
                        update=_on_change(param.path + "_auto"),
                        description="Use the automatic value: " +
                        param.help.split("'auto'")[-1].strip(" =;"))


def _section_class(section, table=params.PARAMS):
    annotations = {}
    for param in table:
        if param.section == section:
            annotations.update(_property(param))
    return type(f"DYNPAINT_PG_{section}", (bpy.types.PropertyGroup,),
                {"__annotations__": annotations, "__doc__": f"Dynamic Painting: {section}"})


SECTION_CLASSES = [_section_class(s) for s in params.SECTIONS]
# §16: a painting's frame mapping, and one per image slot that sets its own
FRAMES_CLASS = _section_class("frames", params.FRAME_PARAMS)


def _own_frames(channel):
    return BoolProperty(name="Own Frames", update=_on_change(f"frames_{channel}_own"),
                        description=f"The {channel.replace('_', ' ')} image follows a frame "
                                    f"mapping of its own instead of the painting's (§16)")


def _image_pointer(channel):
    what, kind = params.CHANNELS[channel]
    return PointerProperty(type=bpy.types.Image, name=channel.replace("_", " ").title(),
                           description=f"{what[0].upper()}{what[1:]} ({kind})",
                           update=_on_change("images." + channel))


class DYNPAINT_PG_light(bpy.types.PropertyGroup):
    """A light the tree was built for (in order) and its baked cos-θ image (§6)."""
    object: PointerProperty(type=bpy.types.Object, name="Light")
    kind: StringProperty(description="SUN or POINT, as the tree was built")
    shadow: PointerProperty(type=bpy.types.Image, name="Shadow")
    bake_key: StringProperty(description="The light position and settings of the last bake")


class DYNPAINT_PG_derived(bpy.types.PropertyGroup):
    """An image numpy made from the inputs (height copy, blurred E/B): channel → image."""
    channel: StringProperty()
    image: PointerProperty(type=bpy.types.Image)
    key: StringProperty(description="The settings it was made with")


def _set_canvas(self, context):
    show_layer(self.id_data, context.scene)


def _painted_image(role, name, description):
    """One of a painted shape's images (Paint Shape): a change of it remakes the shape."""
    return PointerProperty(type=bpy.types.Image, name=name, description=description,
                           update=_on_change("painted." + role))


PAINTED_ANNOTATIONS = {
    "made": PointerProperty(type=bpy.types.Image, name="Painted Shape",
                            description="The shape image made from the layers (the painting's "
                                        "shape image while it is painted)"),
    "base": _painted_image("base", "Base", "The shape image before Paint Shape: its heights "
                           "are the made shape's floor (kept, never written)"),
    "base_scale": FloatProperty(name="Base Relief", default=0.05, min=0.0, precision=4,
                                description="Image widths of relief of the base's white",
                                update=_on_change("painted.base_scale")),
    "base_preblur": FloatProperty(default=0.0, min=0.0, options={"HIDDEN"}),
    "base_reads": StringProperty(options={"HIDDEN"},
                                 description="A normal-map base's §2 settings (empty: a height "
                                             "map)"),
    "mask": _painted_image("mask", "Figure Mask", "Paint white where the figure is: it is "
                           "inflated part by part into the shape"),
    "height_layer": _painted_image("height_layer", "Height Layer", "Paint lighter to raise the "
                                   "shape, darker to lower it (grey ½: the canvas)"),
    "structure": _painted_image("structure", "Structure", "A tileable image whose luminance "
                                "is added to the figure as height detail (a fabric, a canvas)"),
    "strength": FloatProperty(name="Strength", default=0.05, soft_min=-0.25, soft_max=0.25,
                              precision=4, step=0.1, subtype="DISTANCE",
                              description="Image widths the height layer raises the shape "
                                          "where it is painted white (lowers where black)",
                              update=_on_change("painted.strength")),
    "layer": EnumProperty(name="Paint On", items=[
        ("height_layer", "Height", "Paint the height layer: lighter raises, darker lowers"),
        ("mask", "Figure Mask", "Paint where the figure is (white): it is inflated")],
        description="Which layer Texture Paint paints", update=_set_canvas),
    "key": StringProperty(options={"HIDDEN"}),
    **{o.name: option_property(o, update=_on_change("painted." + o.name))
       for o in PAINTED_OPTIONS},
}
DYNPAINT_PG_painted = type("DYNPAINT_PG_painted", (bpy.types.PropertyGroup,),
                           {"__annotations__": PAINTED_ANNOTATIONS,
                            "__doc__": "Dynamic Painting: a shape painted in layers (Paint "
                                       "Shape)"})


SETTINGS_ANNOTATIONS = {
    "is_painting": BoolProperty(default=False, options={"HIDDEN"}),
    "plane": PointerProperty(type=bpy.types.Object, name="Plane",
                             description="The plane that shows this painting"),
    "light_collection": PointerProperty(
        type=bpy.types.Collection, name="Lights",
        description="Only the Sun and Point lights in this collection light the painting "
                    "(empty: every light in the scene)",
        update=_on_change("light_collection")),
    "lights": CollectionProperty(type=DYNPAINT_PG_light),
    "derived": CollectionProperty(type=DYNPAINT_PG_derived),
    "signature": StringProperty(options={"HIDDEN"}),
    "layer_thickness": FloatProperty(
        name="Thickness", default=0.0, min=0.0, soft_max=0.2, precision=3, step=0.1,
        description="How far this layer reaches behind its plane when it shadows the layers "
                    "behind it, in image widths of the back layer (0: its tallest relief, at "
                    "least a pixel). pipeline.md §15",
        update=_on_change("layer.thickness")),
    "shadows_stale": BoolProperty(default=False, options={"HIDDEN"}),
    "painted": PointerProperty(type=DYNPAINT_PG_painted),
    **{f"image_{c}": _image_pointer(c) for c in params.CHANNELS},
    **{s: PointerProperty(type=cls) for s, cls in zip(params.SECTIONS, SECTION_CLASSES)},
    "frames": PointerProperty(type=FRAMES_CLASS),
    **{f"frames_{c}": PointerProperty(type=FRAMES_CLASS) for c in params.CHANNELS},
    **{f"frames_{c}_own": _own_frames(c) for c in params.CHANNELS},
}
DYNPAINT_PG_settings = type("DYNPAINT_PG_settings", (bpy.types.PropertyGroup,),
                            {"__annotations__": SETTINGS_ANNOTATIONS,
                             "__doc__": "Dynamic Painting settings of a material"})

CLASSES = (*SECTION_CLASSES, FRAMES_CLASS, DYNPAINT_PG_light, DYNPAINT_PG_derived,
           DYNPAINT_PG_painted, DYNPAINT_PG_settings)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Material.dynamic_painting = PointerProperty(type=DYNPAINT_PG_settings)


def unregister():
    del bpy.types.Material.dynamic_painting
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
