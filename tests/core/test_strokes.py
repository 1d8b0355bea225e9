"""A stroke's edit decoded and baked again where it changed (issue 41, core/strokes.py,
crossings.sun_cos_theta_edited): after any sequence of strokes the shape and the cos-θ terms
equal those of the whole edited image."""
import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core import bake as core_bake, crossings, strokes
from dynpaint_addon.core.bake import bake, bake_edited
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.pipeline import shape_normals, shape_normals_edited
from dynpaint_addon.core.sampling import enlarged_box, resample_separable
from dynpaint_addon.core.shape import slopes_from_normals

SUNS = [Light("sun", v) for v in ((1, 0.3, 0.5), (-0.2, -1, 0.3), (0.05, 0.9, 1.2),
                                  (1, 0, 0.2), (0, 0, 1))]     # high, low, grazing, overhead


def _dome(n):
    y, x = (np.mgrid[0:n, 0:n] + 0.5) / n
    h = np.sqrt(np.clip(1 - ((x - 0.5) ** 2 + (y - 0.45) ** 2) / 0.12, 0, None))
    return np.dstack([h] * 3).astype(np.float32)


def _stroke(rng, px):
    """A dab of random size, depth and place (partly off the image at times)."""
    n = px.shape[0]
    r = rng.integers(1, 24)
    cy, cx = rng.integers(-8, n + 8, 2)
    # the cone reaches r px from its centre: only that box is computed (the whole image's
    # cone took longer than the edit it tests at 768²)
    y0, y1, x0, x1 = (max(0, cy - r), max(0, min(n, cy + r + 1)),
                      max(0, cx - r), max(0, min(n, cx + r + 1)))
    y, x = np.ogrid[y0:y1, x0:x1]
    cone = np.clip(1 - np.hypot(x - cx, y - cy) / r, 0, 1)[..., None]
    out = px.copy()
    part = out[y0:y1, x0:x1, :3]
    part[:] = np.clip(part + rng.uniform(-0.3, 0.3) * cone, 0, 1)
    return out


def _stroked(rng, img, p, shape, n):
    """`n` random strokes on a height map's image, each decoded from the decode before →
    (stroke number, the edited image, (its decode, normals' box, heights' box)) of those
    that changed a pixel."""
    for k in range(n):
        pixels = _stroke(rng, img.pixels)
        box = strokes.changed_box(img.pixels, pixels)
        img = ImageData(pixels, 16)
        if box is not None:
            edited = shape_normals_edited(img, p, shape, box)
            shape = edited[0]
            yield k, img, edited


def _carry(ts, lights, shape, normals_box, heights_box, whole, edited):
    """Each light's term `ts[i]` carried across an edit of a height map: re-traced by
    `edited`, or baked `whole` where that declines → how many were re-traced."""
    retraced = 0
    for i, light in enumerate(lights):
        t = edited(shape[0], light, 0.01, ts[i], normals_box, heights_box, heights_px=shape[1])
        retraced += t is not None
        ts[i] = t if t is not None else whole(shape[0], light, 0.01, heights_px=shape[1])
    return retraced


@pytest.mark.parametrize("preblur", [0.0, 1.5])
def test_random_strokes_on_a_height_map_equal_the_whole_decode_and_bake(preblur):
    """120 random strokes on a 160² height map, 5 suns (one straight up: baked whole): after
    each the edited decode equals the whole decode bit for bit, and the cos-θ terms carried
    from stroke to stroke equal whole bakes (checked every 20 strokes) within 1e-6. (A
    chain of 200 caught no fault that 120 do not: a stroke's rays left out fail at the first
    stroke, margins narrowed to nothing at neither length.)"""
    rng = np.random.default_rng(41)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale, p.shape.preblur = "height", 0.2, preblur
    img = ImageData(_dome(160), 16)
    shape = shape_normals(img, p)
    ts = [crossings.sun_cos_theta(shape[0], sun, 0.01, heights_px=shape[1]) for sun in SUNS]
    retraced = 0
    for k, img, (shape, normals_box, heights_box) in _stroked(rng, img, p, shape, 120):
        whole = shape_normals(img, p)
        assert np.array_equal(shape[0], whole[0]) and np.array_equal(shape[1], whole[1]), k
        retraced += _carry(ts, SUNS, shape, normals_box, heights_box,
                           crossings.sun_cos_theta, crossings.sun_cos_theta_edited)
        if k % 20 == 19:
            for sun, t in zip(SUNS, ts):
                full = crossings.sun_cos_theta(whole[0], sun, 0.01, heights_px=whole[1])
                assert np.abs(t - full).max() <= 1e-6, (k, sun.vector)
    assert retraced >= 90 * 4           # every sun but the overhead one re-traced


