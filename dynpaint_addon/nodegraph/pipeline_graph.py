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

from .features import Features
from .graph import FLOAT, VECTOR, Graph

UP = (0.0, 0.0, 1.0)


# -- reusable sub-graphs (node groups) ------------------------------------------------------
_GROUPS = {}


def _subgraph(name, inputs, outputs):
    """Decorator: build the sub-graph once per name; same name → same node group."""
    def wrap(fn):
        def get():
            if name not in _GROUPS:
                g = Graph(name, inputs, outputs)
                fn(g, *[g.group_input(n) for n, _ in inputs])
                _GROUPS[name] = g
            return _GROUPS[name]
        return get
    return wrap


def _finalize(g, n, z_min):
    """§2 finalize: renormalize; |N| < 0.05 → +z; N.z < z_min pushed radially to z_min.

    Mirrors core.shape.finalize_normals (NaN/Inf cannot come out of a texture lookup).
    """
    ok = g.math("LESS_THAN", g.vmath("LENGTH", n), 0.05, label="|N| < 0.05")
    unit = g.vmath("NORMALIZE", n)
    x, y, z = g.separate(unit)
    rxy = g.vmath("LENGTH", g.combine(x, y), label="|N.xy|")
    low = g.math("LESS_THAN", z, z_min, label="N.z < z_min")
    # a vector pointing straight down has no azimuth to keep: degenerate as well
    flat_down = g.math("MULTIPLY", low, g.math("LESS_THAN", rxy, 1e-6))
    bad = g.math("MAXIMUM", ok, flat_down, label="degenerate")
    reach = g.math("SQRT", g.math("SUBTRACT", 1.0, g.math("MULTIPLY", z_min, z_min)))
    scale = g.mix_float(low, 1.0, g.math("DIVIDE", reach, rxy), label="radial push")
    pushed = g.combine(g.math("MULTIPLY", x, scale), g.math("MULTIPLY", y, scale),
                       g.mix_float(low, z, z_min))
    return g.mix_vector(bad, pushed, UP, label="Normal")


@_subgraph("DP Normal Map (§2)", [("Color", VECTOR), ("Flip Green", FLOAT), ("Z Min", FLOAT)],
           [("Normal", VECTOR)])
def _normal_map(g, color, flip, z_min):
    n = g.vmath("MULTIPLY_ADD", color, (2.0, 2.0, 2.0), (-1.0, -1.0, -1.0), label="2C − 1")
    sign = g.combine(1.0, g.math("MULTIPLY_ADD", flip, -2.0, 1.0), 1.0, label="flip green")
    g.set_outputs(Normal=_finalize(g, g.vmath("MULTIPLY", n, sign), z_min))


@_subgraph("DP Height Gradient (§2)", [("Left", FLOAT), ("Right", FLOAT), ("Down", FLOAT),
                                       ("Up", FLOAT), ("Slope Scale", FLOAT), ("Z Min", FLOAT)],
           [("Normal", VECTOR)])
def _height_gradient(g, left, right, down, up, slope_scale, z_min):
    # central differences of z_px = H·h·W: ∂z/∂x = (H(x+1) − H(x−1))/2 · h·W (pixels cancel)
    half = g.math("MULTIPLY", slope_scale, 0.5)
    gx = g.math("MULTIPLY", g.math("SUBTRACT", right, left), half, label="∂z/∂x")
    gy = g.math("MULTIPLY", g.math("SUBTRACT", up, down), half, label="∂z/∂y")
    n = g.combine(g.math("MULTIPLY", gx, -1.0), g.math("MULTIPLY", gy, -1.0), 1.0)
    g.set_outputs(Normal=_finalize(g, n, z_min))


