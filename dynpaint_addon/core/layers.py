"""Layers that shadow each other (pipeline.md §15): a scene of paintings at depths.

Each layer is a whole painting on the plane z = z_i of one shared canvas, placed by an offset
and a scale (`Placement`). It is shaded by §2–§11 in its own pixels, except that its cos-θ
term is t = t_own·T, where T is what the layers in front let through along the ray from
each pixel's surface point toward the light (core/transmittance.py, each layer in front an
`Occluder`, core/occluders.py); the scene is then composited back to front
(`render_scene`), and `scene_notes` says what an artist should know of it.
"""
import copy
import os
import threading
from dataclasses import dataclass, replace

import numpy as np

from .bake import QUALITY, quality_settings
from .input_rules import image_channels, input_notes, silhouette_channel
from .inputs import about
from .layer_edits import ALL, changed_over, near_edges, rays_changed, rays_lifted, solid_change
from .occluders import Occluder, Placement, edited_from, on_faces_lattice
from .pipeline import (normal_map_relief_px, prepare, render, shadow_term,
                       shadow_term_edited, silhouette_alpha, transparency_k)
from .sampling import pixel_centres, resample_separable, sample_bilinear
from .strokes import changed_box, union, widened
from .transmittance import light_points, transmittance

# §15 for each quality level (§13): the resolution T is found at (receivers and occluders
# alike, then resampled to each layer's pixels, as §13's bakes), the march's spacing along
# a ray in pixels of the layer crossed at that resolution, how many points of a light's
# disc a light with a size is sampled at (and at how many again where those disagree: a
# penumbra, "Light size"), the grid of rays (per side) across a pixel on a shadow's edge
# (transmittance's antialias) and how many of the light's points each of those is sampled
# at (edge_points; 0: all, the reference's).
# The slab of a flat card is crossed in a few pixels, so few samples are exact enough; a
# relief's slab takes one sample per `spacing` pixels of its crossing, at most `steps`.
# A preview (a dragged light) leaves the penumbra alone: sampling it again there cost 2.5×
# (a 5°-wide sun, 1024²), and the final follows when the light stops. The final's 8 points
# find the penumbrae its 64 sample (16 gave the same error against the reference, 0.5°–3°
# suns and a point light, 512²: 30 % slower; issue 61).
LAYER_QUALITY = {
    "draft": {"scale": 0.125, "spacing": 1.0, "disc": 4, "penumbra": 0, "antialias": 1,
              "edge_points": 0},
    "preview": {"scale": 0.5, "spacing": 1.0, "disc": 8, "penumbra": 0, "antialias": 2,
                "edge_points": 4},
    "final": {"scale": 1.0, "spacing": 1.0, "disc": 8, "penumbra": 64, "antialias": 4,
              "edge_points": 4},
    "reference": {"scale": 1.0, "spacing": 0.25, "disc": 64, "penumbra": 256, "antialias": 4,
                  "edge_points": 0},
}
MAX_LAYERS = 8           # documented limit: the web page draws up to 8 (issue 30)
BAKE_THREADS = min(2, os.cpu_count() or 1)   # layers a bake works on at once (numpy lets go
                        # of Python's lock in its loops: a stroke's two layers behind are traced
                        # side by side); two, as each layer in flight holds its own full-size
                        # arrays (the final of 3 layers at 1024²: 1.87× one layer's peak, ≤ 2×)


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


def _origins(ready, place, scale=1.0):
    """Each pixel's surface point P_S on its relief (§15: T's rays start there, not at §6's
    P0 — d below the surface would move every cast shadow by d·cot of the light's
    elevation) in canvas pixels → (H, W, 3); at `scale`, the centres of a grid of that
    share of the layer's pixels."""
    h, w = ready.size
    hs, ws = _scaled(h, scale), _scaled(w, scale)
    x, y = pixel_centres(hs, ws, np.float32)
    zs = np.zeros((hs, ws), np.float32) if ready.z_px is None else \
        resample_separable(np.nan_to_num(ready.z_px.astype(np.float32)), hs, ws)
    out = np.empty((hs, ws, 3), np.float32)        # (float32: 1e-3 px at 8192 px)
    out[..., 0], out[..., 1], out[..., 2] = place.to_canvas(
        x * np.float32(w / ws), y * np.float32(h / hs), zs)
    return out