def test_random_strokes_on_a_normal_maps_slopes_equal_the_whole_bake():
    """A normal map's shadows along the ray (slopes, rebuilt heights run on along each row):
    60 strokes that tip the normals, re-traced from the normals' changed box, equal the whole
    bake within 1e-6."""
    rng = np.random.default_rng(7)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    n = shape_normals(ImageData(_dome(128), 16), p)[0]
    suns = SUNS[:3]
    ts = [crossings.sun_cos_theta(n, sun, 0.01, slopes=slopes_from_normals(n), reach=0.3)
          for sun in suns]
    for k in range(60):
        r0, c0 = rng.integers(0, 120, 2)
        after = n.copy()
        tip = rng.normal(0, 0.4, 3) * [1, 1, 0]
        part = after[r0:r0 + rng.integers(1, 12), c0:c0 + rng.integers(1, 12)]
        part += tip
        part /= np.linalg.norm(part, axis=-1, keepdims=True)
        box = strokes.changed_box(n, after)
        n = after
        for i, sun in enumerate(suns):
            ts[i] = crossings.sun_cos_theta_edited(n, sun, 0.01, ts[i], box, None,
                                                   slopes=slopes_from_normals(n), reach=0.3)
    for sun, t in zip(suns, ts):
        full = crossings.sun_cos_theta(n, sun, 0.01, slopes=slopes_from_normals(n), reach=0.3)
        assert np.abs(t - full).max() <= 1e-6, sun.vector


def test_a_stroke_re_traces_a_small_part_of_the_image():
    """What the saving rests on: a dab of radius 16 at 512² under a sun re-traces few rays —
    the bake's pixels outside the rays that read the dab are the ones before (untouched),
    the dab's shadow changes downlight of it only."""
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    img = ImageData(_dome(512), 16)
    shape = shape_normals(img, p)
    sun = Light("sun", (1, 0.2, 0.6))
    t = crossings.sun_cos_theta(shape[0], sun, 0.01, heights_px=shape[1])
    pixels = img.pixels.copy()
    y, x = np.ogrid[0:512, 0:512]
    pixels[..., :3] += 0.3 * np.clip(1 - np.hypot(x - 300, y - 200) / 16, 0, 1)[..., None]
    edited = ImageData(pixels, 16)
    shape2, nb, hb = shape_normals_edited(edited, p, shape, strokes.changed_box(img.pixels,
                                                                                 pixels))
    t2 = bake_edited(shape2[0], sun, 0.01, "final", t, nb, hb, heights_px=shape2[1])
    changed = np.argwhere(t2 != t)
    assert changed.size and changed[:, 1].max() <= 300 + 20          # downlight (−x) of it
    assert np.abs(t2 - bake_edited(shape2[0], sun, 0.01, "final", t, strokes.whole(512, 512),
                                   strokes.whole(512, 512), heights_px=shape2[1])).max() <= 1e-6
    # a reduced level with no reduced bake kept for t, and a point light whose foot is over
    # the dab (every row of its grid reads it), are baked whole
    assert bake_edited(shape2[0], sun, 0.01, "draft", t, nb, hb, heights_px=shape2[1]) is None
    over = Light("point", (300 / 512 - 0.5, (200 - 256) / 512, 0.5))
    assert bake_edited(shape2[0], over, 0.01, "final", t, nb, hb, heights_px=shape2[1]) is None


# point lights (x, y, z in image widths from the centre): foot inside the image (its grid
# a full circle), beside it, low and far; the strokes pass under the first at times
POINTS = [Light("point", v) for v in ((0.1, -0.05, 0.4), (0.9, 0.6, 0.3), (-0.3, 1.2, 0.15))]


