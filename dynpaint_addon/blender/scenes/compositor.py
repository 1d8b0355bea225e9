"""The Dynamic Painting compositor node group: build it, add it to a scene, composite a recipe.

The group is generated from the same description as the material (pipeline_graph.describe)
with the compositor backend; it relights images without any 3D scene.
"""
import os

import numpy as np

import bpy

from ... import params
from ...core.input_rules import pixel_role
from ...core.pipeline import shadow_term, shape_normals
from ...inputs.imageio import read_image, write_exr
from ...inputs.recipe import Recipe
from ...nodegraph.derived_inputs import make_derived, prepare
from ...nodegraph.features import Features
from ...nodegraph.pipeline_graph import describe
from ..nodes import build
from ..nodes.compositor_backend import INPUT_OF, CompositorBackend, input_name, param_inputs
from ..state.images import prepare_channel_image
from ..state.lights import painting_lights
from ..state.painting_state import image_source
from .painting_scene import output_settings

GROUP_NAME = "Dynamic Painting"


def compositor_tree(scene):
    """The node group the scene's compositor runs, or None. Blender 5.3 keeps it on the
    scene's active compositor effect; Scene.compositing_node_group, 5.0's way, reads that
    effect there but is deprecated, to go in 6.0 (docs/blender-notes.md)."""
    effects = getattr(scene, "compositor_effects", None)
    if effects is None:
        return scene.compositing_node_group
    return effects.active.node_group if effects.active else None


def set_compositor_tree(scene, tree):
    """Make `tree` the node group the scene's compositor runs: on 5.3 the active effect's, a
    new effect where the scene has none (as compositing_node_group's setter does there)."""
    effects = getattr(scene, "compositor_effects", None)
    if effects is None:
        scene.compositing_node_group = tree
    else:
        (effects.active or effects.new(name="Scene Effect")).node_group = tree


def build_group(features, name=GROUP_NAME):
    """A compositor node group for `features` (a new one; an existing name gets a suffix)."""
    group = bpy.data.node_groups.new(name, "CompositorNodeTree")
    backend = CompositorBackend(features.silhouette, features.lights, features.size)
    build.build(group, describe(features), backend)
    group["dp_features"] = features.key()
    return group


def set_group_inputs(node, recipe, p=None):
    """Feed a group node the recipe's parameter values and lights (painting frame)."""
    p = p or recipe.params
    for sock in node.inputs:
        name = sock.name
        if name.startswith("Light "):
            i, what = name.split(" ", 2)[1:]
            light = recipe.lights[int(i) - 1]
            if what in ("Direction", "Position"):
                sock.default_value = light.vector
            elif what == "Color":
                sock.default_value = (*light.colour, 1.0)
            elif what == "Strength":
                sock.default_value = light.strength
    for param in params.PARAMS:
        if param.kind != "enum":
            for name, value in param_inputs(param, getattr(getattr(p, param.section), param.key)):
                if name in node.inputs:
                    node.inputs[name].default_value = value


# The derived images (nodegraph/derived_inputs.py) that replace a group input: a normal map in
# the standard convention, masks as read, the pre-blurred height through the Shape input (INPUT_OF), E and B
# straight (the group premultiplies them itself).
GROUP_DERIVED = ("shape", "height", "environment", "background", "background_sharp",
                 "transparency", "gloss")


def _straight(rgba):
    a = rgba[..., 3:4]
    return np.concatenate([np.where(a > 0, rgba[..., :3] / np.where(a > 0, a, 1), 0), a], -1)


def _numpy_prepared(recipe, plan, folder):
    """The derived images the group takes as inputs (plan: derived_inputs.prepare's), as float
    EXRs → {group channel: image}."""
    p = recipe.params
    plan = [d for d in plan if d.channel in GROUP_DERIVED]
    made, _ = make_derived(plan, lambda c: read_image(recipe.images[c]),
                           lambda c: pixel_role(c, p))
    prepared = {}
    for item in plan:
        channel, rgba = item.channel, made[item.channel]
        if item.same_as and item.same_as in prepared:
            prepared[channel] = prepared[item.same_as]
            continue
        if rgba is None:            # the input as it is
            continue
        path = os.path.join(folder, f"prepared_{channel}.exr")
        write_exr(path, _straight(rgba) if channel in ("environment", "background",
                                                       "background_sharp") else rgba)
        img = bpy.data.images.load(path, check_existing=False)
        img.colorspace_settings.name = "Non-Color"
        img.alpha_mode = "CHANNEL_PACKED"
        prepared[INPUT_OF.get(channel, channel)] = img
    return prepared


