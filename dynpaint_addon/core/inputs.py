"""Rules for imperfect input images, shared by the numpy core and the add-on (§14).

- Non-finite pixels (NaN, ±Inf; only float files can hold them): in a normal map the pixel
  becomes the flat normal (0.5, 0.5, 1.0) (what §2's fallback makes of it anyway); in a height
  map 0; in every other image NaN and −Inf become 0 and +Inf the image's largest finite value
  (a stray firefly stays as bright as the brightest real pixel, not infinite). Reported.
- A normal map must look like one: a grey image (one channel, or R = G = B everywhere) or one
  whose blue is below ½ (N.z < 0, facing away from the viewer) in most pixels is refused with
  a message that says what it looks like instead.
- Per-pixel images of another size than the shape image are resampled to it (reported).
No bpy here.
"""
import numpy as np

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


def normal_map_problem(px, name="shape image"):
    """Why these pixels cannot be a normal map (one line), or None if they can.

    px: (H, W, C) file values in 0..1 (C = 1 … 4).
    """
    px = np.asarray(px)
    if px.shape[-1] < 3:
        return (f"{name} is a grey image: a normal map is RGB (read it as a height map: "
                f"shape kind 'height')")
    rgb = np.nan_to_num(px[..., :3].astype(np.float32))
    if np.allclose(rgb[..., 0], rgb[..., 1], atol=2e-3) and \
            np.allclose(rgb[..., 1], rgb[..., 2], atol=2e-3):
        return (f"{name} is grey (R = G = B everywhere): a normal map is coloured (flat = "
                f"light blue 0.5, 0.5, 1.0); read it as a height map: shape kind 'height'")
    away = float(np.mean(rgb[..., 2] < 0.5))
    if away > 0.5:
        return (f"{name} does not look like a normal map: blue < 0.5 (a normal facing away from "
                f"the viewer) in {away:.0%} of its pixels; is it a colour or height image?")
    return None


def size_message(channel, size, shape_size):
    return (f"{channel} image is {size[0]}×{size[1]}, resampled to the shape image's "
            f"{shape_size[0]}×{shape_size[1]}")
