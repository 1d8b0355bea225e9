"""Layers that shadow each other (pipeline.md §15): a scene of paintings at depths.

Each layer is a whole painting on the plane z = z_i of one shared canvas, placed by an offset
and a scale (`Placement`). It is shaded by §2–§11 in its own pixels, except that its cos-θ
term is t = t_own·T, where T is what the layers in front let through along its §6 ray
(`transmittance`); the scene is then composited back to front (`render_scene`).

Layer k, seen from the layers behind it, is the solid
S_k = {(x, y, z): α_k(x, y) ≥ ½, z_k − τ_k ≤ z ≤ z_k + relief_k(x, y)} of opacity
ρ_k = 1 − k_k, and T = Π_{k in front} (1 − ρ_k·v_k), v_k saying whether the ray passes
through S_k. A light with a size (a sun's angular diameter, a point light's radius) replaces
v_k by the share of its disc whose rays do. Distances here are pixels of the canvas, z toward
the viewer from the plane of depth 0.

    >>> import numpy as np
    >>> from dynpaint_addon.core.lights import Light
    >>> card = Occluder(alpha=np.ones((8, 8)), relief_px=np.zeros((8, 8)), z_px=4.0,
    ...                 thickness_px=1.0, opacity=np.ones((8, 8)))
    >>> origins = np.zeros((8, 8, 3)); origins[..., 0] = 4.5; origins[..., 1] = 4.5
    >>> float(transmittance(origins, Light("sun", (0, 0, 1)), [card]).max())
    0.0
"""
from dataclasses import dataclass, field, replace

import numpy as np

from .pipeline import (normal_map_relief_px, prepare, render, silhouette_alpha,
                       transparency_k)
from .sampling import pixel_centres, sample_bilinear

# §15 for each quality level (§13): the march's spacing along a ray, in pixels of the layer
# that is crossed, and how many points of a light's disc a light with a size is sampled at.
# The slab of a flat card is crossed in a few pixels, so few samples are exact enough; a
# relief's slab takes one sample per `spacing` pixels of its crossing, at most `steps`.
LAYER_QUALITY = {
    "draft": {"spacing": 2.0, "disc": 4},
    "preview": {"spacing": 1.0, "disc": 8},
    "final": {"spacing": 0.5, "disc": 16},
    "reference": {"spacing": 0.25, "disc": 64},
}
MAX_LAYERS = 8           # documented limit: the web page draws up to 8 (issue 30)


@dataclass(frozen=True)
class Placement:
    """Where a layer's pixels lie on the canvas (§15): canvas pixel = corner + px × layer
    pixel (x right, y up), its plane at depth z (canvas pixels toward the viewer)."""
    corner: tuple = (0.0, 0.0)
    px: float = 1.0
    z: float = 0.0

    def to_canvas(self, x, y, z):
        return (self.corner[0] + self.px * x, self.corner[1] + self.px * y, self.z + self.px * z)

    def to_layer(self, x, y):
        return (x - self.corner[0]) / self.px, (y - self.corner[1]) / self.px

    @property
    def identity(self):
        return self.corner == (0.0, 0.0) and self.px == 1.0


@dataclass
class Layer:
    """One painting of a scene (§15): its images and parameters, and where it lies."""
    images: dict                   # {channel: ImageData}, as a one-painting recipe gives them
    p: object                      # its §1–§11 parameters
    name: str = ""
    depth: float = 0.0             # z_i, canvas widths toward the viewer
    thickness: object = None       # τ_i, canvas widths; None: its tallest relief, ≥ 1 pixel
    offset: tuple = (0.0, 0.0)     # its centre from the canvas's centre, canvas widths
    scale: float = 1.0             # its width over the canvas's width


def placement(layer, size, canvas):
    """The Placement of a layer whose shape image is `size` (H, W) on a canvas (H, W)."""
    (h, w), (ch, cw) = size, canvas
    px = float(layer.scale) * cw / w
    cx = cw / 2 + float(layer.offset[0]) * cw
    cy = ch / 2 + float(layer.offset[1]) * cw
    return Placement((cx - w / 2 * px, cy - h / 2 * px), px, float(layer.depth) * cw)


