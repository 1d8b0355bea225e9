"""Ambient occlusion of a height map, for game-engine export (docs/shape-from-painting.md).

Horizon-based: along each of D directions in the image plane, the highest horizon seen within
`radius` (tan α = max over steps of (z(P + s·dir) − z(P)) / s); the open sky above a pixel
is the mean over directions of 1 − sin α. A plane gives 1, the floor of a pit less.

    >>> import numpy as np
    >>> float(ambient_occlusion(np.zeros((16, 16))).min())
    1.0
"""
import numpy as np


def ambient_occlusion(height, radius=0.03, directions=8, steps=8):
    """AO (H, W) in 0..1 of heights (H, W) in image widths, y up; radius in image widths."""
    z = np.asarray(height, np.float64)
    h, w = z.shape
    reach = max(1, int(np.ceil(radius * w)))
    padded = np.pad(z, reach, mode="edge")
    open_sky = np.zeros((h, w))
    for k in range(directions):
        angle = 2 * np.pi * k / directions
        dx, dy = np.cos(angle), np.sin(angle)
        tangent = np.zeros((h, w))
        for s in range(1, steps + 1):
            dist = reach * s / steps                       # pixels
            ox, oy = int(round(dx * dist)), int(round(dy * dist))
            if ox == 0 and oy == 0:
                continue
            seen = padded[reach + oy:reach + oy + h, reach + ox:reach + ox + w]
            tangent = np.maximum(tangent, (seen - z) * w / np.hypot(ox, oy))
        open_sky += 1 - tangent / np.sqrt(1 + tangent * tangent)
    return open_sky / directions
