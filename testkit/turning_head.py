"""A head that turns and blinks, rendered from 3D by Cycles frame by frame (issue 31): the
true heights, normals and silhouette of every frame, for the animated sample
(sample_scenes/make_samples.py) and the temporal-stability benchmark
(benchmarks/frames_stability.py).

Blender's Suzanne (subdivided, facing the viewer) turns about the vertical axis, ±`turn`
degrees over one cycle of `frames`; its eyeballs sink into the head for a blink (a shape key,
full at `blink` frames, half on the frames beside). A small box stands still beside it (a part
of the drawing that never changes). Orthographic camera looking down −Z: world normals are the
painting's (§0). Deterministic: one sample at each pixel's centre, no randomness.
"""
import math
import os
import tempfile

import numpy as np

from dynpaint_addon.core.laplace import graph_parts
from dynpaint_addon.inputs.imageio import read_image
from testkit.render3d import cycles_to_exr, emission_material, ortho_camera


def _eye_vertices(mesh):
    """Indices of the vertices of Suzanne's two eyeballs: her loose parts other than the
    largest (the head)."""
    edges = np.empty(len(mesh.edges) * 2, np.int64)
    mesh.edges.foreach_get("vertices", edges)
    labels, _ = graph_parts(len(mesh.vertices), edges[0::2], edges[1::2])
    head = np.argmax(np.bincount(labels))
    return np.flatnonzero(labels != head)


def render_turning_head(size=256, frames=24, turn=25.0, blink=(10, 11), box=True,
                        sphere=False):
    """sphere: also a ball that never moves, at the lower left (a still part whose shading
    shows its own relief's shadows: benchmarks/frames_stability.py's render flicker).
    → dict of y-up float arrays per frame: 'height' (frames, H, W) in image widths above the
    lowest point of the head's range, 'normal' (frames, H, W, 3) unit vectors (flat (0, 0, 1)
    outside), 'alpha' (frames, H, W) 0 … 1 (pixel-centre coverage: 0 or 1)."""
    import bpy
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_monkey_add(size=2.0)
    head = bpy.context.object
    head.rotation_mode = "XYZ"
    eyes = _eye_vertices(head.data)
    head.shape_key_add(name="Basis")
    key = head.shape_key_add(name="Blink", from_mix=False)
    for i in eyes:                               # Suzanne's front is −Y: back is +Y
        key.data[i].co.y += 0.3
    mod = head.modifiers.new("smooth", "SUBSURF")
    mod.levels = mod.render_levels = 2
    bpy.ops.object.shade_smooth()
    parts = [head]
    if box:
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(1.25, -1.15, -0.45))
        parts.append(bpy.context.object)
    if sphere:
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(-1.3, -1.3, -0.6),
                                             segments=64, ring_count=32)
        bpy.ops.object.shade_smooth()
        parts.append(bpy.context.object)
    z_low = -1.0                                 # heights are measured from here (world units)
    width = 3.4                                  # the camera's view: one image width

    def height_nodes(nt):
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        xyz = nt.nodes.new("ShaderNodeSeparateXYZ")
        nt.links.new(geo.outputs["Position"], xyz.inputs[0])
        return xyz.outputs["Z"]

    def normal_nodes(nt):
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        return geo.outputs["Normal"]
    materials = {"height": emission_material("height", height_nodes),
                 "normal": emission_material("normal", normal_nodes)}
    for obj in parts:
        obj.data.materials.append(materials["height"])
    ortho_camera(scene, width, (0, -0.1, 10))
    cycles_to_exr(scene, size, 1)
    r = scene.render
    r.film_transparent = True
    r.filter_size = 0.01                         # one sample at each pixel's centre
    scene.cycles.pixel_filter_type = "BOX"
    out = {"height": [], "normal": [], "alpha": []}
    with tempfile.TemporaryDirectory() as tmp:
        for f in range(frames):
            angle = math.radians(turn) * math.sin(2 * math.pi * f / frames)
            head.rotation_euler = (-math.pi / 2, angle, 0)  # faces +Z (the viewer), turned
            key.value = 1.0 if f in blink else 0.5 if any(abs(f - b) == 1 for b in blink) else 0.0
            for what, mat in materials.items():
                for obj in parts:
                    obj.material_slots[0].material = mat
                r.filepath = os.path.join(tmp, f"{what}_{f}.exr")
                bpy.ops.render.render(write_still=True)
                px = read_image(r.filepath).pixels
                if what == "height":
                    alpha = np.clip(px[..., 3], 0, 1)
                    out["alpha"].append(alpha)
                    out["height"].append(np.where(alpha > 0, (px[..., 0] - z_low) / width, 0))
                else:
                    n = np.where(px[..., 3:4] > 0, px[..., :3], [0, 0, 1])
                    out["normal"].append(n / np.linalg.norm(n, axis=-1, keepdims=True))
    return {k: np.asarray(v, np.float32) for k, v in out.items()}
