"""Sprite sheets in the material: a copy of the frame's cell, or the whole sheet looked up at a
UV offset per frame? (issue 31, pipeline.md §16) — measured in EEVEE and Cycles.

One plane, an emission material showing one frame of a sheet of --frames cells of --size²,
rendered at the cell's size, frame after frame, two ways in the same run:
  - copy (the add-on's way): an image the cell's size whose pixels are written per frame
    (foreach_set of the cell cut with numpy), the material samples it as it is;
  - offset: the material samples the whole sheet, a Mapping node scales the plane's UVs to one
    cell and moves them to the frame's cell (keyframed, constant interpolation), no pixels
    written per frame.
Per frame: the frame change (scene.frame_set with the copy written) and the render, the
median over the frames; and the GPU memory each way holds (the sheet against one cell).

    .venv/bin/python benchmarks/sheet_lookup.py --size 512 --out docs/sheet-lookup.md
"""
import argparse
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from report import command_line, publish  # noqa: E402

from dynpaint_addon.blender.state.images import float_image  # noqa: E402
from dynpaint_addon.core.frames import SheetGrid, sheet_cell  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from testkit.animated import sheet_of  # noqa: E402
from testkit.render3d import ortho_camera  # noqa: E402


def scene_for(size, engine):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=1.0)
    plane = bpy.context.object
    ortho_camera(scene, 1.0, (0, 0, 5))
    r = scene.render
    r.engine = engine
    r.resolution_x = r.resolution_y = size
    if engine == "CYCLES":
        scene.cycles.samples = 1
        scene.cycles.use_denoising = False
        scene.cycles.device = "CPU"
    else:
        scene.eevee.taa_render_samples = 1
    return scene, plane


def emission(plane, image, mapping=None):
    mat = bpy.data.materials.new("m")
    nt = mat.node_tree
    nt.nodes.clear()
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = "Closest"
    em = nt.nodes.new("ShaderNodeEmission")
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(tex.outputs["Color"], em.inputs["Color"])
    nt.links.new(em.outputs[0], out.inputs[0])
    if mapping is not None:
        coords = nt.nodes.new("ShaderNodeTexCoord")
        node = nt.nodes.new("ShaderNodeMapping")
        nt.links.new(coords.outputs["UV"], node.inputs["Vector"])
        nt.links.new(node.outputs["Vector"], tex.inputs["Vector"])
        mapping(node)
    plane.data.materials.append(mat)


def run(size, frames, engine, way, folder):
    """Median ms a frame: (frame change, render)."""
    columns = math.ceil(math.sqrt(frames))
    grid = SheetGrid(columns, math.ceil(frames / columns), frames)
    rng = np.random.default_rng(0)
    cells = [rng.random((size, size, 4), np.float32) for _ in range(frames)]
    sheet = sheet_of(cells, grid.columns, grid.rows)
    scene, plane = scene_for(size, engine)
    if way == "copy":
        img = float_image("cell", cells[0])
        emission(plane, img)

        def show(f):
            float_image("cell", np.ascontiguousarray(sheet_cell(sheet, grid, f % frames)))
    else:
        img = float_image("sheet", sheet)

        def keys(node):
            node.inputs["Scale"].default_value = (1 / grid.columns, 1 / grid.rows, 1)
            loc = node.inputs["Location"]
            for f in range(frames):
                x0, y0, _, _ = grid.cell_box(f, *sheet.shape[1::-1])
                loc.default_value = (x0 / sheet.shape[1], y0 / sheet.shape[0], 0)
                loc.keyframe_insert("default_value", frame=f + 1)
            for fc in node.id_data.animation_data.action.layers[0].strips[0] \
                    .channelbag(node.id_data.animation_data.action_slot).fcurves:
                for kp in fc.keyframe_points:
                    kp.interpolation = "CONSTANT"
        emission(plane, img, keys)

        def show(f):
            pass
    change, draw = [], []
    for f in range(1, frames + 1):
        start = time.perf_counter()
        scene.frame_set(f)
        show(f - 1)
        mid = time.perf_counter()
        scene.render.filepath = os.path.join(folder, f"{way}_{f}.exr")
        scene.render.image_settings.file_format = "OPEN_EXR"
        bpy.ops.render.render(write_still=True)
        change.append(mid - start)
        draw.append(time.perf_counter() - mid)
    return float(np.median(change)) * 1000, float(np.median(draw[1:])) * 1000


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=512, help="a cell's side in pixels")
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--out")
    args = ap.parse_args(argv)
    rows, same = [], {}
    with tempfile.TemporaryDirectory() as folder:
        for engine in ("CYCLES", "BLENDER_EEVEE"):
            for way in ("copy", "offset"):
                rows.append((engine, way, *run(args.size, args.frames, engine, way, folder)))
            # both ways show the same cell (the offset's lookups land on the cell's texels)
            same[engine] = max(float(np.abs(read_image(os.path.join(folder, f"copy_{f}.exr"))
                                            .pixels - read_image(os.path.join(
                                                folder, f"offset_{f}.exr")).pixels).max())
                               for f in range(1, args.frames + 1))
    cell_mb = args.size * args.size * 16 / 2**20
    lines = ["# Sprite sheets in the material: a copy of the cell, or a UV offset?", "",
             f"`{command_line(__file__, argv)}` — a sheet of {args.frames} float RGBA cells of "
             f"{args.size}², one plane rendered at a cell's size frame after frame (1 sample, "
             f"this machine's CPU: Cycles, and EEVEE on software OpenGL); the median a frame. "
             f"*Copy*: the add-on's way, the cell written into an image per frame; *offset*: "
             f"the whole sheet sampled at a keyframed UV offset. GPU memory: one cell is "
             f"{cell_mb:.0f} MB, the sheet {cell_mb * args.frames:.0f} MB.", "",
             "| engine | way | frame change | render | total | copy − offset, largest |",
             "|---|---|---|---|---|---|"]
    for engine, way, change, draw in rows:
        lines.append(f"| {'EEVEE' if engine != 'CYCLES' else 'Cycles'} | {way} | "
                     f"{change:.1f} ms | {draw:.0f} ms | {change + draw:.0f} ms | "
                     f"{same[engine]:.1e} |")
    publish(lines, args.out)
    return rows


if __name__ == "__main__":
    main()
