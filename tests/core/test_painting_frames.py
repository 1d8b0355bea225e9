"""Paintings that move (§16, issue 31): sequences and sprite sheets read per scene frame
(painting_frames.py), [frames] recipes, and bad input said with the frame or the numbers.
EXR files only here (read without Blender); PNG frames are tested under tests/blender."""
import os

import numpy as np
import pytest

from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.inputs.imageio import read_image, write_exr
from dynpaint_addon.inputs.painting_frames import (FrameError, PaintingFrames, painting_slots,
                                            sequence_numbers, slot_frames, slot_settings)
from dynpaint_addon.inputs.recipe import (RecipeError, load_images, load_recipe, parse_recipe,
                                   recipe_to_toml)
from dynpaint_addon.params import frame_defaults
from testkit.animated import moving_dome, sheet_of, write_sequence, write_sheet


def _mapping(**kw):
    return dict(frame_defaults(), **kw)


def test_a_sequence_starts_at_its_first_file_and_runs_to_its_last(tmp_path):
    """Blender's Open: offset = first number − 1, frames = last − first + 1."""
    frames = moving_dome(8, 5)
    write_sequence(str(tmp_path / "h_####.exr"), frames, first=10)
    slot = slot_frames("shape", str(tmp_path / "h_####.exr"), _mapping())
    assert (slot.kind, slot.offset, slot.count, slot.numbers) == \
        ("sequence", 9, 5, (10, 11, 12, 13, 14))
    assert [slot.file_number(f) for f in range(1, 8)] == [10, 11, 12, 13, 14, 10, 11]
    painting = PaintingFrames({"shape": slot})
    for f in range(1, 6):
        np.testing.assert_array_equal(painting.image("shape", f).pixels[..., 0], frames[f - 1])
    assert "files 10–14; 5 frames from scene frame 1 (offset 9), cyclic" in painting.notes[0]


def test_c_style_numbers_and_an_explicit_mapping(tmp_path):
    write_sequence(str(tmp_path / "h_%03d.exr"), moving_dome(8, 4), first=0)
    slot = slot_frames("shape", str(tmp_path / "h_%03d.exr"),
                       _mapping(offset=0, count=3, mode="hold", start=5))
    assert slot.numbers == (0, 1, 2, 3)
    assert [slot.file_number(f) for f in (1, 5, 6, 7, 30)] == [1, 1, 2, 3, 3]


@pytest.mark.parametrize("margin, spacing", [(0, 0), (3, 2)])
def test_a_sheets_cells_run_row_by_row_from_the_top_left(tmp_path, margin, spacing):
    frames = moving_dome(6, 7)
    path = write_sheet(str(tmp_path / "sheet.exr"), frames, 3, 3, margin, spacing)
    slot = slot_frames("shape", path, _mapping(columns=3, rows=3, count=7, margin=margin,
                                               spacing=spacing))
    painting = PaintingFrames({"shape": slot})
    for f in range(1, 15):
        np.testing.assert_array_equal(painting.image("shape", f).pixels[..., 0],
                                      frames[(f - 1) % 7])
    assert painting.key(1) == painting.key(8) != painting.key(2)   # cyclic: 8 shows cell 0


def test_the_painting_frame_is_the_key_of_what_is_shown(tmp_path):
    """Bakes and derived images are kept by it: frames showing one drawing share a key."""
    write_sequence(str(tmp_path / "h_####.exr"), moving_dome(8, 3))
    write_exr(str(tmp_path / "still.exr"), np.ones((8, 8, 3), np.float32))
    slots = painting_slots({"shape": str(tmp_path / "h_####.exr"),
                            "dark": str(tmp_path / "still.exr")},
                           {"": {"mode": "hold", "rate": 0.5}})
    painting = PaintingFrames(slots)
    keys = [painting.key(f) for f in range(1, 9)]
    assert keys[0] == keys[1] != keys[2] == keys[3]                 # on twos
    assert keys[4:] == [(("shape", 3),)] * 4                       # held at the end
    assert not PaintingFrames({"dark": slots["dark"]}).animated


def test_the_environment_takes_no_grid_of_the_paintings_own():
    frames = {"": {"columns": 2, "rows": 2}, "background": {"columns": 4}}
    assert slot_settings(frames, "dark")["columns"] == 2
    assert slot_settings(frames, "environment")["columns"] == 1
    assert slot_settings(frames, "background")["columns"] == 4


# -- bad input: one clear message naming the frame or the numbers ---------------------------
def test_a_pattern_that_matches_nothing(tmp_path):
    with pytest.raises(FrameError, match=r"walk_####.png: no file matches \(looked for names "
                                         r"like walk_0000.png"):
        sequence_numbers(str(tmp_path / "walk_####.png"))


