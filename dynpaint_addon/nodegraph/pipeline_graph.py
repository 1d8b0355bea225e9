"""The pipeline (pipeline.md §2–§11) as one node-graph description, pruned per scene (§12).

`describe(features)` returns a Graph (graph.py) that `blender/nodes/build.py` turns into the shader
material or the compositor group. It mirrors core/pipeline.py step by step; the core is the
reference and the parity tests compare the two pixel by pixel.

Channels the graph samples (the add-on supplies an image for each):
  shape            normal map, as painted (data)                         §2
  height           the height map pre-blurred by numpy (grey)
  silhouette       whose alpha is the silhouette: a float copy of the shape or dark image's
                   alpha in the material (EEVEE reads 8-bit alpha 1/255 off), the image itself
                   in the compositor
  dark, bright     colour images (sRGB decoded by Blender)                §5
  specular_color, gloss, transparency                                     §7, §11
  environment, background   linear premultiplied copies, blurred by numpy for glossy /
                   translucent looks (§11); background_sharp: the unblurred background seen
                   outside the silhouette
  shadow_<i>       the cos-θ term of light i, baked by numpy (§6)

Structure (what exists) comes from `Features`; values (t0, η, …) are live `dp.param` nodes, so
changing a value never rebuilds the tree, and toggling a feature rebuilds only the tree.
"""
from dataclasses import dataclass, field

from . import subgraphs
from .features import Features
from .graph import Graph

# -- the pipeline -----------------------------------------------------------------------
EXTENSION_MODES = {"wrap": "REPEAT", "extend": "EXTEND", "mirror": "MIRROR"}


@dataclass
class Build:
    """What the terms of describe() share: the graph, the features, the pixel's UV, normal and
    surface point (§2), and what earlier terms left — the colour so far (C), its alpha, the
    highlight weight s and colour, and the passes a backend may expose."""
    g: Graph
    f: Features
    uv: object
    u: object
    v: object
    size: tuple                    # the shape image's (width, height) refs
    normal: object = None
    surface: object = None
    colour: object = (0.0, 0.0, 0.0)
    alpha: object = 1.0
    s_mix: object = (0.0, 0.0, 0.0)
    c_spec: object = (1.0, 1.0, 1.0)
    acc_s: object = (0.0, 0.0, 0.0)
    passes: dict = field(default_factory=dict)
    _aspect: object = None

    def aspect(self):
        """The painting's aspect W/H (v per image width along y) → a ref, made where a term
        first needs it."""
        if self._aspect is None:
            self._aspect = self.g.math("DIVIDE", *self.size, label="aspect W/H")
        return self._aspect


TERMS = []


def term(fn):
    """Register a term of the graph: describe() adds them in the order they are defined, each
    the twin of the core's term of the same name (core/pipeline.py)."""
    TERMS.append(fn)
    return fn


def _shape(g, f, uv, u, v, size, z_min):
    """§2: the pixel's unit normal and its surface point P_S (image widths from the painting's
    centre, the frame point lights live in, §0) → (normal, surface)."""
    width, height = size
    with g.section("Shape (§2)"):
        surface_z = 0.0
        if f.shape_kind == "height":
            across = g.combine(g.math("DIVIDE", 1.0, width), label="one texel across")
            up = g.combine(0.0, g.math("DIVIDE", 1.0, height), label="one texel up")
            hs = {}
            for name, op, off in (("Left", "SUBTRACT", across), ("Right", "ADD", across),
                                  ("Down", "SUBTRACT", up), ("Up", "ADD", up)):
                at = g.vmath(op, uv, off, label=f"{name} texel")
                hs[name] = g.sample("height", at, "EXTEND", label=f"height {name.lower()}")[0]
            hs = {k: g.separate(c)[0] for k, c in hs.items()}
            h_scale = g.param("shape.height_scale")
            slope = g.math("MULTIPLY", h_scale, width, label="h·W")
            normal = g.group(subgraphs.height_gradient(), {**hs, "Slope Scale": slope,
                                                           "Z Min": z_min})
            centre_h = g.separate(g.sample("height", None, "EXTEND", label="height")[0])[0]
            surface_z = g.math("MULTIPLY", centre_h, h_scale, label="P_S.z = h·H")
        else:
            color, _ = g.sample("shape", None, "EXTEND", label="normal map")
            normal = g.group(subgraphs.normal_map(), {"Color": color,
                                                      "Flip Green": g.param("shape.flip_green"),
                                                      "Z Min": z_min})
        surface = g.combine(g.math("SUBTRACT", u, 0.5),
                            g.math("MULTIPLY", g.math("SUBTRACT", v, 0.5),
                                   g.math("DIVIDE", height, width, label="H/W")),
                            surface_z, label="P_S")
    return normal["Normal"], surface