def composite_recipe(recipe, out, shadow_folder=None):
    """Relight a recipe's images in the compositor only → the written file (tests, benchmark).

    Shadows, when on, are baked with the numpy core into EXR files the group reads.
    """
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    folder = shadow_folder or os.path.dirname(os.path.abspath(out))
    images = {}
    for channel, path in recipe.images.items():
        img = bpy.data.images.load(os.path.abspath(path), check_existing=True)
        prepare_channel_image(img, channel)
        images[channel] = img
    f, plan = prepare(recipe.params, {c: image_source(img) for c, img in images.items()},
                      [lt.kind for lt in recipe.lights])
    images.update(_numpy_prepared(recipe, plan, folder))
    group = build_group(f)
    tree = bpy.data.node_groups.new("Composite", "CompositorNodeTree")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    set_compositor_tree(scene, tree)
    node = tree.nodes.new("CompositorNodeGroup")
    node.node_tree = group
    for channel, img in images.items():
        src = tree.nodes.new("CompositorNodeImage")
        src.image = img
        if input_name(channel) in node.inputs:
            tree.links.new(src.outputs["Image"], node.inputs[input_name(channel)])
    if recipe.params.shadows.enabled:
        n, z, slopes = shape_normals(read_image(recipe.images["shape"]), recipe.params)
        for i, light in enumerate(recipe.lights):
            t = shadow_term(n, z, slopes, light, recipe.params)
            path = os.path.join(folder, f"shadow_{i + 1}.exr")
            write_exr(path, np.repeat(t[..., None], 3, axis=2))
            img = bpy.data.images.load(path, check_existing=False)
            img.colorspace_settings.name = "Non-Color"
            src = tree.nodes.new("CompositorNodeImage")
            src.image = img
            tree.links.new(src.outputs["Image"], node.inputs[f"Light {i + 1} Shadow"])
    set_group_inputs(node, recipe)
    tree.links.new(node.outputs["Image"], tree.nodes.new("NodeGroupOutput").inputs["Image"])
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x, r.resolution_y = images["shape"].size
    r.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    r.dither_intensity = 0.0
    output_settings(scene, out)
    bpy.ops.render.render(write_still=True)
    return out


def features_for_options(kind, suns, points, shadows, specular, channels, silhouette):
    """Features of a group chosen by hand (the operator's options)."""
    p = params.defaults()
    p.shape.kind, p.shadows.enabled, p.specular.enabled = kind, shadows, specular
    p.transparency.amount = "auto" if "transparency" in channels else (
        1.0 if {"environment", "background"} & set(channels) else "auto")
    lights = ["sun"] * suns + ["point"] * points
    chans = {"shape", "dark", "bright", *channels}
    return Features.from_params(p, chans, lights, (1024, 1024), {silhouette} if silhouette else (),
                                {c: (1024, 1024) for c in chans})


def add_group_node(scene, group):
    """Put a group node into the scene's compositor (made if the scene has none) → the node."""
    tree = compositor_tree(scene)
    if tree is None:
        tree = bpy.data.node_groups.new("Compositor", "CompositorNodeTree")
        tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        set_compositor_tree(scene, tree)
        out = tree.nodes.new("NodeGroupOutput")
        out.location = (600, 0)
    node = tree.nodes.new("CompositorNodeGroup")
    node.node_tree = group
    node.width = 240
    for n in tree.nodes:
        n.select = False
    node.select = True
    tree.nodes.active = node
    outs = [n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"]
    if outs and not outs[0].inputs[0].is_linked:
        tree.links.new(node.outputs["Image"], outs[0].inputs[0])
    return node


def wire_painting(scene, node, mat, state):
    """Feed a group node built for a painting its images, settings and current lights
    (state: the painting's PaintingState)."""
    s = mat.dynamic_painting
    tree = compositor_tree(scene)
    images = dict(state.images)
    for item in s.derived:        # numpy-prepared copies: height, blurred E/B; the frame a
        #                           moving painting shows (§16: remade as the frame changes)
        if item.image and (item.channel in GROUP_DERIVED or (state.frame and
                                                             item.channel in images)):
            images[INPUT_OF.get(item.channel, item.channel)] = item.image
    for i, item in enumerate(s.lights):
        if item.shadow is not None:
            images[f"Light {i + 1} Shadow"] = item.shadow
    for k, (channel, img) in enumerate(images.items()):
        name = channel if channel.startswith("Light ") else input_name(channel)
        if name in node.inputs:
            src = tree.nodes.new("CompositorNodeImage")
            src.image = img
            src.location = (node.location.x - 300, node.location.y - 120 * k)
            tree.links.new(src.outputs["Image"], node.inputs[name])
    set_group_inputs(node, Recipe(state.params, painting_lights(mat, scene)))
