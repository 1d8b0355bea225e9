"""Dynamic Painting, the Blender extension (repository root = extension root).

The add-on's operators, panels and handlers live in dynpaint_addon/ next to the numpy core
they shade with; this file only hands Blender's register/unregister to them.
"""
from . import dynpaint_addon  # noqa: F401  (the package must import cleanly inside Blender)


def register():
    # The UI (Add › Dynamic Painting, panels, light drivers) arrives with the add-on issue;
    # until then enabling the extension loads the core and registers nothing.
    pass


def unregister():
    pass