def _clamp_step_group(curve):
    @_subgraph(f"DP Clamp&Step {curve} (§3)", [("Value", FLOAT), ("T0", FLOAT), ("T1", FLOAT)],
               [("Value", FLOAT)])
    def build(g, t, t0, t1):
        # Map Range is CS except at t0 = t1, where it outputs To Min (blender-notes.md):
        # add the Heaviside step [t > t0] there (§3). t0 > t1 inverts on its own.
        u = g.map_range(t, t0, t1, 0.0, 1.0, "LINEAR", label="ramp")
        step = g.math("MULTIPLY", g.math("COMPARE", t0, t1, 0.0), g.math("GREATER_THAN", t, t0),
                      label="t0 = t1 step")
        u = g.math("ADD", u, step, clamp=True)
        if curve != "linear":
            u = g.map_range(u, 0.0, 1.0, 0.0, 1.0, curve.upper(), label=curve)
        g.set_outputs(Value=u)
    return build()


def _light_group(kind, shadows, specular, diffuse_curve, specular_curve):
    name = (f"DP Light {kind}" + (" shadowed" if shadows else "")
            + (f" specular {specular_curve}" if specular else "") + f" {diffuse_curve} (§4–§7)")
    inputs = [("Normal", VECTOR), ("Light", VECTOR), ("Surface", VECTOR), ("Shadow", FLOAT),
              ("T0", FLOAT), ("T1", FLOAT), ("S0", FLOAT), ("S1", FLOAT)]
    outputs = [("Diffuse", FLOAT), ("Specular", FLOAT)]

    @_subgraph(name, inputs, outputs)
    def build(g, n, light, surface, shadow, t0, t1, s0, s1):
        if kind == "sun":
            l_vec = g.vmath("NORMALIZE", light, label="L")
        else:   # point light: L = normalize(P_L − P_S) (§0)
            l_vec = g.vmath("NORMALIZE", g.vmath("SUBTRACT", light, surface), label="L")
        ndl = g.vmath("DOT_PRODUCT", n, l_vec, label="N·L")
        raw = shadow if shadows else ndl          # §4: t = CS(t_shadow) with cos-θ shadows
        diffuse = g.group(_clamp_step_group(diffuse_curve), {"Value": raw, "T0": t0, "T1": t1})
        spec = 0.0
        if specular:   # §7: R_L·I = 2(N·L)N.z − L.z, gated where N·L ≤ 0
            _, _, nz = g.separate(n)
            _, _, lz = g.separate(l_vec)
            rz = g.math("SUBTRACT", g.math("MULTIPLY", g.math("MULTIPLY", ndl, 2.0), nz), lz,
                        label="R_L·I")
            s = g.group(_clamp_step_group(specular_curve), {"Value": rz, "T0": s0, "T1": s1})
            spec = g.math("MULTIPLY", s["Value"], g.math("GREATER_THAN", ndl, 0.0))
        g.set_outputs(Diffuse=diffuse["Value"], Specular=spec)
    return build()


@_subgraph("DP Inverse-Square Falloff (§5)", [("Weight", VECTOR), ("Light", VECTOR),
                                              ("Surface", VECTOR), ("Radius", FLOAT)],
           [("Weight", VECTOR)])
def _inverse_square(g, weight, light, surface, radius):
    """k·c of a point light at P_S: × 1/(1 + |P_L − P_S|²/r²) = r²/(r² + |P_L − P_S|²)."""
    to_light = g.vmath("SUBTRACT", light, surface)
    r2 = g.math("MULTIPLY", radius, radius, label="r²")
    fade = g.math("DIVIDE", r2, g.math("ADD", r2, g.vmath("DOT_PRODUCT", to_light, to_light),
                                       label="r² + dist²"), label="falloff")
    g.set_outputs(Weight=g.vmath("SCALE", weight, scale=fade, label="k·c·falloff"))


@_subgraph("DP Weight (§5)", [("Sum", VECTOR), ("Term", FLOAT), ("Weight", VECTOR)],
           [("Sum", VECTOR)])
def _accumulate(g, acc, term, weight):
    g.set_outputs(Sum=g.vmath("MULTIPLY_ADD", weight, g.combine(term, term, term), acc,
                              label="Σ k·c·t"))


def _per_channel(g, colour, fn, label):
    r, gr, b = g.separate(colour)
    return g.combine(fn(g, r), fn(g, gr), fn(g, b), label=label)


