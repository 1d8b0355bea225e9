"""Operators on the active painting: bake its shadows, apply a look, face the camera, rebuild."""
import bpy
from bpy.props import EnumProperty

from ...looks import LOOKS
from ..bake.layers import bake_painting
from ..material.sync import batch, update
from ..material.tree import rebuild_tree
from ..scenes.painting_scene import face_camera
from ..state.frames import painting_size
from .common import PaintingOperator, active_painting, run_and_report


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

        def work(progress):     # the cursor shows it; long bakes report per band
            ms = bake_painting(mat, context.scene, context.evaluated_depsgraph_get(),
                               progress=progress)
            rebuild_tree(mat, context.scene)
            n = len(mat.dynamic_painting.lights)
            w, h = painting_size(mat)
            return [("INFO", f"Baked shadows of {n} light{'s' * (n != 1)} at {w}×{h} "
                             f"in {ms:.0f} ms")]
        return run_and_report(self, context, work, progress=True,
                              failure="Bake failed, the previous shadows are kept: ")


class DYNPAINT_OT_apply_look(PaintingOperator, bpy.types.Operator):
    """Apply a ready-made look to the painting's settings"""
    bl_idname = "dynpaint.apply_look"
    bl_label = "Apply Look"
    bl_options = {"REGISTER", "UNDO"}

    look: EnumProperty(name="Look", items=[(k, v[0], v[1]) for k, v in LOOKS.items()])

    def execute(self, context):
        mat = active_painting(context)
        s = mat.dynamic_painting
        with batch():
            for path, value in LOOKS[self.look][2].items():
                section, key = path.split(".")
                setattr(getattr(s, section), key, value)
        try:
            update(mat, context.scene)
        except ValueError as exc:
            self.report({"WARNING"}, str(exc))
        self.report({"INFO"}, f"Applied the {LOOKS[self.look][0]} look")
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
        face_camera(plane, context.scene.camera)
        return {"FINISHED"}


class DYNPAINT_OT_rebuild(PaintingOperator, bpy.types.Operator):
    """Rebuild the painting's material, derived images and shadows from its settings"""
    bl_idname = "dynpaint.rebuild"
    bl_label = "Rebuild Material"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        mat = active_painting(context)

        def work():
            update(mat, context.scene, force=True)
            return [("INFO", f"Rebuilt {mat.name}")]
        return run_and_report(self, context, work)


CLASSES = (DYNPAINT_OT_bake_shadows, DYNPAINT_OT_apply_look, DYNPAINT_OT_face_camera,
           DYNPAINT_OT_rebuild)
