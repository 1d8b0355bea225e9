"""A painting that moves (§16): its image slots as sequences of files or sprite sheets, read
per scene frame with a bounded cache. The glue between image files and the core, like
layered_files.py: the frame mapping and sheet cells are core/frames.py's; files are read by
imageio. No bpy here.

A slot is a **sequence** when its file name holds a frame number (`walk_####.png`, Blender's
convention, or `walk_%04d.png`), a **sheet** when its mapping has a grid of more than one cell
(`[frames] columns`/`rows`), else **still**. A [frames] grid makes the painting's per-pixel
still images (shape, dark, bright, specular colour, gloss, transparency) sheets; a sequence
is frames already, and the environment and background stay still unless their own
`[frames.environment]` table gives them a grid.

    >>> slot = slot_frames("dark", "dark_sheet.png", {**frame_defaults(), "columns": 4,
    ...                                                 "rows": 2, "count": 6})
    >>> slot.kind, [slot.frame_of(f) for f in range(1, 9)]
    ('sheet', [0, 1, 2, 3, 4, 5, 0, 1])

Make Shape reads a method's inputs frame by frame the same way (`FrameInputs`):

    >>> FrameInputs(["sheet.png"], SheetGrid(2, 1)).names()
    ['cell 1', 'cell 2']
"""
import hashlib
import math
import os
import re
from collections import OrderedDict
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..core.frames import SheetGrid, expand_pattern, frame_number, is_pattern, sheet_cell
from ..core.input_rules import PER_PIXEL_CHANNELS, ImageData
from ..errors import UserError
from ..params import FRAME_BY_KEY, frame_defaults
from .imageio import read_image

# the slots a [frames] grid makes sheets; the others (environment, background) need their own
SHEET_BY_DEFAULT = ("shape",) + PER_PIXEL_CHANNELS
GRID_KEYS = ("columns", "rows", "margin", "spacing")
# a slot's "path" for an image its caller holds (Blender's, by name), not a file
HELD = "held:"
# the longest loop exported or played as a whole (web pages, sheets of maps): 10 s at 24 fps
# of a painting whose slots come round together only after that take their longest's
MAX_LOOP = 240
# what the frame cache may hold by default: 24 frames of three 1024² float RGBA slots fit
DEFAULT_CACHE_MB = 1024


class FrameError(UserError):
    """A sequence or sheet that cannot be read as asked; the message names the frame or the
    numbers."""


def slot_settings(frames, channel, sequence=False):
    """The mapping of one slot: the painting's [frames] (`frames[""]`), then the slot's own
    table (`frames[channel]`). The painting's grid is not taken by the environment and
    background, nor by a `sequence` (its files are its frames already)."""
    base = dict(frame_defaults(), **frames.get("", {}))
    if channel not in SHEET_BY_DEFAULT or sequence:
        base.update({k: frame_defaults()[k] for k in GRID_KEYS})
    return dict(base, **frames.get(channel, {}))


def check_frame_settings(table, where):
    """A [frames] (or [frames.<slot>]) table's values checked by params.FRAME_PARAMS →
    {key: value}; ValueError naming the key."""
    out = {}
    for key, value in table.items():
        param = FRAME_BY_KEY.get(key)
        if param is None:
            raise ValueError(f"{where}.{key}: unknown key (frames keys: "
                             f"{', '.join(FRAME_BY_KEY)})")
        try:
            out[key] = param.check(value)
        except ValueError as exc:
            raise ValueError(f"{where}.{key}: {exc}") from None
    return out


def sequence_numbers(pattern):
    """The frame numbers of the files a pattern names, sorted (`walk_####.png` → the numbers
    of walk_0001.png …); FrameError when none exists."""
    folder, name = os.path.split(os.path.abspath(pattern))
    probe = expand_pattern(name, 0)
    # the pattern's text around its number, the number as digits of any length
    head, tail = _around_number(name)
    rx = re.compile(re.escape(head) + r"(-?\d+)" + re.escape(tail) + r"\Z")
    numbers = []
    try:
        entries = os.listdir(folder or ".")
    except OSError:
        raise FrameError(f"{pattern}: its folder {folder} cannot be read") from None
    for entry in entries:
        m = rx.match(entry)
        if m and expand_pattern(name, int(m.group(1))) == entry:
            numbers.append(int(m.group(1)))
    if not numbers:
        raise FrameError(f"{pattern}: no file matches (looked for names like {probe} in "
                         f"{folder})")
    return tuple(sorted(numbers))


