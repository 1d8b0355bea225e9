"""Make Shape on a painting that moves (pipeline.md §16): one method run on every frame of a
sequence of files or a sprite sheet, its shapes written in the same layout. No bpy here.

A method's input images are read per frame by `inputs.painting_frames.FrameInputs` (a
frame-numbered name gives its file of that number, a sprite sheet its cell, a still image the
same image each frame). Frames that hold the same pixels give the same shape, bit for bit, and
a part of the drawing that does not change keeps its heights (core/laplace.solve_parts
solves each part alone). The heights of all frames share one floor (integration: the lowest
point of the whole sequence is 0) and one white for a 16-bit PNG, so a frame's heights never
shift because another frame dips lower. Memory holds one frame, or the sheet: the frames wait
on disk between the two passes.

    >>> [h.tolist() for h in on_one_floor([np.array([1.0, 2.0]), np.array([0.5, 3.0])])]
    [[0.5, 1.5], [0.0, 2.5]]
"""
import os
import tempfile

import numpy as np


class MadeFrames:
    """The shapes of every frame between the two passes (.npy files in a temporary folder),
    with the lowest and highest value seen: `floor` and `top` for the second pass."""

    def __init__(self):
        self._dir = tempfile.TemporaryDirectory(prefix="dynpaint-frames-")
        self.count = 0
        self.low, self.high = np.inf, -np.inf

    def put(self, i, values):
        np.save(os.path.join(self._dir.name, f"{i}.npy"), values)
        self.low = min(self.low, float(np.min(values)))
        self.high = max(self.high, float(np.max(values)))
        self.count = max(self.count, i + 1)

    def get(self, i):
        return np.load(os.path.join(self._dir.name, f"{i}.npy"))

    def close(self):
        self._dir.cleanup()


def on_one_floor(heights):
    """The heights of every frame shifted by one amount, so that the lowest point of them all
    is 0 (integrated heights: no frame moves because another dips lower)."""
    low = min(float(h.min()) for h in heights)
    return [h - low for h in heights]


def fill_sheet(cells, grid, size, fill):
    """Cells (y-up arrays of one size) laid into a sheet of `size` (width, height) on the
    grid, `fill` between them (a height of 0, a flat normal)."""
    w, h = size
    first = cells[0]
    sheet = np.empty((h, w) + first.shape[2:], first.dtype)
    sheet[...] = fill
    for i, cell in enumerate(cells):
        x0, y0, x1, y1 = grid.cell_box(i, w, h)
        sheet[y0:y1, x0:x1] = cell
    return sheet
