"""§15 Layers, the core's reference: what the layers in front of a pixel let through along its
§6 ray (issue 30, first step: layers on one canvas, lights without size)."""
import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.bake import own_size_t
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.layers import Layer, Scene, placement, render_scene, scene_notes
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.core.sampling import pixel_centres, resample_separable
from dynpaint_addon.core.occluders import Occluder, on_faces_lattice
from dynpaint_addon.core.transmittance import transmittance
from dynpaint_addon.inputs.recipe import load_images, load_recipe
from dynpaint_addon.inputs.samples import recipe_path
from dynpaint_addon.inputs.testpainting import builtin_scene_layers

N = 64


def plane_origins(z=0.0):
    """P_S of a flat layer at depth z (pixels): its pixel centres."""
    x, y = pixel_centres(N, N, np.float64)
    return np.dstack([x, y, np.full((N, N), z)])


def card(lo, hi, z, thickness=2.0, opacity=1.0):
    """A flat square card covering pixels lo … hi − 1 in x and y."""
    alpha = np.zeros((N, N))
    alpha[lo:hi, lo:hi] = 1.0
    return Occluder(alpha, np.zeros((N, N)), z, thickness, np.full((N, N), opacity))


def card_shadow(lo, hi, z, thickness, direction):
    """Where a flat card's solid (its square, z − thickness … z) shades a plane at z = 0 under
    a sun along `direction`: the union of the square shifted back along the light over the
    card's depths → (certainly in shadow, certainly lit), each with a 2-pixel margin."""
    x, y, _ = np.moveaxis(plane_origins(), -1, 0)
    lx, ly, lz = np.asarray(direction) / np.linalg.norm(direction)
    depths = np.linspace(z - thickness, z, 41)
    dist = np.full((N, N), np.inf)               # distance from the square at any depth
    for d in depths:
        cx, cy = x + lx / lz * d, y + ly / lz * d
        dx = np.maximum(np.maximum(lo - cx, cx - hi), 0)
        dy = np.maximum(np.maximum(lo - cy, cy - hi), 0)
        inside = np.minimum(np.minimum(cx - lo, hi - cx), np.minimum(cy - lo, hi - cy))
        dist = np.minimum(dist, np.where((dx > 0) | (dy > 0), np.hypot(dx, dy), -inside))
    return dist < -2, dist > 2


def test_nothing_in_front_lets_everything_through():
    assert np.array_equal(transmittance(plane_origins(), Light("sun", (0.3, 0.2, 0.9)), []),
                          np.ones((N, N)))


@pytest.mark.parametrize("direction", [(0.0, 0.0, 1.0), (0.3, 0.2, 0.9), (-0.5, 0.4, 0.7)])
def test_an_opaque_card_casts_its_projected_shadow(direction):
    """§15: an opaque card in front of a plane: T = 0 in its shadow (the card's solid
    projected along the light), 1 outside it."""
    t = transmittance(plane_origins(), Light("sun", direction), [card(24, 40, 16.0)])
    shadow, lit = card_shadow(24, 40, 16.0, 2.0, direction)
    assert shadow.sum() > 100 and lit.sum() > 1000
    assert t[shadow].max() == 0.0 and t[lit].min() == 1.0


def test_a_glass_card_lets_its_transparency_through():
    """k = 0.6 (opacity 0.4): 0.6 of the light in its shadow (§15's example)."""
    direction = (0.3, 0.2, 0.9)
    t = transmittance(plane_origins(), Light("sun", direction), [card(24, 40, 16.0, opacity=0.4)])
    shadow, lit = card_shadow(24, 40, 16.0, 2.0, direction)
    assert np.allclose(t[shadow], 0.6) and t[lit].min() == 1.0


def test_two_cards_multiply():
    t = transmittance(plane_origins(), Light("sun", (0, 0, 1)),
                      [card(24, 40, 16.0, opacity=0.5), card(30, 50, 30.0, opacity=0.5)])
    assert t[32, 32] == pytest.approx(0.25) and t[26, 26] == pytest.approx(0.5)
    assert t[45, 45] == pytest.approx(0.5) and t[5, 5] == 1.0


