"""Writers for image files the project never makes itself but artists have: palette PNGs and
CMYK TIFFs (tests feed them to the add-on and the command line)."""
import struct
import zlib

import numpy as np


def _chunk(tag, data):
    return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))


def write_palette_png(path, index_rows, palette_rgb):
    """An 8-bit palette PNG (colour type 3). index_rows: (H, W) uint8 indices, top row first;
    palette_rgb: (N, 3) uint8."""
    idx = np.asarray(index_rows, np.uint8)
    h, w = idx.shape
    raw = b"".join(b"\x00" + row.tobytes() for row in idx)
    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n"
                 + _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 3, 0, 0, 0))
                 + _chunk(b"PLTE", np.asarray(palette_rgb, np.uint8).tobytes())
                 + _chunk(b"IDAT", zlib.compress(raw)) + _chunk(b"IEND", b""))


def write_cmyk_tiff(path, cmyk_rows):
    """An uncompressed 8-bit CMYK TIFF (PhotometricInterpretation 5, InkSet CMYK).
    cmyk_rows: (H, W, 4) uint8, top row first."""
    px = np.ascontiguousarray(np.asarray(cmyk_rows, np.uint8))
    h, w, _ = px.shape
    data = px.tobytes()
    entries = [  # tag, type (3 SHORT, 4 LONG), count, value
        (256, 4, 1, w), (257, 4, 1, h), (258, 3, 4, None), (259, 3, 1, 1), (262, 3, 1, 5),
        (273, 4, 1, None), (277, 3, 1, 4), (278, 4, 1, h), (279, 4, 1, len(data)),
        (284, 3, 1, 1), (332, 3, 1, 1)]
    ifd_offset = 8
    ifd_size = 2 + 12 * len(entries) + 4
    bits_offset = ifd_offset + ifd_size
    data_offset = bits_offset + 8
    out = bytearray(b"II*\x00" + struct.pack("<I", ifd_offset))
    out += struct.pack("<H", len(entries))
    for tag, typ, count, value in entries:
        if tag == 258:
            value = bits_offset
        elif tag == 273:
            value = data_offset
        if typ == 3 and count == 1:
            out += struct.pack("<HHIHH", tag, typ, count, value, 0)
        else:
            out += struct.pack("<HHII", tag, typ, count, value)
    out += struct.pack("<I", 0)
    out += struct.pack("<4H", 8, 8, 8, 8)
    out += data
    with open(path, "wb") as fh:
        fh.write(bytes(out))
