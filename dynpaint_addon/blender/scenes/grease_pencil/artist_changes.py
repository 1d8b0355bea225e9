"""What an artist changed on a lit copy, kept when it is made anew (a layer added to the
drawing or removed, other frames: live._made_anew) — nothing of theirs lost: each layer's
painting settings but its shape (drawn again from the drawing), its material's animation
(keyframes on a layer's gloss) and its plane's visibility, keyed by the drawing's layer it
shows; and the objects the artist parented to the lit copy (a camera that follows it),
where they were in the world.
"""
from dataclasses import dataclass, field

from .... import params
from ...material.sync import batch, update
from ...state.settings import params_to_settings, settings_to_params
from .lit_copy import LAYER
from .reading import stem_layers

# the sections the lit copy draws again from the drawing: the artist's own are the others
DRAWN = ("shape",)
KEPT = tuple(s for s in params.SECTIONS if s not in DRAWN)


@dataclass
class ArtistChanges:
    """A lit copy's layers' settings, animation and visibility (by the layer each shows) and
    the objects parented to it that it did not make, with their world matrices."""
    settings: dict = field(default_factory=dict)     # layer → params namespace
    actions: dict = field(default_factory=dict)      # layer → its material's (action, slot)
    hidden: dict = field(default_factory=dict)       # layer → (hide_render, hide_viewport)
    children: list = field(default_factory=list)     # [(object, world matrix)]

    @classmethod
    def of(cls, parent):
        """What the artist may have changed on the lit copy `parent` (read before it goes)."""
        out = cls()
        for child in parent.children:
            name = _layer_of(child)
            if name is None:
                out.children.append((child, child.matrix_world.copy()))
                continue
            mat = child.active_material
            out.settings[name] = settings_to_params(mat.dynamic_painting)
            out.hidden[name] = (child.hide_render, child.hide_viewport)
            anim = mat.animation_data
            if anim is not None and anim.action is not None:
                out.actions[name] = (anim.action, anim.action_slot)
        return out

    def own(self, parent):
        """The lit copy's own objects (the layers' planes it made): those the artist did not
        parent to it."""
        theirs = {child for child, _ in self.children}
        return [child for child in parent.children if child not in theirs]

    def given_to(self, context, parent, bake="now"):
        """The changes kept given to the lit copy made anew, `parent`: a layer's settings
        where it shows the same layer (its shadows baked again where they differ: `bake` as
        material.sync.update's), its animation and visibility, and the artist's objects
        parented to it where they were."""
        for child in list(parent.children):
            name = _layer_of(child)
            if name is None:
                continue
            settings = child.active_material.dynamic_painting
            kept = self.settings.get(name)
            if kept is not None and _differ(settings_to_params(settings), kept):
                with batch():
                    params_to_settings(kept, settings, KEPT)
                update(child.active_material, context.scene, bake=bake)
            if name in self.actions:
                anim = child.active_material.animation_data_create()
                anim.action, anim.action_slot = self.actions[name]
            child.hide_render, child.hide_viewport = self.hidden.get(
                name, (child.hide_render, child.hide_viewport))
        for child, world in self.children:
            child.parent = parent
            child.matrix_world = world


def _layer_of(obj):
    """The drawing's layer a lit copy's plane shows (its material's LAYER, without its place
    in the stack: reading.stem_layers), else None."""
    mat = obj.active_material
    stem = None if mat is None else mat.get(LAYER)
    return None if stem is None else stem_layers(stem)


def _differ(a, b):
    """Whether two params namespaces differ in a section kept (KEPT)."""
    return any(vars(getattr(a, s)) != vars(getattr(b, s)) for s in KEPT)
