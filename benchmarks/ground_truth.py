"""The cos-θ bake against real 3D (issue 4): Blender renders the ground truth.

(benchmarks/shape_from_painting.py renders its own scenes with these functions: Suzanne too,
and the lighting profiles.)

A scene of a sphere, a torus, boxes of different heights and a floating plate (an overhang) on a
ground plane, seen from above by an orthographic camera looking down −Z (one image width = one
scene unit, so heights are in image widths):
  - rendered as a height map (world z), a normal map (world normals) and an object-index map;
  - rendered in Cycles with a hard sun (angle 0), white diffuse materials, direct light only,
    sun strength π (a lit white plane facing the sun reads exactly cos θ): the ground truth
    N·L × visibility;
  - the numpy bake of the cos-θ term from the height map and from the normal map is compared
    with it, per object and per sun: mean |t − ground truth|, and the IoU of the cast-shadow
    regions (pixels that face the sun yet get less than half of N·L).

    .venv/bin/python benchmarks/ground_truth.py --size 256 --out docs/ground-truth.md
"""
import argparse
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from report import command_line, publish  # noqa: E402

from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from dynpaint_addon.core.shape import decode_normal_map, normals_from_height_px  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from testkit.render3d import emission_material  # noqa: E402

# (name, kind, location, size): heights in image widths, the image spans [-0.5, 0.5]²
OBJECTS = [
    ("sphere", "sphere", (-0.22, 0.2, 0.12), 0.12),
    ("torus", "torus", (0.22, 0.22, 0.035), (0.1, 0.035)),
    ("low box", "box", (-0.25, -0.22, 0.025), (0.1, 0.08, 0.05)),
    ("tall box", "box", (0.02, -0.05, 0.1), (0.06, 0.06, 0.2)),
    ("wide box", "box", (0.25, -0.25, 0.06), (0.12, 0.1, 0.12)),
    ("plate (overhang)", "box", (0.0, 0.3, 0.15), (0.14, 0.1, 0.01)),
]
# What 2.5D cannot do, measured alone: a floating plate (the height map fills the space under
# it) and a pole one pixel thin at 256² (a march with steps longer than a pixel can step over).
LIMITS = {
    "floating plate": [("plate", "box", (0.05, 0.1, 0.15), (0.2, 0.16, 0.01))],
    "thin pole": [("pole", "pole", (0.1, 0.1, 0.125), (0.002, 0.25))],
}
SUNS = [(15, 30), (30, 135), (45, 220), (60, 300)]   # (elevation, azimuth) in degrees


def build_scene(size, objects=OBJECTS):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=4.0)
    ground = bpy.context.object
    ground.name = "ground"
    for i, (name, kind, loc, dims) in enumerate(objects, start=1):
        if kind == "pole":
            bpy.ops.mesh.primitive_cylinder_add(radius=dims[0], depth=dims[1], location=loc,
                                                vertices=16)
        elif kind == "sphere":
            bpy.ops.mesh.primitive_uv_sphere_add(radius=dims, location=loc, segments=96,
                                                 ring_count=48)
            bpy.ops.object.shade_smooth()
        elif kind == "monkey":        # Suzanne, smooth, her face toward the camera (+z)
            bpy.ops.mesh.primitive_monkey_add(size=dims, location=loc,
                                              rotation=(-math.pi / 2, 0.0, 0.0))
            bpy.context.object.modifiers.new("smooth", "SUBSURF").levels = 2
            bpy.ops.object.shade_smooth()
        elif kind == "torus":
            bpy.ops.mesh.primitive_torus_add(major_radius=dims[0], minor_radius=dims[1],
                                             location=loc, major_segments=96, minor_segments=32)
            bpy.ops.object.shade_smooth()
        else:
            bpy.ops.mesh.primitive_cube_add(size=1.0, location=loc)
            bpy.context.object.scale = dims
        obj = bpy.context.object
        obj.name = name
        obj.pass_index = i
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 1.0
    cam.location = (0.0, 0.0, 5.0)
    scene.camera = cam
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    exact_render_settings(scene, "cycles")
    scene.render.film_transparent = False
    return scene


def assign(material):
    for obj in bpy.context.scene.objects:
        if obj.type == "MESH":
            obj.data.materials.clear()
            obj.data.materials.append(material)


def render_to(scene, path):
    output_settings(scene, path)
    bpy.ops.render.render(write_still=True)
    return read_image(path).pixels


