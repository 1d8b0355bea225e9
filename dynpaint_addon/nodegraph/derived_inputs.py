"""Images derived from a painting's inputs before shading, for every backend (no bpy).

A node tree (material, compositor group, OSL shader, web page) samples a few images that are
not the artist's own but made from them by numpy:

  height             the §2 pre-blurred height map (grey; alpha: the shape image's) — none
                     where a one-channel 8/16-bit shape image is not pre-blurred: its red is
                     that already (a still image, sampled itself)
  relief             a normal map's integrated relief in image widths (§6 "Relief"), for
                     the OSL march
  silhouette         the alpha of the silhouette channel (§11) as a float image
  environment        E and B as the warped lookups read them (§8, §9): linear
  background         premultiplied RGBA, blurred for glossy / translucent looks (§11)
  background_sharp   B unblurred, shown outside the silhouette (§11)
  <input channel>    a copy of a moving slot's current frame (§16: sequences, sheets);
                     a finite copy of a float input that holds NaN/Inf (§14, core/inputs.py);
                     for a normal map also the map in the standard RGB convention when it is
                     stored otherwise (two-channel) or its tilts are scaled (§2); for the
                     transparency and gloss maps the values read (luminance or a channel)

`prepare` gives every backend what it builds from, in one call: the Features of a painting
(what its images, alphas and lights decide) and the plan of its derived images.
`derived_inputs` plans them from the features of the graph and the parameters (cheap: no
pixel is read); `Derived.make` makes one from its source's pixels. Each carries a key built
from what it depends on — its source image and the parameters whose `derives` role names it
(params.py) — so a backend remakes an image exactly when its key changes. Without bpy, so
the material, the compositor group, the OSL shader and the web page share one preparation.

    >>> from dynpaint_addon import params
    >>> from dynpaint_addon.nodegraph.features import Features
    >>> f = Features(size=(8, 8), shape_kind="height")
    >>> [d.channel for d in derived_inputs(f, params.defaults(), {"shape": Source("h.png", 8)})]
    ['height']
    >>> p = params.defaults(); p.shape.kind = "height"
    >>> f, plan = prepare(p, {"shape": Source("h.png", 8, (64, 48)), "dark": Source("d.png")}, ["sun"])
    >>> f.size, f.lights, [d.channel for d in plan]
    ((64, 48), ('sun',), ['height'])
"""
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from .. import params
from ..core.colour import srgb_to_linear
from ..core.inputs import mask_values
from ..core.input_rules import (MASKS, PER_PIXEL_CHANNELS, ImageData, finite_image,
                               mask_setting)
from ..core.cut_out import needs_cleaning
from ..core.pipeline import lookup_copy, shape_normals
from ..core.sampling import gaussian_radius
from ..core.shape import (default_preblur_px, fits_height_field, normal_vectors,
                          preblurred_height, resolve_encoding, resolve_strength,
                          slopes_from_normals)
from ..core.strokes import changed_box, grow, inner
from .features import Features


@dataclass(frozen=True)
class Source:
    """What the plan needs to know of an input image without reading it."""
    name: str            # identifies the image (and so its pixels)
    bits: int = 8        # 8, 16 or 32 (float: may hold NaN/Inf)
    size: tuple = (0, 0)     # (W, H) in pixels
    alpha: bool = False      # it has an alpha channel
    frame: object = None     # a moving slot's painting frame (§16); None: a still image
    version: int = 0         # how many times its pixels were edited in place (Blender: issue 41)
    grey: bool = False       # its file holds one grey channel (every reader: R = G = B = it)


def prepare(p, sources, light_kinds):
    """What every backend builds a painting from (§12): its Features and the derived images
    its graph samples → (Features, [Derived]).

    p: the parameters; sources: {channel: Source} of the images it has (a shape image among
    them); light_kinds: "sun" or "point" per light, in the graph's order.
    """
    features = Features.from_params(p, sources.keys(), light_kinds, sources["shape"].size,
                                    {c for c, src in sources.items() if src.alpha},
                                    {c: src.size for c, src in sources.items()})
    return features, derived_inputs(features, p, sources)