def _scaled(n, scale):
    return max(2, int(round(n * scale)))


def _reduced(occ, scale):
    """An occluder's images at `scale` of its pixels (its place's pixels grown to match)."""
    h, w = occ.alpha.shape
    hs, ws = _scaled(h, scale), _scaled(w, scale)
    place = Placement(occ.place.corner, occ.place.px * w / ws, occ.place.z)
    return Occluder(*(resample_separable(a, hs, ws) for a in (occ.alpha, occ.relief_px)),
                    occ.z_px, occ.thickness_px, resample_separable(occ.opacity, hs, ws), place)


def _occluder(ready, p, place, thickness):
    """A prepared layer as the layers behind it meet it (§15 "Occluders")."""
    if ready.z_px is not None:
        relief = ready.z_px
    else:                                        # a normal map: its integrated relief (§6)
        relief = normal_map_relief_px(ready.n, ready.imgs["shape"])
    relief = np.nan_to_num(np.asarray(relief, np.float64)) * place.px
    alpha = silhouette_alpha(ready.imgs, p)
    alpha = np.ones(ready.size) if alpha is None else alpha.astype(np.float64)
    if thickness is None:           # §15's default: its tallest relief, at least a pixel
        thickness = max(on_faces_lattice(float(np.max(relief, initial=0.0))), place.px)
    return Occluder(alpha, relief, place.z, thickness, 1.0 - transparency_k(ready, p), place)


