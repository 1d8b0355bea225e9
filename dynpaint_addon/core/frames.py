"""Paintings that move (§16, issue 31): which painting frame a scene frame shows, and
where a frame lies in a sequence of files or a sprite sheet. No bpy, no file reading.

The frame mapping is the one Blender artists know from the Image Texture node (an image
sequence's Frames, Start Frame, Offset and Cyclic; BKE_image_user_frame_calc), with two
more endings and a rate:

    n = floor((f − start) · rate) + 1          the sequence's own frame, 1 at `start`
    cyclic:    n wraps into 1 … count          (count + 1 shows frame 1 again)
    ping-pong: 1 … count … 2, 1 … again         (the ends shown once per swing)
    hold:      n clamped to 1 … count           (Blender without Cyclic)
    file number = n + offset; a sprite sheet's cell = file number − 1

With the defaults (start 1, offset 0, rate 1) scene frame f shows file number f, as in
Blender, and a sheet's cell f − 1.

    >>> [frame_number(f, count=3, mode="cyclic") for f in range(0, 8)]
    [3, 1, 2, 3, 1, 2, 3, 1]
    >>> [frame_number(f, count=3, mode="ping-pong") for f in range(1, 9)]
    [1, 2, 3, 2, 1, 2, 3, 2]
    >>> [frame_number(f, count=3, mode="hold") for f in (-5, 1, 2, 9)]
    [1, 1, 2, 3]
    >>> expand_pattern("walk_####.png", 7), expand_pattern("walk_%04d.png", 12)
    ('walk_0007.png', 'walk_0012.png')
"""
import math
import re
from dataclasses import dataclass

MODES = ("cyclic", "ping-pong", "hold")

# Blender's frame numbers in a file name (`walk_####.png`: as many digits as #), and C's
# (`walk_%04d.png`)
_HASHES = re.compile(r"#+")
_PRINTF = re.compile(r"%(0?)(\d*)d")


def frame_number(f, start=1, offset=0, count=None, mode="hold", rate=1.0):
    """The file number scene frame `f` shows (the module's mapping).

    Parameters
    ----------
    f : int
        The scene frame (negative frames are frames too).
    start : int
        The scene frame that shows the sequence's first frame.
    offset : int
        Added to the sequence's frame to give the file number.
    count : int or None
        How many frames the sequence has (None: unbounded, no wrapping or holding).
    mode : str
        'cyclic', 'ping-pong' or 'hold' (MODES): what the frames beyond the sequence show.
    rate : float
        Painting frames per scene frame (0.5: each drawing held for two frames, "on twos").
    """
    if mode not in MODES:
        raise ValueError(f"frame mode must be one of {', '.join(MODES)}, got {mode!r}")
    if not (rate > 0 and math.isfinite(rate)):
        raise ValueError(f"painting frames per scene frame must be a number > 0, got {rate!r}")
    n = math.floor((f - start) * rate + 1e-9)          # 0-based; a hair over for 1/3-rates
    if count is not None:
        if count < 1:
            raise ValueError(f"a sequence needs at least one frame, got {count}")
        if mode == "cyclic":
            n %= count
        elif mode == "ping-pong":
            period = max(1, 2 * count - 2)
            n %= period
            n = n if n < count else period - n
        else:
            n = min(max(n, 0), count - 1)
    return n + 1 + offset


def expand_pattern(pattern, number):
    """A frame-numbered file name for `number`: Blender's `####` (zero-padded to the number
    of #) or C's `%04d`; a name with neither is returned as it is (a still image)."""
    if _HASHES.search(pattern):
        return _HASHES.sub(lambda m: f"{number:0{len(m.group())}d}", pattern, count=1)
    if _PRINTF.search(pattern):
        return _PRINTF.sub(lambda m: f"{number:{m.group(1)}{m.group(2)}d}", pattern, count=1)
    return pattern


def is_pattern(name):
    """Whether a file name holds a frame number to fill in (`####`, `%04d`)."""
    return bool(_HASHES.search(name) or _PRINTF.search(name))


@dataclass(frozen=True)
class SheetGrid:
    """A sprite sheet's layout: `columns` × `rows` cells, `count` of them used (row by row
    from the top left), `margin` pixels around the grid and `spacing` between cells."""
    columns: int
    rows: int
    count: int = 0              # 0: every cell
    margin: int = 0
    spacing: int = 0

    def frames(self):
        return self.count or self.columns * self.rows

    @classmethod
    def squarest(cls, count):
        """The grid closest to square that holds `count` frames (as many columns as rows, or
        one more), every cell but the last row's used."""
        columns = math.ceil(math.sqrt(count))
        return cls(columns, math.ceil(count / columns), count)

    def sheet_size(self, cell_width, cell_height):
        """The (width, height) of a sheet of cells of that size on this grid (cell_size's
        inverse)."""
        return (2 * self.margin + self.columns * cell_width + (self.columns - 1) * self.spacing,
                2 * self.margin + self.rows * cell_height + (self.rows - 1) * self.spacing)

    def cell_size(self, width, height):
        """The (width, height) of one cell of a sheet of width × height pixels; ValueError
        naming the numbers when the sheet does not divide into the grid."""
        if self.columns < 1 or self.rows < 1:
            raise ValueError(f"a sprite sheet needs at least one column and one row, got "
                             f"{self.columns} × {self.rows}")
        if self.count > self.columns * self.rows:
            raise ValueError(f"{self.count} frames do not fit a sheet of {self.columns} × "
                             f"{self.rows} cells ({self.columns * self.rows})")
        inner_w = width - 2 * self.margin - (self.columns - 1) * self.spacing
        inner_h = height - 2 * self.margin - (self.rows - 1) * self.spacing
        if inner_w <= 0 or inner_h <= 0 or inner_w % self.columns or inner_h % self.rows:
            raise ValueError(
                f"a {width}×{height} sheet does not divide into {self.columns} × {self.rows} "
                f"cells (margin {self.margin}, spacing {self.spacing}): its cells would be "
                f"{inner_w / self.columns:.4g} × {inner_h / self.rows:.4g} pixels")
        return inner_w // self.columns, inner_h // self.rows

    def cell_box(self, index, width, height):
        """Where cell `index` (0-based, row by row from the top left) lies in the sheet, as
        (x0, y0, x1, y1) pixel bounds with y up (row 0 of the array at the bottom, §0)."""
        if not 0 <= index < self.frames():
            raise ValueError(f"frame {index + 1} of a sheet of {self.frames()} frames")
        cw, ch = self.cell_size(width, height)
        col, row = index % self.columns, index // self.columns
        x0 = self.margin + col * (cw + self.spacing)
        top = self.margin + row * (ch + self.spacing)          # from the top of the image
        y1 = height - top
        return x0, y1 - ch, x0 + cw, y1


def sheet_cell(pixels, grid, index):
    """Cell `index` of a sprite sheet's pixels (H, W, …), y up → a view of it."""
    h, w = pixels.shape[:2]
    x0, y0, x1, y1 = grid.cell_box(index, w, h)
    return pixels[y0:y1, x0:x1]
