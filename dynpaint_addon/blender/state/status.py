"""What is wrong with a painting, said once: errors kept for the panel, health checks.

Handlers, timers and bakes never raise into Blender: they report here (printed, and the newest
shown in the painting's panel); `problems` lists what keeps a painting from rendering as set
up (deleted plane or images, image files gone from disk).
"""
from ...inputs.imageio import missing_file, missing_file_message
from .settings import channel_images

LAST_ERRORS = []      # (material name, message), newest last: the panel shows them


def report(mat, exc):
    """Print a painting's problem and keep it for the panel (the newest 20), once until the
    painting is up to date again (clear_errors)."""
    name = mat if isinstance(mat, str) else mat.name
    if (name, str(exc)) in LAST_ERRORS:     # said already (each handler meets it again)
        return
    print(f"Dynamic Painting: {name}: {exc}")
    LAST_ERRORS.append((name, str(exc)))
    del LAST_ERRORS[:-20]


def clear_errors(mat):
    """The painting is up to date again: the panel stops showing its old errors."""
    LAST_ERRORS[:] = [e for e in LAST_ERRORS if e[0] != mat.name]


def errors_of(mat):
    return [message for name, message in LAST_ERRORS if name == mat.name]


def problems(mat):
    """What keeps the painting from rendering as set up, one line each (the panel shows them,
    renders report them): deleted plane or images, image files gone from disk."""
    s = mat.dynamic_painting
    found = []
    if s.plane is None:
        found.append("its plane was deleted: add the painting again (Add › Dynamic Painting)")
    if s.image_shape is None:
        found.append("it has no shape image (deleted?): open one under Images")
    if s.image_dark is None and s.image_bright is None:
        found.append("it has no dark or bright image (deleted?): open one under Images")
    for channel, img in channel_images(s).items():
        if path := missing_file(img):
            found.append(missing_file_message(img.name, path))
    return found
