"""Make Shape: the painting's shape image made by numpy from what it has (issue 16,
docs/shape-from-painting.md): its silhouette inflated, its normal map integrated into heights,
its height map's normals, or a normal map from lighting profiles or a red/green photograph.
The adjust-last-operation panel is the preview: change a setting and the painting is made
again, one undo step. On a painting that moves (§16) each drawing gets its shape: a packed
sheet whose cells follow the frames."""
import bpy
import numpy as np
from bpy.props import EnumProperty

from ...core.frames import SheetGrid
from ...core.photometric import SIDES
from ...inputs.channel_names import sprite_lamp_siblings
from ...inputs.imageio import image_data_from_blender, read_image
from ...shapes.frames import fill_sheet, on_one_floor
from ...shapes.maker import read_as_made
from ...shapes.methods import METHODS, OPTIONS, SHAPE_MAKERS, make_shape, options
from ..material.sync import batch, update
from ..state.frames import frame_data, painting_frames
from ..state.images import made_shape_image
from ..state.settings import channel_images, params_to_settings, set_own_frames, settings_to_params
from ..state.shape_options import option_property
from .common import PaintingOperator, active_painting, run_and_report


READ = ("shape", "dark", "bright")        # what a method reads of the painting


def made_per_frame(mat, painting, method, p, values, progress):
    """Make Shape on a painting that moves (§16): the method run on each drawing one loop
    shows (shapes.frames' rules: one floor for integrated heights), laid out as a sheet of one
    cell per frame of the loop → (kind, sheet RGBA, report lines, the shape slot's own frame
    mapping that shows each cell on its frame)."""
    shown, sequence = painting.drawings()
    made = []
    for i, f in enumerate(shown):
        images = {c: frame_data(mat, c, f) for c in READ if c in painting.slots}
        kind, rgba, lines = make_shape(method, images, p, floor=0.0, **values)
        made.append(rgba)
        progress(0.2 + 0.5 * (i + 1) / len(shown))
    if method == "integrate":                   # the lowest point of all the frames is 0
        grey = on_one_floor([m[..., :3] for m in made])
        made = [np.concatenate([g, m[..., 3:]], -1) for g, m in zip(grey, made)]
    grid = SheetGrid.squarest(len(sequence))
    h, w = made[0].shape[:2]
    sheet = fill_sheet([made[k] for k in sequence], grid, grid.sheet_size(w, h), 0.0)
    holds = all(sl.mode == "hold" for sl in painting.slots.values() if sl.kind != "still")
    mapping = {"start": painting.start, "offset": 0, "count": len(sequence),
               "mode": "hold" if holds else "cyclic", "rate": 1.0, "columns": grid.columns,
               "rows": grid.rows, "margin": 0, "spacing": 0}
    return kind, sheet, [f"{lines[0]} — for each of {len(shown)} drawings, a sheet of "
                         f"{len(sequence)} frames ({grid.columns} × {grid.rows})"], mapping


class DYNPAINT_OT_make_shape(PaintingOperator, bpy.types.Operator):
    """Make the painting's shape image from what it has: inflate its silhouette, integrate its
    normal map into a height map, or take its height map's normals"""
    bl_idname = "dynpaint.make_shape"
    bl_label = "Make Shape"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = {
        "method": EnumProperty(name="Method", items=[(k, METHODS[k].label, METHODS[k].help)
                                                     for k in SHAPE_MAKERS]),
        **{o.name: option_property(o) for o in OPTIONS if o.where in ("both", "addon")},
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
            painting = painting_frames(mat)
            if any(painting.slots[c].kind != "still" for c in READ if c in painting.slots):
                kind, rgba, lines, mapping = made_per_frame(mat, painting, self.method, p,
                                                            values, progress)
            else:
                images = {c: image_data_from_blender(img) for c, img in
                          channel_images(s).items() if c in READ}
                kind, rgba, lines = make_shape(self.method, images, p, **values)
                mapping = None
            progress(0.7)
            img = made_shape_image(f"{mat.name} {'height' if kind == 'height' else 'normal'}"
                                   f" ({self.method})", rgba)
            with batch():
                params_to_settings(read_as_made(p, kind), s, sections=("shape",))
                s.image_shape = img
                if mapping is not None:             # the sheet's cells follow the frames
                    set_own_frames(s, "shape", mapping)
            update(mat, context.scene, rebake=True)
            return [("INFO", f"{lines[0]}; the shape image is now {img.name} (packed in "
                             f"the .blend)")]
        return run_and_report(self, context, work, progress=True, failure="Make Shape: ",
                              catch=(ValueError, MemoryError))    # ShapeError, ImageReadError


CLASSES = (DYNPAINT_OT_make_shape,)
