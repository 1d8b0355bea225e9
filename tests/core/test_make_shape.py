"""Shape from the painting (issue 16): each method's exact cases and its extremes, bpy-free.

Integration of a plane and a smooth bump, the residual of a field no height map has, masks
that cut a figure from its background, a ramp whose hidden wall is known; inflation of a disc
into a hemisphere; lighting profiles rendered by the core itself; the red/green photograph;
NaN-free on empty, one-pixel, flat and non-square inputs.
"""
import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.inflate import PROFILES, RESHAPED, inflate
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.integrate import components, integrate
from dynpaint_addon.core.laplace import Grid, _coarsest_inverse, poisson_neumann, solve
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.occlusion import ambient_occlusion
from dynpaint_addon.core.photometric import (normals_from_profiles, normals_from_rg_photo,
                                             profile_directions)
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.inputs.channel_names import sprite_lamp_side
from dynpaint_addon.shapes.maker import encode_normals, figure_mask, normals_of_height
from dynpaint_addon.shapes.methods import make_shape


def grid_xy(h, w):
    """Pixel centres in image widths from the image's centre (y up)."""
    y, x = (np.mgrid[0:h, 0:w] + 0.5) / w
    return x - 0.5, y - h / w / 2


def bump(h=96, w=128, top=0.08):
    """A smooth Gaussian hill (image widths) and its §2 normals."""
    x, y = grid_xy(h, w)
    z = top * np.exp(-(x * x + y * y) / (2 * 0.12 ** 2))
    return z, normals_of_height(z)


def angle_deg(a, b):
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1, 1)))


def test_poisson_neumann_solves_the_grid_laplacian_exactly():
    b = np.random.default_rng(0).normal(size=(9, 13))
    b -= b.mean()
    z = poisson_neumann(b)
    full = Grid(np.ones((9, 12)), np.ones((8, 13)))
    assert np.abs(full.apply(z) - b).max() < 1e-12


def test_a_plane_integrates_exactly_with_no_residual():
    h, w = 40, 60
    n = np.zeros((h, w, 3))
    n[..., 0], n[..., 1], n[..., 2] = -0.2, 0.1, 1.0
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    r = integrate(n)
    x, y = grid_xy(h, w)
    expected = 0.2 * x - 0.1 * y
    assert np.abs((r.height - r.height.mean()) - (expected - expected.mean())).max() < 1e-12
    assert r.residual_share < 1e-12 and r.residual.max() < 1e-10


def test_a_smooth_bump_comes_back_within_half_a_percent_of_its_relief():
    z, n = bump()
    r = integrate(n)
    err = np.abs((r.height - r.height.min()) - (z - z.min()))
    assert err.max() < 0.005 * np.ptp(z)
    assert r.residual_share < 0.01


