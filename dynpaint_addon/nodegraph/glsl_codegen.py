"""GLSL ES 3.00 from the graph description: the pipeline as one WebGL2 fragment shader (issue 17).

The fourth backend of pipeline_graph.describe, the web page's. Ordinary nodes are written by
text_codegen.py exactly as for OSL, with the same node helpers (snippets/shared/dp_nodes.h, read
through snippets/glsl/dp_words.glsl's #defines); here only the lookups (snippets/glsl/dp_tex.glsl)
and the pseudo nodes differ:

  dp.uv      the fragment's place in the painting's rectangle (`dp_rect`, framebuffer pixels)
  dp.sample  dp_tex_hw on a sampler2D uniform `tex_<channel>`: one hardware-filtered fetch where
             the page lets the GPU filter the image (`hw_<channel>`, the sampler's wrap that
             of `wraps`), else explicit texel taps
  dp.param   a float uniform per parameter (text_codegen.param_name), set by the page
  dp.light   `light<n>_vector` (a sun's direction or a point light's position in the painting
             frame, §0) and `light<n>_weight` (k·c, §5), set by the page as the viewer drags
  dp.output  the premultiplied linear result; shown over the page's backdrop in sRGB, or kept
             as it is (`dp_display` 0) for a float framebuffer read back by the tests

The cos-θ term is marched in the shader (snippets/shared/cos_theta.h, the OSL shader's own march,
§6) for features whose shadow source is 'osl'; with baked shadows the frame reads `tex_shadow_<i>`
like any image — the page draws those textures with the shader of
pipeline_graph.describe_shadow when a light moves.
"""
from .graph import FLOAT, VECTOR, Ref
from .text_codegen import Emitter, Program, ident, indent, param_name, read_snippet

WRAPS = {"REPEAT": 0, "EXTEND": 1, "MIRROR": 2}
INTERPS = {"Linear": 0, "Closest": 1}


ENCODE = "DP sRGB Encode (§5)"


class GlslEmitter(Emitter):
    """The graph's nodes as GLSL statements and its pseudo nodes as uniforms and lookups.

    Two shortcuts of its own (issue 29). An image whose colour is read only to be sRGB-encoded
    (the painted-space mix of dark and bright, §5) and that holds sRGB codes is read as its
    codes — the texture the page binds for it then is not decoded — and the encode is
    skipped: one decode after the mix instead of a decode per texel and an encode per image.
    A bilinear lookup built of four texel taps (Graph.sample_bilinear: the warped lookups of
    §8, §9) is one fetch: the GPU's filter where it may, else dp_tex's own bilinear.
    """
    VEC = "vec3"

    def emit(self):
        readers = {}
        for n in self.graph.nodes:
            for value in n.inputs.values():
                if isinstance(value, Ref):
                    readers.setdefault((value.node, value.output), []).append(n)
        self.as_codes, self.skipped = set(), {}
        self.bilinear_at = {b.nodes[-1]: b for b in self.graph.bilinears}
        self.inside_bilinear = {i for b in self.graph.bilinears for i in b.nodes[:-1]}
        for n in self.graph.nodes:
            if n.op != "dp.sample" or n.props["channel"] not in self.program.srgb_channels:
                continue
            users = readers.get((n.id, "color"), [])
            if users and all(u.op == "dp.group" and u.props["graph"].name == ENCODE
                             for u in users):
                self.as_codes.add(n.id)
                self.skipped.update({u.id: n for u in users})
        for n in self.graph.nodes:
            if n.id in self.inside_bilinear:
                continue
            if n.id in self.bilinear_at:
                self.bilinear(self.bilinear_at[n.id])
                continue
            getattr(self, "op_" + ident(n.op))(n)
        return self.lines

    def bilinear(self, b):
        tex, hw = self.program.filtered(b.channel, b.extension)
        uv = self.vec(self.ref(b.u), self.ref(b.v), "0.0")
        name = f"n{b.color.node}"
        self.lines.append(f"float {name}_a;")
        self.lines.append(f"vec3 {name}_bilinear = dp_tex_hw({tex}, {hw}, {uv}, "
                          f"{WRAPS[b.extension]}, 0, {name}_a);")
        self.bind(self.graph.nodes[b.color.node], b.color.output, VECTOR, f"{name}_bilinear")
        self.bind(self.graph.nodes[b.alpha.node], b.alpha.output, FLOAT, f"{name}_a")

    def op_dp_group(self, n):
        if n.id in self.skipped:                      # its image is read as its codes
            self.bind(n, "Color", VECTOR, self.values[(self.skipped[n.id].id, "color")])
            return
        super().op_dp_group(n)

    def op_dp_uv(self, n):
        self.define(n, 0, VECTOR, "dp_uv()")

    def op_dp_sample(self, n):
        channel = n.props["channel"]
        uv = self.ref(n.inputs["uv"], VECTOR) if "uv" in n.inputs else "dp_uv()"
        if channel.startswith("shadow_") and self.program.features.shadow_source == "osl":
            self.define(n, "color", VECTOR, "vec3({})".format(self.program.march_call(
                self.ref(n.inputs["normal"], VECTOR), self.ref(n.inputs["light"], VECTOR),
                n.props["kind"], uv)))
            self.bind(n, "alpha", FLOAT, "1.0")
            return
        extension, interpolation = n.props["extension"], n.props["interpolation"]
        if n.id in self.as_codes:
            self.program.codes.add(channel)
        if interpolation == "Linear":
            tex, hw = self.program.filtered(channel, extension)
        else:
            tex, hw = self.program.image(channel)[0], "0"     # a Closest tap: texel by texel
        self.lines.append(f"float n{n.id}_a;")
        self.define(n, "color", VECTOR, f"dp_tex_hw({tex}, {hw}, {uv}, {WRAPS[extension]}, "
                    f"{INTERPS[interpolation]}, n{n.id}_a)")
        self.bind(n, "alpha", FLOAT, f"n{n.id}_a")

    def op_dp_param(self, n):
        self.bind(n, 0, FLOAT, self.program.param(n.props["path"], n.props.get("index")))

    def op_dp_light(self, n):
        vector, weight = self.program.light(n.props["index"])
        self.bind(n, "vector", VECTOR, vector)
        self.bind(n, "weight", VECTOR, weight)

    def op_dp_output(self, n):
        self.lines.append(f"dp_show({self.ref(n.inputs['rgb'], VECTOR)}, "
                          f"{self.ref(n.inputs['alpha'])});")


