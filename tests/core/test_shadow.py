"""§6 cos-θ shadows and its §14 rows: planes are exact, extremes stay finite and in [0, 1]."""
import numpy as np
import pytest

from conftest import flat_normals, unit
from dynpaint_addon.core.bake import QUALITY
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.shadow import ShadowStats, cos_theta_shadow
from dynpaint_addon.core.shape import decode_normal_map, height_field_px, normals_from_height_px, \
    slopes_from_normals

LIGHTS = [(0.3, 0.2, 0.8), (1, 0, 0.2), (-1, -1, 0.1), (0, 0, 1), (-0.2, 0.9, 0.4)]


def _both(n, z_px, light, d, k, **kw):
    """(height-map bake, normal-map bake) of the same surface."""
    return (cos_theta_shadow(n, light, d, k, heights_px=z_px, **kw),
            cos_theta_shadow(n, light, d, k, slopes=slopes_from_normals(n), **kw))


@pytest.mark.parametrize("L", LIGHTS)
@pytest.mark.parametrize("d", [1e-4, 0.003, 0.05, 0.4])
@pytest.mark.parametrize("k", [0, 1, 7, 64, 100000])
def test_flat_plane_gives_cos_theta(L, d, k):
    """§6/§14: flat plane, any L, d, K → t = cos θ to float precision (1e-5 in float32)."""
    n = flat_normals(24, 32)
    z = np.zeros((24, 32), np.float32)
    for t in _both(n, z, Light("sun", L), d, k):
        assert t.dtype == np.float32
        np.testing.assert_allclose(t, unit(L)[2], atol=1e-5)


@pytest.mark.parametrize("L", LIGHTS + [(-0.9, 0.1, 0.1)])
@pytest.mark.parametrize("d", [0.001, 0.02, 0.5])
@pytest.mark.parametrize("k", [0, 1, 16])
def test_tilted_plane_gives_clamped_n_dot_l(L, d, k):
    """§6: on a tilted plane t = max(N·L, 0), for height maps and normal maps, up to the border."""
    w = 48
    y, x = np.mgrid[0:w, 0:w].astype(np.float64) + 0.5
    z = (0.3 * x + 0.1 * y).astype(np.float32)               # pixels: slopes 0.3 and 0.1
    n = normals_from_height_px(z)
    expected = max(float(n[5, 5] @ unit(L)), 0.0)
    for t in _both(n, z, Light("sun", L), d, k):
        np.testing.assert_allclose(t, expected, atol=1e-4)


def test_vertical_light_on_a_normal_map_gives_n_z(rng):
    """§6: with L = (0, 0, 1) the normal-map march gives t = N.z exactly, even when the map is
    non-conservative (random normals: no height field produces them)."""
    rgb = rng.uniform(0, 1, (40, 50, 3)).astype(np.float32)
    n = decode_normal_map(rgb)
    for d, k in [(0.01, 64), (0.2, 8), (0.001, 1)]:
        t = cos_theta_shadow(n, Light("sun", (0, 0, 1)), d, k, slopes=slopes_from_normals(n))
        np.testing.assert_allclose(t, n[..., 2], atol=2e-5)


def test_point_light_over_a_plane_gives_cos_theta_at_p0_tending_to_n_dot_l():
    """§6 Which ray: the segment from P0 = P_S − d·N to the light, so on a plane t = cos θ0,
    θ0 the angle between N and P_L − P0; as d → 0 it tends to N·L(P_S)."""
    n = flat_normals(32, 32)
    z = np.zeros((32, 32), np.float32)
    light = Light("point", (0.2, -0.1, 0.3))
    y, x = np.mgrid[0:32, 0:32].astype(np.float64) + 0.5
    p = light.position_px(32, 32)
    for d in (0.02, 0.1):
        z0 = -d * 32
        expected = (p[2] - z0) / np.sqrt((p[0] - x) ** 2 + (p[1] - y) ** 2 + (p[2] - z0) ** 2)
        for t in _both(n, z, light, d, 32):
            np.testing.assert_allclose(t, expected, atol=1e-5)
    n_dot_l = p[2] / np.sqrt((p[0] - x) ** 2 + (p[1] - y) ** 2 + p[2] ** 2)
    gaps = [np.abs(cos_theta_shadow(n, light, d, 32, heights_px=z) - n_dot_l).max()
            for d in (0.02, 0.002, 0.0002)]
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 1e-3, gaps


@pytest.mark.parametrize("L", [(1, 0, 0), (0.5, 0.5, -0.2), (0, 0, -1)])
def test_sun_at_or_below_the_horizon_gives_zero(L):
    """§14: L.z = 0 or < 0 → finite; t = 0 below the horizon."""
    n = flat_normals(8, 8)
    for t in _both(n, np.zeros((8, 8), np.float32), Light("sun", L), 0.01, 16):
        assert np.all(t == 0)


def _bumpy(size=64, seed=3):
    rng = np.random.default_rng(seed)
    hgt = np.zeros((size, size))
    y, x = np.mgrid[0:size, 0:size] / size
    for _ in range(6):
        cx, cy, r = rng.uniform(0.2, 0.8), rng.uniform(0.2, 0.8), rng.uniform(0.05, 0.2)
        hgt = np.maximum(hgt, np.sqrt(np.clip(1 - ((x - cx) ** 2 + (y - cy) ** 2) / r**2, 0, 1)))
    z = height_field_px(hgt.astype(np.float32), 0.15)
    return normals_from_height_px(z), z