def render_maps(scene, folder):
    """Height (world z), world normal and object index at each pixel centre."""
    def position(nt):
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        return geo.outputs["Position"]

    def normal(nt):
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        return geo.outputs["Normal"]

    def index(nt):
        info = nt.nodes.new("ShaderNodeObjectInfo")
        return info.outputs["Object Index"]
    scene.world = None     # no sky light: a world's Background node would add ≈0.05 of grey
    maps = {}
    for name, fn in (("position", position), ("normal", normal), ("index", index)):
        assign(emission_material(name, fn))
        maps[name] = render_to(scene, os.path.join(folder, f"{name}.exr"))
    return (maps["position"][..., 2].astype(np.float32), maps["normal"][..., :3],
            np.rint(maps["index"][..., 0]).astype(int))


def render_truth(scene, folder, elevation, azimuth):
    """Cycles, hard sun of strength π, white diffuse, direct light only → N·L × visibility."""
    mat = bpy.data.materials.new("white")
    nt = mat.node_tree
    nt.nodes.clear()
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(bsdf.outputs[0], out.inputs[0])
    assign(mat)
    for obj in [o for o in scene.objects if o.type == "LIGHT"]:
        bpy.data.objects.remove(obj)
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.data.energy = math.pi
    sun.data.angle = 0.0
    direction = sun_direction(elevation, azimuth)
    from mathutils import Vector
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = Vector(direction).to_track_quat("Z", "Y")
    scene.cycles.max_bounces = 0
    # the sun is hard and the pixel filter 0.01 px, so samples only remove light-sampling
    # noise; edges stay as sharp as the pixel grid
    scene.cycles.samples = 64
    return render_to(scene, os.path.join(folder, f"truth_{elevation}_{azimuth}.exr"))[..., 0]


def sun_direction(elevation, azimuth):
    e, a = math.radians(elevation), math.radians(azimuth)
    return (math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e))


def cast_shadow(value, ndl):
    """Pixels that face the sun yet receive less than half of N·L."""
    return (ndl > 0.05) & (value < 0.5 * ndl)


QUALITY_LEVELS = ("draft", "preview", "final", "reference")


def level_errors(size=256, offset=0.01, objects=OBJECTS):
    """Each quality level of the bake (bake.bake) against truth, averaged over SUNS:
    [(level, shape, mean |t − truth|, cast-shadow IoU)] (for docs/shadow-quality.md)."""
    from dynpaint_addon.core.bake import bake
    folder = tempfile.mkdtemp()
    scene = build_scene(size, objects)
    z, nworld, _ = render_maps(scene, folder)
    n_height = normals_from_height_px((z * size).astype(np.float32))
    n_map = decode_normal_map(ImageData((nworld + 1) / 2, 32).rgb()).astype(np.float32)
    acc = {}
    for elevation, azimuth in SUNS:
        truth = render_truth(scene, folder, elevation, azimuth)
        light = Light("sun", sun_direction(elevation, azimuth))
        ndl_true = np.clip(nworld @ np.array(sun_direction(elevation, azimuth)), 0, 1)
        for level in QUALITY_LEVELS:
            for label, t in (
                    ("height map", bake(n_height, light, offset, level,
                                        heights_px=(z * size).astype(np.float32))),
                    ("normal map", bake(n_map, light, offset, level,
                                        slopes=-n_map[..., :2] / n_map[..., 2:3]))):
                a, b = cast_shadow(truth, ndl_true), cast_shadow(t, ndl_true)
                iou = (a & b).sum() / max((a | b).sum(), 1)
                acc.setdefault((level, label), []).append((float(np.abs(t - truth).mean()), iou))
    return [(level, label, float(np.mean([e for e, _ in v])), float(np.mean([i for _, i in v])))
            for (level, label), v in acc.items()]


