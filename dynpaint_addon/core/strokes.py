"""What a stroke changed (issue 41, docs/pipeline.md §2, §6): a box of pixels, the shape decoded
again there, and the boxes the bake must look at again.

A Texture Paint stroke changes a small box of an image. Decoding the whole shape again and
baking every ray again costs the same for a dab as for a new image; here a height map's §2
decode (pre-blur, central differences, the z_min rule) is redone in the box grown by what each
step reads, and the boxes where the decoded shape really changed are handed to the bake
(crossings.sun_cos_theta_edited re-traces only the rays that read them). Every step is local
and reads the same pixels as the whole-image step, so the result is the whole decode's.

Boxes are (r0, r1, c0, c1): rows r0 … r1 − 1, columns c0 … c1 − 1 of the image (row 0 at the
bottom, §0).

>>> import numpy as np
>>> a = np.zeros((8, 8)); b = a.copy(); b[2, 5] = 1; b[3, 6] = 1
>>> changed_box(a, b), grow((2, 4, 5, 7), 3, 8, 8)
((2, 4, 5, 7), (0, 7, 2, 8))
"""
import numpy as np

from .input_rules import ImageData
from .sampling import gaussian_radius
from .shape import normals_from_height_px, preblurred_height


def changed_box(before, after):
    """The smallest box holding every pixel where `after` differs from `before` (any channel;
    NaN = NaN), or None where nothing changed or the sizes differ (then everything did)."""
    if before.shape != after.shape:
        return None
    # bit patterns: cheaper than float comparison, and a NaN left as it was is unchanged (a
    # channel of an RGBA buffer too: the same item size views in place, strided)
    view = {4: np.uint32, 8: np.uint64, 2: np.uint16}.get(before.dtype.itemsize)
    a, b = (before, after) if view is None or after.dtype != before.dtype else \
        (before.view(view), after.view(view))
    return box_of(a != b)


def box_of(mask):
    """The smallest box holding every True pixel of `mask` ((H, W), or (H, W, C): a pixel
    whose any channel is True), or None."""
    h = mask.shape[0]
    rows = np.flatnonzero(mask.reshape(h, -1).any(axis=1))   # a row's channels: one run
    if rows.size == 0:
        return None
    band = mask[rows[0]:rows[-1] + 1].any(axis=0)
    cols = np.flatnonzero(band if band.ndim == 1 else band.any(axis=1))
    return int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1


def whole(h, w):
    """The box of the whole image."""
    return 0, h, 0, w


def grow(box, margin, h, w):
    """`box` grown by `margin` pixels on every side, inside an h × w image (None stays None)."""
    if box is None:
        return None
    r0, r1, c0, c1 = box
    m = int(np.ceil(margin))
    return max(0, r0 - m), min(h, r1 + m), max(0, c0 - m), min(w, c1 + m)


def widened(mask, r=1):
    """`mask` (H, W) bool grown by r pixels (a square: every pixel within r rows and r
    columns of a True one).

    >>> dot = np.zeros((5, 5), bool); dot[2, 2] = True
    >>> int(widened(dot).sum()), int(widened(dot, 2).sum())
    (9, 25)
    """
    out = mask.copy()
    for axis in (0, 1):
        src = out.copy()
        for s in range(1, min(r, out.shape[axis] - 1) + 1):
            lo, hi = [slice(None)] * 2, [slice(None)] * 2
            lo[axis], hi[axis] = slice(0, -s), slice(s, None)
            out[tuple(lo)] |= src[tuple(hi)]
            out[tuple(hi)] |= src[tuple(lo)]
    return out