def _around_number(name):
    """(text before, text after) a pattern's frame number."""
    marker = "\0"
    expanded = re.sub(r"#+|%0?\d*d", marker, name, count=1)
    head, _, tail = expanded.partition(marker)
    return head, tail


@dataclass(frozen=True)
class SlotFrames:
    """One image slot of a painting and how it follows the scene's frames."""
    channel: str
    path: str                   # a file, or a frame-numbered pattern
    kind: str                   # 'still', 'sequence' or 'sheet'
    mode: str = "cyclic"
    start: int = 1
    offset: int = 0
    count: int = 1
    rate: float = 1.0
    grid: SheetGrid = None      # a sheet's
    numbers: tuple = ()         # a sequence's files found

    def file_number(self, f):
        """The file number scene frame `f` shows (core.frames.frame_number)."""
        return frame_number(f, self.start, self.offset, self.count, self.mode, self.rate)

    def frame_of(self, f):
        """What scene frame `f` shows of this slot: a sequence's file number, a sheet's cell
        (0-based), None for a still image (every frame the same)."""
        if self.kind == "still":
            return None
        n = self.file_number(f)
        return n if self.kind == "sequence" else n - 1

    def file(self, f):
        return expand_pattern(self.path, self.file_number(f)) if self.kind == "sequence" \
            else self.path

    @property
    def first_file(self):
        return expand_pattern(self.path, self.numbers[0]) if self.numbers else self.path

    def files(self):
        """Every file the slot reads (a sequence's files found)."""
        if self.kind == "sequence":
            return [expand_pattern(self.path, n) for n in self.numbers]
        return [self.path]

    @property
    def name(self):
        return os.path.basename(self.path.removeprefix(HELD))

    def describe(self):
        """The one line an artist gets about what was read as frames."""
        name = self.name
        rate = "" if self.rate == 1 else f", {self.rate:g} painting frames a scene frame"
        if self.kind == "sequence":
            lo, hi = self.numbers[0], self.numbers[-1]
            missing = (hi - lo + 1) - len(self.numbers)
            gaps = f", {missing} missing" if missing else ""
            return (f"{self.channel}: {name}: files {lo}–{hi}{gaps}; {self.count} frames "
                    f"from scene frame {self.start} (offset {self.offset}), {self.mode}{rate}")
        if self.kind == "sheet":
            g = self.grid
            return (f"{self.channel}: {name}: a sprite sheet of {g.columns} × {g.rows} cells, "
                    f"{self.count} frames from scene frame {self.start}, {self.mode}{rate}")
        return ""


def grid_of(values):
    """A sheet's grid from {columns, rows, count, margin, spacing} ([frames] keys; count 0 when
    not given), or None for 1 × 1: not a sheet."""
    if values["columns"] * values["rows"] <= 1:
        return None
    return SheetGrid(values["columns"], values["rows"], values.get("count", 0),
                     values["margin"], values["spacing"])


def slot_frames(channel, path, settings):
    """A slot's path and mapping (slot_settings) → SlotFrames, its sequence's files listed;
    FrameError for a pattern that matches nothing or a grid that cannot hold the count."""
    grid = grid_of(settings)
    common = dict(mode=settings["mode"], start=settings["start"], rate=settings["rate"])
    if is_pattern(os.path.basename(path)):
        if grid is not None:
            raise FrameError(f"{channel}: {path} is a sequence of files and its mapping gives "
                             f"a sprite-sheet grid of {grid.columns} × {grid.rows}: a slot is "
                             f"one or the other")
        numbers = sequence_numbers(path)
        offset = numbers[0] - 1 if settings["offset"] == "auto" else settings["offset"]
        count = settings["count"] or numbers[-1] - numbers[0] + 1
        return SlotFrames(channel, path, "sequence", offset=offset, count=count,
                          numbers=numbers, **common)
    if grid is not None:
        cells = grid.columns * grid.rows
        if grid.count > cells:
            raise FrameError(f"{channel}: {path}: {grid.count} frames do not fit a sheet of "
                             f"{grid.columns} × {grid.rows} cells ({cells})")
        offset = 0 if settings["offset"] == "auto" else settings["offset"]
        return SlotFrames(channel, path, "sheet", offset=offset, count=grid.frames(),
                          grid=grid, **common)
    return SlotFrames(channel, path, "still")


