"""Lights in the painting frame (pipeline.md §0, §5).

A sun has a direction toward the light; a point light a position. Positions are in image
widths with the origin at the *centre* of the painting (x right, y up, z toward the viewer),
which is also the origin of the plane object in Blender.
"""
from dataclasses import dataclass, field

import numpy as np

LIGHT_KINDS = ("sun", "point")
FALLOFFS = ("none", "inverse_square")
# What lights a painting that names no light (a recipe without [[lights]], a layered file, an
# Add with no light in the scene): a white sun from the upper left, in front
DEFAULT_SUN_DIRECTION = (-0.45, 0.5, 0.74)


@dataclass
class Light:
    kind: str                      # 'sun' or 'point'
    vector: tuple                  # sun: direction toward the light; point: position (image widths)
    colour: tuple = (1.0, 1.0, 1.0)  # linear RGB
    strength: float = 1.0          # k_i of §5 (dimensionless)
    name: str = field(default="", compare=False)
    size: float = 0.0              # §15: a sun's angular diameter (radians), a point's radius
                                   # (image widths); 0 = the paper's lights

    def __post_init__(self):
        if self.kind not in LIGHT_KINDS:
            raise ValueError(f"light kind must be one of {', '.join(LIGHT_KINDS)}, got {self.kind!r}")
        v = np.asarray(self.vector, dtype=np.float64)
        if v.shape != (3,) or not np.all(np.isfinite(v)):
            raise ValueError(f"light {'direction' if self.kind == 'sun' else 'position'} must be "
                             f"three finite numbers, got {self.vector!r}")
        if self.kind == "sun" and np.linalg.norm(v) == 0:
            raise ValueError("sun direction must not be (0, 0, 0)")
        self.vector = tuple(float(c) for c in v)
        self.colour = tuple(float(c) for c in self.colour)
        self.strength = float(self.strength)
        if not (np.isfinite(self.size) and 0 <= self.size):
            raise ValueError(f"light size must be a finite number ≥ 0, got {self.size!r}")
        self.size = float(self.size)

    def position_px(self, height, width):
        """Point-light position in pixel units (origin at the bottom-left corner)."""
        x, y, z = self.vector
        return np.array([x * width + width / 2, y * width + height / 2, z * width])


def falloff(dist, mode, radius):
    """§5: how much of a point light's strength reaches a point `dist` image widths from it.

    none: 1 everywhere (the paper's lights). inverse_square: 1 / (1 + (dist/radius)²), which is
    1 at the light, ½ at `radius` and (radius/dist)² far away: an inverse-square tail that
    never becomes infinite near the light.

        >>> falloff(np.array([0.0, 0.5, 5.0]), "inverse_square", 0.5).round(4).tolist()
        [1.0, 0.5, 0.0099]
    """
    if mode == "none":
        return np.ones_like(dist)
    if mode == "inverse_square":
        q = dist / dist.dtype.type(radius)
        return 1 / (1 + q * q)
    raise ValueError(f"unknown falloff {mode!r} (expected one of {', '.join(FALLOFFS)})")


def light_vectors(light, x_px, y_px, z_px, dtype=np.float32, image_size=None):
    """Unit vectors toward the light for surface points P_S = (x, y, z) in pixels (§0).

    Returns (L, dist): L of shape (H, W, 3) and, for point lights, the distance to the light
    in pixels (None for suns). A point light exactly at a surface point gives L = (0, 0, 1).
    image_size: (H, W) of the whole image when the points are only some of its rows (the
    light's position is measured from the image's centre).
    """
    shape = np.broadcast(x_px, y_px, z_px).shape
    if light.kind == "sun":
        v = np.asarray(light.vector, dtype=np.float64)
        v = (v / np.linalg.norm(v)).astype(dtype)
        return np.broadcast_to(v, shape + (3,)), None
    h, w = image_size or shape
    p = light.position_px(h, w).astype(dtype)
    vec = np.stack(np.broadcast_arrays(p[0] - x_px, p[1] - y_px, p[2] - z_px), axis=-1).astype(dtype)
    dist = np.sqrt(np.sum(vec * vec, axis=-1))
    safe = np.where(dist > 0, dist, 1)[..., None]
    up = np.zeros_like(vec)
    up[..., 2] = 1
    return np.where(dist[..., None] > 0, vec / safe, up), dist


def default_sun():
    """The sun that lights a painting whose source names no light (DEFAULT_SUN_DIRECTION)."""
    return Light("sun", DEFAULT_SUN_DIRECTION, (1.0, 1.0, 1.0), 1.0, "Sun")
