"""Make Shape on a painting that moves (pipeline.md §16): one method run on every frame of a
sequence of files or a sprite sheet, its shapes written in the same layout. No bpy here.

A method's input images are read per frame: a frame-numbered name (`walk_####.png`) gives its
file of that number, every input of a sprite sheet (a grid) its cell, a still image the same
image each frame. Frames that hold the same pixels give the same shape, bit for bit, and
a part of the drawing that does not change keeps its heights (core/laplace.solve_parts
solves each part alone). The heights of all frames share one floor (integration: the lowest
point of the whole sequence is 0) and one white for a 16-bit PNG, so a frame's heights never
shift because another frame dips lower. Memory holds one frame, or the sheet: the frames wait
on disk between the two passes.

    >>> grid = SheetGrid(2, 1)
    >>> FrameInputs(["sheet.png"], grid).names()
    ['cell 1', 'cell 2']
"""
import hashlib
import os
import tempfile

import numpy as np

# (SheetGrid: the docstring's example)
from .core.frames import SheetGrid, expand_pattern, is_pattern, sheet_cell
from .core.input_rules import ImageData
from .imageio import read_image
from .painting_frames import FrameError, sequence_numbers


class FrameInputs:
    """A method's input files as frames: the numbers of the first frame-numbered input (every
    other one must have them too), or the cells of a sheet (`grid`), or one still frame."""

    def __init__(self, paths, grid=None):
        self.paths = [p for p in paths if p]
        patterns = [p for p in self.paths if is_pattern(os.path.basename(p))]
        if patterns and grid is not None:
            raise FrameError(f"{patterns[0]} is a sequence of files and a sheet grid of "
                             f"{grid.columns} × {grid.rows} was given: one or the other")
        self.grid = grid
        self.pattern = patterns[0] if patterns else None
        if self.pattern:
            self.numbers = list(sequence_numbers(self.pattern))
        elif grid is not None:
            self.numbers = list(range(grid.frames()))
        else:
            self.numbers = [None]
        self._images = {}              # stills and sheets, read once

    @property
    def animated(self):
        return self.numbers != [None]

    def __len__(self):
        return len(self.numbers)

    def names(self):
        if self.pattern:
            return [os.path.basename(expand_pattern(self.pattern, n)) for n in self.numbers]
        return [f"cell {n + 1}" for n in self.numbers] if self.grid else ["the image"]

    def read(self, path, i):
        """Input `path` at frame `i` (0-based) → ImageData."""
        n = self.numbers[i]
        if is_pattern(os.path.basename(path)):
            file = expand_pattern(path, n)
            if not os.path.isfile(file):
                raise FrameError(f"{os.path.basename(file)}: frame {n} of "
                                 f"{os.path.basename(path)} is missing (the frames follow "
                                 f"{os.path.basename(self.pattern)}'s numbers)")
            return read_image(file)
        if path not in self._images:
            self._images[path] = read_image(path)
        data = self._images[path]
        if self.grid is None:
            return data
        try:
            cell = sheet_cell(data.pixels, self.grid, n)
        except ValueError as exc:
            raise FrameError(f"{os.path.basename(path)}: {exc}") from None
        return ImageData(np.ascontiguousarray(cell), data.bits, f"{data.name} [{n + 1}]")

    def sheet_size(self):
        """The (width, height) of the input sheet (the output sheet's)."""
        first = next(p for p in self.paths if p in self._images)
        return self._images[first].size

    def fingerprint(self, i):
        """A digest of every input's pixels at frame i: frames that hold the same pixels
        have the same one (their shape is made once)."""
        digest = hashlib.blake2b(digest_size=16)
        for path in self.paths:
            px = self.read(path, i).pixels
            digest.update(str(px.shape).encode())
            digest.update(np.ascontiguousarray(px).tobytes())
        return digest.hexdigest()


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
