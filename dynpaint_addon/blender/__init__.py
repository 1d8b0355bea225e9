"""Blender glue: properties, operators, panels and handlers; the only folder that imports bpy. `register()` is called by the extension's root __init__.

Imports run one way, from what Blender calls down to the helpers:

    properties, preferences, operators/, panels, handlers      (registered with Blender)
      → sync (keep a painting current), scene, turntable, compositor, headless
        → tree, osl, live_bake, shadow_images
          → painting_state (settings, images and lights read once per update)
            → images, lights, status, settings
              → nodes/ (the graph built as node trees) → nodegraph/ → core/
"""
import bpy

from . import handlers, live_bake, operators, panels, preferences, properties

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