def test_a_pure_curl_has_no_height_and_is_all_residual():
    """g = (∂ψ/∂y, −∂ψ/∂x) has no divergence: the least-squares height is flat, the whole
    field is residual (a painted, impossible normal map's case)."""
    h, w = 64, 64
    x, y = grid_xy(h, w)
    psi = np.exp(-(x * x + y * y) / (2 * 0.1 ** 2))
    dpsi_dy, dpsi_dx = np.gradient(psi, 1 / w)
    p, q = dpsi_dy, -dpsi_dx                       # slopes ∂z/∂x, ∂z/∂y
    n = np.dstack([-p, -q, np.ones_like(p)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    r = integrate(n)
    assert np.ptp(r.height) < 0.02 * np.abs(p).max() * 0.1    # flat next to the field's scale
    assert r.residual_share > 0.95
    # the bump plus the curl: the bump comes back, the curl is the residual
    z, nb = bump(h, w)
    gb = -nb[..., :2] / nb[..., 2:]
    g = gb + np.dstack([p, q]) * 0.3
    mixed = np.dstack([-g[..., 0], -g[..., 1], np.ones((h, w))])
    mixed /= np.linalg.norm(mixed, axis=2, keepdims=True)
    rm = integrate(mixed)
    assert np.abs((rm.height - rm.height.min()) - (z - z.min())).max() < 0.02 * np.ptp(z)
    curl_share = np.sqrt(np.sum((0.3 * np.dstack([p, q])) ** 2) / np.sum(g * g))
    assert rm.residual_share == pytest.approx(curl_share, rel=0.05)


def test_a_box_needs_its_mask_and_depth():
    """A raised flat square: its normals are all (0, 0, 1), so nothing but the mask and the
    depth can say it stands out; with them its top comes back exactly."""
    h, w = 48, 64
    n = np.zeros((h, w, 3))
    n[..., 2] = 1
    box = np.zeros((h, w), bool)
    box[10:30, 20:44] = True
    assert np.ptp(integrate(n).height) == 0
    r = integrate(n, box, depth=0.1)
    assert np.allclose(r.height[box], 0.1) and np.allclose(r.height[~box], 0)
    assert r.parts == 2


def test_a_ramp_around_a_hidden_wall_comes_back_once_the_wall_is_known():
    """A spiral ramp z = a·θ/2π climbs once around its centre and drops by `a` at a wall along
    θ = 0. Its normals are smooth everywhere (the wall is invisible to them) and their slope
    field has no divergence, so least squares finds next to no height; cut at the wall
    (`breaks`), the ramp comes back to 2 % of its drop (the field turns within a pixel at the
    centre, which the edges' mean slopes cannot follow)."""
    h = w = 96
    a = 0.1
    x, y = grid_xy(h, w)
    r2 = x * x + y * y
    p, q = -a / (2 * np.pi) * y / r2, a / (2 * np.pi) * x / r2      # ∂z/∂x, ∂z/∂y of a·θ/2π
    n = np.dstack([-p, -q, np.ones_like(p)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    assert np.ptp(integrate(n).height) < 0.05 * a       # a twentieth of the ramp
    wall_x = np.zeros((h, w - 1), bool)
    wall_y = np.zeros((h - 1, w), bool)
    wall_y[h // 2 - 1, w // 2:] = True              # between the rows either side of θ = 0
    got = integrate(n, breaks=(wall_x, wall_y))
    truth = a * (np.arctan2(y, x) % (2 * np.pi)) / (2 * np.pi)
    away = r2 > 0.1 ** 2
    err = np.abs((got.height - got.height[away].mean()) - (truth - truth[away].mean()))[away]
    assert err.max() < 0.02 * a and err.mean() < 0.01 * a
    assert got.parts == 1


def test_each_part_of_a_mask_is_integrated_on_its_own():
    """Two tilted plates on a flat ground: each plate is a plane (no residual), its border
    stands `depth` above the ground on average."""
    h, w = 50, 80
    n = np.zeros((h, w, 3))
    n[..., 2] = 1
    mask = np.zeros((h, w), bool)
    mask[5:25, 5:30] = True
    mask[30:45, 40:75] = True
    n[mask] = [-0.3, 0.0, 1.0]
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    r = integrate(n, mask, depth=0.05)
    assert r.parts == 3 and r.residual_share < 1e-6
    rows = r.height[10, 5:30]
    assert np.allclose(np.diff(rows), 0.3 / w, rtol=1e-6)          # slope 0.3 kept
    assert np.allclose(r.height[~mask], r.height[0, 0])


def test_components_counts_parts_joined_by_edges():
    mask = np.zeros((6, 7), bool)
    mask[1:3, 1:3] = True
    mask[4, 5] = True
    wx, wy = mask[:, 1:] == mask[:, :-1], mask[1:, :] == mask[:-1, :]
    labels, count = components(wx, wy)
    assert count == 3 and labels[1, 1] == labels[2, 2] != labels[4, 5]


def test_a_disc_inflates_into_a_hemisphere():
    size, radius = 256, 0.4
    x, y = grid_xy(size, size)
    r2 = x * x + y * y
    disc = r2 < radius ** 2
    result = inflate(disc)
    true = np.sqrt(np.clip(radius ** 2 - r2, 0, None))
    inner = r2 < (0.9 * radius) ** 2
    assert abs(result.height.max() - radius) < 0.01 * radius
    assert np.abs(result.height - true)[inner].max() < 0.01 * radius
    assert np.all(result.height[~disc] == 0)


@pytest.mark.parametrize("profile", RESHAPED)
def test_profiles_share_the_round_peak_and_stay_inside(profile):
    x, y = grid_xy(64, 80)
    mask = (np.abs(x) < 0.3) & (np.abs(y) < 0.2)
    z = inflate(mask, profile).height
    top = inflate(mask, "round").height.max()
    assert z.max() == pytest.approx(top) and np.all(z[~mask] == 0) and np.all(z >= 0)
    if profile == "flat":
        assert np.mean(z[mask] > 0.99 * top) > 0.2          # a plateau
    if profile == "soft":
        assert np.mean(z[mask]) < np.mean(inflate(mask, "round").height[mask])


def test_the_tube_profile_gives_a_disc_its_hemisphere_a_ring_its_torus_a_strip_its_cylinder():
    """Round cross-sections as wide as the figure (core/inflate's docstring): where the round
    profile makes a ring's tube and a strip half as tall again, the tube profile is within
    1.5 pixels over the inner half of each cross-section and at its top (256²; the edge is
    read between pixel centres)."""
    size = 256
    x, y = grid_xy(size, size)
    r = np.hypot(x, y)
    disc = r < 0.4
    hemisphere = np.sqrt(np.clip(0.4 ** 2 - r * r, 0, None))
    ring = (r > 0.2) & (r < 0.4)
    torus = np.sqrt(np.clip(0.1 ** 2 - (r - 0.3) ** 2, 0, None))
    strip = (np.abs(y) < 0.1) & (np.abs(x) < 0.45)
    cylinder = np.sqrt(np.clip(0.1 ** 2 - y * y, 0, None))
    middle = np.abs(x) < 0.3                       # away from the strip's rounded ends
    # near the edge the profile is steep: half a pixel there is much of the height
    inner = ((disc, hemisphere, r < 0.2, 0.4), (ring, torus, np.abs(r - 0.3) < 0.05, 0.1),
             (strip, cylinder, (np.abs(y) < 0.05) & middle, 0.1))
    for mask, true, where, radius in inner:
        tube = inflate(mask, "tube").height
        assert np.abs(tube - true)[where].max() < 1.5 / size
        assert abs(tube.max() - radius) < 1.5 / size
        assert np.all(tube[~mask] == 0) and np.all(tube >= 0)
    assert inflate(ring).height.max() > 1.4 * 0.1 > 1.3 * inflate(ring, "tube").height.max()
    assert inflate(strip).height[strip & middle].max() > 1.35 * 0.1


def test_the_tube_profile_keeps_each_part_bit_for_bit_when_another_moves():
    """§16: a figure's heights depend on its own pixels only, whatever else the image holds."""
    x, y = grid_xy(96, 128)
    still = (x + 0.25) ** 2 / 0.15 ** 2 + y * y / 0.3 ** 2 < 1
    moved = [still | ((x - c) ** 2 + y * y < 0.1 ** 2) for c in (0.15, 0.3)]
    a, b = (inflate(m, "tube").height for m in moved)
    assert np.array_equal(a[still], b[still]) and not np.array_equal(a, b)


def test_inflated_detail_follows_the_luminance():
    x, y = grid_xy(64, 64)
    disc = x * x + y * y < 0.35 ** 2
    lum = (x > 0).astype(float)
    plain = inflate(disc).height
    embossed = inflate(disc, detail=0.02, luminance=lum, detail_blur=0.0).height
    diff = embossed - plain
    assert diff[disc & (x > 0.05)].mean() > diff[disc & (x < -0.05)].mean() + 0.015


def core_profiles(n, sides, elevation):
    """Each profile rendered by the numpy core: black dark image, white bright one, linear
    mix, a sun from that side: the image is max(N·L, 0) (§4–§5)."""
    h, w = n.shape[:2]
    p = params.defaults()
    p.diffuse.mix_space = "linear"
    images = {"shape": ImageData(((n + 1) / 2).astype(np.float32), 32),
              "dark": ImageData(np.zeros((h, w, 3), np.float32), 32),
              "bright": ImageData(np.ones((h, w, 3), np.float32), 32)}
    dirs = profile_directions(sides, elevation)
    return {s: render(images, [Light("sun", tuple(d))], p, np.float64).rgba[..., 0]
            for s, d in dirs.items()}


def sphere_normals(size=96, radius=0.45):
    x, y = grid_xy(size, size)
    z = np.sqrt(np.clip(radius ** 2 - x * x - y * y, 0, None))
    n = np.dstack([x, y, np.maximum(z, 0.3 * radius)])
    return n / np.linalg.norm(n, axis=2, keepdims=True), x * x + y * y < (0.95 * radius) ** 2


@pytest.mark.parametrize("sides,limit", [
    (("left", "right", "top", "bottom", "front"), 0.01),
    (("left", "right", "top", "bottom"), 0.05),     # steep pixels seen by two: completed
    (("left", "right", "top"), 5.0),
    (("left", "right"), 30.0)])                     # N.y's sign is unseen: a prior
def test_profiles_rendered_by_the_core_give_back_its_normals(sides, limit):
    n, inside = sphere_normals()
    shots = core_profiles(n, sides, 35.0)
    got = normals_from_profiles(shots, 35.0)
    err = angle_deg(got, n)[inside]
    assert np.all(np.isfinite(got)) and np.mean(err) < limit, np.mean(err)


def test_the_red_green_photograph_is_a_normal_map():
    n, _ = sphere_normals(32)
    photo = (n + 1) / 2
    assert np.abs(normals_from_rg_photo(photo) - n).max() < 1e-9
    mirrored = photo.copy()
    mirrored[..., 0] = 1 - mirrored[..., 0]
    mirrored[..., 1] = 1 - mirrored[..., 1]
    assert np.abs(normals_from_rg_photo(mirrored, "left", "bottom") - n).max() < 1e-9


def test_sprite_lamp_names_say_the_side():
    assert [sprite_lamp_side(p) for p in ("a/portrait_left.png", "Bob-Top.PNG",
                                          "x_front.tif", "leftover.png")] == \
        ["left", "top", "front", None]


def test_export_helpers():
    n = np.array([[[0.0, 0.6, 0.8]]])
    assert encode_normals(n, "directx")[0, 0].tolist() == pytest.approx([0.5, 0.2, 0.9])
    assert encode_normals(n)[0, 0].tolist() == pytest.approx([0.5, 0.8, 0.9])
    pit = np.zeros((32, 32))
    pit[12:20, 12:20] = -0.05
    ao = ambient_occlusion(pit, radius=0.2)
    assert ao[16, 16] < 0.75 and ao[0, 0] == 1.0      # walls 0.05 high, 4 px away


def test_figure_mask_reads_alpha_else_a_painted_mask():
    rgba = np.ones((4, 5, 4), np.float32)
    rgba[..., 3] = 0
    rgba[1:3, 1:3, 3] = 1
    assert figure_mask(ImageData(rgba, 8)).sum() == 4
    red = np.zeros((4, 5, 3), np.float32)
    red[0, :, 0] = 1
    assert figure_mask(ImageData(red, 8)).sum() == 5


@pytest.mark.parametrize("h,w", [(1, 1), (1, 9), (7, 1), (5, 8), (33, 17)])
def test_every_method_is_finite_on_tiny_flat_empty_and_one_pixel_inputs(h, w):
    flat = np.zeros((h, w, 3))
    flat[..., 2] = 1
    empty = np.zeros((h, w), bool)
    one = empty.copy()
    one[h // 2, w // 2] = True
    for mask in (None, empty, one, ~empty):
        r = integrate(flat, mask)
        assert np.all(np.isfinite(r.height)) and np.all(np.isfinite(r.residual))
        assert np.ptp(r.height) == 0
    for mask in (empty, one, ~empty):
        for profile in PROFILES:
            z = inflate(mask, profile, detail=0.01, luminance=np.zeros((h, w))).height
            assert np.all(np.isfinite(z)) and np.all(z >= 0)
    dark = {s: np.zeros((h, w)) for s in ("left", "right", "top", "bottom")}
    assert np.all(np.isfinite(normals_from_profiles(dark)))
    assert np.all(np.isfinite(normals_from_rg_photo(np.zeros((h, w, 3)))))
    assert np.all(np.isfinite(ambient_occlusion(np.zeros((h, w)))))


def test_the_multigrid_solver_handles_cut_and_held_pixels():
    """A 1-D chain cut in two, one end held at 0: each part solved (consistent singular part
    included)."""
    rng = np.random.default_rng(1)
    wx = np.ones((30, 39))
    wx[:, 19] = 0                                     # cut between columns 19 and 20
    wy = np.ones((29, 40))
    d = np.zeros((30, 40))
    d[:, 0] = 1                                       # the left part held at 0 beyond its edge
    grid = Grid(wx, wy, d)
    b = rng.normal(size=(30, 40))
    b[:, 20:] -= b[:, 20:].mean()                     # the free right part: sources sum to 0
    z, it, res = solve(grid, b, tol=1e-10)
    assert res < 1e-10 and np.abs(grid.apply(z) - b).max() < 1e-8 and it < 40


def test_normal_map_shadows_fall_from_the_integrated_relief():
    """§6 Relief: a normal map's shadows marched over its integrated height, which on a real
    shape is the true one; the paper's along-the-ray rebuild is kept (and is what 'auto'
    picks for a map without an alpha: docs/relief-choice.md)."""
    from dynpaint_addon.core.pipeline import shape_normals
    from dynpaint_addon.core.shadow import cos_theta_shadow
    size = 96
    x, y = grid_xy(size, size)
    z = np.sqrt(np.clip(0.3 ** 2 - x * x - y * y, 0, None))          # a hemisphere
    n = normals_of_height(z)
    image = ImageData(((n + 1) / 2).astype(np.float32), 32)
    p = params.defaults()
    assert p.shadows.relief == "auto" and shape_normals(image, p)[1] is None   # no alpha
    p.shadows.relief = "integrated"
    sun = Light("sun", (np.cos(np.radians(30)), 0.0, np.sin(np.radians(30))))
    n32, relief, slopes = shape_normals(image, p)
    assert slopes is None and abs(relief.max() / size - 0.3) < 0.02
    truth = cos_theta_shadow(n32, sun, 0.01, 256, heights_px=(z * size).astype(np.float32))
    integrated = cos_theta_shadow(n32, sun, 0.01, 256, heights_px=relief)
    p.shadows.relief = "along_ray"
    _, none, slopes = shape_normals(image, p)
    assert none is None
    along = cos_theta_shadow(n32, sun, 0.01, 256, slopes=slopes, reach=p.shadows.reach)
    err_int, err_ray = np.abs(integrated - truth).mean(), np.abs(along - truth).mean()
    assert err_int < 0.01 and err_int < 0.5 * err_ray, (err_int, err_ray)


def test_a_soft_shadow_in_one_of_four_profiles_is_left_out():
    """Painted shadows are seldom black: a profile darkened to 30 % where a shadow falls is
    found darker than the other three predict and dropped."""
    n, inside = sphere_normals()
    shots = core_profiles(n, ("left", "right", "top", "bottom"), 45.0)
    x, _ = grid_xy(*n.shape[:2])
    shadow = (x > 0.05) & (shots["left"] > 0.2)
    lit_by_all = np.all([s > 0.05 for s in shots.values()], axis=0)   # before the shadow
    shots["left"] = np.where(shadow, 0.3 * shots["left"], shots["left"])
    err = angle_deg(normals_from_profiles(shots, 45.0), n)
    where = inside & shadow & lit_by_all        # three others left to decide alone
    assert where.sum() > 100 and err[where].mean() < 0.1, err[where].mean()


def test_an_opaque_alpha_cuts_nothing_when_integrating():
    """The figure of a normal map is its alpha ≥ ½, the rule the shadow relief uses: an
    alpha opaque everywhere cuts nothing (it was read as the map's luminance instead)."""
    _, n = bump(48, 64)
    rgba = np.concatenate([(n + 1) / 2, np.ones(n.shape[:2] + (1,))], -1)
    p = params.defaults()
    _, cut, _ = make_shape("integrate", {"shape": ImageData(rgba.astype(np.float32), 32)}, p)
    _, plain, _ = make_shape("integrate", {"shape": ImageData(rgba[..., :3].astype(np.float32),
                                                                32)}, p)
    assert np.allclose(cut[..., 0], plain[..., 0], atol=1e-9)


def test_the_command_line_is_generated_from_the_one_table():
    """make-shape METHOD takes exactly the table's options for it (shapes.methods.OPTIONS, issue
    28), each range checked by Option.check as the operator's sliders clamp."""
    import argparse
    from dynpaint_addon.cli import build_parser
    from dynpaint_addon.shapes.methods import METHODS, options
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    methods = next(a for a in sub.choices["make-shape"]._actions
                   if isinstance(a, argparse._SubParsersAction))
    assert set(methods.choices) == {m.command for m in METHODS.values()}
    for name, method in METHODS.items():
        dests = {a.dest for a in methods.choices[method.command]._actions} - {"help", "verbose", "out"}
        # a method that makes one shape reads sprite sheets too: the [frames] grid keys (§16)
        sheet = {"columns", "rows", "count", "margin", "spacing"} if method.make else set()
        assert dests == {o.name for o in options(name, "cli")} | sheet, name
    with pytest.raises(SystemExit):
        methods.choices["inflate"].parse_args(["x.png", "--height", "20", "--out", "h.exr"])


def test_a_grids_matrix_is_what_it_does_to_each_unit_vector_bit_for_bit():
    """Grid.dense (the multigrid's coarsest level, solved by a (pseudo-)inverse) is built from
    the weights at once; it is, byte for byte, what apply gives each unit vector (the
    heights inflated before it came are the same to the last bit), cut edges, odd sizes,
    Dirichlet pixels and single rows and columns included."""
    rng = np.random.default_rng(1)
    for dtype in (np.float32, np.float64):
        for h, w in ((16, 16), (5, 7), (1, 9), (9, 1)):
            wx = rng.random((h, w - 1)) * (rng.random((h, w - 1)) > 0.3)
            wy = rng.random((h - 1, w)) * (rng.random((h - 1, w)) > 0.3)
            grid = Grid(wx, wy, (rng.random((h, w)) > 0.8) * rng.random((h, w)), dtype)
            by_apply = np.array([grid.apply(e.reshape(grid.shape)).ravel()
                                 for e in np.eye(h * w, dtype=grid.dtype)])
            assert grid.dense().tobytes() == by_apply.tobytes()


def test_the_coarsest_level_is_inverted_where_every_part_is_held():
    """The multigrid's coarsest level (laplace._coarsest_inverse): where every connected part
    of its unknowns holds a Dirichlet pixel, the inverse of their block (4× cheaper) — the
    pseudo-inverse but for rounding; with a free part (heights up to a constant) the
    pseudo-inverse itself. A pixel with no edge and no Dirichlet term is no unknown."""
    rng = np.random.default_rng(3)
    for held_right in (True, False):
        wx, wy = rng.random((12, 15)) + 0.1, rng.random((11, 16)) + 0.1
        wx[:, 7] = 0                                  # two parts, columns 0–7 and 8–15
        wx[11, 14], wy[10, 15] = 0, 0                 # pixel (11, 15) joined to nothing
        d = np.zeros((12, 16))
        d[0, 0] = 0.5
        d[5, 12] = 0.3 if held_right else 0.0
        grid = Grid(wx, wy, d)
        a = grid.dense()
        pinv = np.linalg.pinv(a, hermitian=True)
        got = _coarsest_inverse(grid)
        if held_right:
            assert np.abs(got - pinv).max() <= 1e-10 * np.abs(pinv).max()
            free = grid.free.ravel()
            assert not free[11 * 16 + 15] and not got[11 * 16 + 15].any()
            np.testing.assert_allclose((got @ a)[np.ix_(free, free)], np.eye(free.sum()),
                                       atol=1e-10)
        else:
            assert got.tobytes() == pinv.tobytes()
