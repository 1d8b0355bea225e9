"""What the layers in front let through (pipeline.md §15): T along a ray from each pixel's
surface point toward the light, through the solids of the layers in front.

Layer k, seen from the layers behind it, is the solid
S_k = {(x, y, z): α_k(x, y) ≥ ½, z_k − τ_k ≤ z ≤ z_k + relief_k(x, y)} of opacity
ρ_k = 1 − k_k, and T = Π_{k in front} (1 − ρ_k·v_k), v_k saying whether the ray passes
through S_k. A light with a size (a sun's angular diameter, a point light's radius) replaces
v_k by the share of its disc whose rays do. Distances here are pixels of the canvas, z toward
the viewer from the plane of depth 0. Three ways find v_k, fastest first: a sun's table over
a layer of one opacity (`SunTable`, core/occluders.py), a line map marched once on the
occluder's own pixels (`line_map`), the reference march (`_march`); core/layers.py makes the
scene they serve.

    >>> import numpy as np
    >>> from dynpaint_addon.core.lights import Light
    >>> from dynpaint_addon.core.occluders import Occluder
    >>> card = Occluder(alpha=np.ones((8, 8)), relief_px=np.zeros((8, 8)), z_px=4.0,
    ...                 thickness_px=1.0, opacity=np.ones((8, 8)))
    >>> origins = np.zeros((8, 8, 3)); origins[..., 0] = 4.5; origins[..., 1] = 4.5
    >>> float(transmittance(origins, Light("sun", (0, 0, 1)), [card]).max())
    0.0
"""
from dataclasses import dataclass

import numpy as np

from .occluders import kept_on, sample_layer, sun_table
from .sampling import pixel_centres
from .strokes import stepped, widened


def disc_points(n):
    """n points spread evenly over the unit disc (a sunflower spiral; the centre for n = 1),
    each standing for an equal share of its area → (n, 2)."""
    if n <= 1:
        return np.zeros((1, 2))
    j = np.arange(n) + 0.5
    r, phi = np.sqrt(j / n), j * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)


def _basis(d):
    """Two unit vectors perpendicular to the unit vector d and to each other."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(d, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(d, u)


def light_points(light, canvas, disc):
    """The points a light is sampled at (§15 "Light size") → [(kind, vector)]: a sun's
    directions (unit) over its angular disc, a point light's positions (canvas pixels) over
    its disc facing the canvas's centre; the light itself when it has no size."""
    points = disc_points(disc if light.size > 0 else 1)
    if light.kind == "sun":
        d = np.asarray(light.vector, np.float64)
        d /= np.linalg.norm(d)
        u, v = _basis(d)
        spread = np.tan(light.size / 2)
        tilted = [d + spread * (a * u + b * v) for a, b in points]
        return [("sun", t / np.linalg.norm(t)) for t in tilted]
    centre = light.position_px(*canvas)
    axis = centre - np.array([canvas[1] / 2, canvas[0] / 2, 0.0])
    u, v = _basis(axis / max(np.linalg.norm(axis), 1e-12))
    radius = light.size * canvas[1]
    return [("point", centre + radius * (a * u + b * v)) for a, b in points]


def _toward(o, kind, vector):
    """Unit directions (N, 3) from origins o (N, 3) toward a light point, and the rays'
    lengths (a sun's never end)."""
    if kind == "sun":
        return np.broadcast_to(vector, o.shape), np.full(len(o), np.inf)
    to = vector - o
    length = np.linalg.norm(to, axis=-1)
    return to / np.maximum(length, 1e-12)[:, None], length