class Scene:
    """A scene of layers made ready to light (§15): each layer's inputs prepared once, its
    placement on the canvas, and (on first use) each layer as an occluder.

    layers: [Layer] (equal depths keep their order); canvas: (H, W) in pixels (default: the
    back layer's shape image's size); prepared: {index: its prepared inputs} of layers
    another Scene prepared already (the same images and parameters)."""

    def __init__(self, layers, canvas=None, dtype=np.float32, prepared=None, before=None):
        if not layers:
            raise ValueError("a layered scene needs at least one layer")
        if len(layers) > MAX_LAYERS:
            raise ValueError(f"{len(layers)} layers: a scene holds at most {MAX_LAYERS}")
        self.layers, self.canvas = layers, canvas_size(layers, canvas)
        self.order = sorted(range(len(layers)), key=lambda i: float(layers[i].depth))
        prepared = prepared or {}
        self.ready = {i: prepared[i] if i in prepared else
                      prepare(layers[i].images, layers[i].p, dtype,
                              before=_edited_from(before, layers, i)) for i in self.order}
        self.places = {i: placement(layers[i], self.ready[i].size, self.canvas)
                       for i in self.order}
        self._occluders, self._origins = {}, {}
        self.own = {}            # the last bake's own terms (bake's `own`)
        # per (layer, light name, level …): (the light's key, what the layer's full-size bake
        # of it gave) — an edited copy of this scene (`before`) patches them (_Earlier)
        self._throughs, self._owns = {}, {}
        self._changes = {}       # layer k → how an edit changed its solid (solid_change)
        self._earlier = _Earlier.of(before, self)
        self._making = threading.RLock()    # (occluders are made once, by one of bake's threads)

    def occluder(self, k, scale=1.0):
        """Layer k as the layers behind it meet it, its images at `scale` of its pixels (an
        earlier scene's where its inputs, place and thickness are the same: its maps kept)."""
        with self._making:
            return self._occluder(k, scale)

    def _occluder(self, k, scale):
        if (k, scale) not in self._occluders:
            e = self._earlier
            if scale == 1.0 and e is not None and e.ready[k] is self.ready[k] and \
                    k in e.occluders and e.layers[k].thickness == self.layers[k].thickness:
                self._occluders[k, scale] = e.occluders[k]
            elif scale == 1.0:
                tau = self.layers[k].thickness
                made = _occluder(self.ready[k], self.layers[k].p, self.places[k],
                                 None if tau is None else float(tau) * self.canvas[1])
                was = None if e is None else e.occluders.get(k)
                if was is not None and was.alpha.shape == made.alpha.shape:
                    # (an edited layer: its sun tables made again where the edit reads)
                    edited_from(was, made, union(changed_box(was.alpha, made.alpha),
                                                 changed_box(was.relief_px, made.relief_px)))
                self._occluders[k, scale] = made
            else:
                self._occluders[k, scale] = _reduced(self.occluder(k), scale)
        return self._occluders[k, scale]

    def own_lights(self, i, lights):
        """The scene's lights as layer i sees them (light_in_layer)."""
        return [light_in_layer(lt, self.places[i], self.ready[i].size, self.canvas)
                for lt in lights]

    def bake(self, light, quality=None, progress=None, reduced=1.0, own=None, own_size=False):
        """t = t_own·T of one light on every layer → [(H_i, W_i)] in the layers' order;
        each at its own shadows' quality level, or at `quality` for all (a live bake while
        a light is dragged: 'draft'). The inputs stay prepared: a scene made once serves
        every light of a drag. reduced: how many times smaller the scene's layers are than
        the paintings they stand for (§15, a scene drawn small): each level's reduction of the
        pixels is divided by it, so the level reads about as many pixels as it would at
        full size (its K and sampling kept; the own term marched). own: {index: an entry
        of an earlier bake's `self.own`} of layers whose inputs and parameters are those it
        was baked from (a stroke on another layer: draft_group): its t_own is used where the
        light it saw and the level are this bake's, not marched again; this bake's entries
        are left in `self.own`. own_size: a layer's t at a reduced level at the size its own
        term was baked at (core/bake.bake's own_size; T resampled to it), for a caller that
        writes images, which every backend enlarges alike: a drag then upsamples nothing.
        Up to BAKE_THREADS layers are baked at once (progress is called from this thread)."""
        out, own, self.own = [None] * len(self.layers), own or {}, {}

        def layer(i):
            p = self.layers[i].p
            if quality is not None or reduced != 1.0:
                p = copy.deepcopy(p)
                p.shadows.quality = quality or p.shadows.quality
            level = p.shadows.quality
            if reduced != 1.0 and level in QUALITY:
                p.shadows.steps, scale, _ = quality_settings(level)
                p.shadows.quality, p.shadows.resolution = "custom", min(1.0, scale * reduced)
            seen = (self.own_lights(i, [light])[0], quality, reduced, own_size)
            t_own = own[i][1] if i in own and own[i][0] == seen else self._own_term(i, seen, p)
            self.own[i] = (seen, t_own)
            through = self.through(i, [light], level, reduced, t_own.shape)
            return t_own if through is None else t_own * through[0].astype(t_own.dtype)
        baked = _side_by_side(layer, self.order, min(BAKE_THREADS, len(self.order)))
        for position, (i, t) in enumerate(zip(self.order, baked)):
            out[i] = t
            if progress is not None:
                progress((position + 1) / len(self.order))
        e = self._earlier             # (every bake it had made again: let it go)
        if e is not None and set(e.throughs) <= set(self._throughs) and \
                set(e.owns) <= set(self._owns):
            self._earlier = None
        return out

    def through(self, i, lights, quality=None, reduced=1.0, size=None):
        """Per light, T of layer i (§15): what the layers in front let through along its
        rays, at its own shadows' quality level (its pixels' reduction divided by
        `reduced`: bake), resampled to `size` (h, w; default the layer's); None when nothing
        is in front."""
        p = self.layers[i].p
        level = quality or p.shadows.quality
        q = dict(LAYER_QUALITY.get(level, LAYER_QUALITY["final"]))
        q["scale"] = min(1.0, q["scale"] * reduced)
        front = [self.occluder(k, q["scale"]) for k in self.order[self.order.index(i) + 1:]]
        if not front:
            return None
        h, w = size or self.ready[i].size
        if (i, q["scale"]) not in self._origins:         # a drag moves the light only
            e = self._earlier            # (a layer an edit left alone: its surface as it was)
            same = e is not None and q["scale"] == 1.0 and e.ready[i] is self.ready[i] \
                and i in e.origins
            self._origins[i, q["scale"]] = e.origins[i] if same else \
                _origins(self.ready[i], self.places[i], q["scale"])
        origins = self._origins[i, q["scale"]]

        def traced(lt, o, only=None, clearance=False):
            got = transmittance(o, lt, front, p.shadows.steps, canvas=self.canvas,
                                spacing=q["spacing"], disc=q["disc"], penumbra=q["penumbra"],
                                maps=level != "reference", antialias=q["antialias"],
                                edge_points=q["edge_points"], only=only, clearance=clearance)
            return (got[0].astype(np.float32), got[1]) if clearance else \
                got.astype(np.float32)
        out = []
        for lt in lights:
            slot = (i, lt.name, level, q["scale"], p.shadows.steps)
            if q["scale"] == 1.0:     # (kept with its clearance: an edited copy patches it)
                t, clear = self._patched(i, lt, slot, q, traced) or \
                    traced(lt, origins, clearance=True)
                self._throughs[slot] = (_light_key(lt), t, clear)
            else:
                t = traced(lt, origins)
            out.append(resample_separable(t, h, w))
        return out

    def _patched(self, i, lt, slot, q, traced):
        """T of layer i for one light patched from an earlier scene's (_Earlier: the scene
        before an edit) at the same light and level: traced again only where a ray can meet
        what the edit changed (core/layer_edits.py), the rest kept → (T (H, W), its
        clearance), or None where there is nothing to patch from or the change cannot be
        bounded. A kept pixel's clearance shrinks by how far the relief its rays read
        moved (rays_lifted); one no rule tells (a start moved, a slab moved) becomes 0."""
        e = self._earlier
        kept = None if e is None else e.throughs.get(slot)
        if kept is None or kept[0] != _light_key(lt):
            return None
        (before, clear), origins = kept[1:], self._origins[i, 1.0]
        points = [pt for n in {1, q["disc"], q["penumbra"]}
                  for pt in light_points(lt, self.canvas, n)]
        changed, clear = np.zeros(before.shape, bool), clear.copy()
        if e.ready[i] is not self.ready[i]:          # this layer's own surface moved
            was = e.origins.get(i)
            if was is None or was.shape != origins.shape:
                return None
            moved = changed_over(was[..., 2], origins[..., 2])
            if moved is not None:
                changed[moved[0]:moved[1], moved[2]:moved[3]] = True
            # (a start moved a little: its ray moves as little, and can change where it grazes)
            started = was[..., 2] != origins[..., 2]
            changed |= started & near_edges(before, 1)
            clear[started] = 0.0
        for k in self.order[self.order.index(i) + 1:]:
            if k not in self._changes:        # (every layer behind k compares the same two)
                self._changes[k] = solid_change(e.occluders.get(k), self.occluder(k))
            change = self._changes[k]
            if change is ALL:
                return None
            if change is None:
                continue
            may = rays_changed(origins, points, change, before, self.places[i].px)
            if change.lifts is None:
                clear[:] = 0.0
            else:
                lifted_may, lifted = rays_lifted(origins, points, change, before, clear,
                                                 self.places[i].px)
                may &= lifted_may
                with np.errstate(invalid="ignore"):      # (inf − inf: not known, NaN)
                    clear -= lifted
            changed |= may
        if not changed.any():
            return before, clear
        # traced where rays changed and at their neighbours (whose antialiasing compares T
        # with theirs)
        changed = widened(changed)
        t = before.copy()
        new_t, new_clear = traced(lt, origins, changed, clearance=True)
        t[changed], clear[changed] = new_t[changed], new_clear[changed]
        return t, clear

    def _own_term(self, i, seen, p):
        """Layer i's own cos-θ term t_own (§6) of the light it sees (`seen`: bake's): an
        earlier scene's where the layer is the same, patched from it where an edit changed
        its shape (pipeline.shadow_term_edited), else baked."""
        ready, slot = self.ready[i], (i, seen[0].name) + seen[1:]
        light_key, e = _light_key(seen[0]), self._earlier
        kept = None if e is None else e.owns.get(slot)
        t = None
        if kept is not None and kept[0] == light_key:
            was = e.ready[i]
            if was is ready:
                t = kept[1]
            elif _same_painting(e.layers[i], self.layers[i]) and was.size == ready.size \
                    and (was.z_px is None) == (ready.z_px is None):
                t = shadow_term_edited(
                    ready.n, ready.z_px, ready.slopes, seen[0], p, kept[1],
                    changed_box(was.n, ready.n),
                    None if ready.z_px is None else changed_box(was.z_px, ready.z_px))
        if t is None:
            t = shadow_term(ready.n, ready.z_px, ready.slopes, seen[0], p, own_size=seen[3])
        self._owns[slot] = (light_key, t)
        return t


