"""A painting's images in Blender: its inputs (colour management, loading) and the images numpy
derives from them (nodegraph/derived_inputs.py), remade exactly when their keys change."""
import os
from dataclasses import dataclass

import numpy as np

import bpy

from ... import params
from ...core.frames import expand_pattern, is_pattern
from ...core.input_rules import pixel_role
from ...core.sampling import enlarged_box, resample_separable
from ...core.strokes import changed_box, union
from ...inputs.imageio import file_channels, file_header, image_data_from_blender
from ...inputs.memory import check_read
from ...inputs.painting_frames import BoundedCache, sequence_numbers
from ...nodegraph.derived_inputs import GreyMade, grey_rgba, make_derived
from .edits import note_edited

COLOUR_CHANNELS = {c for c, (_, kind) in params.CHANNELS.items() if kind == "colour"}


def bits_of(img):
    """Bits per channel of a loaded image (8, 16 or 32), without reading its pixels. 16-bit PNG
    and TIFF get float buffers in Blender but hold sRGB-encoded codes like 8-bit files."""
    if not img.is_float:
        return 8
    return 16 if img.file_format in ("PNG", "TIFF") else 32


def is_float_file(img):
    """Does the image come from a float file (EXR, HDR: linear values)?"""
    return bits_of(img) == 32


def has_alpha(img):
    return file_channels(img) in (2, 4)


def is_grey(img):
    """Its file holds one grey channel (Blender's buffer: R = G = B = it, alpha 1)."""
    return file_channels(img) == 1


def prepare_channel_image(img, channel):
    """Colour images are sRGB-decoded by Blender (8/16-bit) or linear (float); data images
    are never colour-managed (§0). Alpha is kept apart from colour (channel packed)."""
    # (each set only where it differs: setting one reloads the image's pixels and tells every
    # painting that shows it that they were edited)
    space = "sRGB" if channel in COLOUR_CHANNELS and not is_float_file(img) else "Non-Color"
    if img.colorspace_settings.name != space:   # 8- and 16-bit files hold sRGB codes (§0)
        img.colorspace_settings.name = space
    if img.alpha_mode != "CHANNEL_PACKED":
        img.alpha_mode = "CHANNEL_PACKED"
    if img.use_half_precision:       # 16-bit GPU textures cost EEVEE ~1e-2 on steep slopes
        img.use_half_precision = False


def downsampled(img, max_size):
    """A still image's copy scaled so its longest side is `max_size` pixels (Add's Max Size),
    packed with the .blend (the file on disk is unchanged) → (image, report line); the image
    itself, and '', when it is no larger or max_size is 0."""
    w, h = img.size
    if not max_size or max(w, h) <= max_size or img.source in ("SEQUENCE", "MOVIE", "TILED"):
        return img, ""
    k = max_size / max(w, h)
    nw, nh = max(1, round(w * k)), max(1, round(h * k))
    small = img.copy()
    small.name = f"{img.name} ({nw}×{nh})"
    small.scale(nw, nh)
    small.pack()            # float images pack as OpenEXR, byte ones as PNG: nothing lost
    return small, (f"{os.path.basename(img.filepath) or img.name}: {w}×{h} downsampled to "
                   f"{nw}×{nh} (Max Size; packed with the .blend, the file is unchanged)")


def load_image(path, channel):
    """Load (or reuse) an image file for a channel, colour-managed as §0 says. A frame-numbered
    name (`walk_####.png`, §16) loads its first file as a Blender image sequence."""
    path = os.path.abspath(path)
    if is_pattern(os.path.basename(path)):
        img = load_image(expand_pattern(path, sequence_numbers(path)[0]), channel)
        img.source = "SEQUENCE"
        return img
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: file not found")
    header = file_header(path)
    if header is not None:      # a size that cannot fit is refused before Blender loads it
        check_read(header, os.path.basename(path))
    known = set(bpy.data.images)
    try:
        img = bpy.data.images.load(path, check_existing=True)
    except RuntimeError as exc:
        raise ValueError(f"{path}: Blender cannot read it ({str(exc).strip()})") from None
    if img.size[0] == 0 or img.size[1] == 0 or not img.has_data:
        if img not in known:
            bpy.data.images.remove(img)      # leave no broken image behind
        raise ValueError(f"{path}: not an image Blender can read (unknown or corrupt format)")
    prepare_channel_image(img, channel)
    return img


