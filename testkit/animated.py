"""Paintings that move, as other tools write them (§16): frame-numbered files (Blender's
`name_####.png`, ffmpeg's `name_%04d.png`) and sprite sheets (a grid of cells row by row from
the top left, with a margin and spacing, as TexturePacker, Aseprite and Godot's SpriteFrames
expect). The frames are y-up arrays (core convention); the writers flip them into files."""
import os

import numpy as np

from dynpaint_addon.core.frames import expand_pattern
from dynpaint_addon.inputs.imageio import write_exr, write_png


def moving_dome(size, frames, radius=0.22, travel=0.25, blink=()):
    """`frames` height fields (size², 0 … 1): a dome that slides right and back (one
    cosine cycle); its left half stays put near the start; frames in `blink` are flattened
    (a drawing that changes by a lot in one frame). Also the frames where nothing moves: a
    static square in the lower left corner, the same pixels every frame."""
    yy, xx = np.mgrid[0:size, 0:size]
    x = (xx + 0.5) / size - 0.5
    y = (yy + 0.5) / size - 0.5
    out = []
    for i in range(frames):
        cx = -0.1 + travel * 0.5 * (1 - np.cos(2 * np.pi * i / frames))
        r2 = (x - cx) ** 2 + (y - 0.1) ** 2
        h = np.sqrt(np.clip(radius ** 2 - r2, 0, None)) / radius
        if i in blink:
            h = h * 0.2
        static = (np.abs(x + 0.3) < 0.1) & (np.abs(y + 0.3) < 0.1)
        out.append(np.where(static, 0.5, h).astype(np.float32))
    return out


def write_sequence(pattern, frames, first=1, bits=32):
    """Write frames as frame-numbered files from number `first` (.exr float, or .png of
    `bits` 8/16) → the paths."""
    paths = []
    for i, px in enumerate(frames):
        path = expand_pattern(pattern, first + i)
        _write(path, px, bits)
        paths.append(path)
    return paths


def sheet_of(frames, columns, rows, margin=0, spacing=0, fill=0.0):
    """Frames (equal size, y-up) laid out row by row from the top left → one sheet, y-up."""
    h, w = frames[0].shape[:2]
    extra = frames[0].shape[2:]
    sh = 2 * margin + rows * h + (rows - 1) * spacing
    sw = 2 * margin + columns * w + (columns - 1) * spacing
    sheet = np.full((sh, sw) + extra, fill, np.float32)
    for i, px in enumerate(frames):
        col, row = i % columns, i // columns
        x0 = margin + col * (w + spacing)
        top = margin + row * (h + spacing)
        sheet[sh - top - h:sh - top, x0:x0 + w] = px
    return sheet


def write_sheet(path, frames, columns, rows, margin=0, spacing=0, bits=32):
    _write(path, sheet_of(frames, columns, rows, margin, spacing), bits)
    return path


def _write(path, px, bits):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    if path.endswith(".exr"):
        write_exr(path, px)
    else:
        write_png(path, np.clip(px, 0, 1), bits=bits)
