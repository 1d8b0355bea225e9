"""What one update of a painting reads from Blender, read once and passed down (issue 28).

A setting change, a light move or a frame change reads the painting's settings, images and
lights here, once, as glTF-Blender-IO builds its `export_settings` once per export; the
derived images, the bakes and the node tree are then made from this one `PaintingState`
instead of each converting the settings again. The Features and the derived-image plan come
from nodegraph/derived_inputs.prepare, the function every backend (material, compositor
group, web page) builds from.
"""
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Callable

from ...nodegraph.derived_inputs import Source, prepare
from ...nodegraph.features import Features
from .edits import version
from .frames import frame_data, shown_frame
from .images import bits_of, has_alpha, is_grey
from .lights import linked_lights
from .settings import channel_images, settings_to_params


@dataclass
class PaintingState:
    params: SimpleNamespace     # the settings as parameters (params.defaults() layout)
    images: dict                # {channel: bpy Image}: the artist's input images
    lights: list                # the linked light objects, in the tree's order
    features: Features          # what the graph is built for (§12)
    plan: list                  # [derived_inputs.Derived]: the images numpy derives
    read: Callable = None       # channel → its ImageData now (a moving slot's frame, §16),
    #                             read once per state
    frame: tuple = ()           # the painting frame shown: (channel, its frame) of each slot
    #                             that moves (§16); () for a still painting


def image_source(img):
    """A Blender image as the derived-image plan knows it (no pixel read), and how many times
    its pixels were edited in place (edits.py)."""
    return Source(img.name, bits_of(img), tuple(img.size), has_alpha(img), version=version(img),
                  grey=is_grey(img))


def frame_source(img, data, frame):
    """A moving slot's image (§16) as the plan knows it: its frame's depth, size and alpha,
    and the painting frame (in every key made from it)."""
    return Source(img.name, data.bits, data.size, data.has_alpha, frame, version(img))


def read_state(mat, scene):
    """The painting as it is now → PaintingState. Raises ValueError when it lacks the images
    every painting needs (a shape image; a dark or a bright one)."""
    s = mat.dynamic_painting
    images = channel_images(s)
    if "shape" not in images:
        raise ValueError("the painting has no shape image (normal or height map)")
    if "dark" not in images and "bright" not in images:
        raise ValueError("the painting needs a dark or a bright image")
    p = settings_to_params(s)
    lights = linked_lights(mat, scene)
    f = scene.frame_current
    sources = {c: frame_source(img, frame_data(mat, c, f), frame)
               if (frame := shown_frame(mat, c, f)) is not None else image_source(img)
               for c, img in images.items()}
    features, plan = prepare(p, sources, [o.data.type.lower() for o in lights])
    reads = {}

    def read(c):           # (each image read once per update: the derived images, the bake)
        if c not in reads:
            reads[c] = frame_data(mat, c, f)
        return reads[c]
    return PaintingState(p, images, lights, features, plan, read,
                         tuple((c, src.frame) for c, src in sources.items()
                               if src.frame is not None))
