"""Memory asked for before it is spent (issue 38): what reading an image, a render, a bake
and the add-on's Add will need, from the image headers and the settings, against what the
machine has — refused with both numbers and what to do, before any large allocation.

The estimates follow the work's phases (read, prepare the shape, bake each light, shade,
write): each phase's peak is what it keeps plus what it holds for a while; bounded parts
(shading in bands of rows, tracing rays in chunks, the crossings' tables in groups) are
bounded here as in the core. The per-pixel figures were measured with tracemalloc on 512²
and 2048² paintings; `benchmarks/memory.py` checks the whole estimate against measured peaks
(RSS) at 1024², 4096² and 8192² → docs/memory-numbers.md.

    >>> shape = (4096, 4096, 1, 2)                  # a 16-bit height map's header
    >>> round(read_bytes(*shape)[0] / 2**20)        # Blender's float buffer, ours, the copy
    576
"""
import math
import os
from dataclasses import dataclass

try:
    import resource
except ImportError:         # Windows: no address-space limits to read
    resource = None

from ..core import crossing_blocks, crossings
from ..core.either_relief import casts_either
from ..core.input_rules import PER_PIXEL_CHANNELS, relief_of
from ..core.shadow import BAND_PIXELS
from ..errors import UserError

MiB = 2 ** 20
# Python, numpy and Blender's module loaded: what a command holds before its first image
# (bpy 5.0.1; where Blender's module is loaded, what it measured: hold_base)
BASE_BYTES = 260 * MiB
_base = [BASE_BYTES]
# Shading in bands of rows (core.pipeline.RENDER_BAND_PIXELS): its temporaries per pixel
SHADE_BAND_PX = 1 << 20
SHADE_BAND_BYTES = 114
# Preparing the shape (§2): (bytes kept per pixel, held a while per pixel, fixed)
# ("either": the normals, both reliefs, and the first relief's term while the second bakes)
PREPARE = {"height": (16, 23, 16 * MiB), "along_ray": (20, 41, 8 * MiB),
           "integrated": (16, 118, 0), "either": (28, 126, 8 * MiB)}
# A bake beside its crossings' tables: per pixel up to the rays traced at once, per pixel
# always (the terms and starts at full size), fixed; a light whose largest block of tables
# would not fit marches instead (core.bake): per pixel of the band marched at once
BAKE_TRACED, BAKE_PX, BAKE_FIXED = 90, 13, 24 * MiB
MARCH_BAND_BYTES = 200
# Leave this share of what the machine has free for Blender, the desktop and the rest
HEADROOM = 0.9
# glibc keeps a freed block below its mmap threshold (at most 32 MiB on 64-bit) for reuse
# instead of giving it back: a phase's temporaries that small stay in the resident set
STICKY_BYTES = 32 * MiB
# A read of an image Blender holds keeps its RGBA float buffer for the next read (a stroke
# reads the shape each dab: imageio._read_buffer), for images up to this many pixels
READ_BUFFER_PX = 4096 * 4096


class NotEnoughMemory(UserError):
    """A command or an Add that would need more memory than the machine has."""


def available_bytes():
    """The memory this process can be given now, or None where it cannot tell (then nothing is
    refused): the machine's (Linux: MemAvailable; elsewhere the free physical pages), less
    where a limit on the process is lower (issue 60): its cgroup's (a container, a systemd
    slice: memory.max − memory.current) or its address-space limit (`ulimit -v`, less what
    it maps already)."""
    limits = [machine_bytes(), cgroup_bytes(), rlimit_bytes()]
    known = [n for n in limits if n is not None]
    return min(known) if known else None


def machine_bytes():
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def cgroup_bytes(root="/sys/fs/cgroup"):
    """What the process's cgroup (v2) lets it add: memory.max − memory.current, or None
    without a limit."""
    try:
        with open("/proc/self/cgroup") as fh:
            path = next(line.split(":", 2)[2].strip() for line in fh if line.startswith("0::"))
        folder = os.path.join(root, path.lstrip("/"))
        with open(os.path.join(folder, "memory.max")) as fh:
            limit = fh.read().strip()
        if limit == "max":
            return None
        with open(os.path.join(folder, "memory.current")) as fh:
            return max(0, int(limit) - int(fh.read()))
    except (OSError, ValueError, StopIteration):
        return None


