"""Test shapes the suites and benchmarks share (not shipped with the extension)."""
import numpy as np


def quantized_dome(size, bits):
    """A hemisphere height map (radius 0.4 image widths, centred) quantized to `bits` (32 =
    float), and the mask of its inner 80 %: the §2/§14 bit-depth yardstick."""
    y, x = np.mgrid[0:size, 0:size].astype(np.float64)
    r2 = ((x + 0.5 - size / 2) ** 2 + (y + 0.5 - size / 2) ** 2) / (0.4 * size) ** 2
    height = np.sqrt(np.clip(1 - r2, 0, 1))
    if bits < 32:
        q = 2 ** bits - 1
        height = np.round(height * q) / q
    return height, r2 < 0.8 ** 2