def test_random_strokes_under_point_lights_equal_the_whole_bake():
    """Issue 61: a dab under a point light re-traces the rays at the angles about its foot
    that see the dab (crossings.point_cos_theta_edited): 60 random strokes on a 160² height
    map, three point lights, carried from stroke to stroke, equal whole bakes (checked every
    10 strokes) within 1e-6; a stroke under a light's foot bakes that light whole."""
    rng = np.random.default_rng(61)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    img = ImageData(_dome(160), 16)
    shape = shape_normals(img, p)
    ts = [crossings.point_cos_theta(shape[0], light, 0.01, heights_px=shape[1])
          for light in POINTS]
    retraced = 0
    for k, img, (shape, nb, hb) in _stroked(rng, img, p, shape, 60):
        retraced += _carry(ts, POINTS, shape, nb, hb, crossings.point_cos_theta,
                           crossings.point_cos_theta_edited)
        if k % 10 == 9:
            for light, t in zip(POINTS, ts):
                full = crossings.point_cos_theta(shape[0], light, 0.01, heights_px=shape[1])
                assert np.abs(t - full).max() <= 1e-6, (k, light.vector)
    assert retraced >= 0.8 * 3 * 50


def test_a_dab_under_a_point_light_re_traces_its_wedge_only():
    """The rays that can read a dab are those at its angles about the light's foot, farther
    from the foot than the dab: every pixel the edit changed lies in that wedge (and the
    whole bake's equal), and the edit costs a fraction of the whole bake's rays."""
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    img = ImageData(_dome(256), 16)
    shape = shape_normals(img, p)
    light = Light("point", (-0.3, -0.2, 0.3))            # foot at (51, 77) px
    t = crossings.point_cos_theta(shape[0], light, 0.01, heights_px=shape[1])
    pixels = img.pixels.copy()
    y, x = np.ogrid[0:256, 0:256]
    pixels[..., :3] += 0.3 * np.clip(1 - np.hypot(x - 150, y - 140) / 10, 0, 1)[..., None]
    shape2, nb, hb = shape_normals_edited(ImageData(pixels, 16), p, shape,
                                          strokes.changed_box(img.pixels, pixels))
    t2 = crossings.point_cos_theta_edited(shape2[0], light, 0.01, t, nb, hb,
                                          heights_px=shape2[1])
    assert np.abs(t2 - crossings.point_cos_theta(shape2[0], light, 0.01,
                                                 heights_px=shape2[1])).max() <= 1e-6
    rows, cols = np.nonzero(t2 != t)
    assert rows.size > 50
    fx, fy = light.position_px(256, 256)[:2]
    angle = np.arctan2(rows + 0.5 - fy, cols + 0.5 - fx) - np.arctan2(140 - fy, 150 - fx)
    assert np.abs(angle).max() < 0.15                    # the dab's 10 px at ~120 px: ±0.08
    assert np.hypot(rows + 0.5 - fy, cols + 0.5 - fx).min() > 120 - 15


def test_random_strokes_on_a_normal_maps_slopes_under_a_point_light_equal_the_whole_bake():
    """A normal map along the ray under a point light: 30 strokes tipping the normals,
    re-traced from the normals' box (rebuilt heights run on along the whole row), equal the
    whole bake within 1e-6."""
    rng = np.random.default_rng(9)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    n = shape_normals(ImageData(_dome(128), 16), p)[0]
    light = POINTS[1]
    t = crossings.point_cos_theta(n, light, 0.01, slopes=slopes_from_normals(n), reach=0.3)
    for k in range(30):
        r0, c0 = rng.integers(0, 120, 2)
        after = n.copy()
        part = after[r0:r0 + rng.integers(1, 12), c0:c0 + rng.integers(1, 12)]
        part += rng.normal(0, 0.4, 3) * [1, 1, 0]
        part /= np.linalg.norm(part, axis=-1, keepdims=True)
        box = strokes.changed_box(n, after)
        n = after
        t = crossings.point_cos_theta_edited(n, light, 0.01, t, box, None,
                                             slopes=slopes_from_normals(n), reach=0.3)
    full = crossings.point_cos_theta(n, light, 0.01, slopes=slopes_from_normals(n), reach=0.3)
    assert np.abs(t - full).max() <= 1e-6


