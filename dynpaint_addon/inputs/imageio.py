"""Reading and writing image files; the only place rows are flipped (pipeline.md §0).

Files store the top row first; the core works y-up (row 0 at the bottom), so `read_image`
returns y-up arrays and the writers take y-up arrays. EXR goes through the OpenEXR package;
PNG, JPEG, TIFF and the rest through Blender's own image loader (bpy, imported on first use,
so the core and EXR-only commands never need it). PNGs are written by a small exact encoder.
"""
import contextlib
import os
import struct
import sys
import zlib

import numpy as np

from ..core.colour import linear_to_srgb
from ..core.input_rules import ImageData
from ..errors import UserError
from .memory import READ_BUFFER_PX, check_read
from .whole_files import written_whole

EXR_MAGIC = b"\x76\x2f\x31\x01"


class ImageWriteError(UserError):
    """An image that cannot be written as asked (an unsupported format)."""


class ImageReadError(UserError):
    """An image could not be read; the message names the file and the problem."""


def read_image(path):
    """Read any supported image → ImageData (float32, y-up, channels 1–4, bits 8/16/32)."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise ImageReadError(f"{path}: file not found")
    if os.path.isdir(path):
        raise ImageReadError(f"{path}: is a folder, not an image")
    if not os.path.isfile(path):        # a pipe (FIFO), a device: reading would wait forever
        raise ImageReadError(f"{path}: is not a regular file (a pipe or a device), not an "
                             f"image")
    with open(path, "rb") as fh:
        head = fh.read(4)
    if not head:
        raise ImageReadError(f"{path}: file is empty")
    header = file_header(path)
    if header is not None:          # a size that cannot fit is refused before decoding
        check_read(header, os.path.basename(path))
    if head == EXR_MAGIC:
        return _read_exr(path)
    return _read_with_blender(path)


def file_header(path):
    """image_header(path) and whether the file is an OpenEXR one (read by OpenEXR, not
    Blender), or None."""
    header = image_header(path)
    if header is None:
        return None
    with open(path, "rb") as fh:
        return (*header, fh.read(4) == EXR_MAGIC)


def png_header(head):
    """(width, height, channels, bytes per channel) from a PNG's first 26 bytes, or None."""
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR" or len(head) < 26:
        return None
    w, h, depth, colour = struct.unpack(">IIBB", head[16:26])
    return w, h, {0: 1, 2: 3, 3: 3, 4: 2, 6: 4}.get(colour, 4), max(1, depth // 8)


# A PNG file's size can exceed its raw pixels by zlib's stored blocks (5 bytes each 16 KiB)
# and its chunks; anything larger is not a PNG of that size (a zip bomb's member)
PNG_SLACK = 1.01


def png_bound(width, height, channels, bytes_per_channel):
    """The most bytes a PNG of that size and kind can hold (its filter bytes, zlib's worst
    case, its chunks)."""
    raw = height * (1 + width * channels * bytes_per_channel)
    return int(raw * PNG_SLACK) + (1 << 16)


def image_header(path):
    """(width, height, channels, bytes per channel) from a file's header, without decoding its
    pixels (PNG, JPEG, OpenEXR, BMP); None for a format or file it cannot tell. What memory is
    checked against before an image is read (memory.py)."""
    if not os.path.isfile(path):        # a pipe would block the open: read_image says so
        return None
    try:
        with open(path, "rb") as fh:
            head = fh.read(64)
            if png_header(head):
                return png_header(head)
            if head[:2] == b"\xff\xd8":
                return _jpeg_header(fh)
            if head[:4] == EXR_MAGIC:
                return _exr_header(head + fh.read(1 << 16))
            if head[:2] == b"BM":
                w, h = struct.unpack("<ii", head[18:26])
                return w, abs(h), 4 if struct.unpack("<H", head[28:30])[0] == 32 else 3, 1
    except (OSError, struct.error, ValueError):
        return None
    return None


def painting_headers(files):
    """{channel: file_header} of a painting's files ({channel: path}), or None when the shape
    image's header cannot be read (the estimate then waits for the pixels)."""
    headers = {c: file_header(path) for c, path in files.items()}
    if headers.get("shape") is None:
        return None
    return {c: h for c, h in headers.items() if h is not None}


def _jpeg_header(fh):
    """A JPEG's size from its first start-of-frame marker (SOF0–SOF15 but DHT, JPG, DAC)."""
    fh.seek(2)
    while True:
        marker = fh.read(2)
        if len(marker) < 2 or marker[0] != 0xFF:
            return None
        length = struct.unpack(">H", fh.read(2))[0]
        if 0xC0 <= marker[1] <= 0xCF and marker[1] not in (0xC4, 0xC8, 0xCC):
            bits, h, w, channels = struct.unpack(">BHHB", fh.read(6))
            return w, h, channels, max(1, bits // 8)
        fh.seek(length - 2, 1)


def _exr_header(data):
    """An OpenEXR file's size (its dataWindow) and channel count from its header bytes."""
    pos, window, channels = 8, None, 0
    while pos < len(data) and data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        name, kind = data[pos:name_end], data[name_end + 1:type_end]
        size = struct.unpack("<i", data[type_end + 1:type_end + 5])[0]
        value = data[type_end + 5:type_end + 5 + size]
        if name == b"dataWindow" and kind == b"box2i":
            x0, y0, x1, y1 = struct.unpack("<iiii", value)
            window = (x1 - x0 + 1, y1 - y0 + 1)
        elif name == b"channels":            # each: its name, \0, then 16 bytes
            at = 0
            while at < len(value) and value[at] != 0:
                at = value.index(b"\0", at) + 17
                channels += 1
        pos = type_end + 5 + size
    return None if window is None else (*window, max(1, min(4, channels)), 4)


def _read_exr(path):
    import OpenEXR
    try:
        with OpenEXR.File(path, separate_channels=True) as f:
            channels = {name: np.asarray(ch.pixels) for name, ch in f.channels().items()}
    except Exception as exc:  # the bindings raise plain Exceptions for corrupt files
        raise ImageReadError(f"{path}: not a readable OpenEXR file ({exc})") from None
    if not channels:
        raise ImageReadError(f"{path}: the EXR file has no channels")
    names = _pick_exr_channels(channels)
    px = np.stack([channels[c].astype(np.float32) for c in names], axis=-1)
    return ImageData(np.ascontiguousarray(px[::-1]), bits=32, name=os.path.basename(path))


def _pick_exr_channels(channels):
    """RGBA / RGB / Y(A) by name (layer prefixes allowed), else the first four in file order."""
    def find(suffix):
        hits = [c for c in channels if c == suffix or c.endswith("." + suffix)]
        return hits[0] if hits else None
    rgb = [find(c) for c in "RGB"]
    a = find("A")
    if all(rgb):
        return rgb + ([a] if a else [])
    y = find("Y") or find("Z") or find("V")
    if y:
        return [y] + ([a] if a else [])
    return sorted(channels)[:4]


@contextlib.contextmanager
def quiet_native(fd=2):
    """Silence what native code writes straight to file descriptor `fd` (Blender's image
    libraries' complaints on 2; its render log's "Video append frame" lines on 1), while
    Python's own sys.stdout / sys.stderr keep reaching the terminal: the command line says
    what happened in lines of its own."""
    stream = sys.stdout if fd == 1 else sys.stderr
    try:
        stream.flush()
        saved = os.dup(fd)
    except (OSError, ValueError, AttributeError):
        yield
        return
    keep = open(saved, "w", buffering=1, closefd=False, encoding="utf-8", errors="replace")
    swapped = {1: "stdout", 2: "stderr"}[fd]
    original = getattr(sys, swapped)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            setattr(sys, swapped, keep)
            yield
    finally:
        setattr(sys, swapped, original)
        keep.flush()
        keep.close()
        os.dup2(saved, fd)
        os.close(saved)


def _read_with_blender(path):
    import bpy
    # decoding happens lazily: keep the whole read quiet (Blender logs to stdout, its image
    # libraries complain on stderr; the error below says it in one line of ours)
    with quiet_native(1), quiet_native(2):
        try:
            img = bpy.data.images.load(path, check_existing=False)
        except RuntimeError as exc:
            raise ImageReadError(f"{path}: Blender cannot read it ({str(exc).strip()})") from None
        try:
            # Data, never colour-managed here: the core decodes sRGB itself (§0).
            img.colorspace_settings.name = "Non-Color"
            return image_data_from_blender(img, path)
        finally:
            bpy.data.images.remove(img)


def missing_file(img):
    """The file a Blender image is loaded from when that file is gone (moved, deleted since
    the .blend was saved), else ''."""
    path = bpy_path(img)
    return path if path and not os.path.isfile(path) else ""


def missing_file_message(what, path):
    """One line for an image whose file is gone, the same wherever it is found."""
    return (f"{what}: its file is missing: {path} (File › External Data › Find Missing "
            f"Files, or open it again)")


def image_data_from_blender(img, path=None):
    """A Blender image's pixels → ImageData, exactly what an Image Texture node samples.

    Byte images hold file values (bits 8; colour ones are sRGB-decoded by the core, as Blender
    does when sampling). Float buffers hold what Blender made of the file: linear values for
    colour-managed images, raw ones for Non-Color: bits 32, except the 16-bit PNG/TIFF files
    `read_image` loads as data (bits 16, for the core's sRGB decode and pre-blur default).
    path: the file `read_image` loaded `img` from, read once — its RGBA buffer is its own,
    freed with the read; an image Blender holds (path None) is read through the buffer kept
    for its next read (_read_buffer).
    """
    where = path or img.filepath or img.name
    w, h = img.size
    c = img.channels
    gone = missing_file(img) if path is None else ""
    if gone:
        raise ImageReadError(missing_file_message(img.name, gone))
    if w == 0 or h == 0 or not img.has_data or c == 0:
        raise ImageReadError(f"{where}: not an image Blender can read (unknown or corrupt format)")
    keep = file_channels(img)
    shared = keep < c and path is None
    px = _read_buffer(w * h * c) if shared else np.empty(w * h * c, dtype=np.float32)
    img.pixels.foreach_get(px)
    if not img.is_float:
        bits = 8
    elif path is not None and img.file_format in ("PNG", "TIFF"):
        bits = 16
    else:
        bits = 32
    px = px.reshape(h, w, c)   # Blender buffers are bottom row first: already y-up
    px = px[..., :1] if keep == 1 else px[..., :keep]
    name = os.path.basename(where)
    return ImageData(px.copy() if keep < c else px, bits=bits, name=name,
                     notes=cut_short_notes(path or bpy_path(img), px, name))


# The RGBA buffer a read copies its file's channels out of, kept for the next read: a live
# stroke reads the shape image per dab, and a fresh 268 MB buffer (4096²) made the kernel find
# huge pages each time — 50 ms a read, at times 400–600 ms (benchmarks/paint_latency.py).
# Kept up to READ_BUFFER_PX pixels (the largest painting that keeps its decode for edits;
# memory.add_bytes counts it); a file read once (read_image: the command line) does not keep
# it — 256 MiB at 4096² (benchmarks/memory.py).
_READ_BUFFER = [np.empty(0, np.float32)]


def _read_buffer(n):
    """n float32s to read a Blender image into and copy out of (not kept by the caller)."""
    if n > READ_BUFFER_PX * 4:
        return np.empty(n, np.float32)
    if _READ_BUFFER[0].size < n:
        _READ_BUFFER[0] = np.empty(n, np.float32)
    return _READ_BUFFER[0][:n]


def bpy_path(img):
    """The file a Blender image was read from ('' for a packed or generated one)."""
    if img.source != "FILE" or img.packed_file is not None:
        return ""
    import bpy
    return bpy.path.abspath(img.filepath, library=img.library)


def cut_short_notes(path, px, name):
    """A JPEG whose file stops before its end marker (a download or copy cut short) decodes
    with its missing rows filled in one grey: say how much of the picture holds data."""
    if not path or not os.path.isfile(path):
        return []
    with open(path, "rb") as fh:
        head = fh.read(2)
        fh.seek(max(0, os.path.getsize(path) - 64))
        tail = fh.read()
    if head != b"\xff\xd8" or b"\xff\xd9" in tail:
        return []
    # y-up: the file's last rows are the array's first; count the filled ones
    flat = np.all(px == px[:1, :1], axis=(1, 2))
    filled = int(np.argmin(flat)) if not flat.all() else len(flat)
    if filled == 0:
        return []
    return [f"{name}: the file is cut short (it ends before the JPEG's end marker): only the "
            f"top {1 - filled / len(flat):.0%} of the picture holds data, the rest is flat "
            f"grey; save or download it again"]


# Blender always hands out RGBA; its `depth` (bits per pixel) says what the file held.
# Measured on bpy 5.0.1: 8-bit grey 8, RGB 24, RGB(A)/grey+alpha 32; 16-bit grey 32 (float),
# RGB 96, RGBA 128. Grey+alpha comes back as RGBA with R = G = B, which reads the same.
FILE_CHANNELS = {(False, 8): 1, (False, 24): 3, (False, 32): 4,
                  (True, 32): 1, (True, 96): 3, (True, 128): 4}


def file_channels(img):
    """How many channels a Blender image's file held (its buffer always has four): grey 1,
    RGB 3, RGBA 4; generated and packed-from-memory images count their buffer."""
    if img.source == "FILE":
        return FILE_CHANNELS.get((img.is_float, img.depth), img.channels)
    return img.channels


def write_exr(path, pixels, channel_names=None):
    """Write a y-up float array (H, W) or (H, W, C) as a 32-bit float EXR (ZIP compressed)."""
    import OpenEXR
    px = np.asarray(pixels, dtype=np.float32)
    if px.ndim == 2:
        px = px[..., None]
    names = channel_names or {1: ["Y"], 2: ["Y", "A"], 3: list("RGB"), 4: list("RGBA")}[px.shape[2]]
    top_first = px[::-1]
    channels = {name: np.ascontiguousarray(top_first[..., i]) for i, name in enumerate(names)}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with written_whole(path) as part, OpenEXR.File(header, channels) as f:
        f.write(part)


def write_png(path, pixels, bits=8, level=6):
    """Write y-up values in 0..1 (already display-encoded) as an 8- or 16-bit PNG.

    (H, W) or (H, W, C) with C = 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA; level: zlib's (0, not
    compressed, for a file read back at once; 6 for one kept).
    """
    px = np.asarray(pixels)
    if px.ndim == 2:
        px = px[..., None]
    h, w, c = px.shape
    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[c]
    scale, dt = (255, ">u1") if bits == 8 else (65535, ">u2")
    flipped = px[::-1]                       # files store the top row first
    z = zlib.compressobj(level)
    data = []
    rows = max(1, (1 << 20) // max(1, w))    # quantize and compress in bands of rows
    for r in range(0, h, rows):
        band = np.asarray(flipped[r:r + rows], dtype=np.float64)
        q = np.round(np.clip(np.nan_to_num(band), 0, 1) * scale).astype(dt)
        data.append(z.compress(b"".join(b"\x00" + row.tobytes() for row in q)))
    data.append(z.flush())

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    ihdr = struct.pack(">IIBBBBB", w, h, bits, colour_type, 0, 0, 0)
    with written_whole(path) as part, open(part, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", b"".join(data))
                 + chunk(b"IEND", b""))


def write_render(path, rgba):
    """Write premultiplied linear RGBA: .exr as is (float), .png as 8-bit sRGB straight alpha."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".exr":
        write_exr(path, rgba)
    elif ext == ".png":
        out = np.empty(rgba.shape[:2] + (4,), np.float32)
        rows = max(1, (1 << 20) // max(1, rgba.shape[1]))     # bands: bounded temporaries
        for r in range(0, rgba.shape[0], rows):
            band = rgba[r:r + rows]
            a = band[..., 3:4]
            straight = np.where(a > 0, band[..., :3] / np.where(a > 0, a, 1), 0)
            out[r:r + rows, :, :3] = linear_to_srgb(straight)
            out[r:r + rows, :, 3:] = a
        write_png(path, out, bits=8)
    else:
        raise ImageWriteError(f"{path}: unsupported output format '{ext}' (use .png or .exr)")