def _side_by_side(fn, items, threads):
    """fn of each of `items`, in `threads` daemon threads (1: here) → their results in the
    items' order, as each is ready (one's exception raised there). Daemon threads, as a UI's
    worker bake runs in: a Blender that quits mid-bake does not wait for it."""
    if threads <= 1:
        yield from map(fn, items)
        return
    items, claimed = list(items), threading.Lock()
    results, ready, queue = [None] * len(items), [threading.Event() for _ in items], \
        iter(range(len(items)))

    def work():
        while True:
            with claimed:
                j = next(queue, None)
            if j is None:
                return
            try:
                results[j] = (True, fn(items[j]))
            except BaseException as exc:        # (raised in the caller's thread)
                results[j] = (False, exc)
            ready[j].set()
    for _ in range(threads):
        threading.Thread(target=work, daemon=True).start()
    for j in range(len(items)):
        ready[j].wait()
        ok, value = results[j]
        if not ok:
            raise value
        yield value


def _edited_from(before, layers, i):
    """The Prepared of layer i in the scene `before` an edit, where it is the same painting
    (prepare decodes its shape again where it changed), else None."""
    if before is None or len(before.layers) != len(layers) or \
            not _same_painting(before.layers[i], layers[i]):
        return None
    return before.ready[i]


