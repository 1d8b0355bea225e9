"""Image files: EXR through OpenEXR, PNG through Blender's loader; row order handled once."""
import bpy
import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.inputs import imageio
from dynpaint_addon.inputs.imageio import (ImageReadError, image_data_from_blender, read_image,
                                           write_exr, write_png)


def test_exr_round_trip_multichannel_float32(tmp_path, rng):
    for c in (1, 2, 3, 4):
        px = rng.normal(size=(5, 7, c)).astype(np.float32) * 100
        px[0, 0, 0] = np.inf
        path = str(tmp_path / f"x{c}.exr")
        write_exr(path, px)
        back = read_image(path)
        assert back.bits == 32 and back.pixels.dtype == np.float32
        np.testing.assert_array_equal(back.pixels, px)


@pytest.mark.parametrize("bits", [8, 16])
@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_png_round_trip_through_blender(tmp_path, rng, bits, channels):
    px = rng.uniform(0, 1, (6, 9, channels))
    path = str(tmp_path / "x.png")
    write_png(path, px, bits)
    back = read_image(path)
    q = 2 ** bits - 1
    assert back.bits == bits
    expected = np.round(px * q) / q
    if channels == 2:                       # Blender hands grey+alpha back as RGBA
        np.testing.assert_allclose(back.grey(), expected[..., 0], atol=1e-6)
        np.testing.assert_allclose(back.alpha(), expected[..., 1], atol=1e-6)
    else:
        assert back.pixels.shape == (6, 9, channels)
        np.testing.assert_allclose(back.pixels, expected, atol=1e-6)


def test_files_store_the_top_row_first(tmp_path):
    """§0: a y-up array written and read back is unchanged, and the file's first row is the top."""
    px = np.zeros((4, 3), np.float32)
    px[3] = 1.0                              # top row (y up: the last array row)
    write_png(str(tmp_path / "t.png"), px)
    import zlib
    data = (tmp_path / "t.png").read_bytes()
    raw = zlib.decompress(data[data.index(b"IDAT") + 4:])
    assert raw[1:4] == b"\xff\xff\xff" and raw[5:8] == b"\x00\x00\x00"
    np.testing.assert_array_equal(read_image(str(tmp_path / "t.png")).pixels[..., 0], px)
    write_exr(str(tmp_path / "t.exr"), px)
    np.testing.assert_array_equal(read_image(str(tmp_path / "t.exr")).pixels[..., 0], px)


def test_colour_images_are_decoded_from_srgb_data_are_not(tmp_path):
    """§0: an 8-bit mid-grey colour image shades as linear 0.214; an EXR colour image as is."""
    shape = ImageData(np.tile(np.array([0.5, 0.5, 1.0], np.float32), (2, 2, 1)), 8)
    p = params.defaults()
    dark = np.full((2, 2, 3), 0.5, np.float32)
    out = render({"shape": shape, "dark": ImageData(dark, 8)}, [Light("sun", (0, 0, 1))], p).rgba
    assert out[0, 0, 0] == pytest.approx(0.2140, abs=1e-4)
    out = render({"shape": shape, "dark": ImageData(dark, 32)}, [Light("sun", (0, 0, 1))], p).rgba
    assert out[0, 0, 0] == pytest.approx(0.5)


def test_bad_files_give_clear_errors(tmp_path):
    with pytest.raises(ImageReadError, match="file not found"):
        read_image(str(tmp_path / "missing.png"))
    (tmp_path / "text.png").write_text("this is not an image")
    with pytest.raises(ImageReadError, match="text.png: not an image Blender can read"):
        read_image(str(tmp_path / "text.png"))
    (tmp_path / "empty.png").write_bytes(b"")
    with pytest.raises(ImageReadError, match="empty"):
        read_image(str(tmp_path / "empty.png"))
    (tmp_path / "broken.exr").write_bytes(b"\x76\x2f\x31\x01" + b"\x00" * 40)
    with pytest.raises(ImageReadError, match="broken.exr: not a readable OpenEXR file"):
        read_image(str(tmp_path / "broken.exr"))
    with pytest.raises(ImageReadError, match="is a folder"):
        read_image(str(tmp_path))


@pytest.mark.parametrize("fmt,ext,depth", [("JPEG", "jpg", "8"), ("TIFF", "tif", "8"), ("TIFF", "tif", "16")])
def test_jpeg_and_tiff_through_blender(tmp_path, fmt, ext, depth):
    """JPEG and 8/16-bit TIFF written by Blender read back y-up with their bit depth."""
    img = bpy.data.images.new("t", 8, 6, alpha=False, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    px = np.zeros((6, 8, 4), np.float32)
    px[..., 3] = 1
    px[3:, :, 0] = 1.0                       # top half red
    px[:, :4, 1] = 0.5                       # left half half-green
    img.pixels.foreach_set(px.ravel())
    settings = bpy.context.scene.render.image_settings
    settings.file_format, settings.color_mode = fmt, "RGB"
    if fmt == "TIFF":
        settings.color_depth = depth
    path = str(tmp_path / f"x.{ext}")
    img.save_render(path)
    bpy.data.images.remove(img)
    back = read_image(path)
    assert back.bits == int(depth) and back.pixels.shape == (6, 8, 3)
    tol = 0.02 if fmt == "JPEG" else 1 / 255
    np.testing.assert_allclose(back.pixels[0, 0], [0, 0.5, 0], atol=tol)    # bottom-left
    np.testing.assert_allclose(back.pixels[5, 7], [1, 0, 0], atol=tol)      # top-right


def test_reads_that_keep_fewer_channels_than_blender_holds_do_not_share_their_pixels(tmp_path,
                                                                                     rng,
                                                                                     monkeypatch):
    """image_data_from_blender reads an image Blender holds (a grey or RGB file's RGBA
    buffer) into one buffer it keeps for the next read (a stroke reads the shape each dab):
    what it returns is a copy, so one read's pixels stay as they were after the next (even a
    1 × 1 image's). A file read_image reads once keeps no buffer (the command line: 256 MiB
    at 4096²)."""
    monkeypatch.setattr(imageio, "_READ_BUFFER", [np.empty(0, np.float32)])   # none kept yet
    reads = []
    for i, (h, w, c) in enumerate([(6, 9, 1), (4, 5, 3), (1, 1, 1), (7, 3, 1)]):
        px = rng.uniform(0, 1, (h, w, c))
        write_png(str(tmp_path / f"{i}.png"), px, 16)
        img = bpy.data.images.load(str(tmp_path / f"{i}.png"))
        img.colorspace_settings.name = "Non-Color"
        reads.append((np.round(px * 65535) / 65535, image_data_from_blender(img)))
    assert imageio._READ_BUFFER[0].size == 9 * 6 * 4          # the largest read's RGBA
    for want, got in reads:
        assert got.pixels.flags.c_contiguous
        np.testing.assert_allclose(got.pixels, want, atol=1e-6)
    write_png(str(tmp_path / "large.png"), rng.uniform(0, 1, (40, 30, 1)), 16)
    once = read_image(str(tmp_path / "large.png"))
    assert once.pixels.flags.c_contiguous and once.pixels.shape == (40, 30, 1)
    assert imageio._READ_BUFFER[0].size == 9 * 6 * 4          # not grown by a file read once
