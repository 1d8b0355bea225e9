"""Layered files (issue 30): OpenRaster and folders of layer images read into a scene — made
here as Krita and Photoshop write them (testkit/layered_files.py) — and every bad file a
clear message."""
import os
import zipfile

import numpy as np
import pytest

from conftest import run_cli
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.layers import render_scene
from dynpaint_addon.inputs.layered_files import (DEFAULT_SHADE, FileLayer, LayeredFileError,
                                                 load_scene, painting_of, read_ora, shaded)
from testkit.layered_files import window_scene, write_ora, write_photoshop_folder

SIZE = 64


@pytest.fixture(scope="module")
def ora(tmp_path_factory):
    return write_ora(str(tmp_path_factory.mktemp("ora") / "window.ora"), SIZE, window_scene(SIZE))


def test_an_ora_file_becomes_a_scene_back_to_front(ora):
    layers, lights, notes = load_scene(ora, spacing=0.1)
    assert [layer.name for layer in layers] == ["sky", "hill", "figure"]
    assert [layer.depth for layer in layers] == [0.0, 0.1, 0.2]
    sky, hill, figure = layers
    # the hill: half the canvas high, its corner at the canvas's left, bottom half
    assert hill.scale == 1.0 and hill.offset == pytest.approx((0.0, -0.25))
    assert hill.images["shape"].pixels.shape[:2] == (SIZE // 2, SIZE)
    # a plain layer: bright is the layer, dark its shaded copy, the shape inflated
    assert hill.p.shape.kind == "height" and hill.images["shape"].pixels.max() > 0
    assert "flat card" in " ".join(notes) and "hill: inflated" in " ".join(notes)
    # a group: its channels by their names, the normal map read as one
    assert set(figure.images) == {"dark", "bright", "shape"} and figure.p.shape.kind == "normal"
    scene = render_scene(layers, lights)
    assert scene.rgba.shape == (SIZE, SIZE, 4) and np.all(scene.rgba[..., 3] > 0.99)


def test_a_photoshop_folder_reads_as_the_ora_does(ora, tmp_path):
    folder = write_photoshop_folder(str(tmp_path / "export"), SIZE, window_scene(SIZE))
    assert sorted(os.listdir(folder))[0] == "_0000_figure"
    layers, _, _ = load_scene(folder)
    assert [layer.name for layer in layers] == ["sky", "hill", "figure"]
    # exported at the canvas's size: placed at offset 0, scale 1, the hill's alpha the same
    from_ora = {layer.name: layer for layer in load_scene(ora)[0]}
    assert all(layer.offset == (0.0, 0.0) and layer.scale == 1.0 for layer in layers)
    hill = layers[1].images["bright"].alpha()
    np.testing.assert_array_equal(hill[:SIZE // 2], from_ora["hill"].images["bright"].alpha())


def test_a_backdrop_within_a_clear_margin_is_a_flat_card():
    """Issue 61 (the walk sample's sky inflated into a pillow, the post's shadow bending on
    it): a layer that fills its canvas but a clear margin (a Grease Pencil fill drawn to the
    drawing's bounds, which are drawn 2 % apart from the picture's edge) is a backdrop, a
    flat card, said; a figure of the same size but with room around it is inflated."""
    px = np.zeros((SIZE, SIZE, 4), np.float32)
    px[2:-2, 2:-2] = (0.4, 0.6, 0.9, 1.0)
    images, _, notes = painting_of(FileLayer("sky", {"painted": ImageData(px, 8)}))
    assert images["shape"].pixels[..., :3].max() == 0
    assert np.array_equal(images["shape"].alpha(), px[..., 3])     # its figure, as inflated
    assert notes == ["sky: fills 88% of the canvas, a backdrop: a flat card (give it a shape "
                     "image for relief)"]
    y, x = np.mgrid[0:SIZE, 0:SIZE]
    px[..., 3] = np.hypot(x - SIZE / 2, y - SIZE / 2) < SIZE * 0.45
    images, _, notes = painting_of(FileLayer("moon", {"painted": ImageData(px, 8)}))
    assert images["shape"].pixels.max() > 0 and "moon: inflated" in notes[0]


def test_the_shaded_copy_is_the_share_of_the_linear_colour():
    img = ImageData(np.array([[[1.0, 0.5, 0.0, 0.7]]], np.float32), 8)
    dark = shaded(img, DEFAULT_SHADE)
    assert dark.pixels[0, 0, 3] == pytest.approx(0.7) and dark.pixels[0, 0, 2] == 0.0
    assert dark.pixels[0, 0, 0] == pytest.approx(1.055 * 0.35 ** (1 / 2.4) - 0.055, abs=1e-5)


def test_hidden_layers_and_blend_modes_are_said(tmp_path):
    path = write_ora(str(tmp_path / "a.ora"), SIZE, window_scene(SIZE),
                     {"hill": {"visibility": "hidden"},
                      "sky": {"composite-op": "svg:multiply", "opacity": "0.5"}})
    layers, _, notes = load_scene(path)
    assert [layer.name for layer in layers] == ["sky", "figure"]
    assert "hill: hidden: left out" in notes
    assert "sky: blend mode multiply read as normal" in notes
    assert any(n.startswith("sky: opacity 0.5 read as 1") for n in notes)


def broken_stack(path):
    return write_ora(path, SIZE, window_scene(SIZE), stack_xml="<image w='64' h='64'><stack>")


def no_stack(path):
    write_ora(path, SIZE, window_scene(SIZE))
    with zipfile.ZipFile(path) as z:
        members = {n: z.read(n) for n in z.namelist() if n != "stack.xml"}
    with zipfile.ZipFile(path, "w") as z:
        for n, data in members.items():
            z.writestr(n, data)
    return path


def jpeg_layer(path):
    return write_ora(path, SIZE, window_scene(SIZE), stack_xml=(
        "<image w='64' h='64'><stack><layer name='photo' src='data/photo.jpg'/></stack></image>"))


def not_a_zip(path):
    with open(path, "w") as fh:
        fh.write("hello")
    return path


@pytest.mark.parametrize("make,message", [
    (broken_stack, "its stack.xml is not valid XML"),
    (no_stack, "not an OpenRaster file: it has no stack.xml"),
    (jpeg_layer, "layer 'photo' is data/photo.jpg: OpenRaster layers are PNG"),
    (not_a_zip, "not an OpenRaster file (.ora is a zip archive"),
])
def test_broken_ora_files_say_what_is_wrong(tmp_path, make, message):
    path = make(str(tmp_path / "bad.ora"))
    with pytest.raises(LayeredFileError, match=message.replace("(", r"\(").replace(".", r"\.")):
        read_ora(path)


def test_too_many_or_no_visible_layers(tmp_path):
    many = [(f"l{i}", window_scene(SIZE)[0][1], 0, 0) for i in range(9)]
    with pytest.raises(LayeredFileError, match="9 visible layers; a scene holds at most 8"):
        load_scene(write_ora(str(tmp_path / "many.ora"), SIZE, many))
    hidden = write_ora(str(tmp_path / "hidden.ora"), SIZE, window_scene(SIZE)[:1],
                       {"sky": {"visibility": "hidden"}})
    with pytest.raises(LayeredFileError, match="no visible layer"):
        load_scene(hidden)


def test_the_command_line_renders_and_bakes_an_ora(ora, tmp_path):
    res = run_cli("render", ora, "--out", tmp_path / "w.png")
    assert res.returncode == 0, res.stderr
    assert "rendered 3 layers on 64×64" in res.stdout and "note: hill: inflated" in res.stderr
    res = run_cli("bake-shadow", "--layers", ora, "--light", 0.5, 0.3, 0.8, "--out", tmp_path / "t")
    assert res.returncode == 0, res.stderr
    assert sorted(os.listdir(tmp_path / "t")) == ["layer_0.exr", "layer_1.exr", "layer_2.exr"]