@pytest.mark.parametrize("size", [512, 768])
@pytest.mark.parametrize("quality", ["draft", "preview"])
def test_a_shape_edited_in_place_is_baked_from_its_edit_at_every_level(size, quality):
    """Issue 61 (drafts that never followed the brush): a draft's or preview's whole bake
    reads the shape's reduction kept for its arrays (bake.reduced_inputs); an edit into
    those very arrays (in_place) drops it, so the next bake, sun or point light, at a whole
    factor smaller (768²) or not (512² draft: 96²), equals that of a fresh decode of the
    edited image."""
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    img = ImageData(_dome(size), 16)
    shape = shape_normals(img, p)
    lights = [SUNS[0], POINTS[1]]
    before = [bake(shape[0], light, 0.01, quality, heights_px=shape[1]) for light in lights]
    pixels = img.pixels.copy()
    y, x = np.ogrid[0:size, 0:size]
    pixels[..., :3] += 0.4 * np.clip(1 - np.hypot(x - size / 3, y - size / 2) / 40, 0, 1)[..., None]
    edited = ImageData(pixels, 16)
    patched, _, _ = shape_normals_edited(edited, p, shape, strokes.changed_box(img.pixels,
                                                                                pixels),
                                         in_place=True)
    assert patched[0] is shape[0]
    fresh = shape_normals(edited, p)
    for light, t in zip(lights, before):
        got = bake(patched[0], light, 0.01, quality, heights_px=patched[1])
        want = bake(fresh[0], light, 0.01, quality, heights_px=fresh[1])
        assert np.abs(got - want).max() <= 1e-6, light.kind
        assert np.abs(want - t).max() > 0.1             # (the dab casts a shadow)


@pytest.mark.parametrize("quality", ["draft", "preview"])
def test_random_strokes_at_a_reduced_level_equal_its_whole_bake(quality):
    """The draft and preview levels bake a sun by crossings at a whole factor smaller (768²:
    96², 192²): 30 random strokes, each baked from the last bake (the reduced inputs patched
    where the stroke reaches them, the reduced rays that read it traced again), equal the
    level's whole bake of the edited shape within 1e-6 after each of them."""
    rng = np.random.default_rng(5)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.2
    img = ImageData(_dome(768), 16)
    shape = shape_normals(img, p)
    suns = SUNS[:2]
    ts = [bake(shape[0], sun, 0.01, quality, heights_px=shape[1]) for sun in suns]
    for k, img, (shape, nb, hb) in _stroked(rng, img, p, shape, 30):
        for i, sun in enumerate(suns):
            t = bake_edited(shape[0], sun, 0.01, quality, ts[i], nb, hb, heights_px=shape[1])
            assert t is not None, (k, i)
            whole = bake(shape[0], sun, 0.01, quality, heights_px=shape[1])
            assert np.abs(t - whole).max() <= 1e-6, (k, sun.vector)
            ts[i] = t


def test_boxes():
    a = np.zeros((6, 5, 4), np.float32)
    b = a.copy()
    assert strokes.changed_box(a, b) is None
    b[1, 2, 3] = np.nan
    assert strokes.changed_box(a, b) == (1, 2, 2, 3)
    assert strokes.changed_box(b, b.copy()) is None          # a NaN left as it was
    assert strokes.changed_box(a, a[:3]) is None             # (sizes differ: not a box)
    assert strokes.union(None, (1, 2, 3, 4), (0, 1, 5, 6)) == (0, 2, 3, 6)
    assert strokes.grow((1, 2, 3, 4), 2.2, 5, 5) == (0, 5, 0, 5)


