"""Saved files and render farms (issue 7): a .blend with an animated painting, reopened in a
fresh background process, renders the same pixels (Cycles, bit-exact); a chunk of frames
rendered on its own equals the same frames of one sequential animation render."""
import os
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("bpy")

from dynpaint_addon.inputs.imageio import read_image  # noqa: E402

from conftest import REPO  # noqa: E402
from parity_recipes import write_images  # noqa: E402

PRELUDE = f"""
import os, sys
sys.path.insert(0, {REPO!r})
import bpy
from dynpaint_addon import blender
from dynpaint_addon.blender import handlers, headless
from dynpaint_addon.blender.state import status
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings
from dynpaint_addon.blender.scenes.turntable import add_light_turntable
blender.register_once()
"""

AUTHOR = PRELUDE + """
from dynpaint_addon.core.lights import Light
from parity_recipes import make_recipe
images, out = sys.argv[1], sys.argv[2]
paths = {n.rsplit(".", 1)[0] if n.endswith(".png") else n: os.path.join(images, n)
         for n in os.listdir(images)}
recipe = make_recipe("shadows_height", paths)
recipe.lights.append(Light("point", (-0.3, -0.2, 0.3), (0.6, 0.7, 1.0), 0.5, "Fill"))
plane, mat = headless.build_recipe_scene(recipe)
scene = bpy.context.scene
sun = bpy.data.objects["Sun"]
add_light_turntable(bpy.context, mat, sun, "SUN", 1, 6, 0.6, 1.0, 2.0)
fill = bpy.data.objects["Fill"]
for frame, x in ((1, -0.3), (6, 0.35)):              # a keyframed point light too
    fill.location.x = x
    fill.keyframe_insert("location", index=0, frame=frame)
exact_render_settings(scene, "cycles")
output_settings(scene, os.path.join(out, "x.exr"))
scene.render.filepath = os.path.join(out, "seq_####")
bpy.ops.render.render(animation=True)               # the sequential render, frames 1..6
scene.frame_set(3)
scene.render.filepath = os.path.join(out, "before.exr")
bpy.ops.render.render(write_still=True)
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "linked.blend"))
bpy.ops.file.pack_all()
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "packed.blend"))
print("AUTHORED", len(mat.node_tree.animation_data.drivers))
"""

REOPEN = PRELUDE + """
blend, out, tag = sys.argv[1], sys.argv[2], sys.argv[3]
bpy.context.preferences.filepaths.use_scripts_auto_execute = False
bpy.ops.wm.open_mainfile(filepath=blend)
scene = bpy.context.scene
mat = next(m for m in bpy.data.materials if m.dynamic_painting.is_painting)
drivers = mat.node_tree.animation_data.drivers
assert all(d.is_valid and d.driver.is_valid for d in drivers), "a driver broke"
assert scene.frame_current == 3
exact_render_settings(scene, "cycles")       # preferences are not in the file
scene.render.filepath = os.path.join(out, tag + "_still.exr")
bpy.ops.render.render(write_still=True)
scene.frame_start, scene.frame_end = 4, 6       # a farm's chunk, nothing rendered before it
scene.render.filepath = os.path.join(out, tag + "_####")
bpy.ops.render.render(animation=True)
print("REOPENED", len(drivers), bpy.app.autoexec_fail, status.LAST_ERRORS)
"""


def _run(code, *args, cwd):
    res = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True,
                         text=True, timeout=600, cwd=cwd,
                         env={**os.environ, "PYTHONPATH": os.pathsep.join(
                             [REPO, os.path.join(REPO, "tests")])})
    return res


@pytest.fixture(scope="module")
def authored(tmp_path_factory):
    root = tmp_path_factory.mktemp("saved")
    images = root / "images"
    write_images(str(images))
    res = _run(AUTHOR, images, root, cwd=str(root))
    assert "AUTHORED" in res.stdout, res.stdout[-3000:] + res.stderr[-3000:]
    return root


def _same(a, b):
    pa, pb = read_image(str(a)).pixels, read_image(str(b)).pixels
    return pa.shape == pb.shape and np.array_equal(pa, pb), float(np.abs(pa - pb).max())


