"""How high the relief rises along one ray's path (§6 "march length"): a bound from what the
ray passes over only.

A march samples each ray K times between P0 and where it can no longer meet the relief. That
end used to come from the highest point of the whole image, so a part of a painting that does
not change was marched with other steps whenever another part grew taller (a moving painting's
frames, §16: its shadows flickered by up to 0.05). Here the end comes from the ray's own path:
the path is cut into PATH_SEGMENTS pieces, each bounded by the maxima of a pyramid of blocks
(2ᵏ px, each widened by its eight neighbours) at the level whose blocks are as long as a
piece. A piece's bound covers every point of it and the pixels its bilinear lookups read, so
no crossing is cut off; the bound reads only blocks within two of the path.

    >>> import numpy as np
    >>> z = np.zeros((64, 64)); z[40:44, 50:54] = 9.0      # a tower far off the path
    >>> pyramid = MaxPyramid(z)
    >>> one = lambda v: np.array([v])
    >>> path = pyramid.along(one(10.5), one(10.5), one(1.0), one(0.0), one(20.0))
    >>> max(float(b[0]) for b in path)          # along y = 10.5: the tower is not met
    0.0
    >>> path = pyramid.along(one(10.5), one(41.5), one(1.0), one(0.0), one(40.0))
    >>> max(float(b[0]) for b in path)          # along y = 41.5 it is
    9.0
"""
import numpy as np

PATH_SEGMENTS = 32   # pieces a ray's path is bounded in (a gather each: ½ of K = 64's cost)
MIN_LEVEL = 2        # blocks of 4 px: half a block + a bilinear lookup's reach fit one block


class ImageMax:
    """The bound of the whole image for every piece of every path: how the march ended
    before (a part that does not change was marched with other steps whenever another part
    grew taller); benchmarks/frames_stability.py's baseline."""

    def __init__(self, field):
        self.value = np.max(field)

    def along(self, x0, y0, ux, uy, length, segments=PATH_SEGMENTS):
        for _ in range(segments):
            yield np.full(np.shape(x0), self.value)


class MaxPyramid:
    """Maxima of a field (H, W) over blocks of 2ᵏ × 2ᵏ pixels, k ≥ MIN_LEVEL, each block's
    value the maximum over it and its eight neighbours; all levels in one flat array."""

    def __init__(self, field):
        field = np.asarray(field)
        low = np.finfo(field.dtype).min if field.dtype.kind == "f" else field.min()
        values, offsets, shapes = [], [], []
        level, k, start = field, 0, 0
        while True:
            ny, nx = -(-level.shape[0] // 2), -(-level.shape[1] // 2)
            padded = np.full((2 * ny, 2 * nx), low, field.dtype)
            padded[:level.shape[0], :level.shape[1]] = level
            level = padded.reshape(ny, 2, nx, 2).max(axis=(1, 3))
            k += 1
            if k >= MIN_LEVEL:
                wide = np.pad(level, 1, constant_values=low)
                near = np.max([wide[i:i + ny, j:j + nx] for i in range(3) for j in range(3)],
                              axis=0)
                values.append(near.ravel())
                offsets.append(start)
                shapes.append((ny, nx))
                start += ny * nx
            if ny == 1 and nx == 1 and k >= MIN_LEVEL:
                break
        self.flat = np.concatenate(values)
        self.top = len(shapes) - 1           # index of the coarsest level kept
        self._offsets = np.asarray(offsets)
        self._ny, self._nx = np.asarray(shapes).T
        self._block = np.left_shift(1, np.arange(len(shapes)) + MIN_LEVEL)

    def at(self, level, x, y):
        """The bound of the level-`level` block (index into the kept levels) holding the
        pixel-coordinate point (x, y); points outside the image read the nearest block."""
        offsets = self._offsets[level]
        ny, nx = self._ny[level], self._nx[level]
        block = self._block[level].astype(x.dtype)
        # (np.minimum of np.maximum, not np.clip, whose own cost is µs a call: every step)
        bx = np.minimum(np.maximum(np.floor(x / block), 0), nx - 1).astype(np.int64)
        by = np.minimum(np.maximum(np.floor(y / block), 0), ny - 1).astype(np.int64)
        return self.flat[offsets + by * nx + bx]

    def along(self, x0, y0, ux, uy, length, segments=PATH_SEGMENTS):
        """Per ray (arrays of one shape): start (x0, y0) in pixels, unit horizontal direction
        (ux, uy), horizontal length (px) → yields, piece by piece (j = 0 … segments − 1, the
        j-th of `segments` equal pieces of the path), the field's bound over that piece."""
        piece = np.maximum(length / segments, 1.0)
        level = np.clip(np.ceil(np.log2(piece)).astype(np.int64) - MIN_LEVEL, 0, self.top)
        for j in range(segments):
            centre = (j + 0.5) / segments * length
            yield self.at(level, x0 + centre * ux, y0 + centre * uy)


BOUNDS = {"path": MaxPyramid, "image": ImageMax}    # shadow.cos_theta_shadow's `bounds`
