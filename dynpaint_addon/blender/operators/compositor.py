"""Add › Dynamic Painting Group in the compositor: the pipeline as a node group (compositor.py)."""
import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty

from ..scenes.compositor import (add_group_node, build_group, features_for_options,
                          wire_painting)
from ..state.painting_state import read_state
from .common import active_painting, run_and_report


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
    suns: IntProperty(name="Suns", default=1, min=0, max=8)
    points: IntProperty(name="Point Lights", default=0, min=0, max=8)
    shadows: BoolProperty(name="Shadows", description="cos-θ shadow image inputs, one per light")
    specular: BoolProperty(name="Highlights")
    environment: BoolProperty(name="Environment (reflection)")
    background: BoolProperty(name="Background (refraction)")
    transparency: BoolProperty(name="Transparency Map")

    def execute(self, context):
        mat = active_painting(context) if self.match_painting else None

        def work():
            if mat is not None:
                state = read_state(mat, context.scene)
                features = state.features
            else:
                chans = [c for c in ("environment", "background", "transparency")
                         if getattr(self, c)]
                features = features_for_options(self.shape_kind, self.suns, self.points,
                                                self.shadows, self.specular, chans, "")
            group = build_group(features)
            node = add_group_node(context.scene, group)
            if mat is not None:
                wire_painting(context.scene, node, mat, state)
            return [("INFO", f"Added '{group.name}' to the compositor"
                     + (f" for {mat.name}" if mat is not None else ""))]
        return run_and_report(self, context, work, catch=(ValueError, KeyError))


CLASSES = (DYNPAINT_OT_add_compositor_group,)
