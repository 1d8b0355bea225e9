"""The files artists already have (issue 59), without Blender: a colour sprite beside its normal
map named as each tool names it, lit as an albedo (§1, amended 2026-11-29) and cut out by its
own alpha; the map's green read the way it fits; a rim blended with black kept from becoming a
cliff; texture atlases read as the frames they list."""
import json

import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.colour import srgb_to_linear
from dynpaint_addon.core.cut_out import cut_out_pixels, needs_cleaning
from dynpaint_addon.core.input_rules import ImageData, input_notes, relief_guess
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.map_convention import green_reading
from dynpaint_addon.core.pipeline import render, shape_normals
from dynpaint_addon.inputs.atlas import AtlasError, AtlasFrame, atlas_in, cut_frame, parse_atlas
from dynpaint_addon.inputs.painting_folder import kind_of_names, painting_channels
from dynpaint_addon.inputs.sprite_files import map_suffix, sprite_pairs
from testkit.sprite_sets import encode, figure

SUN = Light("sun", (-0.45, 0.5, 0.74), (1.0, 1.0, 1.0), 1.0, "Key")


@pytest.mark.parametrize("colour, normal, kind", [
    ("knight.png", "knight_n.png", "normal"),           # SpriteIlluminator, Laigter, Godot
    ("knight.png", "knight-n.png", "normal"),           # Phaser's examples
    ("knight.png", "knight_Normal.png", "normal"),      # Sprite Lamp, Unity
    ("knight.png", "knightNormal.png", "normal"),       # camelCase
    ("knight.png", "knight_normalmap.png", "normal"),
    ("knight.png", "knight_Depth.png", "height"),       # Sprite Lamp's depth map
    ("knight.png", "knightn.png", ""),                  # a word, not a suffix
    ("knight.png", "knight_s.png", ""),                 # Laigter's specular map
    ("knight_Diffuse.png", "knight_Normal.png", "normal"),  # Sprite Lamp: siblings of a stem
    ("hero_d.png", "hero_n.png", "normal"),             # an engine's _d / _n
    ("StoneWall_Diffuse.png", "StoneWall_NormalDepth.png", "normal"),   # its depth in alpha
    ("wall_d.png", "wall_nh.png", "normal"),            # the Daemon engine's normal + height
    ("hero_d.png", "hero_dn.png", ""),
])
def test_a_map_is_known_by_its_name_beside_its_sprite(colour, normal, kind):
    assert map_suffix(colour, normal) == kind


def test_a_sprite_and_its_map_are_one_painting_whatever_their_words_say():
    # "foreground" names the reflection image, but beside its own map it is the painting
    channels, rest, why = painting_channels(["foreground_01.png", "foreground_01_n.png"])
    assert channels == {"shape": "foreground_01_n.png", "bright": "foreground_01.png"}
    assert "named as foreground_01.png's map" in why["images.bright"] and rest == []
    assert kind_of_names(["foreground_01.png", "foreground_01_n.png"]) == "painting"
    # Laigter's other maps are not used, and said so
    _, rest, _ = painting_channels(["k.png", "k_n.png", "k_o.png", "k_p.png"])
    assert rest == ["k_o.png", "k_p.png"]
    # an unnamed colour image beside a dark one and a map is the bright image
    channels, _, _ = painting_channels(["pear.png", "pear_normal.png", "pear_dark.png"])
    assert channels == {"shape": "pear_normal.png", "bright": "pear.png", "dark": "pear_dark.png"}
    channels, _, _ = painting_channels(["face.png", "face_shape.png", "face_dark.png"])
    assert channels["bright"] == "face.png"


def test_sprite_lamps_maps_share_the_sprites_stem():
    # Sprite Lamp names the colour image by its profile (_Diffuse) and saves its maps beside it
    channels, rest, _ = painting_channels(["knight_AmbientOcclusion.png", "knight_Depth.png",
                                           "knight_Diffuse.png", "knight_Normal.png"])
    assert channels == {"shape": "knight_Normal.png", "bright": "knight_Diffuse.png"}
    assert sorted(rest) == ["knight_AmbientOcclusion.png", "knight_Depth.png"]   # said unused


