"""Folders of an artist's files as they arrive (issue 38), made by numpy (and Blender's JPEG
writer): what `dynpaint new`, `render FOLDER` and the walkthrough are tried on.

- `glass_eye`: nine files for one painting in the names and conventions artists use — a
  normal map, dark and lit paintings, an environment photograph (JPEG), a black background,
  a transparency mask painted in red, specular and gloss maps, and a reference photo that
  is no channel;
- `research_portrait`: a normal map made for the original research system (every pixel faces
  away under a standard decoder, vectors not unit length) with its dark and bright images;
- `cutout`: one painting with its figure in the alpha and no shape image;
- `cut_short`: a painting whose bright image is a JPEG cut short in copying;
- `write_bomb`: a small PNG file that declares a huge image (a decompression bomb, or a poster
  scan's size).

Each writer returns the folder's path.
"""
import os
import struct
import zlib

import numpy as np

from dynpaint_addon.inputs.imageio import write_png
from testkit import example_paintings as ex


def write_jpeg(path, rgb, quality=90):
    """RGB 0..1 (y-up) as a JPEG by Blender's writer (the values as they are, no view
    transform), as a painting program exports one."""
    import bpy
    h, w = rgb.shape[:2]
    img = bpy.data.images.new("testkit jpeg", w, h, alpha=False, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    rgba = np.ones((h, w, 4), np.float32)
    rgba[..., :3] = rgb
    img.pixels.foreach_set(rgba.ravel())
    scene = bpy.context.scene
    scene.view_settings.view_transform = "Standard"
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.quality = "JPEG", "RGB", quality
    img.save_render(path, scene=scene)
    bpy.data.images.remove(img)
    return path


def _paint(size, figure, colour, alpha=None):
    """A painted image: `colour` over the figure with soft strokes, darker outside."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    strokes = 0.05 * np.sin(40 * x + 9 * y) * np.cos(23 * y)
    rgb = np.where(figure[..., None], np.asarray(colour) + strokes[..., None],
                   np.asarray(colour) * 0.3)
    rgb = np.clip(rgb, 0, 1)
    return rgb if alpha is None else np.dstack([rgb, alpha])


def glass_eye(folder, size=96):
    """Nine files of one glass painting, named as artists name them."""
    os.makedirs(folder, exist_ok=True)
    n, inside = ex.sphere(size, 0.4)
    p = lambda name: os.path.join(folder, name)          # noqa: E731
    write_png(p("Eye_normal.png"), ex.normal_map_rgb(n))
    write_png(p("Eye_dark.png"), _paint(size, inside, (0.1, 0.12, 0.25)))
    write_png(p("Eye_lit.png"), _paint(size, inside, (0.55, 0.7, 0.95)))
    write_jpeg(p("Eye_env.jpg"), ex.photograph(size, size, seed=2))
    write_png(p("Eye_background.png"), np.zeros((size, size, 3)))
    write_png(p("Eye_mask.png"), ex.red_mask(inside.astype(float)))
    write_png(p("Eye_spec.png"), np.full((size, size, 3), 0.9))
    write_png(p("Eye_gloss.png"), inside.astype(float))
    write_jpeg(p("reference_photo.jpg"), ex.photograph(size, size, seed=5))
    return folder


def research_portrait(folder, size=96):
    """A normal map as the original research system's artists made it, with its paintings."""
    os.makedirs(folder, exist_ok=True)
    n, inside = ex.sphere(size, 0.4)
    write_png(os.path.join(folder, "picasso_normal.png"), ex.normal_map_all_away(n))
    write_png(os.path.join(folder, "picasso_dark.png"), _paint(size, inside, (0.2, 0.1, 0.1)))
    write_png(os.path.join(folder, "picasso_bright.png"), _paint(size, inside, (0.9, 0.7, 0.5)))
    return folder


def cutout(folder, size=96):
    """One painting with its figure in the alpha, and no shape image."""
    os.makedirs(folder, exist_ok=True)
    _, inside = ex.sphere(size, 0.3)
    alpha = inside.astype(float)
    write_png(os.path.join(folder, "pear.png"), _paint(size, inside, (0.8, 0.7, 0.2), alpha))
    return folder


def cut_short(folder, size=256, keep=0.3):
    """A painting (normal map, dark image) whose bright image is a JPEG of which only the
    first `keep` of the bytes arrived."""
    os.makedirs(folder, exist_ok=True)
    n, inside = ex.sphere(size, 0.4)
    write_png(os.path.join(folder, "pear_normal.png"), ex.normal_map_rgb(n))
    write_png(os.path.join(folder, "pear_dark.png"), _paint(size, inside, (0.3, 0.2, 0.05)))
    full = write_jpeg(os.path.join(folder, "full.jpg"), _paint(size, inside, (0.8, 0.7, 0.2)))
    data = open(full, "rb").read()
    os.remove(full)
    with open(os.path.join(folder, "pear_bright.jpg"), "wb") as fh:
        fh.write(data[:int(len(data) * keep)])
    return folder


def write_bomb(path, size=30000):
    """A PNG of size × size black RGB pixels, about 2.6 MB for 30000² (zlib packs the rows of
    zeros a thousand times over): what a reader must refuse before decoding. Written in a
    blink: a block of rows deflated once and repeated (a full flush leaves no state, so each
    copy is what deflating the block again would give), then the last rows; the checksum of
    n zeros is Adler-32's closed form."""
    row = bytes(1 + 3 * size)                      # filter byte 0, then the row's zeros
    block_rows = 256
    pack = zlib.compressobj(9, zlib.DEFLATED, -15)            # raw deflate: the header below
    block = pack.compress(row * block_rows) + pack.flush(zlib.Z_FULL_FLUSH)
    tail = pack.compress(row * (size % block_rows)) + pack.flush()
    n = size * len(row)
    data = (b"\x78\xda" + block * (size // block_rows) + tail
            + struct.pack(">I", (n % 65521) << 16 | 1))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body))
    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 2,
                                                                  0, 0, 0))
                 + chunk(b"IDAT", data) + chunk(b"IEND", b""))
    return path
