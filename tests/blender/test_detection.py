"""Guesses that survive real files (issue 27): every convention as 8/16-bit PNG, noisy export
and JPEG files (benchmarks/detection.py writes them) is read as meant, each guess is said, an
explicit setting is obeyed, and every command says the same notes."""
import os
import sys

import numpy as np
import pytest

from conftest import REPO, run_cli

sys.path.insert(0, os.path.join(REPO, "benchmarks"))

import detection  # noqa: E402

from testkit import example_paintings as ex  # noqa: E402
from testkit.artist_folders import write_jpeg  # noqa: E402
from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData, input_notes  # noqa: E402
from dynpaint_addon.inputs.imageio import write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import Recipe, recipe_to_toml  # noqa: E402


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return str(tmp_path_factory.mktemp("detection"))


def test_every_convention_in_every_kind_of_file_is_guessed_as_meant(folder):
    rows = detection.measure(64, folder) + detection.measure(128, folder)
    cut_outs = [c for c in detection.conventions(8).values() if c[0].shape[-1] == 4]
    jpegs = [v for v in detection.VARIANTS if v.startswith("jpeg")]
    assert len(rows) == 2 * (len(detection.conventions(8)) * len(detection.VARIANTS)
                             - len(cut_outs) * len(jpegs))     # a JPEG holds no cut-out
    wrong = [(name, variant, got) for name, variant, _, got, want, _ in rows if got != want]
    assert not wrong


def test_the_face_away_note_fires_only_where_it_changes_the_picture(folder):
    """Issue 38: never on a map read as meant (antialiased cut-outs, JPEG noise, a map whose
    every pixel faces away read as its original system read it); always on a map read the
    wrong way."""
    rows = detection.measure(64, folder)
    fired = {(name, variant) for name, variant, *_, note in rows if note}
    assert {name for name, _ in fired} == {"halving decoder, other lengths",
                                           "photograph as a normal map"}
    assert len(fired) == 2 * len(detection.VARIANTS)


def test_the_fourteen_sets_render_as_meant_and_say_what_was_guessed(folder):
    sets = detection.example_sets(128, folder)
    assert len(sets) == len(detection.SETS) == 17
    for name, cost, noise, other, notes in sets:
        assert cost == 0, name                       # every guess right: the same pixels
        assert other > 2 * noise, name               # … and the other reading is visible
        said = " ".join(notes)
        if "mask painted in" in name:
            assert "read from its" in said, name
        if "two-channel" in name:
            assert "two-channel" in said, name
        if "unit vectors" in name:
            assert "halves each tilt" in said and "strength 0.5" in said, name


def test_an_explicit_setting_is_obeyed_and_a_map_that_cannot_tell_says_the_fix(folder):
    rgb = detection.conventions(64)["halving decoder, other lengths"][0]
    img = detection.as_file(rgb, "jpeg75", folder, "explicit")
    p = params.defaults()
    p.shape.kind = "normal"
    notes = " ".join(input_notes({"shape": img}, p))
    assert "shape.strength = 0.5" in notes and "cannot tell" in notes
    p.shape.strength = 0.5
    assert input_notes({"shape": img}, p) == []      # obeyed: no refusal, nothing to say
    p.shape.strength, p.shape.encoding = "auto", "rg"
    assert input_notes({"shape": img}, p) == []      # read as asked, even if odd


def _glass_recipe(tmp_path, shape_name):
    """The glass sample's settings with a normal map without alpha (a JPEG) → recipe path."""
    n, _ = ex.sphere(48, 0.4)
    write_jpeg(str(tmp_path / shape_name), ex.normal_map_rgb(n), 90)
    write_png(tmp_path / "dark.png", np.full((48, 48, 3), 0.3))
    write_png(tmp_path / "bg.png", ex.photograph(48, 48))
    p = params.defaults()
    p.shape.kind = "normal"
    p.transparency.amount = 0.9
    recipe = Recipe(p, [], {"shape": str(tmp_path / shape_name), "dark": str(tmp_path / "dark.png"),
                            "background": str(tmp_path / "bg.png")}, "glass")
    path = tmp_path / "painting.toml"
    path.write_text(recipe_to_toml(recipe, str(tmp_path)))
    return path


def test_a_glass_painting_without_alpha_gets_a_note_in_every_command(tmp_path):
    recipe = _glass_recipe(tmp_path, "normal.jpg")
    said = "no alpha in the colour, shape or dark image (a JPEG has none): the whole canvas is glass"
    for args in (("render", recipe, "--out", tmp_path / "a.png"),
                 ("export-web", recipe, "--out", tmp_path / "a.html"),
                 ("turntable", recipe, "--frames", "2", "--out", tmp_path / "a.mp4"),
                 ("make-shape", "export-maps", recipe, "--out", tmp_path / "maps")):
        res = run_cli(*args)
        assert res.returncode == 0, res.stderr
        notes = [ln for ln in res.stderr.splitlines() if ln.startswith("note: ")]
        assert any(said in ln for ln in notes), (args[0], res.stderr)
    res = run_cli("bake-shadow", tmp_path / "normal.jpg", "--kind", "normal", "--light", "0", "1",
                  "1", "--out", tmp_path / "t.exr")
    assert res.returncode == 0 and "note: " not in res.stderr, res.stderr    # no glass there


def test_the_note_names_the_alpha_only_where_glass_or_a_background_needs_it():
    shape = ImageData(np.full((8, 8, 3), (0.5, 0.5, 1.0), np.float32), 8)
    p = params.defaults()
    p.shape.kind = "normal"
    assert input_notes({"shape": shape}, p) == []
    assert "hides the background" in input_notes({"shape": shape, "background": shape}, p)[0]
    with_alpha = ImageData(np.full((8, 8, 4), (0.5, 0.5, 1.0, 1.0), np.float32), 8)
    assert input_notes({"shape": with_alpha, "background": shape}, p) == []
    p.silhouette.source = "none"                       # the artist says: the canvas is whole
    assert input_notes({"shape": shape, "background": shape}, p) == []
