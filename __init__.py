"""Dynamic Painting, the Blender extension (repository root = extension root).

The add-on's properties, operators, panels and handlers live in dynpaint_addon/blender/, next
to the numpy core they shade with; this file only hands Blender's register/unregister to them.
"""
from .dynpaint_addon import blender as _glue


def register():
    _glue.register()


def unregister():
    _glue.unregister()
