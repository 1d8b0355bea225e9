"""The whole 2.5D pipeline on whole images (pipeline.md §2–§11): the reference for every backend.

Inputs are `ImageData` (pixels y-up as read from a file, 0..1 for 8/16-bit; floats for EXR)
keyed by channel name (§1); what is read of them and how (masks, silhouette, branches, notes)
is input_rules.py's. Output is premultiplied linear RGBA plus the intermediate passes.

Neutral defaults of missing channels (§12). A pruned graph must give the pixels of the full
graph fed these values:
  dark / bright   at least one is required; one alone is the colour image A, lit as an
                  albedo (§1: C0 = a·A, C1 = A)
  specular_colour white (1, 1, 1)
  gloss           1 everywhere
  transparency    1 everywhere (the slider alone sets k; its 'auto' default is then 0)
  environment     the refracted background stands in for it (C_M := C_T): G = C_T, F unused
  background      the reflected environment stands in for it (C_T := C_M): G = C_M, F unused,
                  and outside the silhouette the result is transparent (alpha 0)
  both E and B    G = transparent black: transparent parts show what lies behind the plane
  silhouette      alpha 1 everywhere
"""
from dataclasses import dataclass, field

import numpy as np

from . import fresnel as fr
from . import shading, warps
from .colour import srgb_to_linear
from .input_rules import (PER_PIXEL_CHANNELS, ImageData, finite_image, input_notes,
                          mask_channels, normal_map_normals, pixel_role, relief_of,
                          silhouette_channel, transparency_branch, albedo_channel,
                          image_channels)
from .inputs import mask_values
from .integrate import relief_px
from .lights import falloff, light_vectors
from .sampling import gaussian_blur, pixel_centres, resample, sample_bilinear
from .bake import bake as shadow_bake
from .bake import bake_edited, forget_reductions
from .either_relief import both_reliefs, either_shadow
from .shape import (default_preblur_px, height_field_px, normals_from_height_px, reach_of,
                    slopes_from_normals)
from .strokes import changed_box, height_shape_edited

@dataclass
class RenderResult:
    rgba: np.ndarray                           # premultiplied linear RGBA (H, W, 4), y-up
    passes: dict = field(default_factory=dict)  # 't' (per light), 'W', 's', 'F', 'k', 'normal'
    warnings: list = field(default_factory=list)


def _linear(img, dtype):
    """sRGB-decoded RGB for 8/16-bit colour images; float images are linear already (§0)."""
    rgb = img.rgb().astype(dtype, copy=False)
    return rgb if img.bits >= 32 else srgb_to_linear(rgb)


def _premultiplied(img, dtype):
    """Linear premultiplied RGBA of a colour image (straight alpha in files)."""
    rgb = _linear(img, dtype)
    a = img.alpha()
    a = np.ones(rgb.shape[:2], dtype) if a is None else np.clip(a.astype(dtype), 0, 1)
    return np.concatenate([rgb * a[..., None], a[..., None]], axis=2)


def shape_normals(shape, p, dtype=np.float32, relief=True):
    """§2: decode the shape image → (normals, heights_px or None, slopes or None).

    A normal map gives its slopes, or with `shadows.relief` integrated (and `relief`: the
    caller will march shadows) the heights its shadows fall from (§6 "Relief")."""
    if p.shape.kind == "height":
        z_px = height_field_px(shape.grey().astype(dtype), p.shape.height_scale,
                               _preblur_px(shape, p))
        return normals_from_height_px(z_px, p.shape.z_min), z_px, None
    n = normal_map_normals(shape, p, dtype)
    if relief and relief_of(p.shadows.relief, shape.has_alpha) == "integrated":
        return n, normal_map_relief_px(n, shape), None
    return n, None, slopes_from_normals(n)


def _preblur_px(shape, p):
    """§2's pre-blur σ (px) of a height map."""
    sigma = p.shape.preblur
    return float(default_preblur_px(shape.bits) if sigma == "auto" else sigma)


