"""A .blend file as an artist saves it after Add › Dynamic Painting and Add Light Turntable
(issue 64): the scene `dynpaint turntable` renders of a recipe (headless.build_turntable_scene),
saved — so `dynpaint animation` of the file gives `turntable`'s frames of the recipe, bit for
bit, when the reopened file bakes each frame's own shadows."""


def save_turntable_blend(recipe_path, blend, frames):
    """Build the recipe's turntable scene in this process's Blender and save it at `blend`
    (its images stay where the recipe has them, linked by path)."""
    import bpy
    from dynpaint_addon.blender.headless import build_turntable_scene
    from dynpaint_addon.inputs.recipe import load_recipe

    build_turntable_scene(load_recipe(str(recipe_path)), frames)
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
