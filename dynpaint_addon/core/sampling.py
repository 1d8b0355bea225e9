"""Image lookups shared by every stage: bilinear sampling, extension modes, resampling, blur.

Convention (pipeline.md §0): arrays are indexed [row, column] with row 0 at the *bottom*
(y up), so a pixel (i, j) has its centre at x = j + 0.5, y = i + 0.5 in pixel units.
The same lookups are what Blender's Image Texture node does with Linear interpolation and
REPEAT / EXTEND / MIRROR extension, which is what the node-tree parity tests rely on.
"""
import numpy as np

EXTENSIONS = ("wrap", "extend", "mirror")


def wrap_index(k, n, extension):
    """Map integer texel indices k into [0, n) by the lookup's extension rule (§8: the paper's
    modulo is a floor-mod, so negative offsets wrap too)."""
    if extension == "wrap":
        return np.mod(k, n)
    if extension == "extend":
        return np.clip(k, 0, n - 1)
    if extension == "mirror":
        m = np.mod(k, 2 * n)
        return np.where(m >= n, 2 * n - 1 - m, m)
    raise ValueError(f"unknown extension {extension!r} (expected one of {', '.join(EXTENSIONS)})")


def sample_bilinear(img, x, y, extension="extend"):
    """Bilinearly sample `img` (H, W) or (H, W, C) at pixel coordinates x, y (any equal shapes).

    Non-finite coordinates are treated as 0 so a bad warp never produces an index error.
    Returns an array of shape x.shape (+ (C,) for multi-channel images), in img's dtype.
    """
    h, w = img.shape[:2]
    dtype = img.dtype
    px = np.asarray(x, dtype=dtype) - dtype.type(0.5)
    py = np.asarray(y, dtype=dtype) - dtype.type(0.5)
    px = np.where(np.isfinite(px), px, 0)
    py = np.where(np.isfinite(py), py, 0)
    j0f = np.floor(px)
    i0f = np.floor(py)
    fx = (px - j0f).astype(dtype, copy=False)
    fy = (py - i0f).astype(dtype, copy=False)
    j0 = j0f.astype(np.int64)
    i0 = i0f.astype(np.int64)
    j1 = wrap_index(j0 + 1, w, extension)
    i1 = wrap_index(i0 + 1, h, extension)
    j0 = wrap_index(j0, w, extension)
    i0 = wrap_index(i0, h, extension)
    if img.ndim == 3:
        fx = fx[..., None]
        fy = fy[..., None]
    if img.ndim == 3 and img.flags.c_contiguous:   # gathered by flat index: 1.6–2.6× faster
        flat = img.reshape(h * w, img.shape[2])
        i0 *= w
        i1 *= w

        def at(i, j):
            return np.take(flat, i + j, axis=0)
    else:         # (one channel: the 2D index is the faster; a view: no copy of it each call)
        def at(i, j):
            return img[i, j]
    top = at(i1, j0) * (1 - fx) + at(i1, j1) * fx
    bottom = at(i0, j0) * (1 - fx) + at(i0, j1) * fx
    return bottom * (1 - fy) + top * fy


def sample_bilinear_extend(img, x, y):
    """sample_bilinear(img, x, y, "extend") for a 2D image of at least 2×2 and finite x, y,
    with flat gathers (≈ 2× faster; the fast shadow bake's lookups). Clamping the coordinate
    to the box of pixel centres is what "extend" does to the indices."""
    h, w = img.shape
    f = img.dtype.type
    # (in place, corner indices by offset views of one index: this runs on every ray)
    px, py = np.asarray(x, img.dtype) - f(0.5), np.asarray(y, img.dtype) - f(0.5)
    for v, top in ((px, w - 1), (py, h - 1)):     # (np.clip's own cost is µs a call)
        np.maximum(v, 0, out=v)
        np.minimum(v, top, out=v)
    j0, i0 = np.minimum(np.floor(px), f(w - 2)), np.minimum(np.floor(py), f(h - 2))
    px -= j0                                    # the weights fx, fy
    py -= i0
    k = i0.astype(np.int64)
    k *= w
    k += j0.astype(np.int64)
    flat = img.reshape(-1)
    bottom, right = flat.take(k), flat[1:].take(k)
    right -= bottom
    right *= px
    bottom += right
    top, right = flat[w:].take(k), flat[w + 1:].take(k)
    right -= top
    right *= px
    top += right
    top -= bottom
    top *= py
    top += bottom
    return top


def sample_extend(img, x, y):
    """Bilinear "extend" lookups of a 2D or multi-channel image at finite x, y: the flat
    gathers of sample_bilinear_extend where the image allows (2D, at least 2×2), else
    sample_bilinear's."""
    if min(img.shape[:2]) >= 2 and img.ndim == 2:
        return sample_bilinear_extend(img, x, y)
    return sample_bilinear(img, np.asarray(x, img.dtype), np.asarray(y, img.dtype), "extend")