@pytest.mark.parametrize("d", [0.0, 1e-7, 1e-3])
@pytest.mark.parametrize("k", [0, 1, 3, 50000])
def test_extremes_stay_finite_and_in_range(d, k):
    """§14: d → 0, K = 0, K = 1, huge K → finite, t ∈ [0, 1], on a relief with cast shadows."""
    n, z = _bumpy()
    for light in (Light("sun", (1, 0.3, 0.25)), Light("point", (0.1, 0.1, 0.05)),
                  Light("point", (0.0, 0.0, -0.2))):
        for t in _both(n, z, light, d, k):
            assert np.all(np.isfinite(t)) and t.min() >= 0 and t.max() <= 1


def test_huge_k_is_capped_per_pixel_of_march():
    n, z = _bumpy(32)
    stats = ShadowStats()
    cos_theta_shadow(n, Light("sun", (1, 0, 1)), 0.01, 10**9, heights_px=z, stats=stats)
    assert stats.steps <= 4 * 32 * np.sqrt(2) + 1


def test_d_to_zero_is_n_dot_l_times_hard_visibility():
    """§6: d → 0 gives max(N·L, 0) × hard visibility: lit pixels equal N·L, shadowed ones 0."""
    n, z = _bumpy(64)
    light = Light("sun", (1, 0.2, 0.35))
    t0 = cos_theta_shadow(n, light, 0.0, 256, heights_px=z)
    ndl = np.maximum(n @ unit(light.vector), 0).astype(np.float32)
    lit = t0 > 0
    np.testing.assert_allclose(t0[lit], ndl[lit], atol=1e-6)
    assert np.mean(~lit & (ndl > 0.2)) > 0.01    # some sunlit-facing pixels are in cast shadow
    # A tiny offset sees the same lit/shadowed split, and on most lit pixels the same value.
    # (Not on all: as d → 0 the march follows the bilinear surface, whose slope differs slightly
    # from the central-difference normal used for N·L.)
    t_small = cos_theta_shadow(n.astype(np.float64), light, 1e-5, 256, heights_px=z.astype(np.float64))
    assert np.mean((t_small > 0.05) == lit) > 0.98
    assert np.median(np.abs(t_small - t0)[lit]) < 1e-6


@pytest.mark.parametrize("quality", ["preview", "final"])
def test_d_zero_is_the_hard_limit_at_every_level(quality, monkeypatch):
    """d = 0 at a level that bakes by crossings: the limit of the march (max(N·L, 0) × hard
    visibility), for suns and point lights, height maps and normal maps — not zero (a point
    light's crossings once gave 0 everywhere: d / max(r, d) with d = 0)."""
    from dynpaint_addon.core import bake as bake_levels
    monkeypatch.setattr(bake_levels, "FAST_FINAL_MIN_PX", 32)
    n, z = _bumpy(64)
    for light in (Light("sun", (1, 0.2, 0.35)), Light("point", (0.3, -0.2, 0.6))):
        for kw in ({"heights_px": z}, {"slopes": slopes_from_normals(n), "reach": 0.05}):
            t = bake_levels.bake(n, light, 0.0, quality, **kw)
            if quality == "final":
                np.testing.assert_array_equal(t, cos_theta_shadow(n, light, 0.0, 64, **kw))
            assert np.mean(t > 0.1) > 0.5, (light.kind, list(kw))


def test_point_light_inside_the_relief_caps_the_segment():
    """§6: a point light inside the relief: the segment stops at the light; t stays in [0, 1]."""
    n, z = _bumpy(64)
    light = Light("point", (0.0, 0.0, 0.005))     # below the tops of the bumps
    t = cos_theta_shadow(n, light, 0.01, 64, heights_px=z)
    assert np.all(np.isfinite(t)) and t.min() >= 0 and t.max() <= 1
    # pixels right under the light see it through very little relief: lit
    assert t[32, 32] > 0.0


def test_linear_crossing_beats_the_midpoint_count():
    """§6: linear-crossing occupancy is far more accurate than the paper's binary midpoint count."""
    n, z = _bumpy(64)
    light = Light("sun", (0.8, 0.3, 0.6))
    ref = cos_theta_shadow(n.astype(np.float64), light, 0.01, 2048, heights_px=z.astype(np.float64))
    lin = cos_theta_shadow(n, light, 0.01, 16, heights_px=z)
    mid = cos_theta_shadow(n, light, 0.01, 16, heights_px=z, occupancy="midpoint")
    e_lin, e_mid = np.mean(np.abs(lin - ref)), np.mean(np.abs(mid - ref))
    assert e_lin < e_mid / 3


def test_more_steps_converge_to_the_reference():
    n, z = _bumpy(64)
    light = Light("sun", (-0.6, 0.5, 0.5))
    ref = cos_theta_shadow(n.astype(np.float64), light, 0.01, 4096, heights_px=z.astype(np.float64))
    errs = [np.mean(np.abs(cos_theta_shadow(n, light, 0.01, k, heights_px=z) - ref))
            for k in (4, 16, 64, 256)]
    assert errs == sorted(errs, reverse=True) and errs[-1] < 2e-3 and errs[0] > 5 * errs[-1]
    assert QUALITY["reference"]["dtype"] == "float64"


def test_cast_shadow_falls_away_from_the_light():
    """A tall box on the ground, sun from +x: the ground at −x of the box is dark, +x lit."""
    size = 64
    hgt = np.zeros((size, size), np.float32)
    hgt[24:40, 28:36] = 1
    z = height_field_px(hgt, 0.2)
    n = normals_from_height_px(z)
    t = cos_theta_shadow(n, Light("sun", (1, 0, 0.6)), 0.005, 128, heights_px=z)
    cos_sun = unit((1, 0, 0.6))[2]
    assert t[32, 20] < 0.05                    # in the box's shadow
    assert t[32, 45] == pytest.approx(cos_sun, abs=1e-3)   # lit ground on the light's side
    tn = cos_theta_shadow(n, Light("sun", (1, 0, 0.6)), 0.005, 128, slopes=slopes_from_normals(n))
    assert tn[32, 45] == pytest.approx(cos_sun, abs=1e-3)


