"""A shape painted in layers (issue 41: the add-on's Paint Shape; docs/addon.md).

The artist paints two images over the painting: a **figure mask** (white where the figure is)
and a **height layer** (grey ½ is the canvas; lighter raises, darker lowers). The shape image
the painting reads is made from them, in image widths:

    height = base + relief(mask) + strength · (layer − ½)

- base: the painting's own height map before Paint Shape (its §2 pre-blur and scale), or 0;
  over a normal map, the painted relief's slopes are added to the map's own instead
  (painted_normals: the made shape is a normal map);
- relief: the mask inflated part by part (core.inflate), its painting's luminance embossed
  as detail, then the effects (shapes/relief.py: bevel, smoothing, structure);
- strength: image widths of relief for a layer painted from ½ to white.

No bpy here: the add-on (blender/state/painted.py) keeps the relief while only the height
layer changes, so a stroke on it changes the made image in the stroke's box alone (and the
bake follows incrementally, core/strokes.py).

>>> import numpy as np
>>> mask = np.zeros((64, 64), bool); mask[16:48, 16:48] = True
>>> layer = np.full((64, 64), 0.5); layer[0, 0] = 1.0
>>> z = painted_height(None, figure_relief(mask), layer, 0.1)
>>> round(float(z[0, 0]), 3), bool(z[32, 32] > 0.1), float(z[2, 2])
(0.05, True, 0.0)
>>> flat = np.dstack([np.zeros((64, 64)), np.zeros((64, 64)), np.ones((64, 64))])
>>> bool(np.allclose(painted_normals(flat, np.zeros((64, 64))), flat))
True
"""
import numpy as np

from .methods import OPTIONS as MAKE_SHAPE_OPTIONS
from .relief import snapped_relief

NEUTRAL = 0.5        # the height layer's canvas: a grey both Add and Subtract brushes move
MASK_LEVEL = 0.5     # a mask pixel at or above it is the figure

# The relief's options: Make Shape › Inflate's (bevel, smoothing, detail, structure), without
# the files the command line reads (the add-on gives images) and its mask channel
OPTIONS = tuple(o for o in MAKE_SHAPE_OPTIONS if "inflate" in o.methods
                and o.kind != "file" and o.name != "mask_channel")


def defaults():
    """{option name: default} of the relief."""
    return {o.name: o.default for o in OPTIONS}


def painted_figure(mask):
    """The figure (H, W) bool of a painted mask (bool, or 0..1 read at MASK_LEVEL)."""
    mask = np.asarray(mask)
    return mask if mask.dtype == bool else mask >= MASK_LEVEL


def figure_relief(mask, luminance=None, structure_tile=None, **values):
    """The figure's relief (H, W) in image widths (shapes/relief.py): the painted mask
    (painted_figure) snapped onto the painting's edges where values['snap'] asks, inflated,
    `luminance` embossed, the effects — `values` OPTIONS, their defaults where not given."""
    return snapped_relief(painted_figure(mask), luminance, structure_tile,
                          {**defaults(), **values})


def painted_height(base, relief, layer, strength):
    """base + relief + strength · (layer − ½), image widths (float32); base and layer may be
    None (nothing there)."""
    z = np.asarray(relief, np.float32).copy()
    if base is not None:
        z += np.asarray(base, np.float32)
    if layer is not None:
        z += np.float32(strength) * (np.asarray(layer, np.float32) - np.float32(NEUTRAL))
    return z


def painted_normals(base_normals, height):
    """A normal map painted over: the base's unit normals (H, W, 3) tilted by the slopes of the
    painted relief `height` (image widths; §2's central differences) — slopes add, so a
    relief of 0 gives the base's normals back."""
    h, w = height.shape
    z = np.asarray(height, np.float64) * w                     # in pixels: slopes unitless
    gx = np.gradient(z, axis=1) if w >= 2 else np.zeros_like(z)
    gy = np.gradient(z, axis=0) if h >= 2 else np.zeros_like(z)
    n = np.asarray(base_normals, np.float64)
    out = np.stack([n[..., 0] / n[..., 2] - gx, n[..., 1] / n[..., 2] - gy, np.ones_like(z)], -1)
    return out / np.linalg.norm(out, axis=-1, keepdims=True)