@_subgraph("DP sRGB Encode (§5)", [("Color", VECTOR)], [("Color", VECTOR)])
def _to_display(g, colour):
    """core.colour.linear_to_srgb per channel: linear → the value as painted (negatives → 0)."""
    def encode(g, c):
        c = g.math("MAXIMUM", c, 0.0)
        curve = g.math("MULTIPLY_ADD", g.math("POWER", g.math("MAXIMUM", c, 0.0031308),
                                              1 / 2.4), 1.055, -0.055)
        return g.mix_float(g.math("GREATER_THAN", c, 0.0031308), g.math("MULTIPLY", c, 12.92),
                           curve)
    g.set_outputs(Color=_per_channel(g, colour, encode, "as painted"))


@_subgraph("DP sRGB Decode (§5)", [("Color", VECTOR)], [("Color", VECTOR)])
def _to_linear(g, colour):
    """core.colour.srgb_to_linear per channel: the value as painted → linear."""
    def decode(g, v):
        curve = g.math("POWER", g.math("DIVIDE", g.math("ADD", g.math("MAXIMUM", v, 0.04045),
                                                       0.055), 1.055), 2.4)
        return g.mix_float(g.math("GREATER_THAN", v, 0.04045), g.math("DIVIDE", v, 12.92),
                           curve)
    g.set_outputs(Color=_per_channel(g, colour, decode, "linear"))


def _clip01(g, v, label=""):
    return g.vmath("MAXIMUM", g.vmath("MINIMUM", v, (1.0, 1.0, 1.0)), (0.0, 0.0, 0.0),
                   label=label)


def _reflection_group(mode):
    @_subgraph(f"DP Reflection Offset {mode} (§8)",
               [("Normal", VECTOR), ("Distance", FLOAT), ("Max Offset", FLOAT)],
               [("Offset", VECTOR)])
    def build(g, n, d, dmax):
        x, y, nz = g.separate(n)
        rxy = g.vmath("LENGTH", g.combine(x, y))
        dmax = g.math("MAXIMUM", dmax, 0.0)
        if mode == "stereographic":        # 2·d_E·N.xy/N.z
            mag = g.math("DIVIDE", g.math("MULTIPLY", g.math("MULTIPLY", d, 2.0), rxy), nz)
        else:   # the paper's d_E·R.xy/R.z, R = 2N.z·N − I, "infinite" (→ Δmax) past 45°
            abs_d = g.math("ABSOLUTE", d)
            r_xy = g.math("MULTIPLY", g.math("MULTIPLY", nz, 2.0), rxy, label="|R.xy|")
            r_z = g.math("MULTIPLY_ADD", g.math("MULTIPLY", nz, nz), 2.0, -1.0, label="R.z")
            inside = g.math("GREATER_THAN", g.math("MULTIPLY", r_z, dmax),
                            g.math("MULTIPLY", abs_d, r_xy), label="below 45°")
            paper = g.math("DIVIDE", g.math("MULTIPLY", abs_d, r_xy), r_z)
            mag = g.math("MULTIPLY", g.mix_float(inside, dmax, paper), g.math("SIGN", d))
        mag = g.math("MAXIMUM", g.math("MINIMUM", mag, dmax), g.math("MULTIPLY", dmax, -1.0),
                     label="|Δ| ≤ Δmax")
        along = g.math("DIVIDE", mag, rxy)          # radial: along N.xy (0 where N.xy = 0)
        g.set_outputs(Offset=g.combine(g.math("MULTIPLY", x, along), g.math("MULTIPLY", y, along)))
    return build()


def _eta(g, value):
    """§9: η clamped to [½, 2]."""
    return g.math("MAXIMUM", g.math("MINIMUM", value, 2.0), 0.5, label="η ∈ [½, 2]")


