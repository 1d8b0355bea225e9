"""The painting recipe: validation names the key; writing and reading round-trips."""
import os

import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.inputs.recipe import (RecipeError, load_layers, load_recipe, parse_recipe,
                                   recipe_to_toml)
from dynpaint_addon.inputs.testpainting import write_test_painting


@pytest.fixture(scope="module")
def painting(tmp_path_factory):
    folder = tmp_path_factory.mktemp("painting")
    return write_test_painting(str(folder), size=32)


BASE = {"images": {"shape": "height.png", "dark": "dark.png"}}


def parse(extra, folder):
    return parse_recipe({**BASE, **extra}, folder, "r.toml")


@pytest.mark.parametrize("extra,message", [
    ({"shadows": {"ofset": 0.1}}, "r.toml: shadows.ofset: unknown key (did you mean 'offset'?)"),
    ({"shadow": {}}, "r.toml: shadow: unknown key (did you mean 'shadows'?)"),
    ({"shadows": {"steps": "many"}}, "r.toml: shadows.steps: expected an integer, got 'many'"),
    ({"shadows": {"steps": 2.5}}, "r.toml: shadows.steps: expected an integer, got 2.5"),
    ({"shadows": {"enabled": 1}}, "r.toml: shadows.enabled: expected true or false, got 1"),
    ({"shadows": {"offset": -1.0}}, "r.toml: shadows.offset: -1.0 is out of range [0.0, 1.0] image widths"),
    ({"refraction": {"ior": 3.0}}, "r.toml: refraction.ior: 3.0 is out of range [0.5, 2.0]"),
    ({"diffuse": {"curve": "cubic"}}, "r.toml: diffuse.curve: must be one of linear, smoothstep, smootherstep"),
    ({"shape": {"preblur": "lots"}}, "r.toml: shape.preblur: expected a number or \"auto\", got 'lots'"),
    ({"diffuse": {"t0": float("nan")}}, "r.toml: diffuse.t0: must be a finite number"),
    ({"lights": [{"type": "spot", "direction": [0, 0, 1]}]}, "r.toml: lights[0].type: must be one of sun, point"),
    ({"lights": [{"direction": [0, 0]}]}, "r.toml: lights[0].direction: expected three numbers"),
    ({"lights": [{"direction": [0, 0, 0]}]}, "r.toml: lights[0].direction: must not be [0, 0, 0]"),
    ({"lights": [{"type": "point", "direction": [0, 0, 1]}]}, "r.toml: lights[0].direction: a point light takes 'position'"),
    ({"lights": [{"direction": [0, 0, 1], "colour": [1, 1, 1]}]}, "r.toml: lights[0].colour: unknown key (did you mean 'color'?)"),
    ({"lights": [{"direction": [0, 0, 1], "strength": -2}]}, "r.toml: lights[0].strength: expected a number ≥ 0"),
    ({"images": {"shape": "height.png", "dark": "dark.png", "drak": "x.png"}}, "r.toml: images.drak: unknown image channel (did you mean 'dark'?)"),
    ({"images": {"shape": "missing.png", "dark": "dark.png"}}, "r.toml: images.shape: file not found"),
    ({"images": {"dark": "dark.png"}}, "r.toml: images.shape: missing"),
    ({"images": {"shape": "height.png"}}, "r.toml: images.dark: missing"),
    # issue 60: what would run for minutes or make a page of 100 MB
    ({"lights": [{"direction": [0, 0, 1]}] * 65}, "r.toml: lights: 65 lights; a painting takes at most 64"),
    ({"credits": "x" * 10001}, "r.toml: credits: 10001 characters; at most 10000"),
    ({"lights": [{"type": "point", "position": [0, 0, 1e160]}]},
     "r.toml: lights[0].position: 1e+160 image widths away; at most 1e+06"),
    ({"lights": [{"direction": [0, 0, 1], "name": "x" * 10001}]},
     "r.toml: lights[0].name: 10001 characters; at most 10000"),
])
def test_bad_recipes_name_the_key(painting, extra, message):
    with pytest.raises(RecipeError) as err:
        parse(extra, os.path.dirname(painting))
    assert str(err.value).startswith(message)


def test_every_parameter_accepts_its_default_and_bounds(painting):
    folder = os.path.dirname(painting)
    for prm in params.PARAMS:
        values = [prm.default] + [v for v in (prm.min, prm.max) if v is not None] + list(prm.choices)
        for v in values:
            v = int(v) if prm.kind is int else v
            v = (v, v) if prm.kind == "vec2" and not isinstance(v, tuple) else v
            r = parse({prm.section: {prm.key: v}}, folder)
            assert getattr(getattr(r.params, prm.section), prm.key) == v


def test_a_two_number_parameter_is_checked_by_component(painting):
    folder = os.path.dirname(painting)
    r = parse({"reflection": {"offset": [0.25, -1]}}, folder)
    assert r.params.reflection.offset == (0.25, -1.0)
    for bad, message in (([1.0], "expected two numbers"), (0.5, "expected two numbers"),
                         ([0.0, 11.0], r"offset\[1\]: 11.0 is out of range"),
                         ([0.0, "x"], r"offset\[1\]: expected a number")):
        with pytest.raises(RecipeError, match=message):
            parse({"reflection": {"offset": bad}}, folder)


def test_round_trip(painting, tmp_path):
    r = load_recipe(painting)
    assert r.name == "Built-in test painting" and r.params.shape.kind == "height"
    assert [lt.kind for lt in r.lights] == ["sun", "point"]
    r.params.fresnel.mode = "art"
    r.params.diffuse.t0 = -0.25
    r.params.refraction.offset = (0.5, -0.125)
    for only_changed in (True, False):
        out = tmp_path / f"copy{only_changed}.toml"
        out.write_text(recipe_to_toml(r, str(tmp_path), only_changed))
        back = load_recipe(str(out))
        assert params.as_dict(back.params) == params.as_dict(r.params)
        assert back.lights == r.lights and back.images == r.images and back.name == r.name