def test_a_missing_frame_names_it_and_the_files_found(tmp_path):
    paths = write_sequence(str(tmp_path / "h_####.exr"), moving_dome(8, 6))
    os.remove(paths[3])
    painting = PaintingFrames({"shape": slot_frames("shape", str(tmp_path / "h_####.exr"),
                                                    _mapping())})
    assert "1 missing" in painting.notes[0]
    painting.images(3)
    with pytest.raises(FrameError, match=r"h_0004.exr \(frame 4 of h_####.exr, scene frame "
                                         r"4\) is missing; files found: 1–3, 5–6"):
        painting.images(4)


def test_frames_of_different_sizes(tmp_path):
    write_sequence(str(tmp_path / "h_####.exr"), moving_dome(8, 2) + moving_dome(6, 1))
    painting = PaintingFrames({"shape": slot_frames("shape", str(tmp_path / "h_####.exr"),
                                                    _mapping())})
    painting.images(1)
    with pytest.raises(FrameError, match="h_0003.exr is 6×6, h_0001.exr 8×8: every frame"):
        painting.images(3)


def test_a_sheet_that_does_not_divide_and_a_count_larger_than_the_sheet(tmp_path):
    path = str(tmp_path / "sheet.exr")
    write_exr(path, np.zeros((10, 13), np.float32))
    slot = slot_frames("dark", path, _mapping(columns=4, rows=2))
    with pytest.raises(FrameError, match=r"dark: sheet.exr: a 13×10 sheet does not divide "
                                         r"into 4 × 2 cells"):
        PaintingFrames({"dark": slot}).images(1)
    with pytest.raises(FrameError, match=r"9 frames do not fit a sheet of 4 × 2 cells \(8\)"):
        slot_frames("dark", path, _mapping(columns=4, rows=2, count=9))


def test_float_and_integer_frames_do_not_mix_but_8_and_16_bit_do(tmp_path):
    write_sequence(str(tmp_path / "h_####.exr"), moving_dome(4, 3))
    bits = {1: 8, 2: 16, 3: 32}

    def read(path):           # a decoder giving each frame its file's depth
        data = read_image(path)
        return ImageData(data.pixels, bits[int(path[-8:-4])], data.name)
    painting = PaintingFrames({"shape": slot_frames("shape", str(tmp_path / "h_####.exr"),
                                                    _mapping())}, read=read)
    assert painting.image("shape", 2).bits == 8
    assert "h_0002.exr is 16-bit, h_0001.exr 8-bit: read alike" in painting.notes[-1]
    with pytest.raises(FrameError, match="h_0003.exr is float, h_0001.exr 8-bit"):
        painting.images(3)


def test_ten_thousand_frames_keep_the_cache_bounded(tmp_path):
    """Memory stays bounded however long the sequence: the cache drops the oldest frames."""
    for n in range(1, 10001):
        open(tmp_path / f"f_{n:05d}.exr", "wb").close()

    def read(path):            # a 128² RGBA float frame (64 KiB · 4) per file
        return ImageData(np.full((128, 128, 4), int(path[-9:-4]), np.float32), 32)
    slot = slot_frames("shape", str(tmp_path / "f_#####.exr"), _mapping())
    assert slot.count == 10000
    painting = PaintingFrames({"shape": slot}, cache_mb=2, read=read)
    for f in range(1, 10001, 7):
        assert painting.image("shape", f).pixels[0, 0, 0] == f
    assert painting.peak_bytes <= 2 * 2**20 + 128 * 128 * 16
    assert painting.cached_bytes <= 2 * 2**20


# -- recipes ---------------------------------------------------------------------------------
def _animated_recipe(tmp_path, extra=""):
    write_sequence(str(tmp_path / "height_####.exr"), moving_dome(16, 4))
    write_sheet(str(tmp_path / "dark_sheet.exr"),
                [np.full((16, 16, 3), 0.1 * (i + 1), np.float32) for i in range(4)], 2, 2)
    write_exr(str(tmp_path / "bright.exr"), np.full((16, 16, 3), 0.8, np.float32))
    (tmp_path / "painting.toml").write_text(
        '[images]\nshape = "height_####.exr"\ndark = "dark_sheet.exr"\nbright = "bright.exr"\n'
        '[shape]\nkind = "height"\n[frames]\nmode = "ping-pong"\n'
        '[frames.dark]\ncolumns = 2\nrows = 2\n' + extra +
        '[[lights]]\ndirection = [0.5, 0.2, 0.6]\n')
    return load_recipe(str(tmp_path / "painting.toml"))