# -- quality levels (§13, issue 4) --------------------------------------------------------
from dynpaint_addon.core.bake import QUALITIES, bake  # noqa: E402
from dynpaint_addon.core.shadow import BakeCancelled  # noqa: E402


@pytest.mark.parametrize("quality", QUALITIES)
def test_plane_is_cos_theta_at_every_quality(quality):
    n = flat_normals(48, 64)
    light = Light("sun", unit((0.4, -0.3, 0.5)))
    t = bake(n, light, 0.01, quality, heights_px=np.zeros((48, 64)), steps=8, scale=0.3)
    assert t.shape == (48, 64)
    assert np.abs(t - unit((0.4, -0.3, 0.5))[2]).max() < 1e-5


def test_quality_levels_converge_to_the_reference():
    from dynpaint_addon.inputs.testpainting import builtin_images
    from dynpaint_addon.core.shape import height_field_px, normals_from_height_px
    z = height_field_px(builtin_images(192)["shape"].grey(), 0.25)
    n = normals_from_height_px(z)
    light = Light("sun", (-0.6, 0.5, 0.45))
    ref = bake(n.astype(np.float64), light, 0.01, "reference", heights_px=z.astype(np.float64))
    errs = [np.abs(bake(n, light, 0.01, q, heights_px=z) - ref).mean()
            for q in ("draft", "preview", "final")]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 5e-3, errs


def test_a_bake_can_be_superseded():
    n = flat_normals(16, 16)
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) > 3
    z = np.zeros((16, 16))
    z[6:10, 6:10] = 8.0          # a tall block: the march takes all its steps
    with pytest.raises(BakeCancelled):
        bake(n, Light("sun", (0.3, 0.2, 0.5)), 0.01, "custom", heights_px=z, steps=32,
             cancel=cancel)
    assert len(calls) == 4


# -- the fast sun bake (crossings.py) ------------------------------------------------------
from dynpaint_addon.core import crossing_blocks, crossing_search, crossings  # noqa: E402


@pytest.mark.parametrize("kind", ["height", "normal"])
def test_sun_crossings_match_the_reference(kind):
    """Exact crossings against the K = 1024 float64 march, on tall relief."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    from dynpaint_addon.core.shape import height_field_px, normals_from_height_px
    z = height_field_px(builtin_images(192)["shape"].grey().astype(np.float64), 0.25)
    n = normals_from_height_px(z)
    kw = {"heights_px": z} if kind == "height" else {"slopes": slopes_from_normals(n)}
    light = Light("sun", (-0.6, 0.5, 0.45))
    ref = cos_theta_shadow(n, light, 0.01, 1024, **kw)
    fast = crossings.sun_cos_theta(n.astype(np.float32), light, 0.01,
                                   **{k: v.astype(np.float32) for k, v in kw.items()})
    assert fast.shape == ref.shape and fast.dtype == np.float32
    # resolution-dependent: the light-aligned grid smears one-pixel walls (1.4e-4 at 1024²)
    assert np.abs(fast - ref).mean() < 3e-3
    assert np.all((fast >= 0) & (fast <= 1))


@pytest.mark.parametrize("light", [Light("sun", (0, 0, 1)), Light("sun", (0.3, 0.2, -0.1)),
                                   Light("sun", (1, 0, 1e-9))])
def test_sun_crossings_extremes(light):
    """Straight up (no horizontal direction), below the horizon, grazing: finite, in [0, 1]."""
    z = np.zeros((20, 30))
    z[8:12, 10:20] = 6.0
    from dynpaint_addon.core.shape import normals_from_height_px
    n = normals_from_height_px(z)
    t = crossings.sun_cos_theta(n, light, 0.01, heights_px=z)
    assert np.all(np.isfinite(t)) and np.all((t >= 0) & (t <= 1))
    if light.vector[2] <= 0:
        assert np.all(t == 0)


def test_large_images_fall_back_to_the_march(monkeypatch):
    n = flat_normals(16, 16)
    z = np.zeros((16, 16))
    z[5:9, 5:9] = 4.0
    light = Light("sun", (0.5, 0.2, 0.4))
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", 0)
    marched = bake(n, light, 0.01, "final", heights_px=z)
    assert np.array_equal(marched, cos_theta_shadow(n, light, 0.01, 64, heights_px=z))


def test_banded_march_equals_one_band_and_bounds_its_memory(monkeypatch):
    """The march runs in bands of rows (shadow.BAND_PIXELS): bit-identical to one band, with a
    peak of extra memory that follows the band, not the image."""
    import tracemalloc
    from dynpaint_addon.core import shadow
    rng = np.random.default_rng(5)
    h, w = 128, 192
    y, x = np.mgrid[0:h, 0:w]
    z = (60 * np.exp(-((x - 75) ** 2 + (y - 60) ** 2) / 750) + rng.uniform(0, 2, (h, w)))
    z = z.astype(np.float32)
    n = normals_from_height_px(z)
    out = {}
    for light in (Light("sun", (0.6, 0.2, 0.4)), Light("point", (0.3, -0.2, 0.25))):
        for band in (1 << 20, 1500):
            monkeypatch.setattr(shadow, "BAND_PIXELS", band)
            calls = []
            tracemalloc.start()
            t = shadow.cos_theta_shadow(n, light, 0.01, 32, heights_px=z, progress=calls.append)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            out[band] = (t, peak)
            assert calls[-1] == 1.0 and len(calls) == -(-h // max(1, band // w))
        assert np.array_equal(out[1 << 20][0], out[1500][0]), light
        whole, banded = out[1 << 20][1], out[1500][1]
        assert banded < whole / 4, (light.kind, whole, banded)


# -- point lights by crossings on a polar grid (crossings._PointGrid) -----------------------
POINT_LIGHTS = [(0.3, -0.2, 0.6),      # foot inside the image: the grid covers every angle
                (1.5, 0.4, 0.5),       # foot outside: the grid covers the image's angles only
                (20, 5, 8),            # far away: the grid stops at the image
                (0.0, 0.0, 0.2),       # low, over the middle
                (0.1, 0.1, 0.05),      # almost on the surface
                (0.2, 0.3, -0.1)]      # below the canvas


@pytest.mark.parametrize("shape", ["height", "normal"])
@pytest.mark.parametrize("pos", POINT_LIGHTS[:4])
def test_point_crossings_over_a_plane_give_cos_theta(pos, shape):
    """On a plane the grid's ray from P0 to the light is §6's: t = cos θ0 per pixel, for the
    grid's every layout, drawn as a height map or as a normal map."""
    h, w = 40, 56
    light = Light("point", pos)
    y, x = np.mgrid[0:h, 0:w].astype(np.float64) + 0.5
    p = light.position_px(h, w)
    z0 = -0.02 * w
    expected = (p[2] - z0) / np.sqrt((p[0] - x) ** 2 + (p[1] - y) ** 2 + (p[2] - z0) ** 2)
    kw = {"heights_px": np.zeros((h, w), np.float32)} if shape == "height" else \
        {"slopes": np.zeros((h, w, 2), np.float32), "reach": 0.05}
    t = crossings.point_cos_theta(flat_normals(h, w), light, 0.02, **kw)
    np.testing.assert_allclose(t, expected, atol=2e-4)


