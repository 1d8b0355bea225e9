"""A figure's relief, made one way for every caller (docs/shape-from-painting.md): the mask
snapped onto the painting's edges (core.snap), inflated by parts (core.inflate) with the
painting's luminance embossed, then the effects (core.effects). make-shape inflate and Make
Shape's Inflate Silhouette (shapes/maker.py) and Paint Shape's figure mask (shapes/painted.py)
all make it here. No bpy; the option values are Make Shape › Inflate's (shapes.methods.OPTIONS).
"""
import numpy as np

from ..core.effects import bevel, smooth, structure
from ..core.inflate import inflate
from ..core.snap import snapped


def reads_painting(values):
    """Whether a relief of `values` reads the painting's luminance: its detail embossed, or
    the mask snapped onto its edges."""
    return bool(values["detail"] or values["snap"])


def with_effects(heights, mask, bevel_width=0.0, bevel_height=0.0, bevel_profile="round",
                 smoothing=0.0, structure_tile=None, structure_scale=None,
                 structure_strength=0.0):
    """An inflated figure's heights with the effects (core/effects.py) that are asked for: a
    bevel added, then smoothed, then a structure pattern added (after the smoothing, which
    would blur it away). Each is off unless given (its values as shapes.methods.OPTIONS
    offers them)."""
    z = np.asarray(heights, np.float64)
    if bevel_width > 0 and bevel_height:
        z = z + bevel(mask, bevel_width, bevel_height, bevel_profile)
    if smoothing > 0:
        z = smooth(z, mask, smoothing)
    if structure_tile is not None and structure_strength:
        z = z + structure(structure_tile, mask, structure_scale, structure_strength)
    return z


def relief_of_figure(figure, luminance, structure_tile, values):
    """A figure (H, W) bool, snapped already, inflated by parts with `values` (every inflate
    option the add-on shows; structure_scale and structure_strength too where a
    structure_tile is given), the painting's `luminance` embossed where values['detail']
    asks, then the effects (image widths)."""
    if not figure.any():
        return np.zeros(figure.shape)
    v = values
    z = inflate(figure, v["profile"], v["height"], v["detail"], luminance, v["detail_blur"]).height
    structure_args = () if structure_tile is None else (
        structure_tile, v["structure_scale"], v["structure_strength"])
    return with_effects(z, figure, v["bevel_width"], v["bevel_height"], v["bevel_profile"],
                        v["smoothing"], *structure_args)


def snapped_relief(figure, luminance, structure_tile, values):
    """relief_of_figure of the figure (H, W) bool snapped onto the painting's edges within
    values['snap'] image widths (core.snap; as it is where that is 0 or luminance None)."""
    return relief_of_figure(snapped(figure, luminance, values["snap"]), luminance,
                            structure_tile, values)