def stepped(t, over=0.0):
    """The pixels of `t` (H, W) on either side of a step larger than `over` to a neighbour
    (a row's or a column's; NaN steps none).

    >>> stepped(np.array([[1.0, 1.0, 0.0, 0.0]])).astype(int).tolist()
    [[0, 1, 1, 0]]
    """
    edge = np.zeros(t.shape, bool)
    for axis in (0, 1):
        step = np.abs(np.diff(t, axis=axis)) > over
        lo, hi = [slice(None)] * 2, [slice(None)] * 2
        lo[axis], hi[axis] = slice(0, -1), slice(1, None)
        edge[tuple(lo)] |= step
        edge[tuple(hi)] |= step
    return edge


def union(*boxes):
    """The smallest box holding every box given (None: none given)."""
    boxes = [b for b in boxes if b is not None]
    if not boxes:
        return None
    r0, r1, c0, c1 = zip(*boxes)
    return min(r0), max(r1), min(c0), max(c1)


def inside(box, rows, cols):
    """Whether pixels (rows, cols) lie in `box` (False everywhere for None)."""
    if box is None:
        return np.zeros(np.shape(rows), bool)
    r0, r1, c0, c1 = box
    return (rows >= r0) & (rows < r1) & (cols >= c0) & (cols < c1)


def _part(a, box):
    r0, r1, c0, c1 = box
    return a[r0:r1, c0:c1]


def height_shape_edited(shape, before, box, height_scale, preblur_px, z_min, in_place=False):
    """A height map's decoded shape (§2: core.pipeline.shape_normals) after its image
    (`shape`, an ImageData) changed in `box`, from the shape decoded before: → ((normals, heights_px, None),
    normals' changed box, heights' changed box), equal to decoding the whole edited image —
    new arrays (a bake in flight keeps reading the old ones), or with `in_place` the arrays
    before, patched (nothing else reads them: copying 4096²'s 268 MB took 45 ms a dab, and
    at times 0.2–0.9 s while the kernel found memory for them).

    The pre-blur reads 3σ around each pixel and the gradient one pixel more, so heights are
    redone in the box grown by 3σ, normals in that grown by 1, each from the grey image
    grown by what it reads; where a box meets the image's edge the image's own edge rule
    applies, as in the whole decode. The changed boxes are where the new arrays differ.
    """
    normals, heights, _ = before
    h, w = heights.shape
    dtype = heights.dtype
    radius = gaussian_radius(preblur_px) if preblur_px > 0 else 0
    z_box = grow(box, radius, h, w)
    n_box = grow(z_box, 1, h, w)
    z_read = grow(n_box, 1, h, w)           # heights the gradient of n_box reads …
    g_read = grow(z_read, radius, h, w)     # … and the grey pixels their blur reads
    g = ImageData(_part(shape.pixels, g_read), shape.bits).grey().astype(dtype, copy=False)
    z = preblurred_height(g, preblur_px) * dtype.type(height_scale * w)
    # z over z_read, cut out of the blurred window (its own edges are not the image's)
    z = z[inner(z_read, g_read)]
    n = normals_from_height_px(z, z_min)
    z, n = z[inner(z_box, z_read)], n[inner(n_box, z_read)]
    changed = (_offset(changed_box(_part(normals, n_box), n), n_box),
               _offset(changed_box(_part(heights, z_box), z), z_box))
    if not in_place:
        normals, heights = normals.copy(), heights.copy()
    _part(heights, z_box)[...] = z
    _part(normals, n_box)[...] = n
    return ((normals, heights, None), *changed)


def inner(box, window):
    """The slices of `box` in an array that holds the part `window` of the image (box inside
    window): _offset's inverse.

    >>> inner((3, 5, 10, 12), (2, 8, 9, 20))
    (slice(1, 3, None), slice(1, 3, None))
    """
    return (slice(box[0] - window[0], box[1] - window[0]),
            slice(box[2] - window[2], box[3] - window[2]))


def _offset(box, within):
    """A box found in the part `within` of an image, in the image's rows and columns."""
    if box is None:
        return None
    return box[0] + within[0], box[1] + within[0], box[2] + within[2], box[3] + within[2]