def test_reopened_file_renders_bit_identical_pixels_and_farm_chunks_match(authored):
    res = _run(REOPEN, authored / "linked.blend", authored, "linked", cwd=str(authored))
    assert "REOPENED" in res.stdout, res.stdout[-3000:] + res.stderr[-3000:]
    line = next(ln for ln in res.stdout.splitlines() if ln.startswith("REOPENED"))
    assert line.endswith("False []"), line          # no auto-run needed, no errors
    ok, err = _same(authored / "before.exr", authored / "linked_still.exr")
    assert ok, f"reopened still differs by {err:.3e}"
    for frame in (4, 5, 6):
        ok, err = _same(authored / f"seq_{frame:04d}.exr", authored / f"linked_{frame:04d}.exr")
        assert ok, f"farm chunk frame {frame} differs from the sequential render by {err:.3e}"
    # the frames do differ from each other (the lights move)
    assert not _same(authored / "seq_0004.exr", authored / "seq_0006.exr")[0]


def test_packed_file_renders_without_its_image_files(authored, tmp_path):
    moved = tmp_path / "moved"
    shutil.move(str(authored / "images"), str(moved))     # the painting's files are gone
    try:
        res = _run(REOPEN, authored / "packed.blend", authored, "packed", cwd=str(tmp_path))
    finally:
        shutil.move(str(moved), str(authored / "images"))
    assert "REOPENED" in res.stdout, res.stdout[-3000:] + res.stderr[-3000:]
    ok, err = _same(authored / "before.exr", authored / "packed_still.exr")
    assert ok, f"packed file's still differs by {err:.3e}"
    ok, err = _same(authored / "seq_0005.exr", authored / "packed_0005.exr")
    assert ok, f"packed file's frame 5 differs by {err:.3e}"


def test_without_the_load_handler_a_reopened_file_would_be_wrong(authored):
    """Guards the test above: a saved file really loses the generated images' pixels, so the
    load handler is what makes reopening exact."""
    code = PRELUDE + textwrap.dedent("""
        import numpy as np
        from dynpaint_addon.inputs.imageio import image_data_from_blender
        bpy.app.handlers.load_post.remove(handlers.remake_generated_images)
        bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
        mat = next(m for m in bpy.data.materials if m.dynamic_painting.is_painting)
        shadow = mat.dynamic_painting.lights[0].shadow
        px = image_data_from_blender(shadow).pixels
        print("SHADOW", float(np.ptp(px[..., 0])))
    """)
    res = _run(code, authored / "linked.blend", cwd=str(authored))
    line = next((ln for ln in res.stdout.splitlines() if ln.startswith("SHADOW")), None)
    assert line is not None, res.stdout[-3000:] + res.stderr[-3000:]
    assert float(line.split()[1]) == 0.0, line      # a blank generated image, not the bake


OLD = PRELUDE + """
import numpy as np
from dynpaint_addon.blender.state.settings import settings_to_params
from dynpaint_addon.core.pipeline import render as core_render
from dynpaint_addon.inputs.imageio import image_data_from_blender, read_image
bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
scene = bpy.context.scene
mat = next(m for m in bpy.data.materials if m.dynamic_painting.is_painting)
s = mat.dynamic_painting
exact_render_settings(scene, "cycles")
worst = 0.0
for frame in (4, 7):
    scene.frame_set(frame)
    output_settings(scene, os.path.join(sys.argv[2], f"old_{frame}.exr"))
    bpy.ops.render.render(write_still=True)
    got = read_image(scene.render.filepath).pixels
    images = {c: image_data_from_blender(getattr(s, "image_" + c)) for c in ("shape", "dark", "bright")}
    lights = [painting_frame_light(o, s.plane.matrix_world) for o in linked_lights(mat, scene)]
    want = core_render(images, lights, settings_to_params(s)).rgba
    worst = max(worst, float(np.abs(got - want)[1:-1, 1:-1].max()))
print("OLD", worst, status.LAST_ERRORS)
"""


@pytest.mark.parametrize("fixture", sorted(
    f for f in os.listdir(os.path.join(REPO, "tests", "data")) if f.endswith(".blend")))
def test_files_saved_by_earlier_versions_open_and_render(fixture, tmp_path):
    """tests/data/painting_v*.blend were saved by earlier versions (make_old_version_fixture.py):
    each opens in this version and renders what the core renders for its settings and lights."""
    res = _run(OLD, os.path.join(REPO, "tests", "data", fixture), tmp_path, cwd=str(tmp_path))
    line = next((ln for ln in res.stdout.splitlines() if ln.startswith("OLD")), None)
    assert line is not None, res.stdout[-3000:] + res.stderr[-3000:]
    worst = float(line.split()[1])
    assert worst <= 1e-4 and line.endswith("[]"), line