def rlimit_bytes():
    """What `ulimit -v` (RLIMIT_AS) leaves the process to map, or None without a limit."""
    if resource is None:
        return None
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    if soft == resource.RLIM_INFINITY:
        return None
    try:
        with open("/proc/self/statm") as fh:
            mapped = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        mapped = 0
    return max(0, soft - mapped)


def gib(n):
    """Bytes as GiB, one decimal (a size past any machine's memory in powers of ten).

    >>> gib(3 * 2**29), gib(2**60)
    ('1.5 GiB', '1.1e+09 GiB')
    """
    g = n / 2**30
    return f"{g:.1f} GiB" if g < 1e6 else f"{g:.2g} GiB"


def fits(needed):
    """Whether `needed` bytes fit in the memory free now (less HEADROOM); True where the
    machine cannot tell."""
    have = available_bytes()
    return have is None or needed <= HEADROOM * have


def resident_bytes():
    """This process's resident memory now (Linux: /proc/self/statm), or None where it cannot
    tell."""
    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError, AttributeError):
        return None


def hold_base(nbytes):
    """Estimates made in this process start from `nbytes` (what it holds before its first
    image, measured when Blender's module was loaded: 264 MiB with bpy 5.0.1, 404 MiB with
    5.3.0), never less than BASE_BYTES; None keeps BASE_BYTES."""
    _base[0] = max(BASE_BYTES, nbytes or 0)


def base_bytes():
    """What a command holds before its first image (BASE_BYTES, or hold_base's)."""
    return _base[0]


def check(needed, what, advice):
    """Raise NotEnoughMemory naming both numbers and `advice` when `needed` bytes are more than
    the machine has (less HEADROOM); return `needed`. advice: a line, or a function that
    makes it (asked only when refusing)."""
    if not fits(needed):
        have = available_bytes()
        advice = advice() if callable(advice) else advice
        raise NotEnoughMemory(f"{what} would need about {gib(needed)} of memory; this machine "
                              f"has {gib(have)} free: {advice}")
    return needed


# One video frame's share of a turntable: Cycles' render buffers, the render result, its
# display copy and FFmpeg's frame buffers. Measured with `turntable --frames 2 --samples 1`
# (bpy 5.0.1): 431 MB peak at 1024², 1879 MB at 4096²: 92 bytes a pixel beyond the painting
VIDEO_FRAME_PX_BYTES = 92


def video_frame_bytes(width, height):
    """The memory a turntable's frames of width × height take (VIDEO_FRAME_PX_BYTES)."""
    return VIDEO_FRAME_PX_BYTES * width * height


def largest_video_side(held=0):
    """The largest even square frame whose video fits the memory free now, beside `held`
    bytes still to come (None where the machine cannot tell)."""
    have = available_bytes()
    if have is None:
        return None
    side = int(math.sqrt(max(HEADROOM * have - held, 0) / VIDEO_FRAME_PX_BYTES))
    return max(16, side - side % 2)


def check_video(width, height, held=0):
    """Refuse a turntable whose frames (and `held` bytes more: the command's own, before
    Blender starts) do not fit, before the work."""
    side = largest_video_side(held)
    return check(held + video_frame_bytes(width, height), f"a {width}×{height} turntable",
                 f"choose a smaller --size (at most {side} {side} here)" if side else
                 "choose a smaller --size")


def check_read(header, name):
    """Refuse to read an image whose decoding would not fit (a decompression bomb, a poster
    scan): header as imageio.image_header gives it, with whether it is an EXR."""
    w, h, c, b, exr = header
    return check(base_bytes() + read_bytes(w, h, c, b, exr)[0], f"reading {name} ({w}×{h})",
                 "give a smaller image (scale it down in a painting program)")