def painting_slots(images, frames):
    """{channel: path} and a painting's frames table ({"": [frames], channel: [frames.x]}) →
    {channel: SlotFrames}."""
    return {ch: slot_frames(ch, path, slot_settings(frames, ch,
                                                    is_pattern(os.path.basename(path))))
            for ch, path in images.items()}


class PaintingFrames:
    """A painting's images at any scene frame, read once and kept in a cache of at most
    `cache_mb` megabytes (the least recently used out first; the frame asked for is always
    kept; of a sheet its cells are kept, not the sheet, which is read again only when a cell
    it held was dropped). Every
    frame of a sequence must have its first file's size; 8- and 16-bit frames mix (both hold
    codes in 0 … 1: read as the first file's bits, said in notes), floats and integers do
    not."""

    def __init__(self, slots, cache_mb=DEFAULT_CACHE_MB, read=read_image):
        self.slots = slots
        self._read = read
        self._cache = BoundedCache(cache_mb)      # file path → ImageData
        self._first = {}                 # channel → (size, bits) of its first file
        self._firsts = {}                # a sheet's path → the first cell like each cell
        self.notes = [s.describe() for s in slots.values() if s.kind != "still"]

    @property
    def animated(self):
        return any(s.kind != "still" for s in self.slots.values())

    @property
    def start(self):
        """The scene frame that shows the painting's first frame (its first moving slot's)."""
        return next((s.start for s in self.slots.values() if s.kind != "still"), 1)

    def loop(self):
        """Scene frames the painting takes to come round: the least common multiple of its
        moving slots' periods (a cycle, a swing forth and back; a slot that holds: the frames
        before it holds), or — beyond MAX_LOOP frames, or for rates that never line up — the
        longest of them. 1 for a still painting."""
        periods = [Fraction(2 * s.count - 2 if s.mode == "ping-pong" and s.count > 1
                            else s.count) / Fraction(s.rate).limit_denominator(1000)
                   for s in self.slots.values() if s.kind != "still"]
        if not periods:
            return 1
        common = periods[0]
        for period in periods[1:]:       # lcm of fractions: lcm of numerators / gcd of denominators
            common = Fraction(math.lcm(common.numerator * period.denominator,
                                       period.numerator * common.denominator),
                              common.denominator * period.denominator)
        longest = max(math.ceil(p) for p in periods)
        if common.denominator == 1 and common <= MAX_LOOP:
            return max(int(common), longest)
        return longest

    def drawings(self):
        """One loop of the painting from its start → (the scene frame that first shows each
        drawing, in order; the drawing each frame of the loop shows, as indices into them)."""
        first, sequence = {}, []
        for f in range(self.start, self.start + self.loop()):
            sequence.append(first.setdefault(self.key(f), len(first)))
        frames = sorted(first, key=first.get)
        return [self.start + sequence.index(first[k]) for k in frames], sequence

    def web_frames(self, fps, images=None):
        """One loop as a web page plays it (web/page.py page_data's `frames`): the images of
        each drawing it shows, the drawing of each frame, `fps`. images(f): a frame's images
        {channel: ImageData} (default: read here; the add-on passes what Blender holds)."""
        shown, sequence = self.drawings()
        images = images or self.images
        return {"drawings": [images(f) for f in shown], "sequence": sequence, "fps": fps}

    def shown(self, f):
        """What scene frame `f` shows, in words: 'shape frame 3, dark frame 2'."""
        return ", ".join(f"{ch} frame {n + 1 if self.slots[ch].kind == 'sheet' else n}"
                         for ch, n in self.key(f))

    def key(self, f):
        """The painting frame scene frame `f` shows: (channel, its frame) of every slot that
        moves. Two scene frames with the same key show the same drawing (bakes and derived
        images are kept by it)."""
        return tuple((ch, s.frame_of(f)) for ch, s in self.slots.items() if s.kind != "still")

    def shown_cell(self, channel, f):
        """frame_of(f) of a slot — of a sheet, the first of its cells that holds the same
        pixels (a drawing held over frames, as a lit Grease Pencil drawing's sheets hold
        theirs: its frames share one bake and one set of derived images, §16's m(f))."""
        slot = self.slots[channel]
        n = slot.frame_of(f)
        if slot.kind != "sheet":
            return n
        if slot.path not in self._firsts:
            self._cut(slot, n)                       # (its cells' digests, read once)
        return self._firsts[slot.path][n]

    def images(self, f):
        """{channel: ImageData} of scene frame `f`."""
        return {ch: self.image(ch, f) for ch in self.slots}

    def image(self, channel, f):
        slot = self.slots[channel]
        if slot.kind != "sheet":
            return self._file(slot, slot.file(f), f)
        cell = slot.frame_of(f)
        hit = self._cache.get((slot.path, cell))
        return hit if hit is not None else self._cut(slot, cell)

    def _cut(self, slot, wanted):
        """Read a sheet and keep its cells (not the sheet: its frames are what is shown, and
        a sheet of large frames is large), the one wanted last → that cell."""
        data = self._read(slot.path)
        cells = [c for c in range(slot.grid.frames()) if c != wanted] + [wanted]
        seen, firsts = {}, {}
        try:
            for cell in cells:
                px = np.ascontiguousarray(sheet_cell(data.pixels, slot.grid, cell))
                self._cache.put((slot.path, cell), ImageData(px, data.bits,
                                                             f"{data.name} [{cell + 1}]"),
                                px.nbytes)
                digest = hashlib.blake2b(px.tobytes(), digest_size=16).digest()
                seen[digest] = min(seen.get(digest, cell), cell)
                firsts[cell] = digest
        except ValueError as exc:
            raise FrameError(f"{slot.channel}: {slot.name}: {exc}") from None
        self._firsts[slot.path] = [seen[firsts[c]] for c in range(len(cells))]
        return self._cache.get((slot.path, wanted))

    def _file(self, slot, path, f):
        hit = self._cache.get(path)
        if hit is not None:
            return hit
        if slot.kind == "sequence" and not os.path.isfile(path):
            raise FrameError(self._missing(slot, path, f))
        data = self._consistent(slot, self._read(path), path)
        self._cache.put(path, data, data.pixels.nbytes)
        return data

    def forget(self):
        """Read every file again (one was replaced behind the cache's back)."""
        self._cache.clear()
        self._firsts.clear()

    def _missing(self, slot, path, f):
        n = slot.file_number(f)
        return (f"{slot.channel}: {os.path.basename(path)} (frame {n} of "
                f"{os.path.basename(slot.path)}, scene frame {f}) is missing; files found: "
                f"{_ranges(slot.numbers)}")

    def _consistent(self, slot, data, path):
        """The frame as the slot's first file reads it (whichever frame is read first, so a
        frame reads the same alone and in sequence), or FrameError naming both."""
        first_path = slot.first_file
        if path == first_path:
            self._first[slot.channel] = (data.size, data.bits)
            return data
        if slot.channel not in self._first:
            first = self._read(first_path)
            self._first[slot.channel] = (first.size, first.bits)
        size, bits = self._first[slot.channel]
        name, first_name = os.path.basename(path), os.path.basename(first_path)
        if data.size != size:
            raise FrameError(f"{slot.channel}: {name} is {data.size[0]}×{data.size[1]}, "
                             f"{first_name} {size[0]}×{size[1]}: every frame of a sequence "
                             f"must have one size")
        if data.bits != bits:
            if 32 in (data.bits, bits):
                raise FrameError(f"{slot.channel}: {name} is {_depth(data.bits)}, {first_name} "
                                 f"{_depth(bits)}: a sequence's frames are all float (linear) "
                                 f"or all 8/16-bit (sRGB codes)")
            note = (f"{slot.channel}: {name} is {_depth(data.bits)}, {first_name} "
                    f"{_depth(bits)}: read alike (codes 0 … 1), as {_depth(bits)} for the "
                    f"pre-blur")
            if note not in self.notes:
                self.notes.append(note)
            return ImageData(data.pixels, bits, data.name, data.notes)
        return data

    @property
    def peak_bytes(self):
        return self._cache.peak_bytes

    @property
    def cached_bytes(self):
        return self._cache.bytes


