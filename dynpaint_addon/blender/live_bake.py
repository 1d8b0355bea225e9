"""The live cos-θ bake (issue 4): current shadows while an artist drags a light.

When a linked light (or the plane) moves interactively, its painting bakes at *preview*
quality at once, then at the painting's own quality once the light has been still for
DEBOUNCE_S. Bakes run in a worker thread on numpy arrays prepared on the main thread (the
worker never touches Blender data); a timer on the main thread writes finished images. A newer
request supersedes a bake in flight (its march stops at the next step: BakeCancelled) instead
of queueing behind it, so the UI never waits and never shows a stale light.

Rendering (and background Blender) does not come here: frame_change_post bakes synchronously
at final quality, so each rendered frame has the bake of its own light positions.
"""
import queue
import threading
import time

import numpy as np

import bpy

from ..core.pipeline import shadow_term
from ..core.shadow import BakeCancelled
from . import material as M
from .properties import settings_to_params

DEBOUNCE_S = 0.3
TIMER_S = 0.05


class LiveBake:
    def __init__(self):
        self.generation = {}        # material name → newest request number
        self.still_since = {}       # material name → time of the newest preview request
        self.results = queue.Queue()
        self.threads = []
        self.latencies = []         # (quality, ms from request to updated image)
        self.superseded = 0

    # -- main thread --------------------------------------------------------------------
    def request(self, mat, scene, depsgraph=None, quality="preview"):
        """Start a bake of `mat`'s lights where they are now; supersedes one in flight."""
        s = mat.dynamic_painting
        p = settings_to_params(s)
        if quality != "final":
            p.shadows.quality = quality
        plane = s.plane
        plane_m = (plane.evaluated_get(depsgraph) if depsgraph else plane).matrix_world
        items = [i for i in s.lights if i.object is not None and i.shadow is not None]
        lights = [M.painting_frame_light(i.object, plane_m, depsgraph) for i in items]
        shape = M.bake_shape(mat, p)
        name = mat.name
        gen = self.generation.get(name, 0) + 1
        self.generation[name] = gen
        if quality != "final":
            self.still_since[name] = time.perf_counter()
        keys = [M.bake_key(light, p, s) for light in lights]
        job = (name, gen, quality, [i.object.name for i in items], lights, keys, shape, p,
               time.perf_counter())
        thread = threading.Thread(target=self._run, args=job, daemon=True)
        self.threads = [t for t in self.threads if t.is_alive()] + [thread]
        thread.start()
        if not bpy.app.background and not bpy.app.timers.is_registered(_tick):
            bpy.app.timers.register(_tick, first_interval=TIMER_S)
        return gen

    def apply(self):
        """Write finished bakes into their images (main thread) → number applied."""
        applied = 0
        while True:
            try:
                name, gen, quality, names, keys, results, t_request = self.results.get_nowait()
            except queue.Empty:
                return applied
            mat = bpy.data.materials.get(name)
            if mat is None or gen != self.generation.get(name):
                continue                                 # superseded while it finished
            for item in mat.dynamic_painting.lights:
                if item.object is not None and item.object.name in names:
                    k = names.index(item.object.name)
                    M.float_image(item.shadow.name, M.grey_rgba(results[k]))
                    item.bake_key = keys[k]
            self.latencies.append((quality, (time.perf_counter() - t_request) * 1000))
            del self.latencies[:-50]
            applied += 1

    def tick(self, now=None):
        """Apply results; start the final bake of paintings whose lights have been still."""
        self.apply()
        now = time.perf_counter() if now is None else now
        for name, since in list(self.still_since.items()):
            if now - since >= DEBOUNCE_S:
                del self.still_since[name]
                mat = bpy.data.materials.get(name)
                if mat is not None and mat.dynamic_painting.is_painting:
                    self.request(mat, bpy.context.scene, quality="final")
        return bool(self.still_since) or any(t.is_alive() for t in self.threads)

    def wait(self, timeout=60.0):
        """Join running bakes and apply them (background mode and tests)."""
        for t in list(self.threads):
            t.join(timeout)
        return self.apply()

    # -- worker thread ------------------------------------------------------------------
    def _run(self, name, gen, quality, names, lights, keys, shape, p, t_request):
        n, z, slopes = shape
        cancel = lambda: self.generation.get(name) != gen   # noqa: E731
        try:
            results = [shadow_term(n, z, slopes, light, p, cancel=cancel) for light in lights]
        except BakeCancelled:
            self.superseded += 1
            return
        except Exception as exc:        # keep the last good image; the panel says why
            from .handlers import LAST_ERRORS
            print(f"Dynamic Painting: {name}: live bake failed: {exc}")
            LAST_ERRORS.append((name, f"live bake failed, the last good shadows are kept: {exc}"))
            return
        self.results.put((name, gen, quality, names, keys, [np.asarray(r) for r in results],
                          t_request))


LIVE = LiveBake()


def _tick():
    try:
        busy = LIVE.tick()
    except Exception as exc:            # a timer must never raise into Blender
        print(f"Dynamic Painting: live bake: {exc}")
        busy = False
    return TIMER_S if busy else None


def lights_moved(mat, depsgraph=None):
    """True if a light or the plane moved since the images were baked."""
    s = mat.dynamic_painting
    plane = s.plane
    if plane is None:
        return False
    m = (plane.evaluated_get(depsgraph) if depsgraph else plane).matrix_world
    for item in s.lights:
        if item.object is None or item.shadow is None:
            continue
        light = M.painting_frame_light(item.object, m, depsgraph)
        if M.light_key(light) not in item.bake_key:
            return True
    return False


def shutdown():
    """The add-on is being disabled: supersede bakes in flight, stop the timer."""
    for name in list(LIVE.generation):
        LIVE.generation[name] += 1
    LIVE.still_since.clear()
    if bpy.app.timers.is_registered(_tick):
        bpy.app.timers.unregister(_tick)
