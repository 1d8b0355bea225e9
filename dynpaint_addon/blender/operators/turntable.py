"""Add Light Turntable: a light orbiting the painting in a seamless loop (turntable.py)."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from ..scenes.turntable import add_light_turntable, video_output
from ..state.lights import linked_lights
from .common import PaintingOperator, active_painting, run_and_report


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
                     for o in linked_lights(mat, context.scene)] + items
        _ITEMS_KEEPALIVE[:] = items      # Blender needs the strings kept alive
        return items

    light: EnumProperty(name="Light", items=_light_items,
                        description="The light that orbits (its own location/rotation keys "
                                    "are replaced)")
    frame_start: IntProperty(name="Start Frame", default=1, min=0)
    frame_end: IntProperty(name="End Frame", default=96, min=0,
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
        mat = active_painting(context)
        light = None if self.light.startswith("NEW_") else context.scene.objects.get(self.light)
        kind = "POINT" if self.light == "NEW_POINT" else "SUN"

        def work():
            _, orbiting, messages = add_light_turntable(
                context, mat, light, kind if light is None else light.data.type,
                self.frame_start, self.frame_end, self.elevation, self.radius, self.start_angle,
                self.direction == "CW")
            if self.set_output:
                video_output(context.scene, self.filepath)
            frames = self.frame_end - self.frame_start + 1
            return [("WARNING" if "not" in m else "INFO", m) for m in messages] + [
                ("INFO", f"'{orbiting.name}' orbits the painting every {frames} frames"
                 + (f"; output: {self.filepath}" if self.set_output else ""))]
        return run_and_report(self, context, work, catch=(ValueError, TypeError))


_ITEMS_KEEPALIVE = []


CLASSES = (DYNPAINT_OT_add_light_turntable,)
