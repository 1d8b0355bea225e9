"""File › Export › Dynamic Painting (.html): the painting as a web page where viewers drag the
light (issue 17), with its current settings, lights and their animation."""
import os
import time

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from ... import params
from ...inputs.imageio import ImageReadError, image_data_from_blender
from ...web.page import page_data, scene_data, write_page
from ..bake.layers import group_layers, group_materials, layer_parent
from ..state.frame_sampling import reading_lights
from ..state.frames import frame_data, moves, painting_frames
from ..state.lights import painting_lights
from ..state.settings import channel_images, settings_to_params
from .common import PaintingOperator, active_painting, run_and_report

STEPS = params.BY_PATH["shadows.steps"]
MAX_ANIMATION_FRAMES = 2000


def light_animation(mat, scene, progress=None):
    """The lights' vectors (painting frame) on every frame of the scene's range → {'fps',
    'frames'}, or None when no light moves. The frame is put back afterwards, the shadows as
    they were (nothing is baked for the frames visited)."""
    start, end = scene.frame_start, min(scene.frame_end, scene.frame_start
                                        + MAX_ANIMATION_FRAMES - 1)
    here = scene.frame_current
    frames = []
    with reading_lights():           # no shadow bakes for frames only visited to read them
        try:
            for frame in range(start, end + 1):
                scene.frame_set(frame)
                frames.append([list(lt.vector) for lt in painting_lights(mat, scene)])
                if progress:       # reading the lights is about a sixth of the export
                    progress(0.2 * (frame - start + 1) / (end - start + 1))
        finally:
            scene.frame_set(here)
    if all(f == frames[0] for f in frames):
        return None
    return {"fps": scene.render.fps / scene.render.fps_base, "frames": frames}


def painting_page(mat, scene, title, credits="", steps=None, max_size=None, animation=True,
                  progress=None):
    """The painting's web page data (web/page.py) → (data, warnings); a layer's: its whole
    scene of layers (§15), its lights where they are now."""
    parent = layer_parent(mat)
    if parent is not None:
        mats = group_materials(parent)
        return scene_data(group_layers(mats), painting_lights(mats[0], scene), title=title,
                          credits=credits, steps=steps, max_size=max_size)
    s = mat.dynamic_painting
    frames = None
    if moves(mat):                  # §16: every drawing of one loop, at the scene's rate
        painting = painting_frames(mat)
        frames = painting.web_frames(scene.render.fps / scene.render.fps_base,
                                     lambda f: {c: frame_data(mat, c, f) for c in painting.slots})
        images = frames["drawings"][0]
    else:
        images = {c: image_data_from_blender(img) for c, img in channel_images(s).items()}
    anim = light_animation(mat, scene, progress) if animation else None
    return page_data(images, painting_lights(mat, scene), settings_to_params(s), title=title,
                     credits=credits, steps=steps, max_size=max_size, animation=anim,
                     frames=frames)


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
    max_size: IntProperty(name="Max Size", default=0, min=0, max=16384, subtype="PIXEL",
                          description="Longest side of the painting in the page, in pixels "
                          "(0: the shape image's size; smaller pages load faster)")
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