def test_an_enlarged_image_redone_where_an_edit_reads_equals_the_whole():
    """enlarged_box (a stroke's draft written again only where it changed, issue 42): the
    enlarged image with that box resampled again from the edited small one is the whole
    enlargement of it, bit for bit, for whole and other factors."""
    rng = np.random.default_rng(7)
    for small, big in [((24, 32), (192, 256)), ((31, 17), (100, 40)), ((9, 9), (9, 27))]:
        img = rng.random(small + (4,)).astype(np.float32)
        out = resample_separable(img, *big)
        for _ in range(20):
            r0, c0 = rng.integers(0, small[0]), rng.integers(0, small[1])
            box = (r0, min(small[0], r0 + rng.integers(1, 4)), c0,
                   min(small[1], c0 + rng.integers(1, 4)))
            img = img.copy()
            img[box[0]:box[1], box[2]:box[3]] = rng.random((box[1] - box[0], box[3] - box[2], 4))
            b0, b1, b2, b3 = again = enlarged_box(box, small, big)
            out[b0:b1, b2:b3] = resample_separable(img, *big, again)
            assert np.array_equal(out, resample_separable(img, *big))


def test_an_edited_reduced_bake_upsamples_only_what_changed_and_equals_the_whole():
    """_upsampled(before=) (core/bake.py): after an edit of a reduced bake's t only the full-size
    pixels that read a changed reduced pixel are upsampled again (a 4096² draft's dab: 11 ms,
    not 190–370 ms); the same array as upsampling the whole, bit for bit, for random edits
    and for none."""
    rng = np.random.default_rng(7)
    t_s = rng.random((48, 40)).astype(np.float32)
    t = core_bake._upsampled(t_s, 384, 320, np.float32)
    for _ in range(20):
        edited = t_s.copy()
        r, c = rng.integers(0, 44), rng.integers(0, 36)
        edited[r:r + rng.integers(0, 5), c:c + rng.integers(0, 5)] = rng.random()
        got = core_bake._upsampled(edited, 384, 320, np.float32, before=(t_s, t))
        assert np.array_equal(got, core_bake._upsampled(edited, 384, 320, np.float32))
        t_s, t = edited, got


def test_a_decode_edited_in_place_equals_one_into_copies_and_copies_leave_the_old_alone():
    """in_place (nothing else reads the decode before: shadow_images' _READING): 40 strokes
    decoded into the arrays before equal those decoded into copies bit for bit, with the same
    changed boxes; into copies, the decode before is left as it was (a live bake's worker
    reads it)."""
    rng = np.random.default_rng(5)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale, p.shape.preblur = "height", 0.2, 1.5
    img = ImageData(_dome(96), 16)
    copied, patched = shape_normals(img, p), shape_normals(img, p)
    for k in range(40):
        pixels = _stroke(rng, img.pixels)
        box = strokes.changed_box(img.pixels, pixels)
        img = ImageData(pixels, 16)
        if box is None:
            continue
        old = [a.copy() for a in copied[:2]]
        a = shape_normals_edited(img, p, copied, box)
        assert all(np.array_equal(x, y) for x, y in zip(old, copied[:2])), k
        b = shape_normals_edited(img, p, patched, box, in_place=True)
        assert b[0][0] is patched[0] and b[0][1] is patched[1], k
        assert a[1:] == b[1:] and all(np.array_equal(x, y) for x, y in zip(a[0][:2], b[0][:2]))
        copied, patched = a[0], b[0]


def test_changed_box_reads_channels_and_strided_views_as_the_pixels_they_are():
    """changed_box compares bit patterns in place: one channel of an RGBA buffer (a strided
    view), every channel of an RGBA image, a NaN left as it was (unchanged)."""
    rng = np.random.default_rng(2)
    rgba = rng.random((30, 40, 4)).astype(np.float32)
    rgba[3, 4, 1] = np.nan
    grey = rgba[..., 0].copy()
    grey[7:9, 20:25] += 1
    assert strokes.changed_box(rgba[..., 0], grey) == (7, 9, 20, 25)
    after = rgba.copy()
    assert strokes.changed_box(rgba, after) is None
    after[12, 33, 2] = 0.0
    after[25, 1, 3] = 2.0
    assert strokes.changed_box(rgba, after) == (12, 26, 1, 34)
    assert strokes.changed_box(rgba[..., 2:3], after[..., 2:3]) == (12, 13, 33, 34)