def _march(o, d, length, k, spacing, steps, clearance=True):
    """(v, ρ, clearance) of one occluder for rays (N, 3) from o along d up to length,
    marched: whether each ray passes through its solid, the opacity where it first does, and
    how far its relief may move (canvas px, up or down, everywhere) before that can change
    (CLEARANCE; None without `clearance`: a line map keeps none)."""
    hit, rho = np.zeros(len(o), bool), np.zeros(len(o), np.float32)
    clear = np.full(len(o), np.inf, np.float32) if clearance else None
    with np.errstate(divide="ignore", invalid="ignore"):
        s0 = np.where(d[:, 2] > 0, (k.bottom - o[:, 2]) / d[:, 2], np.inf)
        s1 = np.where(d[:, 2] > 0, (k.top - o[:, 2]) / d[:, 2], -np.inf)
    s0, s1 = np.maximum(s0, 0.0), np.minimum(s1, length)
    live = s1 > s0
    if k.box is None or not live.any():
        return hit, rho, clear
    # rays whose crossing of the slab misses the solid's box never meet it
    ends = [o[:, :2] + np.where(live, s, 0.0)[:, None] * d[:, :2] for s in (s0, s1)]
    lo, hi = np.minimum(*ends), np.maximum(*ends)
    x0, y0, x1, y1 = k.box
    live &= (hi[:, 0] >= x0) & (lo[:, 0] <= x1) & (hi[:, 1] >= y0) & (lo[:, 1] <= y1)
    idx = np.flatnonzero(live)
    if not idx.size:
        return hit, rho, clear
    o, d, s0, s1 = o[idx], d[idx], s0[idx], s1[idx]
    # The slab in two parts, each sampled on its own: the card below the plane (τ thin: a
    # march over the whole slab could step over it) and the relief above it, each with one
    # sample per `spacing` pixels of the layer it crosses, its two ends among them (a thin
    # card's shadow ends where a ray grazes its faces), at most `steps`.
    with np.errstate(divide="ignore", invalid="ignore"):
        s_plane = np.clip((k.z_px - o[:, 2]) / d[:, 2], s0, s1)
    todo = np.arange(idx.size)       # the rays not yet inside, as positions into idx
    for a, b in ((s0, s_plane), (s_plane, s1)):
        todo = _march_part(o, d, a, b, k, spacing, steps, todo, idx, hit, rho, clear)
        if not todo.size:
            break
    return hit, rho, clear


MARCH_POINTS = 1 << 20     # a march's points sampled together (≈ 80 MB of arrays at most)


