"""Texture atlases as TexturePacker writes them (issue 59): a sheet of packed sprites, its
normal-map sheet beside it, and a JSON file that lists the frames — read as the frames it
lists, each at its source size (trimmed transparent borders put back, rotated frames turned
back), so that a packed walk cycle is a painting that moves (§16). No bpy.

Three JSON forms are read: TexturePacker's *hash* (`frames` a name → frame mapping) and *array*
(`frames` a list with `filename`), each with `meta.image`, and Phaser 3's *multiatlas*
(`textures`, each with its `image`, `normalMap` and `frames`). The normal-map sheet is the one
the file names (`normalMap`, `meta.normal_map`), else the sheet's own map by name
(`character.png` → `character_n.png`, sprite_files).

    >>> frames = parse_atlas({"frames": {"b.png": {"frame": {"x": 0, "y": 0, "w": 2, "h": 3},
    ...     "rotated": False, "trimmed": True, "spriteSourceSize": {"x": 1, "y": 0, "w": 2, "h": 3},
    ...     "sourceSize": {"w": 4, "h": 3}}}, "meta": {"image": "sheet.png"}})
    >>> frames[0].image, frames[0].name, frames[0].source
    ('sheet.png', 'b.png', (4, 3))
"""
import json
import os
import re
from dataclasses import dataclass

import numpy as np

from ..errors import UserError
from .sprite_files import map_suffix

MAX_JSON_BYTES = 16 << 20     # an atlas lists frames: a JSON larger than this is not one
# TexturePacker's JSON, also as Unity's text asset (.txt) for Unity's Futile and others
ATLAS_EXTENSIONS = (".json", ".txt")


class AtlasError(UserError):
    """A JSON file that names itself an atlas but cannot be read as one."""


@dataclass(frozen=True)
class AtlasFrame:
    name: str
    image: str             # the sheet it is packed in (a file name beside the JSON)
    normal_map: str        # that sheet's normal map ('' if none)
    box: tuple             # (x, y, w, h) in the sheet, top-left origin, as the sprite stands
    rotated: bool          # packed turned 90° clockwise
    offset: tuple          # (x, y) of the trimmed box in the source, top-left origin
    source: tuple          # (w, h) of the source sprite


def _box(d, where):
    try:
        return tuple(int(d[k]) for k in ("x", "y", "w", "h"))
    except (KeyError, TypeError, ValueError):
        raise AtlasError(f"{where}: expected {{x, y, w, h}}, got {d!r}") from None


def _frame(name, entry, image, normal_map, where):
    if not isinstance(entry, dict) or "frame" not in entry:
        raise AtlasError(f"{where}: a frame without its 'frame' box")
    box = _box(entry["frame"], f"{where}.frame")
    trimmed = entry.get("spriteSourceSize")
    offset = _box(trimmed, f"{where}.spriteSourceSize")[:2] if trimmed else (0, 0)
    size = entry.get("sourceSize") or {"w": box[2], "h": box[3]}
    try:
        source = (int(size["w"]), int(size["h"]))
    except (KeyError, TypeError, ValueError):
        raise AtlasError(f"{where}.sourceSize: expected {{w, h}}, got {size!r}") from None
    if min(box[2:]) < 1 or min(source) < 1 or offset[0] + box[2] > source[0] or \
            offset[1] + box[3] > source[1]:
        raise AtlasError(f"{where}: its box {box[2]}×{box[3]} at {offset} does not fit its "
                         f"source size {source[0]}×{source[1]}")
    return AtlasFrame(str(name), image, normal_map, box, bool(entry.get("rotated")), offset,
                      source)


def parse_atlas(data, where="atlas"):
    """An atlas JSON's data → [AtlasFrame], in the order their names sort (01, 02, …, 10);
    AtlasError for data that says it is an atlas but is not whole; [] for other JSON."""
    if not isinstance(data, dict):
        return []
    frames = []
    if isinstance(data.get("textures"), list):                  # Phaser 3 multiatlas
        for i, tex in enumerate(data["textures"]):
            if not isinstance(tex, dict) or "image" not in tex:
                raise AtlasError(f"{where}: textures[{i}] names no image")
            for j, entry in enumerate(tex.get("frames") or []):
                frames.append(_frame(entry.get("filename", j) if isinstance(entry, dict) else j,
                                     entry, str(tex["image"]), str(tex.get("normalMap") or ""),
                                     f"{where}: textures[{i}].frames[{j}]"))
    elif "frames" in data and isinstance(data.get("meta"), dict) and "image" in data["meta"]:
        meta = data["meta"]
        image, normal_map = str(meta["image"]), str(meta.get("normal_map") or
                                                     meta.get("normalMap") or "")
        entries = data["frames"]
        items = entries.items() if isinstance(entries, dict) else \
            ((e.get("filename", i) if isinstance(e, dict) else i, e)
             for i, e in enumerate(entries or []))
        frames = [_frame(name, entry, image, normal_map, f"{where}: frames[{name!r}]")
                  for name, entry in items]
    else:
        return []
    return sorted(frames, key=lambda f: _natural(f.name))


def _natural(name):
    return [int(t) if t.isdigit() else t.lower() for t in re.split(r"(\d+)", name)]


def atlas_in(folder, image_names):
    """The atlas a folder holds (a .json or .txt file of TexturePacker's JSON) → (its path,
    [AtlasFrame]) with each frame's normal-map sheet found, or None. AtlasError for an atlas JSON that is broken or names a missing sheet."""
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if not name.lower().endswith(ATLAS_EXTENSIONS) or not os.path.isfile(path) or \
                os.path.getsize(path) > MAX_JSON_BYTES:
            continue
        try:
            with open(path, encoding="utf-8") as fh:
                data = json.load(fh)
        except (OSError, UnicodeDecodeError, ValueError):
            continue            # not JSON: some other file
        frames = parse_atlas(data, name)
        if not frames:
            continue
        for sheet in {f.image for f in frames}:
            if sheet not in image_names:
                raise AtlasError(f"{path}: its sheet {sheet} is not in {folder}")
        maps = {f.image: f.normal_map or next((m for m in image_names
                                               if map_suffix(f.image, m) == "normal"), "")
                for f in frames}
        return path, [AtlasFrame(f.name, f.image, maps[f.image], f.box, f.rotated, f.offset,
                                 f.source) for f in frames]
    return None


def cut_frame(sheet, frame):
    """One frame's pixels (y-up, as ImageData holds them) cut from its sheet's (y-up) and put
    back at its source size: turned back if packed rotated, its trimmed border transparent."""
    top_first = sheet[::-1]
    x, y, w, h = frame.box
    if frame.rotated:           # packed turned 90° clockwise: its box in the sheet is h × w
        cut = np.rot90(top_first[y:y + w, x:x + h], 1)
    else:
        cut = top_first[y:y + h, x:x + w]
    if cut.shape[:2] != (h, w):
        raise AtlasError(f"frame {frame.name}: its box {frame.box} lies outside the sheet "
                         f"{frame.image} ({sheet.shape[1]}×{sheet.shape[0]})")
    channels = sheet.shape[2]
    out = np.zeros((frame.source[1], frame.source[0], max(channels, 4) if channels in (1, 3)
                    else channels), sheet.dtype)
    ox, oy = frame.offset
    if channels in (1, 3):      # no alpha of its own: the cut is opaque, the border clear
        cut = np.concatenate([cut if channels == 3 else np.repeat(cut, 3, -1),
                              np.ones(cut.shape[:2] + (1,), sheet.dtype)], -1)
    out[oy:oy + h, ox:ox + w] = cut
    return out[::-1]