def test_a_recipe_with_frames_renders_each_frame_from_its_own_images(tmp_path):
    recipe = _animated_recipe(tmp_path)
    slots = recipe.slots()
    assert PaintingFrames(slots).animated and {c: s.kind for c, s in slots.items()} == \
        {"shape": "sequence", "dark": "sheet", "bright": "still"}
    for f, number in [(1, 1), (3, 3), (5, 3), (6, 2)]:     # ping-pong: 1 2 3 4 3 2 …
        images = load_images(recipe, f)
        np.testing.assert_array_equal(images["shape"].pixels,
                                      read_image(str(tmp_path / f"height_{number:04d}.exr")).pixels)
        assert images["dark"].pixels[0, 0, 0] == pytest.approx(0.1 * number)
        alone = render({"shape": read_image(str(tmp_path / f"height_{number:04d}.exr")),
                        "dark": images["dark"], "bright": images["bright"]},
                       recipe.lights, recipe.params)
        np.testing.assert_array_equal(render(images, recipe.lights, recipe.params).rgba,
                                      alone.rgba)


def test_frames_round_trip_through_toml(tmp_path):
    recipe = _animated_recipe(tmp_path)
    text = recipe_to_toml(recipe, str(tmp_path))
    assert '[frames]\nmode = "ping-pong"' in text and "[frames.dark]\ncolumns = 2" in text
    (tmp_path / "again.toml").write_text(text)
    again = load_recipe(str(tmp_path / "again.toml"))
    assert again.frames == recipe.frames and again.slots() == recipe.slots()


@pytest.mark.parametrize("frames, message", [
    ({"mode": "bounce"}, "frames.mode: must be one of cyclic, ping-pong, hold"),
    ({"rate": 0}, r"frames.rate: 0 is out of range \[0.01, 100.0\]"),
    ({"offset": 1.5}, 'frames.offset: expected an integer or "auto"'),
    ({"colums": 2}, "frames.colums: unknown key"),
    ({"drak": {"columns": 2}}, r"frames.drak: unknown image channel \(did you mean 'dark'\?\)"),
    ({"dark": {"columns": 2, "rows": 2, "count": 5}},
     r"5 frames do not fit a sheet of 2 × 2 cells \(4\)"),
])
def test_bad_frames_tables_name_the_key(tmp_path, frames, message):
    write_exr(str(tmp_path / "n.exr"), np.ones((4, 4, 3), np.float32))
    data = {"images": {"shape": "n.exr", "dark": "n.exr"}, "frames": frames}
    with pytest.raises(RecipeError, match=message):
        parse_recipe(data, str(tmp_path))


def test_a_recipes_pattern_that_matches_nothing(tmp_path):
    write_exr(str(tmp_path / "n.exr"), np.ones((4, 4, 3), np.float32))
    with pytest.raises(RecipeError, match=r"images.shape: .*walk_####.exr: no file matches"):
        parse_recipe({"images": {"shape": "walk_####.exr", "dark": "n.exr"}}, str(tmp_path))


def test_a_sheet_of_frames_laid_out_as_other_tools_do():
    """testkit's sheet writer: cell 0 top left, cell 1 to its right, row 2 below."""
    frames = [np.full((2, 2), i, np.float32) for i in range(4)]
    sheet = sheet_of(frames, 2, 2, margin=1, spacing=1)
    top_row_first = sheet[::-1]
    assert top_row_first[1, 1] == 0 and top_row_first[1, 4] == 1 and top_row_first[4, 1] == 2


def test_a_loop_lasts_until_every_slot_comes_round_together():
    """Exported pages and sheets of maps hold one loop: the slots' periods' least common
    multiple (a 24- and a 16-frame cycle: 48; ping-pong over 4: 6; on twos: 8), or, beyond
    MAX_LOOP frames or for periods that never line up, the longest."""
    from dynpaint_addon.core.frames import SheetGrid
    from dynpaint_addon.inputs.painting_frames import SlotFrames

    def loop(*slots):
        return PaintingFrames({f"c{i}": SlotFrames("c", "p", "sheet", mode=m, count=n, rate=r,
                                                   grid=SheetGrid(n, 1))
                               for i, (n, m, r) in enumerate(slots)}).loop()
    assert loop((24, "cyclic", 1.0)) == 24 and loop((24, "cyclic", 1.0), (16, "cyclic", 1.0)) == 48
    assert loop((4, "ping-pong", 1.0)) == 6 and loop((4, "cyclic", 0.5)) == 8
    assert loop((24, "cyclic", 1.0), (7, "cyclic", 1.0)) == 168
    assert loop((24, "cyclic", 1.0), (5, "cyclic", 0.7)) == 24          # 600 > MAX_LOOP
    assert PaintingFrames({}).loop() == 1
