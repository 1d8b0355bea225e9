"""The live cos-θ bake (issue 4): current shadows while an artist drags a light.

When a linked light (or the plane) moves interactively, its painting bakes at a live level at
once, then at the painting's own quality once the light has been still for DEBOUNCE_S. The
live level is *preview* while its bakes keep within LIVE_BUDGET_MS (light change → updated
image: a frame of a 30 fps viewport for suns, 50 ms with a point light, issue 18), *draft*
where they do not (large paintings, slow machines), and back to preview when draft bakes are
well inside the budget. Bakes run in a worker thread on numpy arrays prepared on the main thread (the
worker never touches Blender data); a timer on the main thread writes finished images. A newer
request supersedes a bake in flight (its march stops at the next step: BakeCancelled) instead
of queueing behind it, so the UI never waits and never shows a stale light.

Rendering (and background Blender) does not come here: frame_change_post bakes synchronously
at final quality, so each rendered frame has the bake of its own light positions.
"""
import copy
import queue
import threading
import time

import numpy as np

import bpy

from ...core.shadow import BakeCancelled
from ..state.settings import settings_to_params
from ..state.status import report
from .shadow_images import (bake_key, bake_light, bake_shape, edit_start, held, keep_bake,
                            keeps_bakes, kept_bake, light_bakes, released, write_shadow)

DEBOUNCE_S = 0.3
TIMER_S = 0.01          # polls a queue while a bake is due: cheap, and a small part of the budget
LIVE_BUDGET_MS = {"sun": 33.0, "point": 50.0}
LIVE_LEVELS = ("preview", "draft")       # finer first; each about half the time of the one before


def rendering():
    """Baking must be synchronous: a render is running, or Blender has no UI at all."""
    return bpy.app.background or bpy.app.is_job_running("RENDER")


