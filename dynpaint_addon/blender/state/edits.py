"""Input images edited in place: a painting follows its images' pixels (issue 41, step 1).

Blender says an image's pixels changed by a depsgraph update of the Image: after
`image.update_tag()` the Image is among `depsgraph.updates` (docs/blender-notes.md). Writing
`image.pixels` alone sends nothing, and `image.reload()` updates only the materials that use
the image. Each Image update seen bumps that image's version here; the keys of what is made
from an image — its derived images (nodegraph/derived_inputs), the decoded shape and the
cos-θ bakes (bake/shadow_images), a layered group's scene (bake/layers) — carry the version,
so `sync.update` redoes exactly what the edited image feeds, as a setting change does. An
image the add-on removes counts as edited too (state/images.remove_images): one made again
under its name is not the one a key remembers.
"""
_VERSIONS = {}       # image name → how many times its pixels were seen edited this session
_RESIZED = set()     # images the add-on resized: the next Image update of each is its own


def version(img):
    """How many edits of `img` have been seen (0: none since it was loaded)."""
    return _VERSIONS.get(img.name, 0)


def note_edited(names):
    """Images named `names` were edited (an Image update came): bump their versions."""
    for name in names:
        _VERSIONS[name] = _VERSIONS.get(name, 0) + 1


def note_resized(names):
    """Images named `names` were resized by the add-on, which writes them and notes that edit
    itself (a lit copy framed anew): the Image update Blender sends for a resize (writing
    pixels sends none) is that edit, not an artist's — were it counted again, every derived
    image of the group would be made twice (70–210 ms at 1024²)."""
    _RESIZED.update(names)


def forget_resized():
    """Another file is open, or undo: a resize whose Image update never came is not one of
    its images'."""
    _RESIZED.clear()


def artists_edits(names):
    """Of the images named `names` (an Image update came for each), those edited by someone
    else than the add-on (note_resized's come once)."""
    own = _RESIZED & set(names)
    _RESIZED.difference_update(own)
    return set(names) - own


def key_name(img):
    """An image in a key: its name, and how many times its pixels were edited (once they were)."""
    return img.name if not version(img) else (img.name, version(img))


def versions(images):
    """(channel, version) of the edited ones among {channel: bpy Image}: a key's part, empty
    (the key unchanged) until an image is edited."""
    return tuple((c, version(img)) for c, img in sorted(images.items()) if version(img))
