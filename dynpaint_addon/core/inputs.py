"""Rules for imperfect input images, shared by the numpy core and the add-on (§14).

- Non-finite pixels (NaN, ±Inf; only float files can hold them): in a normal map the pixel
  becomes the flat normal (0.5, 0.5, 1.0) (what §2's fallback makes of it anyway); in a height
  map 0; in every other image NaN and −Inf become 0 and +Inf the image's largest finite value
  (a stray firefly stays as bright as the brightest real pixel, not infinite). Reported.
- Guesses survive 8-bit export and JPEG compression (thresholds measured on noisy variants of
  every convention: docs/detection-numbers.md, benchmarks/detection.py) and are always said; an
  explicit setting (encoding, channel, strength) is obeyed, never refused by a guess.
- A normal map must be coloured: a grey image (one channel, or R = G = B everywhere) read as
  one is refused with a message naming the setting that reads it as a height map. Any coloured
  image is read. A map of unit vectors some of which face away can only be a map made for a
  decoder that halves each tilt, and so can a map of which (nearly) every pixel faces away:
  strength 'auto' reads them at 0.5, and says so; a map of other lengths that faces away in
  part cannot tell (no map of the usual convention does, but neither does a colour image read
  as one): its note names shape strength 0.5. The note on pixels facing away counts only those
  whose tilting back up changes the picture: inside the figure (not its antialiased edge) and
  beyond the minimum N.z (AWAY_NOTE, measured in docs/detection-numbers.md).
- Per-pixel images of another size than the shape image are resampled to it (reported).
No bpy here.
"""
import numpy as np

from .shape import (DEGENERATE_LENGTH, Z_MIN_DEFAULT, facing_away, normal_vectors, resolve_encoding,
                    resolve_strength, scale_tilt)

FLAT_NORMAL_RGB = (0.5, 0.5, 1.0)


def finite_pixels(px, role="colour"):
    """(H, W, C) pixels → (finite copy or the same array, number of non-finite values).

    role: "normal" (shape image read as a normal map), "height", or "colour" (everything else).
    """
    px = np.asarray(px)
    finite = np.isfinite(px)
    bad = int(px.size - np.count_nonzero(finite))
    if not bad:
        return px, 0
    if role == "normal":
        colour = px[..., :3]
        ok = np.all(np.isfinite(colour), axis=-1, keepdims=True)
        flat = np.broadcast_to(np.array(FLAT_NORMAL_RGB, px.dtype), colour.shape)
        out = np.concatenate([np.where(ok, colour, flat), px[..., 3:]], axis=-1)
        return np.where(np.isfinite(out), out, 0).astype(px.dtype, copy=False), bad
    if role == "height":
        return np.where(finite, px, 0).astype(px.dtype, copy=False), bad
    top = float(np.max(px[finite])) if np.any(finite) else 0.0
    out = np.nan_to_num(px, nan=0.0, posinf=top, neginf=0.0)
    return out.astype(px.dtype, copy=False), bad


def non_finite_message(name, bad):
    return (f"{name}: {bad} NaN/Inf value{'s' if bad != 1 else ''} replaced (NaN and −Inf → 0, "
            f"+Inf → the image's largest finite value; in a normal map: flat)")


def normal_map_problem(px, name="shape image", encoding="auto"):
    """Why these pixels cannot be a normal map (one line), or None if they can: only a grey
    image, which holds no direction at all (every coloured image is read, with notes).

    px: (H, W, C) file values in 0..1 (C = 1 … 4); encoding: shape.encoding (§2).
    """
    px = np.asarray(px)
    if px.shape[-1] < 3:
        return (f"{name} is a grey image: a normal map is RGB (read it as a height map: "
                f"shape kind 'height')")
    rgb = np.nan_to_num(px[..., :3].astype(np.float32), posinf=0.0, neginf=0.0)
    if np.allclose(rgb[..., 0], rgb[..., 1], atol=2e-3) and \
            np.allclose(rgb[..., 1], rgb[..., 2], atol=2e-3):
        return (f"{name} is grey (R = G = B everywhere): a normal map is coloured (flat = "
                f"light blue 0.5, 0.5, 1.0); read it as a height map: shape kind 'height'")
    return None


