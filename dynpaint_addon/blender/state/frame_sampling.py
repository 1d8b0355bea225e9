"""Frame changes that only read where the lights are.

The web export steps through the scene's frame range to record the lights' animation; the
shadows frame_change_post would bake for each of those frames are thrown away when the frame is
put back (the portrait with a point light keyframed over 250 frames: 34 s of bakes in
background Blender, against 0.3 s for the whole export; docs/web-numbers.md). Inside
`reading_lights()` the handlers bake nothing.
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