@dataclass
class Occluder:
    """A layer in front, as the rays of the layers behind it meet it (§15 "Occluders").
    alpha, relief_px and opacity are images of its own pixels; relief_px, z_px and
    thickness_px are canvas pixels; place maps canvas x, y to its pixels."""
    alpha: np.ndarray         # (H, W): its silhouette's alpha; the solid is where α ≥ ½
    relief_px: np.ndarray     # (H, W): its relief above its plane (0 for a flat card)
    z_px: float               # its plane's depth
    thickness_px: float       # τ: how far the solid reaches behind its plane
    opacity: np.ndarray       # (H, W): ρ = 1 − k (§11's transparency): 1 opaque, 0 clear
    place: Placement = field(default_factory=Placement)

    def __post_init__(self):
        self.top = self.z_px + float(np.max(self.relief_px, initial=0.0))
        self.bottom = self.z_px - self.thickness_px
        # the canvas box of its solid (where α ≥ ½): rays that miss it skip the layer
        rows, cols = np.nonzero(np.asarray(self.alpha) >= 0.5)
        if rows.size:
            x0, y0, _ = self.place.to_canvas(cols.min(), rows.min(), 0.0)
            x1, y1, _ = self.place.to_canvas(cols.max() + 1.0, rows.max() + 1.0, 0.0)
            self.box = (x0, y0, x1, y1)
        else:
            self.box = None


def disc_points(n):
    """n points spread evenly over the unit disc (a sunflower spiral; the centre for n = 1),
    each standing for an equal share of its area → (n, 2)."""
    if n <= 1:
        return np.zeros((1, 2))
    j = np.arange(n) + 0.5
    r, phi = np.sqrt(j / n), j * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)