def _same_painting(a, b):
    """Whether Layers a and b are one painting with the same parameters (its images may
    differ: an edit)."""
    return a.name == b.name and repr(a.p) == repr(b.p)


def _light_key(light):
    """What a light's bakes depend on (a Light compares by value but is no dict key)."""
    return light.kind, light.vector, light.size


@dataclass
class _Earlier:
    """What an edited copy of a scene takes from the scene before the edit (Scene's
    `before`): its layers, prepared inputs, occluders, full-size origins and the terms
    it baked — not the scene itself, nor what it kept of its own earlier one."""
    layers: list
    ready: dict
    occluders: dict
    origins: dict
    throughs: dict
    owns: dict

    @classmethod
    def of(cls, before, scene):
        """The earlier scene's part, or None where it is none or another scene (other
        layers, canvas or places)."""
        if before is None or before.canvas != scene.canvas or before.places != scene.places \
                or [la.name for la in before.layers] != [la.name for la in scene.layers]:
            return None
        # (list(…) copies at once: a worker may still be baking the earlier scene)
        return cls(before.layers, before.ready,
                   {k: o for (k, s), o in list(before._occluders.items()) if s == 1.0},
                   {i: o for (i, s), o in list(before._origins.items()) if s == 1.0},
                   dict(list(before._throughs.items())), dict(list(before._owns.items())))


