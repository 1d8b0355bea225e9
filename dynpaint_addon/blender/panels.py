"""The Dynamic Painting panel, in Material Properties and in the 3D viewport's sidebar (N).

Sub-panels follow how an artist thinks about a painting: Images, Frames (§16), Lights, then one
per entry of params.PANELS (Shape, Light & Style, Shadows, …), each showing the parameters of its
sections (a parameter's `header` toggle in the panel's header, `shown_if` only when it
applies). The same draw functions serve both places; the classes are generated once per place.
"""
import bpy

from .. import params
from ..looks import LOOKS
from ..shapes.painted import OPTIONS as PAINTED_OPTIONS
from .bake.layers import layer_parent
from .bake.live_bake import LIVE
from .operators.add import draw_add_menu
from .operators.common import active_painting
from .state.frames import painting_frames
from .state.painted import is_painted
from .state.settings import channel_images
from .state.status import errors_of, problems


def _draw_param(layout, group, param):
    if param.kind in ("auto_float", "auto_int"):
        row = layout.row(align=True)
        auto = getattr(group, param.key + "_auto")
        sub = row.row(align=True)
        sub.active = not auto
        sub.prop(group, param.key)
        row.prop(group, param.key + "_auto", text="", icon="AUTO", toggle=True)
    else:
        layout.prop(group, param.key)


def _shown(s, param):
    if param.header:
        return False
    if param.shown_if:
        section, key = param.shown_if[0].split(".")
        return getattr(getattr(s, section), key) == param.shown_if[1]
    return True


def _draw_section(layout, s, section):
    group = getattr(s, section)
    col = layout.column()
    col.use_property_split = True
    col.use_property_decorate = True
    for param in params.PARAMS:
        if param.section == section and _shown(s, param):
            _draw_param(col, group, param)
    if section == "diffuse":
        row = layout.row(align=True)
        for key in ("CLASSIC", "GOOCH", "CARTOON"):
            row.operator("dynpaint.apply_look", text=LOOKS[key][0]).look = key
    if section == "fresnel":
        mode = s.fresnel.mode
        col.enabled = bool(s.image_environment and s.image_background)
        if not col.enabled:
            layout.label(text="Needs an environment and a background image", icon="INFO")
        elif mode == "physical":
            layout.label(text="Uses the refraction IOR", icon="INFO")


def _draw_images(layout, s):
    col = layout.column(align=True)
    for channel, (what, kind) in params.CHANNELS.items():
        row = col.row(align=True)
        row.label(text=channel.replace("_", " ").title())
        img = getattr(s, f"image_{channel}")
        row.label(text=img.name if img else "—", icon="IMAGE_DATA" if img else "BLANK1")
        op = row.operator("dynpaint.image_open", text="", icon="FILEBROWSER")
        op.channel = channel
        if img is not None:
            row.operator("dynpaint.image_remove", text="", icon="X").channel = channel
    layout.operator("dynpaint.make_shape", icon="MOD_SMOOTH")


def _draw_paint_shape(layout, context, mat):
    """Paint Shape (operators/paint_shape.py): the button, then the layers, which one Texture
    Paint paints, the height layer's strength and the figure's relief."""
    s = mat.dynamic_painting
    painting = context.object is not None and context.object.mode == "TEXTURE_PAINT"
    if painting and is_painted(s):
        layout.operator("dynpaint.paint_shape_done", icon="CHECKMARK")
    else:
        layout.operator("dynpaint.paint_shape", icon="BRUSH_DATA")
    if not is_painted(s):
        layout.label(text="Paint the shape: a figure mask and a height layer", icon="INFO")
        return
    pt = s.painted
    layout.row().prop(pt, "layer", expand=True)
    col = layout.column()
    col.use_property_split = True
    col.prop(pt, "strength", text="Height Layer Strength")
    for name in ("mask", "height_layer", "base"):
        col.prop(pt, name)
    if pt.base is not None:
        col.prop(pt, "base_scale")
    col.label(text="Figure")
    for option in PAINTED_OPTIONS:
        if option.name == "structure_scale":
            col.prop(pt, "structure")
        col.prop(pt, option.name)


