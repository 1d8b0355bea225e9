"""make-shape on a painting that moves (§16, issue 31): a sequence or sprite sheet in, the
same layout out, and no flicker where the drawing does not change — same pixels in, same
heights out, bit for bit (EXR frames: no Blender needed)."""
import numpy as np
import pytest

from conftest import cli_in_process
from dynpaint_addon.cli import main as cli_main
from dynpaint_addon.core import laplace
from dynpaint_addon.core.frames import SheetGrid, sheet_cell
from dynpaint_addon.core.inflate import inflate
from dynpaint_addon.core.integrate import integrate
from dynpaint_addon.inputs.imageio import read_image, write_exr
from testkit.animated import moving_dome, write_sequence, write_sheet


def _masks(size=48, frames=6):
    """A dome that slides (its figure changes) and a square that stands still."""
    return [(h > 0).astype(np.float32) for h in moving_dome(size, frames, blink=(3,))]


def _static(size=48):
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    return (np.abs(x + 0.3) < 0.1) & (np.abs(y + 0.3) < 0.1)


def _cut_out_normals(mask):
    """The normals of an inflated figure, flat outside it (a sprite's normal map)."""
    z = inflate(mask).height
    gy, gx = np.gradient(z * len(z))
    n = np.dstack([-gx, -gy, np.ones_like(gx)])
    return np.where(mask[..., None], n / np.linalg.norm(n, axis=2, keepdims=True), [0, 0, 1])


def test_a_part_that_does_not_change_keeps_its_heights_bit_for_bit():
    """Inflation and integration solve each part alone (laplace.solve_parts): the square's
    heights do not move while the dome slides — with the whole image in one solve they moved
    (by 2e-6 here; by 4e-4 under a turning head, docs/frames-stability.md). An integrated
    part stands on the background around it: it keeps its heights where that does not change
    either (a sprite's flat background)."""
    masks = [m > 0 for m in _masks()]
    square = _static()
    by_parts = [inflate(m, "flat").height for m in masks]
    whole = [inflate(m, "flat", by_parts=False).height for m in masks]
    assert all(np.array_equal(h[square], by_parts[0][square]) for h in by_parts)
    assert max(np.abs(h[square] - whole[0][square]).max() for h in whole) > 0    # it moved
    normals = [_cut_out_normals(m) for m in masks]
    heights = [integrate(n, m, floor=0.0).height for n, m in zip(normals, masks)]
    assert all(np.array_equal(h[square], heights[0][square]) for h in heights)


def test_a_sequence_in_gives_a_sequence_out_each_frame_as_alone(tmp_path):
    write_sequence(str(tmp_path / "mask_####.exr"), _masks())
    r = cli_in_process("make-shape", "inflate", tmp_path / "mask_####.exr", "--profile", "flat",
                       "--out", tmp_path / "height_####.exr")
    assert r.returncode == 0, r.stderr
    assert "frame 5/6 (mask_0005.exr): the same pixels as frame 3: its shape" in r.stdout
    assert "wrote 6 frames" in r.stdout and "the figure is where" in r.stderr
    for n in range(1, 7):       # (each alone in this process: the command's own code)
        alone = tmp_path / f"alone_{n}.exr"
        assert cli_main(["make-shape", "inflate", str(tmp_path / f"mask_{n:04d}.exr"),
                         "--profile", "flat", "--out", str(alone)]) == 0
        np.testing.assert_array_equal(read_image(str(tmp_path / f"height_{n:04d}.exr")).pixels,
                                      read_image(str(alone)).pixels)


def test_a_sheet_in_gives_a_sheet_of_the_same_grid_out(tmp_path):
    masks = _masks()
    write_sheet(str(tmp_path / "sheet.exr"), masks, 4, 2, margin=3, spacing=2)
    write_sequence(str(tmp_path / "mask_####.exr"), masks)
    r = cli_in_process("make-shape", "inflate", tmp_path / "sheet.exr", "--columns", "4", "--rows",
                       "2", "--count", "6", "--margin", "3", "--spacing", "2", "--out",
                       tmp_path / "heights.exr")
    assert r.returncode == 0, r.stderr
    assert "wrote a sheet of 6 frames, 4 × 2 cells" in r.stdout
    assert cli_main(["make-shape", "inflate", str(tmp_path / "mask_####.exr"),
                     "--out", str(tmp_path / "h_####.exr")]) == 0
    sheet = read_image(str(tmp_path / "heights.exr")).pixels[..., 0]
    assert sheet.shape == read_image(str(tmp_path / "sheet.exr")).pixels.shape[:2]
    grid = SheetGrid(4, 2, 6, 3, 2)
    for i in range(6):
        np.testing.assert_array_equal(sheet_cell(sheet, grid, i),
                                      read_image(str(tmp_path / f"h_{i + 1:04d}.exr")).pixels[..., 0])
    assert not sheet[:3].any() and not sheet[:, :3].any()      # the margin stays 0