class FrameInputs:
    """A method's input files as frames: the numbers of the first frame-numbered input (every
    other one must have them too), or the cells of a sheet (`grid`), or one still frame."""

    def __init__(self, paths, grid=None):
        self.paths = [p for p in paths if p]
        patterns = [p for p in self.paths if is_pattern(os.path.basename(p))]
        if patterns and grid is not None:
            raise FrameError(f"{patterns[0]} is a sequence of files and a sheet grid of "
                             f"{grid.columns} × {grid.rows} was given: one or the other")
        self.grid = grid
        self.pattern = patterns[0] if patterns else None
        if self.pattern:
            self.numbers = list(sequence_numbers(self.pattern))
        elif grid is not None:
            self.numbers = list(range(grid.frames()))
        else:
            self.numbers = [None]
        self._images = {}              # stills and sheets, read once

    @property
    def animated(self):
        return self.numbers != [None]

    def __len__(self):
        return len(self.numbers)

    def names(self):
        if self.pattern:
            return [os.path.basename(expand_pattern(self.pattern, n)) for n in self.numbers]
        return [f"cell {n + 1}" for n in self.numbers] if self.grid else ["the image"]

    def read(self, path, i):
        """Input `path` at frame `i` (0-based) → ImageData."""
        n = self.numbers[i]
        if is_pattern(os.path.basename(path)):
            file = expand_pattern(path, n)
            if not os.path.isfile(file):
                raise FrameError(f"{os.path.basename(file)}: frame {n} of "
                                 f"{os.path.basename(path)} is missing (the frames follow "
                                 f"{os.path.basename(self.pattern)}'s numbers)")
            return read_image(file)
        if path not in self._images:
            self._images[path] = read_image(path)
        data = self._images[path]
        if self.grid is None:
            return data
        try:
            cell = sheet_cell(data.pixels, self.grid, n)
        except ValueError as exc:
            raise FrameError(f"{os.path.basename(path)}: {exc}") from None
        return ImageData(np.ascontiguousarray(cell), data.bits, f"{data.name} [{n + 1}]")

    def sheet_size(self):
        """The (width, height) of the input sheet (the output sheet's)."""
        first = next(p for p in self.paths if p in self._images)
        return self._images[first].size

    def fingerprint(self, i):
        """A digest of every input's pixels at frame i: frames that hold the same pixels
        have the same one (their shape is made once)."""
        digest = hashlib.blake2b(digest_size=16)
        for path in self.paths:
            px = self.read(path, i).pixels
            digest.update(str(px.shape).encode())
            digest.update(np.ascontiguousarray(px).tobytes())
        return digest.hexdigest()