def read_bytes(width, height, channels, bytes_per_channel, exr=False):
    """(peak while reading, kept after) of one image file decoded to core ImageData: OpenEXR's
    channels, their stack and the flipped copy; or Blender's buffer (bytes for 8-bit files,
    floats for 16-bit and float ones), our float copy of it, and the channels kept."""
    px = width * height
    kept = 4 * channels * px
    if exr:
        return 3 * kept, kept
    blender = 4 if bytes_per_channel == 1 else 16
    return (blender + 16) * px + kept, kept


@dataclass
class Painting:
    """What a painting's estimate reads: its shape's size at the work's resolution, the bytes
    its images keep, the most reading one takes above that and what reading them leaves in
    the resident set (STICKY_BYTES), how its shape is prepared."""
    width: int
    height: int
    kept: int
    reading: int
    read_left: int
    shape: str             # 'height', 'along_ray' or 'integrated'

    @property
    def px(self):
        return self.width * self.height

    def left(self, held_px):
        """What a phase that held `held_px` bytes a pixel leaves resident after it: all of
        it when its one-channel arrays are below glibc's threshold."""
        return held_px * self.px if 4 * self.px < STICKY_BYTES else 0


def painting(headers, p, width=None):
    """Painting from {channel: (w, h, channels, bytes per channel, exr)} headers, read with
    parameters p, rendered at `width` (None: the shape image's)."""
    sw, sh = headers["shape"][:2]
    w, h = (sw, sh) if not width else (width, max(1, round(sh * width / sw)))
    kept, reading, left = 0, 0, 0
    for channel, (iw, ih, c, b, exr) in headers.items():
        peak, keep = read_bytes(iw, ih, c, b, exr)
        reading = max(reading, peak - keep)
        left += peak - keep if 16 * iw * ih < STICKY_BYTES else 0
        at_size = channel == "shape" or channel in PER_PIXEL_CHANNELS
        kept += keep if not at_size or (iw, ih) == (w, h) else 4 * c * w * h + keep
    return Painting(w, h, kept, reading, left, shape_work(p, headers["shape"][2] in (2, 4)))


def shape_work(p, shape_has_alpha):
    """How the shape is prepared (PREPARE's key): a height map, or a normal map's relief (both
    where it may cast the shadow of either: core/either_relief.py)."""
    if p.shape.kind == "height":
        return "height"
    return "either" if casts_either(p) else relief_of(p.shadows.relief, shape_has_alpha)


# What export-web holds beside the images it reads: the page's textures and their PNG and
# base64 text. Measured (the test painting, bpy 5.0.1): 81 MB above base + kept + reading at
# 1024², 66 MB at 2048² (reading's transient overlaps: the model is high by ~25 % there)
PAGE_FIXED = 96 * 2**20


def page_bytes(pt):
    """The peak of `export-web` of Painting `pt`: its images read whole (the page may be
    drawn smaller, --max-size), and the page made from them."""
    return base_bytes() + pt.kept + pt.reading + PAGE_FIXED


def final_bake_bytes(w, h, shape, lights, offset):
    """The peak of a final bake of `lights` on a prepared shape (w, h) of PREPARE key `shape`:
    the lights bake one after the other, each at its own peak."""
    kept_px = PREPARE[shape][0]
    return base_bytes() + max(bake_bytes(w, h, light, offset, kept_px) for light in lights)


# Past this many pixels a side the crossings' grid is not built to count its tables (building
# it for --width 4e7 took 73 s and 10 GB before refusing): at 16384² every light's largest
# block is already 3.8–11.7 GiB, past MAX_TABLE_BYTES, so a bake that size marches (§6)
LARGEST_COUNTED_SIDE = 65536


