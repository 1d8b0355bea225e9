"""Artists' Grease Pencil drawings as they come, lit as a newcomer lights them (issue 61):
each .blend of benchmarks/artists_drawings.toml opened in Blender and every drawing in it
made a lit copy by From Grease Pencil at --size, with no hand edit; beside them, in the same
run, the project's own three-layer drawing (testkit.grease_pencil.figure_on_a_hill_in_the_sun),
the baseline.

Per drawing: its layers and strokes, who draws it (numpy, or Blender's Grease Pencil renderer
and the reason a note gives the artist: scenes/grease_pencil/strokes.unsupported), the seconds
From Grease Pencil took as a script waits for it, and whether the lit copy is lit: each
layer's shadow image baked, the range of its cos-θ term.

    .venv/bin/python benchmarks/artists_drawings.py --out docs/artists-drawings.md
"""
import argparse
import os
import sys
import time
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

import bpy  # noqa: E402

from artists_files import fetch  # noqa: E402
from report import command_line, publish  # noqa: E402

from dynpaint_addon.blender import register_once  # noqa: E402
from dynpaint_addon.blender.bake.layers import group_materials, settle  # noqa: E402
from dynpaint_addon.blender.scenes.grease_pencil.reading import drawn_layers  # noqa: E402
from dynpaint_addon.blender.scenes.grease_pencil.strokes import unsupported  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender  # noqa: E402
from testkit.grease_pencil import figure_on_a_hill_in_the_sun  # noqa: E402

FETCH_LIST = os.path.join(HERE, "artists_drawings.toml")


def strokes_of(obj):
    """How many strokes the drawing shows on the current frame, over its layers."""
    count = 0
    for layer in obj.data.layers:
        frame = layer.current_frame()
        count += len(frame.drawing.strokes) if frame is not None else 0
    return count


def lit(obj, size):
    """(seconds From Grease Pencil took, [(layer, lowest, highest cos-θ)]) of a drawing."""
    bpy.ops.object.select_all(action="DESELECT")
    obj.hide_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    start = time.perf_counter()
    assert bpy.ops.dynpaint.add_grease_pencil(resolution=size) == {"FINISHED"}
    settle()
    seconds = time.perf_counter() - start
    terms = []
    for mat in group_materials(bpy.context.object):
        for item in mat.dynamic_painting.lights:
            t = image_data_from_blender(item.shadow).pixels[..., 0]
            terms.append((mat.name, float(t.min()), float(t.max())))
    return seconds, terms


def tried(source, size):
    """The report's rows of every drawing in the open file."""
    rows = []
    for obj in [o for o in bpy.context.scene.objects if o.type == "GREASEPENCIL"]:
        why = unsupported(obj, drawn_layers(obj)[0])
        drawn_by = "numpy" if not why else f"Blender's renderer: {why}"
        layers, strokes = len(obj.data.layers), strokes_of(obj)
        try:
            seconds, terms = lit(obj, size)
            shown = "; ".join(f"{name}: {lo:.2f}–{hi:.2f}" for name, lo, hi in terms) or \
                "no shadow image"
            rows.append(f"| {source} | {obj.name} | {layers} | {strokes} | {drawn_by} | "
                        f"{seconds:.1f} s | {shown} |")
        except Exception as exc:          # a newcomer's file: what failed is the finding
            rows.append(f"| {source} | {obj.name} | {layers} | {strokes} | {drawn_by} | "
                        f"failed | {type(exc).__name__}: {exc} |")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    with open(FETCH_LIST, "rb") as fh:
        entries = tomllib.load(fh)["set"]
    bpy.ops.wm.read_homefile(use_empty=True)
    register_once()
    figure_on_a_hill_in_the_sun(bpy.context.scene)
    rows = tried("this project's figure on a hill (baseline)", args.size)
    for entry in entries:
        folder = fetch(entry)
        for name in entry["files"]:
            bpy.ops.wm.open_mainfile(filepath=os.path.join(folder, name))
            register_once()
            rows += tried(f"{entry['name']} ({entry['tool']}; {entry['repo']})", args.size)
    lines = ["# Artists' Grease Pencil drawings, lit as they come (issue 61)", "",
             f"`{command_line(__file__, argv)}` — each drawing made a lit copy by From Grease "
             f"Pencil at {args.size}² (no hand edit), as a script waits for it (the final "
             f"bake in place); the cos-θ range of each layer's shadow image says it is lit.",
             "", "| file | drawing | layers | strokes | drawn by | From Grease Pencil | "
             "cos-θ per layer |", "|---|---|---|---|---|---|---|"] + rows
    publish(lines, args.out)


if __name__ == "__main__":
    main()