def float_image(name, rgba):
    """A float RGBA image holding `rgba` (y-up (H, W, 4)), reused when the name exists."""
    h, w = rgba.shape[:2]
    img = bpy.data.images.get(name)
    if img is not None and img.source == "GENERATED" and img.use_generated_float:
        # resized in place: the nodes that show it keep it (a cos-θ image changes size between
        # a live draft and the final bake, shadow_images.write_shadow)
        resized_image(img, w, h)
    if img is None or tuple(img.size) != (w, h) or not img.is_float:
        if img is not None:
            bpy.data.images.remove(img)
        img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True, is_data=True)
    # before the pixels, and only when it differs: assigning a colour space, even the same
    # one, regenerates the image's buffer (a moving painting's uploads took 2.5× as long)
    if img.colorspace_settings.name != "Non-Color":
        img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "CHANNEL_PACKED"
    img.use_half_precision = False
    img.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    return img


@dataclass
class _Kept:
    """What grey_image last wrote into an image: the next write fills the box that changed
    alone (a stroke's cos-θ and derived images: grey_rgba of 4096² takes ~115 ms on 2 cores, a
    stroke's box next to nothing); the image always receives the whole buffer, so it is right
    whatever else wrote it meanwhile."""
    rgba: np.ndarray            # float32 (H, W, 4): grey_rgba of the grey and alpha written
    alpha: bool                 # it had an alpha
    source: np.ndarray = None   # a derived image's: the source pixels it was made from (the
    recipe: str = ""            # array read, not a copy) and by what recipe (GreyMade)
    spare: np.ndarray = None    # the RGBA it last wrote at another size: a cos-θ image goes
    #                             between a live draft's size and its own (write_shadow), and
    #                             the final after a stroke then writes the stroke's box alone

    @property
    def nbytes(self):
        return sum(a.nbytes for a in (self.rgba, self.source, self.spare) if a is not None)


# image name → _Kept, up to KEPT_RGBA_MB (a 4096² painting's derived height, its source and
# one cos-θ image: 603 MB)
KEPT_RGBA_MB = 640
_KEPT_RGBA = BoundedCache(KEPT_RGBA_MB)


def grey_image(name, grey, alpha=None):
    """A float image holding a grey (H, W) in RGB and `alpha` (H, W; None: 1), written from
    the RGBA kept since its last write where there is one (only the pixels that changed are
    copied into it: the same RGBA as grey_rgba's)."""
    return made_grey_image(name, GreyMade(grey, alpha))


def made_grey_image(name, made):
    """grey_image of a GreyMade (make_derived's): of the whole image, or of its box alone
    (the source edited there; kept_source said what the rest was made from)."""
    grey = np.asarray(made.grey, np.float32)
    alpha = None if made.alpha is None else np.asarray(made.alpha, np.float32)
    hit = _KEPT_RGBA.get(name)
    if hit is not None and hit.rgba.shape[:2] != grey.shape and hit.spare is not None and \
            hit.spare.shape[:2] == grey.shape:
        hit.rgba, hit.spare = hit.spare, hit.rgba
    if made.box is not None:               # (make_derived asked kept_source: it is kept)
        rgba, box = hit.rgba, made.box
        grey_box = (0, grey.shape[0], 0, grey.shape[1])
    elif hit is None or hit.rgba.shape[:2] != grey.shape or hit.alpha != (alpha is not None):
        rgba, box = grey_rgba(grey, alpha), None
        other_size = hit is not None and hit.rgba.shape[:2] != grey.shape and \
            hit.alpha == (alpha is not None)      # (a spare always has its _Kept's alpha)
        hit = _Kept(rgba, alpha is not None, spare=hit.rgba if other_size else None)
    else:
        rgba = hit.rgba
        box = grey_box = union(changed_box(rgba[..., 0], grey),
                               None if alpha is None else changed_box(rgba[..., 3], alpha))
    if box is not None:
        r0, r1, c0, c1 = box
        g0, g1, h0, h1 = grey_box
        rgba[r0:r1, c0:c1, :3] = grey[g0:g1, h0:h1, None]
        if alpha is not None:
            rgba[r0:r1, c0:c1, 3] = alpha[g0:g1, h0:h1]
    hit.source, hit.recipe = made.source, made.recipe
    _KEPT_RGBA.put(name, hit, hit.nbytes)
    return float_image(name, rgba)