class GlslProgram(Program):
    """The whole fragment shader: helpers, one function per sub-graph, uniforms, main."""
    OUT = "out"

    def __init__(self, features, srgb_channels=frozenset()):
        super().__init__(features)
        self.srgb_channels = srgb_channels   # images the page stores as sRGB codes
        self.codes = set()           # of those, the ones read as codes (GlslEmitter)
        self.uniforms = {}           # name → GLSL type
        self.textures = {}           # channel → sampler uniform
        self.wraps = {}              # channel → the extension its sampler wraps with

    def uniform(self, name, kind="float"):
        self.uniforms.setdefault(name, kind)
        return name

    def param(self, path, index=None):
        return self.uniform(param_name(path, index))

    def image(self, channel):
        """The sampler of an image channel and its `hw_<channel>` flag: 1 when the page lets
        the GPU filter it (a filterable format, its sampler's wrap that of `wraps`)."""
        self.textures[channel] = self.uniform(f"tex_{channel}", "sampler2D")
        return self.textures[channel], self.uniform(f"hw_{channel}", "int")

    def filtered(self, channel, extension):
        """(sampler, filter flag) of a Linear lookup of `channel` with `extension`: the flag is
        `hw_<channel>` where the GPU's wrap may serve it — the first extension a program reads
        an image with sets its sampler (`wraps`) — else 0 (texel by texel)."""
        tex, hw = self.image(channel)
        return tex, hw if self.wraps.setdefault(channel, extension) == extension else "0"

    def image_arguments(self, channel):
        """The march's image (dp_image_at: linear, edges extended) and its filter flag."""
        return self.filtered(channel, "EXTEND")

    def light(self, i):
        return (self.uniform(f"light{i + 1}_vector", "vec3"),
                self.uniform(f"light{i + 1}_weight", "vec3"))

    def bound(self, name):
        return self.uniform(name)


def generate(graph, features, srgb_channels=frozenset()):
    """GLSL ES 3.00 fragment shader of the whole pipeline for `features`
    (graph = describe(features)) → (source, GlslProgram: its uniforms, textures, the wrap of
    each image the GPU may filter, and the images it reads as their sRGB codes).
    srgb_channels: the images the page stores as sRGB codes (colour images of 8 or 16 bits)."""
    prog = GlslProgram(features, frozenset(srgb_channels))
    body = GlslEmitter(graph, prog).emit()
    functions = "\n".join(src for _, src in prog.functions.values())
    march_src = ""
    if features.shadows:
        march_src = prog.march_source()
    uniforms = "".join(f"uniform {kind} {name};\n" for name, kind in prog.uniforms.items())
    head = ("#version 300 es\n"
            "// Generated by dynpaint_addon/nodegraph/glsl_codegen.py from the pipeline's graph\n"
            "// description (pipeline.md §2–§11); do not edit: regenerate.\n"
            f"// Features: {features.key()}\n"
            "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n\n")
    return (head + read_snippet("glsl", "dp_main.glsl") + uniforms + "\n"
            + read_snippet("glsl", "dp_words.glsl") + read_snippet("shared", "dp_nodes.h") + "\n"
            + read_snippet("glsl", "dp_tex.glsl") + "\n" + functions + "\n"
            + march_src + "void main()\n{\n" + indent(body) + "}\n"), prog

