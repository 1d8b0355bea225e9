"""A painting's settings (Material.dynamic_painting) read and written as params namespaces.

The properties themselves are defined in properties.py (generated from params.py); the
functions here only read and write them, so every layer of the glue can use them.
"""
from .. import params


def settings_to_params(settings):
    """The settings as a params namespace (params.defaults() layout), for the core."""
    p = params.defaults()
    for param in params.PARAMS:
        group = getattr(settings, param.section)
        value = getattr(group, param.key)
        if param.kind == "auto_float" and getattr(group, param.key + "_auto"):
            value = "auto"
        elif param.kind == "vec2":
            value = tuple(float(f"{c:.7g}") for c in value)
        elif isinstance(value, float):
            value = float(f"{value:.7g}")   # Blender stores float32: 0.01 reads 0.0099999998
        setattr(getattr(p, param.section), param.key, value)
    return p


def params_to_settings(p, settings, sections=params.SECTIONS):
    """Write a params namespace (those of its sections) into the settings (recipe import)."""
    for param in (prm for prm in params.PARAMS if prm.section in sections):
        group = getattr(settings, param.section)
        value = getattr(getattr(p, param.section), param.key)
        if param.kind == "auto_float":
            setattr(group, param.key + "_auto", value == "auto")
            if value == "auto":
                continue
        setattr(group, param.key, value)


def channel_images(settings):
    """{channel: bpy Image} of the images assigned to the painting."""
    return {c: getattr(settings, f"image_{c}") for c in params.CHANNELS
            if getattr(settings, f"image_{c}") is not None}