def test_unreadable_recipe_files(tmp_path):
    with pytest.raises(RecipeError, match="recipe file not found"):
        load_recipe(str(tmp_path / "nope.toml"))
    bad = tmp_path / "bad.toml"
    bad.write_text("[shape\nkind = 1")
    with pytest.raises(RecipeError, match="not valid TOML"):
        load_recipe(str(bad))
    binary = tmp_path / "bin.toml"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(RecipeError):
        load_recipe(str(binary))


def test_enum_choices_keep_the_numbers_saved_files_hold():
    """A .blend stores an enum setting as its item's index: a new choice goes at the end (the
    choices of released versions keep their places; issue 27 added relief and strength
    'auto')."""
    assert params.BY_PATH["shadows.relief"].choices == ("integrated", "along_ray", "auto")
    assert params.BY_PATH["shape.encoding"].choices == ("auto", "rgb", "rg")


# -- layered recipes (§15) -----------------------------------------------------------------

LAYER = {"images": {"shape": "height.png", "dark": "dark.png"}}


@pytest.mark.parametrize("data,message", [
    ({**BASE, "layers": [LAYER]}, "r.toml: images: a layered recipe's images belong to its layers"),
    ({"layers": []}, "r.toml: layers: expected an array of tables"),
    ({"layers": [LAYER] * 9}, "r.toml: layers: 9 layers; a scene holds at most 8"),
    ({"layers": [{**LAYER, "lights": []}]}, "r.toml: layers[0].lights: the lights belong to the scene"),
    ({"layers": [{**LAYER, "layers": []}]}, "r.toml: layers[0].layers: a layer holds one painting"),
    ({"layers": [{**LAYER, "depth": "far"}]}, "r.toml: layers[0].depth: expected a number, got 'far'"),
    ({"layers": [{**LAYER, "thickness": -1}]}, "r.toml: layers[0].thickness: must be ≥ 0"),
    ({"layers": [{**LAYER, "offset": [1]}]}, "r.toml: layers[0].offset: expected two numbers"),
    ({"layers": [{**LAYER, "scale": 0}]}, "r.toml: layers[0].scale: must be ≥ 1e-06"),
    ({"layers": [{**LAYER, "visible": "no"}]}, "r.toml: layers[0].visible: expected true or false"),
    ({"layers": [{"images": {"dark": "dark.png"}}]}, "r.toml: layers[0]: images.shape: missing"),
    ({"layers": [{**LAYER, "shadows": {"stpes": 3}}]}, "r.toml: layers[0]: shadows.stpes: unknown key (did you mean 'steps'?)"),
    ({"layers": [LAYER], "lights": [{"direction": [0, 0, 1], "radius": 0.1}]}, "r.toml: lights[0].radius: a sun light's size is its 'angle'"),
    ({"layers": [LAYER], "lights": [{"direction": [0, 0, 1], "angle": 200}]}, "r.toml: lights[0].angle: must be in 0 … 180"),
])
def test_bad_layered_recipes_name_the_key(painting, data, message):
    with pytest.raises(RecipeError) as err:
        parse_recipe(data, os.path.dirname(painting), "r.toml")
    assert str(err.value).startswith(message)


def test_a_layered_recipe_round_trips_and_its_layers_start_from_the_scene_sections(painting):
    folder = os.path.dirname(painting)
    data = {"name": "Window", "shadows": {"offset": 0.02},
            "layers": [{**LAYER, "name": "back"},
                       {**LAYER, "name": "front", "depth": 0.2, "thickness": 0.01,
                        "offset": [0.1, -0.05], "scale": 0.5, "visible": False,
                        "shadows": {"steps": 16}}],
            "lights": [{"direction": [0.3, 0.2, 0.9], "angle": 5.0},
                       {"type": "point", "position": [0, 0, 1], "radius": 0.05}]}
    r = parse_recipe(data, folder, "r.toml")
    assert r.layered and [lay.name for lay in r.layers] == ["back", "front"]
    front = r.layers[1]
    assert front.recipe.params.shadows.offset == 0.02 and front.recipe.params.shadows.steps == 16
    assert (front.depth, front.thickness, front.offset, front.scale, front.visible) == \
        (0.2, 0.01, (0.1, -0.05), 0.5, False)
    assert r.lights[0].size == pytest.approx(np.radians(5.0)) and r.lights[1].size == 0.05
    out = os.path.join(folder, "scene.toml")
    with open(out, "w", encoding="utf-8") as fh:
        fh.write(recipe_to_toml(r, folder))
    back = load_recipe(out)
    assert back.lights == r.lights and back.layers[1].depth == 0.2
    for a, b in zip(back.layers, r.layers):
        assert params.as_dict(a.recipe.params) == params.as_dict(b.recipe.params)
        assert (a.name, a.depth, a.thickness, a.offset, a.scale, a.visible, a.recipe.images) == \
            (b.name, b.depth, b.thickness, b.offset, b.scale, b.visible, b.recipe.images)
    assert [lay.name for lay in load_layers(back)] == ["back"]       # hidden layers skipped


def test_a_recipe_nested_past_reading_is_one_line(tmp_path):
    """A TOML array nested 5000 deep (Python's reader recurses): one line, no traceback."""
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(RecipeError, match="nest deeper than Python reads"):
        load_recipe(str(path))
