"""Which channel (docs/pipeline.md §1) an image file is for, from its name (no bpy).

Add › Dynamic Painting › From Images assigns the files an artist picks by the words in their
names, checked in this order ("specular" before "light", …):

    >>> guess_channels(["face_normal.png", "face_dark.png", "face_lit.png", "notes.png"])
    ({'shape': 'face_normal.png', 'dark': 'face_dark.png', 'bright': 'face_lit.png'}, ['notes.png'])
"""
import os

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".bmp", ".tga", ".webp",
                    ".hdr")
# File-name words → channel, checked in this order ("specular" before "light", …).
CHANNEL_WORDS = (
    ("specular_color", ("specular", "spec")),
    ("gloss", ("gloss", "rough")),
    ("environment", ("environment", "env", "reflect")),
    ("background", ("background", "backdrop", "bg")),
    ("transparency", ("transparency", "transp", "opacity")),
    ("shape", ("normal", "nrm", "height", "depth", "disp", "bump", "shape")),
    ("dark", ("dark", "shadow", "c0")),
    ("bright", ("bright", "lit", "light", "c1")),
)


def guess_channels(paths):
    """Assign image files to channels by their names → ({channel: path}, [unassigned])."""
    found, rest = {}, []
    for path in paths:
        stem = os.path.splitext(os.path.basename(path))[0].lower()
        channel = next((c for c, words in CHANNEL_WORDS if c not in found
                        and any(w in stem for w in words)), None)
        if channel is None:
            rest.append(path)
        else:
            found[channel] = path
    return found, rest