def evaluate(objects, size, offset, steps, images=None):
    """Bake against truth for every sun → (overall rows, per-object rows)."""
    folder = tempfile.mkdtemp()
    scene = build_scene(size, objects)
    z, nworld, index = render_maps(scene, folder)
    n_height = normals_from_height_px(z * size)
    n_map = decode_normal_map(ImageData((nworld + 1) / 2, 32).rgb())
    names = ["ground"] + [o[0] for o in objects]
    rows, overall = [], []
    for elevation, azimuth in SUNS:
        truth = render_truth(scene, folder, elevation, azimuth)
        light = Light("sun", sun_direction(elevation, azimuth))
        ndl_true = np.clip(nworld @ np.array(sun_direction(elevation, azimuth)), 0, 1)
        t_h = cos_theta_shadow(n_height, light, offset, steps, heights_px=z * size)
        t_n = cos_theta_shadow(n_map, light, offset, steps,
                               slopes=-n_map[..., :2] / n_map[..., 2:3])
        for label, t in (("height map", t_h), ("normal map", t_n)):
            err = np.abs(t - truth)
            a, b = cast_shadow(truth, ndl_true), cast_shadow(t, ndl_true)
            iou = (a & b).sum() / max((a | b).sum(), 1)
            overall.append((elevation, azimuth, label, float(err.mean()), float(iou)))
            for i, name in enumerate(names):
                mask = index == i
                if mask.any():
                    rows.append((name, elevation, azimuth, label, float(err[mask].mean())))
        if images and (elevation, azimuth) == SUNS[0]:
            os.makedirs(os.path.dirname(images), exist_ok=True)
            strip = np.concatenate([np.clip(truth, 0, 1), t_h, t_n,
                                    np.clip(z / max(z.max(), 1e-6), 0, 1)], axis=1)
            write_png(images, strip ** (1 / 2.2))
    return overall, rows, names


def sun_table(overall):
    lines = ["| sun elevation / azimuth | shape | mean \\|t − truth\\| | cast-shadow IoU |",
             "|---|---|---|---|"]
    for e, a, label, err, iou in overall:
        lines.append(f"| {e}° / {a}° | {label} | {err:.4f} | {iou:.3f} |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--offset", type=float, default=0.01, help="d in image widths")
    ap.add_argument("--steps", type=int, default=256)
    ap.add_argument("--out", help="Markdown report")
    ap.add_argument("--images", help="folder for the small pictures of the report")
    args = ap.parse_args(argv)
    pic = os.path.join(args.images, "ground-truth-15deg.png") if args.images else None
    overall, rows, names = evaluate(OBJECTS, args.size, args.offset, args.steps, pic)
    command = command_line(__file__, argv)
    lines = ["# The cos-θ bake against 3D ground truth (issue 4)", "",
             f"`{command}` — a {args.size}² orthographic view of the scene in "
             f"`benchmarks/ground_truth.py` (sphere, torus, three boxes, a floating plate on a "
             f"ground plane); truth = Cycles, hard sun (angle 0), white diffuse, direct light "
             f"only, so a lit pixel reads N·L. Bake: the numpy core, d = {args.offset} image "
             f"widths, K = {args.steps}. Cast shadow: a pixel facing the sun that gets less than "
             f"half of N·L.", "", "## Per sun, whole image", ""] + sun_table(overall)
    lines += ["", "## Per object (mean |t − truth| over its pixels)", "",
              "| object | " + " | ".join(f"{e}°/{a}° height | normal" for e, a in SUNS) + " |",
              "|---|" + "---|---|" * len(SUNS)]
    for name in names:
        vals = []
        for e, a in SUNS:
            for label in ("height map", "normal map"):
                hit = [r[4] for r in rows if r[0] == name and (r[1], r[2], r[3]) == (e, a, label)]
                vals.append(f"{hit[0]:.4f}" if hit else "–")
        lines.append(f"| {name} | " + " | ".join(vals) + " |")
    if pic:
        lines += ["", "Truth, height-map bake, normal-map bake, height map (15° sun):", "",
                  "![truth, height-map bake, normal-map bake, height map](img/ground-truth-15deg.png)"]
    lines += ["", "Reading it: lit ground and smooth shapes match within a few hundredths; the "
              "height-map bake's errors sit on box edges (a one-pixel wall gives a steep normal "
              "on its rim) and within d of them (the cos-θ term's translucent look, by design). "
              "A normal map knows no heights across vertical walls: its bakes miss the boxes' "
              "cast shadows (IoU 0.1–0.3) while shading their tops exactly.",
              "", "## What 2.5D cannot do, measured", "",
              "Each scene below holds only the named object on the ground.", ""]
    notes = {"floating plate": "The height map fills the space under the plate, so its shadow "
                               "is that of a solid block reaching down to the ground: longer "
                               "and wrongly placed at low suns (IoU 0.28 at 15°, 0.82 at 60°). "
                               "A normal map sees only a flat top and casts nothing.",
             "thin pole": "A pole one pixel thin barely reaches the height map's pixel centres, "
                          "so no bake sees it: its cast shadow is lost (IoU 0 for most suns); "
                          "the mean error stays small only because the shadow is thin."}
    for title, objects in LIMITS.items():
        lim, _, _ = evaluate(objects, args.size, args.offset, args.steps)
        lines += [f"### {title}", "", notes[title], ""] + sun_table(lim) + [""]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
