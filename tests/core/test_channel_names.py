"""Add › From Images: which channel each picked file is for, by its name (issue 15, point 3)."""
import doctest

import pytest

from dynpaint_addon.inputs import channel_names
from dynpaint_addon.inputs.channel_names import common_name, guess_channels


def test_the_docstring_examples_hold():
    assert doctest.testmod(channel_names).failed == 0


@pytest.mark.parametrize("name,channel", [
    ("diffuse.png", "bright"), ("albedo.png", "bright"), ("Color.jpg", "bright"),
    ("lit.png", "bright"), ("shade.png", "dark"), ("portrait_dark.png", "dark"),
    ("alpha.png", "transparency"), ("mask.png", "transparency"), ("matte.tif", "transparency"),
    ("reflect.jpg", "environment"), ("env.exr", "environment"),
    ("refract.png", "background"), ("bg.png", "background"), ("back.jpg", "background"),
    ("nrm.png", "shape"), ("face_normal.png", "shape"), ("depth.exr", "shape"),
    ("disp.png", "shape"), ("height16.png", "shape"), ("portraitNormal.png", "shape"),
    ("gloss.png", "gloss"), ("roughness.png", "gloss"), ("spec.png", "specular_color"),
])
def test_common_names_and_synonyms(name, channel):
    assert guess_channels([name])[0] == {channel: name}


def test_words_count_whole_and_unknown_names_stay_unassigned():
    # 'bg' is a word, not the letters of 'bright_glow'; 'backlight' is not 'back'
    assert guess_channels(["bright_glow.png"])[0] == {"bright": "bright_glow.png"}
    found, rest = guess_channels(["diffuse.png", "alpha.png", "trees.jpg", "tree_blurry.jpg",
                                  "noise.jpg", "nrm.png"])
    assert found == {"bright": "diffuse.png", "transparency": "alpha.png", "shape": "nrm.png"}
    assert rest == ["trees.jpg", "tree_blurry.jpg", "noise.jpg"]


def test_the_painting_takes_the_images_common_name():
    assert common_name(["Eye_normal.png", "Eye_dark.png", "Eye_bright.png"]) == "Eye"
    assert common_name(["mirror sphere - nrm.png", "mirror sphere - diffuse.png"]) == \
        "mirror sphere"
    assert common_name(["normal.png", "dark.png"]) == ""