def _draw_frame_params(layout, group):
    col = layout.column()
    col.use_property_split = True
    for param in params.FRAME_PARAMS:
        _draw_param(col, group, param)


def _draw_frames(layout, context, mat):
    """A painting that moves (§16): what moves and what the frame shows, the painting's frame
    mapping, and the slots that follow one of their own."""
    s = mat.dynamic_painting
    try:
        frames = painting_frames(mat)
        f = context.scene.frame_current
        col = layout.column(align=True)
        for note in frames.notes:
            col.label(text=note, icon="SEQUENCE")
        if frames.animated:
            col.label(text=f"Frame {f} shows {frames.shown(f)}", icon="TIME")
        else:
            col.label(text="Still: give a slot an image sequence (name_####.png) or set a "
                           "sprite sheet's columns and rows", icon="INFO")
    except (ValueError, OSError) as exc:       # a broken sequence: said, never raised
        layout.label(text=str(exc), icon="ERROR")
    _draw_frame_params(layout, s.frames)
    for channel, img in channel_images(s).items():
        box = layout.box()
        box.prop(s, f"frames_{channel}_own", text=f"{channel.replace('_', ' ').title()}: "
                                                  f"Own Frames")
        if getattr(s, f"frames_{channel}_own"):
            _draw_frame_params(box, getattr(s, f"frames_{channel}"))


def _draw_lights(layout, context, mat):
    s = mat.dynamic_painting
    layout.prop(s, "light_collection")
    col = layout.column(align=True)
    for item in s.lights:
        if item.object is None:
            continue
        row = col.row(align=True)
        row.label(text=item.object.name, icon="LIGHT_SUN" if item.kind == "SUN" else "LIGHT_POINT")
        row.prop(item.object.data, "color", text="")
        row.prop(item.object.data, "energy", text="")
    if not s.lights:
        col.label(text="No Sun or Point light: the painting shows its dark image", icon="INFO")
    layout.operator("dynpaint.add_light_turntable", icon="ORIENTATION_GIMBAL")


def _draw_layers(layout, mat):
    """The layers of the scene this painting belongs to (§15), back to front: depth (its
    plane's height over the parent), thickness, shown in renders and the viewport."""
    parent = layer_parent(mat)
    if parent is None:
        layout.label(text="Not a layer: add one with Add › Dynamic Painting › Layered…",
                     icon="INFO")
        return
    layout.label(text=f"Scene: {parent.name}", icon="RENDERLAYERS")
    col = layout.column(align=True)
    layers = sorted((c for c in parent.children if c.active_material is not None
                     and c.active_material.dynamic_painting.is_painting),
                    key=lambda o: o.location.z)
    for plane in layers:
        row = col.row(align=True)
        current = plane.active_material == mat
        row.label(text=plane.name, icon="RADIOBUT_ON" if current else "RADIOBUT_OFF")
        row.prop(plane, "location", index=2, text="Depth")
        row.prop(plane.active_material.dynamic_painting, "layer_thickness", text="")
        row.prop(plane, "hide_render", text="", emboss=False)
        row.prop(plane, "hide_viewport", text="", emboss=False)
    if mat.dynamic_painting.shadows.source == "osl":
        layout.label(text="In-shader (OSL) shadows leave out the layers in front: use Baked",
                     icon="ERROR")
    layout.label(text="The layers in front shadow those behind (pipeline.md §15)", icon="INFO")


class _Base:
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return active_painting(context) is not None


