"""sRGB transfer functions (pipeline.md §0: colour images are shaded in linear RGB).

Only painted colour images go through these; shape and control maps are data.
"""
import numpy as np


def srgb_to_linear(c):
    """IEC 61966-2-1 decode, applied per channel; keeps the input dtype."""
    c = np.asarray(c)
    lo = c / 12.92
    hi = ((np.maximum(c, 0.04045) + 0.055) / 1.055) ** 2.4
    return np.where(c <= 0.04045, lo, hi).astype(c.dtype, copy=False)


def linear_to_srgb(c):
    """IEC 61966-2-1 encode; negative values map to 0."""
    c = np.maximum(np.asarray(c), 0)
    lo = c * 12.92
    hi = 1.055 * np.power(np.maximum(c, 0.0031308), 1 / 2.4) - 0.055
    return np.where(c <= 0.0031308, lo, hi).astype(c.dtype, copy=False)