def shape_normals_edited(shape, p, before, box, in_place=False):
    """shape_normals of a shape image edited in `box`, from its decode `before` (issue 41):
    → (decoded, normals' changed box, heights' changed box), equal to decoding the whole
    edited image; None where the decode is not local (a normal map's: its strength, encoding
    and relief are read off the whole image), so decode it whole. in_place: into before's
    arrays (strokes.height_shape_edited), where nothing else reads them."""
    if p.shape.kind != "height" or before[1] is None:
        return None
    edited = height_shape_edited(shape, before, box, p.shape.height_scale,
                                 _preblur_px(shape, p), p.shape.z_min, in_place)
    if in_place:                # the bakes' kept reductions of these arrays: stale now
        forget_reductions(edited[0][0])
    return edited


def normal_map_relief_px(n, shape, precise=False, floor=None):
    """§6 "Relief": the height field a normal map's shadows fall from, in pixels: the
    least-squares integral of its slopes (core/integrate.py), its figure (the shape image's
    alpha) integrated apart from the background (an alpha over every pixel cuts nothing: a
    full-frame map's, as without one). `precise`: to 1e-6 rather than the 1e-4 a
    shadow bake needs (exported height maps); floor: the height (image widths) made 0, None:
    for a cut-out the background's (its parts stand at mean 0: each part then keeps its
    heights bit for bit while another part of a moving painting changes, §16), else the
    lowest (integrate's)."""
    alpha = shape.alpha()
    mask = None if alpha is None else np.nan_to_num(alpha) >= 0.5
    if mask is not None and mask.all():      # an alpha that cuts nothing out: a full frame
        mask = None
    if floor is None and mask is not None:
        floor = 0.0
    return relief_px(n, mask, precise=precise, floor=floor)


def shadow_term(n, z_px, slopes, light, p, cancel=None, progress=None, own_size=False,
                stats=None):
    """The raw cos-θ term of one light (§6) at the parameters' quality level (§13);
    own_size: a reduced level's at the size it was baked at; stats: the bake's (core/bake.bake).
    A normal map with relief auto at a final level casts the shadow of either relief
    (either_relief.py)."""
    def bake_one(heights_px, slopes, reach, progress):
        return shadow_bake(n, light, p.shadows.offset, p.shadows.quality, heights_px=heights_px,
                           slopes=slopes, steps=p.shadows.steps, scale=p.shadows.resolution,
                           occupancy=p.shadows.occupancy, reach=reach, stats=stats,
                           cancel=cancel, progress=progress, own_size=own_size)
    both = both_reliefs(n, z_px, slopes, p)
    t = either_shadow(bake_one, *both, progress) if both else \
        bake_one(z_px, slopes, reach_of(p.shadows.reach, slopes), progress)
    return t.astype(n.dtype, copy=False)


def shadow_term_edited(n, z_px, slopes, light, p, t_before, normals_box, heights_box):
    """shadow_term of a shape an edit changed in these boxes, from t_before, the term of the
    shape before it (core/bake.bake_edited): None where the level bakes the whole anyway, or
    where it casts the shadow of either relief (a normal map's: decoded whole)."""
    if both_reliefs(n, z_px, slopes, p):
        return None
    t = bake_edited(n, light, p.shadows.offset, p.shadows.quality, t_before, normals_box,
                    heights_box, heights_px=z_px, slopes=slopes, steps=p.shadows.steps,
                    scale=p.shadows.resolution, occupancy=p.shadows.occupancy,
                    reach=reach_of(p.shadows.reach, slopes))
    return None if t is None else t.astype(n.dtype, copy=False)