def render_scene(layers, lights, canvas=None, dtype=np.float32, progress=None):
    """Render a scene of layers (§15) → SceneResult.

    layers: [Layer], back to front by depth (equal depths keep their order); lights: the
    scene's [Light] (positions in image widths from the canvas's centre); canvas: (H, W) in
    pixels (default: the back layer's shape image's size). Each layer is rendered by
    pipeline.render in its own pixels with its lights' terms times T (Scene.through; a layer
    whose shadows are off takes none, as its material and page show none), then
    the layers are placed on the canvas and composited back to front by their alpha
    (orthographic). progress: optional callable(fraction done), once per layer. One layer at
    offset 0 and scale 1 on its own canvas renders exactly as pipeline.render.
    """
    scene = Scene(layers, canvas, dtype)
    results, terms, warnings = [None] * len(layers), [None] * len(layers), []
    for position, i in enumerate(scene.order):
        layer = layers[i]
        through = scene.through(i, lights) if layer.p.shadows.enabled else None
        results[i] = render(layer.images, scene.own_lights(i, lights), layer.p, dtype,
                            prepared=scene.ready[i], through=through)
        terms[i] = results[i].passes.get("t", [])
        warnings += [f"layer {layer.name or i}: {w}" for w in results[i].warnings]
        if progress is not None:
            progress((position + 1) / len(scene.order))
    rgba = np.zeros(scene.canvas + (4,), dtype)
    for i in scene.order:                             # back to front, each over the rest
        top = _on_canvas(results[i].rgba, scene.places[i], scene.canvas)
        rgba = top + rgba * (1 - top[..., 3:4])
    return SceneResult(rgba, results, terms, warnings)


def bake_scene(layers, light, canvas=None, progress=None):
    """The cos-θ term t = t_own·T of one light on every layer (§15) → [(H_i, W_i)], one per
    layer in the order given, each the size of that layer's shape image; each layer's own
    term at its shadows' quality level (§13), shadows on whatever its recipe says."""
    layers = [replace(layer, p=_with_shadows(layer.p)) for layer in layers]
    return Scene(layers, canvas).bake(light, progress=progress)


def scene_notes(layers, canvas=None):
    """What a scene's layers make the core guess (§15), one line each: a layer resampled to
    its place on the canvas, a layer without alpha that hides every layer behind it, layers
    at one depth (kept in their order), and each layer's own input notes."""
    notes, canvas = [], canvas_size(layers, canvas)
    order = sorted(range(len(layers)), key=lambda i: float(layers[i].depth))
    for position, i in enumerate(order):
        layer = layers[i]
        name = layer.name or f"layer {i}"
        notes += about(name, input_notes(layer.images, layer.p))
        size = layer.images["shape"].pixels.shape[:2]
        place = placement(layer, size, canvas)
        if abs(place.px - 1.0) > 1e-9:
            notes.append(f"{name}: its {size[1]}×{size[0]} pixels are drawn {place.px:.3g}× "
                         f"on the {canvas[1]}×{canvas[0]} canvas (resampled)")
        if position and _silhouette_of(layer) is None:
            notes.append(f"{name} has no alpha: it covers every layer behind it, and shadows "
                         f"them wherever the light comes through it")
        if position + 1 < len(order) and layers[order[position + 1]].depth == layer.depth:
            notes.append(f"{name} and {layers[order[position + 1]].name or 'the next layer'} "
                         f"are at the same depth: the first listed is behind")
    return notes


def _silhouette_of(layer):
    return silhouette_channel(layer.p.silhouette.source, *image_channels(layer.images)) or None


def _with_shadows(p):
    q = copy.deepcopy(p)
    q.shadows.enabled = True
    return q


def _on_canvas(rgba, place, canvas):
    """A layer's premultiplied RGBA placed on the canvas: sampled bilinearly at each canvas
    pixel's centre, transparent outside the layer."""
    h, w = rgba.shape[:2]
    if place.identity and (h, w) == tuple(canvas):
        return rgba
    x, y = place.to_layer(*pixel_centres(*canvas, np.float64))
    inside = (x >= 0) & (x <= w) & (y >= 0) & (y <= h)
    return sample_bilinear(rgba, x, y) * inside[..., None].astype(rgba.dtype)