def test_a_point_light_casts_a_central_projection_and_layers_behind_never_shade():
    """Aimed at a point light above the canvas's centre, the pixel under the card is in its
    shadow, a far corner sees the light past it; a card behind the receiver casts nothing;
    a ray that ends at a light below the card is not shaded by it."""
    light = Light("point", (0.0, 0.0, 1.0))         # one image width above the centre
    t = transmittance(plane_origins(), light, [card(28, 36, 16.0)])
    assert t[32, 32] == 0.0 and t[0, 0] == 1.0 and t[63, 63] == 1.0
    behind = transmittance(plane_origins(20.0), light, [card(28, 36, 16.0)])
    assert behind.min() == 1.0
    low = Light("point", (0.0, 0.0, 10.0 / N))       # 10 px up: below the card at 14–16 px
    assert transmittance(plane_origins(), low, [card(28, 36, 16.0)]).min() == 1.0


# -- a scene of layers (render_scene) ------------------------------------------------------

def flat_painting(alpha=None, transparency=None, colour=0.6):
    """A flat painting N×N (a height map of zeros, float), its dark and bright one grey, cut
    out by `alpha` (on the dark image) where given, its transparency map where given."""
    p = params.defaults()
    p.shape.kind = "height"
    p.shadows.enabled = True
    grey = np.full((N, N, 3), colour, np.float32)
    dark = grey if alpha is None else np.dstack([grey, alpha])
    images = {"shape": ImageData(np.zeros((N, N, 1), np.float32), 32),
              "dark": ImageData(dark, 32), "bright": ImageData(grey, 32)}
    if transparency is not None:
        images["transparency"] = ImageData(np.full((N, N, 1), transparency, np.float32), 32)
        p.transparency.amount = 1.0
    return images, p


def square(lo, hi):
    a = np.zeros((N, N), np.float32)
    a[lo:hi, lo:hi] = 1.0
    return a


SUN = (0.5, 0.0, np.sqrt(0.75))      # 30° from the viewer's axis: cos θ = 0.866 on a plane


def back_and_card(card_alpha, depth=0.25, **card):
    back = Layer(*flat_painting(), name="back")
    front = Layer(*flat_painting(card_alpha, **card), name="card", depth=depth)
    return [back, front]


def test_one_layer_renders_as_the_painting_does():
    """§15: one layer is today's painting, bit for bit."""
    recipe = load_recipe(recipe_path("portrait"))
    images = load_images(recipe)
    want = render(images, recipe.lights, recipe.params)
    got = render_scene([Layer(images, recipe.params)], recipe.lights)
    assert np.array_equal(got.rgba, want.rgba)
    assert all(np.array_equal(a, b) for a, b in zip(got.t[0], want.passes["t"]))


def test_an_opaque_card_over_a_plane_gives_zero_in_its_shadow_and_cos_theta_elsewhere():
    scene = render_scene(back_and_card(square(24, 40)), [Light("sun", SUN)])
    t = scene.t[0][0]
    shadow, lit = card_shadow(24, 40, 16.0, 1.0, SUN)
    assert shadow.sum() > 100 and lit.sum() > 1000
    assert t[shadow].max() == 0.0
    assert np.allclose(t[lit], np.sqrt(0.75), atol=1e-3)
    assert np.allclose(scene.t[1][0], np.sqrt(0.75), atol=1e-3)     # nothing in front of it


def test_a_glass_card_lets_k_cos_theta_through():
    scene = render_scene(back_and_card(square(24, 40), transparency=0.6), [Light("sun", SUN)])
    shadow, _ = card_shadow(24, 40, 16.0, 1.0, SUN)
    assert np.allclose(scene.t[0][0][shadow], 0.6 * np.sqrt(0.75), atol=1e-3)


def test_a_card_whose_shadow_misses_the_plane_changes_nothing():
    """A card so far in front that its shadow lands beyond the canvas (128 px up, a 30° sun:
    74 px to the left) leaves the plane's t as it is alone."""
    layers = back_and_card(square(24, 40), depth=2.0)
    alone = render_scene(layers[:1], [Light("sun", SUN)])
    scene = render_scene(layers, [Light("sun", SUN)])
    assert np.array_equal(scene.t[0][0], alone.t[0][0])


def test_the_composite_puts_the_card_over_the_plane():
    scene = render_scene(back_and_card(square(24, 40)), [Light("sun", SUN)])
    card_px, back_px = scene.layers[1].rgba[32, 32], scene.layers[0].rgba[32, 60]
    assert np.allclose(scene.rgba[32, 32], card_px) and np.allclose(scene.rgba[32, 60], back_px)