def light_terms(n, z_px, slopes, lights, p, dtype=np.float32, rows=None, shadows=None,
                through=None):
    """Per light: the raw light term (cos-θ or N·L, §4/§6), the specular term (§7) and the
    strength k reaching each pixel (§5: the light's strength, times a point light's falloff).

    rows: (r0, r1) to compute only those rows (n, z_px are then the full images); shadows:
    the cos-θ terms already baked for the whole image, one per light; through: per light,
    what the layers in front let through (§15, whole image), or None.
    """
    h, w = n.shape[:2]
    r0, r1 = rows or (0, h)
    x, y = pixel_centres(h, w, dtype)
    x, y, nb = x[r0:r1], y[r0:r1], n[r0:r1]
    # P_S lies on the relief of a height map, on the canvas for a normal map (§0): a normal
    # map's integrated relief only casts its shadows
    zs = z_px[r0:r1] if z_px is not None and p.shape.kind == "height" else \
        np.zeros((r1 - r0, w), dtype)
    raw, spec, strength = [], [], []
    for i, light in enumerate(lights):
        lvec, dist = light_vectors(light, x, y, zs, dtype, image_size=(h, w))
        if p.shadows.enabled:
            t = shadows[i] if shadows is not None else shadow_term(n, z_px, slopes, light, p)
            t = t[r0:r1]
        else:
            t = shading.n_dot_l(nb, lvec)
        if through is not None:             # §15: t = t_own·T
            t = t * through[i][r0:r1].astype(dtype, copy=False)
        raw.append(t)
        if p.specular.enabled:
            spec.append(shading.specular_term(nb, lvec, p.specular.s0, p.specular.s1,
                                              p.specular.curve))
        k = dtype(light.strength)
        fades = dist is not None and p.falloff.mode != "none"    # else one number per light
        strength.append(k * falloff(dist / dtype(w), p.falloff.mode, p.falloff.radius)
                        if fades else k)
    return raw, spec, strength


def _lookup_source(imgs, name, sigma_widths, extension, dtype, cache):
    """Linear premultiplied copy of E or B, blurred for glossy/translucent looks (§11).

    Cached per input image object and settings, so re-rendering with a moving light does not
    blur again; the entry holds the image itself, so a hit can never be a different image.
    """
    img = imgs[name]
    key = (name, float(sigma_widths), extension, np.dtype(dtype).str)
    hit = cache.get(key)
    if hit is not None and hit[0] is img:
        return hit[1]
    out = lookup_copy(img, sigma_widths, extension, dtype)
    cache[key] = (img, out)
    return out


def lookup_copy(img, sigma_widths=0.0, extension="extend", dtype=np.float32):
    """E or B as the warped lookups read it (§8, §9): linear premultiplied RGBA, blurred by
    σ (image widths) for glossy / translucent looks (§11). Node trees sample this same copy."""
    rgba = _premultiplied(img, dtype)
    return gaussian_blur(rgba, sigma_widths * rgba.shape[1], extension)


def placement(section):
    """(offset, scale) of the reflection or refraction settings: where E or B sits (§8, §9)."""
    return tuple(section.offset), section.scale


def _warped_lookup(img_rgba, offset, painting_shape, extension, place, rows=None):
    """Sample an image placed over the painting (place = (offset, scale), warps.placed_uv) at
    each pixel + the warp's offset (§8, §9); rows (r0, r1): only those rows of the painting
    (offset holds just them)."""
    h, w = painting_shape
    x, y = pixel_centres(h, w, img_rgba.dtype.type)
    if rows is not None:
        x, y = x[rows[0]:rows[1]], y[rows[0]:rows[1]]
    u, v = warps.placed_uv(x / w + offset[..., 0], y / h + offset[..., 1] * (w / h), *place, w / h)
    eh, ew = img_rgba.shape[:2]
    return sample_bilinear(img_rgba, u * ew, v * eh, extension)


@dataclass
class Prepared:
    """A painting's inputs as every render of it reads them: the images made finite and
    per-pixel ones resampled to the shape's size (core/input_rules.py), the channel each mask
    is read from, the decoded shape (§2) and what was noted on the way."""
    imgs: dict
    masks: dict
    n: np.ndarray
    z_px: object
    slopes: object
    warnings: list

    @property
    def size(self):
        """(H, W) of the shape image: the painting's pixels."""
        return self.n.shape[:2]


