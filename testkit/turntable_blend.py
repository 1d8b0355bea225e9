"""A .blend file as an artist saves it after Add › Dynamic Painting and Add Light Turntable
(issue 64): a recipe's painting with its first Sun turning once, framed pixel for pixel as
`dynpaint turntable` frames it — so `dynpaint animation` of the file gives `turntable`'s
frames of the recipe, bit for bit, when each frame bakes its own shadows."""


def save_turntable_blend(recipe_path, blend, frames):
    """Build the recipe's turntable scene in this process's Blender and save it at `blend`
    (its images stay where the recipe has them, linked by path)."""
    import bpy
    from dynpaint_addon.blender import headless
    from dynpaint_addon.blender.scenes import turntable
    from dynpaint_addon.blender.state.frames import painting_size
    from dynpaint_addon.inputs.recipe import load_recipe

    recipe = load_recipe(str(recipe_path))
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    headless.fit_camera(scene, plane, *painting_size(mat))
    headless.video_render_settings(scene, "cycles", exact=True)
    light, elevation, azimuth, radius = headless.turntable_light(recipe.lights, mat, scene)
    turntable.add_light_turntable(bpy.context, mat, light, "SUN", 1, frames, elevation,
                                  radius, azimuth, False)
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
