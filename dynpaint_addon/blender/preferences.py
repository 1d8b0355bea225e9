"""The add-on's preferences (Edit › Preferences › Add-ons › Dynamic Painting): what a machine,
not a painting, decides — how much of a moving painting's frames stays in memory (§16)."""
import bpy
from bpy.props import IntProperty

from ..inputs.painting_frames import DEFAULT_CACHE_MB
from .state.frames import ADDON, forget_frames


def _cache_changed(self, context):
    forget_frames()              # every painting's frames kept again under the new bound


class DYNPAINT_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = ADDON

    frame_cache_mb: IntProperty(
        name="Frame Cache", default=DEFAULT_CACHE_MB, min=64, soft_max=16384, max=1 << 20,
        description="Megabytes of a moving painting's frames kept in memory (image sequences "
                    "and sprite sheets, pipeline.md §16): more plays long or large sequences "
                    "without reading their files again; the least recently shown frames go "
                    "first", update=_cache_changed)

    def draw(self, context):
        self.layout.prop(self, "frame_cache_mb")


CLASSES = (DYNPAINT_AP_preferences,)


register, unregister = bpy.utils.register_classes_factory(CLASSES)
