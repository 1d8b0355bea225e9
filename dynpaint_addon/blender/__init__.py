"""Blender glue: the only folder that imports bpy. `register()` is called by the extension's
root __init__; `headless.py` is the command line's way in.

Grouped by job; imports run one way, from what Blender calls down (tests/core/test_import_graph.py
states the order):

    properties, preferences, panels, handlers, headless    what Blender (or the command line) calls
      → operators/     one module per operator (a poll mixin in common.py)
        → scenes/      a painting's plane, material, lights, camera; layers; turntable; compositor
          → material/  keep a painting current (sync), its node tree and OSL script
            → bake/    the cos-θ shadow images: baked, live while a light moves, a layer group's
              → state/ a painting's settings, images, lights and frame, read once per update
                → nodes/  the graph built as node trees → nodegraph/ → core/
"""
import bpy

from ..inputs import memory
from . import handlers, operators, panels, preferences, properties
from .bake import live_bake

# What a process holds with Blender's module loaded, before its first image: the base of the
# memory estimates made in it (bpy 5.3.0 holds 140 MiB more than 5.0.1)
memory.hold_base(memory.resident_bytes())

_MODULES = (properties, preferences, operators, panels, handlers)


def register():
    for module in _MODULES:
        module.register()


def unregister():
    live_bake.shutdown()
    for module in reversed(_MODULES):
        module.unregister()


def register_once():
    """Register for command-line use (the extension may not be installed)."""
    if not hasattr(bpy.types.Material, "dynamic_painting"):
        register()
