"""Write node_groups/dynamic_painting.blend: ready-made Dynamic Painting compositor groups.

    .venv/bin/python node_groups/make_node_groups.py [--out node_groups/dynamic_painting.blend]

Each group is generated from the pipeline's one graph description (dynpaint_addon/nodegraph),
exactly as the add-on's "Add Compositor Group" operator builds it, and marked as an asset.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from dynpaint_addon.blender.scenes.compositor import build_group, features_for_options  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
# name: (shape kind, suns, points, shadows, highlights, channels, silhouette, what it is for)
VARIANTS = {
    "Dynamic Painting: Normal Map, Sun": (
        "normal", 1, 0, False, False, (), "", "Relight a painting from its normal map"),
    "Dynamic Painting: Normal Map, Sun + Point, Highlights": (
        "normal", 1, 1, False, True, ("specular_color", "gloss"), "",
        "Two lights and coloured highlights"),
    "Dynamic Painting: Height Map, Shadows": (
        "height", 1, 0, True, False, (), "", "cos-θ shadows: feed the baked term "
        "(dynpaint bake-shadow) to 'Light 1 Shadow'"),
    "Dynamic Painting: Glass": (
        "normal", 1, 0, False, True, ("environment", "background", "transparency"), "",
        "Reflection, refraction and Fresnel through a transparency map"),
    "Dynamic Painting: Everything": (
        "height", 1, 1, True, True, ("specular_color", "gloss", "environment", "background",
                                     "transparency"), "shape", "Every input and pass"),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(HERE, "dynamic_painting.blend"))
    args = ap.parse_args(argv)
    bpy.ops.wm.read_homefile(use_empty=True)
    groups = set()
    for name, (kind, suns, points, shadows, spec, chans, silhouette, about) in VARIANTS.items():
        f = features_for_options(kind, suns, points, shadows, spec, chans, silhouette)
        group = build_group(f, name)
        group.asset_mark()
        group.asset_data.description = about
        group.asset_data.tags.new("Dynamic Painting")
        groups.add(group)
    bpy.data.libraries.write(os.path.abspath(args.out), groups, fake_user=True, compress=True)
    print(f"wrote {len(groups)} groups → {args.out}")


if __name__ == "__main__":
    main()
