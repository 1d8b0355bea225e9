"""A painting that moves, in Blender (pipeline.md §16): its slots' frames at a scene frame.

The artist's images stay in the painting's slots: a sequence is a Blender image sequence
(source 'SEQUENCE': its files on disk, by relative path, as Blender's Open makes it), a
sprite sheet an ordinary image (packable). The frame mapping is the painting's `frames`
settings, or a slot's own (`frames_<channel>` with `frames_<channel>_own`). What the material
samples of a moving slot is a copy of the painting frame's pixels — one of the derived images
(nodegraph/derived_inputs.py), whose key holds the painting frame — remade when the scene's
frame shows another drawing; the cos-θ bake's key holds the shape's frame too.

Frames are read through painting_frames.PaintingFrames, one per painting (its cache bounded
by the add-on's preference *Frame Cache*, 1 GB by default), made again when its images or
mappings change; a still image is read from Blender each time, as before (its pixels may have
been painted on).
"""
import os
import re

import bpy

from ...inputs.imageio import image_data_from_blender, read_image
from ...inputs.painting_frames import DEFAULT_CACHE_MB, HELD, PaintingFrames, painting_slots
from .settings import channel_images, frames_table

_PAINTINGS = {}      # material name → PaintingFrames
# the extension's module, which its preferences are registered under ("bl_ext.<repo>.<id>"
# when installed; the package itself when the add-on runs from the repository)
ADDON = __package__.rsplit(".dynpaint_addon", 1)[0]


def sequence_pattern(img):
    """A Blender image sequence's files as a frame-numbered pattern (its file's last number
    becomes ####, as Blender reads it), or None for any other image."""
    if img.source != "SEQUENCE":
        return None
    path = bpy.path.abspath(img.filepath_raw or img.filepath)
    folder, name = os.path.split(path)
    digits = list(re.finditer(r"\d+", name))
    if not digits:
        return None
    last = digits[-1]
    return os.path.join(folder, name[:last.start()] + "#" * len(last.group())
                        + name[last.end():])


def slot_path(img):
    """What PaintingFrames calls a slot's image: a sequence's pattern, else the image."""
    return sequence_pattern(img) or HELD + img.name


def _read(path):
    if path.startswith(HELD):
        return image_data_from_blender(bpy.data.images[path[len(HELD):]])
    return read_image(path)


def cache_mb():
    """How much of the frames is kept in memory (MB): the add-on's preference *Frame Cache*,
    else painting_frames.DEFAULT_CACHE_MB."""
    addon = bpy.context.preferences.addons.get(ADDON)
    return getattr(getattr(addon, "preferences", None), "frame_cache_mb", DEFAULT_CACHE_MB)


def frames_of(images, table):
    """{channel: bpy Image} and a recipe's frames table → PaintingFrames."""
    paths = {c: slot_path(img) for c, img in images.items()}
    return PaintingFrames(painting_slots(paths, table), cache_mb(), _read)


def painting_frames(mat):
    """The painting's PaintingFrames: one per painting, made from its images and mappings
    when first asked for and kept until one of them changes (sync.on_setting_changed, undo
    and file loads call forget_frames), so an update reads the settings once."""
    hit = _PAINTINGS.get(mat.name)
    if hit is None:
        s = mat.dynamic_painting
        hit = _PAINTINGS[mat.name] = frames_of(channel_images(s), frames_table(s))
    return hit


def moves(mat):
    """Does any of the painting's images move (a sequence, or a still read as a sheet)?"""
    return painting_frames(mat).animated


def now():
    """The scene frame being shown or rendered."""
    return bpy.context.scene.frame_current


def slot_frame(mat, channel, f=None):
    """What scene frame `f` (default: now) shows of a slot: its painting frame, or None for a
    still image."""
    slot = painting_frames(mat).slots.get(channel)
    return None if slot is None else slot.frame_of(now() if f is None else f)


def shown_frame(mat, channel, f=None):
    """slot_frame, of a sprite sheet the first of its cells with the same pixels: what bakes
    and derived images are kept by (PaintingFrames.shown_cell: a drawing held over frames
    is baked once)."""
    frames = painting_frames(mat)
    slot = frames.slots.get(channel)
    return None if slot is None else frames.shown_cell(channel, now() if f is None else f)


def frame_data(mat, channel, f=None):
    """A slot's pixels at scene frame `f` (default: now) → ImageData."""
    frames = painting_frames(mat)
    slot = frames.slots[channel]
    if slot.kind == "still":
        return image_data_from_blender(getattr(mat.dynamic_painting, f"image_{channel}"))
    return frames.image(channel, now() if f is None else f)


def painting_size(mat):
    """The painting's (width, height) in pixels: its shape image's, of a moving one the
    frame's (a sheet's cell; an image sequence's own size reads 0 × 0 until Blender shows
    it)."""
    s = mat.dynamic_painting
    if slot_frame(mat, "shape") is None:
        return tuple(s.image_shape.size)
    return frame_data(mat, "shape").size


def forget_frames(mat=None):
    """A painting's images or frame mappings changed (`mat`), or another file is open or undo
    brought back other settings (every painting): read them again when next asked."""
    if mat is None:
        _PAINTINGS.clear()
    else:
        _PAINTINGS.pop(mat.name, None)
