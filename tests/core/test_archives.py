"""OpenRaster files that would spend disk and memory are refused before a byte is unpacked
(issue 60): a stack.xml or a layer that deflates to far more than it could hold, a canvas of
no picture's size. Numbers from the archive's own directory, checked first."""
import struct
import zipfile
import zlib

import pytest

from dynpaint_addon.inputs.layered_files import LayeredFileError, read_ora

STACK = ('<image w="{w}" h="{h}"><stack><layer name="figure" src="data/figure.png"/>'
         '</stack></image>')


def png_head(w, h):
    """A PNG's signature and IHDR chunk (8-bit RGBA) — what the size check reads."""
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + ihdr +
            struct.pack(">I", zlib.crc32(b"IHDR" + ihdr)))


def ora(path, stack, png=png_head(8, 8)):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("mimetype", "image/openraster")
        z.writestr("stack.xml", stack)
        z.writestr("data/figure.png", png)
    return str(path)


def test_a_stack_xml_bomb_is_refused_unread(tmp_path):
    path = ora(tmp_path / "a.ora", STACK.format(w=8, h=8) + " " * (8 << 20))
    with pytest.raises(LayeredFileError, match="stack.xml unpacks to 8 MiB"):
        read_ora(path)


def test_a_layer_that_unpacks_past_its_size_is_refused_unread(tmp_path):
    path = ora(tmp_path / "b.ora", STACK.format(w=8, h=8), png_head(64, 64) + bytes(64 << 20))
    with pytest.raises(LayeredFileError, match="more than a 64×64 PNG can hold"):
        read_ora(path)


@pytest.mark.parametrize("w, h", [(1000000000, 8), (-5, 8), (0, 0)])
def test_a_canvas_of_no_pictures_size_is_refused(tmp_path, w, h):
    with pytest.raises(LayeredFileError, match="not a picture's size"):
        read_ora(ora(tmp_path / "c.ora", STACK.format(w=w, h=h)))
