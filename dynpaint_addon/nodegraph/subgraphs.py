"""The pipeline's reusable sub-graphs (pipeline.md §2–§10): each becomes one node group in
Blender's trees and one function in the OSL and GLSL shaders.

Each sub-graph is built once per name (and per variant: a light's kind and options, a warp's
mode, a Fresnel domain), so the same name always means the same group. pipeline_graph.py
wires them into the painting's graph, one term at a time.
"""
from .graph import FLOAT, VECTOR, Graph

UP = (0.0, 0.0, 1.0)


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
def normal_map(g, color, flip, z_min):
    n = g.vmath("MULTIPLY_ADD", color, (2.0, 2.0, 2.0), (-1.0, -1.0, -1.0), label="2C − 1")
    sign = g.combine(1.0, g.math("MULTIPLY_ADD", flip, -2.0, 1.0), 1.0, label="flip green")
    g.set_outputs(Normal=_finalize(g, g.vmath("MULTIPLY", n, sign), z_min))


@_subgraph("DP Height Gradient (§2)", [("Left", FLOAT), ("Right", FLOAT), ("Down", FLOAT),
                                       ("Up", FLOAT), ("Slope Scale", FLOAT), ("Z Min", FLOAT)],
           [("Normal", VECTOR)])
def height_gradient(g, left, right, down, up, slope_scale, z_min):
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


def light_group(kind, shadows, specular, diffuse_curve, specular_curve):
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
def inverse_square(g, weight, light, surface, radius):
    """k·c of a point light at P_S: × 1/(1 + |P_L − P_S|²/r²) = r²/(r² + |P_L − P_S|²)."""
    to_light = g.vmath("SUBTRACT", light, surface)
    r2 = g.math("MULTIPLY", radius, radius, label="r²")
    fade = g.math("DIVIDE", r2, g.math("ADD", r2, g.vmath("DOT_PRODUCT", to_light, to_light),
                                       label="r² + dist²"), label="falloff")
    g.set_outputs(Weight=g.vmath("SCALE", weight, scale=fade, label="k·c·falloff"))


@_subgraph("DP Weight (§5)", [("Sum", VECTOR), ("Term", FLOAT), ("Weight", VECTOR)],
           [("Sum", VECTOR)])
def accumulate(g, acc, term, weight):
    g.set_outputs(Sum=g.vmath("MULTIPLY_ADD", weight, g.combine(term, term, term), acc,
                              label="Σ k·c·t"))


def _per_channel(g, colour, fn, label):
    r, gr, b = g.separate(colour)
    return g.combine(fn(g, r), fn(g, gr), fn(g, b), label=label)


@_subgraph("DP sRGB Encode (§5)", [("Color", VECTOR)], [("Color", VECTOR)])
def to_display(g, colour):
    """core.colour.linear_to_srgb per channel: linear → the value as painted (negatives → 0)."""
    def encode(g, c):
        c = g.math("MAXIMUM", c, 0.0)
        curve = g.math("MULTIPLY_ADD", g.math("POWER", g.math("MAXIMUM", c, 0.0031308),
                                              1 / 2.4), 1.055, -0.055)
        return g.mix_float(g.math("GREATER_THAN", c, 0.0031308), g.math("MULTIPLY", c, 12.92),
                           curve)
    g.set_outputs(Color=_per_channel(g, colour, encode, "as painted"))


@_subgraph("DP sRGB Decode (§5)", [("Color", VECTOR)], [("Color", VECTOR)])
def to_linear(g, colour):
    """core.colour.srgb_to_linear per channel: the value as painted → linear."""
    def decode(g, v):
        curve = g.math("POWER", g.math("DIVIDE", g.math("ADD", g.math("MAXIMUM", v, 0.04045),
                                                       0.055), 1.055), 2.4)
        return g.mix_float(g.math("GREATER_THAN", v, 0.04045), g.math("DIVIDE", v, 12.92),
                           curve)
    g.set_outputs(Color=_per_channel(g, colour, decode, "linear"))


def clip01(g, v, label=""):
    return g.vmath("MAXIMUM", g.vmath("MINIMUM", v, (1.0, 1.0, 1.0)), (0.0, 0.0, 0.0),
                   label=label)


def reflection_group(mode):
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


def refraction_group(mode):
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
def fresnel_physical(g, n, ior):
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


def fresnel_art_group(domain):
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
