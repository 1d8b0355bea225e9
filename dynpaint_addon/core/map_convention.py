"""Which way a normal map's green channel points (§2 "flip green"), read from the map itself.

Tools and engines disagree: OpenGL-style maps (Blender, Godot's docs, Unity, Sprite Lamp,
Laigter, SpriteIlluminator's default) store +y (up the image) in green, DirectX-style maps
store −y, and nothing in the file says which. Read the wrong way, a map is lit from below and
its slopes stop fitting any height field: flipping one component of the gradient of a height
field H turns (∂H/∂x, ∂H/∂y) into a field whose circulation is −2∂²H/∂x∂y, large wherever the
figure curves. So of the two readings the right one has the smaller circulation
(core.shape.circulation): measured on artists' maps (docs/artists-files.md), the wrong
reading's is 1.6× (a sprite's sharp-edged map) to 25× the right one's, PNG or JPEG; on every
map tried the right reading's was the lower. A map whose readings are within CLEAR_WIN of each
other (a texture of fine grain: 260 and 285) keeps the reading it was given.

Flipping red instead of green reverses the figure (a bump becomes a dent) as well, which a
circulation cannot tell from the right reading: that is left to the artist (no tool we know
writes it).

    >>> import numpy as np
    >>> y, x = np.mgrid[0:64, 0:64] / 64.0 - 0.5
    >>> dome = np.dstack([x, y, np.sqrt(np.clip(0.4 - x * x - y * y, 0.01, None))])
    >>> dome /= np.linalg.norm(dome, axis=-1, keepdims=True)
    >>> green_up, green_down = (dome + 1) / 2, (dome * [1, -1, 1] + 1) / 2
    >>> green_reading(green_up).flip, green_reading(green_down).flip
    (False, True)
"""
from dataclasses import dataclass

import numpy as np

from .shape import Z_MIN_DEFAULT, circulation, decode_normal_map, slopes_from_normals

CLEAR_WIN = 1.25     # the other reading is taken when its circulation is this many times smaller


@dataclass(frozen=True)
class GreenReading:
    """What the map's two readings measure: `curl` {flip_green: circulation per image width}
    and the reading chosen (`flip`), from the one it was `given`."""
    curl: dict
    given: bool

    @property
    def flip(self):
        return min(self.curl, key=self.curl.get) if self.clear else self.given

    @property
    def clear(self):
        """Whether one reading fits clearly better (CLEAR_WIN) than the other."""
        low, high = sorted(self.curl.values())
        return low * CLEAR_WIN < high

    def describe(self, name):
        """One line: the reading chosen and why, in the artist's words."""
        way = "green down (DirectX style)" if self.flip else "green up (OpenGL style)"
        numbers = (f"circulation {self.curl[self.flip]:.2f} per image width, "
                   f"{self.curl[not self.flip]:.2f} the other way")
        if not self.clear:
            return f"{name}: read {way}, as given: it fits about as well either way ({numbers})"
        return f"{name}: read {way}: its slopes fit a height field that way ({numbers})"


def green_of_frames(readings):
    """One reading of a sprite's frames (an atlas's, cut back to their source: a sheet's
    frames packed turned are no height field as they lie): their circulations summed."""
    return GreenReading({flip: sum(r.curl[flip] for r in readings) for flip in (False, True)},
                        readings[0].given)


def green_reading(rgb, alpha=None, encoding="auto", strength=1.0, given=False):
    """Measure both readings of a normal map's pixels (H, W, ≥3, 0..1) → GreenReading.
    alpha: the map's (only the figure's pixels are measured)."""
    rgb, alpha = _at_most(np.asarray(rgb, np.float32)[..., :3], alpha)
    mask = None if alpha is None else alpha > 0.5
    curl = {}
    for flip in (False, True):
        n = decode_normal_map(rgb, flip, Z_MIN_DEFAULT, encoding, strength, alpha)
        curl[flip] = circulation(slopes_from_normals(n), mask)
    return GreenReading(curl, bool(given))


MEASURED_PX = 1024   # a larger map is measured on its box-averaged copy (each reading alike)


def _at_most(rgb, alpha):
    """A map's RGB and alpha box-averaged to at most MEASURED_PX on its longer side: every
    command reads a painting's notes, and a 4K map's two readings would cost seconds."""
    k = -(-max(rgb.shape[:2]) // MEASURED_PX)
    if k <= 1:
        return rgb, None if alpha is None else np.asarray(alpha, np.float32)
    h, w = rgb.shape[0] // k * k, rgb.shape[1] // k * k

    def box(a):
        return a[:h, :w].reshape(h // k, k, w // k, k, *a.shape[2:]).mean((1, 3))
    return box(rgb), None if alpha is None else box(np.asarray(alpha, np.float32))