@dataclass(frozen=True)
class Derived:
    channel: str                         # the channel the graph samples
    source: str                          # the input channel it is made from
    key: str                             # same key, same pixels
    make: Callable = None                # ImageData (finite) → RGBA float32 (H, W, 4), y-up
    finite_copy: bool = False            # replaces its source: needed only if the source has
    #                                      NaN/Inf pixels or `make` converts it (else None)
    same_as: str = ""                    # equal to another derived image: share it
    grey: Callable = None                # a grey image's: ImageData → (grey (H, W), alpha or
    #                                      None); `make` is grey_rgba of it (make_derived's grey)
    reach: int = None                    # a grey image each pixel of which reads its source
    #                                      `reach` pixels around it, no farther: an edit of the
    #                                      source is remade in its box grown so (None: whole)
    recipe: str = ""                     # the key but for the source's edits: what else it
    #                                      was made for (an edit's box holds only within one)


def _grey_item(channel, source, key, grey, reach=None, recipe=""):
    """A derived grey image: made from grey(ImageData) → (grey, alpha or None)."""
    return Derived(channel, source, key, lambda d: grey_rgba(*grey(d)), grey=grey,
                   reach=reach, recipe=recipe)


@dataclass
class GreyMade:
    """A grey item as make_derived(grey=True) makes it: the grey (H, W) and alpha (or None) —
    of the whole image, or where `box` is given, of that box alone (the rest as made before
    from the same recipe); `source`: the pixels it was made from, for the next edit's box."""
    grey: np.ndarray
    alpha: object = None
    box: tuple = None
    source: np.ndarray = None
    recipe: str = ""


def grey_edited(item, data, box):
    """A local grey item (`reach` set) remade after its source (ImageData, finite) changed in
    `box` → GreyMade of the box grown by the reach: the same pixels as making the whole (each
    reads only the window grown by the reach again; at the image's edges that window is cut as
    the image is, so its own edge rule applies, as in the whole). box None: nothing changed —
    an empty box (the writer keeps what it made)."""
    if box is None:
        return GreyMade(np.empty((0, 0), np.float32), box=(0, 0, 0, 0), recipe=item.recipe)
    h, w = data.pixels.shape[:2]
    out = grow(box, item.reach, h, w)
    read = grow(out, item.reach, h, w)
    grey, alpha = item.grey(ImageData(data.pixels[read[0]:read[1], read[2]:read[3]], data.bits,
                                      data.name))
    cut = inner(out, read)
    return GreyMade(np.asarray(grey)[cut], None if alpha is None else np.asarray(alpha)[cut],
                    out, recipe=item.recipe)


def _recipe(channel, source, p, *extra):
    """_key of the same source unedited: a grey image's edits are remade in place within it."""
    return _key(channel, replace(source, version=0), p, *extra)


def _key(channel, source, p, *extra):
    """The source image and every parameter whose `derives` role names this channel."""
    values = [(prm.path, getattr(getattr(p, prm.section), prm.key)) for prm in params.PARAMS
              if channel in prm.derives]
    name = source.name if not source.version else (source.name, source.version)
    return repr((name, *values, *extra) if source.frame is None else
                (name, source.frame, *values, *extra))


def grey_rgba(grey, alpha=None):
    """(H, W) grey → (H, W, 4) RGBA, grey repeated (filled in place: a live bake
    writes one per update, not np.stack: a painted stroke writes two per update)."""
    out = np.empty(grey.shape + (4,), grey.dtype)
    columns, flat = out.reshape(-1, 4), grey.reshape(-1)    # (a column at a time: 2–3× faster
    for c in range(3):                                       # than a broadcast into [..., :3])
        columns[:, c] = flat
    columns[:, 3] = 1 if alpha is None else np.reshape(alpha, -1)
    return out


