"""Rules for imperfect input images, shared by the numpy core and the add-on (§14).

- Non-finite pixels (NaN, ±Inf; only float files can hold them): in a normal map the pixel
  becomes the flat normal (0.5, 0.5, 1.0) (what §2's fallback makes of it anyway); in a height
  map 0; in every other image NaN and −Inf become 0 and +Inf the image's largest finite value
  (a stray firefly stays as bright as the brightest real pixel, not infinite). Reported.
- A normal map must look like one: a grey image (one channel, or R = G = B everywhere) or one
  whose blue is below ½ (N.z < 0, facing away from the viewer) in most opaque pixels is
  refused with a message that says what it looks like instead — or which setting reads it (a
  two-channel map read as RGB). Unit vectors mostly facing away are a map made for a decoder
  that halves each tilt: usable, with a note. A usable map gets notes: read as two-channel,
  the share of its opaque pixels that face away (and the strength that keeps them).
- Per-pixel images of another size than the shape image are resampled to it (reported).
No bpy here.
"""
import numpy as np

from .shape import normal_vectors, resolve_encoding, scale_tilt

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


def _opaque(px):
    """Pixels that show (alpha above ½, or all of them without alpha)."""
    if px.shape[-1] in (2, 4):
        return np.nan_to_num(px[..., -1]) > 0.5
    return np.ones(px.shape[:-1], bool)


def normal_map_problem(px, name="shape image", encoding="auto"):
    """Why these pixels cannot be a normal map (one line), or None if they can.

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
    if resolve_encoding(rgb, encoding) == "rg":
        return None                      # blue is ignored
    opaque = _opaque(px)
    away = float(np.mean(rgb[..., 2][opaque] < 0.5)) if opaque.any() else 0.0
    if away > 0.5 and not _unit_vectors(rgb[opaque]):
        if resolve_encoding(rgb, "auto") == "rg":
            return (f"{name} stores only x and y (blue is 0 in every pixel: the two-channel "
                    f"convention): set the shape encoding to 'rg' or 'auto' "
                    f"(recipe: shape.encoding = \"rg\")")
        return (f"{name} does not look like a normal map: blue < 0.5 (a normal facing away from "
                f"the viewer) in {away:.0%} of its pixels; is it a colour or height image?")
    return None


def _unit_vectors(rgb):
    """Do most pixels hold unit vectors 2C − 1? A map made by software for a decoder that
    halves each tilt stores its tilts doubled — most face away — but every vector is still
    unit length; a colour or height image read as a normal map is not."""
    length = np.sqrt(np.sum((2 * rgb - 1) ** 2, axis=-1))
    return rgb.size > 0 and float(np.mean(np.abs(length - 1) < 0.05)) >= 0.8


def normal_map_notes(px, name="shape image", encoding="auto", strength=1.0):
    """What an artist should know about a usable normal map (§2), one line each: a map read
    as two-channel, and the share of its *opaque* pixels facing away from the viewer (tilted
    up to N.z = z_min), with the strength that would keep them if a halving decoder was meant."""
    px = np.asarray(px)
    rgb = np.nan_to_num(px[..., :3].astype(np.float32), posinf=0.0, neginf=0.0)
    resolved = resolve_encoding(rgb, encoding)
    notes = []
    if encoding == "auto" and resolved == "rg":
        notes.append(f"{name}: read as a two-channel normal map (x, y in red and green, "
                     f"z = √(1 − x² − y²))")
    n = normal_vectors(rgb, resolved, strength)
    opaque = _opaque(px) & (np.sqrt(np.sum(n * n, axis=-1)) >= 0.05)
    if not opaque.any():
        return notes
    away = float(np.mean(n[..., 2][opaque] < 0))
    if away > 0.01:
        hint = ""
        if strength == 1:
            halved = float(np.mean(scale_tilt(n, 0.5)[..., 2][opaque] < 0))
            if halved < away / 4:
                hint = ("; painted for a decoder that halves each tilt? shape strength 0.5 "
                        f"keeps {1 - halved / away:.0%} of them")
        notes.append(f"{name}: {away:.0%} of its opaque pixels face away from the viewer and "
                     f"are tilted up to the minimum N.z{hint}")
    return notes


MASK_CHANNELS = ("auto", "luminance", "red", "green", "blue", "alpha")
_CHANNEL_INDEX = {"red": 0, "green": 1, "blue": 2}


def mask_channel(px, channel="auto"):
    """The channel `mask_values` reads: `channel` itself, or for 'auto' the one pure channel a
    mask is painted in (the others 0 everywhere), else 'luminance'. Decided on the whole image
    (a part of it may look painted in one channel when the whole is not)."""
    px = np.asarray(px)
    if channel != "auto":
        return channel
    if px.shape[-1] >= 3:
        rgb = np.nan_to_num(px[..., :3])
        lit = [i for i in range(3) if np.max(rgb[..., i], initial=0) > 1 / 255]
        if len(lit) == 1 and np.min(rgb[..., lit[0]]) < np.max(rgb[..., lit[0]]):
            return ("red", "green", "blue")[lit[0]]
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
        return (f"{name}: read from its {resolved} channel (a mask painted in pure "
                f"{resolved}); set its channel to 'luminance' to read its brightness")
    return ""


def size_message(channel, size, shape_size):
    return (f"{channel} image is {size[0]}×{size[1]}, resampled to the shape image's "
            f"{shape_size[0]}×{shape_size[1]}")
