"""§2 shape decoding and the §14 rows about normals and height bit depth."""
import numpy as np
import pytest

from dynpaint_addon.core.sampling import gaussian_blur
from testkit.shapes import quantized_dome
from dynpaint_addon.core.shape import (decode_normal_map, default_preblur_px, finalize_normals,
                                       height_field_px, normals_from_height_px)


def test_degenerate_normals_become_finite_units_above_z_min():
    """§14: zero length, NaN, Inf, N.z ≤ 0 → finite unit normal with N.z ≥ z_min."""
    bad = np.array([[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 1], [0, 0, -1], [1, 0, -0.5],
                    [0.01, 0.01, 0.01], [1, 1, 0], [-np.inf, np.nan, np.inf]], np.float32)
    for z_min in (0.05, 0.3):
        n = finalize_normals(bad, z_min)
        assert np.all(np.isfinite(n))
        np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1, atol=1e-6)
        assert np.all(n[..., 2] >= z_min - 1e-6)
    n = finalize_normals(bad, 0.05)
    np.testing.assert_allclose(n[[0, 1, 2, 3, 5, 7]], [[0, 0, 1]] * 6)
    # pushed radially toward +z: the azimuth of (1, 0, −0.5) and (1, 1, 0) is kept
    assert n[4, 1] == 0 and n[4, 0] > 0 and n[4, 2] == pytest.approx(0.05)
    assert n[6, 0] == pytest.approx(n[6, 1]) and n[6, 2] == pytest.approx(0.05)


def test_normal_map_decode_renormalizes_and_flips_green():
    rgb = np.array([[[1.0, 0.5, 1.0], [0.5, 0.9, 0.7], [0.5, 0.5, 0.5]]], np.float32)
    n = decode_normal_map(rgb)
    np.testing.assert_allclose(n[0, 0], [np.sqrt(0.5), 0, np.sqrt(0.5)], atol=1e-6)
    np.testing.assert_allclose(n[0, 1], np.array([0, 0.8, 0.4]) / np.hypot(0.8, 0.4), atol=1e-6)
    np.testing.assert_allclose(n[0, 2], [0, 0, 1])          # mid-grey: fallback
    flipped = decode_normal_map(rgb, flip_green=True)
    assert flipped[0, 1, 1] == pytest.approx(-n[0, 1, 1])


def test_height_map_gradient_in_image_widths():
    """z = h·H; N = normalize(−h ∂H/∂x, −h ∂H/∂y, 1) with x in image widths."""
    w, h_img = 40, 30
    y, x = np.mgrid[0:h_img, 0:w].astype(np.float32)
    ramp = (x + 0.5) / w * 0.5 + (y + 0.5) / w * 0.25        # H rises 0.5 per image width in x
    for h in (0.1, 1.0):
        n = normals_from_height_px(height_field_px(ramp, h))
        expected = np.array([-0.5 * h, -0.25 * h, 1]) / np.linalg.norm([-0.5 * h, -0.25 * h, 1])
        np.testing.assert_allclose(n, np.broadcast_to(expected, n.shape), atol=1e-5)
    # the same relief at twice the resolution gives the same normals (units are image widths)
    y2, x2 = np.mgrid[0:2 * h_img, 0:2 * w].astype(np.float32)
    ramp2 = (x2 + 0.5) / (2 * w) * 0.5 + (y2 + 0.5) / (2 * w) * 0.25
    n1 = normals_from_height_px(height_field_px(ramp, 0.3))
    n2 = normals_from_height_px(height_field_px(ramp2, 0.3))
    np.testing.assert_allclose(n1[5, 5], n2[11, 11], atol=1e-5)


def test_height_pixels_without_neighbours_and_nan():
    n = normals_from_height_px(height_field_px(np.ones((1, 1), np.float32), 0.5))
    np.testing.assert_allclose(n, [[[0, 0, 1]]])
    z = height_field_px(np.array([[np.nan, 1.0], [np.inf, 0.5]], np.float32), 0.5)
    assert np.all(np.isfinite(z))


@pytest.mark.parametrize("bits", [8, 16, 32])
def test_height_bit_depth_error_and_preblur_default(bits):
    """§14: 8 vs 16 bit vs float height — documented error, pre-blur default per bit depth.

    A hemisphere of radius 0.4 image widths (height scale 0.4) lit at 45°: N·L against the
    exact sphere, inside 80% of its radius. 8-bit alone is poor; its default pre-blur of 1.5 px
    cuts the error several-fold; 16-bit and float need no blur.
    """
    size = 256
    exact, mask = quantized_dome(size, 32)
    hq, _ = quantized_dome(size, bits)
    light = np.array([1, 0, 1]) / np.sqrt(2)

    def mean_err(hgt, sigma):
        n = normals_from_height_px(height_field_px(hgt.astype(np.float32), 0.4, sigma))
        return float(np.mean(np.abs((n @ light - n_exact @ light)[mask])))
    n_exact = normals_from_height_px(height_field_px(exact.astype(np.float64), 0.4)).astype(np.float32)
    raw = mean_err(hq, 0.0)
    blurred = mean_err(hq, default_preblur_px(bits))
    if bits == 8:
        assert default_preblur_px(8) == 1.5
        assert raw > 0.005                 # terraced slopes
        assert blurred < raw / 4           # the default blur cuts it several-fold
    else:
        assert default_preblur_px(bits) == 0.0
        assert raw < 2e-4 and blurred == raw


