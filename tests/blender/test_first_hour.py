"""The first hour, second pass (issue 38): from a folder of an artist's files to the look they
meant, on the command line as a newcomer types it — `dynpaint` from any folder, `dynpaint
new`, folders read as the painting they hold, a default sun, notes that are right on real
files (testkit/artist_folders.py makes them)."""
import os
import re
import shlex
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO, run_cli
from dynpaint_addon.core.input_rules import input_notes
from dynpaint_addon.core.lights import DEFAULT_SUN_DIRECTION
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.inputs.imageio import read_image, write_png
from dynpaint_addon.inputs.recipe import load_images, load_recipe
from dynpaint_addon.web.page import data_of_page
from testkit import artist_folders as af

DYNPAINT = os.path.join(os.path.dirname(sys.executable), "dynpaint")


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    root = tmp_path_factory.mktemp("artists")
    return {name: getattr(af, name)(str(root / name))
            for name in ("glass_eye", "research_portrait", "cutout", "cut_short")}


def copy(folder, tmp_path):
    return shutil.copytree(folder, tmp_path / os.path.basename(folder))


def test_the_dynpaint_command_works_from_any_folder(tmp_path):
    """The README's set-up installs `dynpaint` into .venv/bin: no PYTHONPATH, no repository
    as the working folder."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    res = subprocess.run([DYNPAINT, "render", "portrait", "--out", "x.png"], cwd=tmp_path,
                         capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    assert read_image(str(tmp_path / "x.png")).size == (512, 512)
    help_text = subprocess.run([DYNPAINT, "--help"], cwd=tmp_path, capture_output=True,
                               text=True, env=env).stdout
    assert help_text.startswith("usage: dynpaint") and "new" in help_text


def test_a_folder_holding_a_recipe_renders_as_that_recipe(tmp_path):
    res = run_cli("render", os.path.join(REPO, "sample_scenes", "portrait"), "--out",
                  tmp_path / "folder.png")
    assert res.returncode == 0, res.stderr
    assert "layers" not in res.stdout and "thumbnail" not in res.stderr
    assert run_cli("render", "portrait", "--out", tmp_path / "sample.png").returncode == 0
    np.testing.assert_array_equal(read_image(str(tmp_path / "folder.png")).pixels,
                                  read_image(str(tmp_path / "sample.png")).pixels)


def test_a_folder_of_one_paintings_images_is_one_painting(folders, tmp_path):
    """Nine files of one glass painting: one painting, each file its channel by name, the
    reference photo left out (it was a scene of 9 layers: 'at most 8')."""
    res = run_cli("render", folders["glass_eye"], "--out", tmp_path / "eye.png")
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith("rendered 96×96")
    assert "read as one painting" in res.stderr and "shape = Eye_normal.png" in res.stderr
    assert "not used: reference_photo.jpg" in res.stderr
    recipe = load_recipe(folders["glass_eye"])
    assert set(recipe.images) == {"shape", "dark", "bright", "environment", "background",
                                  "transparency", "specular_color", "gloss"}
    assert recipe.params.shape.kind == "normal" and recipe.params.shadows.enabled


def test_new_writes_a_commented_recipe_that_renders_as_the_folder_did(folders, tmp_path):
    folder = copy(folders["glass_eye"], tmp_path)
    before = tmp_path / "before.png"
    assert run_cli("render", folder, "--out", before).returncode == 0
    res = run_cli("new", folder)
    assert res.returncode == 0, res.stderr
    text = open(folder / "painting.toml").read()
    assert 'shape = "Eye_normal.png"' in text and "# its name says 'normal'" in text
    assert 'kind = "normal"' in text and "coloured: a normal map" in text
    assert "[[lights]]" in text and "distance" in text      # glass: the refraction's reach
    assert "# What new noticed:" in text and "reference_photo.jpg" in text
    after = tmp_path / "after.png"
    assert run_cli("render", folder / "painting.toml", "--out", after).returncode == 0
    np.testing.assert_array_equal(read_image(str(before)).pixels,
                                  read_image(str(after)).pixels)
    # a second new keeps the artist's edits unless told
    again = run_cli("new", folder)
    assert again.returncode == 1 and "--force" in again.stderr


def test_new_makes_the_shape_of_a_painting_that_has_none(folders, tmp_path):
    folder = tmp_path / "pear"
    folder.mkdir()
    shutil.copy(os.path.join(folders["cutout"], "pear.png"), folder / "pear_lit.png")
    res = run_cli("render", folder, "--out", tmp_path / "x.png")
    assert res.returncode == 1 and "dynpaint new" in res.stderr       # says how to make one
    res = run_cli("new", folder)
    assert res.returncode == 0, res.stderr
    assert (folder / "pear_height.exr").exists()
    assert f"made {folder / 'pear_height.exr'}" in res.stdout
    recipe = load_recipe(str(folder / "painting.toml"))
    assert recipe.params.shape.kind == "height" and recipe.params.shape.height_scale == 1.0
    heights = read_image(str(folder / "pear_height.exr")).pixels
    assert heights.max() > 0.1 and heights[0, 0, 0] == 0           # inflated inside only
    assert run_cli("render", folder, "--out", tmp_path / "y.png").returncode == 0


def test_a_failing_new_writes_nothing(tmp_path):
    """Issue 59: `new` on a folder it cannot make a painting of (a normal map and nothing
    painted) says why of the recipe it would have written, and leaves the folder as it was:
    no half recipe that the next `new` refuses to replace without --force."""
    folder = tmp_path / "pear"
    folder.mkdir()
    write_png(folder / "pear_normal.png", np.full((32, 32, 3), 0.5) + [0, 0, 0.5])
    for _ in range(2):
        res = run_cli("new", folder)
        assert res.returncode == 1 and "Traceback" not in res.stderr, res.stderr
        assert f"{folder / 'painting.toml'}: images.dark: missing" in res.stderr, res.stderr
        assert sorted(os.listdir(folder)) == ["pear_normal.png"]


def test_a_suggested_command_pastes_whole_where_a_path_has_a_space(folders, tmp_path):
    """Issue 59: the commands the messages suggest quote their paths, so one pasted into a
    shell runs as said (here: split as a shell would, then run)."""
    folder = tmp_path / "my pear"
    folder.mkdir()
    shutil.copy(os.path.join(folders["cutout"], "pear.png"), folder / "pear_lit.png")
    res = run_cli("render", folder, "--out", tmp_path / "x.png")
    suggested = re.findall(r"`dynpaint (new [^`]*)`", res.stderr)
    assert res.returncode == 1 and suggested, res.stderr
    res = run_cli(*shlex.split(suggested[0]))
    assert res.returncode == 0, res.stderr
    suggested = re.findall(r"`dynpaint (render [^`]*)`", res.stdout)
    assert suggested and "'" in suggested[0], res.stdout
    res = run_cli(*shlex.split(suggested[0]), cwd=tmp_path)
    assert res.returncode == 0 and (tmp_path / "render.png").exists(), res.stderr


def test_a_full_frame_painting_takes_a_shape_made_from_a_painted_mask(folders, tmp_path):
    """Issue 41: a painting with no shape image and no alpha — a mask painted beside it, the
    shape made by `make-shape inflate` into the folder — reads its heights in image widths
    (make-shape's EXR), as `new` and every command then do: the figure's shadow falls."""
    folder = tmp_path / "still"
    folder.mkdir()
    y, x = (np.mgrid[0:96, 0:96] + 0.5) / 96 - 0.5
    figure = (x * x + y * y < 0.3 ** 2).astype(np.float64)
    write_png(folder / "still_bright.png", np.dstack([0.5 + 0.4 * figure, 0.5 + 0 * x,
                                                      0.4 + 0 * x]))
    write_png(tmp_path / "figure.png", figure)
    res = run_cli("make-shape", "inflate", tmp_path / "figure.png", "--bevel-width", "0.02",
                  "--out", folder / "still_height.exr")
    assert res.returncode == 0, res.stderr
    res = run_cli("new", folder)
    assert res.returncode == 0, res.stderr
    assert "floats: heights in image widths" in res.stdout + res.stderr
    recipe = load_recipe(str(folder / "painting.toml"))
    assert recipe.params.shape.kind == "height" and recipe.params.shape.height_scale == 1.0
    t = render(load_images(recipe), recipe.lights, recipe.params).passes["t"][0]
    # the default sun is upper left: the ground to the figure's lower right lies in its shadow
    assert float(t[22, 71]) < 0.3 < float(t[74, 25])


def test_new_on_a_folder_of_layers_writes_a_scene(tmp_path):
    from testkit.layered_files import window_scene, write_photoshop_folder
    folder = tmp_path / "window"
    write_photoshop_folder(str(folder), 64, window_scene(64))
    before = tmp_path / "before.png"
    assert "3 layers" in run_cli("render", folder, "--out", before).stdout
    res = run_cli("new", folder)
    assert res.returncode == 0, res.stderr
    assert "read as a scene of 3 layers" in res.stderr
    recipe = load_recipe(str(folder / "painting.toml"))
    assert [lay.name for lay in recipe.layers] == ["sky", "hill", "figure"]
    after = tmp_path / "after.png"
    assert "3 layers" in run_cli("render", folder, "--out", after).stdout
    # the made dark images are 8-bit PNGs: one level of difference at most
    assert np.abs(read_image(str(before)).pixels - read_image(str(after)).pixels).max() \
        <= 1.01 / 255


def test_a_recipe_without_lights_is_lit_by_a_default_sun_and_says_so(tmp_path):
    portrait = os.path.join(REPO, "sample_scenes", "portrait")
    text = (f'[images]\nshape = "{portrait}/height.png"\ndark = "{portrait}/dark.png"\n'
            f'bright = "{portrait}/bright.png"\n[shape]\nkind = "height"\n')
    (tmp_path / "lit.toml").write_text(text)
    (tmp_path / "dark.toml").write_text("lights = []\n" + text)
    res = run_cli("render", tmp_path / "lit.toml", "--out", tmp_path / "lit.png")
    assert res.returncode == 0 and "note: no lights named: lit by a default sun" in res.stderr
    recipe = load_recipe(str(tmp_path / "lit.toml"))
    assert [lt.vector for lt in recipe.lights] == [DEFAULT_SUN_DIRECTION]
    res = run_cli("render", tmp_path / "dark.toml", "--out", tmp_path / "dark.png")
    assert res.returncode == 0 and "default sun" not in res.stderr
    lit, dark = (read_image(str(tmp_path / f"{n}.png")).pixels for n in ("lit", "dark"))
    assert lit[..., :3].mean() > dark[..., :3].mean() + 0.05        # lit, not the dark image
    # the page lists the sun (it said "Lights none" and told the viewer to drag a light)
    res = run_cli("export-web", tmp_path / "lit.toml", "--out", tmp_path / "lit.html",
                  "--allow-outside-images")     # the sample's images, beside the repo
    assert res.returncode == 0 and "1 light(s)" in res.stdout


def test_a_setting_with_no_effect_says_what_to_set(tmp_path, folders):
    folder = copy(folders["glass_eye"], tmp_path)
    assert run_cli("new", folder).returncode == 0
    with open(folder / "painting.toml", "a") as fh:
        fh.write("\n[fresnel]\nkappa = 1.0\n")
    res = run_cli("render", folder, "--out", tmp_path / "x.png")
    assert res.returncode == 0, res.stderr
    assert 'fresnel.kappa has no effect while fresnel.mode = "physical": set fresnel.mode = ' \
           '"art" too' in res.stderr


def test_see_through_paintings_over_black_say_what_is_likely_meant(folders):
    """Escher's eye and sphere as found: glass over a black background."""
    recipe = load_recipe(folders["glass_eye"])
    images = load_images(recipe)
    said = " ".join(input_notes(images, recipe.params))
    assert "fresnel.mode = \"art\" and fresnel.kappa = 1" in said     # a mirror, under physical
    no_env = {c: img for c, img in images.items() if c != "environment"}
    said = " ".join(input_notes(no_env, recipe.params))
    assert "show a black background" in said and "transparency.amount lower" in said
    recipe.params.fresnel.mode = "art"
    assert "fresnel.kappa = 1" not in " ".join(input_notes(images, recipe.params))


def test_a_map_whose_every_pixel_faces_away_renders_as_its_original_system_showed_it(folders):
    recipe = load_recipe(folders["research_portrait"])
    images = load_images(recipe)
    as_found = render(images, recipe.lights, recipe.params)
    recipe.params.shape.strength = 0.5
    as_meant = render(images, recipe.lights, recipe.params).rgba
    np.testing.assert_array_equal(as_found.rgba, as_meant)
    said = " ".join(as_found.warnings)
    assert "halves each tilt" in said and "strength 0.5" in said
    assert "face away from the viewer" not in said          # read as meant: nothing to fix


def test_a_jpeg_cut_short_says_how_much_holds_data(folders, tmp_path):
    res = run_cli("render", folders["cut_short"], "--out", tmp_path / "x.png")
    assert res.returncode == 0, res.stderr
    line = next(ln for ln in res.stderr.splitlines() if "cut short" in ln)
    share = int(line.split("only the top ")[1].split("%")[0])
    assert 5 <= share <= 60, line
    img = read_image(os.path.join(folders["cut_short"], "pear_bright.jpg"))
    assert img.notes == [line.removeprefix("note: ")]


def test_a_corrupt_image_gets_our_line_only(tmp_path):
    """Blender's own log lines (`image.read | ERROR …`, on stdout) stay off the terminal."""
    good = open(os.path.join(REPO, "sample_scenes", "portrait", "height.png"), "rb").read()
    (tmp_path / "height.png").write_bytes(good[:len(good) // 3])
    (tmp_path / "r.toml").write_text('[images]\nshape = "height.png"\n'
                                     'dark = "height.png"\n[shape]\nkind = "height"\n')
    res = run_cli("render", tmp_path / "r.toml", "--out", tmp_path / "x.png")
    assert res.returncode == 1
    assert "image.read" not in res.stdout + res.stderr and "OpenImageIO" not in \
        res.stdout + res.stderr
    assert [ln for ln in res.stderr.splitlines() if ln.startswith("error:")][0].endswith(
        "height.png: not an image Blender can read (unknown or corrupt format)")


# -- memory asked for before it is spent ------------------------------------------------------
@pytest.fixture(scope="module")
def bomb(tmp_path_factory):
    return af.write_bomb(str(tmp_path_factory.mktemp("bomb") / "poster.png"))


def _peak_mb(*args, cwd):
    """(CompletedProcess, peak RSS in MiB) of `dynpaint ARGS` in a fresh process."""
    probe = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:], "
             "capture_output=True, text=True); sys.stdout.write(r.stderr); "
             "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024)")
    res = subprocess.run([sys.executable, "-c", probe, DYNPAINT, *map(str, args)], cwd=cwd,
                         capture_output=True, text=True, timeout=300)
    *lines, mb = res.stdout.splitlines()
    return "\n".join(lines), int(mb)


def test_a_huge_image_is_refused_before_it_is_decoded(bomb, tmp_path):
    """A 2.6 MB PNG that declares 30000 × 30000 (27 GiB to decode): one line with both numbers,
    at once, without the memory (it ran 15 s and ended in MemoryError, or a TypeError)."""
    recipe = tmp_path / "poster.toml"
    recipe.write_text(f'[images]\nshape = "{bomb}"\ndark = "{bomb}"\n')
    for args in (("render", recipe, "--out", "x.png"),
                 ("bake-shadow", bomb, "--kind", "normal", "--light", 0, 0, 1, "--out", "t.exr")):
        said, mb = _peak_mb(*args, cwd=tmp_path)
        assert said.startswith("error: ") and "30000×30000 would need about" in said, said
        assert "GiB of memory; this machine has" in said and "GiB free" in said
        assert mb < 1024, mb                                    # nothing large was allocated
    from dynpaint_addon.inputs.imageio import read_image
    from dynpaint_addon.inputs.memory import NotEnoughMemory
    with pytest.raises(NotEnoughMemory, match="reading poster.png"):
        read_image(bomb)


def test_a_render_too_large_for_the_machine_says_what_fits(tmp_path):
    said, mb = _peak_mb("render", "portrait", "--width", 100000, "--out", "x.png", cwd=tmp_path)
    assert said.startswith("error: rendering 100000×100000 would need about"), said
    assert "render it smaller (--width " in said and mb < 1024
    width = int(said.split("--width ")[1].split(",")[0])
    from dynpaint_addon.inputs import memory
    assert width >= 512 and memory.available_bytes() * memory.HEADROOM > 260 * 2**20


def _under_3_gib(*args, cwd):
    """What `dynpaint ARGS` says on stderr with 3 GiB of address space (as on a small
    machine, whatever this one has)."""
    probe = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:], "
             "capture_output=True, text=True, preexec_fn=lambda: resource.setrlimit("
             "resource.RLIMIT_AS, (3 << 30, 3 << 30))); sys.stdout.write(r.stderr)")
    return subprocess.run([sys.executable, "-c", probe, DYNPAINT, *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=300).stdout


def test_no_estimate_spends_what_it_counts(bomb, tmp_path):
    """Issue 60: the render estimate at --width 4e7 built the crossings' grid (73 s, 10 GB
    before refusing); export-web of a 30000² painting read its images before any estimate;
    a turntable's frames were never counted. Each now refuses with its numbers, at once."""
    said, mb = _peak_mb("render", "portrait", "--width", 40000000, "--out", "x.png",
                        cwd=tmp_path)
    assert said.startswith("error: rendering 40000000×40000000 would need about") and \
        "e+" in said.split("about ")[1].split(" GiB")[0] and mb < 1024, (said, mb)
    recipe = tmp_path / "poster.toml"
    recipe.write_text(f'[images]\nshape = "{bomb}"\ndark = "{bomb}"\n')
    said = _under_3_gib("export-web", recipe, "--out", "x.html", "--allow-outside-images",
                        cwd=tmp_path)
    assert "error: a page of the 30000×30000 painting would need about" in said, said
    said = _under_3_gib("turntable", "portrait", "--size", 8192, 8192, "--out", "x.mp4",
                        cwd=tmp_path)
    assert said.startswith("error: a 8192×8192 turntable would need about 6."), said
    assert "choose a smaller --size (at most " in said and not (tmp_path / "x.mp4").exists()


def test_the_estimates_meet_measured_peaks_at_1024(tmp_path):
    """benchmarks/memory.py's check at one size (its report covers 1024², 4096² and 8192²)."""
    sys.path.insert(0, os.path.join(REPO, "benchmarks"))
    import memory as bench
    path = bench.painting_at("portrait", 1024, str(tmp_path))
    guess, cmds = bench.estimates(path), bench.commands(path, str(tmp_path))
    for command in ("render", "bake-shadow"):
        measured = bench.peak_rss(cmds[command])
        assert abs(guess[command] / measured - 1) <= bench.GOAL, (command, guess, measured)


# -- the smaller items ------------------------------------------------------------------------
def test_every_command_describes_itself_and_options_take_what_their_help_offers(tmp_path):
    from dynpaint_addon.cli import build_parser
    import argparse
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert all(p.description for p in sub.choices.values()), \
        [n for n, p in sub.choices.items() if not p.description]
    bake = run_cli("bake-shadow", "--help").stdout
    assert bake.startswith("usage: dynpaint bake-shadow (SHAPE --kind")
    shape = os.path.join(REPO, "sample_scenes", "portrait", "height.png")
    res = run_cli("bake-shadow", shape, "--kind", "height", "--light", 0, 0.5, 1, "--strength",
                  "auto", "--preblur", "auto", "--out", tmp_path / "t.exr")
    assert res.returncode == 0, res.stderr
    assert "count from 1" in run_cli("render", "--help").stdout


def test_the_layered_page_takes_the_recipes_name(tmp_path):
    res = run_cli("export-web", "window", "--out", tmp_path / "w.html")
    assert res.returncode == 0, res.stderr
    data = data_of_page(open(tmp_path / "w.html", encoding="utf-8").read())
    assert data["title"] == load_recipe("window").name != "window"


def test_the_main_job_says_nothing_a_newcomer_cannot_act_on(tmp_path):
    res = run_cli("turntable", "portrait", "--frames", 2, "--out", tmp_path / "t.mp4")
    assert res.returncode == 0, res.stderr
    assert "note:" not in res.stderr, res.stderr


def test_the_readme_names_every_sample_command_and_measured_ratio():
    from dynpaint_addon.cli import COMMANDS
    from dynpaint_addon.inputs.samples import list_samples
    readme = open(os.path.join(REPO, "README.md"), encoding="utf-8").read()
    names = ", ".join(f"`{s.id}`" for s in list_samples())
    assert f"sample's name ({names})" in " ".join(readme.split())
    table = [ln for ln in readme.splitlines() if ln.startswith("| `")]
    for command in COMMANDS:
        name = command.__name__.rsplit(".", 1)[1].replace("_", "-")
        name = {"parameters": "params"}.get(name, name)
        assert any(ln.startswith(f"| `{name}") for ln in table), name
    main_job = open(os.path.join(REPO, "docs", "main-job.md"), encoding="utf-8").read()
    ratio = main_job.split("EEVEE takes ")[1].split("×")[0]
    assert f"takes about {ratio}× Cycles' time" in readme


def test_add_refuses_a_painting_that_would_not_fit_and_loads_nothing(empty_scene, bomb):
    """Blender out of memory takes the artist's unsaved work with it: Add says so first."""
    import bpy
    from dynpaint_addon.blender.state import status
    folder, name = os.path.split(bomb)
    before = set(bpy.data.images)
    with pytest.raises(RuntimeError, match=r"30000×30000\)? would need about .* GiB free"):
        bpy.ops.dynpaint.add("EXEC_DEFAULT", directory=folder, files=[{"name": name}],
                             confirm=False)
    assert set(bpy.data.images) == before and not bpy.data.objects
    status.LAST_ERRORS.clear()


def test_max_size_downsamples_what_add_reads(empty_scene, tmp_path):
    """Add's Max Size: the painting worked at 128 px, the images packed copies (the files
    unchanged), said; saved and reopened it stays so."""
    import bpy
    from dynpaint_addon.blender.state.frames import painting_size
    recipe = os.path.join(REPO, "sample_scenes", "portrait", "painting.toml")
    res = bpy.ops.dynpaint.add("EXEC_DEFAULT", filepath=recipe,
                               directory=os.path.dirname(recipe),
                               files=[{"name": "painting.toml"}], max_size=128)
    assert res == {"FINISHED"}
    mat = bpy.context.object.active_material
    name = mat.name
    assert tuple(painting_size(mat)) == (128, 128)
    s = mat.dynamic_painting
    assert s.image_shape.packed_file is not None and tuple(s.image_bright.size) == (128, 128)
    assert read_image(os.path.join(os.path.dirname(recipe), "bright.png")).size == (512, 512)
    path = str(tmp_path / "small.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    assert tuple(painting_size(bpy.data.materials[name])) == (128, 128)


def test_a_drawings_recipe_renders_with_cycles_unless_told(monkeypatch, capsys, tmp_path):
    """Issue 61: `dynpaint render walk --out x.png` failed at once with the default engine
    (the numpy core reads no Grease Pencil drawing): Cycles renders it, said; --width draws
    each layer that wide. (The render itself is
    test_the_command_line_renders_a_blend_files_drawing_lit's.)"""
    from dynpaint_addon.blender import headless
    from dynpaint_addon.cli import main
    engines = []
    monkeypatch.setattr(headless, "render_recipe", lambda recipe, engine, out, frame, notes,
                        drawing_width: engines.append((engine, drawing_width)) or 0.1)
    assert main(["render", "walk", "--out", str(tmp_path / "x.png")]) == 0
    assert engines == [("cycles", None)] and "rendered with Cycles" in capsys.readouterr().err
    assert main(["render", "walk", "--out", str(tmp_path / "x.png"), "--engine", "eevee"]) == 0
    # --width: each layer drawn that wide (a quick look: 13 s at 256 px here, 491 s at 1024)
    assert main(["render", "walk", "--out", str(tmp_path / "x.png"), "--width", "256"]) == 0
    assert engines[1:] == [("eevee", None), ("cycles", 256)]
    assert main(["render", "portrait", "--out", str(tmp_path / "x.png"), "--width", "64",
                 "--engine", "cycles"]) == 1
    assert "apply to the numpy engine only" in capsys.readouterr().err