@pytest.mark.parametrize("shape", ["height", "normal"])
@pytest.mark.parametrize("pos", POINT_LIGHTS[:4])
def test_point_crossings_over_a_tilted_plane_give_cos_theta(pos, shape):
    """A tilted plane, as heights or as a normal map (a constant slope integrated along the
    grid's rows, whatever the reach): t = the reference's, cos θ of the tilted normal, away
    from the border (where the reference's tail takes over). A normal map's relief is read
    from each ray's start (exact); heights are read from the blend of two rows, which meets a
    plane on the chord between them, ρ·dφ²/8 off the ray: 1e-3 here, at 48 px with d ≈ 1 px
    (at 1024 px the chord is 20× nearer and d 20× longer)."""
    h, w = 48, 48
    n = np.zeros((h, w, 3))
    n[...] = unit((0.25, -0.15, 1.0))
    sl = slopes_from_normals(n)
    y, x = np.mgrid[0:h, 0:w] + 0.5
    light = Light("point", pos)
    for reach in (0.05, np.inf):
        kw = {"heights_px": sl[..., 0] * x + sl[..., 1] * y} if shape == "height" else \
            {"slopes": sl, "reach": reach}
        ref = cos_theta_shadow(n, light, 0.02, 1024, **kw)
        t = crossings.point_cos_theta(n.astype(np.float32), light, 0.02,
                                      **{k: np.asarray(v, np.float32) if k != "reach" else v
                                         for k, v in kw.items()})
        np.testing.assert_allclose(t[6:-6, 6:-6], ref[6:-6, 6:-6],
                                   atol=2e-4 if shape == "normal" else 2e-3)


@pytest.mark.parametrize("pos", POINT_LIGHTS)
@pytest.mark.parametrize("reach", [0.05, np.inf])
def test_point_crossings_of_normal_maps_follow_the_reference(pos, reach):
    """A normal map's relief rebuilt along each ray (each ray its own shift of its rows'
    running integral, _Rows' bend): close to the K = 1024 march for every light, with the
    default reach and without one."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(128)["shape"].grey().astype(np.float64), 0.25)
    n = normals_from_height_px(z)
    sl = slopes_from_normals(n)
    light = Light("point", pos)
    ref = cos_theta_shadow(n, light, 0.01, 1024, slopes=sl, reach=reach)
    t = crossings.point_cos_theta(n.astype(np.float32), light, 0.01,
                                  slopes=sl.astype(np.float32), reach=reach)
    assert np.all(np.isfinite(t)) and np.all((t >= 0) & (t <= 1))
    # measured 3e-4 – 3.1e-3 at 128² (d = 1.3 px: a ray near the light is steep, and a
    # tenth of a pixel of the rebuilt wall's foot is a third of its length inside)
    assert np.abs(t - ref).mean() < 5e-3


@pytest.mark.parametrize("pos", POINT_LIGHTS)
def test_point_crossings_follow_the_reference(pos):
    """Tall relief (0.25 image widths): close to the K = 1024 march everywhere, finite and
    in [0, 1] for lights far, near, low and below."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(128)["shape"].grey().astype(np.float64), 0.25)
    n = normals_from_height_px(z)
    light = Light("point", pos)
    ref = cos_theta_shadow(n, light, 0.01, 1024, heights_px=z)
    t = crossings.point_cos_theta(n.astype(np.float32), light, 0.01,
                                  heights_px=z.astype(np.float32))
    assert np.all(np.isfinite(t)) and np.all((t >= 0) & (t <= 1))
    # measured 1e-5 – 4.4e-3 at 128²: both follow §6's aimed ray; they differ where the grid's
    # rows and the march's bilinear taps see a shadow's edge a pixel apart
    assert np.abs(t - ref).mean() < 6e-3