def _inputs(g, f):
    """The pixel's UV and its parts, the shape image's (width, height) and the §2 smallest
    N.z."""
    with g.section("Inputs"):
        uv = g.uv()
        u, v, _ = g.separate(uv)
        size = g.image_size()
        z_min = g.param("shape.z_min")
    return uv, u, v, size, z_min


def describe(f):
    """Features → Graph of the whole pipeline, with only the branches the scene needs (§12)."""
    g = Graph("Dynamic Painting")
    uv, u, v, size, z_min = _inputs(g, f)
    normal, surface = _shape(g, f, uv, u, v, size, z_min)
    b = Build(g, f, uv, u, v, size, normal, surface)
    for graph_term in TERMS:
        graph_term(b)
    g.output(b.colour, b.alpha, {"W": b.passes.get("W", (0.0, 0.0, 0.0)), "s": b.s_mix,
                                 "F": b.passes.get("F", 0.0),
                                 **{k: v for k, v in b.passes.items() if k.startswith("t")}})
    return g


def describe_shadow(f, kind):
    """Features → Graph of the raw cos-θ term (§6) of one light of `kind` ('sun' or
    'point', the graph's light 0) at each pixel: grey (t, t, t), alpha 1. The web page draws
    it into a texture when that light moves, and its frame reads it like a baked image."""
    g = Graph("Dynamic Painting cos-θ")
    uv, u, v, size, z_min = _inputs(g, f)
    normal, _ = _shape(g, f, uv, u, v, size, z_min)
    vec, _ = g.light(0, kind)
    t = g.shadow_term(0, kind, normal, vec)
    g.output(g.combine(t, t, t, label="t"), 1.0, {})
    return g


@term
def diffuse(b):
    """§3–§5: per light its term (N·L or the cos-θ image) through Clamp&Step, the weight
    W = clip(Σ k·c·t) and C_d = C0(1 − W) + C1·W."""
    g, f = b.g, b.f
    acc_t = acc_s = (0.0, 0.0, 0.0)
    if f.lights:
        with g.section("Light & Style (§3–§7)"):
            t0, t1 = g.param("diffuse.t0"), g.param("diffuse.t1")
            s0 = g.param("specular.s0") if f.specular else 0.0
            s1 = g.param("specular.s1") if f.specular else 0.0
        for i, kind in enumerate(f.lights):
            with g.section(f"Light {i + 1}"):
                vec, weight = g.light(i, kind)
                if kind == "point" and f.falloff_mode == "inverse_square":
                    weight = g.group(subgraphs.inverse_square(), {
                        "Weight": weight, "Light": vec, "Surface": b.surface,
                        "Radius": g.param("falloff.radius")})["Weight"]
                shadow = g.shadow_term(i, kind, b.normal, vec) if f.shadows else 0.0
                terms = g.group(subgraphs.light_group(kind, f.shadows, f.specular, f.diffuse_curve,
                                             f.specular_curve),
                                {"Normal": b.normal, "Light": vec, "Surface": b.surface,
                                 "Shadow": shadow, "T0": t0, "T1": t1, "S0": s0, "S1": s1})
                b.passes[f"t{i + 1}"] = terms["Diffuse"]
                acc_t = g.group(subgraphs.accumulate(), {"Sum": acc_t, "Term": terms["Diffuse"],
                                                "Weight": weight})["Sum"]
                if f.specular:
                    acc_s = g.group(subgraphs.accumulate(), {"Sum": acc_s, "Term": terms["Specular"],
                                                    "Weight": weight})["Sum"]
    b.acc_s = acc_s
    with g.section("Barycentric mix (§5)"):
        w = subgraphs.clip01(g, acc_t, label="W = clip(Σ k·c·t)") if f.lights else (0.0, 0.0, 0.0)
        b.passes["W"] = w
        if f.albedo:        # §1: one colour image A, lit as an albedo
            a = g.param("diffuse.ambient")
            lit = g.mix_vector(w, g.combine(a, a, a), (1.0, 1.0, 1.0), label="a + (1 − a)·W")
            b.colour = g.vmath("MULTIPLY", g.sample(f.albedo, None, "EXTEND")[0], lit,
                               label="C_d = A·(a + (1 − a)·W)")
            return
        c0 = g.sample("dark", None, "EXTEND")[0]
        c1 = g.sample("bright", None, "EXTEND")[0]
        if f.diffuse_mix_space == "painted":    # the display values mix, the result is linear
            mixed = g.mix_vector(w, g.group(subgraphs.to_display(), {"Color": c0})["Color"],
                                 g.group(subgraphs.to_display(), {"Color": c1})["Color"],
                                 label="C0(1 − W) + C1·W as painted")
            b.colour = g.group(subgraphs.to_linear(), {"Color": mixed})["Color"]
        else:
            b.colour = g.mix_vector(w, c0, c1, label="C_d = C0(1 − W) + C1·W")