def test_a_light_with_a_size_widens_the_penumbra_with_the_distance():
    """A 10° sun: the half-shadow band on the plane (2 % … 98 % of the light) is at most
    Δz·tan β wide (the whole disc's spread) and about twice as wide for a card twice as far;
    a hard sun's is a pixel at most."""
    def band(depth, size):
        scene = render_scene(back_and_card(square(20, 44), depth=depth),
                             [Light("sun", (0.0, 0.0, 1.0), size=size)])
        row = scene.t[0][0][32] / scene.t[0][0][32].max()
        return int(((row > 0.02) & (row < 0.98)).sum() / 2)    # one edge of two
    beta = np.radians(10.0)
    assert band(0.25, 0.0) <= 1
    near, far = band(0.25, beta), band(0.5, beta)
    assert 1 <= near <= 16 * np.tan(beta) + 1 and 2 * near - 1 <= far <= 32 * np.tan(beta) + 1


def test_a_penumbra_crosses_half_where_the_edge_is():
    """§15 "Light size": under a 15° sun straight down, a card 40 px above a plane casts a
    penumbra 2R wide (R = 40·tan 7.5° = 5.3 px); T across each of the card's four edges is
    the share of the sun's disc the card leaves uncovered, (acos(−c) + c·√(1 − c²))/π with
    c = (edge − x)/R, within 0.05, and crosses ½ within 0.1 px of the edge. The 16 points
    of a final bake alone are 0.5 px off on two edges (max error 0.07): the rays that they
    leave undecided are sampled again at 64 (transmittance's `penumbra`)."""
    beta, z, lo, hi = np.radians(15.0), 40.0, 14, 50
    radius = z * np.tan(beta / 2)
    t = transmittance(plane_origins(), Light("sun", (0.0, 0.0, 1.0), size=beta),
                      [card(lo, hi, z, 0.5)], disc=16, penumbra=64, antialias=4)
    x = np.arange(N // 2) + 0.5                          # from the frame's side to the middle
    across = {"left": t[N // 2, :N // 2], "top": t[:N // 2, N // 2],
              "right": t[N // 2, ::-1][:N // 2], "bottom": t[::-1, N // 2][:N // 2]}
    for side, row in across.items():
        edge = lo if side in ("left", "top") else N - hi
        c = np.clip((edge - x) / radius, -1.0, 1.0)
        lit = (np.arccos(-c) + c * np.sqrt(1 - c * c)) / np.pi
        assert np.abs(row - lit).max() <= 0.05, side
        assert abs(np.interp(-0.5, -row, x) - edge) <= 0.1, side


def test_a_point_light_sees_a_placed_layer_from_where_it_is():
    """A layer moved and scaled on the canvas is lit by a point light as if the light were
    measured in its own frame: N·L at each of its pixels equals the direction from that
    pixel's place on the canvas to the light."""
    images, p = flat_painting()
    p.shadows.enabled = False
    layer = Layer(images, p, depth=0.1, offset=(0.2, -0.1), scale=0.5)
    light = Light("point", (0.1, 0.2, 0.4))
    scene = render_scene([Layer(*flat_painting()), layer], [light], canvas=(N, N))
    place = placement(layer, (N, N), (N, N))
    x, y = pixel_centres(N, N, np.float64)
    cx, cy, cz = place.to_canvas(x, y, 0.0)
    to = light.position_px(N, N)[None, None, :] - np.dstack([cx, cy, np.full_like(cx, cz)])
    assert np.allclose(scene.t[1][0], to[..., 2] / np.linalg.norm(to, axis=-1), atol=1e-5)


def test_the_fast_paths_find_the_shadows_the_march_finds():
    """Sun tables (a sun over one-opacity layers), line maps (a point light, a glass layer of
    two opacities) and the march of rays that start inside a slab, against every ray marched
    (the reference): the same shadows but for a few edge pixels."""
    layers = [Layer(images, p, name, depth) for name, depth, images, p in builtin_scene_layers(96)]
    half = np.full((96, 96, 1), 0.5, np.float32)
    half[:, :48] = 0.2
    layers[1].images = {**layers[1].images, "transparency": ImageData(half, 32)}
    layers[1].p.transparency.amount = 1.0
    scene = Scene(layers)
    for light in (Light("sun", SUN), Light("point", (0.2, 0.1, 0.6)),
                  Light("sun", (0.0, 0.0, 1.0))):
        for i in (0, 1):
            fast = scene.through(i, [light])[0]
            slow = scene.through(i, [light], "reference")[0]
            assert np.mean(np.abs(fast - slow) > 0.1) < 0.02, (light, i)


def crossing(light, x, y, depth):
    """Where the ray from (x, y, 0) toward a light (canvas N × N) crosses the plane z = depth."""
    if light.kind == "sun":
        lx, ly, lz = np.asarray(light.vector) / np.linalg.norm(light.vector)
        return x + lx / lz * depth, y + ly / lz * depth
    lp = light.position_px(N, N)
    k = depth / lp[2]
    return x + k * (lp[0] - x), y + k * (lp[1] - y)


@pytest.mark.parametrize("light", [Light("sun", (0.45, -0.5, 0.74)),
                                   Light("sun", (-0.2, 0.6, 0.77)),
                                   Light("point", (0.2, 0.1, 0.9))],
                         ids=["sun table", "sun table, steep", "line map"])
@pytest.mark.parametrize("level", ["final", "reference"])
def test_a_straight_edged_shadow_is_each_pixels_share_in_shadow(light, level):
    """The shadow of a card's straight edge between two plain layers (issue 39: 'dots on
    every other pixel along the edges'): at final and reference quality each pixel's T is
    the share of the pixel the shadow covers, as a render's pixel shows it: within 0.15 at
    every pixel (4 × 4 rays across an edge pixel, measured ≤ 0.125; each pixel's centre
    alone: 0.52–0.56) and 0.06 on average along the edge (measured ≤ 0.05)."""
    normal = np.array([np.cos(0.4), np.sin(0.4)])
    c = float(normal @ [N / 2, N / 2])
    sub = 8
    s = (np.arange(N * sub) + 0.5) / sub
    qx, qy = np.meshgrid(s, s)
    alpha = (normal[0] * qx + normal[1] * qy < c).reshape(N, sub, N, sub).mean(axis=(1, 3))
    p = params.defaults()
    p.shape.kind, p.shadows.enabled = "height", True
    grey = np.full((N, N, 3), 0.5, np.float32)
    flat = ImageData(np.zeros((N, N, 1), np.float32), 32)
    back = Layer({"shape": flat, "dark": ImageData(grey, 32), "bright": ImageData(grey, 32)},
                 p, "back", 0.0)
    front = Layer({"shape": flat, "bright": ImageData(grey, 32),
                   "dark": ImageData(np.dstack([grey, alpha]).astype(np.float32), 32)},
                  p, "front", 12 / N, 2 / N)
    t = Scene([back, front]).through(0, [light], level)[0]
    # the card's solid spans depths 10 … 12: a ray meets it at its lower or upper face if at
    # all (the edge test is linear along the ray); each pixel sampled sub × sub times
    shade = np.zeros(qx.shape, bool)
    for depth in (10.0, 12.0):
        cx, cy = crossing(light, qx, qy, depth)
        shade |= normal[0] * cx + normal[1] * cy < c
    want = 1 - shade.reshape(N, sub, N, sub).mean(axis=(1, 3))
    x, y = pixel_centres(N, N, np.float64)
    inside = np.ones((N, N), bool)         # the rays that cross the card's image, not past it
    for depth in (10.0, 12.0):
        cx, cy = crossing(light, x, y, depth)
        inside &= (cx > 2) & (cx < N - 2) & (cy > 2) & (cy < N - 2)
    err = np.abs(t - want)
    edge = inside & (want > 0.02) & (want < 0.98)
    assert edge.sum() > N / 2
    assert err[inside].max() <= 0.15, (err[inside].max(), np.argwhere(inside & (err > 0.15)))
    assert err[edge].mean() <= 0.06, err[edge].mean()


def test_scene_notes_say_what_was_guessed():
    """Layers of another size (placed and resampled), a layer without alpha in front (it
    hides everything behind), equal depths (kept in their order)."""
    small_images, p = flat_painting()
    small = {c: ImageData(img.pixels[::2, ::2], img.bits) for c, img in small_images.items()}
    layers = [Layer(*flat_painting(), name="back"),
              Layer(small, p, name="small", depth=0.1),
              Layer(*flat_painting(), name="opaque", depth=0.1)]
    notes = scene_notes(layers)
    assert "small: its 32×32 pixels are drawn 2× on the 64×64 canvas (resampled)" in notes
    assert any(n.startswith("opaque has no alpha: it covers every layer behind it")
               for n in notes)
    assert "small and opaque are at the same depth: the first listed is behind" in notes
    assert not any(n.startswith("back") for n in notes)


def test_a_normal_map_layer_shadows_by_its_integrated_relief():
    """A dome drawn as a normal map (with its alpha) in front of a plane: the fast paths and
    the march find the same shadow, and it is the dome's, not a flat card's."""
    r = np.hypot(*np.meshgrid(np.arange(N) + 0.5 - 32, np.arange(N) + 0.5 - 32)) / 16
    inside = r < 1
    nz = np.sqrt(np.clip(1 - r ** 2, 0, 1))
    x, y = np.meshgrid(np.arange(N) + 0.5 - 32, np.arange(N) + 0.5 - 32)
    n = np.dstack([np.where(inside, x / 16, 0), np.where(inside, y / 16, 0),
                   np.where(inside, nz, 1)])
    shape = np.dstack([n * 0.5 + 0.5, inside.astype(float)]).astype(np.float32)
    p = params.defaults()
    p.shape.kind, p.shadows.enabled = "normal", True
    dome = {"shape": ImageData(shape, 32), "bright": ImageData(np.full((N, N, 3), 0.7), 32)}
    scene = Scene([Layer(*flat_painting()), Layer(dome, p, "dome", 0.2)])
    low = Light("sun", (0.8, 0.0, 0.6))
    fast = scene.through(0, [low])[0]
    slow = scene.through(0, [low], "reference")[0]
    assert np.mean(np.abs(fast - slow) > 0.1) < 0.02
    assert (fast < 0.5).sum() > (inside.sum() * 1.1)     # taller than a card: a longer shadow


def test_a_receiver_wholly_above_a_layer_takes_nothing_from_it():
    """Rays that start above a layer's slab rise away from it (§15): T = 1, for the sun
    table, the line maps and the march alike."""
    for light in (Light("sun", (0.3, 0.2, 0.9)), Light("point", (0.0, 0.0, 2.0))):
        for maps in (True, False):
            t = transmittance(plane_origins(40.0), light, [card(24, 40, 16.0)], maps=maps)
            assert t.min() == 1.0


def test_a_scene_made_small_bakes_a_draft_as_near_as_the_full_sized_draft():
    """Scene.bake(reduced=f) of the scene drawn f× smaller (a stroke's draft, issue 42):
    each level's reduction divided by f, its t enlarged is about as near the full-size final
    bake as the full-size draft is, and nearer than the small scene's plain draft."""
    light = Light("sun", (0.45, -0.5, 0.74))

    def scene(size):
        return Scene([Layer(images, p, name, depth)
                      for name, depth, images, p in builtin_scene_layers(size)])
    big, small = scene(384), scene(96)
    final, draft = big.bake(light, "final"), big.bake(light, "draft")

    def error(ts):
        return max(float(np.abs(resample_separable(t, *want.shape) - want).mean())
                   for t, want in zip(ts, final))
    reduced, plain = error(small.bake(light, "draft", reduced=4.0)), \
        error(small.bake(light, "draft"))
    assert reduced <= 1.5 * error(draft) and reduced < plain


def test_a_layer_left_alone_keeps_its_own_term_and_the_bake_equals_a_fresh_one():
    """Scene.bake(own=) with an earlier bake's own terms (a stroke's draft, issue 42: the
    layers the stroke left alone): a layer whose light and level are as before takes its
    t_own as it was, the rest are marched, and t equals a fresh bake's bit for bit; a
    turned light is marched again."""
    light, turned = Light("sun", (0.45, -0.5, 0.74)), Light("sun", (-0.3, 0.4, 0.8))
    layers = [Layer(images, p, name, depth)
              for name, depth, images, p in builtin_scene_layers(64)]
    first = Scene(layers)
    first.bake(light, "draft")
    edited = dict(layers[-1].images)
    edited["shape"] = ImageData(np.roll(edited["shape"].pixels, 5, axis=1),
                                edited["shape"].bits)
    layers[-1] = Layer(edited, layers[-1].p, layers[-1].name, layers[-1].depth)
    left_alone = {i: first.own[i] for i in range(len(layers) - 1)}
    for lt, kept in ((light, True), (turned, False)):
        scene = Scene(layers, prepared={i: first.ready[i] for i in left_alone})
        t = scene.bake(lt, "draft", own=left_alone)
        assert all((scene.own[i][1] is left_alone[i][1]) == kept for i in left_alone)
        assert all(np.array_equal(a, b) for a, b in zip(t, Scene(layers).bake(lt, "draft")))


def test_a_drags_draft_at_its_own_size_is_as_near_the_final_as_the_full_sized_draft():
    """Scene.bake(own_size=True) (a dragged light's draft, written as small images that every
    backend enlarges alike; issue 62: nothing upsampled): the layer with nothing in front is
    its own term's reduced bake bit for bit, a shadowed one t_own·T at that size — enlarged,
    about as near the final as the full-sized draft (the product of the enlarged terms):
    measured 5–11 % farther at 384², within 3 % from 768² — and a final bake is the same
    either way."""
    light = Light("sun", (0.45, -0.5, 0.74))
    layers = [Layer(images, p, name, depth)
              for name, depth, images, p in builtin_scene_layers(384)]
    final = Scene(layers).bake(light, "final")
    full, small = Scene(layers).bake(light, "draft"), Scene(layers).bake(light, "draft",
                                                                       own_size=True)
    assert all(s.shape == (96, 96) for s in small)
    np.testing.assert_array_equal(small[-1], own_size_t(full[-1]))
    for s, f, want in zip(small[:-1], full[:-1], final):
        enlarged = np.clip(resample_separable(s, *f.shape), 0, 1)
        assert np.abs(enlarged - want).mean() <= 1.15 * np.abs(f - want).mean()
    assert all(np.array_equal(a, b) for a, b in zip(final, Scene(layers).bake(
        light, "final", own_size=True)))


@pytest.mark.parametrize("light", [Light("sun", (0.45, -0.5, 0.74), size=0.05),
                                   Light("point", (0.3, 0.2, 0.6), size=0.03)],
                         ids=["sun", "point"])
def test_a_scene_edited_in_a_box_patches_its_bake_and_equals_a_fresh_one(light, monkeypatch):
    """Scene(before=) of a scene whose one layer an edit changed (a stroke, issue 61): its
    final bake equals a fresh scene's bit for bit — a dab inside the front layer's relief
    (its slab kept), one that raises it (its slab moves: τ follows the tallest relief), one on
    the middle layer, and the front layer's heights moved a little everywhere (a part
    inflated again: under TOLERANCE far from the stroke, τ by a thousandth of a pixel) —
    while only the pixels whose rays can meet the change are traced again (for a small
    move, those on the edges of its shadow), and the edited layer's own term is patched,
    not baked whole."""
    import dynpaint_addon.core.layers as core_layers
    size = 48
    layers = [Layer(images, p, name, depth)
              for name, depth, images, p in builtin_scene_layers(size)]
    first = Scene(layers)
    first.bake(light, "final")
    traced = []
    whole = core_layers.transmittance
    monkeypatch.setattr(core_layers, "transmittance", lambda o, *a, only=None, **k: traced.append(
        o.shape[0] * o.shape[1] if only is None else int(only.sum())) or whole(o, *a, only=only,
                                                                               **k))

    def lifted(px, lift):
        px[25:28, 19:22] += lift
        return px
    edits = [(2, lambda px: lifted(px, -0.02), 0.6), (2, lambda px: lifted(px, 0.3), 0.6),
             (1, lambda px: lifted(px, 0.05), 0.6), (2, lambda px: px * np.float32(1.0003), 0.4)]
    for which, edit, share in edits:
        images = dict(layers[which].images)
        images["shape"] = ImageData(edit(images["shape"].pixels.copy()), images["shape"].bits)
        edited = list(layers)
        edited[which] = Layer(images, layers[which].p, layers[which].name, layers[which].depth)
        traced.clear()
        patched = Scene(edited, prepared={i: first.ready[i] for i in range(len(layers))
                                          if i != which}, before=first)
        t = patched.bake(light, "final")
        assert sum(traced) < share * size * size * which       # the layers behind: a part
        assert all(np.array_equal(a, b) for a, b in zip(t, Scene(edited).bake(light, "final")))


@pytest.mark.parametrize("light", [Light("sun", (0.45, -0.5, 0.74), size=0.05),
                                   Light("point", (0.3, 0.2, 0.6), size=0.03)],
                         ids=["sun", "point"])
def test_edits_patched_by_their_clearance_equal_fresh_bakes_and_trace_fewer_pixels(
        light, monkeypatch):
    """core/layer_edits.rays_lifted (issue 61): a part of the front layer inflated again
    (its heights moved by ½ px at a dab and by thousandths of a pixel 20 px away, its slab
    kept), a dab that paints it bigger (α grows), one that erases it (α shrinks), each
    patched from the one before (the clearances kept shrink by each move): every patched
    bake equals a fresh one bit for bit, and with a sun (the table's clearances) fewer
    pixels are traced than by the rule that knows no clearance (rays_changed alone)."""
    import dynpaint_addon.core.layers as core_layers
    size = 64
    layers = [Layer(images, p, name, depth)
              for name, depth, images, p in builtin_scene_layers(size)]
    x, y = (np.arange(size)[None, :] + 0.5) / size, (np.arange(size)[:, None] + 0.5) / size
    near = np.hypot(x - 0.47, y - 0.35) * size                  # px from the dab, on an arm
    tip = np.hypot(x - 0.55, y - 0.35) < 0.03                   # past an arm's tip

    def inflated(images):
        shape = images["shape"].pixels
        lift = np.float32(0.13) * np.exp(-near / 3.0).astype(np.float32)[..., None]
        lift *= shape > 0
        return {**images, "shape": ImageData(shape + lift, images["shape"].bits)}

    def cut(alpha):
        def edit(images):
            dark = images["dark"].pixels.copy()
            dark[..., 3] = np.where(tip, alpha, dark[..., 3])
            return {**images, "dark": ImageData(dark, images["dark"].bits)}
        return edit
    traced = []
    whole = core_layers.transmittance
    monkeypatch.setattr(core_layers, "transmittance", lambda o, *a, only=None, **k: traced.append(
        o.shape[0] * o.shape[1] if only is None else int(only.sum())) or whole(o, *a, only=only,
                                                                               **k))

    fresh = {}

    def patched_chain():
        scene = Scene(layers)
        scene.bake(light, "final")
        counts, edited = [], list(layers)
        for step, edit in enumerate((inflated, cut(1.0), inflated, cut(0.0))):
            edited[2] = Layer(edit(dict(edited[2].images)), layers[2].p, layers[2].name,
                              layers[2].depth)
            traced.clear()
            scene = Scene(list(edited), prepared={i: scene.ready[i] for i in (0, 1)},
                          before=scene)
            t = scene.bake(light, "final")
            counts.append(sum(traced))
            if step not in fresh:
                fresh[step] = Scene(edited).bake(light, "final")
            assert all(np.array_equal(a, b) for a, b in zip(t, fresh[step]))
        return counts
    with_clearance = patched_chain()
    monkeypatch.setattr(core_layers, "rays_lifted", lambda origins, *a: (
        np.ones(origins.shape[:2], bool), np.zeros(origins.shape[:2], np.float32)))
    without = patched_chain()
    assert all(0 < a <= b for a, b in zip(with_clearance, without))
    if light.kind == "sun":
        assert sum(with_clearance) < 0.6 * sum(without)


CLEARANCE_LIGHTS = {"sun": Light("sun", (0.6, 0.3, 0.5), size=0.05),
                    "hard sun": Light("sun", (-0.8, 0.2, 0.45)),
                    "point": Light("point", (-0.3, 0.1, 0.35), size=0.03)}


@pytest.mark.parametrize("quality, light, glass", [
    (q, name, False) for q in ("final", "draft", "reference") for name in CLEARANCE_LIGHTS
    if q != "reference" or name == "hard sun"] + [("final", "hard sun", True)])
def test_a_pixels_clearance_bounds_the_relief_move_that_can_change_its_T(light, quality,
                                                                         glass):
    """transmittance's `clearance`: a pixel whose rays all keep their answers keeps its T —
    every relief moved by a random amount up to δ (noise, not a smooth move), a pixel whose
    clearance and whose neighbours' exceed δ + CLEARANCE has the same T after, bit for bit
    (the neighbours: the edge test compares them); and some pixels do change. A layer of
    one opacity (a sun's table), and of two (glass: the march's first point inside gives
    its ρ). (The reference only with a hard sun: a sized light's 256 points take 3–12 s.)"""
    from dynpaint_addon.core.layer_edits import CLEARANCE
    from dynpaint_addon.core.layers import LAYER_QUALITY
    from dynpaint_addon.core.strokes import widened
    rng, light = np.random.default_rng(7), CLEARANCE_LIGHTS[light]
    n = 40
    yy, xx = np.mgrid[0:n, 0:n]
    dome = np.clip(4.9 - np.hypot(xx - 20, yy - 20) / 2, 0, None).astype(np.float32)
    alpha = (dome > 0).astype(np.float32)
    q = LAYER_QUALITY[quality]
    origins = np.dstack([xx + 0.5, yy + 0.5, np.zeros((n, n))]).astype(np.float32)
    options = dict(canvas=(n, n), spacing=q["spacing"], disc=q["disc"],
                   penumbra=q["penumbra"], maps=quality != "reference",
                   antialias=q["antialias"], edge_points=q["edge_points"])
    rho = np.where(xx < 20, 1.0, 0.5) if glass else np.ones((n, n))
    front = Occluder(alpha, dome, 3.0, 2.0, rho)
    t, clear = transmittance(origins, light, [front], **options, clearance=True)
    changed = 0
    for delta in (0.003, 0.03, 0.3):
        noise = rng.uniform(-delta, delta, dome.shape).astype(np.float32)
        noise[20, 20] = 0.0                            # (the tallest kept: the slab stays)
        moved = Occluder(alpha, np.clip(dome + noise * (dome > 0), 0, 5.0), 3.0, 2.0, rho)
        assert moved.top == front.top
        after = transmittance(origins, light, [moved], **options)
        kept = ~widened(~(clear > delta + CLEARANCE))
        assert np.array_equal(after[kept], t[kept]), delta
        changed += int((after != t).sum())
    assert changed > 0


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_layers_baked_side_by_side_come_back_in_order_and_raise_where_one_fails(threads):
    """Scene.bake's threads (core/layers._side_by_side): results in the layers' order however
    long each takes, in daemon threads (a quitting Blender does not wait), and a layer's
    exception raised in the caller's thread when its turn comes."""
    import threading
    import time
    from dynpaint_addon.core.layers import _side_by_side
    seen = []

    def slow(i):
        time.sleep(0.02 * (3 - i))
        seen.append(threading.current_thread().daemon)
        return i * i
    assert list(_side_by_side(slow, range(4), threads)) == [0, 1, 4, 9]
    assert all(seen) == (threads > 1)

    def failing(i):
        if i == 2:
            raise ValueError("layer 2")
        return i
    got = _side_by_side(failing, range(4), threads)
    assert [next(got), next(got)] == [0, 1]
    with pytest.raises(ValueError, match="layer 2"):
        next(got)


def test_an_occluders_change_is_moved_where_it_moved_far_and_grazed_where_it_moved_little():
    """core/layer_edits.solid_change (§15 "An edited scene"): a relief raised by more than
    ¼ px in a box is `moved` there (every ray meeting it traced); heights that moved by
    less everywhere with a thickness that moved graze the whole solid, where τ is its
    default (the tallest relief on the faces' lattice) and stays, only the part that moved;
    a layer moved ½ px in depth moves the whole solid; and only the pixels near an edge of
    T before the edit are traced for a graze (near_edges)."""
    from dynpaint_addon.core.layer_edits import SLAB_SHIFT, near_edges, solid_change
    y, x = np.mgrid[0:32, 0:32]
    dome = np.clip(8 - np.hypot(x - 16, y - 16) / 2, 0, None).astype(np.float32)
    alpha, ones = (dome > 0).astype(np.float32), np.ones((32, 32), np.float32)
    old = Occluder(alpha, dome, 40.0, 8.0, ones)
    assert solid_change(old, Occluder(alpha, dome.copy(), 40.0, 8.0, ones)) is None
    bumped = dome.copy()
    bumped[20:23, 10:12] += 0.5                         # below the top: the slab kept
    change = solid_change(old, Occluder(alpha, bumped, 40.0, 8.0, ones))
    assert change.grazed is None and change.moved[:4] == (8.0, 18.0, 14.0, 25.0)
    swollen = solid_change(old, Occluder(alpha, dome * np.float32(1.0003), 40.0, 8.0024, ones))
    assert swollen.moved is None and swollen.shift <= SLAB_SHIFT
    assert swollen.grazed[:4] == (-1.0, -1.0, 34.0, 34.0)      # the whole solid, grown
    deeper = solid_change(old, Occluder(alpha, dome, 40.5, 8.0, ones))
    assert deeper.grazed is None and deeper.moved[:4] == (-1.0, -1.0, 34.0, 34.0)
    # a part of a layer of two inflated again, its tallest point moving by hundredths of a
    # pixel under the faces' lattice (τ its default, FACE_STEP): the slab's faces kept, only
    # that part grazed, not the other part (x 38–44)
    y, x = np.mgrid[0:32, 0:48]
    two = np.clip(7.9 - np.hypot(x - 16, y - 16) / 2, 0, None).astype(np.float32)
    two[4:12, 38:44] = 1.0
    alpha2, ones2 = (two > 0).astype(np.float32), np.ones(two.shape, np.float32)

    def layer(relief):
        return Occluder(alpha2, relief, 40.0, on_faces_lattice(float(relief.max())), ones2)
    swelled = two.copy()
    swelled[:, :34] *= np.float32(1.003)
    part = solid_change(layer(two), layer(swelled))
    assert layer(two).top == layer(swelled).top and part.moved is None
    assert part.grazed[:4] == (-1.0, -1.0, 34.0, 34.0) and layer(two).box[2] == 44.0
    t = np.ones((12, 12))
    t[:, 6:] = 0.0                                      # a shadow's edge between columns 5, 6
    assert np.flatnonzero(near_edges(t, 2).any(axis=0)).tolist() == [3, 4, 5, 6, 7, 8]
