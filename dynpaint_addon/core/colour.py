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


# linear_to_srgb16's table: 2^20 steps of the linear range (sRGB's steepest slope, 12.92,
# turns a step into 1.2e-5 of sRGB, under a 16-bit code's 1.5e-5)
SRGB16_STEPS = 1 << 20
_SRGB16 = []


def linear_to_srgb16(c):
    """linear_to_srgb of values in 0..1 rounded to 16-bit codes (k / 65535), from a table
    (a drawing's million pixels in ~20 ms, not ~100: issue 61); within one code of the
    exact rounding → float32."""
    if not _SRGB16:
        grid = linear_to_srgb(np.linspace(0.0, 1.0, SRGB16_STEPS + 1))
        _SRGB16.append((np.round(grid * 65535) / 65535).astype(np.float32))
    index = (np.clip(np.asarray(c, np.float32), 0, 1) * np.float32(SRGB16_STEPS) + 0.5)
    return _SRGB16[0][index.astype(np.int32)]


def scaled_srgb(c, factor, bits):
    """sRGB values c of a `bits`-bit image (8 or 16) whose linear light is scaled by
    `factor`, still sRGB (a painted image's shaded dark copy): each value read as its code
    and looked up in a table of the codes' exact results — a drawing's million pixels in
    ~10 ms, not ~120 (issue 61) → float32.

    >>> c = np.array([0, 1, 32768, 65535]) / 65535              # 16-bit codes
    >>> exact = linear_to_srgb(0.25 * srgb_to_linear(c))
    >>> float(np.abs(scaled_srgb(c, 0.25, 16) - exact).max()) < 1e-7
    True
    """
    top = (1 << bits) - 1
    table = linear_to_srgb(float(factor) * srgb_to_linear(np.arange(top + 1) / top))
    codes = np.clip(np.rint(np.asarray(c, np.float32) * np.float32(top)), 0, top)
    return table.astype(np.float32)[codes.astype(np.int32)]