def kept_source(name, recipe):
    """The source pixels the grey image `name` was last made from by `recipe`, or None."""
    hit = _KEPT_RGBA.get(name)
    return None if hit is None or hit.recipe != recipe or not recipe else hit.source


# -- derived images -------------------------------------------------------------------------
def derived_image(settings, channel):
    return next((d.image for d in settings.derived if d.channel == channel), None)


def update_derived_images(mat, state, force=False, small=None):
    """Make the images numpy derives from the inputs (state.plan: PaintingState's), only those
    whose key changed (or all: `force`), reading each source once; drop the rest. small:
    {channel: ImageData} of a draft drawn smaller than its images (issue 42): what derives
    from them is made at their size and enlarged into its image (refill_enlarged: where it
    changed), the painting's size kept. → warnings (non-finite pixels replaced)."""
    s = mat.dynamic_painting
    imgs, plan, small = state.images, state.plan, small or {}
    stored = {d.channel: d for d in s.derived}
    todo = [d for d in plan if force or d.channel not in stored or stored[d.channel].image is None
            or stored[d.channel].key != d.key]
    if small:
        made, warnings = make_derived(
            todo, lambda c: small[c] if c in small else state.read(c),
            lambda c: pixel_role(c, state.params))
    else:
        made, warnings = _make(mat, state, todo, edits=not force)
    images = {}
    for item in todo:
        rgba = made[item.channel]
        if item.same_as:
            image = images.get(item.same_as) or derived_image(s, item.same_as)
        elif rgba is None:               # checked: the input itself has no NaN/Inf
            image = imgs[item.source]
        else:
            name = derived_name(mat, item)
            if item.source in small:
                image = enlarged_into(name, rgba, imgs[item.source].size)
            elif isinstance(rgba, GreyMade):
                image = made_grey_image(name, rgba)
            else:
                image = float_image(name, rgba)
        images[item.channel] = image
        _store(s, item.channel, image, item.key)
    wanted = {d.channel for d in plan}
    for i in reversed(range(len(s.derived))):
        if s.derived[i].channel not in wanted:
            s.derived.remove(i)
    return warnings


# A painting that moves (§16) comes round to its frames again: what they derived is kept by
# key, at most FRAME_DERIVED_MB per painting (the least recently shown dropped first), so a
# frame shown before costs the upload of its pixels, not their making.
FRAME_DERIVED_MB = 512
_MADE = {}       # material name → BoundedCache: derived key → RGBA (None: the source does)


def derived_name(mat, item):
    """The Blender image a derived item (derived_inputs.Derived) is written into."""
    return f"DP {mat.name} {item.channel}{' finite' * item.finite_copy}"


def _make(mat, state, todo, edits=True):
    """make_derived for `todo`, from the cache where a moving painting made them before;
    `edits`: a still painting's local grey images made again where their sources' edits
    changed them (not: whole, as Rebuild Material makes them)."""
    def role(channel):
        return pixel_role(channel, state.params)
    if not state.frame:           # a still painting's grey images: written where they changed
        return make_derived(todo, state.read, role, grey=True, made_from=None if not edits else
                            lambda item: kept_source(derived_name(mat, item), item.recipe))
    cache = _MADE.setdefault(mat.name, BoundedCache(FRAME_DERIVED_MB))
    found = {d.channel: cache.get(d.key) for d in todo}
    missing = [d for d in todo if found[d.channel] is None]
    made, warnings = make_derived(missing, state.read, role)
    for item in missing:
        rgba = made[item.channel]
        cache.put(item.key, (rgba,), 0 if rgba is None else rgba.nbytes)
        found[item.channel] = (rgba,)
    return {c: hit[0] for c, hit in found.items()}, warnings


def forget_frames_made():
    """Another file is open: what was derived may belong to same-named paintings of the last
    (and the RGBA kept for the images grey_image writes is memory only)."""
    _MADE.clear()
    _KEPT_RGBA.clear()


def _store(settings, channel, image, key):
    item = next((d for d in settings.derived if d.channel == channel), None)
    if item is None:
        item = settings.derived.add()
        item.channel = channel
    item.image, item.key = image, key


def image_rgba(data):
    """ImageData as the RGBA float32 buffer Blender's image holds (grey repeated, no alpha:
    1); pixels that are that already, as they are."""
    px = data.pixels
    if px.shape[2] == 4 and px.dtype == np.float32 and px.flags.c_contiguous:
        return px
    return np.concatenate([px[..., :1].repeat(3, -1) if px.shape[2] < 3 else px[..., :3],
                           px[..., -1:] if data.has_alpha else np.ones(px.shape[:2] + (1,))],
                          axis=2).astype(np.float32)


