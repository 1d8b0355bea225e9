"""Dynamic Painting, the Blender extension (repository root = extension root).

The add-on's properties, operators, panels and handlers live in dynpaint_addon/blender/, next
to the numpy core they shade with; this file only hands Blender's register/unregister to them.
They import bpy, so they are imported when Blender registers the add-on, not when this
package is imported (test runners import the repository root as a package too).
"""


def register():
    from .dynpaint_addon import blender
    blender.register()


def unregister():
    from .dynpaint_addon import blender
    blender.unregister()