class LiveBake:
    def __init__(self):
        self.generation = {}        # material name → newest request number
        self.still_since = {}       # material name → time of the newest preview request
        self.results = queue.Queue()
        self.threads = []
        self.latencies = []         # (quality, ms from request to updated image)
        self.superseded = 0
        self.wanted = {}            # material name → the final bake keys of the newest request
        self.levels = {}            # material name → its live level (LIVE_LEVELS)

    # -- main thread --------------------------------------------------------------------
    def ensure(self, mat, scene, depsgraph=None, p=None):
        """Request a bake unless the newest request was for these very light places and
        settings (it is in flight, or its final bake is due): asking again on every update
        would keep superseding it. p: the painting's parameters, when the caller has them."""
        p = p or settings_to_params(mat.dynamic_painting)
        keys = [key for item, _, key in light_bakes(mat, depsgraph, p) if item.shadow is not None]
        if self.wanted.get(mat.name) != keys:
            self.request(mat, scene, depsgraph, p=p)

    def request(self, mat, scene, depsgraph=None, quality=None, p=None):
        """Start a bake of `mat`'s lights where they are now, at `quality` (default: the
        painting's live level); supersedes one in flight."""
        quality = quality or self.levels.get(mat.name, LIVE_LEVELS[0])
        # a copy: a live bake writes its own quality into it (and the worker keeps it)
        p = copy.deepcopy(p) if p is not None else settings_to_params(mat.dynamic_painting)
        bakes = [b for b in light_bakes(mat, depsgraph, p) if b[0].shadow is not None]
        self.wanted[mat.name] = [key for _, _, key in bakes]
        if quality != "final":
            p.shadows.quality = quality       # its key says so: the final bake is still due
            bakes = [b for b in light_bakes(mat, depsgraph, p) if b[0].shadow is not None]
        items = [item for item, _, _ in bakes]
        lights = [light for _, light, _ in bakes]
        keys = [key for _, _, key in bakes]
        name = mat.name
        gen = self.generation.get(name, 0) + 1
        self.generation[name] = gen
        if quality != "final":
            self.still_since[name] = time.perf_counter()
        kept = self._kept(mat, lights, p, quality, self.wanted[name])
        if keys and kept is not None:           # a moving shape's loop came round
            for item, (t, key) in zip(items, kept):
                write_shadow(mat, item, t, key)
            return gen
        shape = held(bake_shape(mat, p))        # (released by the worker: _run)
        starts = [edit_start(mat, shape, light, p) for light in lights]
        budget = max((LIVE_BUDGET_MS[light.kind] for light in lights), default=0.0)
        job = (name, gen, quality, [i.object.name for i in items], lights, keys, shape,
               starts, p, budget, time.perf_counter())
        thread = threading.Thread(target=self._run, args=job, daemon=True)
        self.threads = [t for t in self.threads if t.is_alive()] + [thread]
        thread.start()
        if not bpy.app.background and not bpy.app.timers.is_registered(_tick):
            bpy.app.timers.register(_tick, first_interval=TIMER_S)
        return gen

    @staticmethod
    def _kept(mat, lights, p, quality, final_keys):
        """Per light (`lights`: where they are now), (t, key) of the finest bake kept for it
        (shadow_images.kept_bake): its final, else a live level no coarser than `quality` —
        the level may have changed since (_adapt) and a kept final is better than any live
        one. None unless every light has one."""
        if not keeps_bakes(mat):
            return None
        s, at = mat.dynamic_painting, copy.deepcopy(p)
        candidates = [final_keys]
        for level in LIVE_LEVELS[:LIVE_LEVELS.index(quality) + 1] if quality in LIVE_LEVELS \
                else ():
            at.shadows.quality = level
            candidates.append([bake_key(light, at, s) for light in lights])
        kept = []
        for keys in zip(*candidates):
            hit = next(((t, k) for t, k in ((kept_bake(mat, k), k) for k in keys)
                        if t is not None), None)
            if hit is None:
                return None
            kept.append(hit)
        return kept

    def apply(self):
        """Write finished bakes into their images (main thread) → number applied."""
        applied = 0
        while True:
            try:
                name, gen, quality, names, keys, results, budget, t_request, kept = \
                    self.results.get_nowait()
            except queue.Empty:
                return applied
            mat = bpy.data.materials.get(name)
            if mat is None or gen != self.generation.get(name):
                continue                                 # superseded while it finished
            for item in mat.dynamic_painting.lights:
                if item.object is not None and item.object.name in names:
                    k = names.index(item.object.name)
                    write_shadow(mat, item, results[k], keys[k])
            shape, lights, p = kept
            for light, t in zip(lights, results):   # the next edit starts from these
                keep_bake(mat, shape, light, p, t)
            ms = (time.perf_counter() - t_request) * 1000
            self.latencies.append((quality, ms))
            del self.latencies[:-50]
            if quality in LIVE_LEVELS:
                self._adapt(name, quality, ms, budget)
            applied += 1

    def _adapt(self, name, quality, ms, budget):
        """After a live bake: the next coarser level when this one missed the budget, the
        next finer one when this one took under a third of it (the finer takes ~2×)."""
        i = LIVE_LEVELS.index(quality)
        if ms > budget and i + 1 < len(LIVE_LEVELS):
            self.levels[name] = LIVE_LEVELS[i + 1]
        elif ms < budget / 3 and i > 0:
            self.levels[name] = LIVE_LEVELS[i - 1]

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
    def _run(self, name, gen, quality, names, lights, keys, shape, starts, p, budget,
             t_request):
        cancel = lambda: self.generation.get(name) != gen   # noqa: E731
        try:
            # an edit's: only the rays that read what the strokes changed since (bake_light)
            results = [bake_light(shape, light, p, cancel=cancel, start=start)
                       for light, start in zip(lights, starts)]
        except BakeCancelled:
            self.superseded += 1
            return
        except Exception as exc:        # keep the last good image; the panel says why
            report(name, f"live bake failed, the last good shadows are kept: {exc}")
            return
        finally:
            released(shape)
        self.results.put((name, gen, quality, names, keys, [np.asarray(r) for r in results],
                          budget, t_request, (shape, lights, p)))


LIVE = LiveBake()


def _tick():
    try:
        busy = LIVE.tick()
    except Exception as exc:            # a timer must never raise into Blender
        print(f"Dynamic Painting: live bake: {exc}")
        busy = False
    return TIMER_S if busy else None


def shutdown():
    """The add-on is being disabled: supersede bakes in flight, stop the timer."""
    for name in list(LIVE.generation):
        LIVE.generation[name] += 1
    LIVE.still_since.clear()
    if bpy.app.timers.is_registered(_tick):
        bpy.app.timers.unregister(_tick)