@term
def highlights(b):
    """§7: the opaque highlight C_s = C_d(1 − g·s) + C_spec·g·s."""
    g, f = b.g, b.f
    if not (f.specular and f.lights):
        return
    with g.section("Highlights (§7)"):
        b.s_mix = subgraphs.clip01(g, b.acc_s, label="s")
        if "specular_color" in f.channels:
            b.c_spec = g.sample("specular_color", None, "EXTEND")[0]
        amount = g.param("specular.amount")
        gloss = g.math("MULTIPLY", g.separate(g.sample("gloss", None, "EXTEND")[0])[0], amount,
                       clamp=True, label="g") if "gloss" in f.channels \
            else g.math("MULTIPLY", amount, 1.0, clamp=True, label="g")
        gs = g.vmath("SCALE", b.s_mix, scale=gloss, label="g·s")
        b.colour = g.mix_vector(gs, b.colour, b.c_spec, label="C_s")


def _placed_lookup(b, channel, sized_as, section, u, v):
    """`channel` placed over the painting by `section`'s offset and scale (core.warps.placed_uv)
    and looked up at (u, v) texel by texel, with that section's extension → (color, alpha)."""
    g = b.g
    inv_scale = g.math("DIVIDE", 1.0, g.param(f"{section}.scale"), label="1 / scale")
    cu = g.math("ADD", g.param(f"{section}.offset", index=0), 0.5, label="centre u")
    cv = g.math("MULTIPLY_ADD", g.param(f"{section}.offset", index=1), b.aspect(), 0.5,
                label="centre v")
    pu = g.math("MULTIPLY_ADD", g.math("SUBTRACT", u, cu), inv_scale, 0.5, label="placed u")
    pv = g.math("MULTIPLY_ADD", g.math("SUBTRACT", v, cv), inv_scale, 0.5, label="placed v")
    return g.sample_bilinear(channel, pu, pv, dict(b.f.lookup_sizes)[sized_as],
                             EXTENSION_MODES[getattr(b.f, f"{section}_extension")])