def _rgba(px):
    """Any (H, W, C) pixels as RGBA: grey repeated, missing alpha 1."""
    rgb = px[..., :3] if px.shape[2] >= 3 else np.repeat(px[..., :1], 3, 2)
    alpha = px[..., -1:] if px.shape[2] in (2, 4) else np.ones(px.shape[:2] + (1,), px.dtype)
    return np.concatenate([rgb, alpha], -1)


def derived_inputs(features, p, sources):
    """The derived images a graph with `features` samples (see the module) → [Derived].

    sources: {channel: Source} of the painting's input images.
    """
    need = features.image_channels()
    out = []
    for channel in ("shape", *PER_PIXEL_CHANNELS):
        src = sources.get(channel)
        convert = _standard_normal_map(p) if channel == "shape" else \
            _mask(mask_setting(p, channel)) if channel in MASKS else _as_it_is
        if channel in need and src is not None and src.frame is not None:
            # a moving slot: the graph samples a copy of the frame shown (§16)
            out.append(Derived(channel, channel, _key(channel, src, p, "frame"),
                               _frame_copy(channel, convert), finite_copy=True))
        elif channel in need and src is not None and (src.bits == 32 or convert is not _as_it_is):
            out.append(Derived(channel, channel, _key(channel, src, p, "finite"), convert,
                               finite_copy=True))
    if "height" in need:
        src = sources["shape"]
        sigma = p.shape.preblur
        sigma = float(default_preblur_px(src.bits) if sigma == "auto" else sigma)
        if sigma == 0 and src.grey and src.bits != 32 and src.frame is None:
            # (8/16-bit: no NaN; the graph reads red) — a 4096² stroke writes one image less
            out.append(Derived("height", "shape", _key("height", src, p, sigma), _as_it_is))
        else:
            out.append(_grey_item("height", "shape", _key("height", src, p, sigma),
                                  lambda d: (preblurred_height(d.grey(), sigma), _alpha(d)),
                                  gaussian_radius(sigma) if sigma > 0 else 0,
                                  _recipe("height", src, p, sigma)))
    if "relief" in need:
        src = sources["shape"]
        out.append(_grey_item("relief", "shape", _key("relief", src, p),
                              lambda d: (_relief_widths(d, p), None)))
    if "silhouette" in need:
        # A float copy of the alpha: EEVEE reads 8-bit alpha up to 1/255 off (254 → 255).
        channel = features.silhouette
        out.append(_grey_item("silhouette", channel,
                              _key("silhouette", sources[channel], p, channel),
                              lambda d: (np.clip(np.nan_to_num(d.alpha()), 0, 1),) * 2,
                              0, _recipe("silhouette", sources[channel], p, channel)))
    for channel, sec in (("environment", p.reflection), ("background", p.refraction)):
        if channel in need:
            out.append(Derived(channel, channel, _key(channel, sources[channel], p),
                               lambda d, sec=sec: lookup_copy(d, sec.blur, sec.extension)))
    if "background_sharp" in need:
        src = sources["background"]
        same = "background" if "background" in need and p.refraction.blur == 0 else ""
        # shared or not is part of the key: the tree samples another image then
        out.append(Derived("background_sharp", "background",
                           _key("background_sharp", src, p, same),
                           lambda d: lookup_copy(d, 0.0, "extend"), same_as=same))
    return out


def march_bounds(n, z_px, slopes):
    """The in-shader march's global bounds (snippets/shared/cos_theta.h, §6), from the core's
    decode of the shape (core.pipeline.shape_normals): the highest relief in image widths (0
    without heights), the steepest implied slope of the normals, and whether a normal map's
    relief along the ray stops at shadows.reach (1: its slopes fit no height field; 0: the
    whole ray, core.shape.fits_height_field) → {'relief_max', 'slope_max', 'reach_limited'}."""
    relief = float(z_px.max()) / z_px.shape[1] if z_px is not None else 0.0
    sl = slopes if slopes is not None else slopes_from_normals(n)
    limited = slopes is not None and not fits_height_field(slopes)
    return {"relief_max": relief, "slope_max": float(np.hypot(sl[..., 0], sl[..., 1]).max()),
            "reach_limited": float(limited)}


