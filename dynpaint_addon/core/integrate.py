"""Normal map → height map by least squares (docs/shape-from-painting.md, pipeline.md §2).

A normal N gives the slopes of the relief, ∂z/∂x = −N.x/N.z and ∂z/∂y = −N.y/N.z (§2 read
backwards). Between each pair of neighbouring pixels the height difference should equal the
mean of their slopes; the height map that best satisfies all those equations (least squares,
free edges) solves the Poisson equation −Δz = −div g:

    z = argmin Σ_edges (z_b − z_a − g_ab)²

Without a mask the image is solved at once by the discrete cosine transform (laplace.
poisson_neumann). With a mask, equations between a pixel inside and one outside are dropped:
the figure and its background are integrated each on its own, every connected part alone in
its bounding box (laplace.solve_parts: a part's heights depend on its own pixels, so frames
of a drawing keep them where they do not change, §16), and each figure part is lifted
`depth` image widths above the background it borders.

What no height map can reproduce — a painted, impossible normal field has a curl — is left
over as the residual g − ∇z, returned as an image and a share of the field.

    >>> import numpy as np
    >>> y, x = np.mgrid[0:32, 0:48] / 48.0
    >>> n = np.dstack([np.full_like(x, -0.3), np.zeros_like(x), np.ones_like(x)])
    >>> r = integrate(n / np.linalg.norm(n, axis=2, keepdims=True))
    >>> round(float(r.height[0, 47] - r.height[0, 0]), 3), round(r.residual_share, 6)  # 47/48 × 0.3
    (0.294, 0.0)
"""
from dataclasses import dataclass

import numpy as np

from .laplace import Grid, components, edge_sums, poisson_neumann, solve_parts


@dataclass
class Integrated:
    height: np.ndarray       # (H, W) heights in image widths, lowest 0
    residual: np.ndarray     # (H, W) |g − ∇z| around each pixel (slope units, RMS of its edges)
    residual_rms: float      # RMS of g − ∇z over all equations (slope units)
    residual_share: float    # |g − ∇z| / |g|: 0 for a height map's normals, 1 for a pure curl
    parts: int               # connected parts integrated separately (1 without a mask)
    iterations: int          # of the masked solve (0: the DCT solves at once)


def edge_slopes(normals):
    """Slopes on the edges between neighbours: gx (H, W−1) between (i, j) and (i, j + 1), gy
    (H − 1, W) between (i, j) and (i + 1, j); each the mean of its two pixels' −N.xy/N.z."""
    n = np.asarray(normals, dtype=np.float64)
    nz = np.maximum(n[..., 2], 1e-3)        # §2 keeps N.z ≥ z_min; this only guards raw input
    return edge_means(-n[..., 0] / nz, -n[..., 1] / nz)


def edge_means(p, q):
    """Pixel slopes p = ∂z/∂x, q = ∂z/∂y (H, W) → the slope on each edge between neighbours,
    the mean of its two pixels': gx (H, W−1), gy (H − 1, W)."""
    return (p[:, 1:] + p[:, :-1]) / 2, (q[1:, :] + q[:-1, :]) / 2


def _divergence(gx, gy, shape):
    """b = −div g for the normal equations −L z = b (each edge pushes its two pixels apart)."""
    b = np.zeros(shape)
    b[:, :-1] -= gx
    b[:, 1:] += gx
    b[:-1, :] -= gy
    b[1:, :] += gy
    return b


def _border_pairs(mask):
    """Flat indices (figure pixel, background pixel) of every figure pixel beside the background."""
    idx = np.arange(mask.size).reshape(mask.shape)
    fig, bg = [], []
    for a, b in ((idx[:, :-1], idx[:, 1:]), (idx[:-1, :], idx[1:, :])):
        ma, mb = mask.ravel()[a], mask.ravel()[b]
        cut = ma != mb
        fig.append(np.where(ma, a, b)[cut])
        bg.append(np.where(ma, b, a)[cut])
    return np.concatenate(fig), np.concatenate(bg)


