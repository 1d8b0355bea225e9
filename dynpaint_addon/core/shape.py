"""Shape image → unit normals (pipeline.md §2) and the height field the shadow march uses (§6).

Arrays are y-up (row 0 at the bottom, §0). Heights are returned in *pixels* so the shadow
march can work in one unit; normals are unit vectors in the painting frame.
"""
import weakref

import numpy as np

from .cut_out import cut_out_pixels
from .integrate import edge_means
from .sampling import gaussian_blur

Z_MIN_DEFAULT = 0.05
DEGENERATE_LENGTH = 0.05  # §2: |N| below this (mid-grey, black) falls back to +z

# §2: pre-blur σ by bit depth. 8-bit heights quantize slopes (≈0.011 mean N·L error on a
# dome lit at 45°); σ ≈ 1.5 px cuts that tenfold. 16-bit and float maps need none.
PREBLUR_PX_BY_BITS = {8: 1.5, 16: 0.0, 32: 0.0}


def default_preblur_px(bits):
    """Default height pre-blur σ in pixels for a height image with `bits` bits per channel."""
    return PREBLUR_PX_BY_BITS.get(int(bits), 0.0 if bits > 8 else 1.5)


BAND_PIXELS = 1 << 20    # per-pixel work on huge images goes in bands of rows (bounded memory)