def test_integrated_frames_share_one_floor(tmp_path):
    """The lowest point of the whole sequence is 0, so no frame shifts because another dips."""
    masks = [m > 0 for m in _masks(frames=4)]
    for i, m in enumerate(masks):
        n = _cut_out_normals(m)
        write_exr(str(tmp_path / f"n_{i + 1:04d}.exr"), np.dstack([(n + 1) / 2, m]))
    r = cli_in_process("make-shape", "integrate", tmp_path / "n_####.exr", "--mask", "alpha",
                       "--encoding", "rgb", "--strength", "1", "--out", tmp_path / "z_####.exr")
    assert r.returncode == 0, r.stderr
    frames = [read_image(str(tmp_path / f"z_{i:04d}.exr")).pixels[..., 0] for i in range(1, 5)]
    assert min(f.min() for f in frames) == 0
    square = _static()
    assert all(np.array_equal(f[square], frames[0][square]) for f in frames)


@pytest.mark.parametrize("args, message", [
    (["mask_####.exr", "--out", "h.exr"], "a sequence's shapes need a frame number in the name"),
    (["mask_####.exr", "--columns", "2", "--out", "h_####.exr"],
     "is a sequence of files and a sheet grid of 2 × 1 was given"),
    (["nothing_####.exr", "--out", "h_####.exr"], "nothing_####.exr: no file matches"),
    (["mask_0001.exr", "--columns", "5", "--out", "h.exr"],
     "a 48×48 sheet does not divide into 5 × 1 cells"),
])
def test_bad_frames_say_what_is_wrong(tmp_path, args, message):
    write_sequence(str(tmp_path / "mask_####.exr"), _masks(frames=2))
    r = cli_in_process("make-shape", "inflate", *args, cwd=tmp_path)
    assert r.returncode != 0 and message in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_photometric_methods_run_frame_by_frame_too(tmp_path):
    """rg-photo and profiles take sequences as inflate and integrate do: the same numbers in
    every input's name, a sequence of normal maps out, each as the frame alone gives it."""
    rng = np.random.default_rng(3)
    for n in (1, 2):
        write_exr(str(tmp_path / f"photo_{n:04d}.exr"), rng.random((16, 16, 3), np.float32))
        for side in ("left", "right", "top"):
            write_exr(str(tmp_path / f"lit_{side}_{n:04d}.exr"),
                      rng.random((16, 16, 3), np.float32))
    r = cli_in_process("make-shape", "rg-photo", tmp_path / "photo_####.exr", "--out",
                       tmp_path / "n_####.exr")
    assert r.returncode == 0 and "wrote 2 frames" in r.stdout, r.stderr
    r = cli_in_process("make-shape", "profiles", "--left", tmp_path / "lit_left_####.exr",
                       "--right", tmp_path / "lit_right_####.exr", "--top",
                       tmp_path / "lit_top_####.exr", "--out", tmp_path / "p_####.exr")
    assert r.returncode == 0 and "wrote 2 frames" in r.stdout, r.stderr
    assert cli_main(["make-shape", "rg-photo", str(tmp_path / "photo_0002.exr"), "--out",
                     str(tmp_path / "alone.exr")]) == 0
    np.testing.assert_array_equal(read_image(str(tmp_path / "n_0002.exr")).pixels,
                                  read_image(str(tmp_path / "alone.exr")).pixels)


def test_a_part_met_again_is_not_solved_again():
    """solve_parts keeps the parts it solved lately (a stroke re-solves only the part it
    touched): a frame whose square is the last frame's solves the dome alone, and its heights
    equal a solve from nothing kept, bit for bit; a part moved whole is met again too (its
    own box holds the same pixels); what is kept stays under SOLVED_BYTES."""
    masks = [m > 0 for m in _masks()]
    laplace.forget_solved_parts()
    inflate(masks[0], "flat")
    assert len(laplace._SOLVED) == 2                                 # the square, the dome
    assert not np.array_equal(masks[1], masks[0])
    inflate(masks[1], "flat")
    assert len(laplace._SOLVED) == 2                                 # the dome slid
    stroke = masks[0].copy()
    stroke[40:44, 4:10] = True                                       # a dab of its own
    kept = inflate(stroke, "flat").height
    assert len(laplace._SOLVED) == 3                                 # the dab alone
    laplace.forget_solved_parts()
    assert np.array_equal(kept, inflate(stroke, "flat").height)
    bound, laplace.SOLVED_BYTES = laplace.SOLVED_BYTES, 48 * 48 * 8 * 4
    try:
        for m in masks:
            inflate(m, "flat")
        assert sum(z.nbytes for z, _, _ in laplace._SOLVED.values()) <= laplace.SOLVED_BYTES
    finally:
        laplace.SOLVED_BYTES = bound
