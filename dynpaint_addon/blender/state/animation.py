"""Animation data as Blender 5.0 keeps it: an ID's action holds its F-curves in the
channelbag of the ID's own slot (layered actions, blender-notes.md)."""
from bpy_extras import anim_utils


def fcurves(idblock):
    """The F-curves that animate `idblock` (an object, a material, …): its action's
    channelbag for its slot (empty where it has no action)."""
    ad = getattr(idblock, "animation_data", None)
    if ad is None or ad.action is None:
        return []
    bag = anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)
    return bag.fcurves if bag is not None else []