def pixel_centres(height, width, dtype=np.float32):
    """x, y pixel-centre coordinates (pixel units, origin at the bottom-left corner)."""
    x = (np.arange(width, dtype=dtype) + dtype(0.5))[None, :]
    y = (np.arange(height, dtype=dtype) + dtype(0.5))[:, None]
    return np.broadcast_to(x, (height, width)), np.broadcast_to(y, (height, width))


def resample(img, height, width, extension="extend"):
    """Resample `img` to (height, width) by sampling at the new pixel centres (bilinear).

    Used for control images whose size differs from the shape image (the documented rule:
    every per-pixel channel is resampled to the shape image's size) and for `render --width`.
    """
    h, w = img.shape[:2]
    if (h, w) == (height, width):
        return img
    x, y = pixel_centres(height, width, img.dtype.type)
    if height * width <= RESAMPLE_BAND_PIXELS:
        return sample_bilinear(img, x * (w / width), y * (h / height), extension)
    # Huge targets go in bands of rows: the gather's index and weight arrays (several times
    # the output) then exist for one band only. Per pixel the arithmetic is the same.
    out = np.empty((height, width) + img.shape[2:], img.dtype)
    rows = max(1, RESAMPLE_BAND_PIXELS // width)
    for r in range(0, height, rows):
        b = slice(r, min(height, r + rows))
        out[b] = sample_bilinear(img, x[b] * (w / width), y[b] * (h / height), extension)
    return out


RESAMPLE_BAND_PIXELS = 1 << 20


def _rows_enlarged(a, f):
    """resample_separable's pass along the rows of `a` (n ≥ 2 rows) to f·n rows, f a power of
    two, bit for bit (its taps (i + ½)/f − ½ are exact in binary, so every period of f output
    rows takes the same fractions): each output row between two input rows is
    lo + (hi − lo)·frac written straight into the result, hi − lo made once per input row,
    not gathered per output row: one full-size array made, not three (a draft's t enlarged
    8×, §13: 128² → 1024² 11 → 5 ms; a sun dragged over a 4096² painting ~0.55 → ~0.33 s)."""
    n, half = a.shape[0], f // 2
    k = np.arange(f, dtype=np.float64)
    # output row j·f + half + m lies between input rows j and j + 1 (m < f), at fraction
    # (half + m + ½)/f − ½ for m < half and that less 1 beyond
    frac = np.concatenate([(k[half:] + 0.5) / f - 0.5, (k[:half] + 0.5) / f + 0.5])
    extra = (None,) * (a.ndim - 1)
    out = np.empty((n * f,) + a.shape[1:], a.dtype)
    lo = a[:-1]
    body = out[half: n * f - half].reshape((n - 1, f) + a.shape[1:])
    np.multiply((a[1:] - lo)[:, None], frac.astype(a.dtype)[(None, slice(None)) + extra],
                out=body)
    body += lo[:, None]
    # the rows beyond the first and last centres read those at fraction 0, as the clipped
    # taps do (the same arithmetic: a non-finite neighbour still makes NaN there)
    zero = a.dtype.type(0)
    out[:half] = (a[1] - a[0]) * zero + a[0]
    out[n * f - half:] = (a[-1] - a[-1]) * zero + a[-1]
    return out


def resample_separable(img, height, width, box=None):
    """`resample` (bilinear at the new pixel centres, extended edges) of an (H, W) or
    (H, W, C) image, done as two 1-D passes with precomputed indices and weights: the same
    values up to rounding, ~5× faster (the bake resamples to and from its reduced resolution
    with it, §13). box: (r0, r1, c0, c1), only those rows and columns of the result (the
    same values as the whole one's there)."""
    h, w = img.shape[:2]
    r0, r1, c0, c1 = box or (0, height, 0, width)
    if (h, w) == (height, width):
        return img if box is None else img[r0:r1, c0:c1]
    dtype = img.dtype.type
    extra = (None,) * (img.ndim - 2)

    def taps(n_in, n_out, lo, hi):
        c = np.clip((np.arange(lo, hi) + 0.5) * (n_in / n_out) - 0.5, 0, n_in - 1)
        i0 = np.floor(c).astype(np.intp)
        return i0, np.minimum(i0 + 1, n_in - 1), (c - i0).astype(dtype)
    i0, i1, fy = taps(h, height, r0, r1)
    fy = fy[(slice(None), None) + extra]
    j0, j1, fx = taps(w, width, c0, c1)
    fx = fx[(slice(None),) + extra]

    def lerp(lo, hi, f):        # lo + (hi − lo)·f, in hi (a fresh gather)
        hi -= lo
        hi *= f
        hi += lo
        return hi

    def along_rows(a):          # whole rows copied: cheap even when they multiply
        f = height // h
        if box is None and h > 1 and f >= 2 and f * h == height and f & (f - 1) == 0:
            return _rows_enlarged(a, f)
        return lerp(a[i0], a[i1], fy)

    def along_columns(a):
        return lerp(a[:, j0], a[:, j1], fx)
    # the column gathers are the slow pass: run them on the smaller image
    if height > h:
        return along_rows(along_columns(img))
    return along_columns(along_rows(img))


def box_reduced(rgba, k):
    """A straight-alpha (H·k, W·k, C) image (colour, then alpha last) averaged over k × k
    blocks → (H, W, C): alpha the block's mean, colour the alpha-weighted mean (averaged
    premultiplied, divided again; 0 where the block is empty) — what exact coverage of each
    pixel gives a drawing drawn k times its size (issue 42: Grease Pencil supersampled).

    >>> import numpy as np
    >>> a = np.zeros((2, 2, 4), np.float32); a[0, 0] = (1, 0.5, 0, 1); a[1, 1, 3] = 1
    >>> box_reduced(a, 2)[0, 0].tolist()
    [0.5, 0.25, 0.0, 0.5]
    """
    if k == 1:
        return rgba
    alpha = rgba[..., -1:]
    premultiplied = np.concatenate([rgba[..., :-1] * alpha, alpha], axis=-1)
    mean = sum(premultiplied[i::k, j::k] for i in range(k) for j in range(k)) / (k * k)
    alpha = mean[..., -1:]
    mean[..., :-1] = np.divide(mean[..., :-1], alpha, out=np.zeros_like(mean[..., :-1]),
                               where=alpha > 0)
    return mean.astype(rgba.dtype, copy=False)


def enlarged_box(box, size, new_size):
    """The pixels of resample_separable's (bilinear) result at `new_size` (H, W) whose taps
    read a pixel of `box` (r0, r1, c0, c1) of an image of `size` (h, w): what an edit of that
    box changes in the enlarged image (a pixel to spare on each side)."""
    def span(lo, hi, n_in, n_out):
        k = n_out / n_in          # output i reads ⌊(i + ½)/k − ½⌋ and the one after
        return (max(0, int(np.floor((lo - 0.5) * k - 0.5)) - 1),
                min(n_out, int(np.ceil((hi + 0.5) * k - 0.5)) + 1))
    (r0, r1), (c0, c1) = (span(box[0], box[1], size[0], new_size[0]),
                          span(box[2], box[3], size[1], new_size[1]))
    return r0, r1, c0, c1


def laid_into(img, old, new, fill=1.0):
    """An image (y-up (H, W, ...)) spanning the rectangle `old` (x0, x1, y0, y1, in any units)
    laid into one spanning `new` at its own pixel size, `fill` where it does not reach (each
    pixel whole: placed to the nearest pixel, not resampled).

    >>> laid_into(np.zeros((2, 2)), (0, 1, 0, 1), (0, 2, -0.5, 1)).tolist()
    [[1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0]]
    """
    h, w = img.shape[:2]
    dx, dy = (old[1] - old[0]) / w, (old[3] - old[2]) / h
    size = (max(1, round((new[3] - new[2]) / dy)), max(1, round((new[1] - new[0]) / dx)))
    out = np.full(size + img.shape[2:], fill, img.dtype)
    r, c = round((old[2] - new[2]) / dy), round((old[0] - new[0]) / dx)
    r0, c0, r1, c1 = max(r, 0), max(c, 0), min(r + h, size[0]), min(c + w, size[1])
    if r1 > r0 and c1 > c0:
        out[r0:r1, c0:c1] = img[r0 - r:r1 - r, c0 - c:c1 - c]
    return out


def gaussian_radius(sigma_px):
    """Pixels gaussian_blur reads on each side of a pixel (its kernel's reach, 3σ up)."""
    return max(1, int(np.ceil(3 * sigma_px)))


def gaussian_blur(img, sigma_px, extension="extend"):
    """Separable Gaussian blur of an (H, W[, C]) image, sigma in pixels, borders by extension.

    Used for the height pre-blur (§2) and for glossy / translucent copies of E and B (§11).
    sigma_px <= 0 returns the image unchanged.
    """
    if not sigma_px > 0:
        return img
    radius = gaussian_radius(sigma_px)
    offsets = np.arange(-radius, radius + 1)
    kernel = np.exp(-0.5 * (offsets / sigma_px) ** 2)
    kernel = (kernel / kernel.sum()).astype(img.dtype)
    out = img
    for axis in (0, 1):
        n = out.shape[axis]
        if offsets.size > n:      # wider than the image: the weights folded onto its n pixels
            src = wrap_index(np.arange(n)[:, None] + offsets[None, :], n, extension)
            fold = np.zeros((n, n), img.dtype)
            np.add.at(fold, (np.repeat(np.arange(n), offsets.size), src.ravel()),
                      np.tile(kernel, n))
            out = np.moveaxis(np.tensordot(fold, out, axes=([1], [axis])), 0, axis)
            continue
        # Padding by index mapping is exact for every extension, even when radius > n.
        padded = out.take(wrap_index(np.arange(-radius, n + radius), n, extension), axis=axis)
        acc = np.zeros_like(out)
        for k, weight in enumerate(kernel):
            sl = [slice(None)] * out.ndim
            sl[axis] = slice(k, k + n)
            acc += weight * padded[tuple(sl)]
        out = acc
    return out