class BoundedCache:
    """key → value, at most `mb` megabytes of them (each put with its size), the least
    recently used dropped first; the newest is always kept, however large. `peak_bytes`: the
    most it held."""

    def __init__(self, mb):
        self.mb = mb
        self._items = OrderedDict()          # key → (value, bytes)
        self.bytes = self.peak_bytes = 0

    def get(self, key):
        hit = self._items.get(key)
        if hit is None:
            return None
        self._items.move_to_end(key)
        return hit[0]

    def put(self, key, value, nbytes):
        old = self._items.pop(key, None)
        self.bytes += nbytes - (old[1] if old else 0)
        self._items[key] = (value, nbytes)
        self.peak_bytes = max(self.peak_bytes, self.bytes)
        while len(self._items) > 1 and self.bytes > self.mb * 2**20:
            _, (_, dropped) = self._items.popitem(last=False)
            self.bytes -= dropped

    def clear(self):
        self._items.clear()
        self.bytes = 0


def _depth(bits):
    return "float" if bits == 32 else f"{bits}-bit"


def _ranges(numbers):
    """1, 2, 3, 5, 7, 8 → '1–3, 5, 7–8'."""
    out, run = [], [numbers[0]]
    for n in numbers[1:]:
        if n == run[-1] + 1:
            run.append(n)
            continue
        out.append(run)
        run = [n]
    out.append(run)
    return ", ".join(f"{r[0]}–{r[-1]}" if len(r) > 1 else f"{r[0]}" for r in out)
