"""Render a recipe with EEVEE or Cycles in background Blender (the `render` command).

The scene is built exactly as the add-on's Add › Dynamic Painting builds it, then framed by an
orthographic camera pixel for pixel, so the result can be compared with the numpy core.
"""
import os
import time

import bpy

from . import register_once, scene as S


def build_recipe_scene(recipe, size=1.0):
    """Empty scene → the recipe's painting, lights and an exact camera → (plane, material)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    register_once()
    context = bpy.context
    plane, mat, _ = S.create_painting(context, recipe.images, recipe.params, recipe.lights,
                                      name=recipe.name or "Dynamic Painting", size=size,
                                      default_sun=False)
    S.exact_camera(context.scene, plane)
    context.view_layer.update()
    return plane, mat


def render_recipe(recipe, engine, out, frame=None):
    """Render the recipe's painting to `out` (.exr linear float or .png) → seconds rendering."""
    plane, mat = build_recipe_scene(recipe)
    scene = bpy.context.scene
    S.exact_render_settings(scene, engine)
    S.output_settings(scene, out)
    if frame is not None:
        scene.frame_set(frame)
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    t = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t
