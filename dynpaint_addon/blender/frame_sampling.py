"""Frame changes that only read where the lights are.

The web export steps through the scene's frame range to record the lights' animation; the
shadows frame_change_post would bake for each of those frames are thrown away when the frame is
put back (the portrait with a point light: 18 s of bakes for 120 frames in background Blender,
against 0.05 s to read the lights). Inside `reading_lights()` the handler bakes nothing.
"""
import contextlib

_readers = 0


@contextlib.contextmanager
def reading_lights():
    """Frame changes in this block only read the lights: no shadow bakes, live or final."""
    global _readers
    _readers += 1
    try:
        yield
    finally:
        _readers -= 1


def only_reading_lights():
    """True inside `reading_lights()`."""
    return _readers > 0