def test_point_lights_use_crossings_at_every_level_from_512_px(monkeypatch):
    """Draft, preview and final bake point lights by crossings (final from
    FAST_FINAL_MIN_PX up: below it the K = 64 march is more accurate and cheap), each level
    closer to the reference than the one before; normal maps too."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(256)["shape"].grey(), 0.25)
    n = normals_from_height_px(z)
    light = Light("point", (0.3, -0.2, 0.6))
    ref = bake(n.astype(np.float64), light, 0.01, "reference", heights_px=z.astype(np.float64))
    errs = []
    for quality, method in (("draft", "aimed crossings"), ("preview", "aimed crossings"),
                            ("final", "march")):
        stats = ShadowStats()
        t = bake(n, light, 0.01, quality, heights_px=z, stats=stats)
        assert stats.method == method, quality
        errs.append(np.abs(t - ref).mean())
    assert errs[0] > errs[1] > errs[2] and errs[1] < 0.02, errs
    monkeypatch.setattr(bake_module, "FAST_FINAL_MIN_PX", 256)
    stats = ShadowStats()
    t = bake(n, light, 0.01, "final", heights_px=z, stats=stats)
    assert stats.method == "aimed crossings" and stats.size == (256, 256)
    # measured 1.6e-3 at 256² (the grid's columns 0.7 px apart; 5.9e-4 at 512², 3.9e-4 at
    # 1024² with relief 0.5: docs/shadow-quality.md)
    assert np.abs(t - ref).mean() < min(errs[1] / 2, 3e-3)
    stats = ShadowStats()
    bake(n, light, 0.01, "preview", slopes=slopes_from_normals(n), stats=stats)
    assert stats.method == "aimed crossings" and stats.size == (192, 192)


def test_point_grid_blocks_keep_only_the_columns_rays_read():
    """Each block of a polar grid is as wide as the box seen from the light's foot over its
    angles: about half the full circle's cells for a foot inside the image."""
    grid = crossings._PointGrid(Light("point", (0.3, -0.2, 0.6)), 1024, 1024, 0.01)
    cells = sum(n * (c1 - c0) for _, n, c0, c1 in grid.blocks)
    assert len(grid.blocks) == crossings.POINT_BLOCKS
    assert 0.4 < cells / (grid.rows * grid.width) < 0.65
    assert (sum(grid.block_bytes()), max(grid.block_bytes())) == crossings.table_bytes(
        Light("point", (0.3, -0.2, 0.6)), 1024, 1024, 0.01)


def _tall_box(kind):
    """(normals, heights px, light): a 512² plane with a 40 px box, lit by a sun or a point
    light; a final bake of it runs by crossings."""
    n, z = flat_normals(512, 512), np.zeros((512, 512), np.float32)
    z[200:260, 200:260] = 40.0
    light = Light("sun", (0.5, 0.2, 0.4)) if kind == "sun" else Light("point", (0.3, 0.1, 0.4))
    return n, z, light


@pytest.mark.parametrize("kind", ["sun", "point"])
def test_a_final_too_big_for_memory_at_once_bakes_by_crossings_in_groups(kind, monkeypatch):
    """Where a painting's tables would not fit MAX_TABLE_BYTES at once (a 4096² final: about
    2 GiB) the bake's plan still takes crossings while one block fits: the blocks are built
    a group at a time. The result is the same as in one group, bit for bit."""
    n, z, light = _tall_box(kind)
    whole, largest = crossings.table_bytes(light, 512, 512, 0.01)
    one = bake(n, light, 0.01, "final", heights_px=z)
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", (whole + largest) / 3)
    assert whole > crossing_blocks.MAX_TABLE_BYTES >= largest        # not at once, a block at least
    stats = ShadowStats()
    t = bake(n, light, 0.01, "final", heights_px=z, stats=stats)
    assert stats.method.endswith("crossings") and np.array_equal(t, one)
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", largest * 0.99)
    stats = ShadowStats()
    with pytest.raises(BakeCancelled):       # (stopped at its first step: the march it took)
        bake(n, light, 0.01, "final", heights_px=z, stats=stats, cancel=lambda: True)
    assert stats.method == "march" and stats.steps > 0


@pytest.mark.parametrize("kind", ["sun", "point"])
def test_a_long_crossing_bake_reports_progress_and_can_be_superseded(kind, monkeypatch):
    """A large painting's final by crossings (several groups of blocks, several chunks of
    rays: seconds to a minute) tells its progress after each chunk and asks `cancel` before
    each, as the march does per band of rows."""
    n, z, light = _tall_box(kind)
    whole, largest = crossings.table_bytes(light, 512, 512, 0.01)
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", (whole + largest) / 3)   # ≥ 2 groups
    monkeypatch.setattr(crossing_blocks, "TRACE_PIXELS", 512 * 128)                 # 4 chunks
    seen = []
    bake(n, light, 0.01, "final", heights_px=z, progress=seen.append)
    assert len(seen) >= 2 * 4 and seen == sorted(seen) and seen[-1] == 1.0 and seen[0] <= 0.125
    asked = []

    def cancel():
        asked.append(1)
        return len(asked) > 3
    with pytest.raises(BakeCancelled):
        bake(n, light, 0.01, "final", heights_px=z, cancel=cancel)
    assert len(asked) == 4        # once before the bake, then before each chunk