def _refraction_group(mode):
    @_subgraph(f"DP Refraction Offset {mode} (§9)",
               [("Normal", VECTOR), ("Distance", FLOAT), ("IOR", FLOAT), ("Mu", FLOAT)],
               [("Offset", VECTOR)])
    def build(g, n, d, ior, mu):
        x, y, nz = g.separate(n)
        if mode == "physical":   # Δ = d_B(1 − η²)·N.xy / (η²N.z + √max(η² − |N.xy|², 0))
            eta = _eta(g, ior)
            e2 = g.math("MULTIPLY", eta, eta, label="η²")
            rxy2 = g.vmath("DOT_PRODUCT", g.combine(x, y), g.combine(x, y))
            root = g.math("SQRT", g.math("MAXIMUM", g.math("SUBTRACT", e2, rxy2), 0.0))
            denom = g.math("ADD", g.math("MULTIPLY", e2, nz), root)
            scale = g.math("DIVIDE", g.math("MULTIPLY", d, g.math("SUBTRACT", 1.0, e2)), denom)
        else:   # art-directed: Δ = −d_B·μ·N.xy / ((1 − |μ|) + |μ|·N.z)
            mu = g.math("MAXIMUM", g.math("MINIMUM", mu, 1.0), -1.0, label="μ ∈ [−1, 1]")
            a = g.math("ABSOLUTE", mu)
            denom = g.math("ADD", g.math("SUBTRACT", 1.0, a), g.math("MULTIPLY", a, nz))
            scale = g.math("DIVIDE", g.math("MULTIPLY", g.math("MULTIPLY", d, mu), -1.0), denom)
        g.set_outputs(Offset=g.combine(g.math("MULTIPLY", x, scale), g.math("MULTIPLY", y, scale)))
    return build()


@_subgraph("DP Fresnel physical (§10)", [("Normal", VECTOR), ("IOR", FLOAT)],
           [("Fresnel", FLOAT)])
def _fresnel_physical(g, n, ior):
    x, y, nz = g.separate(n)
    eta = _eta(g, ior)
    e2 = g.math("MULTIPLY", eta, eta, label="η²")
    c = g.math("MAXIMUM", g.math("MINIMUM", nz, 1.0), 0.0, label="cos θ")
    s2 = g.math("MINIMUM", g.vmath("DOT_PRODUCT", g.combine(x, y), g.combine(x, y)), 1.0,
                label="sin²θ")
    g2 = g.math("SUBTRACT", e2, s2)
    root = g.math("SQRT", g.math("MAXIMUM", g2, 0.0), label="g")

    def ratio_sq(a):
        num = g.math("SUBTRACT", a, root)
        den = g.math("MAXIMUM", g.math("ADD", a, root), 1e-30)
        q = g.math("DIVIDE", num, den)
        return g.math("MULTIPLY", q, q)
    f = g.math("MULTIPLY", g.math("ADD", ratio_sq(c), ratio_sq(g.math("MULTIPLY", e2, c))), 0.5,
               clamp=True, label="(F_s + F_p)/2")
    tir = g.math("LESS_THAN", g2, 0.0, label="total internal reflection")
    g.set_outputs(Fresnel=g.mix_float(tir, f, 1.0))


def _fresnel_art_group(domain):
    @_subgraph(f"DP Fresnel art {domain} (§10)",
               [("Normal", VECTOR), ("X1", FLOAT), ("X2", FLOAT), ("Kappa", FLOAT)],
               [("Fresnel", FLOAT)])
    def build(g, n, x1, x2, kappa):
        nx, ny, nz = g.separate(n)
        if domain == "sin":
            x = g.math("MINIMUM", g.vmath("LENGTH", g.combine(nx, ny)), 1.0, label="sin θ")
        else:
            x = g.math("SUBTRACT", 1.0, nz, clamp=True, label="1 − cos θ")
        x1 = g.math("MAXIMUM", g.math("MINIMUM", x1, 1.0), 0.0)
        x2 = g.math("MAXIMUM", g.math("MINIMUM", x2, 1.0), x1)
        rise1 = g.mix_float(g.math("GREATER_THAN", x2, x1), 0.5,
                            g.math("MULTIPLY", g.math("DIVIDE", g.math("SUBTRACT", x, x1),
                                                      g.math("SUBTRACT", x2, x1)), 0.5))
        rise2 = g.mix_float(g.math("LESS_THAN", x2, 1.0), 1.0,
                            g.math("MULTIPLY_ADD", g.math("DIVIDE", g.math("SUBTRACT", x, x2),
                                                          g.math("SUBTRACT", 1.0, x2)), 0.5, 0.5))
        f = g.mix_float(g.math("GREATER_THAN", x, x2), rise1, rise2)
        f = g.mix_float(g.math("GREATER_THAN", x, x1), 0.0, f)
        f = g.mix_float(g.math("GREATER_THAN", x, 0.99999994), f, 1.0, label="F(1) = 1")
        k = g.math("MAXIMUM", g.math("MINIMUM", kappa, 1.0), -1.0, label="κ")
        # κ ≥ 0: F + κ(1 − F);  κ < 0: (1 + κ)F  — one expression: F + κ⁺(1 − F) + κ⁻F
        up = g.math("MULTIPLY", g.math("MAXIMUM", k, 0.0), g.math("SUBTRACT", 1.0, f))
        down = g.math("MULTIPLY", g.math("MINIMUM", k, 0.0), f)
        g.set_outputs(Fresnel=g.math("ADD", g.math("ADD", f, up), down, clamp=True))
    return build()


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
    aspect: float
    normal: object = None
    surface: object = None
    colour: object = (0.0, 0.0, 0.0)
    alpha: object = 1.0
    s_mix: object = (0.0, 0.0, 0.0)
    c_spec: object = (1.0, 1.0, 1.0)
    acc_s: object = (0.0, 0.0, 0.0)
    passes: dict = field(default_factory=dict)