def _march_part(o, d, a, b, k, spacing, steps, todo, idx, hit, rho, clear):
    """March rays `todo` (positions into idx) over [a, b] of their crossing, from below: n
    points from end to end sample the silhouette, the relief only where it covers; the first
    point inside marks the ray hit, its ρ the opacity there, and the least |height − relief|
    of the points up to it (of all, for a ray that misses) bounds its clearance where `clear`
    is kept (arrays over all rays, indexed by idx) → the rays still not inside. Every point
    of a group of rays at once (MARCH_POINTS at a time): a loop over the points paid
    Python's overhead at each (a preview 2.3× slower)."""
    todo = todo[b[todo] > a[todo]]
    if not todo.size:
        return todo
    # each ray's own count (not the group's most: a ray's answer is the same whichever rays
    # it is marched with — a scene patched after an edit traces a block of them, Scene._patched)
    across = (b[todo] - a[todo]) * np.hypot(d[todo, 0], d[todo, 1]) / k.place.px
    count = np.minimum(max(steps, 2), np.maximum(2, np.ceil(across / spacing) + 1))
    n = int(count.max())
    lh, lw = k.alpha.shape
    missed, rays = [], max(1, MARCH_POINTS // n)
    for start in range(0, todo.size, rays):
        group = todo[start:start + rays]
        # (each j / (n − 1), as the loop had it; past a ray's own n, its far end again)
        along = np.minimum(np.arange(n)[None, :] / (count[start:start + rays, None] - 1), 1.0)
        s = a[group, None] + (b[group] - a[group])[:, None] * along
        p = o[group, None, :] + s[..., None] * d[group, None, :]
        x, y = k.place.to_layer(p[..., 0], p[..., 1])
        over = (x >= 0) & (x <= lw) & (y >= 0) & (y <= lh)
        over[over] = sample_layer(k.alpha, x[over], y[over]) >= 0.5
        surface = k.z_px + sample_layer(k.relief_px, x[over], y[over])
        if clear is not None:
            gap = np.full(over.shape, np.inf, np.float32)   # |height − relief| on the silhouette
            gap[over] = np.abs(p[..., 2][over] - surface)
        over[over] = p[..., 2][over] <= surface
        inside = over.any(axis=1)
        first = np.argmax(over[inside], axis=1)     # the first point inside, from below
        rows = np.flatnonzero(inside)
        if clear is not None:
            gap[rows] = np.where(np.arange(n)[None, :] <= first[:, None], gap[rows], np.inf)
            clear[idx[group]] = np.minimum(clear[idx[group]], gap.min(axis=1))
        hit[idx[group[inside]]] = True
        rho[idx[group[inside]]] = sample_layer(k.opacity, x[rows, first], y[rows, first])
        missed.append(group[~inside])
    return np.concatenate(missed) if missed else todo


def line_map(k, kind, vector, spacing, steps):
    """Which lines toward a light point pass through occluder k's solid, by where they cross
    its plane: (hit, ρ) images on its pixel grid (float32; hit 1 or 0, ρ the opacity where
    the line first meets the solid from below). Every ray that starts below the solid's
    slab and ends above it is decided by its line alone, so one march on the occluder's own
    pixels serves every pixel of every layer behind it (a shadow map of the solid, cached
    on the occluder per light point)."""
    return kept_on(k, (kind, tuple(np.round(vector, 9)), spacing, steps),
                 lambda: _line_map(k, kind, vector, spacing, steps))


def _line_map(k, kind, vector, spacing, steps):
    """line_map's march on the occluder's pixels near its solid → (hit, ρ) images."""
    lh, lw = k.alpha.shape
    hmap, rmap = np.zeros((lh, lw), np.float32), np.zeros((lh, lw), np.float32)
    rows, cols = _lines_near(k, kind, vector)
    if rows.stop > rows.start and cols.stop > cols.start:
        x, y = pixel_centres(lh, lw, np.float64)
        qx, qy, _ = k.place.to_canvas(x[rows, cols], y[rows, cols], 0.0)
        q = np.stack([qx.ravel(), qy.ravel(), np.full(qx.size, k.z_px)], axis=1)
        d, _ = _toward(q, kind, vector)
        with np.errstate(divide="ignore", invalid="ignore"):
            back = np.where(d[:, 2] > 0, (k.z_px - k.bottom) / d[:, 2], 0.0)
            length = np.where(d[:, 2] > 0, (k.top - k.bottom) / d[:, 2], 0.0)
        start = q - back[:, None] * d                 # where the line enters the slab
        hit, rho, _ = _march(start - 1e-9 * d, d, length + 2e-9, k, spacing, steps,
                             clearance=False)
        shape = (rows.stop - rows.start, cols.stop - cols.start)
        hmap[rows, cols], rmap[rows, cols] = hit.reshape(shape), rho.reshape(shape)
    return hmap, rmap


def _lines_near(k, kind, vector):
    """The rows and columns (slices) of occluder k's pixels whose lines toward a light point
    can meet its solid: its solid's box grown by how far a line moves sideways across the
    slab (a sun's once; a point light's the most at any corner of the layer)."""
    lh, lw = k.alpha.shape
    if k.box is None:
        return slice(0, 0), slice(0, 0)
    if kind == "sun":
        tan = np.hypot(vector[0], vector[1]) / max(vector[2], 1e-12)
    else:
        corners = np.array([k.place.to_canvas(cx, cy, 0.0)[:2] for cx in (0, lw) for cy in (0, lh)])
        rise = vector[2] - k.top
        tan = np.inf if rise <= 0 else np.max(np.hypot(*(corners - vector[:2]).T)) / rise
    grow = min((k.top - k.bottom) * tan, 1e12) / k.place.px + 1.0
    x0, y0 = k.place.to_layer(k.box[0], k.box[1])
    x1, y1 = k.place.to_layer(k.box[2], k.box[3])
    cols = slice(int(max(0, np.floor(x0 - grow))), int(min(lw, np.ceil(x1 + grow))))
    rows = slice(int(max(0, np.floor(y0 - grow))), int(min(lh, np.ceil(y1 + grow))))
    return rows, cols


@dataclass
class _Receiver:
    """The rays of one receiving layer as one occluder sees them: those that start under the
    top of its slab (the others rise away from it), where they start in its pixels and how
    far below its plane (negative inside the slab, above the plane)."""
    under: np.ndarray         # (N,) bool: the origin lies below the slab's top
    below: np.ndarray         # (M,) bool: of those, below the slab's bottom
    x: np.ndarray             # (M,) float32: the origins under the top, in the occluder's px
    y: np.ndarray
    rise: np.ndarray          # (M,) float32: from each up to the occluder's plane, canvas px


def _receiver(o, k):
    under = o[:, 2] < k.top
    x, y = k.place.to_layer(o[under, 0], o[under, 1])
    return _Receiver(under, o[under, 2] < k.bottom, x.astype(np.float32),
                     y.astype(np.float32), (k.z_px - o[under, 2]).astype(np.float32))


def _through_one(o, r, kind, vector, k, spacing, steps, maps, centre, exact):
    """(v, ρ, clearance) of occluder k for rays from o (N, 3) toward one light point (r:
    _receiver(o, k); vector (3,), or (N, 3): each ray's own point of the light, _shared). With `maps`: a sun
    over a layer of one opacity by its SunTable, every ray that starts under the slab's top; otherwise the line map toward the light's centre point (`centre`),
    read where a ray crosses the occluder's plane, for rays that start below the slab and
    whose light lies above it; the rest by a march of each ray. (For a point of a light's
    disc the centre's table or map stands in for its own: the lines differ in slope by at
    most half the light's angle, which moves where they cross a slab of thickness τ by
    τ·tan(β/2) — the light-size filtering of a shadow map.) With `exact`, a ray whose line
    the table or map cannot decide (the solid's edge passes between its samples) is marched;
    without (a draft), the table's nearer row or the map's ½ decides it. Clearance
    (CLEARANCE): the table's and the march's own; a line map's lines are not told apart (0)."""
    hit, rho = np.zeros(len(o), bool), np.zeros(len(o), np.float32)
    clear = np.full(len(o), np.inf, np.float32)
    vector = np.asarray(vector, np.float64)
    under = np.flatnonzero(r.under)

    def of(rays):                   # the light point's coordinates for these rays
        return vector if vector.ndim == 1 else vector[rays]
    table = maps and kind == "sun" and k.uniform is not None
    if table:                       # every ray under the top
        by_line = np.ones(len(r.x), bool)
    elif maps:
        by_line = r.below if kind == "sun" else r.below & (of(under)[..., 2] > k.top)
    else:
        by_line = np.zeros(len(r.x), bool)
    if by_line.any():               # where each line crosses the occluder's plane (its px)
        rx, ry, rise = r.x[by_line], r.y[by_line], r.rise[by_line]
        where = under[by_line]
        v = of(where)
        if kind == "sun":
            along = rise * np.asarray(1 / (v[..., 2] * k.place.px), np.float32)
            x = rx + along * v[..., 0].astype(np.float32)
            y = ry + along * v[..., 1].astype(np.float32)
        else:
            reach = rise / (np.asarray(v[..., 2] - k.z_px, np.float32) + rise)
            lx, ly = k.place.to_layer(v[..., 0], v[..., 1])
            x = rx + reach * (np.asarray(lx, np.float32) - rx)
            y = ry + reach * (np.asarray(ly, np.float32) - ry)
    rest = np.zeros(len(o), bool)
    rest[under[~by_line]] = True
    if table and by_line.any():
        got, doubt, clear[where] = sun_table(k, centre).meets(x, y, rise, exact)
        hit[where], rho[where] = got, np.float32(k.uniform) * got
        rest[where[doubt]] = True
    elif by_line.any():
        hmap, rmap = line_map(k, kind, centre, spacing, steps)
        lh, lw = hmap.shape
        on = (x >= 0) & (x <= lw) & (y >= 0) & (y <= lh)
        cover = np.zeros(len(x), np.float32)
        cover[on] = sample_layer(hmap, x[on], y[on])
        # a line among the map's lines that all meet the solid meets it, one among lines that
        # all miss misses it; between them (the solid's edge) the ray is marched
        got = cover >= np.float32(1 - 1e-6 if exact else 0.5)
        r_got = np.zeros(len(x), np.float32)
        r_got[got] = sample_layer(rmap, x[got], y[got]) / cover[got]   # ρ of the covering lines
        hit[where], rho[where] = got, r_got
        clear[where[on]] = 0.0
        if exact:
            rest[where[~got & (cover > np.float32(1e-6))]] = True
    if rest.any():
        d, length = _toward(o[rest], kind, of(rest))
        hit[rest], rho[rest], marched = _march(o[rest], d, length, k, spacing, steps)
        clear[rest] = np.minimum(clear[rest], marched)
    return hit, rho, clear


def transmittance(origins, light, occluders, steps=64, *, canvas=None, spacing=None, disc=16,
                  penumbra=0, maps=True, antialias=1, edge_points=0, only=None,
                  clearance=False):
    """T (H, W) of §15: what `occluders` (the layers in front) let through along each ray.

    Parameters
    ----------
    origins : ndarray (H, W, 3)
        Each pixel's surface point P_S (on its relief), canvas pixels, z toward the viewer:
        the centres of a grid of pixels.
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
        Points of the light's disc sampled for a light with a size (light_points).
    penumbra : int
        Where the `disc` points of a ray disagree (it starts in a penumbra), its share of
        the disc is sampled again at this many points instead: a share quantised to 1/16
        moves where a penumbra crosses ½ by a good part of the penumbra's width, and the
        rays that need the finer disc are the few in penumbrae. ≤ disc: none.
    maps : bool
        Decide rays that start below an occluder by its line map (line_map) rather than
        each by its own march: the same solid, sampled on the occluder's pixels.
    antialias : int
        Where T steps by more than EDGE_STEP between neighbouring pixels (an edge a pixel's
        centre alone decides all or nothing), T is the mean over an antialias × antialias
        grid of points across the pixel (same height): the share of the pixel in shadow,
        as a render's pixel shows it; and a ray the maps cannot decide is marched. 1 (a
        draft): the centre alone, decided by the maps.
    edge_points : int
        For a light with a size: each of an edge pixel's antialiasing rays sampled at this
        many of the light's points (the finer disc's, shared among the pixel's rays: the
        pixel and the disc integrated together, as a render's samples do) rather than at
        every point (0). 4 with 16 rays: 64 rays a pixel, not 16 × (16 + 64) — 1.7–3.3×
        faster bakes at 512², their mean error against the reference 0–12 % more, against
        Cycles within every goal (docs/pipeline.md §15 "Edges", docs/layers-truth.md).
    only : ndarray (H, W) bool, optional
        Trace these pixels alone (a scene patched after an edit, core/layers.py), their
        neighbours' centres too (the edge test compares them): each equals the whole bake's
        pixel bit for bit (every ray is traced on its own).
    clearance : bool
        Return each pixel's clearance too: the least over every occluder (below).

    Returns
    -------
    ndarray (H, W)
        T in [0, 1]: 1 where nothing in front is met, Π (1 − ρ_k) over the layers met,
        averaged over the light's disc; NaN outside `only`. With `clearance`, (T, (H, W)
        float32): how far any occluder's relief may move (canvas px, up or down, everywhere
        a pixel's rays read it) before a ray that decided the pixel's T can change — the
        least over its rays of |ray height − relief| where they cross a solid's silhouette
        (inf: none does; NaN outside `only`), core/layer_edits.py's CLEARANCE.
    """
    o = np.asarray(origins)
    o = o if o.dtype in (np.float32, np.float64) else o.astype(np.float64)
    shape = o.shape[:2]
    canvas = canvas or shape
    gap = spacing if spacing is not None else 1e-9   # None: always `steps` samples
    points = light_points(light, canvas, disc)
    finer = light_points(light, canvas, penumbra) if penumbra > len(points) > 1 else None
    _, centre = light_points(light, canvas, 1)[0]

    def over_disc(rays, points):
        """T of rays (N, 3) averaged over `points`, whether the points disagreed, and the
        rays' clearance (N,)."""
        receivers = [_receiver(rays, k) for k in occluders]
        total, low, high = np.zeros(len(rays)), np.ones(len(rays)), np.zeros(len(rays))
        clear = np.full(len(rays), np.inf, np.float32)
        for kind, vector in points:
            t = np.ones(len(rays))
            for k, r in zip(occluders, receivers):
                hit, rho, c = _through_one(rays, r, kind, vector, k, gap, steps, maps, centre,
                                           exact=antialias > 1)
                t *= 1.0 - np.clip(rho, 0.0, 1.0) * hit
                np.minimum(clear, c, out=clear)
            total += t
            np.minimum(low, t, out=low)
            np.maximum(high, t, out=high)
        return total / len(points), low < high, clear

    def through(rays):
        t, mixed, clear = over_disc(rays, points)
        if finer is not None and mixed.any():
            t[mixed], c = _each_point(rays[mixed], finer, over_disc)
            clear[mixed] = np.minimum(clear[mixed], c)
        return t, clear

    if only is None:
        t, clear = (a.reshape(shape) for a in through(o.reshape(-1, 3)))
    else:
        near = widened(only)
        t, clear = np.full(shape, np.nan), np.full(shape, np.nan, np.float32)
        t[near], clear[near] = through(o[near])
    edge = _edges(t) if antialias > 1 and min(shape) >= 2 else None
    if edge is not None and only is not None:
        edge &= only
    if edge is not None and edge.any():
        across = (np.arange(antialias) + 0.5) / antialias - 0.5       # the pixel's grid
        gx, gy = np.meshgrid(across, across)
        step_x, step_y = o[0, 1] - o[0, 0], o[1, 0] - o[0, 0]         # one pixel on the canvas
        step_x[2] = step_y[2] = 0.0
        shift = gx.reshape(-1, 1) * step_x + gy.reshape(-1, 1) * step_y
        rays = (o[edge][:, None, :] + shift[None].astype(o.dtype)).reshape(-1, 3)
        n = antialias * antialias
        if 0 < edge_points < len(points):
            t[edge], c = _shared(rays.reshape(-1, n, 3), finer or points, n, edge_points,
                                 over_disc)
        else:
            t_rays, c = through(rays)
            t[edge], c = t_rays.reshape(-1, n).mean(axis=1), c.reshape(-1, n).min(axis=1)
        clear[edge] = np.minimum(clear[edge], c)
    if only is not None:
        t[~only] = np.nan
        clear[~only] = np.nan
    return (t, clear) if clearance else t


def _shared(rays, points, n, each, over_disc):
    """T of edge pixels (rays (N, n, 3): each pixel's n antialiasing rays), the light's
    points shared among a pixel's rays: ray j toward `each` of them, every m-th from j mod
    m (m = len(points) / each: with 64 points and 16 rays, each point once) → the mean
    over the n rays (N,). The n rays of SHARED_PIXELS pixels go together, each toward its
    own point (a stroke's few edges cost the per-call work of numpy 16 times less: issue
    61), the same numbers as one ray j at a time; and each pixel's clearance (its rays'
    least)."""
    m, total = max(1, len(points) // each), np.zeros(len(rays))
    clear = None
    if m * each != len(points):            # (some rays would take one point more)
        for j in range(n):
            t, _, c = over_disc(rays[:, j], points[j % m::m])
            total += t
            clear = c if clear is None else np.minimum(clear, c)
        return total / n, clear
    table, j = np.array([v for _, v in points]), np.arange(n) % m
    for p0 in range(0, len(rays), SHARED_PIXELS):
        chunk = rays[p0:p0 + SHARED_PIXELS]
        own = [(points[0][0], np.tile(table[j + i * m], (len(chunk), 1))) for i in range(each)]
        t, _, c = over_disc(chunk.reshape(-1, 3), own)
        t, c = t.reshape(len(chunk), n), c.reshape(len(chunk), n).min(axis=1)
        clear = c if clear is None else np.concatenate([clear, c])
        for jj in range(n):                 # (summed in ray order, as one at a time)
            total[p0:p0 + SHARED_PIXELS] += t[:, jj]
    return total / n, clear


SHARED_PIXELS = 1024    # edge pixels whose rays _shared traces together (16 rays each)


def _each_point(rays, points, over_disc):
    """T of rays (N, 3) averaged over `points`, as over_disc(rays, points) gives it, with
    every (ray, point) pair a ray toward its own point: PAIRS of them in one call (a
    penumbra's few rays at 64 points cost the per-call work of numpy 64 times less); and
    each ray's clearance (its pairs' least)."""
    table, total = np.array([v for _, v in points]), np.zeros(len(rays))
    clear, step = [], max(1, PAIRS // len(points))
    for a in range(0, len(rays), step):
        chunk = rays[a:a + step]
        own = [(points[0][0], np.tile(table, (len(chunk), 1)))]
        t, _, c = over_disc(np.repeat(chunk, len(points), axis=0), own)
        t = t.reshape(len(chunk), -1)
        clear.append(c.reshape(len(chunk), -1).min(axis=1))
        for i in range(len(points)):        # (summed in point order, as over_disc sums them)
            total[a:a + step] += t[:, i]
    return total / len(points), np.concatenate(clear)


PAIRS = 1 << 14         # (ray, light point) pairs _each_point traces together


EDGE_STEP = 0.25        # T's step between neighbouring pixels that antialiasing resolves


def _edges(t):
    """The pixels on either side of a step of T larger than EDGE_STEP to a neighbour."""
    return stepped(t, EDGE_STEP)