def _relief_widths(data, p):
    n, z_px, _ = shape_normals(data, p, np.float32)
    return z_px / z_px.shape[1]


def _as_it_is(data):
    return None


def _frame_copy(channel, convert):
    """A moving slot's frame as the graph samples the image itself: converted as a still
    image is (`convert`), else its pixels — a colour image's 8/16-bit sRGB codes decoded to
    linear, as Blender decodes the image it samples (§0), since the copy is a float image."""
    colour = params.CHANNELS[channel][1] == "colour"

    def make(data):
        rgba = convert(data)
        if rgba is None:
            rgba = _rgba(data.pixels)
            if colour and data.bits != 32:
                rgba = np.concatenate([srgb_to_linear(rgba[..., :3]), rgba[..., 3:]], -1)
        return rgba
    return make


def _standard_normal_map(p):
    """A normal map in the convention the graph decodes (N = 2C − 1 on RGB), or None when it
    is stored so already (rgb encoding, strength 1): §2's encoding and strength applied."""
    def make(data):
        rgb, a = data.rgb(), data.alpha()
        encoding = resolve_encoding(rgb, p.shape.encoding)
        strength = resolve_strength(rgb, p.shape.strength, encoding, a)
        if encoding == "rgb" and strength == 1 and not needs_cleaning(rgb, a):
            return None
        n = normal_vectors(rgb, encoding, strength, a)
        return _rgba(np.concatenate([(n + 1) / 2] + ([a[..., None]] if a is not None else []),
                                    -1))
    return make


def _mask(setting):
    """A transparency or gloss map as one grey value per pixel, read by `setting`
    (core/inputs.py mask_values): the graph reads its red channel. None for a grey image read
    as its grey: the image itself reads so."""
    def make(data):
        values, resolved = mask_values(data.pixels, setting)
        if data.pixels.shape[-1] < 3 and resolved in ("luminance", "grey"):
            return None
        return grey_rgba(values)
    return make


def _alpha(data):
    a = data.alpha()
    return None if a is None else np.clip(a, 0, 1)


def make_derived(items, read, role_of, grey=False, made_from=None):
    """Make every item that needs pixels, reading each source once → ({channel: RGBA, or None
    where the source itself or the image of `same_as` will do}, warnings).

    read(channel) → ImageData; role_of(channel) → the role core/inputs.py replaces NaN/Inf by
    ('colour', 'normal' or 'height': core.input_rules.pixel_role); grey: a grey item's
    GreyMade instead of its RGBA (for a writer that keeps the RGBA it wrote and fills only
    what changed: the add-on's grey_image). made_from(item) → the source pixels the writer's
    image of a local grey item was last made from by the same recipe, or None: where it has
    them, only the box the source's edit changed is made again (grey_edited; issue 41)."""
    cache, made, warnings = {}, {}, []
    for item in items:
        if item.same_as:
            made[item.channel] = None
            continue
        if item.source not in cache:
            data = read(item.source)
            cache[item.source] = finite_image(data, role_of(item.source), data.name) + (data,)
            if cache[item.source][1]:
                warnings.append(cache[item.source][1])
        data, warning, raw = cache[item.source]
        if grey and item.grey is not None:
            before = None if made_from is None or item.reach is None else made_from(item)
            if before is not None and before.shape == raw.pixels.shape:
                made[item.channel] = grey_edited(item, data, changed_box(before, raw.pixels))
            else:
                made[item.channel] = GreyMade(*item.grey(data), recipe=item.recipe)
            made[item.channel].source = raw.pixels
            continue
        rgba = item.make(data)
        if rgba is None and item.finite_copy and warning:
            rgba = _rgba(data.pixels)            # a finite copy of the source
        made[item.channel] = None if rgba is None else rgba.astype(np.float32, copy=False)
    return made, warnings