@term
def transparency(b):
    """§8–§11: reflection of E and refraction of B by UV warps, mixed by Fresnel (G), the
    highlight added (C2′ = clip(G + s·C_spec)) and shown by k: C = (1 − k)·C_s + k·C2′."""
    g, f, u, v, normal = b.g, b.f, b.u, b.v, b.normal
    if not f.has_lookups:
        return
    aspect = b.aspect()
    with g.section("Reflection & Refraction (§8–§10)"):
        c_m = c_t = None
        a_m = a_t = 0.0

        def warped(channel, offset, section):
            ox, oy, _ = g.separate(offset)
            return _placed_lookup(b, channel, channel, section, g.math("ADD", u, ox),
                                  g.math("ADD", v, g.math("MULTIPLY", oy, aspect)))

        if f.reflects:
            off = g.group(subgraphs.reflection_group(f.reflection_mode),
                          {"Normal": normal, "Distance": g.param("reflection.distance"),
                           "Max Offset": g.param("reflection.max_offset")})["Offset"]
            c_m, a_m = warped("environment", off, "reflection")
        if f.refracts:
            off = g.group(subgraphs.refraction_group(f.refraction_mode),
                          {"Normal": normal, "Distance": g.param("refraction.distance"),
                           "IOR": g.param("refraction.ior")
                           if f.refraction_mode == "physical" else 1.0,
                           "Mu": g.param("refraction.mu")
                           if f.refraction_mode == "linear" else 0.0})["Offset"]
            c_t, a_t = warped("background", off, "refraction")
        if c_m is not None and c_t is not None:
            if f.fresnel_mode == "physical":
                eta = g.param("refraction.ior") if f.refraction_mode == "physical" \
                    else g.math("POWER", 2.0, g.param("refraction.mu"), label="η = 2^μ")
                fres = g.group(subgraphs.fresnel_physical(), {"Normal": normal, "IOR": eta})
            else:
                fres = g.group(subgraphs.fresnel_art_group(f.fresnel_domain),
                               {"Normal": normal, "X1": g.param("fresnel.x1"),
                                "X2": g.param("fresnel.x2"),
                                "Kappa": g.param("fresnel.kappa")})
            fr = fres["Fresnel"]
            b.passes["F"] = fr
            g_rgb = g.mix_vector(g.combine(fr, fr, fr), c_t, c_m,
                                 label="G = F·C_M + (1−F)·C_T")
            g_a = g.mix_float(fr, a_t, a_m)
        elif c_m is not None or c_t is not None:
            g_rgb, g_a = (c_m, a_m) if c_m is not None else (c_t, a_t)
        else:
            g_rgb, g_a = (0.0, 0.0, 0.0), 0.0
    with g.section("Transparency (§11)"):
        c2 = subgraphs.clip01(g, g.vmath("MULTIPLY_ADD", b.s_mix, b.c_spec, g_rgb), label="C2′")
        if f.transparency == "map":
            k = g.separate(g.sample("transparency", None, "EXTEND")[0])[0]
            k = g.math("MULTIPLY", k, 1.0, clamp=True, label="k")
        else:
            amount = g.param("transparency.amount")
            k = g.math("MULTIPLY", g.separate(g.sample("transparency", None, "EXTEND")[0])[0],
                       amount, clamp=True, label="k") if "transparency" in f.channels \
                else g.math("MULTIPLY", amount, 1.0, clamp=True, label="k")
        b.colour = g.mix_vector(g.combine(k, k, k), b.colour, c2, label="C = (1−k)C_s + k·C2′")
        b.alpha = g.mix_float(k, 1.0, g_a)

@term
def silhouette(b):
    """§11: outside the silhouette α the background shows: B·(1 − α) + C·α (B unwarped, placed
    where the refraction places it)."""
    g, f = b.g, b.f
    if not f.silhouette:
        return
    with g.section("Silhouette (§11)"):
        a = g.sample("silhouette", None, "EXTEND", label=f"{f.silhouette} alpha")[1]
        if "background" in f.channels:
            b_rgb, b_a = _placed_lookup(b, "background_sharp", "background", "refraction",
                                        b.u, b.v)
        else:
            b_rgb, b_a = (0.0, 0.0, 0.0), 0.0
        b.colour = g.mix_vector(g.combine(a, a, a), b_rgb, b.colour, label="B(1−α) + C·α")
        b.alpha = g.mix_float(a, b_a, b.alpha)


@term
def view(b):
    """What the painting shows (view.show): itself, or one of its passes alone, opaque."""
    show = b.f.view_show
    if show == "painting":
        return
    g = b.g
    with g.section("View"):
        if show in ("t", "F"):
            if show == "t":     # the largest light term: the order of the lights does not matter
                terms = [v for k, v in b.passes.items() if k.startswith("t")]
                value = terms[0] if terms else 0.0
                for other in terms[1:]:
                    value = g.math("MAXIMUM", value, other)
            else:
                value = b.passes.get("F", 0.0)
            b.colour = g.combine(value, value, value, label=show)
        else:
            b.colour = b.passes.get("W", (0.0, 0.0, 0.0)) if show == "W" else b.s_mix
        b.alpha = 1.0
