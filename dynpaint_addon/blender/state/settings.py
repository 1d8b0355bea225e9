"""A painting's settings (Material.dynamic_painting) read and written as params namespaces.

The properties themselves are defined in properties.py (generated from params.py); the
functions here only read and write them, so every layer of the glue can use them.
"""
from ... import params


def _read(group, param):
    """One property as its parameter holds it ('auto' where an auto toggle is on)."""
    value = getattr(group, param.key)
    if param.kind in ("auto_float", "auto_int") and getattr(group, param.key + "_auto"):
        return "auto"
    if param.kind == "vec2":
        return tuple(float(f"{c:.7g}") for c in value)
    if isinstance(value, float):
        return float(f"{value:.7g}")       # Blender stores float32: 0.01 reads 0.0099999998
    return value


def _write(group, param, value):
    if param.kind in ("auto_float", "auto_int"):
        setattr(group, param.key + "_auto", value == "auto")
        if value == "auto":
            return
    setattr(group, param.key, value)


def settings_to_params(settings):
    """The settings as a params namespace (params.defaults() layout), for the core."""
    p = params.defaults()
    for param in params.PARAMS:
        setattr(getattr(p, param.section), param.key,
                _read(getattr(settings, param.section), param))
    return p


def params_to_settings(p, settings, sections=params.SECTIONS):
    """Write a params namespace (those of its sections) into the settings (recipe import)."""
    for param in (prm for prm in params.PARAMS if prm.section in sections):
        _write(getattr(settings, param.section), param, getattr(getattr(p, param.section),
                                                               param.key))


def channel_images(settings):
    """{channel: bpy Image} of the images assigned to the painting."""
    return {c: getattr(settings, f"image_{c}") for c in params.CHANNELS
            if getattr(settings, f"image_{c}") is not None}


def frames_table(settings):
    """The painting's frame mappings as a recipe's [frames] holds them (§16): {"": the
    painting's keys that differ from the defaults, channel: all of a slot's own}."""
    defaults = params.frame_defaults()
    own = {p.key: _read(settings.frames, p) for p in params.FRAME_PARAMS}
    table = {"": {k: v for k, v in own.items() if v != defaults[k]}}
    for c in params.CHANNELS:
        if getattr(settings, f"frames_{c}_own"):
            group = getattr(settings, f"frames_{c}")
            table[c] = {p.key: _read(group, p) for p in params.FRAME_PARAMS}
    return {k: v for k, v in table.items() if v}


def frames_to_settings(frames, settings):
    """Write a recipe's [frames] tables into the settings: the painting's mapping, and each
    slot that has a table of its own (its other keys the painting's)."""
    painting = dict(params.frame_defaults(), **frames.get("", {}))
    for param in params.FRAME_PARAMS:
        _write(settings.frames, param, painting[param.key])
    for c in params.CHANNELS:
        setattr(settings, f"frames_{c}_own", False)
        if c in frames:
            set_own_frames(settings, c, dict(painting, **frames[c]))


def set_own_frames(settings, channel, values):
    """Give one slot a frame mapping of its own ({key: value} of every [frames] key)."""
    setattr(settings, f"frames_{channel}_own", True)
    for param in params.FRAME_PARAMS:
        _write(getattr(settings, f"frames_{channel}"), param, values[param.key])