def test_gaussian_blur_preserves_constants_and_mass():
    img = np.full((7, 9), 0.25, np.float32)
    for ext in ("wrap", "extend", "mirror"):
        np.testing.assert_allclose(gaussian_blur(img, 3.0, ext), img, atol=1e-6)
    spike = np.zeros((21, 21), np.float64)
    spike[10, 10] = 1
    assert gaussian_blur(spike, 2.0, "wrap").sum() == pytest.approx(1.0)


# -- other tools' normal-map conventions (issue 15) ------------------------------------------
from dynpaint_addon.core.inputs import normal_map_notes, normal_map_problem  # noqa: E402
from dynpaint_addon.core.shape import resolve_encoding, scale_tilt  # noqa: E402


def _unit_normals(rng, count, min_z=0.2):
    n = rng.normal(size=(count, 3))
    n[:, 2] = np.abs(n[:, 2]) + min_z
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def test_two_channel_maps_decode_to_the_same_normals():
    n = _unit_normals(np.random.default_rng(1), 400)[None]
    rg = np.concatenate([(n[..., :2] + 1) / 2, np.zeros(n.shape[:-1] + (1,))], -1)
    assert resolve_encoding(rg) == "rg" and resolve_encoding((n + 1) / 2) == "rgb"
    for encoding in ("auto", "rg"):
        np.testing.assert_allclose(decode_normal_map(rg, z_min=0.001, encoding=encoding), n,
                                   atol=1e-12)
    # blue ignored: whatever it holds
    rg[..., 2] = 0.7
    np.testing.assert_allclose(decode_normal_map(rg, z_min=0.001, encoding="rg"), n, atol=1e-12)


def test_strength_one_half_is_the_halving_decoder_exactly():
    from parity_recipes import doubled_tilts
    n = _unit_normals(np.random.default_rng(2), 400, min_z=0.05)[None]
    stored = doubled_tilts(n)                             # tilts up to ~174°: many face away
    assert np.mean(stored[..., 2] < 0) > 0.2
    decoder = stored + [0, 0, 1]
    decoder /= np.linalg.norm(decoder, axis=-1, keepdims=True)
    got = decode_normal_map((stored + 1) / 2, z_min=0.001, strength=0.5)
    np.testing.assert_allclose(got, decoder, atol=1e-12)
    np.testing.assert_allclose(got, n, atol=1e-12)
    # strength scales the angle: 0 is flat, 1 the map as it is
    np.testing.assert_array_equal(scale_tilt(n, 1.0), n)
    np.testing.assert_allclose(scale_tilt(n, 0.0), np.broadcast_to([0, 0, 1], n.shape),
                               atol=1e-15)


def test_convention_messages_name_the_setting_that_reads_the_map():
    n = _unit_normals(np.random.default_rng(3), 400)[None]
    rg = np.concatenate([(n[..., :2] + 1) / 2, np.zeros(n.shape[:-1] + (1,))], -1)
    assert normal_map_problem(rg, "x.png") is None            # auto: read as two-channel
    assert normal_map_problem(rg, "x.png", "rg") is None
    assert normal_map_problem(rg, "x.png", "rgb") is None     # explicit: obeyed, never refused
    notes = normal_map_notes(rg, "x.png", "rgb")
    assert "'auto' or 'rg' to read x, y" in notes[0] and "halves" not in " ".join(notes)
    assert any("two-channel" in note for note in normal_map_notes(rg, "x.png"))
    # a map for the halving decoder read at strength 1: its back-facing share, and the cure
    from parity_recipes import doubled_tilts
    halving = (doubled_tilts(_unit_normals(np.random.default_rng(4), 400, 0.05)[None]) + 1) / 2
    notes = normal_map_notes(halving, "h.png")
    assert len(notes) == 1 and "face away" in notes[0] and "strength 0.5" in notes[0]
    assert normal_map_notes(halving, "h.png", strength=0.5) == []


def test_back_facing_shares_count_only_opaque_pixels():
    rng = np.random.default_rng(5)
    n = _unit_normals(rng, 400)[None]
    back = n.copy()
    back[..., 2] *= -1                                       # all face away …
    px = np.concatenate([(np.concatenate([n, back], 1) + 1) / 2,
                         np.concatenate([np.ones((1, 400, 1)), np.zeros((1, 400, 1))], 1)], -1)
    assert normal_map_notes(px, "a.png") == []               # … but are transparent
    px[..., 400:, 3] = 1
    assert "50% of its opaque pixels" in normal_map_notes(px, "a.png", strength=1.0)[0]
    assert "face away in 50%" in normal_map_notes(px, "a.png")[0]   # auto: a halving map
    assert normal_map_problem(px[..., :3], "b.png") is None  # half away: usable, not refused
