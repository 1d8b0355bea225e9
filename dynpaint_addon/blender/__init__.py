"""Blender glue: properties, operators, panels and handlers (everything that imports bpy
besides the node-graph builders). `register()` is called by the extension's root __init__."""
_registered = [False]


def _modules():
    from . import handlers, operators, panels, properties
    return (properties, operators, panels, handlers)


def register():
    for module in _modules():
        module.register()
    _registered[0] = True


def unregister():
    from . import live_bake
    live_bake.shutdown()
    for module in reversed(_modules()):
        module.unregister()
    _registered[0] = False


def register_once():
    """Register for command-line use (the extension may not be installed)."""
    import bpy
    if not hasattr(bpy.types.Material, "dynamic_painting"):
        register()
