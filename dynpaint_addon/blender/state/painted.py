"""A painting's shape painted in layers (issue 41, Paint Shape; shapes/painted.py).

Paint Shape gives the painting two images of its size, packed in the .blend: a figure mask
and a height layer. Its shape image becomes a made float height map (image widths) — over a
normal map, a made normal map, its slopes plus the painted relief's — remade
from the layers, the base (the shape image before Paint Shape, kept and never written) and
the relief's settings whenever one of them changes: compared by key, as derived images are
(sync.update calls update_painted_shape first, so a stroke's Image update, a setting and
undo all land here). The mask's relief is kept while only the height layer changes, so a
stroke on the height layer changes the made image in its box alone, and the decode and the
bake follow incrementally (bake/shadow_images.py). A stroke on the mask re-solves the part it
touched and snaps again around its box (core/snap.resnapped); beside the UI that relief is
made in a worker thread (LiveReliefs), the painting kept as it was until it is ready.
"""
import json
import queue
import threading
import time
from dataclasses import dataclass

import numpy as np

from ... import params
from ...core.input_rules import normal_map_normals
from ...core.shape import preblurred_height
from ...inputs.imageio import image_data_from_blender
from ...shapes.maker import at_size, encode_normals, linear_luminance
from ...core.snap import snapped
from ...shapes.painted import NEUTRAL, OPTIONS, painted_figure, painted_height, painted_normals
from ...shapes.relief import reads_painting, relief_of_figure
from .edits import key_name, note_edited
from .images import made_shape_image

LAYERS = ("mask", "height_layer")         # what the artist paints
READ = ("base", "structure")              # what else the made shape reads


def is_painted(settings):
    """Whether the painting shows a painted shape (its shape image is the made one)."""
    made = settings.painted.made
    return made is not None and settings.image_shape == made


def watched_images(settings):
    """{role: image} of a painted shape's images whose edits remake it."""
    if not is_painted(settings):
        return {}
    pt = settings.painted
    return {r: getattr(pt, r) for r in (*LAYERS, *READ) if getattr(pt, r) is not None}


def painted_layers(settings):
    """The layer images of a painted shape (whether or not it is shown now)."""
    pt = settings.painted
    return [img for img in (getattr(pt, r) for r in LAYERS) if img is not None]


def layer_image(name, size, value):
    """A new layer: a float image of `size` (W, H) filled with `value`, packed (undo removes
    it with the step that made it)."""
    w, h = size
    return made_shape_image(name, np.dstack([np.full((h, w), value, np.float32)] * 3
                                            + [np.ones((h, w), np.float32)]))


def new_layers(mat, size, figure=None):
    """The figure mask (from `figure`, an (H, W) 0..1 array, else empty) and the height
    layer (NEUTRAL) of a painting about to be painted → (mask, height layer)."""
    mask = layer_image(f"{mat.name} figure mask", size, 0.0)
    if figure is not None:
        w, h = size
        rgba = np.ones((h, w, 4), np.float32)
        rgba[..., :3] = np.asarray(figure, np.float32)[..., None]
        mask.pixels.foreach_set(rgba.ravel())
    return mask, layer_image(f"{mat.name} height layer", size, NEUTRAL)


def _grey(img, size):
    """An image's grey (linear luminance of colour images), at `size`."""
    return at_size(np.asarray(image_data_from_blender(img).grey(), np.float32), size)


def option_values(painted):
    return {o.name: getattr(painted, o.name) for o in OPTIONS}


def _relief_key(settings):
    pt = settings.painted
    values = option_values(pt)
    painting = settings.image_bright or settings.image_dark
    return repr((key_name(pt.mask) if pt.mask else None, sorted(values.items()),
                 key_name(painting) if reads_painting(values) and painting else None,
                 key_name(pt.structure) if values["structure_strength"] and pt.structure
                 else None))


def _base_key(settings):
    pt = settings.painted
    return repr((key_name(pt.base) if pt.base else None, round(pt.base_scale, 7),
                 round(pt.base_preblur, 4), pt.base_reads))