def _bands(height, width):
    rows = max(1, BAND_PIXELS // max(1, width))
    return [slice(r, min(height, r + rows)) for r in range(0, height, rows)]


def finalize_normals(n, z_min=Z_MIN_DEFAULT):
    """Make any (…, 3) vector field a finite unit normal field with N.z ≥ z_min (§2, §14).

    Degenerate vectors (|N| < 0.05, NaN, Inf, or pointing straight down) become (0, 0, 1).
    Vectors below z_min are pushed radially toward +z: the azimuth (direction of N.xy) is
    kept and the elevation raised to exactly z_min. Large images go in bands of rows (the
    temporaries of one band only); the result is the same.
    """
    n = np.asarray(n)
    if n.ndim == 3 and n.shape[0] * n.shape[1] > BAND_PIXELS:
        out = np.empty(n.shape, n.dtype)
        for band in _bands(*n.shape[:2]):
            out[band] = _finalize(n[band], z_min)
        return out
    return _finalize(n, z_min)


def _finalize(n, z_min):
    n = np.asarray(n)
    dtype = n.dtype
    z_min = dtype.type(np.clip(z_min, 1e-4, 1.0))
    finite = np.all(np.isfinite(n), axis=-1)
    n = np.where(finite[..., None], n, 0)
    length = np.sqrt(np.sum(n * n, axis=-1))
    ok = finite & (length >= DEGENERATE_LENGTH)
    safe_len = np.where(ok, length, 1)
    n = n / safe_len[..., None]
    nz = n[..., 2]
    rxy = np.hypot(n[..., 0], n[..., 1])
    low = nz < z_min
    # Radial push: keep the xy direction, set |xy| = sqrt(1 - z_min²). A vector with no xy
    # part that points down has no direction to keep: treat it as degenerate.
    ok &= ~(low & (rxy < 1e-6))
    scale = np.where(low, np.sqrt(1 - z_min * z_min) / np.where(rxy > 0, rxy, 1), 1)
    out = np.stack([n[..., 0] * scale, n[..., 1] * scale, np.where(low, z_min, nz)], axis=-1)
    up = np.zeros_like(out)
    up[..., 2] = 1
    return np.where(ok[..., None], out, up).astype(dtype, copy=False)


ENCODINGS = ("auto", "rgb", "rg")


# A two-channel map: blue about 0 (its 99th percentile ≤ TWO_CHANNEL_BLUE) and x, y in the
# unit disc (x² + y² ≤ 1.1 in ≥ 98 % of pixels). Measured (docs/detection-numbers.md, 64² to
# 256²): two-channel maps keep blue's 99th percentile ≤ 0.13 down to JPEG quality 30, RGB
# normal maps and colour images ≥ 0.94.
TWO_CHANNEL_BLUE = 0.25


def resolve_encoding(rgb, encoding="auto"):
    """'rgb' or 'rg' for a normal map's pixels (0..1): 'auto' reads a map whose blue is about
    0 and whose x, y lie in the unit disc as a two-channel map (z = √(1 − x² − y²), the
    convention of many engines and tools), whatever 8-bit export or JPEG left in its blue;
    any other as RGB."""
    if encoding != "auto":
        return encoding
    rgb = np.nan_to_num(np.asarray(rgb, dtype=np.float32)[..., :3], posinf=0.0, neginf=0.0)
    if rgb.size == 0:
        return "rgb"
    x, y = 2 * rgb[..., 0] - 1, 2 * rgb[..., 1] - 1
    two_channel = np.percentile(rgb[..., 2], 99) <= TWO_CHANNEL_BLUE and \
        np.mean(x * x + y * y <= 1.1) >= 0.98
    return "rg" if two_channel and np.ptp(rgb[..., :2]) > 0 else "rgb"


def scale_tilt(n, strength):
    """Each normal's tilt from +z (its angle θ) scaled to strength·θ, azimuth and length kept
    (§2): 0.5 is exactly the decoder N = normalize((0,0,1) + normalize(2C − 1)) some web
    relighting tools use (the half-way vector halves the angle); 1 leaves the map as it is."""
    if strength == 1:
        return n
    dtype = n.dtype
    length = np.sqrt(np.sum(n * n, axis=-1))
    rxy = np.hypot(n[..., 0], n[..., 1])
    theta = np.arctan2(rxy, n[..., 2]) * dtype.type(strength)
    along = np.where(rxy > 0, length * np.sin(theta) / np.where(rxy > 0, rxy, 1), 0)
    return np.stack([n[..., 0] * along, n[..., 1] * along, length * np.cos(theta)],
                    axis=-1).astype(dtype, copy=False)


# Unit vectors 2C − 1: |length − 1| below UNIT_TOLERANCE in UNIT_SHARE of the tilted pixels
# (|x, y| > 0.1: a flat background is unit in any map). Measured (docs/detection-numbers.md,
# 64² to 256²): unit maps keep ≥ 0.74 of them within 0.15 down to JPEG quality 30; maps of
# other lengths ≤ 0.56, colour images ≤ 0.38.
UNIT_TOLERANCE = 0.15
UNIT_SHARE = 0.65
# A map painted for a decoder that halves each tilt stores unit vectors with doubled tilts, so
# its steep parts face away, which a map of the usual convention never does: 'auto' strength
# reads a map of unit vectors of which at least HALVING_AWAY (of the opaque, non-degenerate
# pixels) face away at strength 0.5. Measured (docs/detection-numbers.md): usual maps ≤ 0.001
# down to JPEG quality 30, halving maps of a hemisphere ≥ 0.24.
HALVING_AWAY = 0.05
# A map of which (nearly) every pixel faces away has one sensible reading whatever its
# lengths: painted for the halving decoder (the original research system's maps: blue 0–0.11,
# vectors not unit length). Measured (docs/detection-numbers.md): such maps ≥ 0.99; a
# photograph read as a normal map ≤ 0.46, usual maps ≤ 0.001 (two-channel maps, blue 0, are
# read as such before this rule).
ALL_AWAY = 0.9


def unit_share(rgb):
    """The share of tilted pixels (|x, y| > 0.1) whose vector 2C − 1 is unit length (within
    UNIT_TOLERANCE); 1 for a flat map."""
    v = 2 * np.asarray(rgb, np.float32)[..., :3] - 1
    tilted = np.hypot(v[..., 0], v[..., 1]) > 0.1
    if not tilted.any():
        return 1.0
    length = np.sqrt(np.sum(v[tilted] ** 2, axis=-1))
    return float(np.mean(np.abs(length - 1) < UNIT_TOLERANCE))


def facing_away(n, alpha=None):
    """The share of vectors n (…, 3) that face away (z < 0), among the opaque (alpha ≥ ½) and
    non-degenerate ones; 0 if there are none."""
    keep = np.sqrt(np.sum(n * n, axis=-1)) >= DEGENERATE_LENGTH
    if alpha is not None:
        keep &= np.nan_to_num(alpha) > 0.5
    return float(np.mean(n[..., 2][keep] < 0)) if keep.any() else 0.0


def resolve_strength(rgb, strength="auto", encoding="auto", alpha=None):
    """shape.strength as a number (§2): 'auto' is 0.5 for a map painted for a decoder that
    halves each tilt (unit vectors, HALVING_AWAY or more of them facing away; or vectors of
    any length, ALL_AWAY or more of them facing away), else 1.

    >>> n = np.array([[[0.0, 0.8, -0.6], [0.0, 0.0, 1.0]]])   # one of two unit normals faces away
    >>> resolve_strength((n + 1) / 2), resolve_strength((0.7 * n + 1) / 2), resolve_strength(
    ...     (n + 1) / 2, 1.0)
    (0.5, 1.0, 1.0)
    >>> away = np.array([[[0.9, 0.8, -0.9], [-1.0, 0.6, -0.8]]])   # every vector faces away
    >>> resolve_strength((away + 1) / 2)
    0.5
    """
    if strength != "auto":
        return float(strength)
    rgb = np.nan_to_num(np.asarray(rgb, np.float32)[..., :3], posinf=0.0, neginf=0.0)
    if resolve_encoding(rgb, encoding) == "rg":
        return 1.0
    opaque = np.ones(rgb.shape[:-1], bool) if alpha is None else np.nan_to_num(alpha) > 0.5
    if not opaque.any():
        return 1.0
    away = facing_away(2 * rgb - 1, alpha)
    if away >= ALL_AWAY and resolve_encoding(rgb) != "rg":   # a two-channel map read as RGB
        return 0.5                                           # faces away too: its note says so
    return 0.5 if away >= HALVING_AWAY and unit_share(rgb[opaque]) >= UNIT_SHARE else 1.0


def normal_vectors(rgb, encoding="rgb", strength=1.0, alpha=None):
    """§2 normal map → the vectors 2C − 1 (not yet unit, no fallbacks): `encoding` 'rg' takes
    z = √(1 − x² − y²) (blue ignored), 'auto' detects it; `strength` scales each tilt, 'auto'
    as resolve_strength decides (on the opaque pixels: `alpha`). With an alpha, uncovered
    pixels are flat and a rim blended with black is divided by alpha (core/cut_out.py)."""
    rgb = np.asarray(rgb)
    two_channel = resolve_encoding(rgb, encoding) == "rg"
    strength = resolve_strength(rgb, strength, encoding, alpha)
    rgb, empty = cut_out_pixels(rgb, alpha, rim=not two_channel)   # no rim becomes a cliff
    n = 2 * rgb[..., :3] - 1
    if two_channel:
        z = np.sqrt(np.maximum(1 - n[..., 0] ** 2 - n[..., 1] ** 2, 0))
        n = np.concatenate([n[..., :2], z[..., None].astype(n.dtype)], axis=-1)
    n = scale_tilt(n, strength)
    if empty is not None and empty.any():
        n = np.where(empty[..., None], np.array([0, 0, 1], n.dtype), n)
    return n


def decode_normal_map(rgb, flip_green=False, z_min=Z_MIN_DEFAULT, encoding="rgb", strength=1.0,
                      alpha=None):
    """§2 normal map: N = 2C − 1 on RGB (or RG, `encoding`), each tilt scaled by `strength`,
    renormalized, fallbacks, z_min; `flip_green` for DirectX-style maps (green means "lit
    from below"); alpha: the map's, for strength 'auto'."""
    n = normal_vectors(rgb, encoding, strength, alpha)
    if flip_green:
        n = n * np.array([1, -1, 1], dtype=n.dtype)
    return finalize_normals(n, z_min)


def height_field_px(height, height_scale, preblur_px=0.0):
    """§2 height map → relief z = h·H in *pixels* (h in image widths, so z_px = h·H·W).

    Non-finite samples are replaced by 0 (the caller reports them); the optional Gaussian
    pre-blur (σ in pixels) is applied before scaling.
    """
    height = preblurred_height(height, preblur_px)
    return height * height.dtype.type(height_scale * height.shape[1])


def preblurred_height(height, preblur_px=0.0):
    """The height image H (0..1) as the gradient sees it: NaN/Inf → 0, then the §2 pre-blur.

    Node trees sample this copy and scale it by h·W themselves, so the relief stays live.
    """
    height = np.asarray(height)
    if height.ndim == 3:
        height = height[..., 0]
    height = np.where(np.isfinite(height), height, 0).astype(height.dtype, copy=False)
    return gaussian_blur(height, preblur_px, "extend")


def normals_from_height_px(z_px, z_min=Z_MIN_DEFAULT):
    """§2: N = normalize(−∂z/∂x, −∂z/∂y, 1) with central differences (one-sided at borders).

    z_px is the relief in pixels, so the gradient is dimensionless (the same as in image
    widths): pixels cancel.
    """
    # np.gradient needs two samples along an axis; a 1-pixel-wide axis has no slope.
    gx = np.gradient(z_px, axis=1) if z_px.shape[1] >= 2 else np.zeros_like(z_px)
    gy = np.gradient(z_px, axis=0) if z_px.shape[0] >= 2 else np.zeros_like(z_px)
    out = np.empty(z_px.shape + (3,), z_px.dtype)
    for band in _bands(*z_px.shape):        # bounded temporaries on huge images
        n = np.stack([-gx[band], -gy[band], np.ones_like(gx[band])], axis=-1)
        out[band] = _finalize(n, z_min)
    return out


def slopes_from_normals(n):
    """Implied height gradient ∇H = −N.xy / N.z of a normal field (§6, normal maps).

    Finite because N.z ≥ z_min (§2). Returned as an (H, W, 2) array (dz/dx, dz/dy).
    """
    return -n[..., :2] / n[..., 2:3]


# §6 Reach: does a normal map's slope field fit a height field? Measured on Cycles renders of
# objects (benchmarks/relief_choice.py) and on the impossible figures: per image width, the
# circulation of objects' maps is ≤ 1.7 (the occluding contours of smooth shapes, where walls
# hide), of the Penrose tribar and the impossible staircase 3.7–4.4, at 128² to 512².
CURL_STEP = 0.1    # |∮∇H·dl| of one pixel's loop (in pixels) that counts: 8-bit noise is < 0.03
CURL_STEEP = 3.2   # loops with a slope steeper (N.z < 0.3) are left out: a smooth object's
#                    occluding contour, whose hidden wall no normal map records
CURL_LIMIT = 2.5   # circulation per image width above which the normals fit no height field


def circulation(slopes, mask=None):
    """How far a slope field (H, W, 2) is from a height field's (§6 "Reach"): around every
    loop of four pixels, ∮∇H·dl (the mean slopes of its four edges) — 0 for the normals of
    any height field; summed where it exceeds CURL_STEP, over loops no steeper than
    CURL_STEEP (and inside `mask`, where given), per image width: an impossible figure's
    edges, each counted by its length and its jump.

    >>> y, x = np.mgrid[0:64, 0:64] / 64.0
    >>> dome = np.dstack([-(x - 0.5), -(y - 0.5)])              # ∇ of −((x−½)² + (y−½)²)/2
    >>> vortex = np.dstack([-(y - 0.5), x - 0.5]) * 20          # ∮ = 40 × the area inside
    >>> round(circulation(dome), 3), circulation(vortex) > CURL_LIMIT
    (0.0, True)
    """
    s = np.asarray(slopes, np.float64)
    gx, gy = edge_means(s[..., 0], s[..., 1])            # the equations integrate() solves
    loop = gx[:-1, :] + gy[:, 1:] - gx[1:, :] - gy[:, :-1]
    gentle = np.hypot(s[..., 0], s[..., 1]) <= CURL_STEEP
    if mask is not None:
        gentle = gentle & np.asarray(mask, bool)
    counted = gentle[:-1, :-1] & gentle[:-1, 1:] & gentle[1:, :-1] & gentle[1:, 1:]
    size = np.abs(loop) * counted
    return float(size[size > CURL_STEP].sum()) / max(s.shape[1], 1)


_FITTED = {}    # id(slopes) → (weak ref, fits): a dragged light bakes one shape again and again


def fits_height_field(slopes):
    """Whether a normal map's slopes fit a height field (`circulation` below CURL_LIMIT):
    its relief rebuilt along a ray comes back down, so the whole ray may be marched; an
    impossible figure's never does, and only `shadows.reach` keeps its streaks short.
    Measured once per slopes array while it lives."""
    hit = _FITTED.get(id(slopes))
    if hit is None or hit[0]() is not slopes:
        for gone in [k for k, (ref, _) in _FITTED.items() if ref() is None]:
            del _FITTED[gone]
        hit = (weakref.ref(slopes), circulation(slopes) < CURL_LIMIT)
        _FITTED[id(slopes)] = hit
    return hit[1]


def reach_of(reach, slopes):
    """§6 Reach as a bake applies it → image widths: `reach` (shadows.reach) for a normal
    map's slopes that fit no height field, the whole ray (∞) for slopes that do
    (fits_height_field), `reach` unchanged for a height map or an integrated relief (slopes
    None: it has no reach)."""
    return np.inf if slopes is not None and fits_height_field(slopes) else reach
