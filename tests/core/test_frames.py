"""Paintings that move, first step (issue 31): the frame mapping, frame-numbered file names and
sprite-sheet cells (core/frames.py)."""
import numpy as np
import pytest

from dynpaint_addon.core.frames import (SheetGrid, expand_pattern, frame_number, is_pattern,
                                        sheet_cell)


def test_by_default_scene_frame_f_shows_file_number_f():
    assert [frame_number(f) for f in (-3, 0, 1, 2, 250)] == [-3, 0, 1, 2, 250]


@pytest.mark.parametrize("mode, want", [
    ("cyclic", [2, 3, 4, 1, 2, 3, 4, 1, 2, 3, 4, 1]),
    ("ping-pong", [4, 3, 2, 1, 2, 3, 4, 3, 2, 1, 2, 3]),
    ("hold", [1, 1, 1, 1, 2, 3, 4, 4, 4, 4, 4, 4]),
])
def test_the_endings_before_and_after_the_sequence(mode, want):
    """A sequence of 4 frames starting at scene frame 5: frames 2 … 13."""
    assert [frame_number(f, start=5, count=4, mode=mode) for f in range(2, 14)] == want


def test_offset_rate_and_negative_frames():
    assert frame_number(1, offset=10) == 11                       # Blender's Offset
    assert [frame_number(f, rate=0.5) for f in range(1, 7)] == [1, 1, 2, 2, 3, 3]  # on twos
    assert [frame_number(f, rate=1 / 3) for f in range(1, 8)] == [1, 1, 1, 2, 2, 2, 3]
    assert [frame_number(f, rate=2) for f in range(1, 4)] == [1, 3, 5]  # every other drawing
    assert frame_number(-7, count=3, mode="cyclic") == 2          # (−7 − 1) mod 3 = 1: file 2
    assert frame_number(-7, count=3, mode="ping-pong") == 1
    assert frame_number(0, count=1, mode="ping-pong") == 1        # one frame: always it


@pytest.mark.parametrize("kwargs, message", [
    ({"mode": "bounce"}, "frame mode must be one of cyclic, ping-pong, hold"),
    ({"rate": 0}, "painting frames per scene frame must be a number > 0"),
    ({"count": 0}, "a sequence needs at least one frame"),
])
def test_bad_mappings_say_what_is_wrong(kwargs, message):
    with pytest.raises(ValueError, match=message):
        frame_number(1, **kwargs)


def test_frame_numbered_names_in_blenders_and_cs_conventions():
    assert expand_pattern("walk_####.png", 7) == "walk_0007.png"
    assert expand_pattern("walk_#.png", 12) == "walk_12.png"
    assert expand_pattern("walk_%04d.png", 7) == "walk_0007.png"
    assert expand_pattern("walk_%d.png", 7) == "walk_7.png"
    assert expand_pattern("still.png", 7) == "still.png"
    assert is_pattern("a_####.exr") and is_pattern("a.%03d.png") and not is_pattern("a.png")


def test_sheet_cells_run_row_by_row_from_the_top_left():
    """A 3 × 2 sheet of 4 × 5 px cells, margin 1, spacing 2: each cell filled with its index;
    arrays are y up, so the first row of cells is at the top (the end) of the array."""
    grid = SheetGrid(columns=3, rows=2, count=5, margin=1, spacing=2)
    w, h = 2 * 1 + 3 * 4 + 2 * 2, 2 * 1 + 2 * 5 + 1 * 2
    sheet = np.full((h, w), -1.0)
    for i in range(6):
        col, row = i % 3, i // 3
        x0 = 1 + col * 6
        top = 1 + row * 7
        sheet[h - top - 5:h - top, x0:x0 + 4] = i
    assert grid.cell_size(w, h) == (4, 5) and grid.frames() == 5
    for i in range(5):
        cell = sheet_cell(sheet, grid, i)
        assert cell.shape == (5, 4) and np.all(cell == i)
    with pytest.raises(ValueError, match="frame 6 of a sheet of 5 frames"):
        grid.cell_box(5, w, h)


@pytest.mark.parametrize("grid, size, message", [
    (SheetGrid(3, 2), (100, 40), "a 100×40 sheet does not divide into 3 × 2 cells"),
    (SheetGrid(2, 2, count=5), (64, 64), "5 frames do not fit a sheet of 2 × 2 cells"),
    (SheetGrid(0, 2), (64, 64), "at least one column and one row"),
])
def test_bad_sheets_name_the_numbers(grid, size, message):
    with pytest.raises(ValueError, match=message):
        grid.cell_size(*size)


def test_a_still_part_of_a_cut_out_keeps_its_integrated_heights_bit_for_bit():
    """§16, issue 39: the shadows' integrated relief of a moving painting (a normal map with an
    alpha) solves each part alone and stands it on its background, so a part whose pixels do
    not change keeps its heights bit for bit while another part moves and dips lower."""
    from dynpaint_addon.core.input_rules import ImageData
    from dynpaint_addon.core.pipeline import normal_map_relief_px
    size = 64
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size

    def frame(cx, radius):
        n = np.zeros((size, size, 3))
        n[..., 2] = 1
        mask = np.zeros((size, size), bool)
        for c, r in (((0.25, 0.25), 0.15), ((cx, 0.7), radius)):
            dx, dy = (x - c[0]) / r, (y - c[1]) / r
            disc = dx * dx + dy * dy < 1
            n[disc] = np.stack([dx[disc], dy[disc], np.sqrt(1 - dx[disc] ** 2 - dy[disc] ** 2)], -1)
            mask |= disc
        rgba = np.dstack([(n + 1) / 2, mask]).astype(np.float32)
        return normal_map_relief_px(n.astype(np.float32), ImageData(rgba, 32, "n")), mask
    z0, m0 = frame(0.6, 0.2)
    z1, _ = frame(0.7, 0.25)              # the other part moves and grows (its rim dips lower)
    still = m0 & (x < 0.5) & (y < 0.5)
    assert np.array_equal(z0[still], z1[still])
    assert not np.array_equal(z0[~still], z1[~still])