def resized_image(img, w, h):
    """`img` made to hold w × h pixels in place (the nodes and settings that show it keep it;
    its pixels to be written over): a generated image regenerated at that size (1–4 ms at
    1024²) — one packed_image packed is made generated again (scaling it decodes the packed
    file first: 26–75 ms; it is packed again on save, handlers.pack_edited_images) — another
    scaled → whether it holds that size now."""
    if tuple(img.size) != (w, h):
        if img.source == "FILE" and img.packed_file is not None and not img.filepath:
            img.source = "GENERATED"
        if img.source == "GENERATED":
            img.generated_width, img.generated_height = w, h
        else:
            img.scale(w, h)
    return tuple(img.size) == (w, h)


def refill_packed_image(img, data, rgba=None):
    """Write ImageData into an image packed_image made from data of the same size and kind,
    not packed (packing a 1024² image takes 75–260 ms): the file's save packs it
    (handlers.pack_edited_images) → whether it could (False: another size or bit depth);
    rgba: image_rgba(data) where it is made already (a worker thread's)."""
    h, w = data.pixels.shape[:2]
    if tuple(img.size) != (w, h) or img.is_float != (data.bits == 32):
        return False
    img.pixels.foreach_set((image_rgba(data) if rgba is None else rgba).ravel())
    return True


# image name → (the small RGBA refill_enlarged last wrote, its enlarged RGBA, the image's
# pointer: a new image of the name is another)
_ENLARGED = {}


def refill_enlarged(img, data):
    """A draft drawn smaller (ImageData of the image's kind) written into the packed image
    `img` at its size (bilinear, resample_separable), not packed: the full-size drawing that
    follows replaces it (forget_enlarged). After a draft of the same image only the pixels
    that read a changed small pixel are enlarged again (enlarged: the same values).
    → whether it wrote (False: nothing changed, or another bit depth)."""
    if img.is_float != (data.bits == 32):
        return False
    big = enlarged(img.name, img.as_pointer(), tuple(img.size), image_rgba(data))
    if big is None:
        return False
    img.pixels.foreach_set(big.ravel())
    return True


def enlarged(name, pointer, size, small):
    """refill_enlarged's numpy half (any thread): the RGBA `small` enlarged to `size` (w, h)
    into what image `name` (its as_pointer(); None: an image to be made anew, nothing kept)
    shows — after a draft of the same image only the pixels that read a changed small
    pixel (enlarged_box) — kept for the next → the full RGBA to write, or None where
    nothing changed."""
    w, h = size
    if pointer is None:
        return resample_separable(small, h, w)
    last = _ENLARGED.get(name)
    if last is not None and last[2] == pointer and last[0].shape == small.shape \
            and last[1].shape == (h, w, 4):
        box = changed_box(last[0], small)
        if box is None:
            return None
        big = last[1]
        r0, r1, c0, c1 = out = enlarged_box(box, small.shape[:2], (h, w))
        big[r0:r1, c0:c1] = resample_separable(small, h, w, out)
    else:
        big = resample_separable(small, h, w)
    _ENLARGED[name] = (small, big, pointer)
    return big


def keep_enlarged(name, pointer, small, big):
    """Tell refill_enlarged what image `name` (its as_pointer()) shows: `big`, its RGBA at
    full size, whose drawing made small is `small` (RGBA) — so the next draft enlarges only
    where its small drawing differs and keeps the rest as drawn in full (issue 61: the
    first stroke's draft, not the whole image, and not blurred). Any thread."""
    _ENLARGED[name] = (small, big, pointer)


def derived_shown(mat, state, channels):
    """What a draft's derived images are made from small (update_derived_images' `small`):
    the plan's items (state: PaintingState's) whose source is one of `channels` → (items,
    {channel: (image name, pointer, the RGBA it shows now)} of those with a float image of
    the painting's size) — main thread; keep_derived_enlarged uses them in any."""
    items = [d for d in state.plan if d.source in channels and not d.same_as]
    shown = {}
    for item in items:
        img = bpy.data.images.get(derived_name(mat, item))
        if img is not None and img.is_float and \
                tuple(img.size) == tuple(state.images[item.source].size):
            shown[item.channel] = (img.name, img.as_pointer(),
                                   image_rgba(image_data_from_blender(img)))
    return items, shown