def painted_key(settings):
    """What the made shape depends on: the relief's inputs, the base, the height layer and
    its strength."""
    pt = settings.painted
    return repr((_relief_key(settings), _base_key(settings),
                 key_name(pt.height_layer) if pt.height_layer else None,
                 round(pt.strength, 7), tuple(pt.made.size)))


# material name → (key, array): the mask's relief and the base heights, kept while only the
# height layer changes; the painting's luminance, kept while it does not change
_RELIEF, _BASE, _LUMINANCE = {}, {}, {}
# material name → (key, figure, its snap): a stroke on the mask is snapped around its box alone
_SNAPPED = {}


def _kept(cache, mat, key, make):
    hit = cache.get(mat.name)
    if hit is None or hit[0] != key:
        hit = cache[mat.name] = (key, make())
    return hit[1]


@dataclass
class ReliefJob:
    """What a figure relief is made from, read from Blender on the main thread: the rest
    (relief_from) is numpy, for a worker thread too."""
    material: str
    key: str                    # _relief_key
    figure: np.ndarray          # (H, W) bool: the mask painted
    luminance: object           # (H, W) or None: the painting's, where the relief reads it
    tile: object                # the structure image's luminance, or None
    values: dict                # the relief's settings (OPTIONS)
    snap_key: tuple             # the painting and the reach its snap is kept for


def relief_job(mat, settings, size, key):
    """The ReliefJob of a painting's figure mask now, its `key` _relief_key's (None: it has
    no mask)."""
    pt = settings.painted
    if pt.mask is None:
        return None
    values = option_values(pt)
    painting = settings.image_bright or settings.image_dark
    lum = None
    if reads_painting(values) and painting is not None:
        lum = _kept(_LUMINANCE, mat, (key_name(painting), size), lambda: at_size(
            linear_luminance(image_data_from_blender(painting)), size))
    tile = linear_luminance(image_data_from_blender(pt.structure)) \
        if values["structure_strength"] and pt.structure is not None else None
    return ReliefJob(mat.name, key, painted_figure(_grey(pt.mask, size)), lum,
                     tile, values, (key_name(painting) if painting else None, size,
                                    values["snap"]))


def relief_from(job):
    """The job's relief (image widths): its figure snapped — around what changed since the
    last snap of the same painting and reach alone (core/snap.py: bit for bit the whole
    mask's) — inflated and with the effects (shapes/relief.py)."""
    figure = job.figure
    if job.luminance is not None:
        hit = _SNAPPED.get(job.material)
        figure = snapped(figure, job.luminance, job.values["snap"],
                         hit[1:] if hit is not None and hit[0] == job.snap_key else None)
        _SNAPPED[job.material] = (job.snap_key, job.figure, figure)
    return relief_of_figure(figure, job.luminance, job.tile, job.values)


def _relief(mat, settings, size, key):
    job = relief_job(mat, settings, size, key)
    return np.zeros(size[::-1]) if job is None else relief_from(job)