TERMS = []


def term(fn):
    """Register a term of the graph: describe() adds them in the order they are defined, each
    the twin of the core's term of the same name (core/pipeline.py)."""
    TERMS.append(fn)
    return fn


def describe(f):
    """Features → Graph of the whole pipeline, with only the branches the scene needs (§12)."""
    g = Graph("Dynamic Painting")
    width, height = f.size
    aspect = width / height                 # v per image width along y
    with g.section("Inputs"):
        uv = g.uv()
        u, v, _ = g.separate(uv)
        z_min = g.param("shape.z_min")
    with g.section("Shape (§2)"):
        surface_z = 0.0
        if f.shape_kind == "height":
            du, dv = 1.0 / width, 1.0 / height
            hs = {}
            for name, off in (("Left", (-du, 0.0)), ("Right", (du, 0.0)), ("Down", (0.0, -dv)),
                              ("Up", (0.0, dv))):
                at = g.vmath("ADD", uv, (off[0], off[1], 0.0), label=f"{name} texel")
                hs[name] = g.sample("height", at, "EXTEND", label=f"height {name.lower()}")[0]
            hs = {k: g.separate(c)[0] for k, c in hs.items()}
            h_scale = g.param("shape.height_scale")
            slope = g.math("MULTIPLY", h_scale, float(width), label="h·W")
            normal = g.group(_height_gradient(), {**hs, "Slope Scale": slope, "Z Min": z_min})
            centre_h = g.separate(g.sample("height", None, "EXTEND", label="height")[0])[0]
            surface_z = g.math("MULTIPLY", centre_h, h_scale, label="P_S.z = h·H")
        else:
            color, _ = g.sample("shape", None, "EXTEND", label="normal map")
            normal = g.group(_normal_map(), {"Color": color, "Flip Green": g.param("shape.flip_green"),
                                             "Z Min": z_min})
        normal = normal["Normal"]
        # P_S in image widths from the painting's centre, the frame point lights live in (§0)
        surface = g.combine(g.math("SUBTRACT", u, 0.5),
                            g.math("MULTIPLY", g.math("SUBTRACT", v, 0.5), 1.0 / aspect),
                            surface_z, label="P_S")

    b = Build(g, f, uv, u, v, aspect, normal, surface)
    for graph_term in TERMS:
        graph_term(b)
    g.output(b.colour, b.alpha, {"W": b.passes.get("W", (0.0, 0.0, 0.0)), "s": b.s_mix,
                                 "F": b.passes.get("F", 0.0),
                                 **{k: v for k, v in b.passes.items() if k.startswith("t")}})
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
                    weight = g.group(_inverse_square(), {
                        "Weight": weight, "Light": vec, "Surface": b.surface,
                        "Radius": g.param("falloff.radius")})["Weight"]
                shadow = g.shadow_term(i, kind, b.normal, vec) if f.shadows else 0.0
                terms = g.group(_light_group(kind, f.shadows, f.specular, f.diffuse_curve,
                                             f.specular_curve),
                                {"Normal": b.normal, "Light": vec, "Surface": b.surface,
                                 "Shadow": shadow, "T0": t0, "T1": t1, "S0": s0, "S1": s1})
                b.passes[f"t{i + 1}"] = terms["Diffuse"]
                acc_t = g.group(_accumulate(), {"Sum": acc_t, "Term": terms["Diffuse"],
                                                "Weight": weight})["Sum"]
                if f.specular:
                    acc_s = g.group(_accumulate(), {"Sum": acc_s, "Term": terms["Specular"],
                                                    "Weight": weight})["Sum"]
    b.acc_s = acc_s
    with g.section("Barycentric mix (§5)"):
        c0 = g.sample("dark" if "dark" in f.channels else "bright", None, "EXTEND")[0]
        c1 = g.sample("bright" if "bright" in f.channels else "dark", None, "EXTEND")[0]
        w = _clip01(g, acc_t, label="W = clip(Σ k·c·t)") if f.lights else (0.0, 0.0, 0.0)
        if f.diffuse_mix_space == "painted":    # the display values mix, the result is linear
            mixed = g.mix_vector(w, g.group(_to_display(), {"Color": c0})["Color"],
                                 g.group(_to_display(), {"Color": c1})["Color"],
                                 label="C0(1 − W) + C1·W as painted")
            b.colour = g.group(_to_linear(), {"Color": mixed})["Color"]
        else:
            b.colour = g.mix_vector(w, c0, c1, label="C_d = C0(1 − W) + C1·W")
        b.passes["W"] = w


