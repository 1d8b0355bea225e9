"""A lit copy framed anew in place (issue 61): a stroke past its drawing's bounds changes
every layer's framing — the images' size, each plane's size, place and depth (§15: the
layers lie a Spacing apart in widths of the drawing) — but not its layers, their kinds or
frames, so the objects, materials, node trees' images and lights stay; made anew instead,
the lit copy held Blender's main thread 0.7 s at 1024².

The work comes in slices of one layer (Reframe.steps), each well under the 100 ms a UI may
be held at 1024²: a layer's images resized and written, its plane placed and shaped, its
shadows kept where they were (core/sampling.laid_into) — then its derived images made again
and its node tree given the new size (sync.update, no rebuild; the depsgraph update between
may do it first). Meanwhile the group's bakes wait (bake/layers.hold_group); once every
layer is framed the lit copy's parent moves to the drawing's new middle.
"""
from mathutils import Matrix

from ....core.sampling import laid_into
from ....inputs.imageio import image_data_from_blender
from ...material.sync import update
from ...state.edits import note_edited, note_resized
from ...state.images import forget_enlarged, grey_image, refill_packed_image, resized_image
from ..layered_build import layer_place
from ..painting_scene import reshape_plane
from .lit_copy import drawing_place


class Reframe:
    """The slices of one lit copy framed anew: `layers` [(layer stem, material, depth,
    {channel: ImageData})] back to front, the drawing's `bounds` now and `old` ones, rgba:
    {(layer stem, channel): its RGBA} made in a worker already."""

    def __init__(self, parent, obj, layers, bounds, old, rgba):
        self.parent, self.obj, self.layers = parent, obj, layers
        self.bounds, self.old, self.rgba = tuple(bounds), tuple(old), rgba or {}
        self.size = next(iter(layers[0][3].values())).pixels.shape[1::-1]   # (w, h)

    @classmethod
    def of(cls, parent, obj, mats, made, bounds, old, rgba=None):
        """The Reframe of made paintings ([(stem, depth, {channel: ImageData}, …)] of every
        layer: lit_copy.made_paintings') into the lit copy's materials ({stem: material}),
        or None where they cannot be written in place (a layer missing or added, an image
        not of the material's bit depth, images of several sizes)."""
        if {name for name, *_ in made} != set(mats) or any(m[2] is None for m in made):
            return None
        layers = [(name, mats[name], depth, imgs) for name, depth, imgs, *_ in made]
        images = [(getattr(mat.dynamic_painting, f"image_{c}"), data)
                  for _, mat, _, imgs in layers for c, data in imgs.items()]
        if len({data.pixels.shape[:2] for _, data in images}) != 1 or any(
                img is None or img.is_float != (data.bits == 32) for img, data in images):
            return None
        return cls(parent, obj, layers, bounds, old, rgba)

    def steps(self, scene):
        """The slices, one per next(): each layer written (write_layer), then its derived
        images and tree made again (update, no bake); the last places the parent."""
        for layer in self.layers:
            self.write_layer(layer)
            yield
            update(layer[1], scene, bake="none")
            yield
        self.place_parent()

    def write_layer(self, layer):
        """A layer's images resized and written, its plane placed at its depth for the new
        bounds and shaped to their size, its shadows laid into the new framing."""
        stem, mat, depth, imgs = layer
        s, (w, h) = mat.dynamic_painting, self.size
        images = {c: getattr(s, f"image_{c}") for c in imgs}
        note_resized([img.name for img in images.values() if tuple(img.size) != (w, h)])
        for c, img in images.items():
            if not resized_image(img, w, h) or not refill_packed_image(
                    img, imgs[c], rgba=self.rgba.get((stem, c))):
                raise ValueError(f"{img.name}: could not be written at {w}×{h}")
        names = [img.name for img in images.values()]
        forget_enlarged(names)
        note_edited(names)
        self._place(s.plane, depth)
        reshape_plane(s.plane.data, w, h)
        for item in s.lights:          # (read back: a stroke's draft may have written it)
            if item.shadow is not None:
                grey = image_data_from_blender(item.shadow).pixels[..., 0]
                # (each shadow where it was till the group's draft comes, 0.3 s: not
                # stretched over the new framing; lit where it did not reach)
                grey_image(item.shadow.name, laid_into(grey, self.old, self.bounds))

    def place_parent(self):
        """The parent at the drawing's new middle, each plane kept where write_layer put it
        (world matrices: read at once, no depsgraph update between)."""
        planes = [(mat.dynamic_painting.plane, depth) for _, mat, depth, _ in self.layers]
        self.parent.matrix_world = drawing_place(self.obj, self.bounds)
        for plane, depth in planes:
            self._place(plane, depth)

    def _place(self, plane, depth):
        """A plane where a lit copy made for the new bounds puts it (light_drawing's
        layers: no offset, the drawing's width)."""
        location, scale = layer_place(depth, (0.0, 0.0), 1.0, self.bounds[1] - self.bounds[0])
        plane.matrix_world = drawing_place(self.obj, self.bounds) @ \
            Matrix.LocRotScale(location, None, scale)
