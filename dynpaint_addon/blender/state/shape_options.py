"""Make Shape's options (shapes.methods.OPTIONS) as Blender properties: one definition for the
Make Shape operator's dialog and a painted shape's settings (Paint Shape, shapes/painted.py)."""
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty


def option_property(option, update=None):
    """One row of shapes.methods.OPTIONS as a property; `update` is called when it changes."""
    kw = {"name": option.ui_label, "description": option.help}
    if update is not None:
        kw["update"] = update
    if option.kind is bool:
        return BoolProperty(default=option.default, **kw)
    if option.kind is float:
        return FloatProperty(default=option.default, min=option.min, max=option.max,
                             precision=option.precision, **kw)
    if isinstance(option.kind, tuple):
        return EnumProperty(items=[(c, c.replace("_", " ").title(), option.choice_help.get(c, ""))
                                   for c in option.kind], default=option.default, **kw)
    return StringProperty(subtype="FILE_PATH", **kw)