@term
def highlights(b):
    """§7: the opaque highlight C_s = C_d(1 − g·s) + C_spec·g·s."""
    g, f = b.g, b.f
    if not (f.specular and f.lights):
        return
    with g.section("Highlights (§7)"):
        b.s_mix = _clip01(g, b.acc_s, label="s")
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
    cv = g.math("MULTIPLY_ADD", g.param(f"{section}.offset", index=1), b.aspect, 0.5,
                label="centre v")
    pu = g.math("MULTIPLY_ADD", g.math("SUBTRACT", u, cu), inv_scale, 0.5, label="placed u")
    pv = g.math("MULTIPLY_ADD", g.math("SUBTRACT", v, cv), inv_scale, 0.5, label="placed v")
    return g.sample_bilinear(channel, pu, pv, dict(b.f.lookup_sizes)[sized_as],
                             EXTENSION_MODES[getattr(b.f, f"{section}_extension")])


@term
def transparency(b):
    """§8–§11: reflection of E and refraction of B by UV warps, mixed by Fresnel (G), the
    highlight added (C2′ = clip(G + s·C_spec)) and shown by k: C = (1 − k)·C_s + k·C2′."""
    g, f, u, v, aspect, normal = b.g, b.f, b.u, b.v, b.aspect, b.normal
    if not f.has_lookups:
        return
    with g.section("Reflection & Refraction (§8–§10)"):
        c_m = c_t = None
        a_m = a_t = 0.0

        def warped(channel, offset, section):
            ox, oy, _ = g.separate(offset)
            return _placed_lookup(b, channel, channel, section, g.math("ADD", u, ox),
                                  g.math("ADD", v, g.math("MULTIPLY", oy, aspect)))

        if f.reflects:
            off = g.group(_reflection_group(f.reflection_mode),
                          {"Normal": normal, "Distance": g.param("reflection.distance"),
                           "Max Offset": g.param("reflection.max_offset")})["Offset"]
            c_m, a_m = warped("environment", off, "reflection")
        if f.refracts:
            off = g.group(_refraction_group(f.refraction_mode),
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
                fres = g.group(_fresnel_physical(), {"Normal": normal, "IOR": eta})
            else:
                fres = g.group(_fresnel_art_group(f.fresnel_domain),
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
        c2 = _clip01(g, g.vmath("MULTIPLY_ADD", b.s_mix, b.c_spec, g_rgb), label="C2′")
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
