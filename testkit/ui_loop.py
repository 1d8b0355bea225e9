"""Blender's UI loop, run by hand in background mode (issue 61: "Blender's main thread never
held > 100 ms at a time while drawing"): background Blender fires no timer and evaluates
nothing by itself, so here every call the UI would make on its main thread — the depsgraph
update after an edit (the add-on's handlers run inside it), each of the add-on's timers when
it is due — is made in turn and timed, with rendering() reading "a UI is open" (the add-on's
live paths: drafts now, full redraws and final bakes in worker threads).
"""
import contextlib
import threading
import time

import bpy

from dynpaint_addon.blender import handlers
from dynpaint_addon.blender.bake import layers, live_bake
from dynpaint_addon.blender.material import sync
from dynpaint_addon.blender.operators import grease_pencil as from_grease_pencil
from dynpaint_addon.blender.scenes.grease_pencil import live

# the add-on's timers (bpy.app.timers) on the paths a drawing's edit takes
TIMERS = (handlers._redraw_pending, live.finish_drafts, live.finish_redraws,
          layers._final_bakes)


@contextlib.contextmanager
def with_a_ui():
    """rendering() false where the add-on asks it (handlers, live redraws, updates, From
    Grease Pencil), until the block ends."""
    modules = (handlers, live, sync, from_grease_pencil)
    saved = [module.rendering for module in modules]
    try:
        for module in modules:
            module.rendering = lambda: False
        yield
    finally:
        for module, rendering in zip(modules, saved):
            module.rendering = rendering


def waited_s():
    """Seconds this thread has waited for a processor while ready to run (Linux's schedstat:
    other processes' load, not this thread's work nor what it waits on), 0 where unknown."""
    try:
        with open(f"/proc/self/task/{threading.get_native_id()}/schedstat") as fh:
            return int(fh.read().split()[1]) / 1e9
    except (OSError, IndexError, ValueError):
        return 0.0


class MainThread:
    """What Blender's main thread was held for: held = [(what, seconds)] per call — its wall
    time less the time it waited for a processor (another process's turn: on the tests' busy
    2 cores a 15 ms call was once held 136 ms) but with what it waited on (the GIL, a lock)
    — and the processor time it spent in each, worked = [(what, seconds)]."""

    def __init__(self):
        self.held, self.worked = [], []

    def call(self, what, fn, *args):
        start, cpu, waited = time.perf_counter(), time.thread_time(), waited_s()
        try:
            return fn(*args)
        finally:
            self.held.append((what, time.perf_counter() - start - (waited_s() - waited)))
            self.worked.append((what, time.thread_time() - cpu))

    def edit(self, edit):
        """An edit (a stroke), then the depsgraph update the UI makes after it."""
        edit()
        self.call("depsgraph update", bpy.context.view_layer.update)

    def longest(self):
        return max(self.held, key=lambda h: h[1])

    def run(self, timeout_s=300.0):
        """The UI's loop until nothing is due: each registered timer called when its interval
        has passed (its return: the next interval, None: done), the live bake's results
        taken (live_bake._tick) while it has work, a depsgraph update after each call that
        did something — idle between, as the UI is, and while a worker makes the next
        stroke's draft ready (bake/layers.warm_drafts)."""
        due = {fn: time.perf_counter() for fn in TIMERS if bpy.app.timers.is_registered(fn)}
        end = time.perf_counter() + timeout_s
        while time.perf_counter() < end:
            for fn in TIMERS:                       # (one registered by another since)
                if fn not in due and bpy.app.timers.is_registered(fn):
                    due[fn] = time.perf_counter()
            busy = any(t.is_alive() for t in live_bake.LIVE.threads) or \
                not live_bake.LIVE.results.empty()
            if not due and not busy:
                if any(t.is_alive() for t in layers.WARMING.values()):
                    time.sleep(0.005)     # (a first draft made ready: the UI is idle)
                    continue
                return self
            if busy:
                self.call("live bake's results", live_bake.LIVE.tick)
            now = time.perf_counter()
            for fn, at in list(due.items()):
                if at > now:
                    continue
                interval = self.call(fn.__name__, fn)
                if interval is None:
                    del due[fn]
                    if bpy.app.timers.is_registered(fn):
                        bpy.app.timers.unregister(fn)
                else:
                    due[fn] = time.perf_counter() + interval
                self.call("depsgraph update", bpy.context.view_layer.update)
            time.sleep(0.005)
        raise TimeoutError(f"the UI loop still had work after {timeout_s} s: {due}")
