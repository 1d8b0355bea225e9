"""The command line on a painting that moves (§16, issue 31), with the animated sample's PNG
frames (reading PNGs needs Blender's image I/O): `render --frame N` draws the frame's own
images, `export-maps` writes sprite sheets on the painting's own grid, each cell the frame's
maps."""
import json
import os

import numpy as np
import pytest

from conftest import run_cli
from dynpaint_addon.core.frames import sheet_cell
from dynpaint_addon.inputs.imageio import read_image
from dynpaint_addon.inputs.recipe import load_recipe

BLINK = load_recipe("blink")
FOLDER = os.path.dirname(BLINK.path)


def _still_recipe(tmp_path, number):
    """The sample's frame `number` as a painting that does not move (its files by hand)."""
    cells = {"dark": "dark_sheet.png", "bright": "bright_sheet.png"}
    path = tmp_path / "still.toml"
    text = open(BLINK.path, encoding="utf-8").read()
    text = text.replace('"normal_####.png"', f'"{FOLDER}/normal_{number:04d}.png"')
    for name in cells.values():
        text = text.replace(f'"{name}"', f'"{FOLDER}/{name}"')
    path.write_text(text + "\n[frames.shape]\ncolumns = 1\nrows = 1\n")   # a still image
    return path


def test_render_a_frame_of_the_sample_is_its_frames_images(tmp_path):
    r = run_cli("render", "blink", "--frame", "29", "--out", tmp_path / "f29.exr")
    assert r.returncode == 0, r.stderr
    assert "scene frame 29: shape frame 5, dark frame 5, bright frame 5" in r.stdout
    assert "normal_####.png: files 1–24; 24 frames from scene frame 1" in r.stderr
    # the same drawing by hand: frame 5's normal map, the sheets' cell 5 (a grid of one cell
    # per frame is what the sample's [frames] says: 29 → (29 − 1) mod 24 + 1 = 5)
    still = _still_recipe(tmp_path, 5)
    text = still.read_text().replace("columns = 6\nrows = 4", "columns = 6\nrows = 4\n"
                                     "offset = 4\nmode = \"hold\"\ncount = 24")
    still.write_text(text)
    assert run_cli("render", still, "--frame", "1", "--out", tmp_path / "by_hand.exr"
                   ).returncode == 0
    np.testing.assert_array_equal(read_image(str(tmp_path / "f29.exr")).pixels,
                                  read_image(str(tmp_path / "by_hand.exr")).pixels)


@pytest.mark.parametrize("number", [1, 11])
def test_export_maps_of_the_sample_are_sheets_on_its_own_grid(tmp_path, number):
    out = tmp_path / "maps"
    r = run_cli("make-shape", "export-maps", "blink", "--out", out)
    assert r.returncode == 0, r.stderr
    grid = BLINK.slots()["dark"].grid
    sheet = json.loads((out / "sheet.json").read_text())
    assert (sheet["columns"], sheet["rows"], sheet["frames"]) == (6, 4, 24)
    dark = read_image(os.path.join(FOLDER, "dark_sheet.png")).pixels
    normals = read_image(str(out / "normal.png")).pixels
    heights = read_image(str(out / "height.exr")).pixels[..., 0]
    assert normals.shape[:2] == heights.shape == dark.shape[:2]
    # each cell is the frame's own maps (its heights on the sequence's one floor)
    alone = tmp_path / "alone"
    assert run_cli("make-shape", "export-maps", _still_recipe(tmp_path, number), "--out",
                   alone).returncode == 0
    np.testing.assert_array_equal(sheet_cell(normals, grid, number - 1),
                                  read_image(str(alone / "normal.png")).pixels)
    lift = sheet_cell(heights, grid, number - 1) - read_image(str(alone / "height.exr")).pixels[..., 0]
    assert np.ptp(lift) < 1e-6 and heights.min() == 0


def test_a_turntable_of_the_sample_moves_the_painting_as_the_light_turns(tmp_path):
    out = tmp_path / "blink.mp4"
    r = run_cli("turntable", "blink", "--frames", "4", "--out", out)
    assert r.returncode == 0, r.stderr
    assert "frame 4/4" in r.stdout and out.stat().st_size > 1000
    assert "normal_####.png: files 1–24" in r.stderr          # it said what moves