class LiveReliefs:
    """Figure reliefs made in a worker thread beside the UI (a stroke on a large figure's mask
    re-solves its part: ~0.5 s at 1024², docs/paint-latency.md): the painting shows its shape
    as it was meanwhile, and is brought up to date when the relief is ready (material/sync's
    timer). One job per painting at a time; a request while one runs waits for it, the newest
    replacing any older one waiting. Without a UI the relief is made at once (the headless
    contract)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.running, self.waiting = set(), {}
        self.newest = {}            # material name → the key of its newest job
        self.done = queue.Queue()

    def request(self, mat, settings, size, key):
        """Make the painting's relief as its settings and mask are now, `key` _relief_key's
        (unless that is the newest job already)."""
        with self.lock:
            if mat.name in self.running and self.newest.get(mat.name) == key:
                return
        job = relief_job(mat, settings, size, key)
        with self.lock:
            self.newest[mat.name] = key
            if mat.name in self.running:
                self.waiting[mat.name] = job
                return
            self.running.add(mat.name)
        threading.Thread(target=self._run, args=(job,), daemon=True).start()

    def _run(self, job):
        name = job.material
        while job is not None:
            try:
                self.done.put((name, job.key, relief_from(job), None))
            except Exception as exc:             # reported on the main thread
                self.done.put((name, job.key, None, exc))
            with self.lock:
                job = self.waiting.pop(name, None)
                if job is None:
                    self.running.discard(name)

    def busy(self):
        """Whether a relief is being made, or one made is not yet taken (finished)."""
        with self.lock:
            return bool(self.running) or not self.done.empty()

    def finished(self):
        """(main thread) The reliefs made since the last call, kept for their paintings →
        [(material name, the error where one failed, else None)]."""
        out = []
        while True:
            try:
                name, key, relief, exc = self.done.get_nowait()
            except queue.Empty:
                return out
            if relief is not None:
                _RELIEF[name] = (key, relief)
            out.append((name, exc))

    def wait(self, timeout=60.0):
        """(tests) Until no relief is being made."""
        end = time.monotonic() + timeout
        while self.running and time.monotonic() < end:
            time.sleep(0.01)


LIVE_RELIEFS = LiveReliefs()


def base_reads(p):
    """How a normal-map base is read (its §2 settings, as the painting had them), for
    `painted.base_reads`."""
    return json.dumps(vars(p.shape), sort_keys=True)


def _base(settings, size):
    """The base as the made shape reads it — a height map's heights in image widths (its own
    §2 pre-blur and scale), a normal map's unit normals (its own §2 settings) — and its
    alpha."""
    pt = settings.painted
    if pt.base is None:
        return None, None
    data = image_data_from_blender(pt.base)
    if pt.base_reads:
        p = params.defaults()
        vars(p.shape).update(json.loads(pt.base_reads))
        values = normal_map_normals(data, p)
    else:
        values = preblurred_height(data.grey().astype(np.float32),
                                   pt.base_preblur) * np.float32(pt.base_scale)
    alpha = data.alpha()
    return at_size(values, size), None if alpha is None else at_size(alpha, size)


def update_painted_shape(mat, live=False):
    """Remake the made shape image where what it depends on changed (painted_key) → whether
    it was remade. Its edit is noted (state/edits.py), so what is made from the shape image —
    its derived images, the decode, the bakes — follows. live (beside the UI): a relief to
    make again is made in LIVE_RELIEFS' worker, the made shape left as it is until then."""
    s = mat.dynamic_painting
    if not is_painted(s):
        return False
    pt = s.painted
    key = painted_key(s)
    if key == pt.key:
        return False
    size = tuple(pt.made.size)
    relief_key, hit = _relief_key(s), _RELIEF.get(mat.name)
    if live and (hit is None or hit[0] != relief_key) and pt.mask is not None:
        LIVE_RELIEFS.request(mat, s, size, relief_key)
        return False
    relief = _kept(_RELIEF, mat, relief_key, lambda: _relief(mat, s, size, relief_key))
    base, alpha = _kept(_BASE, mat, _base_key(s), lambda: _base(s, size))
    layer = _grey(pt.height_layer, size) if pt.height_layer is not None else None
    over_normals = base is not None and base.ndim == 3
    z = painted_height(None if over_normals else base, relief, layer, pt.strength)
    rgba = np.empty(z.shape + (4,), np.float32)
    rgba[..., :3] = encode_normals(painted_normals(base, z)) if over_normals else z[..., None]
    rgba[..., 3] = 1.0 if alpha is None else alpha
    pt.made.pixels.foreach_set(rgba.ravel())
    note_edited([pt.made.name])
    pt.key = key
    return True


def show_layer(mat, scene):
    """Texture Paint paints the layer the painting's `painted.layer` names (one image, not the
    material's slots: the material shows the lit painting meanwhile)."""
    pt = mat.dynamic_painting.painted
    img = getattr(pt, pt.layer)
    if img is not None:
        paint = scene.tool_settings.image_paint
        paint.mode = "IMAGE"
        paint.canvas = img


def forget_painted(mat=None):
    """Another file is open (every painting), or a painting's layers were replaced."""
    for cache in (_RELIEF, _BASE, _LUMINANCE, _SNAPPED):
        if mat is None:
            cache.clear()
        else:
            cache.pop(mat.name, None)
