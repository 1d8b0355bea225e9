"""A Grease Pencil drawing as data (issue 42): filled shapes on layers, frame by frame — what a
sample ships (its drawing.json, named by its recipe's `drawing`) and the add-on builds into a
Grease Pencil object (blender/scenes/grease_pencil/building.build_drawing). No bpy here.

    {"name": "Walk", "materials": {"sky": [0.35, 0.55, 0.85]},
     "layers": [{"name": "Sky", "translation": [0, 0, 0],
                 "fills": [{"material": "sky", "frame": 1, "points": [[-1, -0.75], …]}]}]}

Points are (x, z) on the drawing's XZ plane (Grease Pencil's front view), colours linear RGB;
layers back to front; a layer's drawing on a frame holds until its next one.

>>> d = parse_drawing({"name": "D", "materials": {"m": [1, 0, 0]}, "layers": [
...     {"name": "L", "fills": [{"material": "m", "frame": 3, "points": [[0, 0], [1, 0], [0, 1]]}]}]})
>>> frame_range(d), d.layers[0].fills[0].points[2]
((3, 3), (0.0, 1.0))
"""
import json
from dataclasses import dataclass, field

from ..errors import UserError


class DrawingError(UserError):
    """A drawing file that cannot be read; the message names the file and the key."""


@dataclass
class Fill:
    material: str
    points: list                 # [(x, z)], closed
    frame: int = 1


@dataclass
class DrawingLayer:
    name: str
    fills: list = field(default_factory=list)
    translation: tuple = (0.0, 0.0, 0.0)


@dataclass
class Drawing:
    name: str
    materials: dict              # name → linear (r, g, b)
    layers: list


def parse_drawing(data, where="drawing"):
    """A drawing as JSON holds it → Drawing (DrawingError says what is wrong, where)."""
    def need(cond, message):
        if not cond:
            raise DrawingError(f"{where}: {message}")
    need(isinstance(data, dict), "expected an object")
    materials = data.get("materials", {})
    need(isinstance(materials, dict) and materials, "materials: expected {name: [r, g, b]}")
    for name, rgb in materials.items():
        need(isinstance(rgb, list) and len(rgb) == 3, f"materials.{name}: expected [r, g, b]")
    layers = data.get("layers")
    need(isinstance(layers, list) and layers, "layers: expected a list of layers")
    out = []
    for i, layer in enumerate(layers):
        at = f"layers[{i}]"
        need(isinstance(layer, dict) and isinstance(layer.get("name"), str),
             f"{at}: expected {{\"name\": …, \"fills\": […]}}")
        fills = []
        for k, fill in enumerate(layer.get("fills", [])):
            need(fill.get("material") in materials,
                 f"{at}.fills[{k}].material: {fill.get('material')!r} is not in materials")
            points = fill.get("points", [])
            need(isinstance(points, list) and len(points) >= 3 and
                 all(isinstance(p, list) and len(p) == 2 for p in points),
                 f"{at}.fills[{k}].points: expected at least 3 [x, z] points")
            fills.append(Fill(fill["material"], [(float(x), float(z)) for x, z in points],
                              int(fill.get("frame", 1))))
        translation = layer.get("translation", [0.0, 0.0, 0.0])
        need(isinstance(translation, list) and len(translation) == 3,
             f"{at}.translation: expected [x, y, z]")
        out.append(DrawingLayer(layer["name"], fills, tuple(float(v) for v in translation)))
    return Drawing(str(data.get("name", "Drawing")),
                   {n: tuple(float(v) for v in rgb) for n, rgb in materials.items()}, out)


def load_drawing(path):
    """A drawing file (JSON) → Drawing."""
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except OSError as exc:
        raise DrawingError(f"{path}: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise DrawingError(f"{path}: not JSON ({exc.msg}, line {exc.lineno})") from None
    return parse_drawing(data, path)


def drawing_json(drawing):
    """A Drawing as the JSON text load_drawing reads (points to 6 decimals)."""
    return json.dumps({
        "name": drawing.name,
        "materials": {n: [round(v, 6) for v in rgb] for n, rgb in drawing.materials.items()},
        "layers": [{"name": layer.name, "translation": list(layer.translation),
                    "fills": [{"material": f.material, "frame": f.frame,
                               "points": [[round(x, 6), round(z, 6)] for x, z in f.points]}
                              for f in layer.fills]} for layer in drawing.layers]}, indent=1)


def frame_range(drawing):
    """(first, last) frame a drawing's fills are drawn on."""
    frames = [f.frame for layer in drawing.layers for f in layer.fills] or [1]
    return min(frames), max(frames)
