"""The painting as one OSL Script node for Cycles, generated from the graph description.

With the OSL shader the cos-θ term can be computed in the shader (no bake: exact per pixel,
per frame, for any light). Its inputs are driven exactly like the node material's (shader
backend): parameters from the material's settings, lights from their transforms. OSL reads
images from files, so images that live only inside Blender (numpy-prepared copies) are
written to a cache folder as EXR first.
"""
import os
import sys

import numpy as np

import bpy

from ... import params
from ...inputs.imageio import write_exr
from ...nodegraph import osl_codegen
from ...nodegraph.derived_inputs import march_bounds
from ...nodegraph.pipeline_graph import describe
from ..bake.shadow_images import bake_shape
from ..nodes.shader_backend import (SETTINGS, ShaderBackend, drive_location, drive_property,
                                        drive_sun_direction, light_strength_expression)
from ..state.images import has_alpha

TEXT_PREFIX = "DP OSL "


def _cycles_osl():
    """Cycles' OSL helpers; their `oslquery` lives in Blender's bundled site-packages."""
    bundled = os.path.join(bpy.utils.system_resource("PYTHON"), "lib",
                           f"python{sys.version_info[0]}.{sys.version_info[1]}", "site-packages")
    if os.path.isdir(bundled) and bundled not in sys.path:
        sys.path.append(bundled)
    from cycles import osl
    return osl


def cache_folder():
    """Where image copies for OSL go: next to the saved .blend, else the temp folder."""
    base = bpy.path.abspath("//dynpaint_cache") if bpy.data.filepath else \
        os.path.join(bpy.app.tempdir or "/tmp", "dynpaint_cache")
    os.makedirs(base, exist_ok=True)
    return base


def image_file(img, name):
    """A file OSL can read holding `img`'s pixels → (path, srgb: decode sRGB in the shader)."""
    srgb_codes = img.colorspace_settings.name == "sRGB"     # the file holds sRGB codes
    src = bpy.path.abspath(img.filepath) if img.filepath else ""
    # OIIO premultiplies the colour of files with straight alpha (PNG) as it reads them; the
    # painting uses colour and alpha apart (channel packed): such images go through an EXR.
    if img.source == "FILE" and img.packed_file is None and os.path.isfile(src) \
            and not has_alpha(img):
        return src, int(srgb_codes)          # OIIO reads the file's codes (8- or 16-bit)
    # byte buffers hold the file's sRGB codes, float buffers (16-bit files too) linear values
    srgb = int(srgb_codes and not img.is_float)
    w, h = img.size
    px = np.empty(w * h * img.channels, np.float32)
    img.pixels.foreach_get(px)
    path = os.path.join(cache_folder(), f"{bpy.path.clean_name(name)}.exr")
    write_exr(path, px.reshape(h, w, img.channels))
    return path, srgb


# Cycles' OSL texture() counted t down the image up to Blender 5.1, up it from 5.2 on
# (blender-notes.md: the images came out upside down)
TEXTURE_T_DOWN = bpy.app.version < (5, 2, 0)


def build_osl_tree(mat, features, images, lights, march, p, tag=""):
    """Replace the material's tree by the OSL Script node (+ output), driven and compiled
    (p: the painting's parameters, for the march's bounds; tag: in the names of the image
    files, a moving painting's drawing)."""
    src = osl_codegen.generate(describe(features), features, march=march,
                               texture_t_down=TEXTURE_T_DOWN)
    text = bpy.data.texts.get(TEXT_PREFIX + mat.name) or bpy.data.texts.new(TEXT_PREFIX + mat.name)
    text.from_string(src)
    tree = mat.node_tree
    script = tree.nodes.new("ShaderNodeScript")
    script.mode = "INTERNAL"
    script.script = text
    script.label = "Dynamic Painting (OSL)"
    messages = []
    _cycles_osl().update_script_node(script, lambda kind, msg: messages.append(msg))
    if "Color" not in script.outputs:
        raise RuntimeError("the OSL shader did not compile: " + "; ".join(messages))
    for sock in script.inputs:
        name = sock.identifier
        if name.startswith("p_"):
            drive_property(sock, "MATERIAL", mat, f"{SETTINGS}.{SETTING_OF_INPUT[name]}")
        elif name.endswith("_file"):
            channel = name[:-5]
            path, srgb = image_file(images[channel], f"{mat.name} {channel}{tag}")
            sock.default_value = path
            script.inputs[channel + "_srgb"].default_value = srgb
            width, height = images[channel].size
            script.inputs[channel + "_width"].default_value = width
            script.inputs[channel + "_height"].default_value = height
        elif name.startswith("light") and name.endswith("_world"):
            i = int(name[5:-6]) - 1
            obj = lights[i]
            _drive_vector(script, sock, obj, features.lights[i])
        elif name.startswith("light") and name.endswith("_color"):
            obj = lights[int(name[5:-6]) - 1]
            for c in range(3):
                drive_property(sock, "LIGHT", obj.data, f"color[{c}]", index=c)
        elif name.startswith("light") and name.endswith("_strength"):
            i = int(name[5:-9]) - 1
            drive_property(sock, "LIGHT", lights[i].data, "energy",
                           expression=light_strength_expression(features.lights[i]))
    coords = tree.nodes.new("ShaderNodeTexCoord")
    tree.links.new(coords.outputs["UV"], script.inputs["painting_uv"])
    coords.location = (-600, 200)
    if march:
        _set_relief_bounds(mat, script, p)
    ShaderBackend(mat, images, lights).output(
        tree, None, {"rgb": script.outputs["Color"], "alpha": script.outputs["Alpha"]})
    script.location = (-300, 0)
    return script


# the shader's parameter name (osl_codegen.param_name) → the setting it is driven by
SETTING_OF_INPUT = {osl_codegen.param_name(param.path, index): param.setting(index)
                    for param in params.PARAMS for index in param.components}


def _drive_vector(script, sock, obj, kind):
    """A vector socket ← the light's world direction (sun) or position (point), via drivers on
    a helper Combine XYZ (drivers on a Script node's vector sockets work the same way)."""
    tree = script.id_data
    comb = tree.nodes.new("ShaderNodeCombineXYZ")
    comb.label = f"{obj.name} (world)"
    (drive_sun_direction if kind == "sun" else drive_location)(comb, obj)
    tree.links.new(comb.outputs[0], sock)
    comb.location = (-600, -200 * len([n for n in tree.nodes if n.bl_idname == "ShaderNodeCombineXYZ"]))


def _set_relief_bounds(mat, script, p):
    """The march's global bounds (derived_inputs.march_bounds), from the numpy copy of the
    shape the material also uses (p: the painting's parameters)."""
    bounds = march_bounds(*bake_shape(mat, p))
    for name, value in bounds.items():
        if name in script.inputs:
            script.inputs[name].default_value = value
