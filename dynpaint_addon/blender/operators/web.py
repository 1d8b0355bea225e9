"""File › Export › Dynamic Painting (.html): the painting as a web page where viewers drag the
light (issue 17), with its current settings, lights and their animation."""
import os
import time

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ... import params
from ...inputs.imageio import ImageReadError
from ...web.device_fit import DEFAULT_MAX_SIZE
from ...web.page import write_page
from ..scenes.web_page import painting_page
from .common import PaintingOperator, active_painting, run_and_report

STEPS = params.BY_PATH["shadows.steps"]


class DYNPAINT_OT_export_web(PaintingOperator, bpy.types.Operator, ExportHelper):
    """Export the painting as one web page (.html, images inside, works offline) where
    viewers drag the light over it; open it with ?embed for the painting alone"""
    bl_idname = "dynpaint.export_web"
    bl_label = "Export Dynamic Painting Web Page"
    filename_ext = ".html"
    filter_glob: StringProperty(default="*.html", options={"HIDDEN"})
    title: StringProperty(name="Title", description="Shown above the painting (default: the "
                          "painting's name)")
    credits: StringProperty(name="Credits", description="Shown under the title: who made it")
    max_size: IntProperty(name="Max Size", default=DEFAULT_MAX_SIZE, min=0, max=16384,
                          subtype="PIXEL",
                          description="Longest side of the painting in the page, in pixels "
                          "(0: the shape image's size; smaller pages load faster). The "
                          "default is the most many phones draw; a page over 2048 px also "
                          "carries smaller copies, and each device draws the largest it can")
    steps: IntProperty(name="Shadow Steps", default=STEPS.default, min=1, max=STEPS.max,
                       description="K: march steps per pixel of the shadows the page computes "
                       "as the light moves (fewer draw faster on slow devices)")
    animation: BoolProperty(name="Light Animation", default=True,
                            description="Play the lights' keyframes of the scene's frame range "
                            "(else the page turns the key light)")

    def invoke(self, context, event):
        mat = active_painting(context)
        self.title = self.title or mat.name
        self.steps = mat.dynamic_painting.shadows.steps
        if not self.filepath:
            folder = os.path.dirname(bpy.data.filepath) if bpy.data.filepath else ""
            self.filepath = os.path.join(folder, bpy.path.clean_name(mat.name) + ".html")
        return super().invoke(context, event)

    def execute(self, context):
        mat = active_painting(context)

        def work(progress):
            start = time.perf_counter()
            data, warnings = painting_page(mat, context.scene, self.title or mat.name,
                                           self.credits, self.steps, self.max_size or None,
                                           self.animation, progress)
            size = write_page(self.filepath, data)
            moving = f", {len(data['animation']['frames'])} animated frames" \
                if data["animation"] else ""
            if data.get("frames"):
                moving += f", the painting's {len(data['frames']['sequence'])} frames"
            return [("WARNING", w) for w in warnings] + [
                ("INFO", f"Wrote {self.filepath} ({size / 1e6:.1f} MB{moving}) in "
                         f"{time.perf_counter() - start:.1f} s")]
        return run_and_report(self, context, work, failure="Could not export the web page: ",
                              catch=(OSError, ValueError, RuntimeError, ImageReadError),
                              progress=True)


CLASSES = (DYNPAINT_OT_export_web,)