def _basis(d):
    """Two unit vectors perpendicular to the unit vectors d (..., 3) and to each other."""
    helper = np.where(np.abs(d[..., 2:3]) < 0.9, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    u = np.cross(d, helper)
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    return u, np.cross(d, u)


def _rays(origins, light, canvas, disc):
    """The rays toward a light from each origin: [(unit directions (H, W, 3), lengths
    (H, W))], one per point of the light's disc (one for a light without size)."""
    o = origins
    points = disc_points(disc if light.size > 0 else 1)
    if light.kind == "sun":
        d = np.asarray(light.vector, np.float64)
        d = d / np.linalg.norm(d)
        u, v = _basis(d)
        spread = np.tan(light.size / 2)
        out = []
        for a, b in points:
            dj = d + spread * (a * u + b * v)
            out.append((np.broadcast_to(dj / np.linalg.norm(dj), o.shape),
                        np.full(o.shape[:2], np.inf)))
        return out
    centre = light.position_px(*canvas)
    to = centre[None, None, :] - o
    u, v = _basis(to / np.maximum(np.linalg.norm(to, axis=-1, keepdims=True), 1e-12))
    radius = light.size * canvas[1]
    out = []
    for a, b in points:                 # the disc of a sphere light as each origin sees it
        toj = to + radius * (a * u + b * v)
        length = np.linalg.norm(toj, axis=-1)
        out.append((toj / np.maximum(length, 1e-12)[..., None], length))
    return out


def _passes_through(o, d, length, k, spacing, steps):
    """(v, ρ) of one occluder for rays from o along d up to length: whether each ray passes
    through its solid, and the opacity where it first does."""
    h, w = o.shape[:2]
    hit, rho = np.zeros((h, w), bool), np.zeros((h, w))
    with np.errstate(divide="ignore", invalid="ignore"):
        s0 = np.where(d[..., 2] > 0, (k.bottom - o[..., 2]) / d[..., 2], np.inf)
        s1 = np.where(d[..., 2] > 0, (k.top - o[..., 2]) / d[..., 2], -np.inf)
    s0, s1 = np.maximum(s0, 0.0), np.minimum(s1, length)
    live = s1 > s0
    if k.box is None or not live.any():
        return hit, rho
    # rays whose crossing of the slab misses the solid's box never meet it
    ends = [o[..., :2] + np.where(live, s, 0.0)[..., None] * d[..., :2] for s in (s0, s1)]
    lo, hi = np.minimum(*ends), np.maximum(*ends)
    x0, y0, x1, y1 = k.box
    live &= (hi[..., 0] >= x0) & (lo[..., 0] <= x1) & (hi[..., 1] >= y0) & (lo[..., 1] <= y1)
    idx = np.nonzero(live)
    if not idx[0].size:
        return hit, rho
    o, d, s0, s1 = o[idx], d[idx], s0[idx], s1[idx]
    # samples: one per `spacing` pixels of the layer crossed, at least one, at most `steps`
    across = float(np.max((s1 - s0) * np.hypot(d[:, 0], d[:, 1]))) / k.place.px
    n = int(min(max(steps, 1), max(1, np.ceil(across / spacing) + 1)))
    got, r = np.zeros(s0.shape, bool), np.zeros(s0.shape)
    lh, lw = k.alpha.shape
    for j in range(n):                          # midpoints of n equal parts of the crossing
        s = s0 + (s1 - s0) * ((j + 0.5) / n)
        p = o + s[:, None] * d
        x, y = k.place.to_layer(p[:, 0], p[:, 1])
        on = ~got & (x >= 0) & (x <= lw) & (y >= 0) & (y <= lh)
        inside = on & (sample_bilinear(k.alpha, x, y) >= 0.5) & \
            (p[:, 2] <= k.z_px + sample_bilinear(k.relief_px, x, y))
        r = np.where(inside, sample_bilinear(k.opacity, x, y), r)
        got |= inside
    hit[idx], rho[idx] = got, r
    return hit, rho


def transmittance(origins, light, occluders, steps=64, *, canvas=None, spacing=None, disc=16):
    """T (H, W) of §15: what `occluders` (the layers in front) let through along each ray.

    Parameters
    ----------
    origins : ndarray (H, W, 3)
        Each pixel's P0 (§6: its surface point moved back by d along its normal), canvas
        pixels, z toward the viewer.
    light : core.lights.Light
        A sun (direction toward the light) or a point light (position, image widths from the
        canvas's centre, §0); its `size` (a sun's angular diameter in radians, a point
        light's radius in image widths) softens the shadows of the layers.
    occluders : list of Occluder
        The layers in front of the receiving one (those behind never occlude: rays rise).
    steps : int
        At most this many samples along the part of a ray inside an occluder's slab
        [z_k − τ_k, z_k + max relief].
    canvas : (H, W)
        The canvas's size in pixels (where a point light is); default origins' own.
    spacing : float
        Samples along a crossing this many pixels of the crossed layer apart (default: one
        sample per pixel of the crossing's length over `steps`, as a plain K-step march).
    disc : int
        Points of the light's disc sampled for a light with a size.

    Returns
    -------
    ndarray (H, W)
        T in [0, 1]: 1 where nothing in front is met, Π (1 − ρ_k) over the layers met,
        averaged over the light's disc.
    """
    o = np.asarray(origins, np.float64)
    canvas = canvas or o.shape[:2]
    total = np.zeros(o.shape[:2])
    rays = _rays(o, light, canvas, disc)
    for d, length in rays:
        t = np.ones(o.shape[:2])
        for k in occluders:
            gap = spacing if spacing is not None else 1e-9   # None: always `steps` samples
            hit, rho = _passes_through(o, d, length, k, gap, steps)
            t *= 1.0 - np.clip(rho, 0.0, 1.0) * hit
        total += t
    return total / len(rays)


# -- a scene of layers ---------------------------------------------------------------------

@dataclass
class SceneResult:
    rgba: np.ndarray           # the composite, premultiplied linear RGBA on the canvas (H, W, 4)
    layers: list               # per layer: its RenderResult in its own pixels
    t: list                    # per layer: its cos-θ terms t = t_own·T, one per light
    warnings: list


def canvas_size(layers, canvas=None):
    """The canvas (H, W): the one given, else the back layer's shape image's size."""
    if canvas is not None:
        return int(canvas[0]), int(canvas[1])
    return tuple(layers[0].images["shape"].pixels.shape[:2])


def light_in_layer(light, place, size, canvas):
    """A scene's light as a layer of `size` (H, W) placed by `place` on `canvas` (H, W) sees
    it (§0 in the layer's own frame): a sun is the same; a point light is moved into the
    layer's pixels and measured in its image widths from its centre."""
    if light.kind == "sun":
        return light
    (h, w), (x, y, z) = size, light.position_px(*canvas)
    lx, ly = place.to_layer(x, y)
    return replace(light, vector=((lx - w / 2) / w, (ly - h / 2) / w,
                                  (z - place.z) / place.px / w))


def _origins(ready, p, place):
    """Each pixel's P0 (§6) in canvas pixels → (H, W, 3)."""
    h, w = ready.size
    n = ready.n.astype(np.float64)
    x, y = pixel_centres(h, w, np.float64)
    zs = ready.z_px if ready.z_px is not None and p.shape.kind == "height" else 0.0
    d = max(0.0, float(p.shadows.offset)) * w
    return np.dstack(place.to_canvas(x - d * n[..., 0], y - d * n[..., 1], zs - d * n[..., 2]))


def _occluder(ready, p, place, thickness):
    """A prepared layer as the layers behind it meet it (§15 "Occluders")."""
    if ready.z_px is not None:
        relief = ready.z_px
    else:                                        # a normal map: its integrated relief (§6)
        relief = normal_map_relief_px(ready.n, ready.imgs["shape"])
    relief = np.nan_to_num(np.asarray(relief, np.float64)) * place.px
    alpha = silhouette_alpha(ready.imgs, p)
    alpha = np.ones(ready.size) if alpha is None else alpha.astype(np.float64)
    tau = float(np.max(relief, initial=0.0)) if thickness is None else thickness
    return Occluder(alpha, relief, place.z, max(tau, place.px) if thickness is None else tau,
                    1.0 - transparency_k(ready, p), place)


def render_scene(layers, lights, canvas=None, dtype=np.float32, progress=None):
    """Render a scene of layers (§15) → SceneResult.

    layers: [Layer], back to front by depth (equal depths keep their order); lights: the
    scene's [Light] (positions in image widths from the canvas's centre); canvas: (H, W) in
    pixels (default: the back layer's shape image's size). Each layer is rendered by
    pipeline.render in its own pixels with its lights' terms times T (`transmittance` through
    the layers in front, at its own shadows' quality level), then the layers are placed on
    the canvas and composited back to front by their alpha (orthographic). progress:
    optional callable(fraction done), once per layer. One layer at offset 0 and scale 1 on
    its own canvas renders exactly as pipeline.render.
    """
    if not layers:
        raise ValueError("a layered scene needs at least one layer")
    canvas = canvas_size(layers, canvas)
    order = sorted(range(len(layers)), key=lambda i: float(layers[i].depth))
    ready = {i: prepare(layers[i].images, layers[i].p, dtype) for i in order}
    places = {i: placement(layers[i], ready[i].size, canvas) for i in order}
    occluders = {}

    def occluder(k):
        if k not in occluders:
            tau = layers[k].thickness
            occluders[k] = _occluder(ready[k], layers[k].p, places[k],
                                     None if tau is None else float(tau) * canvas[1])
        return occluders[k]
    results, terms, warnings = [None] * len(layers), [None] * len(layers), []
    for position, i in enumerate(order):
        layer, place = layers[i], places[i]
        own = [light_in_layer(lt, place, ready[i].size, canvas) for lt in lights]
        front = [occluder(k) for k in order[position + 1:]]
        through = None
        if front:
            q = LAYER_QUALITY.get(layer.p.shadows.quality, LAYER_QUALITY["final"])
            origins = _origins(ready[i], layer.p, place)
            through = [transmittance(origins, lt, front, layer.p.shadows.steps, canvas=canvas,
                                     spacing=q["spacing"], disc=q["disc"]) for lt in lights]
        results[i] = render(layer.images, own, layer.p, dtype, prepared=ready[i],
                            through=through)
        terms[i] = results[i].passes.get("t", [])
        warnings += [f"layer {layer.name or i}: {w}" for w in results[i].warnings]
        if progress is not None:
            progress((position + 1) / len(order))
    rgba = np.zeros(canvas + (4,), dtype)
    for i in order:                                   # back to front, each over the rest
        top = _on_canvas(results[i].rgba, places[i], canvas)
        rgba = top + rgba * (1 - top[..., 3:4])
    return SceneResult(rgba, results, terms, warnings)


def _on_canvas(rgba, place, canvas):
    """A layer's premultiplied RGBA placed on the canvas: sampled bilinearly at each canvas
    pixel's centre, transparent outside the layer."""
    h, w = rgba.shape[:2]
    if place.identity and (h, w) == tuple(canvas):
        return rgba
    x, y = place.to_layer(*pixel_centres(*canvas, np.float64))
    inside = (x >= 0) & (x <= w) & (y >= 0) & (y <= h)
    return sample_bilinear(rgba, x, y) * inside[..., None].astype(rgba.dtype)