def _relief_case(kind):
    """(normals, relief keywords, light, crossing function) for "sun|point, height|normal":
    the built-in relief at 160², as a height map or as a normal map's slopes."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(160)["shape"].grey().astype(np.float32), 0.3)
    n = normals_from_height_px(z)
    kw = {"heights_px": z} if kind.endswith("height") else {"slopes": slopes_from_normals(n)}
    if kind.startswith("sun"):
        return n, kw, Light("sun", (0.5, -0.7, 0.5)), crossings.sun_cos_theta
    return n, kw, Light("point", (0.3, -0.2, 0.6)), crossings.point_cos_theta


@pytest.mark.parametrize("kind", ["sun, height", "sun, normal", "point, height",
                                  "point, normal"])
def test_groups_of_blocks_only_split_the_work(kind, monkeypatch):
    """Blocks built and searched a group at a time (each group's tables freed before the
    next, the rays' starts recomputed per group, t finished in the last): bit-identical to
    all blocks at once."""
    n, kw, light, fn = _relief_case(kind)
    monkeypatch.setattr(crossings, "SUN_BLOCK_ROWS", 16)
    monkeypatch.setattr(crossings, "POINT_BLOCK_CELLS", 1000)
    monkeypatch.setattr(crossing_blocks, "TRACE_PIXELS", 9000)       # several chunks per group
    grid = crossings._SunGrid(np.array(unit(light.vector)), 160, 160) if light.kind == "sun" \
        else crossings._PointGrid(light, 160, 160, 0.01)
    one = fn(n, light, 0.01, **kw)
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", 2.5 * max(grid.block_bytes()))
    groups = grid.groups()
    assert len(groups) >= 3 and sum(groups, []) == list(range(len(grid.blocks)))
    assert np.array_equal(fn(n, light, 0.01, **kw), one)


def test_point_crossings_fall_back_to_the_march_when_the_grid_is_too_big(monkeypatch):
    n = flat_normals(64, 64)
    z = np.zeros((64, 64), np.float32)
    z[20:30, 20:30] = 8.0
    light = Light("point", (0.3, 0.1, 0.4))
    monkeypatch.setattr(crossing_blocks, "MAX_TABLE_BYTES", 0)
    stats = ShadowStats()
    t = bake(n, light, 0.01, "preview", heights_px=z, stats=stats)
    assert stats.method == "march" and np.all(np.isfinite(t))


@pytest.mark.parametrize("kind", ["sun, height", "sun, normal", "point, height",
                                  "point, normal"])
def test_crossings_do_not_depend_on_blocks_chunks_or_threads(kind, monkeypatch):
    """The grid's blocks, the chunks of rays, the threads and the tables' top level (a
    descent that stops at its reach is resumed) only split the work: the same result, up to
    float32 rounding of positions counted from each block's first column."""
    n, kw, light, fn = _relief_case(kind)
    one = fn(n, light, 0.01, **kw)
    assert len(crossings._SunGrid(np.array(unit((0.5, -0.7, 0.5))), 160, 160).blocks) == 1
    monkeypatch.setattr(crossings, "SUN_BLOCK_ROWS", 16)
    monkeypatch.setattr(crossings, "POINT_BLOCK_CELLS", 1000)
    monkeypatch.setattr(crossing_blocks, "TRACE_PIXELS", 3000)
    monkeypatch.setattr(crossing_blocks, "RAY_BAND_PIXELS", 500)
    monkeypatch.setattr(crossing_blocks, "THREADS", 3)
    monkeypatch.setattr(crossing_search, "TABLE_LEVELS", 3)
    assert len(crossings._SunGrid(np.array(unit((0.5, -0.7, 0.5))), 160, 160).blocks) == 8
    assert len(crossings._PointGrid(Light("point", (0.3, -0.2, 0.6)), 160, 160, 0.01).blocks) \
        == crossings.POINT_BLOCKS
    np.testing.assert_allclose(fn(n, light, 0.01, **kw), one, atol=1e-5)


@pytest.mark.parametrize("levels", [1, 4])
def test_descents_capped_by_the_tables_top_level_are_resumed(levels, monkeypatch):
    """Tables stop at TABLE_LEVELS: a descent then advances at most 2**levels − 1 columns and
    its caller resumes it until it finds the crossing, however far (a low sun's long shadows;
    with a fixed number of resumptions this failed: t off by up to 0.87)."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(256)["shape"].grey().astype(np.float32), 0.5)
    n = normals_from_height_px(z)
    light = Light("sun", (np.cos(0.26) * np.cos(0.5), np.cos(0.26) * np.sin(0.5), np.sin(0.26)))
    full = crossings.sun_cos_theta(n, light, 0.01, heights_px=z)
    monkeypatch.setattr(crossing_search, "TABLE_LEVELS", levels)
    np.testing.assert_allclose(crossings.sun_cos_theta(n, light, 0.01, heights_px=z), full,
                               atol=1e-6)


# -- a sun straight above (issue 15, point 6) ------------------------------------------------
from dynpaint_addon.core import bake as bake_module  # noqa: E402
from dynpaint_addon.core.shadow import vertical_cos_theta  # noqa: E402


@pytest.mark.parametrize("kind", ["height", "normal"])
def test_a_sun_straight_above_has_the_marchs_answer_in_closed_form(kind):
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(96)["shape"].grey().astype(np.float64), 0.25)
    n = normals_from_height_px(z)
    kw = {"heights_px": z} if kind == "height" else {"slopes": slopes_from_normals(n)}
    up = Light("sun", (0, 0, 1))
    closed = vertical_cos_theta(n, 0.01, heights_px=kw.get("heights_px"))
    for steps in (64, 1024):
        assert np.abs(closed - cos_theta_shadow(n, up, 0.01, steps, **kw)).max() < 1e-12
    if kind == "height":
        assert closed.min() < 0.5            # the cast shadows of the walls are in it


def test_a_sun_straight_above_never_marches(monkeypatch):
    """Overhead was the slowest case (the crossings fell back to a K = 64 march: 7–34× a
    45° sun, benchmarks/overhead_lights.py); now it is the cheapest, at every level."""
    from dynpaint_addon.inputs.testpainting import builtin_images
    z = height_field_px(builtin_images(512)["shape"].grey().astype(np.float32), 0.25)
    n = normals_from_height_px(z)

    def marched(*args, **kwargs):
        raise AssertionError("a sun straight above was marched")
    for module in (bake_module, crossings):
        monkeypatch.setattr(module, "cos_theta_shadow", marched)
    up = Light("sun", (0, 0, 1))
    for quality in ("draft", "preview", "final"):
        for kw in ({"heights_px": z}, {"slopes": slopes_from_normals(n)}):
            t = bake_module.bake(n, up, 0.01, quality, **kw)
            assert t.shape == z.shape and np.all((t >= 0) & (t <= 1))


# -- §6 Reach (normal maps) ---------------------------------------------------------------------
def _tilted_plane(h=40, w=48, tilt=(0.3, -0.2)):
    n = np.empty((h, w, 3), np.float32)
    n[...] = unit((*tilt, 1.0))
    return n


@pytest.mark.parametrize("reach", [0.0, 0.004, 0.05, 10.0])
@pytest.mark.parametrize("L", [(0.3, 0.2, 0.8), (1, 0, 0.15), (-0.5, 0.4, 0.3)])
def test_a_plane_stays_exact_at_any_reach(reach, L):
    """Beyond the reach the surface is P_S's tangent plane: on a plane that changes nothing,
    even where the ray is still under it at the reach (grazing light, d/N·L > R)."""
    n = _tilted_plane()
    light = Light("sun", L)
    want = max(float(np.dot(n[0, 0], unit(L))), 0.0)
    slopes = slopes_from_normals(n)
    march = cos_theta_shadow(n, light, 0.05, 64, slopes=slopes, reach=reach)
    fast = crossings.sun_cos_theta(n, light, 0.05, slopes=slopes, reach=reach)
    for t in (march, fast):
        np.testing.assert_allclose(t[2:-2, 2:-2], want, atol=2e-5)


def test_crossings_follow_the_reach_like_the_reference():
    from testkit.example_paintings import penrose_triangle
    n, _ = penrose_triangle(256)
    n = n.astype(np.float64)
    slopes = slopes_from_normals(n)
    light = Light("sun", (-0.6, -0.3, 0.55))
    for reach in (0.02, 0.1):
        ref = cos_theta_shadow(n, light, 0.01, 1024, slopes=slopes, reach=reach)
        fast = crossings.sun_cos_theta(n.astype(np.float32), light, 0.01,
                                       slopes=slopes.astype(np.float32), reach=reach)
        assert np.abs(fast - ref).mean() < 2e-3, reach   # measured 0.9e-3, 1.2e-3 (∞: 1.6e-3)


@pytest.mark.parametrize("azimuth", [200, 60, 135])
def test_an_impossible_figure_drawn_as_facets_casts_no_streaks(azimuth):
    """Penrose tribar (example_paintings): with the default reach no facet is darkened farther
    than 0.05 image widths from its edges (every facet is as the artist drew it). With the
    relief felt across the whole image (reach 10, the old behaviour), rebuilt heights that
    never come back down smear long shadows over facets and the canvas."""
    from dynpaint_addon import params
    from dynpaint_addon.core.bake import bake
    from testkit.example_paintings import penrose_triangle, streak_share
    size = 256
    n, facet = penrose_triangle(size)
    n = n.astype(np.float32)
    e, a = np.radians(35), np.radians(azimuth)
    light = Light("sun", (np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)))
    default = params.BY_PATH["shadows.reach"].default
    shares = {reach: streak_share(bake(n, light, 0.01, "final", slopes=slopes_from_normals(n),
                                       reach=reach), n, light, facet, round(0.05 * size))
              for reach in (default, 10.0)}
    assert shares[default] == 0.0, shares
    assert shares[10.0] > 0.005, shares       # measured 1.2 %, 3.7 %, 7.4 %: it failed before


def test_a_shapes_reductions_are_kept_while_it_lives_and_no_longer():
    """A dragged light (or a moving painting's loop) bakes one shape again and again: its
    reductions to a quarter of the pixels or fewer (preview of a normal map: 0.4²) are made
    once; a shape let go leaves no reduction behind at the next one kept."""
    import gc

    from dynpaint_addon.core import bake as bake_levels
    n = flat_normals(64, 64).astype(np.float32)
    slopes = np.zeros((64, 64, 2), np.float32)
    first = bake_levels.reduced_inputs(n, None, slopes, 26, 26)
    assert bake_levels.reduced_inputs(n, None, slopes, 26, 26)[0] is first[0]
    assert bake_levels.reduced_inputs(n, None, slopes, 40, 40)[0] is not \
        bake_levels.reduced_inputs(n, None, slopes, 40, 40)[0]       # over a quarter: not kept
    del n, slopes, first
    gc.collect()
    other = flat_normals(32, 32).astype(np.float32)
    bake_levels.reduced_inputs(other, None, None, 8, 8)
    assert all(refs[0]() is not None for refs, _, _ in bake_levels._REDUCED.values())


# -- §6 Step: a march ends where its own path lets it (issue 39, §16) ---------------------------
def _domes(size, tall):
    """Two domes far apart (heights in px): a still one at the lower left and one at the upper
    right whose height is `tall` (a moving part)."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    z = np.zeros((size, size))
    for cx, cy, r, top in ((0.25, 0.25, 0.15, 12.0), (0.75, 0.75, 0.15, tall)):
        d2 = ((x - cx) ** 2 + (y - cy) ** 2) / r ** 2
        z += np.where(d2 < 1, top * np.sqrt(np.clip(1 - d2, 0, 1)), 0)
    return z


@pytest.mark.parametrize("L", [(0.6, -0.3, 0.7), (-0.2, -0.8, 0.5), (0.1, 0.1, 0.95)])
def test_a_still_part_is_marched_the_same_whatever_another_part_does(L):
    """The still dome's cos-θ term (rays toward the lower left, away from the other dome) is
    the same bit for bit when the other dome doubles its height; with the march ending at the
    whole image's highest point (before) it was not."""
    size = 96
    light = Light("sun", unit(L))
    still = np.zeros((size, size), bool)
    still[:size // 2, :size // 2] = True
    terms = {}
    for bounds in ("path", "image"):
        for tall in (20.0, 40.0):
            z = _domes(size, tall).astype(np.float32)
            n = normals_from_height_px(z).astype(np.float32)
            terms[bounds, tall] = cos_theta_shadow(n, light, 0.01, 64, heights_px=z,
                                                   bounds=bounds)
    assert np.array_equal(terms["path", 20.0][still], terms["path", 40.0][still])
    assert np.abs(terms["image", 20.0] - terms["image", 40.0])[still].max() > 1e-4


def test_the_march_ending_on_its_path_is_closer_to_the_reference():
    """A path-bounded end is never later than the image's, so K steps sample more finely:
    on two domes, final's K = 64 march against K = 4096 is closer than it was."""
    size = 96
    z = _domes(size, 30.0)
    n = normals_from_height_px(z)
    light = Light("sun", unit((0.6, 0.4, 0.45)))
    fine = cos_theta_shadow(n, light, 0.01, 4096, heights_px=z, bounds="image")
    err = {b: np.abs(cos_theta_shadow(n, light, 0.01, 64, heights_px=z, bounds=b) - fine).mean()
           for b in ("path", "image")}
    assert err["path"] < err["image"], err


# -- §6 Reach where the normals fit no height field (issue 39) ----------------------------------
def test_the_circulation_tells_an_impossible_figure_from_an_objects_map():
    """Objects' normal maps (a dome's, from heights) stay under the limit; the Penrose tribar
    is over it at every size."""
    from dynpaint_addon.core.shape import CURL_LIMIT, circulation
    from testkit.example_paintings import penrose_triangle
    y, x = (np.mgrid[0:128, 0:128] + 0.5) / 128
    dome = 30 * np.sqrt(np.clip(1 - ((x - 0.5) ** 2 + (y - 0.5) ** 2) / 0.09, 0, None))
    curl = circulation(slopes_from_normals(normals_from_height_px(dome)))
    assert curl < 0.4 * CURL_LIMIT, curl                # the rim: 0.50
    for size in (128, 256):
        n, _ = penrose_triangle(size)
        assert circulation(slopes_from_normals(n)) > 1.4 * CURL_LIMIT


def test_a_full_frame_map_that_fits_a_height_field_casts_its_whole_shadow():
    """A dome's normal map without an alpha (along the ray): with the defaults its shadow on
    the ground falls as far as its height casts it, beyond shadows.reach (which only an
    impossible figure needs); the Penrose tribar keeps the default reach (no streaks)."""
    from dynpaint_addon import params
    from dynpaint_addon.core.pipeline import shadow_term
    from dynpaint_addon.core.shape import reach_of
    from testkit.example_paintings import penrose_triangle
    size = 128
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    z = 20 * np.sqrt(np.clip(1 - ((x - 0.3) ** 2 + (y - 0.5) ** 2) / 0.01, 0, None))  # 20 px
    n = normals_from_height_px(z).astype(np.float32)
    slopes = slopes_from_normals(n)
    p = params.defaults()
    light = Light("sun", unit((-1.0, 0.0, 0.5)))        # from −x: the shadow falls toward +x
    assert reach_of(p.shadows.reach, slopes) == np.inf
    row = shadow_term(n, None, slopes, light, p)[size // 2]
    ground = (x[0] > 0.42) & (row > 0)
    shade = (x[0] > 0.42) & (row < 0.5 * unit((-1.0, 0.0, 0.5))[2])
    reach = x[0][shade].max() - 0.4                     # 20 px / tan 26.6° = 40 px ≈ 0.31
    assert ground.any() and reach > 4 * p.shadows.reach, reach
    pn, _ = penrose_triangle(size)
    assert reach_of(p.shadows.reach, slopes_from_normals(pn)) == p.shadows.reach


def test_a_march_ending_on_its_path_leaves_a_lit_edge_lit():
    """A box's top edge in float32: the march ends just clear of the path's bound (CLEAR_PX),
    so rounding never leaves the ray 'inside' at its end (whose tail would darken the edge:
    t 0 instead of 0.87 on the wide box of docs/ground-truth.md)."""
    size = 256
    z = np.zeros((size, size), np.float32)
    z[40:80, 150:200] = 30.72
    z[100:160, 20:60] = 61.4
    n = normals_from_height_px(z).astype(np.float32)
    e, a = np.radians(60), np.radians(300)
    light = Light("sun", (np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)))
    path = cos_theta_shadow(n, light, 0.01, 256, heights_px=z, bounds="path")
    image = cos_theta_shadow(n, light, 0.01, 256, heights_px=z, bounds="image")
    assert np.abs(path - image).max() < 0.05, np.abs(path - image).max()