def normal_map_notes(px, name="shape image", encoding="auto", strength="auto"):
    """What an artist should know about a normal map (§2), one line each: a map read as
    two-channel or as painted for a decoder that halves each tilt (the 'auto' guesses), one
    that looks two-channel but is read as RGB by an explicit setting, and the share of its
    *opaque* pixels facing away from the viewer (tilted up to N.z = z_min), with the fix where
    a halving decoder may have been meant but the map cannot tell (its vectors are not unit
    length, as a colour or height image's are not either)."""
    px = np.asarray(px)
    rgb = np.nan_to_num(px[..., :3].astype(np.float32), posinf=0.0, neginf=0.0)
    alpha = px[..., 3] if px.shape[-1] == 4 else None
    resolved = resolve_encoding(rgb, encoding)
    looks_rg = resolve_encoding(rgb, "auto") == "rg"
    notes = []
    if encoding == "auto" and resolved == "rg":
        notes.append(f"{name}: read as a two-channel normal map (x, y in red and green, "
                     f"z = √(1 − x² − y²)); set shape encoding 'rgb' to read its blue")
    elif encoding == "rgb" and looks_rg:
        notes.append(f"{name}: its blue is about 0 everywhere, as in a two-channel map, but "
                     f"shape encoding 'rgb' reads it as blue (set 'auto' or 'rg' to read x, y)")
    k = resolve_strength(rgb, strength, encoding, alpha)
    as_painted = normal_vectors(rgb, resolved, 1.0)
    if strength == "auto" and k != 1:
        away = facing_away(as_painted, alpha)
        notes.append(f"{name}: read as painted for a decoder that halves each tilt, as the "
                     f"original research system's maps are (its vectors face away in "
                     f"{away:.0%} of its pixels): strength {k:g}; set shape strength 1 to read "
                     f"it as it is")
    away = noticeably_away(scale_tilt(as_painted, k), alpha)
    if away > AWAY_NOTE:
        hint = ""
        if strength == "auto" and k == 1 and not looks_rg:
            if noticeably_away(scale_tilt(as_painted, 0.5), alpha) < away / 4:
                hint = ("; painted for a decoder that halves each tilt? shape strength 0.5 "
                        "(recipe: shape.strength = 0.5) reads it so — its vectors are not "
                        "unit length, so the map cannot tell; or is it a colour or height "
                        "image?")
        notes.append(f"{name}: {away:.0%} of its opaque pixels face away from the viewer and "
                     f"are tilted up to the minimum N.z{hint}")
    return notes


# The note on pixels facing away: more than this share of the figure's inside faces away by
# more than the minimum N.z. Measured (docs/detection-numbers.md): usual maps, two-channel
# maps and maps with antialiased edges (alpha, colour premultiplied) ≤ 0.000 down to JPEG
# quality 30; a halving decoder's map read at strength 1 ≥ 0.2.
AWAY_NOTE = 0.01


def noticeably_away(n, alpha=None):
    """The share of a normal map's vectors n (…, 3) that face away by more than the minimum
    N.z (tilting them up changes the picture), among the non-degenerate ones inside the
    figure: opaque (alpha ≥ 0.99) with every neighbour opaque, for an antialiased edge mixes
    the normals with what lies outside. 0 if there are none."""
    length = np.sqrt(np.sum(n * n, axis=-1))
    keep = length >= DEGENERATE_LENGTH
    if alpha is not None:
        solid = np.pad(np.nan_to_num(alpha) >= 0.99, 1, constant_values=True)
        h, w = keep.shape[-2:]
        inside = np.ones(keep.shape, bool)
        for dy in (0, 1, 2):
            for dx in (0, 1, 2):
                inside &= solid[..., dy:dy + h, dx:dx + w]
        keep &= inside
    if not keep.any():
        return 0.0
    z = n[..., 2][keep] / length[keep]
    return float(np.mean(z < -Z_MIN_DEFAULT))


