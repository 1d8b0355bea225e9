"""Write tests/data/painting_v<version>.blend: a tiny painting saved by this version of the
add-on (images packed, a keyframed light, shadows on). Kept in the repo so that later versions
are tested against files made by earlier ones (tests/test_saved_files.py). Run it once per
release; never regenerate an old fixture.

    .venv/bin/python tests/data/make_old_version_fixture.py
"""
import os
import sys
import tempfile
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [REPO, os.path.dirname(HERE)]

import bpy  # noqa: E402

from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights  # noqa: E402
from parity_recipes import make_recipe, write_images  # noqa: E402


def main():
    version = tomllib.load(open(os.path.join(REPO, "blender_manifest.toml"), "rb"))["version"]
    paths = write_images(tempfile.mkdtemp())
    plane, mat = headless.build_recipe_scene(make_recipe("shadows_height", paths))
    scene = bpy.context.scene
    sun = linked_lights(mat, scene)[0]
    sun.rotation_mode = "XYZ"
    for frame, z in ((1, 0.0), (10, 2.0)):
        sun.rotation_euler = (0.7, 0.1, z)
        sun.keyframe_insert("rotation_euler", frame=frame)
    scene.frame_end = 10
    scene.frame_set(4)
    exact_render_settings(scene, "cycles")
    for img in bpy.data.images:
        if img.source == "FILE":
            img.pack()
    out = os.path.join(HERE, f"painting_v{version}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=out, compress=True)
    print(f"wrote {out} ({os.path.getsize(out) // 1024} KiB)")


if __name__ == "__main__":
    main()