def test_an_alpha_opaque_everywhere_cuts_no_figure_out():
    """Many tools save every map as RGBA: an alpha that covers every pixel is a full-frame map,
    whose shadows fall along the ray (integrated, its one cut would be the frame's edge)."""
    n, cov, _ = sprite(32)
    opaque = ImageData(np.dstack([encode(n), np.ones_like(cov)]).astype(np.float32), 8, "w.png")
    cut = ImageData(np.dstack([encode(n), cov]).astype(np.float32), 8, "k.png")
    relief, why = relief_guess(opaque, "w.png")
    assert relief == "along_ray" and "covers every pixel" in why
    assert relief_guess(cut, "k.png") == (None, "")
    assert relief_guess(ImageData(encode(n).astype(np.float32)), "n.png") == (None, "")
    p = params.defaults()
    p.shadows.enabled = True
    colour = ImageData(np.ones((32, 32, 3), np.float32))
    notes = input_notes({"shape": opaque, "bright": colour}, p)
    assert any('set shadows.relief = "along_ray"' in x for x in notes), notes
    assert not any("covers every pixel" in x for x in input_notes({"shape": cut,
                                                                   "bright": colour}, p))


def test_numbered_pairs_are_frames():
    names = [f"{i:02d}{s}.png" for i in range(1, 9) for s in ("", "_n")]
    found = sprite_pairs(names)
    assert (found.colour, found.shape, found.frames) == ("##.png", "##_n.png", 8)
    assert found.first_shape == "01_n.png"
    unpadded = sprite_pairs([f"walk{i}{s}.png" for i in range(1, 12) for s in ("", "_n")])
    assert (unpadded.colour, unpadded.shape) == ("walk#.png", "walk#_n.png")
    # two unrelated sprites are no sequence
    assert sprite_pairs(["a.png", "a_n.png", "b.png", "b_n.png"]).frames == 0


def sprite(size=48, alpha=True):
    n, cov = figure(size, [(0.5, 0.5, 0.35, 0.3, 0.2)])
    colour = np.dstack([np.full((size, size), 0.8), np.full((size, size), 0.5),
                        np.full((size, size), 0.3)] + ([cov] if alpha else []))
    return n, cov, ImageData(colour.astype(np.float32), 8, "sprite.png")


def test_one_colour_image_is_lit_as_an_albedo_and_cut_out_by_its_alpha():
    n, cov, colour = sprite()
    shape = ImageData(encode(n).astype(np.float32), 16, "sprite_n.png")
    p = params.defaults()
    result = render({"shape": shape, "bright": colour}, [SUN], p, np.float64)
    a, w = srgb_to_linear(colour.pixels[..., :3].astype(np.float64)), result.passes["W"]
    want = a * (0.2 + 0.8 * w)
    inside = cov > 0.999
    np.testing.assert_allclose(result.rgba[..., :3][inside], want[inside], atol=1e-6)
    assert w[inside].std() > 0.1                     # the light follows the shape
    np.testing.assert_allclose(result.rgba[..., 3], cov, atol=1e-6)   # the sprite's alpha
    note = [x for x in input_notes({"shape": shape, "bright": colour}, p) if "albedo" in x]
    assert note and "colour × (0.2 + 0.8 × light)" in note[0]
    p.diffuse.ambient = 1.0                          # flat only where the artist asks
    flat = render({"shape": shape, "bright": colour}, [SUN], p, np.float64)
    np.testing.assert_allclose(flat.rgba[..., :3][inside], a[inside], atol=1e-6)
    assert any("drawn flat" in x for x in input_notes({"shape": shape, "bright": colour}, p))


def test_a_map_is_read_the_way_its_green_fits():
    n, cov, _ = sprite(64)
    up, down = encode(n), encode(n, green_down=True)
    assert not green_reading(up).flip and green_reading(down).flip
    reading = green_reading(down)
    assert reading.curl[False] > 3 * reading.curl[True]
    assert "green down (DirectX style)" in reading.describe("m.png")
    # a flat map fits either way: it keeps the reading it was given
    flat = np.full((16, 16, 3), (0.5, 0.5, 1.0))
    assert not green_reading(flat).flip and green_reading(flat, given=True).flip
    # a recipe that reads it the wrong way is told how to read it
    p = params.defaults()
    notes = input_notes({"shape": ImageData(down.astype(np.float32), 16, "m.png"),
                         "bright": ImageData(np.ones((64, 64, 3), np.float32))}, p)
    assert any("set shape.flip_green = true" in x for x in notes), notes