def keep_derived_enlarged(items, shown, small, params):
    """derived_shown's items made from `small` ({channel: ImageData} drawn small) and kept
    for refill_enlarged against what their images show (keep_enlarged): a draft's first
    write enlarges only where it differs (issue 61). Any thread."""
    items = [item for item in items if item.source in small]
    made, _ = make_derived(items, lambda c: small[c], lambda c: pixel_role(c, params))
    for item in items:
        if made.get(item.channel) is not None and item.channel in shown:
            name, pointer, big = shown[item.channel]
            keep_enlarged(name, pointer, made[item.channel], big)


def enlarged_kept(img):
    """The full-size RGBA refill_enlarged keeps of `img` (what it shows), or None."""
    last = _ENLARGED.get(img.name)
    return last[1] if last is not None and last[2] == img.as_pointer() else None


def shows_enlarged(name, size):
    """(name, its as_pointer() or None, size): what enlarged needs to know of the float
    image `name` a draft enlarges into at `size` (w, h) — None where it is missing, or not
    a float image of that size (it is made anew: write_enlarged)."""
    img = bpy.data.images.get(name)
    ok = img is not None and tuple(img.size) == tuple(size) and img.is_float
    return name, img.as_pointer() if ok else None, tuple(size)


def write_enlarged(name, size, big):
    """enlarged's RGBA written into the float image `name`, or a new one where it is
    missing or not of `size` (main thread) → the image."""
    img = bpy.data.images.get(name)
    if img is None or tuple(img.size) != tuple(size) or not img.is_float:
        return float_image(name, big)
    img.pixels.foreach_set(big.ravel())
    return img


def enlarged_into(name, rgba, size):
    """The float image `name` holding RGBA made small, enlarged to `size` (w, h): after a
    draft of the same image only where it changed (enlarged), the whole of it where the
    image is new or of another size."""
    big = enlarged(*shows_enlarged(name, size), rgba)
    return bpy.data.images[name] if big is None else write_enlarged(name, size, big)


def remove_images(images):
    """Images the add-on made, removed (a lit copy made anew, a build that failed): an image
    made again under one of their names is then a new edit of it (its version bumped), so no
    key made of a name and a version mistakes it for the one removed; their kept drafts
    (refill_enlarged) go with them."""
    names = [img.name for img in images]
    for img in images:
        bpy.data.images.remove(img)
    note_edited(names)
    forget_enlarged(names)


def forget_enlarged(names=None):
    """The drafts kept by refill_enlarged of these images (all: None): written over since."""
    for name in list(_ENLARGED) if names is None else names:
        _ENLARGED.pop(name, None)


def packed_image(name, data, channel, pack=True):
    """An image numpy holds (core ImageData: a layer of an .ora file, a shaded copy) → a new
    image packed into the .blend, as the channel reads it (§0): 8- and 16-bit values stay
    file values (sRGB codes for colour), floats are linear or data. pack=False: packed when
    the file is saved (_packed_later)."""
    rgba = image_rgba(data)
    if data.bits == 32:
        return made_shape_image(name, rgba, pack)
    h, w = rgba.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True)
    prepare_channel_image(img, channel)
    img.pixels.foreach_set(np.ascontiguousarray(rgba).ravel())
    img.file_format = "PNG"
    _packed_later(img, pack)
    return img


def made_shape_image(name, rgba, pack=True):
    """A shape image numpy made (Make Shape) → a new float image packed into the .blend: undo
    removes it with the rest of the step, and no file appears beside the artist's images
    (Image › Save As keeps one). pack=False: packed when the file is saved."""
    h, w = rgba.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True, is_data=True)
    img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "CHANNEL_PACKED"
    img.use_half_precision = False
    img.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    img.file_format = "OPEN_EXR"
    _packed_later(img, pack)
    return img


PACK_ON_SAVE = "dynamic_painting_pack_on_save"   # an image made unpacked: pack it on save


def _packed_later(img, pack):
    """Pack `img` now, or (pack False: a lit drawing made again while the artist draws —
    packing a 1024² image takes 75–260 ms) mark it to be packed when the file is saved
    (handlers.pack_edited_images)."""
    if pack:
        img.pack()
    else:
        img[PACK_ON_SAVE] = True