def bake_bytes(w, h, light, offset, kept_px):
    """Peak above what is kept, of one light's final bake at (w, h) (§13; the lower levels
    bake at a fraction of the pixels): the crossings' largest group of tables, the rays
    traced at once, the terms."""
    px = w * h
    fixed = (BAKE_PX + kept_px) * px + BAKE_FIXED
    if max(w, h) > LARGEST_COUNTED_SIDE or \
            crossings.table_bytes(light, h, w, offset)[1] > crossing_blocks.MAX_TABLE_BYTES:
        return MARCH_BAND_BYTES * min(px, BAND_PIXELS) + fixed       # the march (§6)
    traced = min(px, crossing_blocks.TRACE_PIXELS)
    return crossings.table_peak(light, h, w, offset) + BAKE_TRACED * traced + fixed


def render_bytes(pt, p, lights):
    """The peak of `render` by the numpy core (§2–§11) of Painting `pt` with parameters p."""
    kept_px, prep_px, prep_fixed = PREPARE[pt.shape]
    px = pt.px
    shadows = 4 * px * len(lights) if p.shadows.enabled else 0
    prepared = pt.read_left + pt.left(prep_px)          # what the phases after it start on
    later = [kept_px * px + shadows + 16 * px + SHADE_BAND_BYTES * min(px, SHADE_BAND_PX)]
    if p.shadows.enabled:
        later += [bake_bytes(pt.width, pt.height, light, p.shadows.offset, kept_px) + shadows
                  for light in lights]
    return base_bytes() + pt.kept + max(pt.reading, pt.read_left + prep_px * px + prep_fixed,
                                      prepared + max(later))


def bake_shadow_bytes(pt, p, light):
    """The peak of `bake-shadow`: the shape read and prepared, one light baked, written."""
    kept_px, prep_px, prep_fixed = PREPARE[pt.shape]
    return base_bytes() + pt.kept + max(
        pt.reading, pt.read_left + prep_px * pt.px + prep_fixed,
        pt.read_left + pt.left(prep_px) + bake_bytes(pt.width, pt.height, light,
                                                     p.shadows.offset, kept_px) + 4 * pt.px)


def blender_image_bytes(header):
    """What Blender keeps of a loaded image: its byte (8-bit files) or float buffer, RGBA."""
    w, h, _, bytes_per_channel, exr = header
    return w * h * (4 if bytes_per_channel == 1 and not exr else 16)


# Lighting a drawing (issue 42: From Grease Pencil, and a drawing's render, turntable and
# page), per pixel of its frame: each distinct drawing of a layer kept (drawn, its dark copy
# and inflated shape, its sprite-sheet cell), each lit layer (its images in Blender, its
# bake), and a fixed part. Fitted (least squares of the ratio) to peaks (RSS) of the walk
# sample (3 layers, 26 drawings) and a still 3-layer drawing at 256, 512, 1024 and 2048 px,
# numpy drawing the layers (issue 61: Blender's renderer, and its 150 MiB, no longer in
# it): 0.89–1.14 of the peaks (the walk at 2048 px, 12.3 GiB, grows less than its cells).
DRAWING_CELL, DRAWING_LAYER, DRAWING_FIXED = 153, 219, 27 * MiB


def drawing_bytes(drawings, layers, width, height):
    """The peak of lighting a drawing: `drawings` distinct drawings over its `layers` lit
    layers, each drawn width × height."""
    return base_bytes() + DRAWING_FIXED + width * height * (drawings * DRAWING_CELL +
                                                          layers * DRAWING_LAYER)


def add_bytes(headers, p, lights, width=None):
    """The peak of Add › Dynamic Painting: Blender's copy of every image beside the numpy
    work of the first bake and the derived images (a render's phases), the painting worked
    at `width` (Add's Max Size; None: its shape image's)."""
    pt = painting(headers, p, width)
    return render_bytes(pt, p, lights) + sum(blender_image_bytes(h) for h in headers.values()) \
        + read_buffer_bytes(headers)


def read_buffer_bytes(headers):
    """The read buffer Add's reads leave kept (READ_BUFFER_PX): the RGBA floats of its
    largest image whose file has fewer channels than Blender holds (4), if not too large."""
    return 16 * max((w * h for w, h, c, _, _ in headers.values()
                     if c < 4 and w * h <= READ_BUFFER_PX), default=0)