def prepare(images, p, dtype=np.float32, before=None):
    """The inputs of a render (§1, §2) → Prepared; raises ValueError for a painting that
    cannot be rendered (no shape, no dark or bright image, no finite shape pixel).
    before: the Prepared of the same painting, parameters and dtype before an edit of its
    images (a stroke, issue 61): a height map decoded again only where it changed
    (shape_normals_edited: the same arrays as a whole decode)."""
    warnings = []
    if "shape" not in images:
        raise ValueError("a painting needs a shape image (normal or height map)")
    if "dark" not in images and "bright" not in images:
        raise ValueError("a painting needs a dark or a bright image (one may serve both)")
    shape = images["shape"]
    hs, ws = shape.pixels.shape[:2]
    if not np.any(np.isfinite(shape.pixels)):
        raise ValueError("the shape image has no finite pixel (all NaN or Inf)")
    warnings += input_notes(images, p)

    imgs = {}
    for name, img in images.items():     # core/inputs.py: the rules for imperfect images
        img, warning = finite_image(img, pixel_role(name, p), f"{name} image")
        warnings += [warning] if warning else []
        if name in PER_PIXEL_CHANNELS and img.pixels.shape[:2] != (hs, ws):
            img = ImageData(resample(img.pixels.astype(dtype), hs, ws), img.bits, img.name)
        imgs[name] = img
    decoded = None if before is None else _decoded_again(imgs["shape"], p, dtype, before)
    n, z_px, slopes = decoded or shape_normals(imgs["shape"], p, dtype,
                                               relief=p.shadows.enabled)
    return Prepared(imgs, mask_channels(imgs, p), n, z_px, slopes, warnings)


def _decoded_again(shape, p, dtype, before):
    """prepare's decode of `shape` from the Prepared `before` it was edited, or None where
    it must be decoded whole."""
    was = before.imgs["shape"].pixels
    if was.shape != shape.pixels.shape or before.n.dtype != dtype:
        return None
    box = changed_box(was, shape.pixels)
    if box is None:
        return before.n, before.z_px, before.slopes
    edited = shape_normals_edited(shape, p, (before.n, before.z_px, before.slopes), box)
    return None if edited is None else edited[0]