MASK_CHANNELS = ("auto", "luminance", "red", "green", "blue", "alpha")
_CHANNEL_INDEX = {"red": 0, "green": 1, "blue": 2}


# A mask painted in one pure channel (red on black): the other two stay below MASK_LEAK times
# the painted one (99.9th percentiles). Measured (docs/detection-numbers.md, 64² to 256²):
# one-channel masks leak at most 0.28 (JPEG, chroma subsampled), grey masks and colour images
# ≥ 0.93.
MASK_LEAK = 0.45


def mask_channel(px, channel="auto"):
    """The channel `mask_values` reads: `channel` itself, or for 'auto' the one channel a mask
    is painted in (the other two below MASK_LEAK of it, whatever 8-bit export or JPEG left in
    them), else 'luminance'. Decided on the whole image (a part of it may look painted in one
    channel when the whole is not).

    >>> px = np.zeros((4, 4, 3))
    >>> px[..., 0] = np.linspace(0, 1, 16).reshape(4, 4)   # painted in red …
    >>> px[..., 1:] = 0.03                                  # … with JPEG's noise in the others
    >>> mask_channel(px), mask_channel(np.repeat(px[..., :1], 3, -1))
    ('red', 'luminance')
    """
    px = np.asarray(px)
    if channel != "auto":
        return channel
    if px.shape[-1] >= 3:
        rgb = np.nan_to_num(px[..., :3].reshape(-1, 3).astype(np.float32))
        top = np.percentile(rgb, 99.9, axis=0) if len(rgb) else np.zeros(3)
        lit = int(np.argmax(top))
        others = np.delete(top, lit)
        if top[lit] > 1 / 255 and np.all(others <= MASK_LEAK * top[lit]) and \
                np.min(rgb[:, lit]) < np.max(rgb[:, lit]):
            return ("red", "green", "blue")[lit]
    return "luminance"


def mask_values(px, channel="auto"):
    """A data image read as one value per pixel (transparency k, gloss g; §7, §11) →
    (values (H, W), the channel read). 'luminance' is Rec.709 luminance of RGB (grey images:
    their grey); 'red', 'green', 'blue', 'alpha' read that channel; 'auto' reads a mask
    painted in one pure channel (the others 0 everywhere) from that channel, else luminance
    (`mask_channel`).
    """
    px = np.asarray(px)
    c = px.shape[-1]
    channel = mask_channel(px, channel)
    if channel == "alpha":
        return (px[..., -1] if c in (2, 4) else np.ones(px.shape[:-1], px.dtype)), channel
    if c < 3:
        return px[..., 0], channel if channel == "luminance" else "grey"
    if channel == "luminance":
        return px[..., :3] @ np.array([0.2126, 0.7152, 0.0722], px.dtype), channel
    return px[..., _CHANNEL_INDEX[channel]], channel


def mask_note(name, channel, resolved):
    """The line an artist gets when 'auto' read a mask from one pure channel."""
    if channel == "auto" and resolved in _CHANNEL_INDEX:
        return (f"{name}: read from its {resolved} channel (a mask painted in {resolved}; "
                f"the other channels hold at most noise); set its channel to 'luminance' to "
                f"read its brightness")
    return ""


def size_message(channel, size, shape_size):
    return (f"{channel} image is {size[0]}×{size[1]}, resampled to the shape image's "
            f"{shape_size[0]}×{shape_size[1]}")


def about(name, notes):
    """Notes of a layer or painting `name`, each led by its name once (a note of its images
    may name it already: `01_Ground: 01_Ground: …` was printed).

    >>> about("sky", ["sky: flat", "no light"])
    ['sky: flat', 'sky: no light']
    """
    return [n if n.startswith(f"{name}:") or n.startswith(f"{name} ") else f"{name}: {n}"
            for n in notes]