def test_a_rim_blended_with_black_is_no_cliff():
    """A Blender bake's map: (0, 0, 0, 0) outside, the rim premultiplied. Its integrated relief
    is the figure's (≈ 0.2 image widths high), not a wall (14 widths before issue 59)."""
    n, cov, colour = sprite(96)
    baked = np.dstack([encode(n) * cov[..., None], cov]).astype(np.float32)
    straight = np.dstack([encode(n), cov]).astype(np.float32)
    p = params.defaults()
    p.shadows.enabled = True
    heights = {}
    for name, px in (("baked", baked), ("straight", straight)):
        _, z_px, _ = shape_normals(ImageData(px, 16), p)
        heights[name] = z_px.max() / 96
    assert heights["baked"] == pytest.approx(heights["straight"], rel=0.05)
    assert 0.1 < heights["baked"] < 0.3
    assert needs_cleaning(baked[..., :3], cov)
    fixed, empty = cut_out_pixels(baked[..., :3], cov)
    inner = (cov > 0.05) & (cov < 0.95)
    np.testing.assert_allclose(fixed[inner], encode(n)[inner], atol=0.02)
    assert empty[cov == 0].all()
    # a rim written with straight alpha (sprite tools) stays as it is
    same, _ = cut_out_pixels(straight[..., :3], cov)
    np.testing.assert_array_equal(same, straight[..., :3])
    # lit under the upper-left sun, the face is not walled in shadow
    result = render({"shape": ImageData(baked, 16), "bright": colour}, [SUN], p)
    light = np.array(SUN.vector)
    facing = (n @ light >= 0.6) & (cov > 0.999)
    assert np.mean(result.passes["t"][0][facing] < 0.5 * (n @ light)[facing]) < 0.05


def hash_atlas(frames):
    return {"frames": {f"walk_{i:02d}.png": entry for i, entry in frames},
            "meta": {"image": "walk.png", "size": {"w": 8, "h": 8}, "scale": "1"}}


def test_texturepacker_atlases_in_their_three_forms():
    entry = {"frame": {"x": 2, "y": 1, "w": 2, "h": 3}, "rotated": True, "trimmed": True,
             "spriteSourceSize": {"x": 1, "y": 0, "w": 2, "h": 3}, "sourceSize": {"w": 4, "h": 3}}
    plain = {"frame": {"x": 0, "y": 4, "w": 4, "h": 3}, "rotated": False, "trimmed": False,
             "spriteSourceSize": {"x": 0, "y": 0, "w": 4, "h": 3}, "sourceSize": {"w": 4, "h": 3}}
    as_hash = hash_atlas([(10, entry), (2, plain)])
    as_array = {"frames": [{"filename": name, **e} for name, e in as_hash["frames"].items()],
                "meta": as_hash["meta"]}
    multi = {"textures": [{"image": "walk.png", "normalMap": "walk_nm.png",
                           "frames": as_array["frames"]}]}
    for data in (as_hash, as_array, multi):
        frames = parse_atlas(data)
        assert [f.name for f in frames] == ["walk_02.png", "walk_10.png"]    # 2 before 10
        assert frames[1].rotated and frames[1].offset == (1, 0) and frames[1].source == (4, 3)
    assert parse_atlas(multi)[0].normal_map == "walk_nm.png"
    assert parse_atlas({"name": "not an atlas"}) == []
    with pytest.raises(AtlasError, match="does not fit its source size"):
        parse_atlas(hash_atlas([(1, {**plain, "sourceSize": {"w": 2, "h": 2}})]))


def test_a_rotated_trimmed_frame_is_cut_back_to_its_source():
    src = np.arange(12, dtype=np.float32).reshape(3, 4)[..., None].repeat(4, -1)   # top first
    src[..., 3] = 1
    trimmed = src[:, 1:3]
    sheet = np.zeros((5, 6, 4), np.float32)
    sheet[1:3, 2:5] = np.rot90(trimmed, -1)          # packed turned clockwise
    frame = AtlasFrame("a", "s.png", "", (2, 1, 2, 3), True, (1, 0), (4, 3))
    got = cut_frame(sheet[::-1], frame)[::-1]        # ImageData holds rows bottom first
    want = np.zeros((3, 4, 4), np.float32)
    want[:, 1:3] = trimmed
    np.testing.assert_array_equal(got, want)


def test_an_atlas_in_a_folder_finds_its_normal_sheet(tmp_path):
    (tmp_path / "walk.json").write_text(json.dumps(hash_atlas([(1, {
        "frame": {"x": 0, "y": 0, "w": 4, "h": 3}, "sourceSize": {"w": 4, "h": 3}})])))
    (tmp_path / "notes.json").write_text("{not json")
    found = atlas_in(str(tmp_path), ["walk.png", "walk_n.png"])
    assert found and found[1][0].normal_map == "walk_n.png"
    with pytest.raises(AtlasError, match="walk.png is not in"):
        atlas_in(str(tmp_path), ["other.png"])