def _make_panels(space, region, context_name, category, prefix):
    """The main panel and its sub-panels for one place in the UI."""
    main_id = f"DYNPAINT_PT_{prefix}_main"
    where = {"bl_space_type": space, "bl_region_type": region}
    if context_name:
        where["bl_context"] = context_name
    if category:
        where["bl_category"] = category

    def draw_main(self, context):
        mat = active_painting(context)
        s = mat.dynamic_painting
        layout = self.layout
        row = layout.row(align=True)
        row.operator_menu_enum("dynpaint.apply_look", "look", text="Look", icon="PRESET")
        row.operator("dynpaint.bake_shadows", icon="LIGHT_SUN")
        row = layout.row(align=True)
        row.operator("dynpaint.face_camera", icon="CAMERA_DATA")
        row.operator("dynpaint.rebuild", icon="FILE_REFRESH")
        row.operator("dynpaint.export_recipe", text="", icon="EXPORT")
        row.operator("dynpaint.export_web", text="", icon="URL")
        layout.operator("dynpaint.add_compositor_group", text="Add Compositor Group",
                        icon="NODETREE")
        if s.shadows.enabled and s.shadows_stale:
            layout.label(text="Shadows are out of date: Bake Shadows", icon="ERROR")
        if s.shadows.enabled and LIVE.latencies:
            quality, ms = LIVE.latencies[-1]
            layout.label(text=f"Last live bake: {quality}, {ms:.0f} ms", icon="TIME")
        for problem in problems(mat):
            layout.label(text=problem, icon="ERROR")
        errors = errors_of(mat)
        if errors:
            layout.label(text=errors[-1], icon="ERROR")

    main = type(main_id, (_Base, bpy.types.Panel), {
        **where, "bl_label": "Dynamic Painting", "bl_options": set(), "draw": draw_main})
    panels = [main]

    def sub(idname, label, draw, header=None):
        attrs = {**where, "bl_label": label, "bl_parent_id": main_id, "draw": draw}
        if header:
            section, key = header.split(".")

            def draw_header(self, context):
                s = active_painting(context).dynamic_painting
                self.layout.prop(getattr(s, section), key, text="")
            attrs["draw_header"] = draw_header
        panels.append(type(f"DYNPAINT_PT_{prefix}_{idname}", (_Base, bpy.types.Panel), attrs))

    sub("images", "Images", lambda self, context: _draw_images(
        self.layout, active_painting(context).dynamic_painting))
    sub("paint_shape", "Paint Shape", lambda self, context: _draw_paint_shape(
        self.layout, context, active_painting(context)))
    sub("frames", "Frames", lambda self, context: _draw_frames(
        self.layout, context, active_painting(context)))
    sub("lights", "Lights", lambda self, context: _draw_lights(
        self.layout, context, active_painting(context)))
    sub("layers", "Layers", lambda self, context: _draw_layers(
        self.layout, active_painting(context)))
    for idname, (label, sections) in params.PANELS.items():
        header = next((prm.path for prm in params.PARAMS if prm.header and prm.panel == idname), None)
        sub(idname, label, _section_drawer(sections), header)
    return panels


def _section_drawer(sections):
    def draw(self, context):
        s = active_painting(context).dynamic_painting
        for section in sections:
            if len(sections) > 1:
                self.layout.label(text=section.title())
            _draw_section(self.layout, s, section)
    return draw


class DYNPAINT_PT_view3d_samples(bpy.types.Panel):
    """Sidebar › Dynamic Painting › Add: the add operator and the samples, one click each."""
    bl_space_type, bl_region_type, bl_category = "VIEW_3D", "UI", "Dynamic Painting"
    bl_label = "Add Painting"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return True          # with or without a painting selected

    def draw(self, context):
        draw_add_menu(self.layout.column(align=True))


CLASSES = (_make_panels("PROPERTIES", "WINDOW", "material", None, "material")
           + _make_panels("VIEW_3D", "UI", None, "Dynamic Painting", "view3d")
           + [DYNPAINT_PT_view3d_samples])


register, unregister = bpy.utils.register_classes_factory(CLASSES)
