"""What every operator shares: the poll mixin and one way to run work and report it.

Every operator is undoable and reports one clear line; a failure reports why and leaves the
scene as it was (CANCELLED).
"""
from ..bake.layers import LAYERED, group_materials



def active_painting(context):
    """The active object's Dynamic Painting material, or None; the parent of a scene of
    layers (§15) stands for its back layer (the panel, Bake Shadows, Export)."""
    obj = context.object
    if obj is not None and obj.get(LAYERED):
        mats = group_materials(obj)
        return mats[0] if mats else None
    mat = obj.active_material if obj is not None else None
    return mat if mat is not None and mat.dynamic_painting.is_painting else None


class PaintingOperator:
    """Poll mixin: the operator needs the active object to show a Dynamic Painting."""

    @classmethod
    def poll(cls, context):
        return active_painting(context) is not None


def _message(exc):
    if isinstance(exc, MemoryError):
        return "not enough memory for this painting: use smaller images"
    return str(exc)


def run_and_report(operator, context, work, failure="", catch=(Exception,), progress=False):
    """Run `work` and report what it says → FINISHED, or CANCELLED with one ERROR line.

    work() (or work(progress) with `progress`: a callable taking the fraction done, shown by
    the cursor) returns [(level, line)] to report, level 'INFO' or 'WARNING'. An exception of
    `catch` is reported as `failure` + its message.
    """
    wm = context.window_manager
    if progress:
        wm.progress_begin(0, 1000)
    try:
        lines = work(lambda f: wm.progress_update(int(1000 * f))) if progress else work()
    except catch as exc:
        operator.report({"ERROR"}, failure + _message(exc))
        return {"CANCELLED"}
    finally:
        if progress:
            wm.progress_end()
    for level, line in lines or ():
        operator.report({level}, line)
    return {"FINISHED"}