def _place_parts(z, mask, labels, count, depth):
    """Shift each part: background parts to mean 0, then each figure part so that along its
    border it stands `depth` above the background it touches (mean over the border); a
    figure part that touches no background gets mean `depth`."""
    flat, zf = labels.ravel(), z.ravel()
    means = np.bincount(flat, zf, count) / np.maximum(np.bincount(flat, None, count), 1)
    inside = np.bincount(flat, mask.ravel().astype(float), count) > 0
    zf = zf - np.where(inside, 0.0, means)[flat]
    fig, bg = _border_pairs(mask)
    gap = np.bincount(flat[fig], zf[bg] - zf[fig], count)
    touching = np.bincount(flat[fig], None, count)
    lift = np.where(touching > 0, gap / np.maximum(touching, 1), -means) + depth
    return (zf + np.where(inside, lift, 0.0)[flat]).reshape(z.shape)


def _cuts(mask):
    """Edge weights that keep the equations between pixels on the same side of the mask."""
    return ((mask[:, 1:] == mask[:, :-1]).astype(float),
            (mask[1:, :] == mask[:-1, :]).astype(float))


def integrate(normals, mask=None, depth=0.0, precise=True, breaks=None, floor=None,
              by_parts=True):
    """Least-squares height of a unit normal field (H, W, 3), y up → Integrated.

    mask: (H, W) bool, True on the figure; equations across its edge are dropped and each part
    is placed by `depth` (image widths: how far a figure's rim stands above the background).
    precise=False solves a masked field in float32 to 1e-4 (heights within ~2e-4 of the
    relief, 3× faster: what a shadow bake needs).
    breaks: (bx (H, W−1), by (H−1, W)) bool, edges known to cross a hidden wall; their
    equations are dropped too, so the height may jump there. A normal map cannot show where
    its walls are (docs/shape-from-painting.md); the benchmark passes the true ones to
    measure what knowing them would give.
    floor: the height that becomes 0 (default: the lowest); a sequence's frames take one
    floor, so a part that does not change keeps its heights bit for bit (§16).
    by_parts: each connected part solved alone (default); False solves them in one system, as
    before §16 (benchmarks/frames_stability.py compares).
    """
    n = np.asarray(normals, dtype=np.float64)
    h, w = n.shape[:2]
    gx, gy = edge_slopes(n)
    gx, gy = gx / w, gy / w                 # per pixel step, in image widths
    if breaks is None and (mask is None or np.all(mask) or not np.any(mask)):
        wx, wy = np.ones_like(gx), np.ones_like(gy)
        z = poisson_neumann(_divergence(gx, gy, (h, w)))
        iterations, count = 0, 1
    else:
        mask = np.ones((h, w), bool) if mask is None else np.asarray(mask, bool)
        wx, wy = _cuts(mask)
        if breaks is not None:
            wx, wy = wx * ~np.asarray(breaks[0], bool), wy * ~np.asarray(breaks[1], bool)
        labels, count = components(wx > 0, wy > 0)
        # each part alone: a part's heights follow its own pixels only (§16: frames)
        solved = (labels, count) if by_parts else (np.zeros((h, w), np.int64), 1)
        z, iterations, _ = solve_parts(Grid(wx, wy, dtype=np.float64 if precise else np.float32),
                                       _divergence(gx * wx, gy * wy, (h, w)), *solved,
                                       1e-6 if precise else 1e-4)
        z = _place_parts(z, mask, labels, count, depth)
    rx = ((z[:, 1:] - z[:, :-1]) - gx) * w * wx      # back to slope units
    ry = ((z[1:, :] - z[:-1, :]) - gy) * w * wy
    sq = edge_sums(rx * rx, ry * ry, np.zeros((h, w)))       # over each pixel's equations
    k = edge_sums(wx, wy, np.zeros((h, w)))
    equations = wx.sum() + wy.sum()
    total = np.sum(rx * rx) + np.sum(ry * ry)
    field = np.sum((gx * w * wx) ** 2) + np.sum((gy * w * wy) ** 2)
    return Integrated(height=z - (z.min() if floor is None else floor),
                      residual=np.sqrt(sq / np.maximum(k, 1)),
                      residual_rms=float(np.sqrt(total / max(equations, 1))),
                      residual_share=float(np.sqrt(total / field)) if field > 0 else 0.0,
                      parts=count, iterations=iterations)


def relief_px(normals, mask=None, precise=False, floor=None):
    """The heights a shadow bake marches of a normal map's relief (§6 "Relief"): integrate's,
    in pixels of the image's width and in the normals' dtype (precise=False by default: the
    1e-4 a bake needs)."""
    z = integrate(normals, mask, precise=precise, floor=floor).height
    return (z * normals.shape[1]).astype(normals.dtype)