def render(images, lights, p, dtype=np.float32, cache=None, keep_passes=True, *,
           prepared=None, through=None):
    """Render a painting (pipeline.md §2–§11) → RenderResult.

    images: {channel: ImageData} (§1); lights: [core.lights.Light]; p: params namespace
    (params.defaults() and the recipe's values). dtype float32 by default, float64 for references.
    keep_passes=False (the command line) drops the intermediate passes, which lets a large
    image be shaded in bands of rows (bounded memory beyond the decoded shape and shadows).
    prepared: `prepare(images, p, dtype)` when the caller has it already (layers, §15).
    through: per light, what the layers in front let through (§15's T, (H, W)), multiplied
    into that light's term; None: nothing in front.
    """
    cache = {} if cache is None else cache   # keep one across renders of the same images
    ready = prepared or prepare(images, p, dtype)
    n, z_px, slopes = ready.n, ready.z_px, ready.slopes
    hs, ws = ready.size
    shadows = [shadow_term(n, z_px, slopes, light, p) for light in lights] \
        if p.shadows.enabled else None
    ctx = _Shading(ready.imgs, lights, p, dtype, cache, n, z_px, slopes, shadows, hs, ws,
                   ready.masks, through)
    warnings = list(ready.warnings)
    if keep_passes or hs * ws <= RENDER_BAND_PIXELS:
        rgba, passes = _shade(ctx, 0, hs)
        return RenderResult(rgba, passes, warnings)
    # Huge images without passes (the command line): shade in bands of rows, so the
    # per-pixel temporaries exist for one band only. Per pixel the arithmetic is the same.
    rgba = np.empty((hs, ws, 4), dtype)
    rows = max(1, RENDER_BAND_PIXELS // ws)
    for r0 in range(0, hs, rows):
        r1 = min(hs, r0 + rows)
        rgba[r0:r1] = _shade(ctx, r0, r1)[0]
    return RenderResult(rgba, {}, warnings)


RENDER_BAND_PIXELS = 1 << 20


@dataclass
class _Shading:
    """What every band of a render shares: the inputs, the decoded shape, the shadow terms."""
    imgs: dict
    lights: list
    p: object
    dtype: object
    cache: dict
    n: np.ndarray
    z_px: object
    slopes: object
    shadows: object
    hs: int
    ws: int
    masks: dict            # transparency/gloss → the channel each is read from (whole image)
    through: object = None  # per light: §15's T from the layers in front, or None


def _rows(img, r0, r1):
    """The rows r0 … r1 − 1 of a per-pixel input image (same size as the shape image)."""
    return ImageData(img.pixels[r0:r1], img.bits, img.name)


@dataclass
class Band:
    """Rows r0 … r1 − 1 of the painting being shaded: what the terms read and write, in order.

    Each term of §4–§11 is one function below, registered by @term in the order the pipeline
    applies it; it reads the inputs (`image`, `p`, the decoded normals `n`) and what earlier
    terms left (`rgba`, `s_mix`, `c_spec`), and writes its result and its passes.
    """
    ctx: _Shading
    r0: int
    r1: int
    rgba: np.ndarray = None          # premultiplied linear RGBA so far
    s_mix: np.ndarray = None         # §7 highlight weight s (RGB), 0 without highlights
    c_spec: np.ndarray = None        # §7 highlight colour
    diffuse_terms: list = None       # §4 per-light terms t after Clamp&Step
    specular_terms: list = None      # §7 per-light highlight terms (from the light terms)
    strengths: list = None           # §5 per-light k reaching each pixel (point-light falloff)
    passes: dict = field(default_factory=dict)

    def __post_init__(self):
        self.p, self.dtype, self.lights = self.ctx.p, self.ctx.dtype, self.ctx.lights
        self.n = self.ctx.n[self.r0:self.r1]
        self.shape = (self.r1 - self.r0, self.ctx.ws)
        self.s_mix = np.zeros(self.shape + (3,), self.dtype)

    def has(self, channel):
        return channel in self.ctx.imgs

    def image(self, channel):
        """A per-pixel input's rows of this band."""
        return _rows(self.ctx.imgs[channel], self.r0, self.r1)

    def colour(self, channel):
        """A colour input's rows, linear RGB (§0)."""
        return _linear(self.image(channel), self.dtype)

    def finite_colour(self, channel):
        """`colour`, its non-finite values 0."""
        c = self.colour(channel)
        return np.where(np.isfinite(c), c, 0)

    def mask(self, channel):
        """A mask input's rows as one value per pixel, read from the channel decided on the
        whole image (core/inputs.py mask_values), or 1 everywhere without the image."""
        if not self.has(channel):
            return np.ones(self.shape, self.dtype)
        return mask_values(self.image(channel).pixels, self.ctx.masks[channel])[0] \
            .astype(self.dtype)


TERMS = []


def term(fn):
    """Register a shading term: the pipeline applies them in the order they are defined."""
    TERMS.append(fn)
    return fn


def _shade(ctx, r0, r1):
    """§3–§11 for rows r0 … r1 − 1 of the painting → (premultiplied RGBA, passes)."""
    band = Band(ctx, r0, r1)
    for shading_term in TERMS:
        shading_term(band)
    rgba = np.where(np.isfinite(band.rgba), band.rgba, 0)
    return rgba.astype(ctx.dtype, copy=False), band.passes


@term
def diffuse(b):
    """§4–§5: the light terms, the weight W = clip(Σ k·c·t) and C_d = C0(1 − W) + C1·W, or
    for one colour image A (§1) C_d = A·(a + (1 − a)·W), a the ambient."""
    p, dtype, lights = b.p, b.dtype, b.lights
    ctx = b.ctx
    raw, spec, b.strengths = light_terms(ctx.n, ctx.z_px, ctx.slopes, lights, p, dtype,
                                         (b.r0, b.r1), ctx.shadows, ctx.through)
    terms = [shading.clamp_step(t, p.diffuse.t0, p.diffuse.t1, p.diffuse.curve) for t in raw]
    if lights:
        w_mix = shading.light_weight(terms, [lt.colour for lt in lights], b.strengths)
    else:
        w_mix = np.zeros(b.shape + (3,), dtype)
    albedo = albedo_channel(ctx.imgs)
    if albedo:
        c_d = shading.albedo_lit(b.finite_colour(albedo), w_mix, p.diffuse.ambient)
    else:
        c_d = shading.barycentric_mix(b.finite_colour("dark"), b.finite_colour("bright"),
                                      w_mix, p.diffuse.mix_space)
    b.passes.update({"normal": b.n, "t": raw, "W": w_mix})
    b.diffuse_terms, b.specular_terms = terms, spec
    b.rgba = np.concatenate([c_d, np.ones(b.shape + (1,), dtype)], axis=2)


@term
def highlights(b):
    """§7: the opaque highlight C_s = C_d(1 − g·s) + C_spec·g·s."""
    p, dtype, lights = b.p, b.dtype, b.lights
    b.c_spec = b.colour("specular_color") if b.has("specular_color") else np.ones(3, dtype)
    if not (p.specular.enabled and lights):
        return
    b.s_mix = shading.light_weight(b.specular_terms, [lt.colour for lt in lights], b.strengths)
    g = np.clip(b.mask("gloss") * dtype(p.specular.amount), 0, 1)
    c_s = shading.opaque_highlight(b.rgba[..., :3], b.c_spec, g[..., None] * b.s_mix)
    b.rgba = np.concatenate([c_s, b.rgba[..., 3:]], axis=2)
    b.passes["s"] = b.s_mix


def fresnel(n, p):
    """§10: the reflection/refraction ratio F of the normals, physical or art-directed."""
    eta = p.refraction.ior if p.refraction.mode == "physical" else 2.0 ** p.refraction.mu
    if p.fresnel.mode == "physical":
        return fr.fresnel_physical(n, eta)
    return fr.fresnel_art(n, p.fresnel.x1, p.fresnel.x2, p.fresnel.kappa, p.fresnel.domain)


def transparency_amount(p, has_map):
    """§11: the slider's value, 'auto' read as 1 with a transparency map and 0 without."""
    amount = p.transparency.amount
    if amount == "auto":
        return 1.0 if has_map else 0.0
    return float(amount)


def transparency_k(ready, p):
    """§11's k = clip(map × amount) over the whole painting (H, W), for a Prepared painting:
    what a layer lets through of the light that crosses it (§15)."""
    imgs, (h, w) = ready.imgs, ready.size
    amount = transparency_amount(p, "transparency" in imgs)
    values = mask_values(imgs["transparency"].pixels, ready.masks["transparency"])[0] \
        if "transparency" in imgs else np.ones((h, w))
    return np.clip(values * amount, 0, 1)


def silhouette_alpha(imgs, p):
    """§1's silhouette α of a painting's images (H, W), non-finite values read as 0, or None
    when the painting has none."""
    alpha = _silhouette(imgs, p.silhouette.source)
    return None if alpha is None else np.clip(np.where(np.isfinite(alpha), alpha, 0), 0, 1)


@term
def transparency(b):
    """§8–§11: reflection of E and refraction of B by UV warps, mixed by Fresnel (G), the
    highlight added (C2′ = clip(G + s·C_spec)) and shown by k: C = (1 − k)·C_s + k·C2′."""
    p, dtype, ctx = b.p, b.dtype, b.ctx
    amount = transparency_amount(p, b.has("transparency"))
    k = np.clip(b.mask("transparency") * dtype(amount), 0, 1)
    if not (amount > 0 and np.any(k > 0)):
        return
    rows, n = (b.r0, b.r1), b.n
    c_m = c_t = None
    if b.has("environment"):
        e = _lookup_source(ctx.imgs, "environment", p.reflection.blur, p.reflection.extension,
                           dtype, ctx.cache)
        off = warps.reflection_offset(n, p.reflection.distance, p.reflection.mode,
                                      p.reflection.max_offset)
        c_m = _warped_lookup(e, off, (ctx.hs, ctx.ws), p.reflection.extension,
                             placement(p.reflection), rows)
    if b.has("background"):
        bg = _lookup_source(ctx.imgs, "background", p.refraction.blur, p.refraction.extension,
                            dtype, ctx.cache)
        if p.refraction.mode == "physical":
            off = warps.refraction_offset_physical(n, p.refraction.distance, p.refraction.ior)
        else:
            off = warps.refraction_offset_linear(n, p.refraction.distance, p.refraction.mu)
        c_t = _warped_lookup(bg, off, (ctx.hs, ctx.ws), p.refraction.extension,
                             placement(p.refraction), rows)
    if c_m is not None and c_t is not None:
        f = fresnel(n, p)
        g_mix = f[..., None] * c_m + (1 - f[..., None]) * c_t
        b.passes["F"] = f
    elif c_m is not None or c_t is not None:
        g_mix = c_m if c_m is not None else c_t
    else:
        g_mix = np.zeros(b.shape + (4,), dtype)
    c2 = g_mix.copy()
    c2[..., :3] = np.clip(g_mix[..., :3] + b.s_mix * b.c_spec, 0, 1)
    b.rgba = (1 - k[..., None]) * b.rgba + k[..., None] * c2
    b.passes["k"] = k


@term
def silhouette(b):
    """§11: outside the silhouette α the background shows: B·(1 − α) + C·α (B unwarped, placed
    where the refraction places it)."""
    ctx, dtype = b.ctx, b.dtype
    alpha = silhouette_alpha(ctx.imgs, b.p)
    if alpha is None:
        return
    alpha = alpha[b.r0:b.r1].astype(dtype)[..., None]
    behind = _warped_lookup(_lookup_source(ctx.imgs, "background", 0.0, "extend", dtype,
                                           ctx.cache),
                            np.zeros(b.shape + (2,), dtype), (ctx.hs, ctx.ws),
                            b.p.refraction.extension, placement(b.p.refraction), (b.r0, b.r1)) \
        if b.has("background") else np.zeros(b.shape + (4,), dtype)
    b.rgba = behind * (1 - alpha) + b.rgba * alpha


@term
def view(b):
    """What the painting shows (view.show): itself, or one of its passes alone, opaque."""
    show = b.p.view.show
    if show == "painting":
        return
    dtype, zero, p = b.dtype, np.zeros(b.shape, b.dtype), b.p
    if show == "t":         # the largest light term: the order of the lights does not matter
        value = np.maximum.reduce(b.diffuse_terms) if b.diffuse_terms else zero
    elif show == "F":       # also where k ≡ 0 left it uncomputed
        has_both = b.has("environment") and b.has("background") and \
            transparency_branch(p.transparency.amount, b.has("transparency")) != "none"
        value = b.passes["F"] if "F" in b.passes else fresnel(b.n, p) if has_both else zero
    else:
        value = b.passes["W"] if show == "W" else b.s_mix
    rgb = value if np.ndim(value) == 3 else np.repeat(np.asarray(value)[..., None], 3, -1)
    b.rgba = np.concatenate([rgb.astype(dtype), np.ones(b.shape + (1,), dtype)], -1)


def _silhouette(imgs, source):
    """§1: alpha of the colour image A (or the shape, or the dark image), by the recipe's
    silhouette.source."""
    name = silhouette_channel(source, *image_channels(imgs))
    return imgs[name].alpha() if name else None
